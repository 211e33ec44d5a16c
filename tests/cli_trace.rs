//! `rtcosim render --trace FILE --trace-window ...` and `rtcosim trace-dump`,
//! run as the built binary: the file holds exactly the golden model's events
//! for the window, in pixel order, and bad requests fail with a message
//! before anything is written.

use golden::micro::{isa, Processor};
use golden::scene::Scene;
use golden::trace::{format_record, TraceEvent, TraceReader, TraceRecord, TraceSide};
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;

use common::{arg, run_bin, text};

fn rtcosim(args: &[&str]) -> Output {
    run_bin(env!("CARGO_BIN_EXE_rtcosim"), args)
}

fn scratch(test: &str) -> PathBuf {
    common::scratch("cli_trace", test)
}

fn s(p: &Path) -> &str {
    arg(p)
}

#[test]
fn the_trace_file_holds_the_golden_models_events_for_the_window() {
    let dir = scratch("window");
    let (png, rtt) = (dir.join("r.png"), dir.join("t.rtt"));
    let out = rtcosim(&[
        "render",
        "--model",
        "micro",
        "--scene",
        "mirror",
        "--size",
        "80x60",
        "--threads",
        "1",
        "--out",
        s(&png),
        "--trace",
        s(&rtt),
        "--trace-window",
        "38,28,41,30",
    ]);
    assert!(
        out.status.success(),
        "rtcosim failed: {}{}",
        text(&out.stdout),
        text(&out.stderr)
    );
    assert!(png.is_file());

    // The golden model's events for the same pixels, row by row.
    let scene = Scene::builtin("mirror")
        .expect("builtin")
        .resized(80, 60, "test")
        .expect("resized");
    let proc = Processor::new(&scene);
    let mut expected: Vec<TraceRecord> = Vec::new();
    let mut writes = 0;
    for y in 28..=30 {
        for x in 38..=41 {
            let r = proc.render_pixel(x, y, |e: &TraceEvent, _: &_| {
                expected.push(TraceRecord::Event(*e))
            });
            writes += r.ops.register_writes;
            expected.push(TraceRecord::PixelEnd {
                x: x as u16,
                y: y as u16,
                rgb: r.rgb.map(f32::to_bits),
                cycles: r.cycles as u32,
            });
        }
    }
    assert_eq!(expected.len() as u64, writes + 12);

    let file = std::fs::File::open(&rtt).expect("the trace file exists");
    let reader = TraceReader::new(std::io::BufReader::new(file)).expect("a trace file");
    assert_eq!(reader.header().side, TraceSide::Golden);
    assert_eq!(reader.header().scene_hash, scene.render_hash());
    assert_eq!(reader.header().config_hash, scene.config_hash());
    assert_eq!(
        Scene::from_toml(&reader.header().scene, "header").expect("the scene reads back"),
        scene
    );
    let config = &reader.header().config;
    for field in [
        "model=micro",
        "scene=mirror",
        "size=80x60",
        "window=38,28,41,30",
    ] {
        assert!(config.contains(field), "{field} missing from {config:?}");
    }
    let records: Vec<TraceRecord> = reader
        .collect::<Result<_, _>>()
        .expect("every record reads");
    assert_eq!(records.len(), expected.len());
    assert!(
        records == expected,
        "the file's records differ from the model's"
    );
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(&format!("{writes} trace events of 12 pixels")),
        "{stdout}"
    );

    // trace-dump prints a header, one line per event, a count.
    let dump = rtcosim(&["trace-dump", s(&rtt)]);
    assert!(dump.status.success(), "{}", text(&dump.stderr));
    let dump = text(&dump.stdout);
    let lines: Vec<&str> = dump.lines().collect();
    assert_eq!(lines.len(), records.len() + 3);
    assert!(
        lines[0].starts_with('#')
            && lines[0].contains("written by the golden model")
            && lines[0].contains(&format!("{:016x}", scene.render_hash()))
    );
    assert_eq!(
        lines[2],
        format_record(&records[0], &isa::state_name, &isa::register_name)
    );
    assert!(lines[2].contains("PRI_ITOF"), "{}", lines[2]);
    assert_eq!(
        lines[lines.len() - 1],
        format!("# {writes} events, 12 pixels")
    );
}

#[test]
fn one_pixel_can_be_traced_as_x_comma_y() {
    let dir = scratch("pixel");
    let rtt = dir.join("p.rtt");
    let out = rtcosim(&[
        "render",
        "--model",
        "micro",
        "--size",
        "40x30",
        "--threads",
        "1",
        "--out",
        s(&dir.join("p.png")),
        "--trace",
        s(&rtt),
        "--trace-window",
        "20,15",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let scene = Scene::reference().resized(40, 30, "test").expect("resized");
    let r = Processor::new(&scene).render_pixel(20, 15, |_, _| {});
    let file = std::fs::File::open(&rtt).expect("the trace file exists");
    let records = TraceReader::new(file).expect("a trace file").count() as u64;
    assert_eq!(records, r.ops.register_writes + 1, "the events and the end");
}

#[test]
fn a_window_outside_the_image_is_refused_before_rendering() {
    let dir = scratch("bad-window");
    let (png, rtt) = (dir.join("r.png"), dir.join("t.rtt"));
    let out = rtcosim(&[
        "render",
        "--model",
        "micro",
        "--size",
        "80x60",
        "--out",
        s(&png),
        "--trace",
        s(&rtt),
        "--trace-window",
        "70,10,80,12",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("--trace-window 70,10,80,12 is outside the 80x60 image"),
        "{stderr}"
    );
    assert!(!png.exists() && !rtt.exists(), "nothing is written");
}

#[test]
fn bad_trace_requests_are_usage_errors() {
    let dir = scratch("usage");
    let rtt = dir.join("t.rtt");
    let cases: [(&[&str], &str); 4] = [
        // The reference renderer has no instructions.
        (
            &["--trace", s(&rtt), "--trace-window", "1,1"],
            "--trace needs --model micro",
        ),
        // Each flag needs the other.
        (
            &["--model", "micro", "--trace", s(&rtt)],
            "--trace-window <X0,Y0,X1,Y1>",
        ),
        (
            &["--model", "micro", "--trace-window", "1,1"],
            "--trace <FILE>",
        ),
        // Corners out of order.
        (
            &[
                "--model",
                "micro",
                "--trace",
                s(&rtt),
                "--trace-window",
                "5,5,4,6",
            ],
            "X0 <= X1",
        ),
    ];
    for (args, message) in cases {
        let out = rtcosim(&[&["render", "--size", "40x30"], args].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = text(&out.stderr);
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    }
    assert!(!rtt.exists());
}

#[test]
fn trace_dump_refuses_a_file_that_is_not_a_trace() {
    let dir = scratch("not-a-trace");
    let path = dir.join("x.rtt");
    std::fs::write(&path, b"hello, world").expect("writing");
    let out = rtcosim(&["trace-dump", s(&path)]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("not an rtcosim trace file"),
        "{}",
        text(&out.stderr)
    );
}
