//! Where the RTL decodes each controller state: the `file:line` in
//! `rtl/pp/pp_ctrl.v` of the state's item in the controller's one
//! `case (st_q)`, mapped at build time (`build.rs` reads the case labels),
//! so divergence reports name the Verilog line beside the golden model's
//! Rust line. `tests/state_table.rs` reads pp_ctrl.v on its own and checks
//! every mapped line names its state.

use golden::micro::isa::state_name;
use std::fmt;

include!(concat!(env!("OUT_DIR"), "/rtl_state_lines.rs"));

/// The controller, as the repository names it.
pub const PP_CTRL: &str = "rtl/pp/pp_ctrl.v";

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

/// The line of pp_ctrl.v that decodes `state`, when the ISA names the state
/// and the controller has an item for it.
pub fn state_line(state: u16) -> Option<VerilogLine> {
    let name = state_name(state)?;
    PP_CTRL_STATE_LINES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, line)| VerilogLine {
            file: PP_CTRL,
            line,
        })
}
