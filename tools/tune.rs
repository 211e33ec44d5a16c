//! `rtcosim tune`: the cheapest configuration that renders a scene within
//! an error target by a chosen cost (harness/campaign/tune.rs), why, the build it
//! runs on co-simulated before it is recommended, and with --area the
//! register file it needs against the full build's.

use crate::args::{RtlCheckArgs, SceneArgs, ThreadsArgs};
use crate::ui::{progress_bar, progress_spinner};
use anyhow::{Context, Result};
use golden::fp::Method;
use golden::scene::MAX_DEPTH;
use rtcosim::campaign::sweep::{Config, Row, RtlCheck};
use rtcosim::campaign::tune::{self, report, Cost, Measure, Tuned};
use rtcosim::check::compare::CompareReport;
use rtcosim::design::processor::ProcessorKind;
use rtcosim::output::area::{self, FloatUnit, UnitArea, Yosys};
use rtcosim::output::device::CostTable;
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

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
    /// What "cheapest" means: device-fps, the most frames a second from one
    /// Virtex-6 LX760 filled with the build's processors; area, the most
    /// processors on it (then the fewest LUTs each); cycles, the fewest
    /// cycles one processor takes for the frame.
    #[arg(long, value_enum, default_value_t = Cost::DeviceFps)]
    pub cost: Cost,
    /// Tune one pixel processor only: compact or fast (default: both).
    #[arg(long, value_enum)]
    pub processor: Option<ProcessorKind>,
    #[command(flatten)]
    pub check: RtlCheckArgs,
    /// Also write the answer as JSON to FILE: the pick's and the full
    /// build's rows (sweep.csv's columns), the build, its cost and its
    /// check on the RTL.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Also measure with yosys what the tuned compact build needs against
    /// the full build: the register file (STACK_DEPTH; about a second) and
    /// the reciprocal and square-root units in their methods (a synthesis
    /// of minutes per unit the first time, then cached under target/).
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

/// The answer as `--json` writes it.
#[derive(Serialize)]
struct Answer<'a> {
    scene: &'a str,
    width: u32,
    height: u32,
    measure: String,
    max_error: f64,
    cost: String,
    configurations: usize,
    /// Whether the pick met the target and its build agreed with golden.
    recommended: bool,
    pick: Option<&'a Row>,
    full: Option<&'a Row>,
    build: Option<String>,
    build_cost: Option<&'a rtcosim::output::device::Cost>,
    rtl: Option<RtlAnswer>,
}

/// The pick's check on the RTL, for `--json`.
#[derive(Serialize)]
struct RtlAnswer {
    pixels: u64,
    differing_from_full: u64,
    divergent_pixels: u64,
    agreed: bool,
}

/// Runs the grid and checks the pick on the RTL; Ok(false) when no
/// configuration meets the target or the RTL disagrees with golden on it.
pub fn run(args: TuneArgs) -> Result<bool> {
    let scene = args.scene.load()?;
    let pool = args.threads.pool()?;
    let processors: Vec<ProcessorKind> = args.processor.into_iter().collect();
    // The pick is co-simulated before it is recommended: any pick's model.
    rtcosim::campaign::sweep::check_rtl_models(
        &tune::grid(&scene, &processors).configs_for(&scene),
        std::slice::from_ref(&scene),
    )
    .map_err(|e| anyhow::anyhow!("tune co-simulates its pick, and needs {e}"))?;
    let bar = progress_bar(
        tune::grid(&scene, &processors).configs_for(&scene).len() as u64,
        "tuning   ",
        "{pos}/{len} configurations ({eta})",
    )?;
    let mut tuned = pool.install(|| {
        tune::tune(
            &args.scene.scene,
            &scene,
            args.max_error,
            args.measure,
            args.cost,
            &processors,
            &|n| bar.inc(n),
        )
    })?;
    bar.finish_and_clear();
    let options = args.check.options();
    let bar = progress_bar(0, "rtl check", "{pos}/{len} pixels ({eta})")?;
    let checked = pool.install(|| {
        tuned.confirm(
            &args.scene.scene,
            &scene,
            &options,
            &|n| bar.set_length(n),
            &|n| bar.inc(n),
        )
    })?;
    bar.finish_and_clear();

    let out = &mut std::io::stdout().lock();
    writeln!(
        out,
        "scene {} ({}x{}), {} error <= {} (0..255 scale) against the f64 reference at depth {MAX_DEPTH}, no cutoff; {} configurations on {}, cheapest by {}",
        args.scene.scene,
        scene.camera.width,
        scene.camera.height,
        args.measure,
        args.max_error,
        tuned.all.len(),
        match args.processor {
            Some(p) => format!("the {p} processor"),
            None => "both processors".into(),
        },
        args.cost
    )?;
    let recommended = match (tuned.best(), &checked) {
        (Some(best), Some((check, report))) => {
            report::explain(out, &tuned, best)?;
            let cost = CostTable::builtin_ref()?.cost(check.build)?;
            report::rtl_build(out, &best.config(), check, cost)?;
            report::rtl_check(out, check, report, &options)?
        }
        _ => {
            let closest = tuned.most_accurate().context("an empty grid")?;
            writeln!(
                out,
                "no configuration meets the target: the most accurate is {} with {} error {:.4}",
                closest.config().label(),
                args.measure,
                tuned.error(closest)
            )?;
            false
        }
    };
    if let Some(path) = &args.json {
        write_json(path, &args, &scene, &tuned, checked.as_ref(), recommended)?;
    }
    if recommended && args.area {
        let best = tuned.best().context("a pick")?;
        area(out, &best.config())?;
    }
    Ok(recommended)
}

/// An option value's name as the command line takes it.
fn value_name(v: impl clap::ValueEnum) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_string())
        .unwrap_or_default()
}

fn write_json(
    path: &Path,
    args: &TuneArgs,
    scene: &golden::scene::Scene,
    tuned: &Tuned,
    checked: Option<&(RtlCheck, CompareReport)>,
    recommended: bool,
) -> Result<()> {
    let table = CostTable::builtin_ref()?;
    let answer = Answer {
        scene: &args.scene.scene,
        width: scene.camera.width,
        height: scene.camera.height,
        measure: value_name(args.measure),
        max_error: args.max_error,
        cost: value_name(args.cost),
        configurations: tuned.all.len(),
        recommended,
        pick: tuned.best(),
        full: tuned.full(),
        build: checked.map(|(c, _)| c.build.instance()),
        build_cost: checked.map(|(c, _)| table.cost(c.build)).transpose()?,
        rtl: checked.map(|(c, r)| RtlAnswer {
            pixels: r.counts.pixels,
            differing_from_full: c.differing,
            divergent_pixels: r.counts.divergent_pixels,
            agreed: r.passed(),
        }),
    };
    let text = serde_json::to_string_pretty(&answer).context("the answer as JSON")?;
    std::fs::write(path, text + "\n").with_context(|| format!("--json {}", path.display()))
}

fn area(out: &mut impl Write, tuned: &Config) -> Result<()> {
    if tuned.processor != ProcessorKind::default() {
        writeln!(
            out,
            "area: the {} processor's build is priced by the cost table above; --area's yosys measurements are of the {} processor's register file and float units",
            tuned.processor,
            ProcessorKind::default()
        )?;
        return Ok(());
    }
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
