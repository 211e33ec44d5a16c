//! `rtcosim tune`: the cheapest configuration that renders a scene within
//! an error target (harness/tune.rs), why, its RTL build parameters, and
//! with --area the register file it needs against the full build's.

use crate::args::{SceneArgs, ThreadsArgs};
use crate::ui::{progress_bar, progress_spinner};
use anyhow::{Context, Result};
use golden::fp::Method;
use golden::scene::MAX_DEPTH;
use rtcosim::area::{self, FloatUnit, UnitArea, Yosys};
use rtcosim::sweep::{Config, Row, CUTOFFS};
use rtcosim::tune::{self, Measure, Tuned};
use std::io::Write;
use std::path::Path;

#[derive(clap::Args, Debug)]
pub struct TuneArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The error target on the 0..255 scale, against the f64 reference at
    /// the deepest stack (8) without cutoff: a number in (0, 255].
    #[arg(long, value_parser = parse_target)]
    pub max_error: f64,
    /// How a frame's error is summarised: the largest channel difference,
    /// or the mean.
    #[arg(long, value_enum, default_value_t = Measure::Max)]
    pub measure: Measure,
    /// Also measure with yosys what the tuned build needs against the full
    /// build: the register file (STACK_DEPTH; about a second) and the
    /// reciprocal and square-root units in their methods (a synthesis of
    /// minutes per unit the first time, then cached under target/).
    #[arg(long)]
    pub area: bool,
    #[command(flatten)]
    pub threads: ThreadsArgs,
}

fn parse_target(s: &str) -> Result<f64, String> {
    let e: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a number in (0, 255], got {s:?}"))?;
    tune::check_target(e).map_err(|err| err.to_string())
}

/// Runs the grid; Ok(false) when no configuration meets the target.
pub fn run(args: TuneArgs) -> Result<bool> {
    let scene = args.scene.load()?;
    let pool = args.threads.pool()?;
    let bar = progress_bar(
        tune::grid(&scene).configs().len() as u64,
        "tuning   ",
        "{pos}/{len} configurations ({eta})",
    )?;
    let tuned = pool.install(|| {
        tune::tune(
            &args.scene.scene,
            &scene,
            args.max_error,
            args.measure,
            &|n| bar.inc(n),
        )
    })?;
    bar.finish_and_clear();
    let out = &mut std::io::stdout().lock();
    writeln!(
        out,
        "scene {} ({}x{}), {} error <= {} (0..255 scale) against the f64 reference at depth {MAX_DEPTH}, no cutoff; {} configurations",
        args.scene.scene,
        scene.camera.width,
        scene.camera.height,
        args.measure,
        args.max_error,
        tuned.all.len()
    )?;
    let Some(best) = tuned.best() else {
        let closest = tuned.most_accurate().context("an empty grid")?;
        writeln!(
            out,
            "no configuration meets the target: the most accurate is {} with {} error {:.4}",
            closest.config().label(),
            args.measure,
            tuned.error(closest)
        )?;
        return Ok(false);
    };
    explain(out, &tuned, best)?;
    if args.area {
        area(out, &best.config())?;
    }
    Ok(true)
}

fn line(r: &Row) -> String {
    format!(
        "{}: {:.1} cycles/pixel, largest error {:.4}, mean {:.5}",
        r.config().label(),
        r.cycles_per_pixel,
        r.max_abs_error,
        r.mean_abs_error
    )
}

fn explain(out: &mut impl Write, t: &Tuned, best: &Row) -> Result<()> {
    let m = t.measure;
    let full = t.full().context("the full build is in the grid")?;
    writeln!(out, "cheapest: {}", line(best))?;
    writeln!(out, "full build: {}", line(full))?;
    writeln!(
        out,
        "saves {:.1}% of the cycles",
        100.0 * (1.0 - best.cycles_per_pixel / full.cycles_per_pixel)
    )?;
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
                " (misses the target)"
            } else {
                " but costs more cycles (two instructions per push it checks)"
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
                "  the other {what} method: {:+.1} cycles/pixel, {m} error {:.4}",
                r.cycles_per_pixel - best.cycles_per_pixel,
                err(r)
            )?;
        }
    }
    if let Some(r) = t.best_cheaper() {
        writeln!(
            out,
            "  the most accurate cheaper configuration, {}, costs {:.1} cycles/pixel less but has {m} error {:.4} > {}",
            r.config().label(),
            best.cycles_per_pixel - r.cycles_per_pixel,
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
    rtl_parameters(out, &c)
}

fn rtl_parameters(out: &mut impl Write, c: &Config) -> Result<()> {
    let param = |m| match m {
        Method::Exact => "`FP_METHOD_EXACT",
        Method::Fast => "`FP_METHOD_FAST",
    };
    writeln!(
        out,
        "RTL build: pixel_processor #(.STACK_DEPTH({}), .RECIP_METHOD({}), .SQRT_METHOD({}))",
        c.depth,
        param(c.recip),
        param(c.sqrt)
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
    writeln!(out, "{}", build_checked(c))?;
    Ok(())
}

/// Whether rtcosim itself builds and co-simulates the recommended RTL
/// build, and if not, the command that lints it. build.rs verilates the
/// pixel processor at its default `STACK_DEPTH` ([`MAX_DEPTH`]) only, once
/// per method pair: a shallower stack is simulated there through the
/// scene's `max_depth`, never as the build recommended.
fn build_checked(c: &Config) -> String {
    if c.depth == MAX_DEPTH {
        format!(
            "RTL build verilated and co-simulated: yes, as `rtcosim cosim --recip {} --sqrt {}` runs it (STACK_DEPTH {MAX_DEPTH}); tune itself renders only the micro-op model",
            c.recip.name(),
            c.sqrt.name()
        )
    } else {
        format!(
            "RTL build NOT verilated, linted or co-simulated by rtcosim: build.rs verilates STACK_DEPTH {MAX_DEPTH} only (the co-simulation runs it with max_depth = {} in the scene); lint this build with: verilator --lint-only -Wall -Irtl/fp -Irtl/pp rtl/fp/*.v rtl/pp/*.v --top-module pixel_processor -GSTACK_DEPTH={} -GRECIP_METHOD={} -GSQRT_METHOD={}",
            c.depth,
            c.depth,
            c.recip.code(),
            c.sqrt.code()
        )
    }
}

fn area(out: &mut impl Write, tuned: &Config) -> Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let yosys = Yosys::new();
    let depth = tuned.depth;
    let rf = area::register_file_area(&yosys, &root.join("rtl/pp"), depth)?;
    let rf_full = area::register_file_area(&yosys, &root.join("rtl/pp"), MAX_DEPTH)?;
    writeln!(
        out,
        "area, register file (yosys proc; opt of memory + mem_ctrl, before techmap): {} storage bits and {} cells at STACK_DEPTH {depth}, against {} bits and {} cells at {MAX_DEPTH} ({:.1}% of the storage)",
        rf.memory_bits,
        rf.cells,
        rf_full.memory_bits,
        rf_full.cells,
        100.0 * rf.memory_bits as f64 / rf_full.memory_bits as f64
    )?;
    let fp = root.join("rtl/fp");
    for (unit, method) in [
        (FloatUnit::Recip, tuned.recip),
        (FloatUnit::Sqrt, tuned.sqrt),
    ] {
        let measure = |m: Method| -> Result<UnitArea> {
            let spinner = progress_spinner("yosys    ", "{msg} {elapsed}")?;
            spinner.set_message(format!(
                "{} ({}): a synthesis of minutes the first time, then cached in {}",
                unit.module(),
                m.name(),
                yosys.cache.display()
            ));
            spinner.enable_steady_tick(std::time::Duration::from_millis(200));
            let a = area::float_unit_area(&yosys, &fp, unit, m)?;
            spinner.finish_and_clear();
            Ok(a)
        };
        let t = measure(method)?;
        let full = measure(Method::Exact)?;
        writeln!(
            out,
            "area, {} (yosys synth -flatten, generic cells): {} cells and {} flip-flops ({}), against {} cells and {} flip-flops (exact){}",
            unit.module(),
            t.cells,
            t.flip_flops,
            method.name(),
            full.cells,
            full.flip_flops,
            if method == Method::Exact {
                String::new()
            } else {
                format!(": {:.1}% of the cells", 100.0 * t.cells as f64 / full.cells as f64)
            }
        )?;
    }
    Ok(())
}
