//! `verilator --lint-only -Wall` is clean on every top module of rtl/, with
//! every METHOD and with and without the trace port, using the Verilator the
//! models were built with. Every file of rtl/fp and rtl/pp is read each time,
//! as a reviewer would lint the tree.

mod common;

use std::process::Command;

/// Lints every file of rtl/ with `top` as the top module, or, with `None`,
/// as Verilator finds it (which warns if the tree has more than one top).
fn lint(top: Option<&str>, params: &[&str]) {
    let (dirs, files) = common::rtl_tree();
    let mut cmd = Command::new(env!("RTCOSIM_VERILATOR_BIN"));
    let root = env!("RTCOSIM_VERILATOR_ROOT");
    if !root.is_empty() {
        cmd.env("VERILATOR_ROOT", root);
    }
    common::run_silent(
        cmd.args(["--lint-only", "-Wall"])
            .args(top.map(|t| ["--top-module", t]).into_iter().flatten())
            .args(dirs.iter().map(|d| format!("-I{}", d.display())))
            .args(params)
            .args(&files),
        &format!("lint of {} {params:?}", top.unwrap_or("rtl/")),
    );
}

#[test]
fn combinational_units_lint_clean() {
    for top in ["fp_add", "fp_mul", "fp_itof"] {
        lint(Some(top), &[]);
    }
}

#[test]
fn multi_cycle_units_lint_clean_with_every_method() {
    for top in ["fp_recip", "fp_sqrt"] {
        for method in golden::fp::Method::ALL {
            lint(Some(top), &[&format!("-GMETHOD={}", method.code())]);
        }
    }
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
}
