//! `rtcosim fp-check`, run as the built binary with small operand counts:
//! one row per unit in the order asked for, the cycle column held to the
//! latencies golden::fp promises, --count random operands on top of the
//! edge cases, and bad requests refused with exit 2 naming the option.

mod common;

use common::{assert_refused, both, rtcosim, text};
use golden::fp::{exp_latency, pipelined, recip_latency, sqrt_latency, Method};

/// One row of the table: unit, cycles, operands, mismatches, worst error
/// in ULPs.
#[derive(Debug, PartialEq, Eq)]
struct Row {
    unit: String,
    cycles: String,
    operands: u64,
    mismatches: u64,
    worst_ulps: u64,
}

/// The rows of the table between its column header and the blank line
/// after it.
fn rows(stdout: &str) -> Vec<Row> {
    let mut lines = stdout.lines().skip_while(|l| !l.starts_with("unit "));
    let header: Vec<&str> = lines
        .next()
        .unwrap_or_else(|| panic!("no column header in\n{stdout}"))
        .split_whitespace()
        .collect();
    assert_eq!(
        header,
        [
            "unit",
            "cycles",
            "operands",
            "mismatch",
            "worst",
            "error",
            "Mevals/s/model"
        ],
        "{stdout}"
    );
    lines
        .take_while(|l| !l.is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(f.len(), 7, "{l:?}");
            assert_eq!(f[5], "ulp", "{l:?}");
            let number = |s: &str| {
                s.parse::<u64>()
                    .unwrap_or_else(|_| panic!("{s:?} in {l:?}"))
            };
            assert!(f[6].parse::<f64>().is_ok_and(|m| m > 0.0), "{l:?}");
            Row {
                unit: f[0].into(),
                cycles: f[1].into(),
                operands: number(f[2]),
                mismatches: number(f[3]),
                worst_ulps: number(f[4]),
            }
        })
        .collect()
}

/// Runs `fp-check` with `args`, expecting it to pass; its stdout.
fn passing(args: &[&str]) -> String {
    let mut all = vec!["fp-check"];
    all.extend(args);
    let out = rtcosim(&all);
    assert_eq!(out.status.code(), Some(0), "{args:?}: {}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.ends_with("\nall units agree with golden::fp\n"),
        "{stdout}"
    );
    stdout
}

/// Every unit, in the documented order, each with the latency golden::fp
/// promises (combinational units: "comb"), 0 mismatches, 0 ULP from the
/// correctly rounded result for the exact units and at most 1 for the
/// fast ones and fp_exp; --count adds exactly that many operands to the
/// edge cases of each unit.
#[test]
fn every_unit_agrees_with_the_promised_latency_and_count() {
    let stdout = passing(&["--count", "3000", "--seed", "5", "--threads", "2"]);
    let header = stdout.lines().next().expect("a header");
    assert!(
        header.starts_with(
            "rtcosim fp-check: 16 units, 3000 random operands, seed 5, 2 threads, Verilator "
        ),
        "{header}"
    );
    let with = rows(&stdout);
    let comb = || "comb".to_string();
    let cycles = |n: u32| n.to_string();
    // (unit, cycles, largest error allowed in ULPs)
    let want = [
        ("fp_add", comb(), 0),
        ("fp_mul", comb(), 0),
        ("fp_itof", comb(), 0),
        ("fp_recip(exact)", cycles(recip_latency(Method::Exact)), 0),
        ("fp_recip(fast)", cycles(recip_latency(Method::Fast)), 1),
        ("fp_sqrt(exact)", cycles(sqrt_latency(Method::Exact)), 0),
        ("fp_sqrt(fast)", cycles(sqrt_latency(Method::Fast)), 1),
        ("fp_exp", cycles(exp_latency()), 1),
        // The fast processor's pipelined units (rtl/fast/).
        ("fast_fp_add", cycles(pipelined::ADD_LATENCY), 0),
        ("fast_fp_mul", cycles(pipelined::MUL_LATENCY), 0),
        ("fast_fp_itof", cycles(pipelined::ITOF_LATENCY), 0),
        ("fast_fp_recip(exact)", cycles(pipelined::RECIP_LATENCY), 0),
        ("fast_fp_recip(fast)", cycles(pipelined::RECIP_LATENCY), 1),
        ("fast_fp_sqrt(exact)", cycles(pipelined::SQRT_LATENCY), 0),
        ("fast_fp_sqrt(fast)", cycles(pipelined::SQRT_LATENCY), 1),
        ("fast_fp_exp", cycles(pipelined::EXP_LATENCY), 1),
    ];
    let names: Vec<&str> = with.iter().map(|r| r.unit.as_str()).collect();
    let want_names: Vec<&str> = want.iter().map(|w| w.0).collect();
    assert_eq!(names, want_names, "{stdout}");
    for (row, (unit, cycles, ulps)) in with.iter().zip(&want) {
        assert_eq!(&row.cycles, cycles, "{unit}: {stdout}");
        assert_eq!(row.mismatches, 0, "{unit}: {stdout}");
        assert!(row.worst_ulps <= *ulps, "{unit}: {stdout}");
    }

    // Edge cases alone: each unit has some, and --count adds exactly its
    // number of random operands to them.
    let without = rows(&passing(&["--count", "0", "--threads", "2"]));
    assert_eq!(without.len(), with.len());
    for (a, b) in without.iter().zip(&with) {
        assert_eq!(a.unit, b.unit);
        assert!(a.operands > 0, "{a:?}");
        assert_eq!(b.operands, a.operands + 3000, "{b:?} against {a:?}");
    }
}

/// --unit picks units (a list, or the option repeated) in the order given;
/// one unit and one thread are singular; --exhaustive leaves a binary unit
/// on --count random operands.
#[test]
fn units_are_checked_as_picked() {
    let stdout = passing(&[
        "--unit",
        "sqrt-fast,add",
        "--unit",
        "itof",
        "--count",
        "100",
    ]);
    assert!(
        stdout.starts_with("rtcosim fp-check: 3 units, 100 random operands, seed 1, "),
        "{stdout}"
    );
    let names: Vec<String> = rows(&stdout).into_iter().map(|r| r.unit).collect();
    assert_eq!(names, ["fp_sqrt(fast)", "fp_add", "fp_itof"], "{stdout}");

    let stdout = passing(&["--unit", "mul", "--count", "7", "--threads", "1"]);
    assert!(
        stdout.starts_with("rtcosim fp-check: 1 unit, 7 random operands, seed 1, 1 thread, "),
        "{stdout}"
    );
    let random = rows(&stdout)[0].operands;

    let stdout = passing(&[
        "--unit",
        "mul",
        "--count",
        "7",
        "--exhaustive",
        "--threads",
        "1",
    ]);
    assert!(
        stdout.starts_with("rtcosim fp-check: 1 unit, all 2^32 inputs (unary), seed 1, "),
        "{stdout}"
    );
    assert_eq!(rows(&stdout)[0].operands, random, "{stdout}");
}

/// Bad options: exit 2, the option and the bad value named on stderr,
/// nothing checked, no panic.
#[test]
fn bad_options_are_refused_with_exit_2() {
    let cases: [(&[&str], &[&str]); 7] = [
        (
            &["--unit", "div"],
            &["invalid value 'div' for '--unit", "recip-exact"],
        ),
        (
            &["--unit", "add,"],
            &["a value is required for '--unit <UNIT>' but none was supplied"],
        ),
        (
            &["--count", "-5"],
            &["invalid value '-5' for '--count <COUNT>'"],
        ),
        (
            &["--count", "lots"],
            &["invalid value 'lots' for '--count <COUNT>'"],
        ),
        (
            &["--count", "18446744073709551616"],
            &["invalid value '18446744073709551616' for '--count <COUNT>'"],
        ),
        (
            &["--seed", "0x"],
            &["invalid value '0x' for '--seed <SEED>'"],
        ),
        (
            &["--threads", "0"],
            &["invalid value '0' for '--threads <THREADS>'"],
        ),
    ];
    for (args, messages) in cases {
        let mut all = vec!["fp-check"];
        all.extend(args);
        assert_refused(&all, messages);
    }
}
