//! `rtcosim cosim`: the verilated pixel processor (or the top with N of
//! them, `--procs`) against golden::micro.

use crate::args::{
    check_parent_dir, check_window, parse_fault, parse_window, CoverageArgs, SceneArgs,
    ThreadsArgs, TimeoutArgs,
};
use crate::ui::{plural, progress_bar, write_trace};
use anyhow::{bail, Context, Result};
use golden::micro::isa::state_label;
use golden::scene::Scene;
use golden::window::Window;
use rtcosim::check::cosim::{self, CosimError, CosimOptions, CosimReport};
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::top::Stall;
use rtcosim::design::Design;
use rtcosim::design::{Fault, HangKind, PpError};
use rtcosim::output::artefacts;
use rtcosim::output::wave::Replay;

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct CosimArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The pixels to co-simulate: columns X0..=X1 and rows Y0..=Y1
    /// (inclusive, row 0 at the top), or X,Y for one pixel (default: the
    /// whole image).
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_window)]
    pub window: Option<Window>,
    #[command(flatten)]
    pub threads: ThreadsArgs,
    /// The pixel processor: compact (rtl/pp/pixel_processor.v, one pixel at
    /// a time) or fast (rtl/fast/fast_pp.v: 32 pixel contexts in turns,
    /// pipelined, its cycles the barrel rule's, golden::micro::barrel; run
    /// through its streams, the window in tiles of 4 rows; with --procs N,
    /// N of them through rtl/top.v).
    #[arg(long, value_enum, default_value_t = ProcessorKind::default())]
    pub processor: ProcessorKind,
    /// With --processor fast: the fast processor built without its
    /// exponential (rtl/fast/fast_pp.v with EXPOSURE = 0: no fp_exp, fewer
    /// DSPs), all a scene without exposure needs. A scene that sets
    /// render.exposure is refused. One processor, not a top (--procs).
    #[arg(long)]
    pub no_exp_unit: bool,
    /// Drive the top module (rtl/top.v) with N pixel processors instead of
    /// one bare pixel processor per thread: tiles of the window are streamed
    /// through one top per thread, and the report adds the top's frame
    /// cycles and its dispatcher's idle share. Compact: N = 1 and 4 with
    /// the exact methods are built with the cargo feature `tops`; others
    /// with RTCOSIM_TOPS=N[:recip:sqrt],... set for the build (e.g.
    /// RTCOSIM_TOPS=2,8), N up to 8. Fast (--processor fast): N = 2 exact
    /// with `tops` and `fast`, others with RTCOSIM_TOPS=fast:N[:recip:sqrt],
    /// N up to 64; each pixel's cycles and the frame's are the top's
    /// rule's (golden::micro::barrel::run_top).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=64))]
    pub procs: Option<u32>,
    /// With --procs: hold the top's result stream back (out_ready low) in
    /// this percentage of the cycles, drawn from a seeded generator.
    #[arg(long, value_name = "PERCENT", default_value_t = 0,
          allow_negative_numbers = true, value_parser = clap::value_parser!(u32).range(0..=99))]
    pub stall: u32,
    /// With --stall: each draw of the generator (stalled or ready) holds
    /// for 1 to this many cycles, so that the stream is held back in long
    /// runs (1: every cycle drawn on its own).
    #[arg(long, value_name = "CYCLES", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub stall_burst: u32,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
    /// Self-test of the harness, not a check of the RTL: inject a bit flip
    /// into the RTL's writes in state STATE, so the run must fail (exit 1).
    ///
    /// XOR is XORed into lane x of every register-file write the RTL makes
    /// in controller state STATE (the golden model is left alone), so the
    /// first such write must be reported as the first divergence. STATE is
    /// a state of rtl/pp/isa.vh by name (e.g. PRI_HALF) or number; XOR is
    /// hex (0x400) or decimal, nonzero. A state that writes no register in
    /// the window leaves the run passing, with a warning.
    #[arg(long, value_name = "STATE:XOR", value_parser = parse_fault)]
    pub fault: Option<Fault>,
    /// Also write the RTL's trace (every register-file write from its trace
    /// port, and each pixel's colour and cycles) of the pixels in
    /// --trace-window to this file, in the format of `render --trace`;
    /// `trace-diff` compares it with a golden trace (`render --trace`, with
    /// the same --processor for the cycles). The fault, if any, is in it.
    /// The fast processor's trace comes from one processor fed the window
    /// in tiles of 4 rows.
    #[arg(long, value_name = "FILE")]
    pub trace: Option<PathBuf>,
    /// Write the run's files into DIR (created if missing): both sides'
    /// frames (rtl.png, golden.png, and lossless rtl.exr, golden.exr), their
    /// difference maps (diffmap/), report.json, report.md and junit.xml (one
    /// test case for the scene and method pair), and on a divergence the
    /// waveform window (wave.fst, --wave K cycles either side, default 20).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// The pixels to trace: X0,Y0,X1,Y1 or X,Y (default: --window).
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_window, requires = "trace")]
    pub trace_window: Option<Window>,
    #[command(flatten)]
    pub wave: crate::wave::WaveArgs,
    #[command(flatten)]
    pub coverage: CoverageArgs,
}

impl CosimArgs {
    /// The design the flags name, with the scene's methods; refused with
    /// the flag to change where no build makes it.
    fn design(&self, scene: &Scene) -> Result<Design> {
        let design = Design::for_scene(self.processor, scene)
            .procs(self.procs)
            .exp_unit(!self.no_exp_unit);
        if let Some(why) = design.refusal() {
            let flags = match (self.procs, self.no_exp_unit) {
                (Some(n), true) => format!("--procs {n} --no-exp-unit"),
                (Some(n), false) => format!("--procs {n}"),
                (None, true) => "--no-exp-unit".into(),
                (None, false) => format!("--processor {}", self.processor),
            };
            bail!("{flags}: {design}: {why}");
        }
        if let Some(exposure) = scene.render.exposure.filter(|_| !design.exp_unit) {
            bail!(
                "--no-exp-unit: scene {} sets an exposure (render.exposure = {exposure}), which \
                 the {} processor without its exponential cannot draw; drop --no-exp-unit",
                self.scene.scene,
                design.processor
            );
        }
        if self.stall > 0 && !design.has_result_stream() {
            bail!(
                "--stall holds back a result stream, which the {design} does not have: it needs \
                 --procs or a processor with streams (--processor fast)"
            );
        }
        if self.stall_burst > 1 && self.stall == 0 {
            bail!(
                "--stall-burst {} sets how long each stall lasts: it needs --stall PERCENT",
                self.stall_burst
            );
        }
        if self.coverage.coverage.is_some() && self.procs.is_some() {
            bail!(
                "--coverage measures a pixel processor alone (the compact one, or --processor \
                 fast); the top of --procs has no coverage model: drop one of them"
            );
        }
        design.check().map_err(|e| anyhow::anyhow!("{e}"))?;
        Ok(design)
    }

    fn stall(&self) -> Stall {
        Stall {
            percent: self.stall,
            burst: self.stall_burst,
        }
    }
}

/// Returns whether the RTL agreed with golden everywhere.
pub fn run(args: CosimArgs) -> Result<bool> {
    let scene = args.scene.load()?;
    let window = args.window.unwrap_or(Window::full(&scene));
    check_window("--window", window, &scene)?;
    let trace_window = args.trace_window.unwrap_or(window);
    if let Some(path) = &args.trace {
        check_window("--trace-window", trace_window, &scene)?;
        check_parent_dir("--trace", path)?;
    }
    let design = args.design(&scene)?;
    args.coverage.enable()?;
    args.wave.check(
        args.out.as_deref(),
        &Replay::of(&design, args.stall(), window, window.y),
    )?;
    // Fail before a long run, not after it.
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("--out {}", dir.display()))?;
    }
    let pool = args.threads.pool()?;
    let threads = pool.current_num_threads();
    let mut out = std::io::stdout().lock();
    print_header(&mut out, &args, &scene, &design, window, threads)?;
    let timeout_cycles = args.timeout.cycles(design.processor);
    let options = CosimOptions {
        fault: args.fault,
        timeout_cycles: Some(timeout_cycles),
        // Always: the saturation warning reads golden's frame.
        keep_frames: true,
        stall: args.stall(),
    };
    let bar = progress_bar(
        window.pixels(),
        "co-simulating",
        "{percent:>3}% {pos}/{len} pixels ({per_sec}, {eta})",
    )?;
    let start = Instant::now();
    let result = pool.install(|| cosim::run(&design, &scene, window, &options, &|n| bar.inc(n)));
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let report = result.map_err(|e| {
        let hint = match &e {
            CosimError::Rtl(PpError::Hung {
                kind: HangKind::Timeout,
                ..
            }) => format!(
                "; --timeout-cycles is {}: raise it if the pixel is only slow",
                timeout_cycles
            ),
            _ => String::new(),
        };
        anyhow::anyhow!("{e}{hint}").context("co-simulation stopped")
    })?;
    print_report(&mut out, &report, seconds, threads)?;
    if let Some(warning) = report
        .frames
        .as_ref()
        .and_then(|f| f.golden.saturation_warning())
    {
        writeln!(out, "{warning}")?;
    }
    let coverage = args.coverage.finish(&mut out)?;
    if let Some(dir) = &args.out {
        let run = artefacts::Run {
            scene_name: &args.scene.scene,
            scene: &scene,
            threads,
            seconds,
            coverage: coverage.as_ref(),
        };
        let written = artefacts::write(dir, &run, &report).context("--out")?;
        let names: Vec<String> = written
            .iter()
            .filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
            .collect();
        writeln!(out, "wrote {}: {}", dir.display(), names.join(", "))?;
    }
    if let Some(path) = &args.trace {
        // The processor alone, fed the window in tiles.
        let alone = design.procs(None);
        write_trace(&mut out, path, trace_window, |progress| {
            rtcosim::check::trace_files::write_rtl(
                &scene,
                &args.scene.scene,
                trace_window,
                &alone,
                args.fault,
                timeout_cycles,
                path,
                progress,
            )
        })?;
    }
    args.wave
        .write(&mut out, &scene, &report, args.out.as_deref(), |y| {
            Replay::of(&design, args.stall(), window, y)
        })?;
    Ok(report.passed())
}

/// The run's first line: what runs on what.
fn print_header(
    out: &mut impl Write,
    args: &CosimArgs,
    scene: &Scene,
    design: &Design,
    window: Window,
    threads: usize,
) -> std::io::Result<()> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let contexts = design.row().contexts;
    let stall = args.stall();
    writeln!(
        out,
        "rtcosim cosim: {} processor{}, scene {} ({w}x{h}, stack depth {}, scene hash {:016x}), \
         window {window} ({} pixel{}), recip {}, sqrt {}, {threads} thread{}{}, {}",
        design.processor,
        if design.exp_unit {
            ""
        } else {
            " without its exponential"
        },
        args.scene.scene,
        scene.render.max_depth,
        scene.render_hash(),
        window.pixels(),
        plural(window.pixels()),
        scene.render.recip,
        scene.render.sqrt,
        plural(threads as u64),
        match design.procs {
            Some(n) => format!(
                ", through the top with {n} processor{}{}",
                plural(u64::from(n)),
                if contexts > 1 {
                    format!(" of {contexts} contexts")
                } else {
                    String::new()
                }
            ),
            None if contexts > 1 => format!(", {contexts} contexts"),
            None => String::new(),
        } + &if stall.stalls() {
            format!(" (result stream {stall})")
        } else {
            String::new()
        },
        rtcosim::VERILATOR_VERSION
    )?;
    if let Some(fault) = args.fault {
        writeln!(
            out,
            "self-test: lane x of every RTL register write in state {} is XORed with {:#010x}; \
             the run must fail",
            state_label(fault.state),
            fault.xor
        )?;
    }
    writeln!(out)?;
    out.flush()
}

/// The report, cycles per pixel, speed and the verdict.
fn print_report(
    out: &mut impl Write,
    r: &CosimReport,
    seconds: f64,
    threads: usize,
) -> std::io::Result<()> {
    let c = &r.compare.counts;
    writeln!(out, "{r}")?;
    let per_pixel = |cycles: u64| cycles as f64 / c.pixels.max(1) as f64;
    writeln!(
        out,
        "cycles/pixel: mean {:.1} RTL, {:.1} golden",
        per_pixel(c.a_cycles),
        per_pixel(c.b_cycles)
    )?;
    // The clock cycles simulated: the tiles' frame cycles (one pixel at a
    // time, the pixels' cycles back to back), not a sum of latencies.
    let frame_cycles = r.stats.frame_cycles;
    writeln!(
        out,
        "{} pixel{} in {seconds:.2} s: {:.0} pixels/s, {:.2} M simulated cycles/s ({frame_cycles} \
         frame cycles; {threads} thread{})",
        c.pixels,
        plural(c.pixels),
        c.pixels as f64 / seconds.max(1e-9),
        frame_cycles as f64 / seconds.max(1e-9) / 1e6,
        plural(threads as u64)
    )?;
    writeln!(out)?;
    if r.passed() {
        writeln!(
            out,
            "PASS: the RTL agrees with golden::micro on every pixel: events, colour and cycles"
        )?;
        if let Some(fault) = r.fault {
            writeln!(
                out,
                "warning: the injected fault went unnoticed: no register write in state {} \
                 in this window, or the harness does not see the fault port",
                state_label(fault.state)
            )?;
        }
    } else if c.divergent_pixels > 0 {
        writeln!(
            out,
            "FAIL: {} of {} pixels diverge from golden::micro",
            c.divergent_pixels, c.pixels
        )?;
    } else {
        writeln!(out, "FAIL: no events were compared")?;
    }
    Ok(())
}
