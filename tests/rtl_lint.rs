//! `verilator --lint-only -Wall` is clean on every top module of rtl/, with
//! every METHOD, using the Verilator the models were built with.

use std::path::Path;
use std::process::Command;

fn lint(top: &str, params: &[&str]) {
    let rtl = Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl");
    let fp = rtl.join("fp");
    let mut files: Vec<_> = std::fs::read_dir(&fp)
        .expect("reading rtl/fp")
        .map(|e| e.expect("listing rtl/fp").path())
        .filter(|p| p.extension().is_some_and(|x| x == "v"))
        .collect();
    files.sort();
    let mut cmd = Command::new(env!("RTCOSIM_VERILATOR_BIN"));
    let root = env!("RTCOSIM_VERILATOR_ROOT");
    if !root.is_empty() {
        cmd.env("VERILATOR_ROOT", root);
    }
    let out = cmd
        .args(["--lint-only", "-Wall", "--top-module", top])
        .arg(format!("-I{}", fp.display()))
        .args(params)
        .args(&files)
        .output()
        .expect("running verilator");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && stderr.trim().is_empty(),
        "lint of {top} {params:?}:\n{stderr}"
    );
}

#[test]
fn combinational_units_lint_clean() {
    for top in ["fp_add", "fp_mul", "fp_itof"] {
        lint(top, &[]);
    }
}

#[test]
fn multi_cycle_units_lint_clean_with_every_method() {
    for top in ["fp_recip", "fp_sqrt"] {
        for method in golden::fp::Method::ALL {
            lint(top, &[&format!("-GMETHOD={}", method.code())]);
        }
    }
}

#[test]
fn the_whole_float_unit_tree_lints_clean_as_one_design() {
    // What a reviewer runs over rtl/: every file at once, fp_units on top.
    lint("fp_units", &[]);
}
