//! `rtcosim tune`: its answer on a tiny scene, by the largest and by the
//! mean error (`--measure mean`), against a brute-force search written here
//! from the golden models alone, and its refusals.

mod common;

use common::{both, mirror, rtcosim, text, tune_pick};
use golden::fp::Method;
use golden::scene::{RenderSettings, Scene};

/// One configuration of the grid, measured here.
#[derive(Debug, Clone, Copy)]
struct Measured {
    settings: RenderSettings,
    /// The frame's cycles (golden::micro's, the RTL's cycle for cycle).
    cycles: u64,
    /// Largest and mean absolute channel difference from the truth,
    /// 0..255 scale.
    max: f64,
    mean: f64,
}

/// Every configuration docs/accuracy.md's grid has (depth 1..=8, both
/// methods of each unit, weight cutoff 0 or 2^-8..2^-1, none at depth 1, the
/// scene's own speed-ups), rendered with golden::micro and compared with
/// the f64 reference at depth 8 without cutoff.
fn brute_force(scene: &Scene) -> Vec<Measured> {
    let truth = {
        let r = RenderSettings {
            max_depth: 8,
            weight_cutoff: 0.0,
            ..scene.render
        };
        golden::reference::render(&scene.with_render(r, "truth").expect("valid"), &|_| {})
    };
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
                    let (frame, stats) = golden::micro::render(&s, &|_| {});
                    let diffs: Vec<f64> = frame
                        .pixels
                        .iter()
                        .zip(&truth.pixels)
                        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() * 255.0))
                        .collect();
                    out.push(Measured {
                        settings,
                        cycles: stats.cycles,
                        max: diffs.iter().copied().fold(0.0, f64::max),
                        mean: diffs.iter().sum::<f64>() / diffs.len() as f64,
                    });
                }
            }
        }
    }
    assert_eq!(out.len(), 4 * (1 + 7 * 9));
    out
}

/// The cheapest configuration meeting `target` in `error`, by
/// docs/accuracy.md's rule: fewest cycles, the smaller depth, the fast
/// reciprocal, the fast square root, the larger cutoff (cutoffs are
/// positive, so their bits order as the numbers do).
fn cheapest(rows: &[Measured], target: f64, error: fn(&Measured) -> f64) -> Measured {
    let exact = |m: Method| m == Method::Exact;
    *rows
        .iter()
        .filter(|m| error(m) <= target)
        .min_by_key(|m| {
            let s = &m.settings;
            (
                m.cycles,
                s.max_depth,
                exact(s.recip),
                exact(s.sqrt),
                std::cmp::Reverse(s.weight_cutoff.to_bits()),
            )
        })
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
    let best = cheapest(&rows, target, |m| m.max);
    let (cycles, depth, cheapest) = (best.cycles, best.settings.max_depth, best.settings);

    let out = tune(&format!("{w}x{h}"), &target.to_string(), &[]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    let picked = tune_pick(&stdout, &scene);
    assert_eq!(
        picked, cheapest,
        "tune's pick against the brute force's cheapest ({cycles} cycles, depth {depth})\n{stdout}"
    );
    // Whether the recommended build is one rtcosim verilates: only
    // STACK_DEPTH 8 is (build.rs); any other says so and names the lint.
    let checked = stdout
        .lines()
        .find(|l| l.starts_with("RTL build "))
        .unwrap_or_else(|| panic!("no line on the RTL build's checking\n{stdout}"));
    if depth < 8 {
        assert!(
            checked.starts_with("RTL build NOT verilated, linted or co-simulated")
                && checked.contains(&format!("-GSTACK_DEPTH={depth} ")),
            "{checked}"
        );
    } else {
        assert!(
            checked.starts_with("RTL build verilated and co-simulated: yes"),
            "{checked}"
        );
    }
    // The printed cycles are the brute force's.
    let cpp = format!("{:.1} cycles/pixel", cycles as f64 / f64::from(w * h));
    assert!(
        stdout
            .lines()
            .any(|l| l.starts_with("cheapest:") && l.contains(&cpp)),
        "{cpp}\n{stdout}"
    );
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
    let row = cheapest(&rows, target, |m| m.mean);
    assert_ne!(
        row.settings,
        cheapest(&rows, target, |m| m.max).settings,
        "at this target the two measures pick alike: pick another"
    );

    let size = format!("{w}x{h}");
    let tune_mean = |target: &str| tune(&size, target, &["--measure", "mean"]);
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
        format!(": {cpp:.1} cycles/pixel, "),
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

#[test]
fn a_bad_measure_is_refused_with_exit_2() {
    for bad in ["median", "MEAN", "avg"] {
        let mut args = common::TUNE_MIRROR_4X3.to_vec();
        args.extend(["--measure", bad]);
        common::assert_refused(
            &args,
            &[
                &format!("invalid value '{bad}' for '--measure <MEASURE>'"),
                "[possible values: max, mean]",
            ],
        );
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
