//! `rtcosim render`: a scene to a PNG with a golden model, and the micro-op
//! model's trace of a window.

use crate::args::{
    check_parent_dir, check_window, parse_fault, parse_window, SceneArgs, ThreadsArgs,
};
use crate::ui::{plural, progress_bar, write_trace};
use anyhow::{bail, Result};
use clap::ValueEnum;
use golden::frame::Frame;
use golden::micro::Fault;
use golden::micro::{FrameStats, OpClass};
use golden::scene::Scene;
use golden::window::Window;
use rtcosim::design::processor::ProcessorKind;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// The model that renders.
    #[arg(long, value_enum, default_value_t = Model::Reference)]
    pub model: Model,
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Where to write the PNG.
    #[arg(long, default_value = "render.png")]
    pub out: PathBuf,
    /// Also write the frame losslessly as f32 OpenEXR, for `rtcosim diffmap`
    /// (the f64 reference is rounded to the nearest f32: at most 2^-25 on a
    /// channel <= 1; diffmap's `reference` side renders it exactly).
    #[arg(long, value_name = "FILE")]
    pub exr: Option<PathBuf>,
    #[command(flatten)]
    pub threads: ThreadsArgs,
    /// Also write the micro-op model's trace (every register-file write, in
    /// pixel order) of the pixels in --trace-window to this binary trace
    /// file; `rtcosim trace-dump` prints it. Only with --model micro.
    #[arg(long, value_name = "FILE", requires = "trace_window")]
    pub trace: Option<PathBuf>,
    /// The pixels to trace: columns X0..=X1 and rows Y0..=Y1 (inclusive,
    /// row 0 at the top), or X,Y for one pixel.
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_window, requires = "trace")]
    pub trace_window: Option<Window>,
    /// Self-test of a checker: inject a bit flip into the micro-op model's
    /// writes in state STATE for the trace (as `cosim --fault` does into
    /// the RTL's), so that a trace diff against a clean trace must find it.
    /// Only with --trace.
    #[arg(long, value_name = "STATE:XOR", value_parser = parse_fault, requires = "trace")]
    pub fault: Option<Fault>,
    /// Whose cycles the trace's pixels carry: the compact processor's
    /// (golden::micro's rule), or the fast one's (the barrel rule, the
    /// window streamed in tiles of 4 rows, as `cosim --processor fast
    /// --trace` runs it). Only with --trace.
    #[arg(long, value_enum, default_value_t, requires = "trace")]
    pub processor: ProcessorKind,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// The f64 reference renderer (golden::reference), ground truth.
    Reference,
    /// The f32 micro-op model of the RTL pixel processor (golden::micro):
    /// also reports cycles per pixel and the instruction mix.
    Micro,
}

impl Model {
    fn name(self) -> &'static str {
        match self {
            Model::Reference => "reference",
            Model::Micro => "micro",
        }
    }

    /// Renders `scene` on the current rayon pool, with the cycle statistics
    /// of the models that have them.
    pub fn render(
        self,
        scene: &Scene,
        progress: &(dyn Fn(u64) + Sync),
    ) -> (Frame, Option<FrameStats>) {
        match self {
            Model::Reference => (golden::reference::render(scene, progress), None),
            Model::Micro => {
                let (frame, stats) = golden::micro::render(scene, progress);
                (frame, Some(stats))
            }
        }
    }
}

pub fn run(args: RenderArgs) -> Result<()> {
    let scene = args.scene.load()?;
    // Fail before a long render, not after it.
    check_parent_dir("--out", &args.out)?;
    if let Some(exr) = &args.exr {
        check_parent_dir("--exr", exr)?;
    }
    let trace = match (&args.trace, args.trace_window) {
        (Some(path), Some(window)) => {
            if args.model != Model::Micro {
                bail!(
                    "--trace needs --model micro: the {} model executes no instructions to trace",
                    args.model.name()
                );
            }
            check_window("--trace-window", window, &scene)?;
            check_parent_dir("--trace", path)?;
            Some((path.as_path(), window))
        }
        // clap makes each require the other.
        _ => None,
    };
    let pool = args.threads.pool()?;
    let threads = pool.current_num_threads();
    let mut out = std::io::stdout().lock();
    let (w, h) = (scene.camera.width, scene.camera.height);
    writeln!(
        out,
        "rtcosim render: {} model, scene {} ({w}x{h}, stack depth {}, scene hash {:016x}), {threads} thread{}",
        args.model.name(),
        args.scene.scene,
        scene.render.max_depth,
        scene.render_hash(),
        plural(threads as u64)
    )?;
    let bar = progress_bar(scene.pixel_count(), "rendering", "{percent:>3}% ({eta})")?;
    let start = Instant::now();
    let (frame, stats) = pool.install(|| args.model.render(&scene, &|n| bar.inc(n)));
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    frame.save_png(&args.out)?;
    writeln!(
        out,
        "{w}x{h} in {seconds:.3} s ({:.2} frames/s), largest channel value {:.6}",
        1.0 / seconds.max(1e-9),
        frame.max_channel(),
    )?;
    if let Some(warning) = frame.saturation_warning() {
        writeln!(out, "{warning}")?;
    }
    if let Some(stats) = stats {
        print_cycles(&mut out, &stats)?;
    }
    writeln!(out, "wrote {}", args.out.display())?;
    if let Some(exr) = &args.exr {
        frame.save_exr(exr)?;
        writeln!(out, "wrote {}", exr.display())?;
    }
    if let Some((path, window)) = trace {
        write_trace(&mut out, path, window, |progress| {
            rtcosim::check::trace_files::write_golden(
                &scene,
                &args.scene.scene,
                window,
                args.processor,
                args.fault,
                path,
                progress,
            )
        })?;
    }
    Ok(())
}

/// Cycles per pixel and the instruction mix of a micro-model render.
fn print_cycles(out: &mut impl Write, s: &FrameStats) -> std::io::Result<()> {
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
        "{:<8} {:>12.2} {:>7} {:>14.2}  (+{} done cycle per pixel)",
        "all",
        per_pixel(s.ops.instructions()),
        "",
        per_pixel(s.ops.instruction_cycles()),
        golden::micro::FIXED_CYCLES
    )
}
