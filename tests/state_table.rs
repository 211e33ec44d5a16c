//! The controller's state table (docs/rtl.md, "State table") against the
//! golden model's own trace: every ISA state, and the functions of
//! golden/src/micro/program.rs whose lines issue its instruction, by name,
//! so the table survives line shifts.
//!
//! Every event of every pixel of every builtin scene (at the reduced sizes
//! of tests/pixel_processor.rs) carries the `&'static Location` of the
//! program.rs line that issued it (`#[track_caller]` through the
//! sub-machines); that line must lie in a function the table names for the
//! event's state, and every (state, function) pair of the table must be
//! seen. The RTL side: rtl/pp/pp_ctrl.v has one case item per state of the
//! table, and its functions are named after the program.rs function whose
//! control flow they compute (or, for addresses, golden::micro::isa's).

mod common;

use common::reduced;
use golden::micro::{isa, Processor};
use golden::scene::Scene;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

const DOC: &str = "docs/rtl.md";
const HEADING: &str = "### State table";
const PROGRAM: &str = "golden/src/micro/program.rs";
const ISA_RS: &str = "golden/src/micro/isa.rs";
const PP_CTRL: &str = "rtl/pp/pp_ctrl.v";
const FAST_CTRL: &str = "rtl/fast/fast_ctrl.v";

fn read(rel: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The names between backticks in `cell`.
fn ticked(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// One row of the table.
#[derive(Debug)]
struct Row {
    /// The program.rs functions that issue the state's instruction (none
    /// for a state that issues none).
    functions: BTreeSet<String>,
    /// For a state that writes only F (no trace event): the state whose
    /// events stand for its call (`F only, no event: as `DOT_3``).
    as_state: Option<String>,
}

/// The table: state name -> its row.
fn table() -> BTreeMap<String, Row> {
    let doc = read(DOC);
    let section = doc
        .split_once(HEADING)
        .unwrap_or_else(|| panic!("{DOC} has no {HEADING:?} section"))
        .1;
    let section = section.split("\n#").next().expect("split yields one part");
    let mut rows = BTreeMap::new();
    for line in section.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.split('|').collect();
        assert!(
            cells.len() >= 5,
            "{DOC}: a table row needs 3 cells: {line:?}"
        );
        let state = ticked(cells[1]);
        assert_eq!(state.len(), 1, "{DOC}: one state per row: {line:?}");
        let row = Row {
            functions: ticked(cells[2]).into_iter().collect(),
            as_state: cells[3]
                .contains("F only")
                .then(|| ticked(cells[3]).pop())
                .flatten(),
        };
        let before = rows.insert(state[0].clone(), row);
        assert!(before.is_none(), "{DOC}: state {} twice", state[0]);
    }
    assert!(!rows.is_empty(), "{DOC}: no rows under {HEADING:?}");
    rows
}

/// Functions of a Rust source: (line of `fn`, name), in order.
fn rust_functions(src: &str) -> Vec<(u32, String)> {
    src.lines()
        .enumerate()
        .filter_map(|(i, line)| {
            let code = line.trim_start();
            if code.starts_with("//") {
                return None;
            }
            let (_, rest) = code.split_once("fn ")?;
            let before = &code[..code.len() - rest.len() - 3];
            let qualifiers_only = before
                .split_whitespace()
                .all(|w| matches!(w, "pub" | "pub(crate)" | "const" | "unsafe"));
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            (qualifiers_only && !name.is_empty()).then(|| (i as u32 + 1, name))
        })
        .collect()
}

/// The function a line lies in: the last one declared at or before it.
fn enclosing(functions: &[(u32, String)], line: u32) -> &str {
    functions
        .iter()
        .rev()
        .find(|(at, _)| *at <= line)
        .map_or("<before any function>", |(_, name)| name.as_str())
}

#[test]
fn the_table_names_every_state_once_and_only_isa_states() {
    let table = table();
    let isa_states: BTreeSet<String> = isa::STATES.iter().map(|(n, _)| n.to_string()).collect();
    let listed: BTreeSet<String> = table.keys().cloned().collect();
    let unknown: Vec<_> = listed.difference(&isa_states).collect();
    let missing: Vec<_> = isa_states.difference(&listed).collect();
    assert!(unknown.is_empty(), "{DOC}: not ISA states: {unknown:?}");
    assert!(missing.is_empty(), "{DOC}: ISA states missing: {missing:?}");
    let program: BTreeSet<String> = rust_functions(&read(PROGRAM))
        .into_iter()
        .map(|(_, n)| n)
        .collect();
    for (state, row) in &table {
        if let Some(other) = &row.as_state {
            let stand_in = table
                .get(other)
                .unwrap_or_else(|| panic!("{DOC}: {state} is as {other}, which has no row"));
            assert!(
                stand_in.as_state.is_none() && stand_in.functions == row.functions,
                "{DOC}: {state} is as {other}: the same functions, and {other} writes a register"
            );
        }
        for f in &row.functions {
            assert!(
                program.contains(f),
                "{DOC}: {state}: no fn {f} in {PROGRAM}"
            );
        }
    }
}

#[test]
fn every_golden_event_comes_from_where_the_table_says() {
    let table = table();
    let functions = rust_functions(&read(PROGRAM));
    let mut seen: BTreeSet<(String, String)> = BTreeSet::new();
    // (state, function) -> where it was first seen: line, scene, pixel.
    type FirstSeen<'a> = (String, &'a str, (u32, u32));
    let mut wrong: BTreeMap<(String, String), FirstSeen> = BTreeMap::new();
    let mut fn_of_line: HashMap<u32, String> = HashMap::new();
    let mut events = 0u64;
    // The builtins (the glass ones among them), the mirror scene with a
    // weight cutoff that refuses its deepest reflections (CUT_W, CUT_CMP
    // run only with a cutoff), and the touching glass spheres with one
    // that refuses some refracted children (RF_CUT_W, RF_CUT_CMP).
    let mut scenes: Vec<(&str, Scene)> = Scene::builtin_names()
        .iter()
        .map(|&name| (name, reduced(name)))
        .collect();
    scenes.push(("mirror with a cutoff", common::mirror_with_cutoff()));
    let touching = reduced("touching");
    let mut render = touching.render;
    render.weight_cutoff = 0.05;
    let cut = touching.with_render(render, "test").expect("a cutoff");
    scenes.push(("touching with a cutoff", cut));
    for (name, scene) in &scenes {
        let proc = Processor::new(scene);
        for y in 0..scene.camera.height {
            for x in 0..scene.camera.width {
                proc.render_pixel(x, y, |e, at| {
                    events += 1;
                    let state = isa::state_name(e.state).unwrap_or("<unnamed>").to_string();
                    assert!(
                        at.file().replace('\\', "/").ends_with(PROGRAM),
                        "{state} event issued from {at}, not {PROGRAM}"
                    );
                    let f = fn_of_line
                        .entry(at.line())
                        .or_insert_with(|| enclosing(&functions, at.line()).to_string())
                        .clone();
                    // F-only states have no events: one here is wrong too.
                    let expected = table
                        .get(&state)
                        .is_some_and(|r| r.as_state.is_none() && r.functions.contains(&f));
                    if expected {
                        seen.insert((state, f));
                    } else {
                        wrong
                            .entry((state, f))
                            .or_insert_with(|| (format!("{PROGRAM}:{}", at.line()), name, (x, y)));
                    }
                });
            }
        }
    }
    assert!(events > 0);
    let report: Vec<String> = wrong
        .iter()
        .map(|((state, f), (line, scene, (x, y)))| {
            format!(
                "{state} issued in fn {f} ({line}, first in {scene} at ({x}, {y})); the table says {:?}",
                table.get(state).map(|r| &r.functions)
            )
        })
        .collect();
    assert!(
        report.is_empty(),
        "{DOC} state table disagrees with golden's trace ({events} events):\n{}",
        report.join("\n")
    );
    let unseen: Vec<String> = table
        .iter()
        .filter(|(_, r)| r.as_state.is_none())
        .flat_map(|(s, r)| r.functions.iter().map(move |f| (s.clone(), f.clone())))
        .filter(|pair| !seen.contains(pair))
        .map(|(s, f)| format!("{s} in {f}"))
        .collect();
    assert!(
        unseen.is_empty(),
        "{DOC} lists state/function pairs no builtin scene issues ({events} events): {unseen:?}"
    );
}

#[test]
fn pp_ctrl_has_one_case_item_per_state_and_names_its_functions_after_golden() {
    let table = table();
    let rtl = read(PP_CTRL);
    let mut items: BTreeMap<String, usize> = BTreeMap::new();
    for line in rtl.lines() {
        let code = line.trim_start();
        if let Some(rest) = code.strip_prefix("`ISA_ST_") {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if rest[name.len()..].trim_start().starts_with(':') {
                *items.entry(name).or_default() += 1;
            }
        }
    }
    let states: BTreeSet<&String> = table.keys().collect();
    let with_items: BTreeSet<&String> = items.keys().collect();
    assert_eq!(
        with_items, states,
        "{PP_CTRL}: case items vs the states of {DOC}"
    );
    let twice: Vec<_> = items.iter().filter(|(_, n)| **n > 1).collect();
    assert!(
        twice.is_empty(),
        "{PP_CTRL}: states with more than one case item: {twice:?}"
    );

    let golden: BTreeSet<String> = [PROGRAM, ISA_RS]
        .iter()
        .flat_map(|f| rust_functions(&read(f)))
        .map(|(_, n)| n)
        .collect();
    let mut names = Vec::new();
    for line in rtl.lines() {
        let Some(rest) = line.trim_start().strip_prefix("function ") else {
            continue;
        };
        let rest = rest.trim_start();
        let rest = match rest.strip_prefix('[') {
            Some(r) => r.split_once(']').expect("a closed range").1,
            None => rest,
        };
        let name: String = rest
            .trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        names.push(name);
    }
    assert!(!names.is_empty(), "{PP_CTRL}: no functions found");
    for name in &names {
        let after_golden = golden.iter().any(|g| {
            name == g
                || name
                    .strip_prefix(g.as_str())
                    .is_some_and(|r| r.starts_with('_'))
        });
        assert!(
            after_golden,
            "{PP_CTRL}: function {name} is named after no function of {PROGRAM} or {ISA_RS}"
        );
    }
    assert!(!rtl.contains("task "), "{PP_CTRL}: tasks are gone");
}

/// Every ISA state each controller decodes is mapped to its line, and the
/// mapped line, read here on its own, is the case item that names the
/// state: in pp_ctrl.v's `case (st_dec)`, and in fast_ctrl.v's `plan`
/// function (the fast controller's decode of a state into its micro-op).
#[test]
fn every_state_maps_to_the_verilog_line_that_decodes_it() {
    use rtcosim::design::processor::ProcessorKind;
    use rtcosim::design::rtl_source::{controller, state_line};
    let table = table();
    // The fast controller plans no micro-op for IDLE: an idle context
    // issues nothing (the plan's default, a NOP that writes nothing), so no
    // trace event is ever in IDLE. The compact controller decodes it.
    for (processor, file, within, unplanned) in [
        (ProcessorKind::Compact, PP_CTRL, "case (st_dec)", None),
        (
            ProcessorKind::Fast,
            FAST_CTRL,
            "function [PLVW-1:0] plan(",
            Some("IDLE"),
        ),
    ] {
        let rtl = read(file);
        let lines: Vec<&str> = rtl.lines().collect();
        // The mapped lines lie after `within` and before the next
        // `endfunction` (pp_ctrl's case is in no function: its end).
        let first = 1 + lines
            .iter()
            .position(|l| l.trim_start().starts_with(within))
            .unwrap_or_else(|| panic!("{file}: no {within:?}"));
        let last = first
            + lines[first..]
                .iter()
                .position(|l| l.trim() == "endfunction")
                .unwrap_or(lines.len() - first);
        for name in table.keys() {
            let state = isa::state_code(name).unwrap_or_else(|| panic!("{name}: not an ISA state"));
            if Some(name.as_str()) == unplanned {
                assert_eq!(state_line(processor, state), None, "{file}: {name}");
                continue;
            }
            let at = state_line(processor, state)
                .unwrap_or_else(|| panic!("{file}: {name}: no Verilog line mapped"));
            assert_eq!(at.file, file);
            assert!(
                (first..=last).contains(&(at.line as usize)),
                "{at} ({name}) is outside lines {first}..={last} of {within:?}"
            );
            let text = lines
                .get(at.line as usize - 1)
                .unwrap_or_else(|| panic!("{at}: past the end of the file"));
            let label = format!("`ISA_ST_{name}");
            let item = text.trim_start().split("//").next().unwrap_or_default();
            let names_it = item
                .split(':')
                .next()
                .is_some_and(|labels| labels.split(',').any(|l| l.trim() == label));
            assert!(names_it, "{at} does not name {name}: {text:?}");
        }
        assert_eq!(
            controller(processor).1.len(),
            table.len() - usize::from(unplanned.is_some()),
            "{file}: one mapped line per state of the table"
        );
        // A state the ISA does not name has no line.
        assert!(state_line(processor, u16::MAX).is_none());
    }
}
