//! `trace-diff` (and `rtcosim trace-diff`) on traces written by `rtcosim
//! cosim --trace` (the RTL) and `rtcosim render --trace` (the golden
//! model): injected faults are found at their pixel, event and state and
//! named in the Verilog and the Rust, on either side; numeric and
//! control-flow faults are told apart; tolerances, one pixel, JSON; and
//! bad files are clear errors (exit 2).
//!
//! Expected values come from the golden model run here on its own, and from
//! rtl/pp/pp_ctrl.v and rtl/fast/fast_ctrl.v read here as text, never from
//! trace-diff's code. The fast processor's traces are compared the same
//! way.

mod common;

use common::{arg, run_bin, text};
use golden::micro::{isa, Fault, Processor};
use golden::scene::Scene;
use golden::trace::{TraceEvent, TraceReader, TraceRecord, TraceWriter};
use std::path::{Path, PathBuf};
use std::process::Output;

const SIZE: &str = "80x60";

fn scene() -> Scene {
    Scene::reference().resized(80, 60, "test").expect("resized")
}

fn rtcosim(args: &[&str]) -> Output {
    run_bin(env!("CARGO_BIN_EXE_rtcosim"), args)
}

fn trace_diff(args: &[&str]) -> Output {
    run_bin(env!("CARGO_BIN_EXE_trace-diff"), args)
}

fn ok(out: Output, what: &str) -> Output {
    assert!(
        out.status.success(),
        "{what}: {}\n{}",
        text(&out.stdout),
        text(&out.stderr)
    );
    out
}

/// The RTL's trace of `window`, with `fault` in the RTL.
fn rtl_trace(dir: &Path, name: &str, window: &str, fault: Option<&str>) -> PathBuf {
    rtl_trace_on("compact", dir, name, window, fault)
}

/// [`rtl_trace`] on `processor`.
fn rtl_trace_on(
    processor: &str,
    dir: &Path,
    name: &str,
    window: &str,
    fault: Option<&str>,
) -> PathBuf {
    let path = dir.join(name);
    let mut args = vec![
        "cosim",
        "--size",
        SIZE,
        "--threads",
        "1",
        "--window",
        window,
        "--processor",
        processor,
    ];
    args.extend(["--trace", arg(&path)]);
    if let Some(f) = fault {
        args.extend(["--fault", f]);
    }
    let out = rtcosim(&args);
    // A fault fails the co-simulation (exit 1), but the trace is written.
    let expected = if fault.is_some() { 1 } else { 0 };
    assert_eq!(out.status.code(), Some(expected), "{}", text(&out.stderr));
    path
}

/// The golden model's trace of `window`, with `fault` in the model.
fn golden_trace(dir: &Path, name: &str, window: &str, fault: Option<&str>) -> PathBuf {
    golden_trace_on("compact", dir, name, window, fault)
}

/// [`golden_trace`] with `processor`'s cycles.
fn golden_trace_on(
    processor: &str,
    dir: &Path,
    name: &str,
    window: &str,
    fault: Option<&str>,
) -> PathBuf {
    let path = dir.join(name);
    let png = dir.join(format!("{name}.png"));
    let mut args = vec![
        "render",
        "--model",
        "micro",
        "--size",
        SIZE,
        "--threads",
        "1",
        "--processor",
        processor,
    ];
    args.extend([
        "--out",
        arg(&png),
        "--trace",
        arg(&path),
        "--trace-window",
        window,
    ]);
    if let Some(f) = fault {
        args.extend(["--fault", f]);
    }
    ok(rtcosim(&args), "render --trace");
    path
}

/// The first event in state `state` of pixel (x, y) in the golden model,
/// with the Rust line that issues it.
fn first_in_state(x: u32, y: u32, state: u16) -> (TraceEvent, String) {
    let mut first = None;
    Processor::new(&scene()).render_pixel(x, y, |e, at| {
        if e.state == state && first.is_none() {
            first = Some((*e, format!("{}:{}", at.file(), at.line())));
        }
    });
    first.expect("the pixel visits the state")
}

/// The line of rtl/pp/pp_ctrl.v whose case item names `name`, read here.
fn verilog_line(name: &str) -> String {
    verilog_line_in("rtl/pp/pp_ctrl.v", "module", name)
}

/// The line of `file` whose case item names `name`, the first after the
/// line that starts with `after`, read here.
fn verilog_line_in(file: &str, after: &str, name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    let rtl = std::fs::read_to_string(path).expect("the controller");
    let label = format!("`ISA_ST_{name}");
    let from = rtl
        .lines()
        .position(|l| l.trim_start().starts_with(after))
        .expect("the line to search after");
    let line = rtl
        .lines()
        .enumerate()
        .skip(from)
        .position(|(_, l)| {
            let t = l.trim_start();
            t.starts_with(&label) && t[label.len()..].trim_start().starts_with(':')
        })
        .expect("a case item");
    format!("{file}:{}", from + line + 1)
}

/// Where the state sequences of pixel (x, y) with and without `fault`
/// first differ (in state, destination or lanes), found by running the
/// golden model both ways here.
fn golden_split(x: u32, y: u32, fault: Fault) -> Option<u32> {
    let run = |p: Processor| {
        let mut steps = Vec::new();
        p.render_pixel(x, y, |e, _| steps.push((e.state, e.dst, e.lanes)));
        steps
    };
    let clean = run(Processor::new(&scene()));
    let faulty = run(Processor::new(&scene()).with_fault(Some(fault)));
    (0..clean.len().max(faulty.len()))
        .find(|&i| clean.get(i) != faulty.get(i))
        .map(|i| i as u32)
}

/// A fault's first divergence, checked against the golden model's own run:
/// the pixel, the event, the state on both sides with its Verilog line and
/// its Rust line.
fn assert_located(stdout: &str, pixel: (u32, u32), state_name: &str) {
    assert_located_at(stdout, pixel, state_name, &verilog_line(state_name));
}

/// [`assert_located`], the state's Verilog line `verilog`.
fn assert_located_at(stdout: &str, pixel: (u32, u32), state_name: &str, verilog: &str) {
    let state = isa::state_code(state_name).expect("a state");
    let (event, rust) = first_in_state(pixel.0, pixel.1, state);
    let head = format!(
        "first divergence: pixel ({}, {}) event #{} (",
        pixel.0, pixel.1, event.seq
    );
    assert!(stdout.contains(&head), "expected {head:?} in\n{stdout}");
    let named = format!(
        "state {state_name} ({state}) [{verilog}], dst {}",
        isa::register_label(event.dst)
    );
    assert_eq!(
        stdout
            .matches(&format!(
                "{named}.{}, issued by {rust}",
                isa::lanes_label(event.lanes)
            ))
            .count(),
        2,
        "both sides named in Verilog and Rust ({named}, {rust}) in\n{stdout}"
    );
}

#[test]
fn clean_rtl_and_golden_traces_agree_and_both_binaries_say_so() {
    let dir = common::scratch("trace_diff", "clean");
    let rtl = rtl_trace(&dir, "rtl.rtt", "20,10,35,25", None);
    let golden = golden_trace(&dir, "golden.rtt", "20,10,35,25", None);
    for out in [
        trace_diff(&[arg(&rtl), arg(&golden)]),
        rtcosim(&["trace-diff", arg(&rtl), arg(&golden)]),
    ] {
        let stdout = text(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{stdout}{}", text(&out.stderr));
        assert!(stdout.contains("256 pixels compared"), "{stdout}");
        assert!(
            stdout.contains("side       rtl.rtt: rtl, golden.rtt: golden"),
            "{stdout}"
        );
        assert!(stdout.contains("PASS"), "{stdout}");
    }
}

/// The fast processor's trace (`cosim --processor fast --trace`: one
/// processor fed the window in tiles of 4 rows, its results put back in
/// row order) agrees with golden's trace with the fast processor's cycles
/// (`render --trace --processor fast`); against golden's trace with the
/// compact processor's cycles only the cycles differ, and the headers say
/// why. A fault in it is located at the line of rtl/fast/fast_ctrl.v that
/// decodes the state (its `plan` function), read here.
#[test]
fn the_fast_processors_trace_agrees_and_its_faults_are_located_in_fast_ctrl() {
    let dir = common::scratch("trace_diff", "fast");
    let window = "20,10,35,25";
    let rtl = rtl_trace_on("fast", &dir, "fast.rtt", window, None);
    let golden = golden_trace_on("fast", &dir, "golden-fast.rtt", window, None);
    let out = trace_diff(&[arg(&rtl), arg(&golden)]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}{}", text(&out.stderr));
    assert!(stdout.contains("256 pixels compared"), "{stdout}");
    assert!(stdout.contains("PASS"), "{stdout}");

    // The compact processor's cycles: every pixel's count differs (a
    // barrel pixel waits for its turns), nothing else does.
    let compact = golden_trace(&dir, "golden-compact.rtt", window, None);
    let out = trace_diff(&[arg(&rtl), arg(&compact)]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", text(&out.stderr));
    assert!(
        stdout.contains("processor  fast.rtt: fast, golden-compact.rtt: compact"),
        "{stdout}"
    );
    assert!(stdout.contains("(timing only)"), "{stdout}");
    assert!(
        stdout.contains("divergent pixels: 256 (0 control-flow, 0 numeric drift)"),
        "{stdout}"
    );

    let faulty = rtl_trace_on(
        "fast",
        &dir,
        "faulty.rtt",
        "30,20,33,22",
        Some("PRI_HALF:0x400"),
    );
    let golden = golden_trace_on("fast", &dir, "golden-small.rtt", "30,20,33,22", None);
    let out = trace_diff(&[arg(&faulty), arg(&golden)]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", text(&out.stderr));
    let fast_line = verilog_line_in(
        "rtl/fast/fast_ctrl.v",
        "function [PLVW-1:0] plan(",
        "PRI_HALF",
    );
    assert_ne!(fast_line, verilog_line("PRI_HALF"));
    assert_located_at(&stdout, (30, 20), "PRI_HALF", &fast_line);
    assert!(
        stdout.contains("divergent pixels: 12 (0 control-flow, 12 numeric drift)"),
        "{stdout}"
    );
}

#[test]
fn a_numeric_fault_in_the_rtl_is_located_and_classed_as_drift() {
    let dir = common::scratch("trace_diff", "rtl-numeric");
    let rtl = rtl_trace(&dir, "rtl.rtt", "30,20,33,22", Some("PRI_HALF:0x400"));
    let golden = golden_trace(&dir, "golden.rtt", "30,20,33,22", None);
    let out = trace_diff(&[arg(&rtl), arg(&golden), "--context", "1"]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", text(&out.stderr));
    assert_located(&stdout, (30, 20), "PRI_HALF");
    // The fault moves the ray's direction a little: no branch changes in
    // this window (the golden model agrees: see golden_split).
    let fault: Fault = "PRI_HALF:0x400".parse().expect("fault");
    assert!((20..=22).all(|y| (30..=33).all(|x| golden_split(x, y, fault).is_none())));
    assert!(stdout.contains("(numeric drift):"), "{stdout}");
    assert!(
        stdout.contains("divergent pixels: 12 (0 control-flow, 12 numeric drift)"),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "lane x: rtl.rtt 0xc1200400 (-1.0000977e1), golden.rtt 0xc1200000 (-1e1): 1024 ulp"
        ),
        "{stdout}"
    );
    // --context 1: the one event before it, from both sides.
    assert!(stdout.contains("the 1 event before it:"), "{stdout}");
    assert_eq!(stdout.matches("#0     PRI_ITOF").count(), 2, "{stdout}");
}

#[test]
fn a_control_flow_fault_in_the_rtl_reports_the_split_branch_and_cause() {
    let dir = common::scratch("trace_diff", "rtl-control");
    let fault_text = "SPH_T:0x80000000";
    let rtl = rtl_trace(&dir, "rtl.rtt", "28,9", Some(fault_text));
    let golden = golden_trace(&dir, "golden.rtt", "28,9", None);
    let out = trace_diff(&[arg(&rtl), arg(&golden)]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", text(&out.stderr));
    assert_located(&stdout, (28, 9), "SPH_T");
    let split = golden_split(28, 9, fault_text.parse().expect("fault"))
        .expect("the fault changes the path");
    assert!(stdout.contains("(control-flow divergence):"), "{stdout}");
    assert!(
        stdout.contains(&format!(
            "the state sequences split at event #{split}: the branch after event #{}",
            split - 1
        )),
        "{stdout}"
    );
    assert!(
        stdout.contains("caused by the values apart at the event above")
            || stdout.contains("the first value apart before it"),
        "{stdout}"
    );
}

#[test]
fn faults_on_the_golden_side_are_located_too() {
    let dir = common::scratch("trace_diff", "golden-side");
    let rtl = rtl_trace(&dir, "rtl.rtt", "28,9,31,10", None);
    let numeric = golden_trace(&dir, "numeric.rtt", "28,9,31,10", Some("PRI_HALF:0x400"));
    let out = trace_diff(&[arg(&rtl), arg(&numeric)]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", text(&out.stderr));
    assert_located(&stdout, (28, 9), "PRI_HALF");
    assert!(
        stdout.contains("fault      rtl.rtt: -, numeric.rtt: PRI_HALF:0x400"),
        "{stdout}"
    );
    let control = golden_trace(&dir, "control.rtt", "28,9,31,10", Some("SPH_T:0x80000000"));
    let out = trace_diff(&[arg(&control), arg(&rtl)]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert_located(&stdout, (28, 9), "SPH_T");
    assert!(stdout.contains("(control-flow divergence):"), "{stdout}");
    // Without --all only the first divergence is named in the Rust (once a
    // side); with it, every divergent pixel's is.
    assert_eq!(stdout.matches(", issued by ").count(), 2, "{stdout}");
    let out = trace_diff(&[arg(&control), arg(&rtl), "--all"]);
    let stdout = text(&out.stdout);
    let pixels = stdout.matches("\npixel (").count() + usize::from(stdout.starts_with("pixel ("));
    assert!(pixels > 1, "several divergent pixels listed: {stdout}");
    assert!(
        stdout.matches(", issued by ").count() >= 2 * (pixels + 1),
        "each listed pixel and the first divergence named in the Rust: {stdout}"
    );
}

/// Rewrites trace `from` into `to`, changing records with `edit`.
fn rewrite(from: &Path, to: &Path, mut edit: impl FnMut(usize, &mut TraceRecord)) {
    let reader = TraceReader::new(std::fs::File::open(from).expect("open")).expect("a trace");
    let header = reader.header().clone();
    let mut w =
        TraceWriter::new(std::fs::File::create(to).expect("create"), &header).expect("header");
    for (i, r) in reader.enumerate() {
        let mut r = r.expect("record");
        edit(i, &mut r);
        w.record(r).expect("write");
    }
    w.finish().expect("flush");
}

#[test]
fn max_ulps_pixel_and_json_do_what_they_say() {
    let dir = common::scratch("trace_diff", "options");
    let golden = golden_trace(&dir, "a.rtt", "10,10,12,11", None);
    // One value of pixel (11, 10), 1 ULP up: lane x of its first event from
    // #5 on that writes lane x.
    let nudged = dir.join("b.rtt");
    let mut hit = None;
    rewrite(&golden, &nudged, |_, r| {
        if let TraceRecord::Event(e) = r {
            if (e.x, e.y) == (11, 10) && e.seq >= 5 && e.lanes & 1 == 1 && hit.is_none() {
                e.values[0] += 1;
                hit = Some((e.seq, e.state));
            }
        }
    });
    let (seq, state) = hit.expect("pixel (11, 10) writes lane x after #5");
    let out = trace_diff(&[arg(&golden), arg(&nudged)]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains(&format!(
            "first divergence: pixel (11, 10) event #{seq} (numeric drift)"
        )),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("state {}", isa::state_label(state))),
        "{stdout}"
    );
    assert!(stdout.contains(": 1 ulp"), "{stdout}");
    let out = trace_diff(&[arg(&golden), arg(&nudged), "--max-ulps", "1"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    // Only another pixel: agrees.
    let out = trace_diff(&[arg(&golden), arg(&nudged), "--pixel", "12,11"]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains("1 pixel compared"), "{stdout}");
    // JSON on stdout.
    let out = trace_diff(&[arg(&golden), arg(&nudged), "--json", "-"]);
    assert_eq!(out.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    let d = &json["report"]["first_divergence"];
    assert_eq!(d["pixel"], serde_json::json!([11, 10]));
    assert_eq!(d["seq"], seq);
    assert_eq!(d["classification"]["class"], "numeric_drift");
    assert_eq!(d["a"]["state"], isa::state_name(state).expect("named"));
    assert_eq!(json["report"]["counts"]["divergent_pixels"], 1);
    assert_eq!(json["passed"], false);
}

/// The error of a trace-diff that must fail with exit 2.
fn refusal(a: &Path, b: &Path) -> String {
    let out = trace_diff(&[arg(a), arg(b)]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stdout));
    text(&out.stderr)
}

#[test]
fn bad_truncated_foreign_and_mismatched_files_are_clear_errors() {
    let dir = common::scratch("trace_diff", "bad");
    let good = golden_trace(&dir, "good.rtt", "5,5,6,5", None);
    let bytes = std::fs::read(&good).expect("read");
    // Cut inside a record.
    let cut = dir.join("cut.rtt");
    std::fs::write(&cut, &bytes[..bytes.len() - 30]).expect("write");
    let err = refusal(&good, &cut);
    assert!(
        err.contains("cut.rtt: trace file is truncated: record") && err.contains("byte offset"),
        "{err}"
    );
    // Cut at a record boundary, inside a pixel: no end record.
    let header_len = TraceReader::new(&bytes[..]).expect("a trace").offset() as usize;
    let events = (bytes.len() - header_len) / 24;
    let mid = dir.join("mid.rtt");
    std::fs::write(&mid, &bytes[..header_len + (events - 3) * 24]).expect("write");
    let err = refusal(&good, &mid);
    assert!(
        err.contains("mid.rtt: the file ends inside pixel (6, 5)"),
        "{err}"
    );
    // Not a trace.
    let png = dir.join("good.rtt.png");
    let err = refusal(&png, &good);
    assert!(
        err.contains("good.rtt.png: not an rtcosim trace file"),
        "{err}"
    );
    // Missing.
    let err = refusal(&dir.join("nope.rtt"), &good);
    assert!(err.contains("nope.rtt"), "{err}");
    // Out of order: a sequence number skipped.
    let skipped = dir.join("skipped.rtt");
    rewrite(&good, &skipped, |i, r| {
        if let (3, TraceRecord::Event(e)) = (i, r) {
            e.seq += 1;
        }
    });
    let err = refusal(&good, &skipped);
    assert!(
        err.contains(&format!("skipped.rtt: record 3 (byte offset {}): event of pixel (5, 5) has sequence number 4, expected 3", header_len + 3 * 24)),
        "{err}"
    );
    // Another scene.
    let other = dir.join("other.rtt");
    let png2 = dir.join("other.png");
    ok(
        rtcosim(&[
            "render",
            "--model",
            "micro",
            "--scene",
            "mirror",
            "--size",
            SIZE,
            "--out",
            arg(&png2),
            "--trace",
            arg(&other),
            "--trace-window",
            "5,5,6,5",
        ]),
        "render mirror",
    );
    let err = refusal(&good, &other);
    assert!(err.contains("the traces are of different scenes"), "{err}");
    // The same scene in another configuration is compared, differences first.
    let fast = dir.join("fast.rtt");
    ok(
        rtcosim(&[
            "render",
            "--model",
            "micro",
            "--size",
            SIZE,
            "--recip",
            "fast",
            "--out",
            arg(&png2),
            "--trace",
            arg(&fast),
            "--trace-window",
            "5,5,6,5",
        ]),
        "render fast",
    );
    let out = trace_diff(&[arg(&good), arg(&fast)]);
    let stdout = text(&out.stdout);
    assert!(matches!(out.status.code(), Some(0 | 1)), "{stdout}");
    assert!(
        stdout.contains("configurations differ:\n  recip      good.rtt: exact, fast.rtt: fast"),
        "{stdout}"
    );
}
