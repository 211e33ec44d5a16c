//! `rtcosim tune`: its answer on a tiny scene against a brute-force search
//! written here from the golden models alone, and its refusals.

mod common;

use common::{both, rtcosim, text};
use golden::fp::Method;
use golden::scene::{RenderSettings, Scene};

/// The grid docs/accuracy.md describes: depth 1..=8, both methods of each
/// unit, weight cutoff 0 or 2^-8..2^-1 (none at depth 1), the scene's own
/// speed-ups (the mirror scene meets all three preconditions).
fn grid(scene: &Scene) -> Vec<RenderSettings> {
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
                    out.push(RenderSettings {
                        max_depth,
                        recip,
                        sqrt,
                        weight_cutoff,
                        ..scene.render
                    });
                }
            }
        }
    }
    out
}

/// The largest channel difference between two frames, 0..255 scale.
fn largest_error(a: &golden::frame::Frame, b: &golden::frame::Frame) -> f64 {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() * 255.0))
        .fold(0.0, f64::max)
}

/// The value after `key` in `line` up to the next `,` or `)`.
fn field<'a>(out: &'a str, key: &str) -> &'a str {
    let at = out
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in\n{out}"))
        + key.len();
    let rest = &out[at..];
    rest[..rest.find([',', ')', '\n']).unwrap_or(rest.len())].trim()
}

#[test]
fn tune_picks_the_cheapest_configuration_a_brute_force_search_finds() {
    let (w, h) = (16, 12);
    let target = 6.0;
    let scene = Scene::builtin("mirror")
        .expect("builtin")
        .resized(w, h, "test")
        .expect("valid");
    assert!(
        scene.render.speedups.bounding_box
            && scene.render.speedups.fast_plane
            && scene.render.speedups.shadow_shortcut
    );
    let truth = {
        let r = RenderSettings {
            max_depth: 8,
            weight_cutoff: 0.0,
            ..scene.render
        };
        golden::reference::render(&scene.with_render(r, "truth").expect("valid"), &|_| {})
    };
    // Every configuration: (cycles, depth, settings, error).
    let mut meeting = Vec::new();
    let mut misses = 0;
    for r in grid(&scene) {
        let s = scene.with_render(r, "grid").expect("valid");
        let (frame, stats) = golden::micro::render(&s, &|_| {});
        let err = largest_error(&frame, &truth);
        if err <= target {
            meeting.push((stats.cycles, r.max_depth, r, err));
        } else {
            misses += 1;
        }
    }
    assert!(
        !meeting.is_empty() && misses > 0,
        "the target must split the grid"
    );
    // docs/accuracy.md's rule: fewest cycles, the smaller depth, the fast
    // reciprocal, the fast square root, the larger cutoff (cutoffs are
    // positive, so their bits order as the numbers do).
    let exact = |m: Method| m == Method::Exact;
    meeting.sort_by_key(|m| {
        (
            m.0,
            m.1,
            exact(m.2.recip),
            exact(m.2.sqrt),
            std::cmp::Reverse(m.2.weight_cutoff.to_bits()),
        )
    });
    let (cycles, depth) = (meeting[0].0, meeting[0].1);
    let cheapest = meeting[0].2;

    let size = format!("{w}x{h}");
    let out = rtcosim(&[
        "tune",
        "--scene",
        "mirror",
        "--size",
        &size,
        "--max-error",
        &target.to_string(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    let method = |m: &str| match m {
        "`FP_METHOD_EXACT" | "\"exact\"" => Method::Exact,
        "`FP_METHOD_FAST" | "\"fast\"" => Method::Fast,
        other => panic!("method {other:?}\n{stdout}"),
    };
    let picked = RenderSettings {
        max_depth: field(&stdout, ".STACK_DEPTH(").parse().expect("a depth"),
        recip: method(field(&stdout, ".RECIP_METHOD(")),
        sqrt: method(field(&stdout, ".SQRT_METHOD(")),
        weight_cutoff: field(&stdout, "weight_cutoff = ")
            .parse()
            .expect("a cutoff"),
        ..scene.render
    };
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

/// `rtcosim tune` on the mirror scene at 4x3.
fn tune_tiny(max_error: &str) -> std::process::Output {
    rtcosim(&[
        "tune",
        "--scene",
        "mirror",
        "--size",
        "4x3",
        "--max-error",
        max_error,
    ])
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
