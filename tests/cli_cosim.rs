//! `rtcosim cosim`, run as the built binary on small images: a passing run
//! exits 0 with the report, an injected fault exits 1 naming its state and
//! pixel, and bad requests (or a hung RTL) exit 2 with a message naming the
//! problem. State names other than PRI_HALF and cycle numbers are not
//! written down here: the ISA and the cycle rule change under the tests.

mod common;

use std::process::{Command, Output};

fn rtcosim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtcosim"))
        .args(args)
        .output()
        .expect("running rtcosim")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn both(out: &Output) -> String {
    format!(
        "status {:?}\n--- stdout\n{}--- stderr\n{}",
        out.status.code(),
        text(&out.stdout),
        text(&out.stderr)
    )
}

/// A cosim report's pixels all agree: no divergent pixel, no event and no
/// colour differing.
fn assert_agrees(stdout: &str) {
    assert_eq!(number_in(stdout, "divergent pixels:", " ("), 0, "{stdout}");
    assert_eq!(number_in(stdout, "events:", " differ"), 0, "{stdout}");
    assert_eq!(
        number_in(stdout, "colour:", " pixels differ"),
        0,
        "{stdout}"
    );
}

/// The number before `suffix` (or at the end, for "") on the report line
/// that starts with `prefix` (after indentation), e.g.
/// `("events:", " compared")`.
fn number_in(stdout: &str, prefix: &str, suffix: &str) -> u64 {
    let line = stdout
        .lines()
        .map(str::trim_start)
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no line starting with {prefix:?} in\n{stdout}"));
    let end = if suffix.is_empty() {
        line.len()
    } else {
        line.find(suffix)
            .unwrap_or_else(|| panic!("no {suffix:?} in {line:?}"))
    };
    let before = &line[..end];
    before
        .rsplit(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no number before {suffix:?} in {line:?}"))
}

#[test]
fn a_small_reference_frame_agrees() {
    let out = rtcosim(&["cosim", "--size", "40x30", "--threads", "2"]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    let header = stdout.lines().next().expect("a header");
    for field in [
        "rtcosim cosim: compact processor, scene reference (40x30",
        "window 0,0,39,29 (1200 pixels)",
        "recip exact, sqrt exact",
        "Verilator ",
    ] {
        assert!(header.contains(field), "{field:?} missing from {header:?}");
    }
    assert!(stdout.contains(": 1200 pixels\n"), "{stdout}");
    let compared = number_in(&stdout, "events:", " compared");
    assert!(compared > 0, "{stdout}");
    assert_eq!(number_in(&stdout, "events:", " differ"), 0, "{stdout}");
    assert_eq!(number_in(&stdout, "divergent pixels:", " ("), 0);
    assert!(stdout.contains("cycles/pixel: mean "), "{stdout}");
    assert!(stdout.contains("pixels/s"), "{stdout}");
    assert!(stdout.contains("PASS"), "{stdout}");
    assert!(!stdout.contains("first divergence"), "{stdout}");
}

#[test]
fn a_window_with_method_overrides_agrees() {
    let out = rtcosim(&[
        "cosim",
        "--scene",
        "mirror",
        "--size",
        "40x30",
        "--window",
        "10,5,29,14",
        "--recip",
        "fast",
        "--sqrt",
        "fast",
        "--threads",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("window 10,5,29,14 (200 pixels), recip fast, sqrt fast, 1 thread,"),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "pixel processor (recip fast, sqrt fast), window 20x10 at (10, 5): 200 pixels"
        ),
        "{stdout}"
    );
    assert!(number_in(&stdout, "events:", " compared") > 0, "{stdout}");
}

#[test]
fn an_injected_fault_fails_the_run_at_its_state_and_first_pixel() {
    let out = rtcosim(&["cosim", "--size", "40x30", "--fault", "PRI_HALF:0x400"]);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("self-test"), "{stdout}");
    let first = stdout
        .lines()
        .find(|l| l.starts_with("first divergence: "))
        .unwrap_or_else(|| panic!("no first divergence in\n{stdout}"));
    assert!(first.contains("pixel (0, 0)"), "{first}");
    assert!(stdout.contains("\n  RTL    state PRI_HALF ("), "{stdout}");
    assert!(stdout.contains("[rtl/pp/pp_ctrl.v:"), "{stdout}");
    assert!(
        stdout.contains(", issued by golden/src/micro/program.rs:"),
        "{stdout}"
    );
    // Every pixel writes in PRI_HALF.
    assert_eq!(number_in(&stdout, "divergent pixels:", " ("), 1200);
    assert!(
        stdout.contains("FAIL: 1200 of 1200 pixels diverge"),
        "{stdout}"
    );
}

#[test]
fn bad_windows_are_refused_with_exit_2() {
    let cases: [(&str, &str); 3] = [
        (
            "30,0,40,1",
            "--window 30,0,40,1 is outside the 40x30 image (columns 0..=39, rows 0..=29)",
        ),
        ("5,5,4,6", "X0 <= X1"),
        ("1,2,3", "expected X0,Y0,X1,Y1"),
    ];
    for (window, message) in cases {
        let out = rtcosim(&["cosim", "--size", "40x30", "--window", window]);
        assert_eq!(out.status.code(), Some(2), "{window}: {}", both(&out));
        let stderr = text(&out.stderr);
        assert!(stderr.contains(message), "{window}: {stderr}");
        assert!(!text(&out.stdout).contains("PASS"), "{window}");
    }
}

#[test]
fn bad_fault_specs_are_refused_with_exit_2() {
    let cases: [(&str, &str); 4] = [
        (
            "NO_SUCH_STATE:0x400",
            "\"NO_SUCH_STATE\" is not a controller state",
        ),
        (
            "PRI_HALF:0",
            "the XOR mask \"0\" is not a nonzero 32-bit number",
        ),
        ("PRI_HALF:0xzz", "the XOR mask \"0xzz\""),
        ("PRI_HALF", "expected STATE:XOR"),
    ];
    for (fault, message) in cases {
        let out = rtcosim(&["cosim", "--size", "40x30", "--fault", fault]);
        assert_eq!(out.status.code(), Some(2), "{fault}: {}", both(&out));
        let stderr = text(&out.stderr);
        assert!(stderr.contains("--fault"), "{fault}: {stderr}");
        assert!(stderr.contains(message), "{fault}: {stderr}");
    }
}

/// No pixel finishes in 2 cycles (start, an instruction, done): a hung-RTL
/// error naming the first pixel, exit 2.
#[test]
fn a_hung_rtl_is_an_error_naming_the_pixel() {
    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "3,2",
        "--timeout-cycles",
        "2",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", both(&out));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains(
            "error: co-simulation stopped: hung RTL at pixel (3, 2): no done after 2 cycles"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("--timeout-cycles"), "{stderr}");
}

/// The watchdog on the fast processor, alone and in a top of 2: no pixel
/// finishes in 50 cycles (a barrel pixel needs its turns, thousands of
/// cycles), so the error names the pixel and where it ran: its context, and
/// in the top its processor and the instance.
#[test]
fn a_hung_fast_processor_is_an_error_naming_the_pixel_and_its_context() {
    for (procs, place) in [
        (
            None,
            " of 32 of the fast processor: no done after 51 cycles",
        ),
        (
            Some("2"),
            "(top.g_pp[0].g_fast.u_pp): no done after 51 cycles",
        ),
    ] {
        let mut args = vec![
            "cosim",
            "--size",
            "40x30",
            "--window",
            "3,2",
            "--processor",
            "fast",
            "--timeout-cycles",
            "50",
        ];
        if let Some(n) = procs {
            args.extend(["--procs", n]);
        }
        let out = rtcosim(&args);
        assert_eq!(out.status.code(), Some(2), "{}", both(&out));
        let stderr = text(&out.stderr);
        let head = match procs {
            None => "error: co-simulation stopped: hung RTL at pixel (3, 2) on context ",
            Some(_) => "error: co-simulation stopped: hung RTL at pixel (3, 2) on processor 0 of 2, context ",
        };
        assert!(stderr.contains(head), "{stderr}");
        assert!(stderr.contains(place), "{stderr}");
        assert!(stderr.contains("--timeout-cycles is 50"), "{stderr}");
    }
}

/// Width and height from a PNG's IHDR chunk.
fn png_size(path: &std::path::Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(
        &bytes[..8],
        b"\x89PNG\r\n\x1a\n",
        "{} is a PNG",
        path.display()
    );
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().expect("4 bytes"));
    (be(16), be(20))
}

#[test]
fn out_writes_frames_json_markdown_and_junit_that_say_the_same() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_cosim-out");
    let _ = std::fs::remove_dir_all(&dir);
    let run = |sub: &str, extra: &[&str]| {
        let out_dir = dir.join(sub);
        let mut args = vec![
            "cosim",
            "--size",
            "40x30",
            "--window",
            "4,3,23,12",
            "--threads",
            "2",
        ];
        args.extend(["--out", out_dir.to_str().expect("UTF-8")]);
        args.extend(extra);
        (rtcosim(&args), out_dir)
    };
    // A clean run.
    let (out, clean) = run("clean", &[]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    for f in ["rtl.png", "golden.png", "diffmap/mask-0.5.png"] {
        assert_eq!(png_size(&clean.join(f)), (20, 10), "{f}: the window's size");
    }
    // The float frames are the colours bit for bit, and agree: all-zero maps.
    let rtl = golden::frame::Frame::load_exr(&clean.join("rtl.exr")).expect("rtl.exr");
    let golden = golden::frame::Frame::load_exr(&clean.join("golden.exr")).expect("golden.exr");
    assert_eq!(rtl, golden);
    let table = std::fs::read_to_string(clean.join("diffmap/table.json")).expect("table.json");
    let table: serde_json::Value = serde_json::from_str(&table).expect("JSON");
    assert_eq!(table["differing"], 0, "{table}");
    assert_eq!(table["channels"], 600, "{table}");
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(clean.join("report.json")).expect("report.json"),
    )
    .expect("valid JSON");
    let stdout = text(&out.stdout);
    assert_eq!(json["passed"], true);
    assert_eq!(json["compare"]["counts"]["pixels"], 200);
    assert_eq!(
        json["compare"]["counts"]["events_compared"],
        number_in(&stdout, "events:", " compared")
    );
    let cycles = &json["compare"]["a_cycles_per_pixel"];
    let histogram_pixels: u64 = cycles["histogram"]
        .as_array()
        .expect("histogram")
        .iter()
        .map(|b| b["pixels"].as_u64().expect("count"))
        .sum();
    assert_eq!(histogram_pixels, 200);
    assert!(cycles["min"].as_u64() <= cycles["max"].as_u64());
    let junit = std::fs::read_to_string(clean.join("junit.xml")).expect("junit.xml");
    assert!(junit.contains(r#"tests="1" failures="0""#), "{junit}");
    assert!(
        junit.contains(r#"<testcase name="reference recip=exact sqrt=exact""#),
        "{junit}"
    );
    let md = std::fs::read_to_string(clean.join("report.md")).expect("report.md");
    assert!(
        md.starts_with("# rtcosim cosim: reference recip=exact sqrt=exact — PASS"),
        "{md}"
    );

    // A failing run: the failure and its first divergence in every file.
    let (out, failed) = run("fault", &["--fault", "PRI_HALF:0x400", "--recip", "fast"]);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(failed.join("report.json")).expect("report.json"),
    )
    .expect("valid JSON");
    assert_eq!(json["passed"], false);
    assert_eq!(json["fault"], "PRI_HALF:0x400");
    let d = &json["compare"]["first_divergence"];
    assert_eq!(d["pixel"], serde_json::json!([4, 3]));
    assert_eq!(d["a"]["state"], "PRI_HALF");
    assert!(
        d["a"]["verilog"]
            .as_str()
            .is_some_and(|v| v.starts_with("rtl/pp/pp_ctrl.v:")),
        "{d}"
    );
    assert!(
        d["b"]["rust"]
            .as_str()
            .is_some_and(|v| v.starts_with("golden/src/micro/program.rs:")),
        "{d}"
    );
    let junit = std::fs::read_to_string(failed.join("junit.xml")).expect("junit.xml");
    assert!(junit.contains(r#"failures="1""#), "{junit}");
    assert!(
        junit.contains(r#"<testcase name="reference recip=fast sqrt=exact""#),
        "{junit}"
    );
    assert!(
        junit.contains("<failure message=\"200 of 200 pixels diverge"),
        "{junit}"
    );
    assert!(junit.contains("pixel (4, 3) event #"), "{junit}");
    let md = std::fs::read_to_string(failed.join("report.md")).expect("report.md");
    assert!(
        md.contains("— FAIL") && md.contains("## First divergence"),
        "{md}"
    );
}

/// Colour over 1 is reported, not silently clipped: the overexposed scene
/// without its exposure makes `cosim` (and `render`) print the saturation
/// warning with the count; with its exposure neither prints one.
#[test]
fn colours_over_1_are_warned_about_unless_the_scene_sets_an_exposure() {
    let text_of = golden::scene::Scene::builtin("overexposed")
        .expect("builtin")
        .to_toml();
    assert!(text_of.contains("exposure = -1.5\n"), "{text_of}");
    let dir = std::env::temp_dir().join(format!("rtcosim-cli-exposure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let plain = dir.join("plain.toml");
    std::fs::write(&plain, text_of.replace("exposure = -1.5\n", "")).expect("written");
    let plain = plain.to_str().expect("utf-8 path");
    let png = dir.join("f.png");
    let png = png.to_str().expect("utf-8 path");
    for (scene, warned) in [("overexposed", false), (plain, true)] {
        for args in [
            vec![
                "cosim",
                "--scene",
                scene,
                "--size",
                "16x12",
                "--threads",
                "2",
            ],
            vec!["render", "--scene", scene, "--size", "16x12", "--out", png],
        ] {
            let out = rtcosim(&args);
            assert_eq!(out.status.code(), Some(0), "{args:?}: {}", both(&out));
            let stdout = text(&out.stdout);
            let line = stdout.lines().find(|l| l.starts_with("warning: "));
            match (warned, line) {
                (true, Some(l)) => assert!(
                    l.contains("of 192 pixels have a channel over 1") && l.contains("exposure"),
                    "{args:?}: {l}"
                ),
                (false, None) => {}
                _ => panic!("{args:?}: warning expected {warned}:\n{stdout}"),
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--procs 4`: the same report through the top, with its frame cycles and
/// dispatcher idle share; the fault self-test fails through it; a watchdog
/// names the processor.
#[test]
fn the_top_with_four_processors_agrees_and_reports_its_cycles() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_cosim-top");
    let _ = std::fs::remove_dir_all(&dir);
    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "0,0,39,7",
        "--procs",
        "4",
        "--out",
        dir.to_str().expect("UTF-8"),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("through the top with 4 processors"),
        "{stdout}"
    );
    assert_eq!(number_in(&stdout, "divergent pixels:", " ("), 0, "{stdout}");
    let frame = number_in(&stdout, "top: 4 processors,", " frame cycles");
    let rtl_cycles = number_in(&stdout, "cycles: RTL", ", golden");
    // Four processors: between a quarter of the pixels' cycles and half.
    assert!(
        frame * 4 >= rtl_cycles && frame * 2 < rtl_cycles,
        "{stdout}"
    );
    assert!(stdout.contains("% dispatcher idle"), "{stdout}");
    // report.json carries the same top figures and the throughput.
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("report.json")).expect("report.json"),
    )
    .expect("valid JSON");
    assert_eq!(json["top"]["processors"], 4, "{json}");
    assert_eq!(json["top"]["frame_cycles"], frame, "{json}");
    assert_eq!(json["top"]["pixel_cycles"], rtl_cycles, "{json}");
    let idle = json["top"]["dispatcher_idle_share"]
        .as_f64()
        .expect("idle share");
    let idle_text = stdout
        .split(" frame cycles (first coordinate in to last result out), ")
        .nth(1)
        .and_then(|rest| rest.split('%').next())
        .and_then(|p| p.parse::<f64>().ok())
        .expect("the idle share in the text");
    assert!(
        (100.0 * idle - idle_text).abs() <= 0.05,
        "{idle} vs {idle_text}%"
    );
    let pixels_per_second = json["throughput"]["pixels_per_second"]
        .as_f64()
        .expect("throughput");
    let seconds = json["seconds"].as_f64().expect("seconds");
    assert!(
        (pixels_per_second * seconds - 320.0).abs() < 1e-6 * 320.0,
        "{json}"
    );
    let _ = std::fs::remove_dir_all(&dir);

    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "0,0,39,3",
        "--procs",
        "4",
        "--fault",
        "PRI_HALF:0x400",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    assert!(
        text(&out.stdout).contains("first divergence: pixel (0, 0)"),
        "{}",
        both(&out)
    );

    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--procs",
        "4",
        "--timeout-cycles",
        "20",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", both(&out));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("on processor 0 of 4 (top.g_pp[0].g_compact.u_pp)"),
        "{stderr}"
    );

    let out = rtcosim(&["cosim", "--size", "40x30", "--procs", "3"]);
    assert_eq!(out.status.code(), Some(2), "{}", both(&out));
    assert!(
        text(&out.stderr).contains("top of 3 compact pixel processors")
            && text(&out.stderr).contains("RTCOSIM_TOPS=3:exact:exact cargo build --release"),
        "{}",
        both(&out)
    );
}

/// The cycles golden::micro predicts for the pixels of `window` (x0, y0,
/// x1, y1 inclusive) of the reference scene at 40x30.
fn golden_cycles(x0: u32, y0: u32, x1: u32, y1: u32) -> u64 {
    let scene = golden::scene::Scene::builtin("reference")
        .expect("builtin")
        .resized(40, 30, "reference")
        .expect("valid");
    let p = golden::micro::Processor::new(&scene);
    (y0..=y1)
        .flat_map(|y| (x0..=x1).map(move |x| (x, y)))
        .map(|(x, y)| p.render_pixel(x, y, |_, _| {}).cycles)
        .sum()
}

/// `--stall P` through the top with 4 processors: out_ready is low in P% of
/// the cycles, so every one of the N results, each taking a cycle of its
/// own with out_ready high, waits for the 1% of cycles that have it at
/// P = 99: the frame takes about 100 N cycles (standard deviation about
/// 10 sqrt(N) x 10), where without backpressure it takes about a quarter
/// of the pixels' cycles (about 40 N). Every pixel still agrees with
/// golden, events, colour and cycles, and the pixels' own cycles are
/// golden's with or without the stall.
#[test]
fn stall_holds_the_result_stream_back_and_every_pixel_still_agrees() {
    let (x1, y1) = (23, 15);
    let pixels = u64::from((x1 + 1) * (y1 + 1));
    let golden = golden_cycles(0, 0, x1, y1);
    let window = format!("0,0,{x1},{y1}");
    let run = |stall: &str| {
        let out = rtcosim(&[
            "cosim", "--size", "40x30", "--window", &window, "--procs", "4", "--stall", stall,
        ]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "--stall {stall}: {}",
            both(&out)
        );
        let stdout = text(&out.stdout);
        assert_agrees(&stdout);
        assert_eq!(
            number_in(&stdout, "cycles: RTL", ", golden"),
            golden,
            "{stdout}"
        );
        let frame = number_in(&stdout, "top: 4 processors,", " frame cycles");
        // The idle share is 1 - (the pixels' cycles) / (4 x frame cycles).
        let idle = stdout
            .split(" frame cycles (first coordinate in to last result out), ")
            .nth(1)
            .and_then(|rest| rest.split('%').next())
            .and_then(|p| p.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no idle share in\n{stdout}"));
        let want = 100.0 * (1.0 - golden as f64 / (4.0 * frame as f64));
        assert!((idle - want).abs() <= 0.05, "{idle}% vs {want}%\n{stdout}");
        let events = number_in(&stdout, "events:", " compared");
        (stdout, frame, events)
    };
    let (free, free_frame, free_events) = run("0");
    assert!(
        !free.contains("held back"),
        "no stall, no mention of one:\n{free}"
    );
    let (held, held_frame, held_events) = run("99");
    assert!(
        held.lines().next().is_some_and(|l| l.contains(
            ", through the top with 4 processors (result stream held back 99% of cycles), "
        )),
        "{held}"
    );
    assert_eq!(held_events, free_events);
    // Four processors: at least a quarter of the pixels' cycles.
    assert!(4 * free_frame >= golden, "{free}");
    // Three quarters of the expected 100 N: more than 5 standard
    // deviations below it, and above what the frame takes without a stall.
    let bound = 75 * pixels;
    assert!(free_frame < bound, "{free_frame} >= {bound}\n{free}");
    assert!(held_frame >= bound, "{held_frame} < {bound}\n{held}");
}

/// `--stall P --stall-burst B` on the bare fast processor: the stream held
/// back in runs of up to B cycles, so that the result queue fills; every
/// pixel agrees with golden, and the header says how it was held back.
#[test]
fn stall_bursts_hold_the_fast_result_stream_back_and_every_pixel_agrees() {
    let out = rtcosim(&[
        "cosim",
        "--processor",
        "fast",
        "--size",
        "40x30",
        "--window",
        "0,0,19,5",
        "--stall",
        "50",
        "--stall-burst",
        "20000",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.lines().next().is_some_and(|l| l
            .contains("(result stream held back 50% of cycles, in stalls of 1 to 20000 cycles)")),
        "{stdout}"
    );
    assert_agrees(&stdout);
    // Each pixel's own cycles are the barrel rule's with the refused takes.
    assert!(stdout.contains(" (0 pixels differ)\n"), "{stdout}");
    assert_eq!(
        number_in(&stdout, "fast pixel processor", " pixels"),
        120,
        "{stdout}"
    );
}

/// Bad --stall values: exit 2 naming the option, before anything runs.
#[test]
fn bad_stall_values_are_refused_with_exit_2() {
    let cases: [(&[&str], &str); 7] = [
        (
            &["--procs", "4", "--stall", "100"],
            "invalid value '100' for '--stall <PERCENT>': 100 is not in 0..=99",
        ),
        (
            &["--procs", "4", "--stall", "-1"],
            "invalid value '-1' for '--stall <PERCENT>'",
        ),
        (
            &["--procs", "4", "--stall", "half"],
            "invalid value 'half' for '--stall <PERCENT>'",
        ),
        (
            &["--procs", "4", "--stall", "5%"],
            "invalid value '5%' for '--stall <PERCENT>'",
        ),
        (
            &["--stall", "50"],
            "--stall holds back a result stream, which the compact pixel processor (recip \
             exact, sqrt exact) does not have: it needs --procs or a processor with streams \
             (--processor fast)",
        ),
        (
            &["--procs", "4", "--stall", "50", "--stall-burst", "0"],
            "invalid value '0' for '--stall-burst <CYCLES>': 0 is not in 1..=1000000",
        ),
        (
            &["--procs", "4", "--stall-burst", "100"],
            "--stall-burst 100 sets how long each stall lasts: it needs --stall PERCENT",
        ),
    ];
    for (args, message) in cases {
        let mut all = vec!["cosim", "--size", "40x30", "--window", "0,0"];
        all.extend(args);
        common::assert_refused(&all, &[message]);
    }
}

/// The speed line of a report: its simulated cycles per second are the
/// frame cycles the report counts (the tiles' first coordinate in to last
/// result out, summed) over its wall time, not the pixels' cycles summed.
fn assert_speed_is_frame_cycles_over_wall_time(stdout: &str) {
    let frame = number_in(stdout, "32 contexts,", " frame cycles (first coordinate");
    let speed = stdout
        .lines()
        .find(|l| l.contains(" simulated cycles/s ("))
        .unwrap_or_else(|| panic!("no speed line in\n{stdout}"));
    let field = |after: &str, before: &str| -> f64 {
        let from = speed.find(after).expect("the field") + after.len();
        let to = from + speed[from..].find(before).expect("its end");
        speed[from..to]
            .trim()
            .parse()
            .unwrap_or_else(|e| panic!("{speed}: {e}"))
    };
    let seconds = field(" pixels in ", " s: ");
    let m_per_s = field("pixels/s, ", " M simulated cycles/s");
    let counted = field("cycles/s (", " frame cycles;");
    assert_eq!(counted as u64, frame, "{speed}");
    let pixel_cycles = number_in(stdout, "cycles: RTL", ", golden") as f64;
    assert!(pixel_cycles > 2.0 * frame as f64, "{stdout}");
    // The line rounds seconds to 0.01 and the speed to 0.01 M.
    let lo = frame as f64 / (seconds + 0.005) / 1e6 - 0.005;
    let hi = frame as f64 / (seconds - 0.005).max(1e-3) / 1e6 + 0.005;
    assert!(
        (lo..=hi).contains(&m_per_s),
        "{speed}: not {frame} / {seconds} s"
    );
}

/// The fast processor through the binary: a window agrees in events,
/// colours and cycles, the report names the processor and says the frame
/// took the cycles the barrel rule predicts; an injected fault fails the
/// run; and the choices it cannot take are refused, naming why.
#[test]
fn the_fast_processor_agrees_and_its_bad_requests_are_refused() {
    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "4,4,23,11",
        "--processor",
        "fast",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout
            .lines()
            .next()
            .is_some_and(|l| l.starts_with("rtcosim cosim: fast processor, ")
                && l.contains(", 32 contexts, ")),
        "{stdout}"
    );
    assert!(
        stdout.contains("fast pixel processor (recip exact, sqrt exact)"),
        "{stdout}"
    );
    assert!(stdout.contains("as the barrel rule predicts"), "{stdout}");
    assert_eq!(number_in(&stdout, "events:", " differ"), 0, "{stdout}");
    assert!(number_in(&stdout, "events:", " compared") > 0, "{stdout}");
    assert!(stdout.contains("PASS: "), "{stdout}");
    assert_speed_is_frame_cycles_over_wall_time(&stdout);
    // The check fails on a speed that is not the frame cycles' (here, the
    // pixels' cycles summed over the same time).
    let speed = stdout
        .lines()
        .find(|l| l.contains(" M simulated"))
        .expect("a speed line");
    let seconds: f64 = speed
        .split(" pixels in ")
        .nth(1)
        .and_then(|r| r.split(" s: ").next())
        .expect("s")
        .parse()
        .expect("seconds");
    let summed = number_in(&stdout, "cycles: RTL", ", golden") as f64 / seconds.max(0.01) / 1e6;
    let m = speed
        .split("pixels/s, ")
        .nth(1)
        .and_then(|r| r.split(" M simulated").next())
        .expect("m");
    let wrong = stdout.replace(
        &format!("{m} M simulated"),
        &format!("{summed:.2} M simulated"),
    );
    assert!(
        std::panic::catch_unwind(|| assert_speed_is_frame_cycles_over_wall_time(&wrong)).is_err()
    );

    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "4,4,7,5",
        "--processor",
        "fast",
        "--fault",
        "PRI_HALF:0x400",
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    assert!(
        text(&out.stdout).contains("FAIL: 8 of 8 pixels diverge"),
        "{}",
        both(&out)
    );

    // Through the top of two fast processors, the result stream held back.
    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "0,4,39,11",
        "--processor",
        "fast",
        "--procs",
        "2",
        "--stall",
        "50",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.lines().next().is_some_and(|l| l.contains(
            ", through the top with 2 processors of 32 contexts (result stream held back 50% of cycles), "
        )),
        "{stdout}"
    );
    assert!(
        stdout.contains("top: 2 processors of 32 contexts, 2 tiles: ")
            && stdout.contains("as the top's rule predicts"),
        "{stdout}"
    );
    assert_eq!(number_in(&stdout, "events:", " differ"), 0, "{stdout}");
    assert!(stdout.contains("PASS: "), "{stdout}");

    // A top not built: found when the model is built, named with the way
    // to build it.
    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "0,0",
        "--processor",
        "fast",
        "--procs",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", both(&out));
    assert!(
        text(&out.stderr).contains(
            "top of 3 fast pixel processors (recip exact, sqrt exact): not a model of this \
             build: build it by name: RTCOSIM_TOPS=fast:3:exact:exact cargo build --release"
        ),
        "{}",
        both(&out)
    );

    let cases: [(&[&str], &str); 4] = [
        (
            &["--processor", "fastest"],
            "invalid value 'fastest' for '--processor <PROCESSOR>'",
        ),
        (
            &["--procs", "9"],
            "--procs 9: top of 9 compact pixel processors (recip exact, sqrt exact): a top of compact processors has 1 to 8 of them",
        ),
        (
            &["--processor", "fast", "--procs", "65"],
            "invalid value '65' for '--procs <N>'",
        ),
        (
            &["--processor", "fast", "--procs", "2", "--coverage", "cov"],
            "the top of --procs has no coverage model",
        ),
    ];
    for (args, message) in cases {
        let mut all = vec!["cosim", "--size", "40x30", "--window", "0,0"];
        all.extend(args);
        common::assert_refused(&all, &[message]);
    }
}

/// `cosim --processor fast --no-exp-unit`: the fast processor built without
/// its exponential (EXPOSURE = 0) agrees on a scene without exposure, and
/// the report says which build ran; an injected fault fails it; a scene
/// with exposure is refused by name before anything runs, as are the
/// choices the flag cannot go with.
#[test]
fn the_fast_processor_without_its_exponential_agrees_and_refuses_exposure() {
    let base = [
        "cosim",
        "--size",
        "40x30",
        "--processor",
        "fast",
        "--no-exp-unit",
    ];
    let out = rtcosim(&[&base[..], &["--window", "4,4,23,11"]].concat());
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.lines().next().is_some_and(|l| l
            .starts_with("rtcosim cosim: fast processor without its exponential, scene reference")),
        "{stdout}"
    );
    assert!(
        stdout.contains("fast pixel processor without its exponential (recip exact, sqrt exact)")
            && stdout.contains("as the barrel rule predicts"),
        "{stdout}"
    );
    assert_eq!(number_in(&stdout, "events:", " differ"), 0, "{stdout}");
    assert!(number_in(&stdout, "events:", " compared") > 0, "{stdout}");
    assert!(stdout.contains("PASS: "), "{stdout}");

    let out = rtcosim(
        &[
            &base[..],
            &["--window", "4,4,7,5", "--fault", "PRI_HALF:0x400"],
        ]
        .concat(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    assert!(
        text(&out.stdout).contains("FAIL: 8 of 8 pixels diverge"),
        "{}",
        both(&out)
    );

    common::assert_refused(
        &[
            "cosim",
            "--size",
            "40x30",
            "--window",
            "0,0",
            "--no-exp-unit",
        ],
        &[
            "--no-exp-unit: compact pixel processor without its exponential (recip exact, sqrt \
             exact): the compact processor always has its exponential",
        ],
    );
    let cases: [(&[&str], &str); 2] = [
        (
            &["--scene", "overexposed"],
            "--no-exp-unit: scene overexposed sets an exposure (render.exposure = -1.5), which \
             the fast processor without its exponential cannot draw",
        ),
        (
            &["--procs", "2"],
            "--procs 2 --no-exp-unit: top of 2 fast pixel processors without its exponential \
             (recip exact, sqrt exact): the tops of fast processors are built with the \
             exponential only",
        ),
    ];
    for (args, message) in cases {
        let mut all = base.to_vec();
        all.extend(["--window", "0,0"]);
        all.extend(args);
        common::assert_refused(&all, &[message]);
    }
}
