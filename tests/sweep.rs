//! `rtcosim sweep`: a tiny sweep whose CSV is checked against computations
//! made here, independently of the sweep's code (the micro-op model's frame
//! statistics, the errors against the f64 reference pixel by pixel, the
//! Pareto front by a different algorithm), its chart files, and a fault that
//! makes the RTL confirmation fail.

mod common;

use common::{arg, rtcosim, scratch, text};
use golden::fp::{ulp_distance, Method, UlpDistance};
use golden::frame::Frame;
use golden::micro::barrel::{self, PixelWork};
use golden::scene::{RenderSettings, Scene, Speedups};
use std::collections::HashMap;
use std::path::Path;

/// The documented column order (docs/accuracy.md, "Speed against accuracy").
const HEADER: [&str; 36] = [
    "scene",
    "width",
    "height",
    "processor",
    "recip",
    "sqrt",
    "depth",
    "bounding_box",
    "fast_plane",
    "shadow_shortcut",
    "weight_cutoff",
    "opaque_glass",
    "cycles_per_pixel",
    "max_cycles",
    "frame_cycles",
    "fps_at_clock_mhz",
    "clock_mhz",
    "device_processors",
    "device_binding",
    "device_clock_mhz",
    "device_fps",
    "luts_per_processor",
    "dsp_per_processor",
    "cost_source",
    "mean_abs_error",
    "max_abs_error",
    "share_pixels_over_half",
    "max_ulps",
    "nan_mismatches",
    "rtl_stack_depth",
    "rtl_recip_method",
    "rtl_sqrt_method",
    "pareto",
    "differs_from_full",
    "rtl_pixels",
    "rtl_confirmed",
];

type Record = HashMap<String, String>;

fn read_csv(path: &Path) -> (Vec<String>, Vec<Record>) {
    let mut reader = csv::Reader::from_path(path).expect("sweep.csv");
    let header: Vec<String> = reader
        .headers()
        .expect("a header")
        .iter()
        .map(String::from)
        .collect();
    let rows = reader
        .records()
        .map(|r| {
            let r = r.expect("a well-formed row");
            header
                .iter()
                .cloned()
                .zip(r.iter().map(String::from))
                .collect()
        })
        .collect();
    (header, rows)
}

fn num(r: &Record, col: &str) -> f64 {
    r[col]
        .parse()
        .unwrap_or_else(|e| panic!("{col} = {:?}: {e}", r[col]))
}

/// The reference scene at 24x18 with this configuration.
fn scene(depth: u32, recip: Method, sqrt: Method, speedups: Speedups, cutoff: f32) -> Scene {
    let base = Scene::reference().resized(24, 18, "test").expect("valid");
    #[allow(clippy::needless_update)] // keeps settings the test does not name
    let render = RenderSettings {
        max_depth: depth,
        speedups,
        recip,
        sqrt,
        weight_cutoff: cutoff,
        ..base.render
    };
    Scene::new(
        "test",
        base.camera.clone(),
        base.light.clone(),
        base.spheres.clone(),
        base.planes.clone(),
        render,
    )
    .expect("the reference scene takes every speed-up")
}

fn method(s: &str) -> Method {
    match s {
        "exact" => Method::Exact,
        "fast" => Method::Fast,
        _ => panic!("method {s:?}"),
    }
}

fn row_scene(r: &Record) -> Scene {
    let flag = |c: &str| r[c] == "true";
    scene(
        num(r, "depth") as u32,
        method(&r["recip"]),
        method(&r["sqrt"]),
        Speedups {
            bounding_box: flag("bounding_box"),
            fast_plane: flag("fast_plane"),
            shadow_shortcut: flag("shadow_shortcut"),
        },
        num(r, "weight_cutoff") as f32,
    )
}

/// Errors of `frame` against `reference`, computed channel by channel here:
/// (mean abs, max abs, share of pixels with a channel over 0.5, max ULP).
fn errors(frame: &Frame, reference: &Frame) -> (f64, f64, f64, u32) {
    let (mut sum, mut max, mut over, mut ulps, mut n) = (0.0, 0.0f64, 0usize, 0u32, 0usize);
    for (p, q) in frame.pixels.iter().zip(&reference.pixels) {
        let mut visible = false;
        for ch in 0..3 {
            let d = (p[ch] - q[ch]).abs() * 255.0;
            sum += d;
            n += 1;
            max = max.max(d);
            visible |= d > 0.5;
            if let UlpDistance::Ulps(u) = ulp_distance(p[ch] as f32, q[ch] as f32, true) {
                ulps = ulps.max(u);
            }
        }
        over += usize::from(visible);
    }
    (
        sum / n as f64,
        max,
        over as f64 / frame.pixels.len() as f64,
        ulps,
    )
}

/// The front by another algorithm than the sweep's pairwise test, over
/// points (gain on the axis, more is better; error; a tie-break, more is
/// better): sort by gain descending, then error, then tie-break
/// descending; walking down the gains, a row is on the front iff its
/// error is below every error of a strictly larger gain and it is the
/// first of its own gain in that order (least error, then largest
/// tie-break), or equal to it.
fn front_by_sorting(points: &[(f64, f64, f64)]) -> Vec<bool> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| {
        let (p, q) = (points[a], points[b]);
        q.0.total_cmp(&p.0)
            .then(p.1.total_cmp(&q.1))
            .then(q.2.total_cmp(&p.2))
    });
    let mut on = vec![false; points.len()];
    let mut best_below = f64::INFINITY;
    let mut i = 0;
    while i < order.len() {
        let (gain, least, most) = points[order[i]];
        let mut j = i;
        while j < order.len() && points[order[j]].0 == gain {
            let (_, e, t) = points[order[j]];
            on[order[j]] = e == least && t == most && e < best_below;
            j += 1;
        }
        best_below = best_below.min(least);
        i = j;
    }
    on
}

#[test]
fn a_tiny_sweep_agrees_with_independent_computations() {
    let dir = scratch("sweep", "tiny");
    let out = rtcosim(&[
        "sweep",
        "--scene",
        "reference",
        "--size",
        "24x18",
        "--depths",
        "1,4",
        "--cutoffs",
        "0,1/16",
        "--sample",
        "16",
        "--out",
        arg(&dir),
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    let (header, rows) = read_csv(&dir.join("sweep.csv"));
    assert_eq!(header, HEADER);
    // The table says which clocks its frames/s are at.
    assert!(
        stdout.contains("| device frames/s | frames/s at 8.94 MHz |")
            && stdout.contains(
                "one processor's at 8.94 MHz, our pixel processor's post-route clock on ECP5"
            ),
        "{stdout}"
    );
    // 2 processors x 2 recip x 2 sqrt x 8 speed-up sets x (depth 1 with
    // cutoff 0, depth 4 with cutoffs 0 and 1/16); the reference scene
    // refuses none.
    assert_eq!(rows.len(), 192);
    assert!(
        stdout.contains("192 configurations run, 0 refused"),
        "{stdout}"
    );
    let cut = rows
        .iter()
        .filter(|r| r["weight_cutoff"] == "0.0625")
        .count();
    assert_eq!(cut, 64, "depth 4 only");

    let deepest = scene(8, Method::Exact, Method::Exact, Speedups::default(), 0.0);
    let reference = golden::reference::render(&deepest, &|_| {});
    let full = golden::micro::render(&deepest, &|_| {}).0;
    for r in &rows {
        let s = row_scene(r);
        let (frame, stats) = golden::micro::render(&s, &|_| {});
        let what = format!("{r:?}");
        // The compact processor's cycles are its pixels' sum; the fast
        // one's, the barrel rule's over the pixels in row order, plus the
        // 4 cycles from the stream to the first take and from the last
        // done turn to the result (docs/fast.md).
        let frame_cycles = if r["processor"] == "fast" {
            let work: Vec<PixelWork> = (0..18)
                .flat_map(|y| (0..24).map(move |x| (x, y)))
                .map(|(x, y)| PixelWork::of(&golden::micro::render_pixel(&s, x, y, |_, _| {})))
                .collect();
            barrel::run(32, &work).cycles + 4
        } else {
            assert_eq!(r["processor"], "compact");
            assert_eq!(num(r, "max_cycles"), stats.max_cycles as f64, "{what}");
            assert!((num(r, "cycles_per_pixel") - stats.cycles as f64 / 432.0).abs() < 1e-9);
            stats.cycles
        };
        assert_eq!(num(r, "frame_cycles"), frame_cycles as f64, "{what}");
        // The default clock: our processor's 8.94 MHz after place and
        // route on ECP5 (docs/rtl.md, Synthesis), not the thesis' 34.74.
        assert_eq!(r["clock_mhz"], "8.94", "{what}");
        let fps = num(r, "fps_at_clock_mhz");
        assert!(
            (fps - 8.94e6 / frame_cycles as f64).abs() < 1e-9 * fps,
            "{what}"
        );
        // The device: processors x clock / frame cycles, and for the exact
        // pair the fills docs/rtl.md states (the compact processor: 10 by
        // its 80 DSPs at 7.3 MHz; the fast one, built without its
        // exponential since the reference scene has no exposure: 35 by
        // block RAM at 112.9).
        let device = num(r, "device_fps");
        let want =
            num(r, "device_processors") * num(r, "device_clock_mhz") * 1e6 / frame_cycles as f64;
        assert!((device - want).abs() <= 1e-9 * want, "{what}");
        if (&*r["recip"], &*r["sqrt"]) == ("exact", "exact") {
            let fill = (
                &*r["device_processors"],
                &*r["device_binding"],
                &*r["device_clock_mhz"],
            );
            if r["processor"] == "fast" {
                assert_eq!(fill, ("35", "block RAM", "112.9"), "{what}");
            } else {
                assert_eq!(fill, ("10", "DSP48E1", "7.23"), "{what}");
            }
            assert_eq!(r["cost_source"], "measured");
        }
        let (mean, max, share, ulps) = errors(&frame, &reference);
        assert!(
            (num(r, "mean_abs_error") - mean).abs() <= 1e-12 * mean.max(1.0),
            "{what}"
        );
        assert_eq!(num(r, "max_abs_error"), max, "{what}");
        assert_eq!(num(r, "share_pixels_over_half"), share, "{what}");
        assert_eq!(num(r, "max_ulps"), f64::from(ulps), "{what}");
        assert_eq!(r["rtl_stack_depth"], r["depth"]);
        assert_eq!(
            r["rtl_recip_method"],
            if r["recip"] == "fast" { "1" } else { "0" }
        );
        if r["pareto"] == "true" {
            // Every pixel that differs from the full configuration's frame
            // was co-simulated, and the RTL agreed.
            let differ = frame
                .pixels
                .iter()
                .zip(&full.pixels)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(num(r, "differs_from_full"), differ as f64, "{what}");
            let checked = num(r, "rtl_pixels");
            assert!(
                checked >= differ.max(16) as f64 && checked <= 432.0,
                "{what}"
            );
            assert_eq!(r["rtl_confirmed"], "true", "{what}");
        } else {
            assert_eq!(
                (
                    &*r["differs_from_full"],
                    &*r["rtl_pixels"],
                    &*r["rtl_confirmed"]
                ),
                ("", "", "")
            );
        }
    }
    let points: Vec<(f64, f64, f64)> = rows
        .iter()
        .map(|r| (num(r, "device_fps"), num(r, "mean_abs_error"), 0.0))
        .collect();
    let front = front_by_sorting(&points);
    for (r, on) in rows.iter().zip(&front) {
        assert_eq!(r["pareto"], on.to_string(), "{r:?}");
    }
    assert!(front.iter().filter(|&&on| on).count() >= 2);

    // The chart files.
    for ext in ["svg", "png"] {
        let path = dir.join(format!("chart-reference.{ext}"));
        assert!(stdout.contains(&path.display().to_string()), "{stdout}");
    }
    let png = image::open(dir.join("chart-reference.png")).expect("a valid PNG");
    assert_eq!((png.width(), png.height()), (960, 640));
    let svg = std::fs::read_to_string(dir.join("chart-reference.svg")).expect("the SVG");
    assert!(svg.trim_start().starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(
        svg.contains("thesis: 2 processors, 28.86 MHz")
            && svg.contains("Pareto front")
            && svg.contains("fast processor"),
        "{svg}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("sweep.json")).expect("sweep.json"))
            .expect("valid JSON");
    assert_eq!(
        json["scenes"][0]["rows"].as_array().map(Vec::len),
        Some(192)
    );
    assert_eq!(json["rtl"], true);
    assert_eq!(json["device"], "Virtex-6 LX760");
    assert_eq!(json["clock_mhz"].as_f64(), Some(8.94));
    assert!(
        json["clock_source"]
            .as_str()
            .is_some_and(|s| s.contains("post-route clock on ECP5")),
        "{}",
        json["clock_source"]
    );
}

/// A sweep of the reference scene at 16x12, depth 2, 8 sampled pixels, into
/// `dir`, with `extra` arguments.
fn small_sweep(dir: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "sweep",
        "--scene",
        "reference",
        "--size",
        "16x12",
        "--depths",
        "2",
        "--sample",
        "8",
        "--out",
        arg(dir),
    ];
    args.extend(extra);
    rtcosim(&args)
}

#[test]
fn an_injected_rtl_fault_fails_the_confirmation() {
    let dir = scratch("sweep", "fault");
    let out = small_sweep(&dir, &["--fault", "PRI_HALF:0x400"]);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}{}", text(&out.stderr));
    assert!(stdout.contains("FAILED"), "{stdout}");
    let (_, rows) = read_csv(&dir.join("sweep.csv"));
    let front: Vec<&Record> = rows.iter().filter(|r| r["pareto"] == "true").collect();
    assert!(!front.is_empty());
    assert!(
        front.iter().all(|r| r["rtl_confirmed"] == "false"),
        "{front:?}"
    );
}

/// `--processor fast`: only the fast processor is swept, its front
/// confirmed on it (each configuration's pixels streamed through it,
/// cycles by the barrel rule), and a fault in it fails the confirmation.
#[test]
fn the_front_is_confirmed_on_the_fast_processor_and_a_fault_in_it_fails() {
    for fault in [None, Some("PRI_HALF:0x400")] {
        let dir = scratch(
            "sweep",
            if fault.is_some() {
                "fast-fault"
            } else {
                "fast"
            },
        );
        let mut args = vec!["--processor", "fast"];
        if let Some(f) = fault {
            args.extend(["--fault", f]);
        }
        let out = small_sweep(&dir, &args);
        let stdout = text(&out.stdout);
        let expected = if fault.is_some() { 1 } else { 0 };
        assert_eq!(
            out.status.code(),
            Some(expected),
            "{stdout}{}",
            text(&out.stderr)
        );
        assert!(
            stdout.contains(
                "front: over (device-fps, mean error); each front row co-simulated on its own processor"
            ),
            "{stdout}"
        );
        let (_, rows) = read_csv(&dir.join("sweep.csv"));
        assert!(rows.iter().all(|r| r["processor"] == "fast"));
        let front: Vec<&Record> = rows.iter().filter(|r| r["pareto"] == "true").collect();
        assert!(!front.is_empty());
        let verdict = if fault.is_some() { "false" } else { "true" };
        assert!(
            front
                .iter()
                .all(|r| r["rtl_confirmed"] == verdict && num(r, "rtl_pixels") >= 8.0),
            "{front:?}"
        );
    }
}

/// `--axis luts` and `--axis dsp`: the front is over one processor's
/// area and the error (among rows equal in both, the most device frames/s),
/// by an independent computation; every front row is confirmed on the
/// RTL; the chart's x is the area, without the thesis' hardware (its area
/// is not known); sweep.json names the axis.
#[test]
fn an_area_axis_puts_the_front_on_luts_or_dsps() {
    for (axis, column, title) in [
        ("luts", "luts_per_processor", "slice LUTs of one processor"),
        (
            "dsp",
            "dsp_per_processor",
            "DSP48E1 slices of one processor",
        ),
    ] {
        let dir = scratch("sweep", &format!("axis-{axis}"));
        // Depth 1 as well as 2: the fastest rows, on the frames/s front,
        // are no smaller than depth 2's and worse.
        let out = small_sweep(&dir, &["--axis", axis, "--depths", "1"]);
        let stdout = text(&out.stdout);
        assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
        assert!(
            stdout.contains(&format!("front: over ({axis}, mean error); ")),
            "{stdout}"
        );
        let (_, rows) = read_csv(&dir.join("sweep.csv"));
        let points: Vec<(f64, f64, f64)> = rows
            .iter()
            .map(|r| {
                (
                    -num(r, column),
                    num(r, "mean_abs_error"),
                    num(r, "device_fps"),
                )
            })
            .collect();
        let front = front_by_sorting(&points);
        for (r, on) in rows.iter().zip(&front) {
            assert_eq!(r["pareto"], on.to_string(), "{axis}: {r:?}");
            if *on {
                assert_eq!(r["rtl_confirmed"], "true", "{axis}: {r:?}");
            }
        }
        // Not the frames/s front.
        let fps: Vec<(f64, f64, f64)> = rows
            .iter()
            .map(|r| (num(r, "device_fps"), num(r, "mean_abs_error"), 0.0))
            .collect();
        assert_ne!(front, front_by_sorting(&fps), "{axis}");
        // The least area of the grid is on the front.
        let least = points.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
        assert!(
            rows.iter()
                .zip(&front)
                .any(|(r, on)| *on && -num(r, column) == least),
            "{axis}"
        );
        let svg = std::fs::read_to_string(dir.join("chart-reference.svg")).expect("the SVG");
        assert!(
            svg.contains(title) && !svg.contains("thesis: 2 processors"),
            "{axis}: {svg}"
        );
        let json: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join("sweep.json")).expect("sweep.json"))
                .expect("valid JSON");
        assert_eq!(json["scenes"][0]["axis"], axis);
    }
}

#[test]
fn refused_configurations_are_skipped_and_counted() {
    let dir = scratch("sweep", "box-room");
    let out = rtcosim(&[
        "sweep",
        "--scene",
        "box_room",
        "--size",
        "12x9",
        "--depths",
        "2",
        "--cutoffs",
        "0",
        "--no-rtl",
        "--out",
        arg(&dir),
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", text(&out.stderr));
    // box_room breaks the shadow shortcut's precondition: the 4 speed-up
    // sets with it, of 8, for each of the 4 method pairs and 2 processors.
    assert!(
        stdout.contains("32 configurations run, 32 refused"),
        "{stdout}"
    );
    let (_, rows) = read_csv(&dir.join("sweep.csv"));
    assert_eq!(rows.len(), 32);
    assert!(rows
        .iter()
        .all(|r| r["shadow_shortcut"] == "false" && r["rtl_confirmed"].is_empty()));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("sweep.json")).expect("sweep.json"))
            .expect("valid JSON");
    let skipped = json["scenes"][0]["skipped"].as_array().expect("skipped");
    assert_eq!(skipped.len(), 32);
    assert!(skipped.iter().all(|s| s["reason"]
        .as_str()
        .is_some_and(|r| r.contains("shadow_shortcut"))));
}

#[test]
fn bad_arguments_are_refused_naming_the_flag() {
    let dir = scratch("sweep", "bad");
    let cases: [(&[&str], &str); 6] = [
        (&["--axis", "area"], "--axis"),
        (&["--depths", "0,9"], "--depths"),
        (&["--scene", "no-such-scene"], "no-such-scene"),
        (&["--clock-mhz", "0"], "--clock-mhz"),
        (&["--cutoffs", "0,1.5"], "--cutoffs"),
        (&["--cutoffs", "2/3"], "--cutoffs"),
    ];
    for (extra, message) in cases {
        let mut args = vec!["sweep", "--size", "8x6", "--out", arg(&dir)];
        args.extend_from_slice(extra);
        let out = rtcosim(&args);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(message), "{extra:?}: {stderr}");
    }
}
