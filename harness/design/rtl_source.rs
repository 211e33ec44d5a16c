//! Where the RTL decodes each controller state: the `file:line` of the
//! state's item in each controller's `case` on the state (the compact
//! processor's `case (st_dec)` in `rtl/pp/pp_ctrl.v`, the fast processor's
//! `case (st)` in the `plan` function of `rtl/fast/fast_ctrl.v`), mapped at
//! build time (`build/rtl.rs` reads the case labels), so divergence reports name
//! the Verilog line beside the golden model's Rust line.
//! `tests/state_table.rs` reads both files on its own and checks every
//! mapped line names its state.

use crate::design::processor::ProcessorKind;
use golden::micro::isa::state_name;
use std::fmt;

/// A line of a Verilog file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct VerilogLine {
    pub file: &'static str,
    pub line: u32,
}

impl fmt::Display for VerilogLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file, self.line)
    }
}

/// The controller of `processor`, and its (state name, line) table (its
/// row's).
pub fn controller(processor: ProcessorKind) -> (&'static str, &'static [(&'static str, u32)]) {
    let row = processor.row();
    (row.controller, row.state_lines)
}

/// The line of `processor`'s controller that decodes `state`, when the ISA
/// names the state and the controller has an item for it.
pub fn state_line(processor: ProcessorKind, state: u16) -> Option<VerilogLine> {
    let name = state_name(state)?;
    let (file, lines) = controller(processor);
    lines
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, line)| VerilogLine { file, line })
}
