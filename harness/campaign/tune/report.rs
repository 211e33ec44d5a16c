//! `rtcosim tune`'s report in words: the pick against the full build, its
//! neighbours, the RTL build it needs, the co-simulation that confirms it,
//! (the area against the full build's, `--area`, is the command's own).

use crate::campaign::sweep::{Config, Row, RtlCheck, CUTOFFS};
use crate::campaign::tune::{Cost, Tuned};
use crate::check::compare::CompareReport;
use crate::design::processor::ProcessorKind;
use crate::output::device::BUILT_STACK_DEPTH;
use anyhow::{Context, Result};
use golden::fp::Method;
use std::io::Write;

/// One processor's cycles for the frame, a pixel: the compact
/// processor's mean pixel; the fast one's throughput with 32 pixels in
/// flight (not a pixel's latency, sweep.csv's `cycles_per_pixel`).
pub fn frame_cycles_per_pixel(r: &Row) -> f64 {
    r.frame_cycles as f64 / (f64::from(r.width) * f64::from(r.height))
}

pub fn line(r: &Row) -> String {
    format!(
        "{}: {:.1} device frames/s ({} processors at {:.1} MHz, bound by {}), {:.1} cycles/pixel, largest error {:.4}, mean {:.5}",
        r.config().label(),
        r.device_fps,
        r.device_processors,
        r.device_clock_mhz,
        r.device_binding,
        frame_cycles_per_pixel(r),
        r.max_abs_error,
        r.mean_abs_error
    )
}

pub fn explain(out: &mut impl Write, t: &Tuned, best: &Row) -> Result<()> {
    let m = t.measure;
    let full = t.full().context("the full build is in the grid")?;
    writeln!(out, "cheapest: {}", line(best))?;
    writeln!(out, "full build: {}", line(full))?;
    match t.cost {
        Cost::DeviceFps => writeln!(
            out,
            "draws {:.2}x the full build's device frames/s",
            best.device_fps / full.device_fps
        )?,
        Cost::Area => writeln!(
            out,
            "{} processors on the device against the full build's {}, {} LUTs each against {}",
            best.device_processors,
            full.device_processors,
            best.luts_per_processor,
            full.luts_per_processor
        )?,
        Cost::Cycles => writeln!(
            out,
            "saves {:.1}% of the cycles",
            100.0 * (1.0 - best.frame_cycles as f64 / full.frame_cycles as f64)
        )?,
    }
    writeln!(out, "why:")?;
    let c = best.config();
    let err = |r: &Row| t.error(r);
    if c.depth > 1 {
        let shallower = t.neighbour(|x| {
            x.depth -= 1;
            if x.depth == 1 {
                x.cutoff = 0.0;
            }
        });
        if let Some(r) = shallower {
            writeln!(
                out,
                "  one level less ({}) would miss the target: {m} error {:.4} > {}",
                r.config().label(),
                err(r),
                t.target
            )?;
        }
    } else {
        writeln!(out, "  depth 1, the least there is: no reflection at all")?;
    }
    let next_cut = CUTOFFS.iter().copied().find(|&x| x > c.cutoff);
    match next_cut.and_then(|x| t.neighbour(|y| y.cutoff = x)) {
        Some(r) if c.depth > 1 => writeln!(
            out,
            "  the next larger cutoff ({}) gives {m} error {:.4}{}",
            r.config().label(),
            err(r),
            if err(r) > t.target {
                " (misses the target)".to_string()
            } else {
                format!(
                    " but ranks after it by {} (it checks the weight at every push: two instructions)",
                    t.cost
                )
            }
        )?,
        _ => {}
    }
    for (flip_recip, what) in [(true, "reciprocal"), (false, "square root")] {
        let other = t.neighbour(|x| {
            let m = if flip_recip {
                &mut x.recip
            } else {
                &mut x.sqrt
            };
            *m = match *m {
                Method::Exact => Method::Fast,
                Method::Fast => Method::Exact,
            };
        });
        if let Some(r) = other {
            writeln!(
                out,
                "  the other {what} method: {:.1} device frames/s, {:+.1} cycles/pixel, {m} error {:.4}",
                r.device_fps,
                frame_cycles_per_pixel(r) - frame_cycles_per_pixel(best),
                err(r)
            )?;
        }
    }
    // The glass the other way (a scene with glass only: the grid holds
    // both): opaque is a build without refraction.
    if let Some(r) = t.neighbour(|x| x.opaque_glass = !x.opaque_glass) {
        writeln!(
            out,
            "  {}: {:.1} device frames/s, {:+.1} cycles/pixel, {m} error {:.4}{}",
            if r.opaque_glass {
                "the glass opaque (a build without refraction)"
            } else {
                "the glass refracting (a build with refraction)"
            },
            r.device_fps,
            frame_cycles_per_pixel(r) - frame_cycles_per_pixel(best),
            err(r),
            if err(r) > t.target {
                " (misses the target)"
            } else {
                ""
            }
        )?;
    }
    // The nearest configuration on each other processor.
    for other in ProcessorKind::ALL
        .into_iter()
        .filter(|&k| k != best.processor)
    {
        if let Some(r) = t.neighbour(|x| x.processor = other) {
            writeln!(
                out,
                "  the same on the {} processor (the same image): {}",
                r.processor,
                line(r)
            )?;
        }
    }
    if let Some(r) = t.best_cheaper() {
        writeln!(
            out,
            "  the most accurate cheaper configuration, {}, has {m} error {:.4} > {}",
            line(r),
            err(r),
            t.target
        )?;
    } else {
        writeln!(out, "  nothing in the grid is cheaper")?;
    }
    let s = t.speedups;
    writeln!(
        out,
        "  speed-ups on (their preconditions hold): bounding_box {}, fast_plane {}, shadow_shortcut {}",
        s.bounding_box, s.fast_plane, s.shadow_shortcut
    )?;
    for (name, why) in &t.refused {
        writeln!(out, "  {name} off: {why}")?;
    }
    Ok(())
}

/// The build the pick runs on and is priced as, its cost, and the scene's
/// settings for it.
pub fn rtl_build(
    out: &mut impl Write,
    c: &Config,
    check: &RtlCheck,
    cost: &crate::output::device::Cost,
) -> Result<()> {
    writeln!(out, "RTL build: {}", check.build.instance())?;
    writeln!(
        out,
        "its cost (rtl/synth/costs.toml, {}): {} LUTs ({} as memory), {} flip-flops, {} DSP48E1, {} block RAM36, clock estimate {:.1} MHz",
        cost.source.kind(),
        cost.luts,
        cost.lut_memory,
        cost.flip_flops,
        cost.dsp48e1,
        cost.bram36,
        cost.fmax_mhz
    )?;
    writeln!(
        out,
        "scene [render]: max_depth = {}, recip = \"{}\", sqrt = \"{}\", weight_cutoff = {}, bounding_box = {}, fast_plane = {}, shadow_shortcut = {}",
        c.depth,
        c.recip.name(),
        c.sqrt.name(),
        c.cutoff,
        c.speedups.bounding_box,
        c.speedups.fast_plane,
        c.speedups.shadow_shortcut
    )?;
    if c.opaque_glass {
        writeln!(
            out,
            "scene glass: opaque (every sphere's transmission = 0): nothing refracts, and the build has no refraction (REFRACTION = 0; co-simulated as the build with it, which a scene without glass runs state for state)"
        )?;
    }
    if c.depth < BUILT_STACK_DEPTH {
        writeln!(
            out,
            "STACK_DEPTH {BUILT_STACK_DEPTH} is the build priced and co-simulated: max_depth = {} uses {} of its levels. A build with STACK_DEPTH {} would hold less (tune --area measures the compact register file), but rtcosim neither prices nor verilates it.",
            c.depth, c.depth, c.depth
        )?;
    }
    Ok(())
}

/// Prints the pick's check on the RTL; whether it agreed (the pick is
/// recommended only then).
pub fn rtl_check(
    out: &mut impl Write,
    check: &RtlCheck,
    report: &CompareReport,
    options: &crate::campaign::sweep::ConfirmOptions,
) -> Result<bool> {
    let n = report.counts.pixels;
    let drawn = n.saturating_sub(check.differing);
    writeln!(
        out,
        "co-simulated on the RTL ({}): {n} pixels, {} where the frame differs from the full build's and {drawn} more drawn with seed {}",
        check.build, check.differing, options.seed
    )?;
    if report.passed() {
        writeln!(
            out,
            "RTL and golden agree on all {n}, bit for bit and cycle for cycle: recommended"
        )?;
        Ok(true)
    } else {
        writeln!(out, "{report}")?;
        writeln!(
            out,
            "NOT recommended: the RTL build disagrees with golden on {} of {n} pixels",
            report.counts.divergent_pixels
        )?;
        Ok(false)
    }
}
