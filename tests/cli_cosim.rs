//! `rtcosim cosim`, run as the built binary on small images: a passing run
//! exits 0 with the report, an injected fault exits 1 naming its state and
//! pixel, and bad requests (or a hung RTL) exit 2 with a message naming the
//! problem. State names other than PRI_HALF and cycle numbers are not
//! written down here: the ISA and the cycle rule change under the tests.

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
        "rtcosim cosim: scene reference (40x30",
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
