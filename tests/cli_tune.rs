//! `rtcosim tune`: its answer on a tiny scene, by the largest and by the
//! mean error (`--measure mean`), against a brute-force search written here
//! from the golden models alone, and its refusals.

//! `rtcosim tune`: its answer on a tiny scene, by each cost (`--cost
//! cycles`, `device-fps`, `area`), by the largest and by the mean error
//! (`--measure mean`), on one processor and on both, against a brute-force
//! search written here from the golden models and the cost table; its
//! check of the pick on the RTL (a fault injected into the RTL withdraws
//! the recommendation); `--json`; and its refusals.

mod common;

use common::{both, mirror, rtcosim, scratch, text, tune_pick, tune_processor};
use golden::fp::Method;
use golden::scene::{RenderSettings, Scene};
use rtcosim::design::processor::ProcessorKind;
use rtcosim::output::device::{Build, CostTable, Device};

/// One configuration of the grid on one processor, measured here.
#[derive(Debug, Clone, Copy)]
struct Measured {
    processor: ProcessorKind,
    settings: RenderSettings,
    /// One processor's cycles for the frame: golden::micro's (the compact
    /// RTL's cycle for cycle), or the barrel rule's for the fast one
    /// (`sweep::frame_cycles`, which co-simulation holds the fast RTL to).
    cycles: u64,
    /// Largest and mean absolute channel difference from the truth,
    /// 0..255 scale.
    max: f64,
    mean: f64,
    /// The LX760 filled with the build: processors, LUTs each, frames/s.
    processors: u32,
    luts: u32,
    fps: f64,
}

/// Every configuration of docs/accuracy.md's tuning grid (both processors,
/// depth 1..=8, both methods of each unit, weight cutoff 0 or
/// 2^-8..2^-1, none at depth 1, the scene's own speed-ups), rendered with
/// golden::micro, compared with the f64 reference at depth 8 without
/// cutoff, and priced from rtl/synth/costs.toml: the processors that fit
/// by every resource, at the build's clock, the frame split evenly.
fn brute_force(scene: &Scene) -> Vec<Measured> {
    let truth = {
        let r = RenderSettings {
            max_depth: 8,
            weight_cutoff: 0.0,
            ..scene.render
        };
        golden::reference::render(&scene.with_render(r, "truth").expect("valid"), &|_| {})
    };
    let table = CostTable::builtin().expect("the cost table");
    let lx760 = Device::LX760;
    let cutoffs = [
        0.0f32, 0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625, 0.0078125, 0.00390625,
    ];
    let mut out = Vec::new();
    for max_depth in 1..=8 {
        for recip in [Method::Exact, Method::Fast] {
            for sqrt in [Method::Exact, Method::Fast] {
                for &weight_cutoff in &cutoffs {
                    if max_depth == 1 && weight_cutoff > 0.0 {
                        continue;
                    }
                    let settings = RenderSettings {
                        max_depth,
                        recip,
                        sqrt,
                        weight_cutoff,
                        ..scene.render
                    };
                    let s = scene.with_render(settings, "grid").expect("valid");
                    let (frame, stats, work) = golden::micro::render_work(&s, &|_| {});
                    let diffs: Vec<f64> = frame
                        .pixels
                        .iter()
                        .zip(&truth.pixels)
                        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() * 255.0))
                        .collect();
                    for processor in [ProcessorKind::Compact, ProcessorKind::Fast] {
                        let (cycles, _, _) =
                            rtcosim::campaign::sweep::frame_cycles(processor, &stats, &work);
                        // The build the scene runs on: without the
                        // exponential only if the scene has no exposure
                        // and the table holds that build; without
                        // refraction only if it has no glass and the
                        // table holds that build.
                        let want = Build {
                            processor,
                            recip,
                            sqrt,
                            stack_depth: 8,
                            exposure: s.render.exposure.is_some(),
                            refraction: s.refracts(),
                        };
                        let cost = table
                            .cost(want)
                            .or_else(|_| {
                                table.cost(Build {
                                    exposure: true,
                                    ..want
                                })
                            })
                            .or_else(|_| {
                                table.cost(Build {
                                    exposure: true,
                                    refraction: true,
                                    ..want
                                })
                            })
                            .expect("priced");
                        let fits = |have: f64, need: f64| {
                            if need > 0.0 {
                                (have / need).floor() as u32
                            } else {
                                u32::MAX
                            }
                        };
                        let processors = [
                            fits(lx760.luts.into(), cost.luts.into()),
                            fits(lx760.lut_memory.into(), cost.lut_memory.into()),
                            fits(lx760.flip_flops.into(), cost.flip_flops.into()),
                            fits(lx760.dsp48e1.into(), cost.dsp48e1.into()),
                            fits(lx760.bram36.into(), cost.bram36),
                        ]
                        .into_iter()
                        .min()
                        .expect("five");
                        out.push(Measured {
                            processor,
                            settings,
                            cycles,
                            max: diffs.iter().copied().fold(0.0, f64::max),
                            mean: diffs.iter().sum::<f64>() / diffs.len() as f64,
                            processors,
                            luts: cost.luts,
                            fps: cost.fmax_mhz * 1e6 * f64::from(processors) / cycles as f64,
                        });
                    }
                }
            }
        }
    }
    assert_eq!(out.len(), 2 * 4 * (1 + 7 * 9));
    out
}

/// What `--cost` ranks by first.
#[derive(Debug, Clone, Copy)]
enum By {
    Cycles,
    DeviceFps,
    Area,
}

/// The cheapest configuration meeting `target` in `error` on `processors`,
/// by docs/accuracy.md's rule: first `by` (the most device frames/s; or
/// the most processors on the device, then the fewest LUTs), then fewest
/// cycles, the smaller depth, the fast reciprocal, the fast square root,
/// the compact processor, the larger cutoff (cutoffs are positive, so
/// their bits order as the numbers do).
fn cheapest(
    rows: &[Measured],
    processors: &[ProcessorKind],
    by: By,
    target: f64,
    error: fn(&Measured) -> f64,
) -> Measured {
    let exact = |m: Method| m == Method::Exact;
    let key = |m: &Measured| {
        let s = &m.settings;
        let first = match by {
            By::Cycles => (0u32, 0u32, 0u64),
            // Frames/s of the grid are positive and finite: their bits
            // order as the numbers do; the most first.
            By::DeviceFps => (0, 0, u64::MAX - m.fps.to_bits()),
            By::Area => (u32::MAX - m.processors, m.luts, 0),
        };
        (
            first,
            m.cycles,
            s.max_depth,
            exact(s.recip),
            exact(s.sqrt),
            m.processor == ProcessorKind::Fast,
            std::cmp::Reverse(s.weight_cutoff.to_bits()),
        )
    };
    *rows
        .iter()
        .filter(|m| processors.contains(&m.processor) && error(m) <= target)
        .min_by_key(|m| key(m))
        .expect("something meets the target")
}

/// `rtcosim tune` on the mirror scene at `size` with `target`, and `extra`.
fn tune(size: &str, target: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "tune",
        "--scene",
        "mirror",
        "--size",
        size,
        "--max-error",
        target,
    ];
    args.extend(extra);
    rtcosim(&args)
}

/// The build tune prints for its pick (the rest of its "RTL build: " line).
fn build_line(stdout: &str) -> &str {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix("RTL build: "))
        .unwrap_or_else(|| panic!("no RTL build line\n{stdout}"))
}

/// The compact processor by cycles: the ranking before both processors
/// and device units came.
const COMPACT_BY_CYCLES: [&str; 4] = ["--cost", "cycles", "--processor", "compact"];

/// Each cost, on the compact processor and on both: tune's pick is the
/// brute force's cheapest, its printed figures are the brute force's, and
/// it was co-simulated on the RTL, all 192 pixels (the sample covers the
/// frame), before it was recommended.
#[test]
fn tune_picks_the_cheapest_configuration_a_brute_force_search_finds() {
    let (w, h) = (16, 12);
    let target = 6.0;
    let scene = mirror(w, h);
    assert!(
        scene.render.speedups.bounding_box
            && scene.render.speedups.fast_plane
            && scene.render.speedups.shadow_shortcut
    );
    let rows = brute_force(&scene);
    assert!(
        rows.iter().any(|m| m.max <= target) && rows.iter().any(|m| m.max > target),
        "the target must split the grid"
    );
    use ProcessorKind::{Compact, Fast};
    let cases: [(&[&str], &[ProcessorKind], By); 4] = [
        (&COMPACT_BY_CYCLES, &[Compact], By::Cycles),
        (&[], &[Compact, Fast], By::DeviceFps),
        (&["--cost", "area"], &[Compact, Fast], By::Area),
        (
            &["--cost", "device-fps", "--processor", "compact"],
            &[Compact],
            By::DeviceFps,
        ),
    ];
    let mut picks = Vec::new();
    for (extra, processors, by) in cases {
        let best = cheapest(&rows, processors, by, target, |m| m.max);
        let out = tune(&format!("{w}x{h}"), &target.to_string(), extra);
        assert_eq!(out.status.code(), Some(0), "{extra:?}: {}", both(&out));
        let stdout = text(&out.stdout);
        let picked = (tune_processor(&stdout), tune_pick(&stdout, &scene));
        assert_eq!(
            picked,
            (best.processor, best.settings),
            "{extra:?}: tune's pick against the brute force's cheapest {best:?}\n{stdout}"
        );
        // The printed figures are the brute force's.
        let cheapest_line = stdout
            .lines()
            .find(|l| l.starts_with("cheapest:"))
            .unwrap_or_else(|| panic!("no cheapest line\n{stdout}"));
        for want in [
            format!(
                " {:.1} cycles/pixel,",
                best.cycles as f64 / f64::from(w * h)
            ),
            format!(
                ": {:.1} device frames/s ({} processors ",
                best.fps, best.processors
            ),
        ] {
            assert!(
                cheapest_line.contains(&want),
                "{extra:?}: {want:?} in {cheapest_line}"
            );
        }
        // Co-simulated on the build it is priced as, every pixel, before
        // it is recommended; a shallower stack says what it runs on.
        assert!(
            stdout.contains(&format!(
                "\nRTL and golden agree on all {}, bit for bit and cycle for cycle: recommended\n",
                w * h
            )),
            "{extra:?}\n{stdout}"
        );
        assert!(build_line(&stdout).contains(".STACK_DEPTH(8)"), "{stdout}");
        let depth = best.settings.max_depth;
        assert_eq!(
            stdout.contains(&format!("max_depth = {depth} uses {depth} of its levels")),
            depth < 8,
            "{stdout}"
        );
        // The line after the full build's states the saving in the cost.
        let saving = match by {
            By::Cycles => "saves ".to_string(),
            By::DeviceFps => "draws ".to_string(),
            By::Area => format!(
                "{} processors on the device against the full build's ",
                best.processors
            ),
        };
        assert!(
            stdout.lines().any(|l| l.starts_with(&saving)),
            "{extra:?}: {saving:?}\n{stdout}"
        );
        picks.push(picked);
    }
    // Cycles on the compact processor and device frames/s on both pick
    // differently here: an option tune ignored would fail. (Area and
    // device frames/s pick alike on today's cost table, whose smallest
    // build of each processor is also its fastest on the device; the
    // unit tests of `Cost::order` tell them apart.)
    assert_ne!(picks[0], picks[1], "{picks:?}");
}

/// The checker of the pick can fail: a bit flipped in the RTL's writes
/// (`--fault`) makes the co-simulation disagree, and tune exits 1 without
/// recommending; `--json` says so too, and otherwise carries the pick.
#[test]
fn a_pick_the_rtl_disagrees_on_is_not_recommended() {
    let dir = scratch("cli_tune", "json");
    let json = dir.join("tune.json");
    let path = json.to_str().expect("a UTF-8 path");
    let read = || -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(&json).expect("--json wrote")).expect("JSON")
    };
    let out = tune("16x12", "6", &["--json", path]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    let v = read();
    assert_eq!(v["recommended"], true);
    assert_eq!(v["rtl"]["pixels"], 192);
    assert_eq!(v["rtl"]["divergent_pixels"], 0);
    assert_eq!(v["cost"], "device-fps");
    assert_eq!(v["pick"]["processor"], tune_processor(&stdout).name());
    assert_eq!(
        v["pick"]["depth"],
        tune_pick(&stdout, &mirror(16, 12)).max_depth
    );
    assert_eq!(v["build"], build_line(&stdout));

    for processor in ["compact", "fast"] {
        let out = tune(
            "16x12",
            "6",
            &[
                "--processor",
                processor,
                "--fault",
                "PRI_HALF:0x400",
                "--json",
                path,
            ],
        );
        assert_eq!(out.status.code(), Some(1), "{processor}: {}", both(&out));
        let stdout = text(&out.stdout);
        assert!(
            stdout.contains("NOT recommended: the RTL build disagrees with golden on ")
                && !stdout.contains(": recommended\n"),
            "{processor}: {stdout}"
        );
        let v = read();
        assert_eq!(v["recommended"], false, "{processor}");
        assert_eq!(v["rtl"]["agreed"], false, "{processor}");
        assert_eq!(v["pick"]["processor"], processor);
    }
}

/// The mean-error target of [`measure_mean_ranks_by_the_mean_error`].
const MEAN_TARGET: f64 = 0.5;

/// `--measure mean`: the pick is the brute force's cheapest by the mean
/// error, at a target where the largest error picks another configuration
/// (so a tuner that ignored the option fails); the figures printed for it
/// and for the level below are the brute force's; a target below every
/// mean exits 1 naming the smallest mean.
#[test]
fn measure_mean_ranks_by_the_mean_error() {
    let (w, h) = (16, 12);
    let scene = mirror(w, h);
    let rows = brute_force(&scene);
    let target = MEAN_TARGET;
    assert!(
        rows.iter().any(|m| m.mean <= target) && rows.iter().any(|m| m.mean > target),
        "the target must split the grid"
    );
    // Far from every configuration's mean: a sum in another order cannot
    // move one across it.
    assert!(
        rows.iter().all(|m| (m.mean - target).abs() > 1e-9),
        "a mean within 1e-9 of the target: pick another"
    );
    let compact = [ProcessorKind::Compact];
    let rows: Vec<Measured> = rows
        .into_iter()
        .filter(|m| m.processor == compact[0])
        .collect();
    let row = cheapest(&rows, &compact, By::Cycles, target, |m| m.mean);
    assert_ne!(
        row.settings,
        cheapest(&rows, &compact, By::Cycles, target, |m| m.max).settings,
        "at this target the two measures pick alike: pick another"
    );

    let size = format!("{w}x{h}");
    let tune_mean = |target: &str| {
        let mut extra = vec!["--measure", "mean"];
        extra.extend(COMPACT_BY_CYCLES);
        tune(&size, target, &extra)
    };
    let out = tune_mean(&target.to_string());
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(&format!(", mean error <= {target} (0..255 scale) against ")),
        "{stdout}"
    );
    let pick = tune_pick(&stdout, &scene);
    assert_eq!(
        pick, row.settings,
        "tune's pick against the brute force's cheapest by the mean\n{stdout}"
    );
    // The printed figures of the pick are the brute force's.
    let line = stdout
        .lines()
        .find(|l| l.starts_with("cheapest: "))
        .unwrap_or_else(|| panic!("no cheapest line\n{stdout}"));
    let cpp = row.cycles as f64 / f64::from(w * h);
    for want in [
        format!(" {cpp:.1} cycles/pixel, "),
        format!(", largest error {:.4}, ", row.max),
        format!(", mean {:.5}", row.mean),
    ] {
        assert!(line.contains(&want), "{want:?} in {line:?}");
    }
    // One level less misses the target in the mean.
    if pick.max_depth > 1 {
        let less = RenderSettings {
            max_depth: pick.max_depth - 1,
            weight_cutoff: if pick.max_depth == 2 {
                0.0
            } else {
                pick.weight_cutoff
            },
            ..pick
        };
        let r = rows
            .iter()
            .find(|m| m.settings == less)
            .expect("in the grid");
        assert!(r.mean > target);
        let want = format!(
            " would miss the target: mean error {:.4} > {target}",
            r.mean
        );
        assert!(stdout.contains(&want), "{want:?} in\n{stdout}");
    }

    // Nothing meets a target below every mean: exit 1, naming the most
    // accurate configuration in the mean.
    let out = tune_mean("1e-9");
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    let least = rows.iter().map(|m| m.mean).fold(f64::INFINITY, f64::min);
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("no configuration meets the target: the most accurate is ")
            && stdout.contains(&format!(" with mean error {least:.4}\n")),
        "{least}\n{stdout}"
    );
}

/// A value `--measure`, `--cost` or `--processor` does not know is refused
/// by clap, naming the flag and the values it knows.
#[test]
fn a_bad_measure_cost_or_processor_is_refused_with_exit_2() {
    let cases: [(&str, &str, &[&str], &str); 3] = [
        (
            "--measure",
            "MEASURE",
            &["median", "MEAN", "avg"],
            "max, mean",
        ),
        (
            "--cost",
            "COST",
            &["fps", "luts", "Cycles"],
            "device-fps, area, cycles",
        ),
        (
            "--processor",
            "PROCESSOR",
            &["both", "Fast"],
            "compact, fast",
        ),
    ];
    for (flag, name, bads, known) in cases {
        for bad in bads {
            let mut args = common::TUNE_MIRROR_4X3[..7].to_vec();
            args.extend([flag, bad]);
            common::assert_refused(
                &args,
                &[
                    &format!("invalid value '{bad}' for '{flag} <{name}>'"),
                    &format!("[possible values: {known}]"),
                ],
            );
        }
    }
}

/// `rtcosim tune` on the mirror scene at 4x3.
fn tune_tiny(max_error: &str) -> std::process::Output {
    tune("4x3", max_error, &[])
}

#[test]
fn bad_error_targets_are_refused() {
    for bad in ["0", "-1", "nan", "inf", "256", "lots"] {
        let out = tune_tiny(bad);
        assert_eq!(
            out.status.code(),
            Some(2),
            "--max-error {bad}: {}",
            both(&out)
        );
        let err = text(&out.stderr);
        assert!(err.contains("--max-error"), "{bad}: {err}");
    }
}

#[test]
fn an_unreachable_target_exits_1_and_names_the_most_accurate() {
    let out = tune_tiny("1e-12");
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    assert!(
        text(&out.stdout).contains("no configuration meets the target"),
        "{}",
        both(&out)
    );
}

/// Glass is a knob: on a scene with glass tune tries every configuration
/// with its glass refracting and opaque (every transmission 0, a build
/// without refraction). A target the opaque glass meets gets the opaque
/// glass and a build without refraction (fewer cycles, a smaller build);
/// one it misses gets the refracting glass and a build with refraction,
/// and the report says what the opaque glass would have cost in error.
#[test]
fn tune_draws_glass_opaque_when_its_refraction_adds_nothing_within_the_target() {
    let run = |target: &str| {
        rtcosim(&[
            "tune",
            "--scene",
            "glass_room",
            "--size",
            "16x12",
            "--max-error",
            target,
            "--processor",
            "compact",
        ])
    };
    let loose = run("255");
    assert!(loose.status.success(), "{}", both(&loose));
    let stdout = text(&loose.stdout);
    assert!(stdout.contains("scene glass: opaque"), "{stdout}");
    assert!(build_line(&stdout).contains(".REFRACTION(0)"), "{stdout}");
    // 4 + 7 x 4 x 9 configurations, each with the glass as it is and opaque.
    assert!(stdout.contains(" 512 configurations"), "{stdout}");

    let tight = run("4");
    assert!(tight.status.success(), "{}", both(&tight));
    let stdout = text(&tight.stdout);
    assert!(!stdout.contains("scene glass: opaque"), "{stdout}");
    assert!(build_line(&stdout).contains(".REFRACTION(1)"), "{stdout}");
    let opaque = stdout
        .lines()
        .find(|l| l.contains("the glass opaque (a build without refraction)"))
        .unwrap_or_else(|| panic!("no opaque-glass neighbour\n{stdout}"));
    assert!(opaque.ends_with("(misses the target)"), "{opaque}");
}
