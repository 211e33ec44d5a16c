//! `rtcosim sweep`: speed against accuracy over the grid of configurations.

use crate::args::{parse_cutoff, parse_size, RtlCheckArgs, ShardArgs, Size, ThreadsArgs};
use crate::ui::{plural, progress_bar};
use anyhow::{Context, Result};
use golden::scene::{Scene, MAX_DEPTH};
use rtcosim::campaign::shard::file::{self as shard_file, ShardFile};
use rtcosim::campaign::shard::Shard;
use rtcosim::campaign::sweep::run::{self, NamedScene, RunConfig, ShardResult};
use rtcosim::campaign::sweep::{self, chart, Axis, Row, SceneSweep, ECP5_CLOCK_HZ};
use rtcosim::design::processor::ProcessorKind;
use rtcosim::scenes::{self, Overrides};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// A scene file (TOML) or builtin scene name.
    #[arg(long, default_value = "reference", conflicts_with = "scenes")]
    pub scene: String,
    /// Several scenes, comma-separated (one CSV, one chart per scene).
    #[arg(long, value_delimiter = ',', value_name = "S1,S2,...")]
    pub scenes: Vec<String>,
    /// Image size WxH instead of each scene's (field of view kept).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<Size>,
    /// Stack depths to sweep, comma-separated (default: 1 to 8).
    #[arg(long, value_delimiter = ',', value_name = "D1,D2,...",
          value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_DEPTH)))]
    pub depths: Vec<u32>,
    /// Weight cutoffs to sweep, comma-separated, each a number or 1/N in
    /// [0, 1]; 0 is off (default: 0,1/256,1/16). Depth 1 takes only 0.
    #[arg(long, value_delimiter = ',', value_name = "C1,C2,...", value_parser = parse_cutoff)]
    pub cutoffs: Vec<f32>,
    /// Write sweep.csv, sweep.json and chart-<scene>.svg/.png into DIR
    /// (created if missing); a shard writes its sweep-K-of-N.shard.json.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// The clock the frames/s column is stated at, in MHz: one pixel
    /// processor's frames per second at that clock. Default: our
    /// processor's post-route clock on ECP5 (docs/rtl.md, Synthesis); the
    /// thesis' Virtex-6 clock, which ours does not reach, is 34.74.
    #[arg(long, value_name = "MHZ", default_value_t = ECP5_CLOCK_HZ / 1e6)]
    pub clock_mhz: f64,
    /// Do not co-simulate the front on the RTL (the RTL columns stay empty).
    #[arg(long)]
    pub no_rtl: bool,
    /// Sweep one pixel processor only: compact (rtl/pp/pixel_processor.v)
    /// or fast (rtl/fast/fast_pp.v). Default: both, each front row
    /// co-simulated on its own processor (the fast one streams a
    /// configuration's pixels through it in chunks of 1,024).
    #[arg(long, value_enum)]
    pub processor: Option<ProcessorKind>,
    /// What the Pareto front and the chart's x axis weigh the error
    /// against: device-fps, frames/s of one Virtex-6 LX760 full of the
    /// row's processors; luts or dsp, one processor's LUTs or DSP48E1s
    /// (its area).
    #[arg(long, value_enum, default_value_t = Axis::DeviceFps)]
    pub axis: Axis,
    #[command(flatten)]
    pub check: RtlCheckArgs,
    #[command(flatten)]
    pub threads: ThreadsArgs,
    #[command(flatten)]
    pub shard: ShardArgs,
}

/// Returns whether the RTL confirmed every front configuration (a shard
/// confirms nothing: its merge does).
pub fn run(args: SweepArgs) -> Result<bool> {
    if !(args.clock_mhz.is_finite() && args.clock_mhz > 0.0) {
        anyhow::bail!("--clock-mhz {}: must be a positive number", args.clock_mhz);
    }
    let shard = args.shard.resolve()?;
    let names = if args.scenes.is_empty() {
        vec![args.scene.clone()]
    } else {
        args.scenes.clone()
    };
    let overrides = Overrides {
        size: args.size.map(|s| (s.width, s.height)),
        ..Overrides::default()
    };
    let scenes = names
        .iter()
        .map(|n| {
            let scene = scenes::load_with(n, overrides).with_context(|| format!("--scene {n}"))?;
            Ok(NamedScene {
                name: n.clone(),
                toml: scene.to_toml(),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    std::fs::create_dir_all(&args.out).with_context(|| format!("--out {}", args.out.display()))?;
    let config = RunConfig {
        scenes,
        depths: args.depths.clone(),
        cutoffs: args.cutoffs.clone(),
        clock_mhz: args.clock_mhz,
        rtl: !args.no_rtl,
        sample: args.check.sample,
        seed: args.check.seed,
        fault: args.check.fault.map(|f| f.to_string()),
        timeout_cycles: args.check.timeout.timeout_cycles,
        processors: args.processor.map(|p| vec![p]).unwrap_or_default(),
        axis: args.axis,
        verilator: rtcosim::VERILATOR_VERSION.into(),
    };
    // Every path, the whole run's and a shard's, reads the scenes back
    // from the configuration's text, as a merge does.
    let scenes = config.load_scenes()?;
    if config.rtl {
        sweep::check_rtl_models(&config.grid().configs(), &scenes)
            .map_err(|e| anyhow::anyhow!("the RTL confirmation (--no-rtl skips it) needs {e}"))?;
    }
    let pool = args.threads.pool()?;
    let measured = measure(&config, &scenes, shard.unwrap_or(Shard::WHOLE), &pool)?;
    match shard {
        Some(shard) => {
            let total = config.work().len() as u64;
            let file = ShardFile::new(
                run::TOOL,
                shard_file::run_config(&config),
                shard,
                total,
                ShardResult::new(&measured),
            );
            let path = file.write(&args.out)?;
            let mut stdout = std::io::stdout().lock();
            writeln!(
                stdout,
                "shard {shard}: {} of {total} configurations of {} scene{}; wrote {}",
                measured.len(),
                config.scenes.len(),
                plural(config.scenes.len() as u64),
                path.display()
            )?;
            writeln!(
                stdout,
                "merge every shard's file with: rtcosim merge {} --out DIR",
                args.out.display()
            )?;
            Ok(true)
        }
        None => finish(&config, &scenes, measured, &args.out, &pool),
    }
}

/// Measures `shard`'s configurations with a progress bar.
fn measure(
    config: &RunConfig,
    scenes: &[Scene],
    shard: Shard,
    pool: &rayon::ThreadPool,
) -> Result<Vec<run::Measured>> {
    let items = shard.positions(config.work().len() as u64).len() as u64;
    let bar = progress_bar(
        items,
        "sweep    ",
        "{pos}/{len} configurations {msg} ({eta})",
    )?;
    let measured = pool.install(|| {
        run::measure(
            config,
            scenes,
            shard,
            &|name| bar.set_message(format!("({name})")),
            &|n| bar.inc(n),
        )
    })?;
    bar.finish_and_clear();
    Ok(measured)
}

/// Everything after the measurements, which needs every row of a scene:
/// the front confirmed on the RTL, the tables, the charts, the CSV and the
/// JSON into `out`. The unsharded run and `rtcosim merge` both end here.
/// Returns whether the RTL confirmed every front configuration.
pub fn finish(
    config: &RunConfig,
    scenes: &[Scene],
    measured: Vec<run::Measured>,
    out: &Path,
    pool: &rayon::ThreadPool,
) -> Result<bool> {
    let options = config
        .confirm_options()
        .map_err(|e| anyhow::anyhow!("the run's configuration: {e}"))?;
    let mut stdout = std::io::stdout().lock();
    let mut sweeps = run::assemble(config, scenes, measured);
    let mut all_confirmed = true;
    for s in &mut sweeps {
        if let Some(options) = &options {
            let bar = progress_bar(0, "RTL      ", "{pos}/{len} pixels {msg} ({eta})")?;
            bar.set_message(format!("({})", s.name));
            pool.install(|| sweep::confirm(s, options, &|n| bar.set_length(n), &|n| bar.inc(n)))?;
            bar.finish_and_clear();
        }
        all_confirmed &= s.rows.iter().all(|r| r.rtl_confirmed != Some(false));
        print_scene(&mut stdout, s, config.clock_mhz, options.is_some())?;
        let svg = out.join(format!("chart-{}.svg", file_stem(&s.name)));
        let png = svg.with_extension("png");
        chart::write(s, &svg, &png)?;
        writeln!(stdout, "wrote {} and {}", svg.display(), png.display())?;
    }
    let rows: Vec<Row> = sweeps.iter().flat_map(|s| s.rows.iter().cloned()).collect();
    let csv = out.join("sweep.csv");
    let json = out.join("sweep.json");
    sweep::write_csv(&csv, &rows)?;
    sweep::write_json(&json, &sweeps, config.clock_hz(), options.is_some())?;
    writeln!(stdout, "wrote {} and {}", csv.display(), json.display())?;
    if !all_confirmed {
        writeln!(
            stdout,
            "FAILED: the RTL disagreed with the micro-op model on a front configuration"
        )?;
    }
    Ok(all_confirmed)
}

/// A scene name as a file name: the file stem of a path, else the name.
fn file_stem(name: &str) -> String {
    std::path::Path::new(name)
        .file_stem()
        .map_or_else(|| name.to_string(), |s| s.to_string_lossy().into_owned())
}

/// The scene's front and its thesis configuration, as a table, with
/// frames/s of one device and of one processor at `clock_mhz`, the front
/// confirmed on the RTL if `rtl`.
fn print_scene(out: &mut impl Write, s: &SceneSweep, clock_mhz: f64, rtl: bool) -> Result<()> {
    let (w, h) = (s.scene.camera.width, s.scene.camera.height);
    writeln!(
        out,
        "{} {w}x{h}: {} configuration{} run, {} refused by the scene (a speed-up's precondition)",
        s.name,
        s.rows.len(),
        plural(s.rows.len() as u64),
        s.skipped.len()
    )?;
    writeln!(
        out,
        "device frames/s: one {} filled with processors of the row's build at its clock \
         estimate (rtl/synth/costs.toml); one processor's at {clock_mhz} MHz, {}",
        rtcosim::output::device::Device::LX760.name,
        sweep::clock_source(clock_mhz)
    )?;
    writeln!(
        out,
        "front: over ({}, mean error){}",
        s.axis.name(),
        if rtl {
            "; each front row co-simulated on its own processor"
        } else {
            ""
        }
    )?;
    writeln!(
        out,
        "| processor | depth | recip | sqrt | speed-ups | cutoff | cycles/pixel | LUTs | DSP | processors x MHz | device frames/s | {} | mean err | max err | px > 0.5 | max ULP | front | RTL pixels | RTL |",
        sweep::fps_header(clock_mhz)
    )?;
    writeln!(
        out,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    )?;
    let thesis = s.thesis();
    let mut shown: Vec<&Row> = s.rows.iter().filter(|r| r.pareto).collect();
    // Worst on the axis first, down to the best.
    shown.sort_by(|a, b| s.axis.gain(a).total_cmp(&s.axis.gain(b)));
    if let Some(t) = thesis.filter(|t| !t.pareto) {
        shown.push(t);
    }
    for r in shown {
        let rtl = match r.rtl_confirmed {
            Some(true) => "confirmed",
            Some(false) => "FAILED",
            None => "-",
        };
        let mark = if Some(r) == thesis { " (thesis)" } else { "" };
        writeln!(
            out,
            "| {} | {} | {} | {} | {}{mark} | {} | {:.2} | {} | {} | {} x {} | {:.3} | {:.4} | {:.3e} | {:.4} | {:.3}% | {} | {} | {} | {rtl} |",
            r.processor,
            r.depth,
            r.recip,
            r.sqrt,
            sweep::speedup_label(r.config().speedups),
            r.weight_cutoff,
            r.cycles_per_pixel,
            r.luts_per_processor,
            r.dsp_per_processor,
            r.device_processors,
            r.device_clock_mhz,
            r.device_fps,
            r.fps_at_clock_mhz,
            r.mean_abs_error,
            r.max_abs_error,
            100.0 * r.share_pixels_over_half,
            r.max_ulps,
            if r.pareto { "yes" } else { "no" },
            r.rtl_pixels.map_or("-".into(), |n| n.to_string()),
        )?;
    }
    Ok(())
}
