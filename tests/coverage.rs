//! RTL coverage: the transition table the coverage build's cover points
//! come from is the one of today's controller, and (with the cargo feature
//! `coverage`) the coverage models count what a run does.

use golden::micro::isa;
use std::hash::Hasher;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The table's (from, to) pairs by state name.
fn table() -> (String, Vec<(String, String)>) {
    let path = root().join("rtl/cover/pp_ctrl.transitions");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let pairs = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let (a, b) = l
                .split_once(' ')
                .unwrap_or_else(|| panic!("bad line `{l}`"));
            (a.to_string(), b.to_string())
        })
        .collect();
    (text, pairs)
}

#[test]
fn the_transition_table_was_proved_on_todays_controller() {
    let (text, pairs) = table();
    let ctrl = std::fs::read(root().join("rtl/pp/pp_ctrl.v")).expect("pp_ctrl.v");
    let mut h = fnv::FnvHasher::default();
    h.write(&ctrl);
    let now = format!("# pp_ctrl.v fnv1a64 {:016x}", h.finish());
    assert!(
        text.lines().any(|l| l == now),
        "rtl/cover/pp_ctrl.transitions was made from another rtl/pp/pp_ctrl.v (now `{now}`): \
         run rtl/cover/transitions.sh and commit the new table"
    );
    // Every pair names two states of the ISA, once.
    for (a, b) in &pairs {
        assert!(
            isa::state_code(a).is_some() && isa::state_code(b).is_some(),
            "{a} -> {b}"
        );
    }
    let mut sorted = pairs.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), pairs.len(), "a transition is listed twice");
    // What the controller must be able to do, from the ISA's shape: take a
    // pixel (IDLE -> PRI_ITOF), wait for one (IDLE -> IDLE), end one
    // (PIX_DONE -> IDLE), hold a multi-cycle instruction (SPH_SQRT ->
    // SPH_SQRT); and what it must not: leave PIX_DONE for anything but IDLE.
    for (a, b) in [
        ("IDLE", "PRI_ITOF"),
        ("IDLE", "IDLE"),
        ("PIX_DONE", "IDLE"),
        ("SPH_SQRT", "SPH_SQRT"),
    ] {
        assert!(
            pairs.contains(&(a.into(), b.into())),
            "{a} -> {b} is missing"
        );
    }
    let from_done: Vec<_> = pairs.iter().filter(|(a, _)| a == "PIX_DONE").collect();
    assert_eq!(from_done, [&("PIX_DONE".to_string(), "IDLE".to_string())]);
}

#[test]
fn without_the_coverage_build_coverage_is_refused_with_the_command_that_builds_it() {
    if rtcosim::coverage::BUILT {
        return;
    }
    let dir = std::env::temp_dir().join(format!("rtcosim-cov-refused-{}", std::process::id()));
    let e = rtcosim::coverage::enable(&dir).unwrap_err().to_string();
    assert!(e.contains("--features coverage"), "{e}");
}

/// With the coverage models: a window of pixels counted exactly.
#[cfg(feature = "coverage")]
mod built {
    use super::*;
    use golden::window::Window;
    use rtcosim::cosim::{self, CosimOptions};
    use rtcosim::coverage::{self, Kind};

    #[test]
    fn each_pixel_is_one_start_and_one_end_transition_and_every_point_is_in_the_report() {
        let dir = std::env::temp_dir().join(format!("rtcosim-cov-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        coverage::enable(&dir).expect("the coverage build");
        let scene = rtcosim::scenes::load_with(
            "reference",
            rtcosim::scenes::Overrides {
                size: Some((40, 30)),
                ..Default::default()
            },
        )
        .expect("scene");
        let window = Window::new(10, 10, 6, 4);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("pool");
        let report = pool
            .install(|| cosim::run(&scene, window, &CosimOptions::default(), &|_| {}))
            .expect("run");
        assert!(report.passed());
        let done = coverage::finish(std::slice::from_ref(&dir), &dir, false).expect("finish");
        let data = coverage::collect(&dir.join("coverage.dat")).expect("merged");
        let count = |a: &str, b: &str| {
            data.points()
                .find(|p| p.transition() == Some((a, b)))
                .map(|p| p.count)
                .unwrap_or_else(|| panic!("no point for {a} -> {b}"))
        };
        assert_eq!(count("IDLE", "PRI_ITOF"), window.pixels());
        assert_eq!(count("PIX_DONE", "IDLE"), window.pixels());
        // One point per table line and per state.
        let (_, pairs) = table();
        assert_eq!(
            done.summary.kind(Kind::Transition).total,
            pairs.len() as u64
        );
        assert_eq!(
            done.summary.kind(Kind::State).total,
            isa::STATES.len() as u64
        );
        // The coverage build sees every source file of the processor.
        for f in [
            "rtl/pp/pp_ctrl.v",
            "rtl/pp/alu.v",
            "rtl/fp/fp_add.v",
            "rtl/fp/fp_sqrt.v",
        ] {
            assert!(
                done.summary.files.iter().any(|s| s.file == f),
                "{f} has no points"
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
