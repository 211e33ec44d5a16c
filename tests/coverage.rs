//! RTL coverage: the transition table the coverage build's cover points
//! come from is the one of today's controller, so is the list of those
//! argued unreachable, the directed scenes of rtl/cover/scenes/ agree with
//! golden, and (with the cargo feature `coverage`) the coverage models count
//! what a run does and the directed scenes take the transitions they name.

mod common;

use golden::micro::isa;
use std::hash::Hasher;
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The table's (from, to) pairs by state name.
fn table() -> (String, Vec<(String, String)>) {
    pairs_of("rtl/cover/pp_ctrl.transitions")
}

/// The pairs the fast controller's ring adds to the table.
fn fast_table() -> Vec<(String, String)> {
    pairs_of("rtl/cover/fast_ctrl.transitions").1
}

/// A transition table's text and its (from, to) pairs.
fn pairs_of(file: &str) -> (String, Vec<(String, String)>) {
    let path = root().join(file);
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
    let now = ctrl_hash_line();
    assert!(
        text.lines().any(|l| l == now),
        "rtl/cover/pp_ctrl.transitions was made from another rtl/pp/pp_ctrl.v (now `{now}`): \
         run rtl/cover/transitions.sh and commit the new table"
    );
    assert_on_todays_shared_functions(&text, "rtl/cover/pp_ctrl.transitions");
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

/// Asserts that `text` (the file `what`) names today's
/// `rtl/pp/ctrl_flow.vh`, the functions both controllers include.
fn assert_on_todays_shared_functions(text: &str, what: &str) {
    let now = hash_line("rtl/pp/ctrl_flow.vh");
    assert!(
        text.lines().any(|l| l == now),
        "{what} was made on another rtl/pp/ctrl_flow.vh (now `{now}`): re-derive or re-argue \
         it against the controllers' shared functions and update the hash"
    );
}

/// The `# pp_ctrl.v fnv1a64 ...` line of today's controller.
fn ctrl_hash_line() -> String {
    hash_line("rtl/pp/pp_ctrl.v")
}

/// The `# <name> fnv1a64 ...` line of today's `file`.
fn hash_line(file: &str) -> String {
    let bytes = std::fs::read(root().join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    let mut h = fnv::FnvHasher::default();
    h.write(&bytes);
    let name = Path::new(file)
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or(file);
    format!("# {name} fnv1a64 {:016x}", h.finish())
}

#[test]
fn the_fast_controllers_own_transitions_were_argued_on_todays_fast_controller() {
    let (text, pairs) = pairs_of("rtl/cover/fast_ctrl.transitions");
    let now = hash_line("rtl/fast/fast_ctrl.v");
    assert!(
        text.lines().any(|l| l == now),
        "rtl/cover/fast_ctrl.transitions was argued on another rtl/fast/fast_ctrl.v (now \
         `{now}`): re-read its argument against the new controller and update the hash"
    );
    assert_on_todays_shared_functions(&text, "rtl/cover/fast_ctrl.transitions");
    // Its pairs are the ring's own: none is in the compact table; a done
    // turn that takes a pixel is among them.
    let (_, compact) = table();
    for p in &pairs {
        assert!(
            isa::state_code(&p.0).is_some() && isa::state_code(&p.1).is_some(),
            "{p:?}"
        );
        assert!(!compact.contains(p), "{p:?} is in pp_ctrl.transitions too");
    }
    assert!(pairs.contains(&("PIX_DONE".into(), "PRI_ITOF".into())));
}

#[test]
fn the_transitions_argued_unreachable_are_argued_on_todays_controller() {
    let path = root().join(rtcosim::output::coverage::UNREACHABLE_PATH);
    let text = std::fs::read_to_string(&path).expect("the list");
    let now = ctrl_hash_line();
    assert!(
        text.lines().any(|l| l == now),
        "{} was argued on another rtl/pp/pp_ctrl.v (now `{now}`): check each argument \
         against the new controller and update the hash",
        path.display()
    );
    assert_on_todays_shared_functions(&text, &path.display().to_string());
    // The fast controller's own list: argued on today's fast_ctrl.v, its
    // groups' arguments in its header or the compact list's.
    let fast_path = root().join(rtcosim::output::coverage::FAST_UNREACHABLE_PATH);
    let fast_text = std::fs::read_to_string(&fast_path).expect("the fast list");
    let fast_now = hash_line("rtl/fast/fast_ctrl.v");
    assert!(
        fast_text.lines().any(|l| l == fast_now),
        "{} was argued on another rtl/fast/fast_ctrl.v (now `{fast_now}`): check each argument \
         against the new controller and update the hash",
        fast_path.display()
    );
    assert_on_todays_shared_functions(&fast_text, &fast_path.display().to_string());
    let text = text + &fast_text;
    let (_, mut pairs) = table();
    pairs.extend(fast_table());
    let argued = rtcosim::output::coverage::unreachable().expect("the lists read");
    let mut seen = std::collections::BTreeSet::new();
    for t in &argued {
        assert!(
            pairs.contains(&(t.from.clone(), t.to.clone())),
            "{} -> {} is not a possible transition of the table",
            t.from,
            t.to
        );
        assert!(
            seen.insert((&t.controller, &t.from, &t.to)),
            "{}: {} -> {} twice",
            t.controller,
            t.from,
            t.to
        );
        // Each group's argument is written in the list's header.
        assert!(
            text.lines()
                .any(|l| l.starts_with(&format!("# {}: ", t.group))),
            "group {} has no argument",
            t.group
        );
    }
    // What every pixel does is not argued away.
    for c in ["pp_ctrl", "fast_ctrl"] {
        for (a, b) in [("IDLE", "PRI_ITOF"), ("PIX_DONE", "IDLE")] {
            assert!(
                !seen.contains(&(&c.to_string(), &a.to_string(), &b.to_string())),
                "{c}: {a} -> {b}"
            );
        }
    }
}

/// A transition by its states' names: (from, to).
type Transition = (String, String);

/// The directed scenes of rtl/cover/scenes/: (file, scene, the transitions
/// its `# takes:` line names).
fn cover_scenes() -> Vec<(String, golden::scene::Scene, Vec<Transition>)> {
    let dir = root().join("rtl/cover/scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("rtl/cover/scenes")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path).expect("scene text");
            let takes = text
                .lines()
                .find_map(|l| l.strip_prefix("# takes: "))
                .unwrap_or_else(|| panic!("{}: no `# takes:` line", path.display()))
                .split(", ")
                .map(|t| {
                    let (a, b) = t.split_once(" -> ").expect("FROM -> TO");
                    (a.to_string(), b.to_string())
                })
                .collect();
            let scene = golden::scene::Scene::load(&path).expect("the scene loads");
            (path.display().to_string(), scene, takes)
        })
        .collect()
}

#[test]
fn the_cover_scenes_agree_with_golden_and_name_possible_transitions() {
    let (_, pairs) = table();
    let scenes = cover_scenes();
    assert_eq!(scenes.len(), 8);
    for (file, scene, takes) in &scenes {
        for t in takes {
            assert!(
                pairs.contains(t),
                "{file}: {} -> {} is not in the table",
                t.0,
                t.1
            );
        }
        let window = golden::window::Window::full(scene);
        let report = common::run_compact(
            scene,
            window,
            &rtcosim::check::cosim::CosimOptions::default(),
        )
        .expect("the run");
        assert!(report.passed(), "{file}:\n{report}");
        assert_eq!(report.compare.counts.pixels, window.pixels());
    }
}

/// The transitions golden predicts for every pixel of `scene`
/// (golden::micro::cover, the guided fuzzer's feedback), by state name.
fn predicted(scene: &golden::scene::Scene) -> std::collections::BTreeSet<Transition> {
    golden::micro::Processor::new(scene)
        .coverage(golden::window::Window::full(scene))
        .points()
        .filter_map(|p| match p {
            golden::micro::cover::Point::Transition(a, b) => {
                let name = |s: isa::State| isa::state_name(s.0).expect("a named state").to_string();
                Some((name(a), name(b)))
            }
            golden::micro::cover::Point::Value(..) | golden::micro::cover::Point::Near(..) => None,
        })
        .collect()
}

/// Golden's predicted paths (the guided fuzzer's feedback) take only
/// transitions Yosys finds possible, none argued unreachable, and every one
/// a cover scene was written to take (which the coverage build checks on
/// the RTL): on every builtin scene at 16x12 and the cover scenes.
#[test]
fn golden_predicts_only_possible_transitions_and_those_the_cover_scenes_take() {
    let (_, pairs) = table();
    let pairs: std::collections::BTreeSet<Transition> = pairs.into_iter().collect();
    let argued: std::collections::BTreeSet<Transition> = rtcosim::output::coverage::unreachable()
        .expect("the lists read")
        .into_iter()
        .filter(|a| a.controller == "pp_ctrl")
        .map(|a| (a.from, a.to))
        .collect();
    let mut all = std::collections::BTreeSet::new();
    let builtins = golden::scene::Scene::builtin_names().iter().map(|name| {
        let scene = rtcosim::scenes::load_with(
            name,
            rtcosim::scenes::Overrides {
                size: Some((16, 12)),
                ..Default::default()
            },
        )
        .expect("a builtin at 16x12");
        (format!("builtin {name}"), scene, Vec::new())
    });
    for (what, scene, takes) in builtins.chain(cover_scenes()) {
        let got = predicted(&scene);
        for t in &got {
            assert!(
                pairs.contains(t),
                "{what}: {} -> {} is not in the table",
                t.0,
                t.1
            );
            assert!(
                !argued.contains(t),
                "{what}: {} -> {} is argued unreachable",
                t.0,
                t.1
            );
        }
        for t in &takes {
            assert!(
                got.contains(t),
                "{what}: golden does not take {} -> {}",
                t.0,
                t.1
            );
        }
        all.extend(got);
    }
    // Every pixel starts and ends, and the multi-cycle states wait.
    for (a, b) in [
        ("IDLE", "PRI_ITOF"),
        ("PIX_DONE", "IDLE"),
        ("NORM_ROOTS", "NORM_ROOTS"),
    ] {
        assert!(all.contains(&(a.to_string(), b.to_string())), "{a} -> {b}");
    }
}

#[test]
fn without_the_coverage_build_coverage_is_refused_with_the_command_that_builds_it() {
    if rtcosim::output::coverage::BUILT {
        return;
    }
    let dir = std::env::temp_dir().join(format!("rtcosim-cov-refused-{}", std::process::id()));
    let e = rtcosim::output::coverage::enable(&dir)
        .unwrap_err()
        .to_string();
    assert!(e.contains("--features coverage"), "{e}");
}

/// With the coverage models: a window of pixels counted exactly.
#[cfg(feature = "coverage")]
mod built {
    use super::*;
    use golden::window::Window;
    use rtcosim::check::cosim::{self, CosimOptions};
    use rtcosim::design::processor::ProcessorKind;
    use rtcosim::design::Design;
    use rtcosim::output::coverage::{self, Kind};

    /// Coverage goes to one directory per process: one test at a time.
    static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

    /// Coverage on, into a fresh directory `rtcosim-<name>-<pid>` (one test
    /// at a time: hold the guard until the counts are read).
    fn coverage_into(name: &str) -> (std::sync::MutexGuard<'static, ()>, std::path::PathBuf) {
        let one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
        let dir = std::env::temp_dir().join(format!("rtcosim-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        coverage::enable(&dir).expect("the coverage build");
        (one, dir)
    }

    /// The count of transition `a -> b`, if the data has its point.
    fn taken(data: &coverage::CoverageData, a: &str, b: &str) -> Option<u64> {
        data.points()
            .find(|p| p.transition() == Some((a, b)))
            .map(|p| p.count)
    }

    /// The reference scene at 40x30.
    fn reference_40x30() -> golden::scene::Scene {
        rtcosim::scenes::load_with(
            "reference",
            rtcosim::scenes::Overrides {
                size: Some((40, 30)),
                ..Default::default()
            },
        )
        .expect("scene")
    }

    #[test]
    fn each_pixel_is_one_start_and_one_end_transition_and_every_point_is_in_the_report() {
        let (_one, dir) = coverage_into("cov");
        let scene = reference_40x30();
        let window = Window::new(10, 10, 6, 4);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("pool");
        let report = pool
            .install(|| common::run_compact(&scene, window, &CosimOptions::default()))
            .expect("run");
        assert!(report.passed());
        let done = coverage::finish(std::slice::from_ref(&dir), &dir, false).expect("finish");
        let data = coverage::collect(&dir.join("coverage.dat")).expect("merged");
        let count = |a: &str, b: &str| {
            taken(&data, a, b).unwrap_or_else(|| panic!("no point for {a} -> {b}"))
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

    /// The fast processor's coverage model: a take is a transition into
    /// PRI_ITOF at a context's next turn, from IDLE or from PIX_DONE (the
    /// ring's own), and a pixel's done turn is PIX_DONE's state point.
    #[test]
    fn the_fast_processor_counts_one_take_per_pixel_and_has_every_point() {
        let (_one, dir) = coverage_into("cov-fast");
        let scene = reference_40x30();
        // More pixels than contexts, so that done turns take the next.
        let window = Window::new(0, 10, 40, 2);
        let report = cosim::run(
            &Design::for_scene(ProcessorKind::Fast, &scene),
            &scene,
            window,
            &CosimOptions::default(),
            &|_| {},
        )
        .expect("run");
        assert!(report.passed(), "{report}");
        let done = coverage::finish(std::slice::from_ref(&dir), &dir, false).expect("finish");
        let data = coverage::collect(&dir.join("coverage.dat")).expect("merged");
        let fast = |a: &str, b: &str| {
            data.points()
                .find(|p| p.module == "fast_ctrl_cover" && p.transition() == Some((a, b)))
                .map(|p| p.count)
                .unwrap_or_else(|| panic!("no fast point for {a} -> {b}"))
        };
        let (idle, done_take) = (fast("IDLE", "PRI_ITOF"), fast("PIX_DONE", "PRI_ITOF"));
        assert_eq!(idle + done_take, window.pixels());
        assert!(done_take > 0, "no done turn took a pixel");
        let pix_done = data
            .points()
            .find(|p| p.module == "fast_ctrl_cover" && p.state() == Some("PIX_DONE"))
            .map(|p| p.count);
        assert_eq!(pix_done, Some(window.pixels()));
        // One point per line of both tables and per state. (Counted by
        // module: the tests outside this module that build compact
        // processors run beside this one, and coverage is on for the whole
        // process.)
        let (_, mut pairs) = table();
        pairs.extend(fast_table());
        let points = |kind: Kind| {
            data.points()
                .filter(|p| p.module == "fast_ctrl_cover" && p.kind == kind)
                .count()
        };
        assert_eq!(points(Kind::Transition), pairs.len());
        assert_eq!(points(Kind::State), isa::STATES.len());
        assert!(done.summary.argued_but_taken.is_empty());
        for f in [
            "rtl/fast/fast_ctrl.v",
            "rtl/fast/fast_alu.v",
            "rtl/fast/fast_regfile.v",
            "rtl/fast/fast_fp_exp.v",
        ] {
            assert!(
                done.summary.files.iter().any(|s| s.file == f),
                "{f} has no points"
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn every_cover_scene_takes_the_transitions_it_names_and_none_argued_unreachable() {
        let (_one, dir) = coverage_into("cov-scenes");
        let scenes = cover_scenes();
        for (file, scene, _) in &scenes {
            let report = common::run_compact(scene, Window::full(scene), &CosimOptions::default())
                .expect("run");
            assert!(report.passed(), "{file}");
        }
        let done = coverage::finish(std::slice::from_ref(&dir), &dir, false).expect("finish");
        let data = coverage::collect(&dir.join("coverage.dat")).expect("merged");
        for (file, _, takes) in &scenes {
            for (a, b) in takes {
                let count = taken(&data, a, b).unwrap_or(0);
                assert!(count > 0, "{file} never took {a} -> {b}");
            }
        }
        assert!(
            done.summary.argued_but_taken.is_empty(),
            "taken, though argued unreachable: {:?}",
            done.summary.argued_but_taken
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
