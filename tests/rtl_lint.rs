//! `verilator --lint-only -Wall` is clean on every top module of rtl/, with
//! every METHOD (and every N of the top) and with and without the trace port, using the Verilator the
//! models were built with. Every file of rtl/fp and rtl/pp is read each time,
//! as a reviewer would lint the tree.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Lints every file of rtl/ with `top` as the top module, or, with `None`,
/// as Verilator finds it (which warns if the tree has more than one top).
fn lint(top: Option<&str>, params: &[&str]) {
    lint_tree(common::rtl_tree(), top, params);
}

/// [`lint`] over the files of `tree` (`common::rtl_tree`, `fast_tree`).
fn lint_tree(tree: (Vec<PathBuf>, Vec<PathBuf>), top: Option<&str>, params: &[&str]) {
    let (ok, stderr) = verilate_lint_tree(tree, top, params);
    assert!(
        ok && stderr.trim().is_empty(),
        "lint of {} {params:?}:\n{stderr}",
        top.unwrap_or("rtl/")
    );
}

/// Runs `verilator --lint-only -Wall` over every file of rtl/: whether it
/// succeeded, and what it printed.
fn verilate_lint(top: Option<&str>, params: &[&str]) -> (bool, String) {
    verilate_lint_tree(common::rtl_tree(), top, params)
}

fn verilate_lint_tree(
    (dirs, files): (Vec<PathBuf>, Vec<PathBuf>),
    top: Option<&str>,
    params: &[&str],
) -> (bool, String) {
    let mut cmd = Command::new(env!("RTCOSIM_VERILATOR_BIN"));
    let root = env!("RTCOSIM_VERILATOR_ROOT");
    if !root.is_empty() {
        cmd.env("VERILATOR_ROOT", root);
    }
    let out = cmd
        .args(["--lint-only", "-Wall"])
        .args(top.map(|t| ["--top-module", t]).into_iter().flatten())
        .args(dirs.iter().map(|d| format!("-I{}", d.display())))
        .args(params)
        .args(&files)
        .output()
        .expect("running verilator");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn combinational_units_lint_clean() {
    for top in ["fp_add", "fp_mul", "fp_itof"] {
        lint(Some(top), &[]);
    }
}

/// The fast processor's pipelined units, over rtl/fast and rtl/fp. (Not
/// yet part of the whole-tree lint below: until the fast processor
/// instantiates them they are top modules of their own.)
#[test]
fn pipelined_units_lint_clean() {
    for top in [
        "fast_fp_add",
        "fast_fp_mul",
        "fast_fp_itof",
        "fast_fp_unpack",
        "fast_fp_exp",
    ] {
        lint_tree(common::fast_tree(), Some(top), &[]);
    }
    for method in golden::fp::Method::ALL {
        let method = format!("-GMETHOD={}", method.code());
        for top in ["fast_fp_recip", "fast_fp_sqrt"] {
            lint_tree(common::fast_tree(), Some(top), &[&method]);
        }
    }
}

/// The parameters of every build of the fast processor's ALU: each
/// method pair, with and without exposure.
fn fast_builds() -> Vec<[String; 3]> {
    let mut builds = Vec::new();
    for recip in golden::fp::Method::ALL {
        for sqrt in golden::fp::Method::ALL {
            for exposure in [0, 1] {
                builds.push([
                    format!("-GRECIP_METHOD={}", recip.code()),
                    format!("-GSQRT_METHOD={}", sqrt.code()),
                    format!("-GEXPOSURE={exposure}"),
                ]);
            }
        }
    }
    builds
}

/// The fast processor's parts built so far: the ALU in every method pair,
/// with and without exposure, and the register file at every stack depth.
#[test]
fn fast_processor_parts_lint_clean() {
    for params in fast_builds() {
        let params: Vec<&str> = params.iter().map(String::as_str).collect();
        lint_tree(common::fast_tree(), Some("fast_alu"), &params);
    }
    for depth in 1..=8 {
        let depth = format!("-GSTACK_DEPTH={depth}");
        lint_tree(common::fast_tree(), Some("fast_regfile"), &[&depth]);
    }
    lint_tree(
        common::fast_tree(),
        Some("fast_regfile"),
        &["-GREFRACTION=0"],
    );
}

/// The fast processor (rtl/fast/fast_pp.v with its controller): every
/// method pair with and without exposure, with the trace port (as the
/// harness verilates it) and without (as it is synthesized), and the
/// stack depths at both ends.
#[test]
fn fast_processor_lints_clean() {
    for params in fast_builds() {
        let mut params: Vec<&str> = params.iter().map(String::as_str).collect();
        lint_tree(common::fast_tree(), Some("fast_pp"), &params);
        params.push("-DPP_TRACE");
        lint_tree(common::fast_tree(), Some("fast_pp"), &params);
    }
    for depth in [1, 8] {
        let depth = format!("-GSTACK_DEPTH={depth}");
        lint_tree(
            common::fast_tree(),
            Some("fast_pp"),
            &[&depth, "-DPP_TRACE"],
        );
    }
    // Without refraction (REFRACTION = 0), with and without the trace port.
    lint_tree(common::fast_tree(), Some("fast_pp"), &["-GREFRACTION=0"]);
    lint_tree(
        common::fast_tree(),
        Some("fast_pp"),
        &["-GREFRACTION=0", "-DPP_TRACE"],
    );
}

/// The latencies in rtl/fast/fast_defs.vh are the ones golden promises
/// (golden::fp::pipelined), which the units' test reads the units at.
#[test]
fn fast_defs_latencies_match_golden() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl/fast/fast_defs.vh");
    let text = std::fs::read_to_string(&path).expect("reading fast_defs.vh");
    let defined = |name: &str| -> u32 {
        text.lines()
            .find_map(|line| {
                let mut w = line.split_whitespace();
                match (w.next(), w.next(), w.next()) {
                    (Some("`define"), Some(n), Some(v)) if n == name => v.parse().ok(),
                    _ => None,
                }
            })
            .unwrap_or_else(|| panic!("{}: no numeric `define {name}", path.display()))
    };
    use golden::fp::pipelined as p;
    assert_eq!(defined("FAST_ADD_LATENCY"), p::ADD_LATENCY, "fast_fp_add");
    assert_eq!(defined("FAST_MUL_LATENCY"), p::MUL_LATENCY, "fast_fp_mul");
    assert_eq!(
        defined("FAST_ITOF_LATENCY"),
        p::ITOF_LATENCY,
        "fast_fp_itof"
    );
    assert_eq!(
        defined("FAST_RECIP_LATENCY"),
        p::RECIP_LATENCY,
        "fast_fp_recip"
    );
    assert_eq!(
        defined("FAST_SQRT_LATENCY"),
        p::SQRT_LATENCY,
        "fast_fp_sqrt"
    );
    assert_eq!(defined("FAST_EXP_LATENCY"), p::EXP_LATENCY, "fast_fp_exp");
    use golden::micro::alu::fast_latency;
    assert_eq!(defined("FAST_ALU_LATENCY"), fast_latency(true), "fast_alu");
    assert_eq!(
        defined("FAST_ALU_LATENCY_NOEXP"),
        fast_latency(false),
        "fast_alu, EXPOSURE = 0"
    );
}

#[test]
fn fp_exp_lints_clean() {
    lint(Some("fp_exp"), &[]);
}

#[test]
fn multi_cycle_units_lint_clean_with_every_method() {
    for top in ["fp_recip", "fp_sqrt"] {
        for method in golden::fp::Method::ALL {
            lint(Some(top), &[&format!("-GMETHOD={}", method.code())]);
        }
    }
}

/// A METHOD that names no method stops elaboration, naming the parameter,
/// instead of running as the fast method.
#[test]
fn an_unknown_method_fails_elaboration() {
    for top in ["fp_recip", "fp_sqrt"] {
        for bad in [2, 3, -1] {
            let (ok, stderr) = verilate_lint(Some(top), &[&format!("-GMETHOD={bad}")]);
            assert!(!ok, "{top} with METHOD={bad} elaborated:\n{stderr}");
            assert!(
                stderr.contains("fp_error_METHOD_must_be_FP_METHOD_EXACT_or_FP_METHOD_FAST"),
                "{top} METHOD={bad}: {stderr}"
            );
        }
    }
    let (ok, stderr) = verilate_lint(Some("pixel_processor"), &["-GRECIP_METHOD=5"]);
    assert!(
        !ok,
        "pixel_processor with RECIP_METHOD=5 elaborated:\n{stderr}"
    );
}

#[test]
fn the_whole_rtl_tree_lints_clean_as_one_design() {
    // What a reviewer runs over rtl/: every file at once, no top named, so a
    // second top module (MULTITOP) fails too.
    lint(None, &[]);
}

#[test]
fn the_pixel_processor_lints_clean_with_and_without_its_trace_port() {
    // Every (recip, sqrt) method pair the co-simulation builds.
    for recip in golden::fp::Method::ALL {
        for sqrt in golden::fp::Method::ALL {
            let recip = format!("-GRECIP_METHOD={}", recip.code());
            let sqrt = format!("-GSQRT_METHOD={}", sqrt.code());
            lint(Some("pixel_processor"), &[&recip, &sqrt]);
            lint(Some("pixel_processor"), &[&recip, &sqrt, "-DPP_TRACE"]);
        }
    }
    // Without refraction (REFRACTION = 0).
    lint(Some("pixel_processor"), &["-GREFRACTION=0"]);
    lint(Some("pixel_processor"), &["-GREFRACTION=0", "-DPP_TRACE"]);
}

#[test]
fn the_top_lints_clean_for_every_n_with_and_without_its_trace_ports() {
    // 3: N need not be a power of two.
    for n in [1, 2, 3, 4, 8] {
        let n = format!("-GN={n}");
        lint(Some("top"), &[&n]);
        lint(Some("top"), &[&n, "-DPP_TRACE"]);
    }
}

#[test]
fn the_top_of_fast_processors_lints_clean() {
    // FAST = 1, every method pair and exposure on and off (fast_builds),
    // with and without the trace ports; N = 1 and 3 (one result group),
    // and 3 in groups of 2.
    for n in ["-GN=1", "-GN=3", "-GN=3 -GARB_GROUP=2"] {
        for params in fast_builds() {
            let mut params: Vec<&str> = params.iter().map(String::as_str).collect();
            params.extend(n.split(' '));
            params.push("-GFAST=1");
            lint_tree(common::fast_top_tree(), Some("top"), &params);
            params.push("-DPP_TRACE");
            lint_tree(common::fast_top_tree(), Some("top"), &params);
        }
    }
}

/// `FP_METHOD_*` in rtl/fp/fp_defs.vh and golden::fp::Method name the same
/// methods with the same codes (build.rs verilates one model per define; the
/// harness picks a model by golden's code).
#[test]
fn fp_defs_method_codes_match_golden() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl/fp/fp_defs.vh");
    let text = std::fs::read_to_string(&path).expect("reading fp_defs.vh");
    let mut defined: Vec<(String, u32)> = text
        .lines()
        .filter_map(|line| {
            let mut w = line.split_whitespace();
            match (w.next(), w.next(), w.next()) {
                (Some("`define"), Some(name), Some(code)) => {
                    let name = name.strip_prefix("FP_METHOD_")?;
                    Some((name.to_lowercase(), code.parse().expect("a numeric code")))
                }
                _ => None,
            }
        })
        .collect();
    defined.sort();
    let mut golden: Vec<(String, u32)> = golden::fp::Method::ALL
        .iter()
        .map(|m| (m.name().to_string(), m.code()))
        .collect();
    golden.sort();
    assert_eq!(defined, golden, "{}", path.display());
}
