//! `rtcosim`: co-simulate the handwritten RTL against the golden models.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use golden::fp::Method;
use golden::frame::Frame;
use golden::scene::{Scene, MAX_IMAGE_SIDE};
use indicatif::{ProgressBar, ProgressStyle};
use rtcosim::fp_check::{self, CheckReport, Operands};
use rtcosim::fp_unit::UnitKind;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Co-simulate the float units of rtl/fp against golden::fp: edge cases,
    /// then seeded random operands (or every input, for unary units).
    FpCheck(FpCheckArgs),
    /// Render a scene to a PNG with a golden model.
    Render(RenderArgs),
}

#[derive(clap::Args, Debug)]
struct FpCheckArgs {
    /// Units to check (default: all).
    #[arg(long, value_enum, value_delimiter = ',')]
    unit: Vec<UnitArg>,
    /// Random operands per unit.
    #[arg(long, default_value_t = 1_000_000)]
    count: u64,
    /// Seed of the random operand stream.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Sweep all 2^32 inputs of the unary units instead of random operands
    /// (binary units still get --count random operands).
    #[arg(long)]
    exhaustive: bool,
    /// Worker threads, one verilated model each (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    /// The model that renders.
    #[arg(long, value_enum, default_value_t = ModelArg::Reference)]
    model: ModelArg,
    /// A scene file (TOML), or the name of a builtin scene: reference,
    /// mirror, grazing, light_touch, parallel_plane, box_room.
    #[arg(long, default_value = "reference")]
    scene: String,
    /// Image size WxH instead of the scene's; the image-plane distance
    /// scales with the width, so the horizontal field of view is kept.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<Size>,
    /// Where to write the PNG.
    #[arg(long, default_value = "render.png")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum ModelArg {
    /// The f64 reference renderer (golden::reference), ground truth.
    Reference,
    /// The f32 micro-op model of the RTL pixel processor (golden::micro):
    /// also reports cycles per pixel and the instruction mix.
    Micro,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Size {
    width: u32,
    height: u32,
}

fn parse_size(s: &str) -> Result<Size, String> {
    let bad =
        || format!("expected WIDTHxHEIGHT, each 1..={MAX_IMAGE_SIDE}, e.g. 800x600; got {s:?}");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=MAX_IMAGE_SIDE).contains(n))
            .ok_or_else(bad)
    };
    Ok(Size {
        width: side(w)?,
        height: side(h)?,
    })
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum UnitArg {
    Add,
    Mul,
    Itof,
    RecipExact,
    RecipFast,
    SqrtExact,
    SqrtFast,
}

impl From<UnitArg> for UnitKind {
    fn from(u: UnitArg) -> UnitKind {
        match u {
            UnitArg::Add => UnitKind::Add,
            UnitArg::Mul => UnitKind::Mul,
            UnitArg::Itof => UnitKind::Itof,
            UnitArg::RecipExact => UnitKind::Recip(Method::Exact),
            UnitArg::RecipFast => UnitKind::Recip(Method::Fast),
            UnitArg::SqrtExact => UnitKind::Sqrt(Method::Exact),
            UnitArg::SqrtFast => UnitKind::Sqrt(Method::Fast),
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        // The reader went away (`rtcosim ... | head`): nothing left to say.
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Returns whether every check passed.
fn run(cli: Cli) -> Result<bool> {
    match cli.command {
        Command::FpCheck(args) => fp_check_command(args),
        Command::Render(args) => render_command(args).map(|()| true),
    }
}

/// A scene file if `arg` names one, else a builtin scene of that name.
fn load_scene(arg: &str) -> Result<Scene> {
    let path = Path::new(arg);
    if path.exists() {
        return Ok(Scene::load(path)?);
    }
    Scene::builtin(arg).with_context(|| {
        format!(
            "{arg}: no such scene file, nor a builtin scene (builtins: {})",
            Scene::builtin_names().join(", ")
        )
    })
}

fn render_command(args: RenderArgs) -> Result<()> {
    let mut scene = load_scene(&args.scene)?;
    if let Some(size) = args.size {
        scene = scene.resized(size.width, size.height, "--size")?;
    }
    // Fail before a long render, not after it.
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            bail!(
                "--out {}: no such directory {}",
                args.out.display(),
                dir.display()
            );
        }
    }
    let pool = worker_pool(args.threads)?;
    let mut out = std::io::stdout().lock();
    let (w, h) = (scene.camera.width, scene.camera.height);
    writeln!(
        out,
        "rtcosim render: {} model, scene {} ({w}x{h}, stack depth {}, hash {:016x}), {} thread{}",
        args.model.name(),
        args.scene,
        scene.render.max_depth,
        scene.content_hash(),
        pool.current_num_threads(),
        if pool.current_num_threads() == 1 {
            ""
        } else {
            "s"
        }
    )?;
    let bar = ProgressBar::new(scene.pixel_count()).with_style(
        ProgressStyle::with_template("rendering [{bar:30}] {percent:>3}% ({eta})")
            .context("progress bar template")?
            .progress_chars("=> "),
    );
    let start = Instant::now();
    let (frame, stats) = pool.install(|| render_with(args.model, &scene, &|n| bar.inc(n)))?;
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    frame.save_png(&args.out)?;
    writeln!(
        out,
        "{w}x{h} in {seconds:.3} s ({:.2} frames/s), largest channel value {:.6}{}",
        1.0 / seconds.max(1e-9),
        frame.max_channel(),
        if frame.max_channel() > 1.0 {
            " (> 1: saturates, thesis 3.7)"
        } else {
            ""
        }
    )?;
    if let Some(stats) = stats {
        print_cycles(&mut out, &stats)?;
    }
    writeln!(out, "wrote {}", args.out.display())?;
    Ok(())
}

/// Cycles per pixel and the instruction mix of a micro-model render.
fn print_cycles(out: &mut impl Write, s: &golden::micro::FrameStats) -> std::io::Result<()> {
    use golden::micro::OpClass;
    writeln!(
        out,
        "cycles/pixel: mean {:.1}, max {} at {:?}, min {} ({} cycles in all)",
        s.mean_cycles(),
        s.max_cycles,
        s.max_pixel,
        s.min_cycles,
        s.cycles
    )?;
    let (n, c) = (
        s.ops.instructions().max(1),
        s.ops.instruction_cycles().max(1),
    );
    let per_pixel = |x: u64| x as f64 / s.pixels.max(1) as f64;
    writeln!(
        out,
        "{:<8} {:>12} {:>7} {:>14} {:>7}",
        "class", "instr/pixel", "share", "cycles/pixel", "share"
    )?;
    for class in OpClass::ALL {
        let (ci, cc) = (s.ops.count_of(class), s.ops.cycles_of(class));
        writeln!(
            out,
            "{:<8} {:>12.2} {:>6.1}% {:>14.2} {:>6.1}%",
            class.name(),
            per_pixel(ci),
            100.0 * ci as f64 / n as f64,
            per_pixel(cc),
            100.0 * cc as f64 / c as f64
        )?;
    }
    writeln!(
        out,
        "{:<8} {:>12.2} {:>7} {:>14.2}  (+{} start/done cycles per pixel)",
        "all",
        per_pixel(s.ops.instructions()),
        "",
        per_pixel(s.ops.instruction_cycles()),
        golden::micro::FIXED_CYCLES
    )
}

/// Renders with the chosen model on the current rayon pool, with the cycle
/// statistics of the models that have them. Fallible so that models which
/// can refuse a scene (the RTL) fit in.
fn render_with(
    model: ModelArg,
    scene: &Scene,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(Frame, Option<golden::micro::FrameStats>)> {
    match model {
        ModelArg::Reference => Ok((golden::reference::render(scene, progress), None)),
        ModelArg::Micro => {
            let (frame, stats) = golden::micro::render(scene, progress);
            Ok((frame, Some(stats)))
        }
    }
}

impl ModelArg {
    fn name(self) -> &'static str {
        match self {
            ModelArg::Reference => "reference",
            ModelArg::Micro => "micro",
        }
    }
}

/// A rayon pool of `threads` workers (default: one per core).
fn worker_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(threads) = threads {
        if threads == 0 {
            bail!("--threads must be at least 1");
        }
        builder = builder.num_threads(threads);
    }
    builder.build().context("starting the worker threads")
}

fn fp_check_command(args: FpCheckArgs) -> Result<bool> {
    let mut out = std::io::stdout().lock();
    if let Some(threads) = args.threads {
        if threads == 0 {
            bail!("--threads must be at least 1");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()
            .context("starting the worker threads")?;
    }
    let units: Vec<UnitKind> = if args.unit.is_empty() {
        UnitKind::ALL.to_vec()
    } else {
        args.unit.iter().map(|&u| u.into()).collect()
    };
    writeln!(
        out,
        "rtcosim fp-check: {} units, {}, seed {}, {} threads, {}",
        units.len(),
        if args.exhaustive {
            "all 2^32 inputs (unary)".to_string()
        } else {
            format!("{} random operands", args.count)
        },
        args.seed,
        rayon::current_num_threads(),
        rtcosim::VERILATOR_VERSION
    )?;
    writeln!(out)?;
    writeln!(
        out,
        "{:<16} {:>7} {:>12} {:>10} {:>12} {:>13}",
        "unit", "cycles", "operands", "mismatch", "worst error", "Mevals/s/model"
    )?;
    let mut all_passed = true;
    let mut failures = Vec::new();
    for kind in units {
        let random = if args.exhaustive && !kind.is_binary() {
            Operands::Exhaustive
        } else {
            Operands::Random {
                seed: args.seed,
                count: args.count,
            }
        };
        let edge = fp_check::run(kind, Operands::Edge, &|_| {})?;
        let bar = ProgressBar::new(random.count(kind)).with_style(
            ProgressStyle::with_template("{prefix:<16} [{bar:30}] {pos}/{len} ({eta})")
                .context("progress bar template")?
                .progress_chars("=> "),
        );
        bar.set_prefix(kind.to_string());
        let report = fp_check::run(kind, random, &|n| bar.inc(n))?;
        bar.finish_and_clear();
        let report = edge.merge(report);
        print_row(&mut out, &report)?;
        all_passed &= report.passed();
        if !report.passed() {
            failures.push(report);
        }
    }
    for report in &failures {
        writeln!(out)?;
        writeln!(
            out,
            "{}: {} mismatches, {} cycle-count violations (promised {} cycles)",
            report.unit,
            report.mismatches,
            report.latency_violations,
            report.unit.latency()
        )?;
        for m in &report.first_mismatches {
            writeln!(out, "  {m}")?;
        }
    }
    writeln!(out)?;
    writeln!(
        out,
        "{}",
        if all_passed {
            "all units agree with golden::fp"
        } else {
            "MISMATCHES FOUND"
        }
    )?;
    Ok(all_passed)
}

fn print_row(out: &mut impl Write, r: &CheckReport) -> std::io::Result<()> {
    let cycles = match r.cycles {
        Some((0, 0)) | None => "comb".to_string(),
        Some((lo, hi)) if lo == hi => lo.to_string(),
        Some((lo, hi)) => format!("{lo}-{hi}"),
    };
    writeln!(
        out,
        "{:<16} {:>7} {:>12} {:>10} {:>12} {:>13.2}",
        r.unit.to_string(),
        cycles,
        r.operands,
        r.mismatches,
        r.worst_error.to_string(),
        r.evals_per_second() / 1e6
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn a_typical_render_command_line_parses() {
        let cli = Cli::try_parse_from([
            "rtcosim",
            "render",
            "--model",
            "reference",
            "--scene",
            "mirror",
            "--size",
            "160x120",
            "--out",
            "/tmp/m.png",
            "--threads",
            "2",
        ])
        .expect("valid command line");
        let Command::Render(args) = cli.command else {
            panic!("expected the render subcommand, got {:?}", cli.command);
        };
        assert_eq!(args.model, ModelArg::Reference);
        assert_eq!(args.scene, "mirror");
        assert_eq!(
            args.size,
            Some(Size {
                width: 160,
                height: 120
            })
        );
        assert_eq!(args.out, PathBuf::from("/tmp/m.png"));
        assert_eq!(args.threads, Some(2));
    }

    #[test]
    fn render_defaults_to_the_reference_scene_and_render_png() {
        let cli = Cli::try_parse_from(["rtcosim", "render"]).expect("valid command line");
        let Command::Render(args) = cli.command else {
            panic!("expected the render subcommand");
        };
        assert_eq!(args.model, ModelArg::Reference);
        assert_eq!(args.scene, "reference");
        assert_eq!(args.size, None);
        assert_eq!(args.out, PathBuf::from("render.png"));
    }

    #[test]
    fn bad_sizes_and_unknown_models_are_usage_errors() {
        for size in [
            "0x10",
            "10x0",
            "100000x10",
            "800",
            "axb",
            "800x600x2",
            "-1x5",
        ] {
            let err = Cli::try_parse_from(["rtcosim", "render", "--size", size]).expect_err(size);
            assert_eq!(err.exit_code(), 2, "{size}");
        }
        let err = Cli::try_parse_from(["rtcosim", "render", "--model", "rtl-someday"])
            .expect_err("no such model");
        assert_eq!(err.exit_code(), 2);
        let cli = Cli::try_parse_from(["rtcosim", "render", "--model", "micro"])
            .expect("the micro-op model exists");
        let Command::Render(args) = cli.command else {
            panic!("expected the render subcommand");
        };
        assert_eq!(args.model, ModelArg::Micro);
    }

    #[test]
    fn the_scene_help_lists_every_builtin_scene() {
        let cmd = Cli::command();
        let render = cmd.find_subcommand("render").expect("render subcommand");
        let scene = render
            .get_arguments()
            .find(|a| a.get_id() == "scene")
            .expect("--scene");
        let help = scene.get_help().expect("documented").to_string();
        for name in Scene::builtin_names() {
            assert!(help.contains(name), "--scene help lacks {name}: {help}");
        }
    }

    #[test]
    fn an_unknown_scene_name_lists_the_builtins() {
        let err = load_scene("no-such-scene").expect_err("neither a file nor a builtin");
        let msg = format!("{err:#}");
        assert!(
            msg.contains("no-such-scene") && msg.contains("mirror"),
            "{msg}"
        );
    }
}
