//! `rtcosim`: co-simulate the handwritten RTL against the golden models.

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use golden::fp::Method;
use golden::frame::Frame;
use golden::scene::{Scene, MAX_IMAGE_SIDE};
use golden::trace::{format_event, TraceHeader, TraceReader, TraceWriter};
use indicatif::{ProgressBar, ProgressStyle};
use rtcosim::cosim::{self, CosimError, CosimOptions, CosimReport, Fault};
use rtcosim::fp_check::{self, CheckReport, Operands};
use rtcosim::fp_unit::UnitKind;
use rtcosim::pixel_proc::{state_label, HangKind, PpError, DEFAULT_TIMEOUT_CYCLES};
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
    /// Co-simulate the verilated RTL pixel processor against the golden
    /// micro-op model, pixel by pixel (the main job).
    ///
    /// Every register-file write (state, destination, lanes, bits), every
    /// pixel's colour and cycle count is compared. Exits 0 when everything
    /// agrees, 1 on any divergence, 2 on an error (a hung RTL is one).
    Cosim(CosimArgs),
    /// Co-simulate the float units of rtl/fp against golden::fp: edge cases,
    /// then seeded random operands (or every input, for unary units).
    FpCheck(FpCheckArgs),
    /// Render a scene to a PNG with a golden model (and, with --trace, write
    /// the micro-op model's trace of a window of pixels).
    Render(RenderArgs),
    /// Print a trace file (rtcosim render --trace) as text: one line per
    /// register-file write, with state and register names.
    TraceDump(TraceDumpArgs),
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
struct CosimArgs {
    /// A scene file (TOML), or the name of a builtin scene: reference,
    /// mirror, grazing, light_touch, parallel_plane, box_room.
    #[arg(long, default_value = "reference")]
    scene: String,
    /// Image size WxH instead of the scene's; the image-plane distance
    /// scales with the width, so the horizontal field of view is kept.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<Size>,
    /// The pixels to co-simulate: columns X0..=X1 and rows Y0..=Y1
    /// (inclusive, row 0 at the top), or X,Y for one pixel (default: the
    /// whole image).
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_window)]
    window: Option<Window>,
    /// The reciprocal unit's method, overriding the scene's: picks the RTL
    /// variant verilated with it, and the golden model follows.
    #[arg(long, value_enum)]
    recip: Option<MethodArg>,
    /// The square-root unit's method, overriding the scene's.
    #[arg(long, value_enum)]
    sqrt: Option<MethodArg>,
    /// Worker threads, one verilated pixel processor each (default: all
    /// cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Cycles a pixel may take before the RTL counts as hung: the run stops
    /// with an error naming the pixel and the last state.
    #[arg(
        long,
        value_name = "CYCLES",
        default_value_t = DEFAULT_TIMEOUT_CYCLES,
        value_parser = parse_timeout
    )]
    timeout_cycles: u64,
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
    fault: Option<Fault>,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum MethodArg {
    /// Correctly rounded.
    Exact,
    /// At most 1 ULP from correctly rounded, one cycle faster.
    Fast,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Method {
        match m {
            MethodArg::Exact => Method::Exact,
            MethodArg::Fast => Method::Fast,
        }
    }
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
    /// Also write the micro-op model's trace (every register-file write, in
    /// pixel order) of the pixels in --trace-window to this binary trace
    /// file; `rtcosim trace-dump` prints it. Only with --model micro.
    #[arg(long, value_name = "FILE", requires = "trace_window")]
    trace: Option<PathBuf>,
    /// The pixels to trace: columns X0..=X1 and rows Y0..=Y1 (inclusive,
    /// row 0 at the top), or X,Y for one pixel.
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_window, requires = "trace")]
    trace_window: Option<Window>,
}

#[derive(clap::Args, Debug)]
struct TraceDumpArgs {
    /// The trace file.
    file: PathBuf,
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

/// A rectangle of pixels, corners inclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Window {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
}

impl Window {
    fn pixels(&self) -> u64 {
        u64::from(self.x1 - self.x0 + 1) * u64::from(self.y1 - self.y0 + 1)
    }

    /// Fails unless the window lies inside a `width`x`height` image;
    /// `flag` names the option in the message.
    fn check_inside(&self, flag: &str, width: u32, height: u32) -> Result<()> {
        if self.x1 >= width || self.y1 >= height {
            bail!(
                "{flag} {self} is outside the {width}x{height} image \
                 (columns 0..={}, rows 0..={})",
                width - 1,
                height - 1
            );
        }
        Ok(())
    }
}

impl std::fmt::Display for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{},{},{}", self.x0, self.y0, self.x1, self.y1)
    }
}

fn parse_window(s: &str) -> Result<Window, String> {
    let bad = || {
        format!(
            "expected X0,Y0,X1,Y1 (corners inclusive, X0 <= X1, Y0 <= Y1) or X,Y, \
             e.g. 400,300,403,301; got {s:?}"
        )
    };
    let v: Vec<u32> = s
        .split(',')
        .map(|p| p.trim().parse::<u32>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    let w = match v[..] {
        [x, y] => Window {
            x0: x,
            y0: y,
            x1: x,
            y1: y,
        },
        [x0, y0, x1, y1] => Window { x0, y0, x1, y1 },
        _ => return Err(bad()),
    };
    if w.x0 > w.x1 || w.y0 > w.y1 {
        return Err(bad());
    }
    Ok(w)
}

/// A number in decimal, or in hex with a `0x` prefix.
fn parse_number(s: &str) -> Option<u64> {
    let s = s.trim();
    match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(hex) if !hex.starts_with('+') => u64::from_str_radix(hex, 16).ok(),
        Some(_) => None,
        None => s.parse().ok(),
    }
}

fn parse_timeout(s: &str) -> Result<u64, String> {
    parse_number(s)
        .filter(|&n| n >= 1)
        .ok_or_else(|| format!("expected a number of cycles, at least 1; got {s:?}"))
}

/// `STATE:XOR`: a controller state of rtl/pp/isa.vh by name (any case, an
/// `ISA_ST_` prefix allowed) or number, and a nonzero 32-bit mask.
fn parse_fault(s: &str) -> Result<Fault, String> {
    use golden::micro::isa;
    let (state_arg, xor_arg) = s
        .split_once(':')
        .ok_or_else(|| format!("expected STATE:XOR, e.g. PRI_HALF:0x400; got {s:?}"))?;
    let state_arg = state_arg.trim();
    let state = match parse_number(state_arg) {
        Some(n) => u16::try_from(n)
            .ok()
            .filter(|&id| isa::state_name(id).is_some()),
        None => {
            let upper = state_arg.to_ascii_uppercase();
            isa::state_code(upper.strip_prefix("ISA_ST_").unwrap_or(&upper))
        }
    }
    .ok_or_else(|| {
        let names: Vec<&str> = isa::STATES.iter().map(|&(name, _)| name).collect();
        format!(
            "{state_arg:?} is not a controller state of rtl/pp/isa.vh; the states: {}",
            names.join(", ")
        )
    })?;
    let xor = parse_number(xor_arg)
        .and_then(|n| u32::try_from(n).ok())
        .filter(|&x| x != 0)
        .ok_or_else(|| {
            format!(
                "the XOR mask {:?} is not a nonzero 32-bit number (hex 0x400 or decimal 1024)",
                xor_arg.trim()
            )
        })?;
    Ok(Fault { state, xor })
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
        Command::Cosim(args) => cosim_command(args),
        Command::FpCheck(args) => fp_check_command(args),
        Command::Render(args) => render_command(args).map(|()| true),
        Command::TraceDump(args) => trace_dump_command(args).map(|()| true),
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
    check_parent_dir("--out", &args.out)?;
    let trace = match (&args.trace, args.trace_window) {
        (Some(path), Some(window)) => {
            if args.model != ModelArg::Micro {
                bail!(
                    "--trace needs --model micro: the {} model executes no instructions to trace",
                    args.model.name()
                );
            }
            window.check_inside("--trace-window", scene.camera.width, scene.camera.height)?;
            check_parent_dir("--trace", path)?;
            Some((path.as_path(), window))
        }
        // clap makes each require the other.
        _ => None,
    };
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
    if let Some((path, window)) = trace {
        let events = write_trace(&scene, &args.scene, window, path)?;
        writeln!(
            out,
            "wrote {}: {events} trace events of {} pixel{} (columns {}..={}, rows {}..={})",
            path.display(),
            window.pixels(),
            if window.pixels() == 1 { "" } else { "s" },
            window.x0,
            window.x1,
            window.y0,
            window.y1
        )?;
    }
    Ok(())
}

fn cosim_command(args: CosimArgs) -> Result<bool> {
    let mut scene = load_scene(&args.scene)?;
    if let Some(size) = args.size {
        scene = scene.resized(size.width, size.height, "--size")?;
    }
    let recip = args.recip.map_or(scene.render.recip, Method::from);
    let sqrt = args.sqrt.map_or(scene.render.sqrt, Method::from);
    if (recip, sqrt) != (scene.render.recip, scene.render.sqrt) {
        let mut render = scene.render;
        render.recip = recip;
        render.sqrt = sqrt;
        scene = Scene::new(
            "--recip/--sqrt",
            scene.camera.clone(),
            scene.light.clone(),
            scene.spheres.clone(),
            scene.planes.clone(),
            render,
        )?;
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let window = match args.window {
        Some(window) => {
            window.check_inside("--window", w, h)?;
            window
        }
        None => Window {
            x0: 0,
            y0: 0,
            x1: w - 1,
            y1: h - 1,
        },
    };
    let pool = worker_pool(args.threads)?;
    let threads = pool.current_num_threads();
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "rtcosim cosim: scene {} ({w}x{h}, stack depth {}, hash {:016x}), window {window} \
         ({} pixel{}), recip {recip}, sqrt {sqrt}, {threads} thread{}, {}",
        args.scene,
        scene.render.max_depth,
        scene.content_hash(),
        window.pixels(),
        if window.pixels() == 1 { "" } else { "s" },
        if threads == 1 { "" } else { "s" },
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
    out.flush()?;
    let options = CosimOptions {
        fault: args.fault,
        timeout_cycles: args.timeout_cycles,
    };
    let bar = ProgressBar::new(window.pixels()).with_style(
        ProgressStyle::with_template(
            "co-simulating [{bar:30}] {percent:>3}% {pos}/{len} pixels ({per_sec}, {eta})",
        )
        .context("progress bar template")?
        .progress_chars("=> "),
    );
    let start = Instant::now();
    let cosim_window = cosim::Window::new(
        window.x0,
        window.y0,
        window.x1 - window.x0 + 1,
        window.y1 - window.y0 + 1,
    );
    let result = pool.install(|| cosim::run(&scene, cosim_window, &options, &|n| bar.inc(n)));
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let report = result.map_err(|e| {
        let hint = match &e {
            CosimError::Rtl(PpError::Hung {
                kind: HangKind::Timeout,
                ..
            }) => format!(
                "; --timeout-cycles is {}: raise it if the pixel is only slow",
                args.timeout_cycles
            ),
            _ => String::new(),
        };
        anyhow::anyhow!("{e}{hint}").context("co-simulation stopped")
    })?;
    print_cosim(&mut out, &report, seconds, threads)?;
    Ok(report.passed())
}

/// The report, cycles per pixel, speed and the verdict.
fn print_cosim(
    out: &mut impl Write,
    r: &CosimReport,
    seconds: f64,
    threads: usize,
) -> std::io::Result<()> {
    writeln!(out, "{r}")?;
    let per_pixel = |c: u64| c as f64 / r.pixels.max(1) as f64;
    writeln!(
        out,
        "cycles/pixel: mean {:.1} RTL, {:.1} golden",
        per_pixel(r.rtl_cycles),
        per_pixel(r.golden_cycles)
    )?;
    writeln!(
        out,
        "{} pixel{} in {seconds:.2} s: {:.0} pixels/s, {:.2} M RTL cycles/s ({threads} thread{})",
        r.pixels,
        if r.pixels == 1 { "" } else { "s" },
        r.pixels as f64 / seconds.max(1e-9),
        r.rtl_cycles as f64 / seconds.max(1e-9) / 1e6,
        if threads == 1 { "" } else { "s" }
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
    } else if r.divergent_pixels > 0 {
        writeln!(
            out,
            "FAIL: {} of {} pixels diverge from golden::micro",
            r.divergent_pixels, r.pixels
        )?;
    } else {
        writeln!(out, "FAIL: no events were compared")?;
    }
    Ok(())
}

/// Fails unless the directory `path` would be written into exists.
fn check_parent_dir(flag: &str, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            bail!(
                "{flag} {}: no such directory {}",
                path.display(),
                dir.display()
            );
        }
    }
    Ok(())
}

/// Writes the micro-op model's trace of the pixels in `window`, row by row,
/// left to right, to `path`; returns the number of events.
fn write_trace(scene: &Scene, scene_arg: &str, window: Window, path: &Path) -> Result<u64> {
    let context = || format!("--trace {}", path.display());
    let file = std::fs::File::create(path).with_context(context)?;
    let header = TraceHeader {
        scene_hash: scene.content_hash(),
        config: trace_config(scene, scene_arg, window),
    };
    let mut writer =
        TraceWriter::new(std::io::BufWriter::new(file), &header).with_context(context)?;
    let proc = golden::micro::Processor::new(scene);
    let bar = ProgressBar::new(window.pixels()).with_style(
        ProgressStyle::with_template("tracing   [{bar:30}] {percent:>3}% ({eta})")
            .context("progress bar template")?
            .progress_chars("=> "),
    );
    let mut events = 0;
    for y in window.y0..=window.y1 {
        for x in window.x0..=window.x1 {
            let mut failed = None;
            let r = proc.render_pixel(x, y, |e, _| {
                if failed.is_none() {
                    failed = writer.write(e).err();
                }
            });
            if let Some(e) = failed {
                return Err(e).with_context(context);
            }
            events += r.ops.register_writes;
            bar.inc(1);
        }
    }
    writer.finish().with_context(context)?;
    bar.finish_and_clear();
    Ok(events)
}

/// The trace header's configuration text: `key=value` pairs.
fn trace_config(scene: &Scene, scene_arg: &str, window: Window) -> String {
    let r = &scene.render;
    let speedups: Vec<&str> = [
        (r.speedups.bounding_box, "bounding_box"),
        (r.speedups.fast_plane, "fast_plane"),
        (r.speedups.shadow_shortcut, "shadow_shortcut"),
    ]
    .into_iter()
    .filter_map(|(on, name)| on.then_some(name))
    .collect();
    format!(
        "writer=rtcosim-{} model=micro scene={} size={}x{} depth={} recip={} sqrt={} speedups={} window={window}",
        env!("CARGO_PKG_VERSION"),
        scene_arg.replace(char::is_whitespace, "_"),
        scene.camera.width,
        scene.camera.height,
        r.max_depth,
        r.recip,
        r.sqrt,
        if speedups.is_empty() {
            "none".to_string()
        } else {
            speedups.join(",")
        },
    )
}

fn trace_dump_command(args: TraceDumpArgs) -> Result<()> {
    use golden::micro::isa;
    let path = args.file.display();
    let file = std::fs::File::open(&args.file).with_context(|| format!("{path}"))?;
    let reader =
        TraceReader::new(std::io::BufReader::new(file)).with_context(|| format!("{path}"))?;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(
        out,
        "# {path}: rtcosim trace version {}, scene hash {:016x}",
        golden::trace::VERSION,
        reader.header().scene_hash
    )?;
    writeln!(out, "# {}", reader.header().config)?;
    let mut events = 0u64;
    for event in reader {
        let event = event.with_context(|| format!("{path}"))?;
        writeln!(
            out,
            "{}",
            format_event(&event, &isa::state_name, &isa::register_name)
        )?;
        events += 1;
    }
    writeln!(out, "# {events} events")?;
    out.flush()?;
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
        "{:<8} {:>12.2} {:>7} {:>14.2}  (+{} done cycle per pixel)",
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
    fn trace_windows_parse_as_inclusive_corners_or_one_pixel() {
        assert_eq!(
            parse_window("400,300,403,301"),
            Ok(Window {
                x0: 400,
                y0: 300,
                x1: 403,
                y1: 301
            })
        );
        assert_eq!(
            parse_window(" 7, 9"),
            Ok(Window {
                x0: 7,
                y0: 9,
                x1: 7,
                y1: 9
            })
        );
        assert_eq!(parse_window("0,0,799,599").map(|w| w.pixels()), Ok(480_000));
        for bad in [
            "",
            "1",
            "1,2,3",
            "1,2,3,4,5",
            "4,0,3,0",
            "0,4,0,3",
            "-1,0",
            "a,b",
        ] {
            assert!(parse_window(bad).is_err(), "{bad:?}");
        }
        let w = parse_window("0,0,79,59").expect("valid");
        assert!(w.check_inside("--window", 80, 60).is_ok());
        assert!(w.check_inside("--window", 79, 60).is_err());
        assert!(w.check_inside("--window", 80, 59).is_err());
    }

    #[test]
    fn a_trace_command_line_parses() {
        let cli = Cli::try_parse_from([
            "rtcosim",
            "render",
            "--model",
            "micro",
            "--trace",
            "/tmp/t.rtt",
            "--trace-window",
            "1,2,3,4",
        ])
        .expect("valid command line");
        let Command::Render(args) = cli.command else {
            panic!("expected the render subcommand");
        };
        assert_eq!(args.trace, Some(PathBuf::from("/tmp/t.rtt")));
        assert_eq!(
            args.trace_window.map(|w| w.to_string()),
            Some("1,2,3,4".into())
        );
        let cli = Cli::try_parse_from(["rtcosim", "trace-dump", "/tmp/t.rtt"]).expect("valid");
        assert!(matches!(cli.command, Command::TraceDump(_)));
    }

    #[test]
    fn cosim_defaults_to_the_whole_reference_scene_with_its_methods() {
        let cli = Cli::try_parse_from(["rtcosim", "cosim"]).expect("valid command line");
        let Command::Cosim(args) = cli.command else {
            panic!("expected the cosim subcommand, got {:?}", cli.command);
        };
        assert_eq!(args.scene, "reference");
        assert_eq!((args.size, args.window), (None, None));
        assert_eq!((args.recip, args.sqrt), (None, None));
        assert_eq!(args.timeout_cycles, DEFAULT_TIMEOUT_CYCLES);
        assert_eq!((args.threads, args.fault), (None, None));
    }

    #[test]
    fn a_full_cosim_command_line_parses() {
        let cli = Cli::try_parse_from([
            "rtcosim",
            "cosim",
            "--scene",
            "box_room",
            "--size",
            "40x30",
            "--window",
            "1,2,30,20",
            "--recip",
            "fast",
            "--sqrt",
            "exact",
            "--threads",
            "1",
            "--timeout-cycles",
            "5000",
            "--fault",
            "PRI_HALF:0x400",
        ])
        .expect("valid command line");
        let Command::Cosim(args) = cli.command else {
            panic!("expected the cosim subcommand");
        };
        assert_eq!(args.window.map(|w| w.to_string()), Some("1,2,30,20".into()));
        assert_eq!(args.recip, Some(MethodArg::Fast));
        assert_eq!(args.sqrt, Some(MethodArg::Exact));
        assert_eq!(args.timeout_cycles, 5000);
        assert_eq!(
            args.fault,
            Some(Fault {
                state: golden::micro::isa::state::PRI_HALF,
                xor: 0x400
            })
        );
        for bad in [
            &["--timeout-cycles", "0"][..],
            &["--recip", "slow"],
            &["--window", "5,5,4,6"],
            &["--fault", "PRI_HALF"],
        ] {
            let err = Cli::try_parse_from([&["rtcosim", "cosim"][..], bad].concat())
                .expect_err("a usage error");
            assert_eq!(err.exit_code(), 2, "{bad:?}");
        }
    }

    #[test]
    fn faults_name_a_state_by_name_or_number_and_a_nonzero_mask() {
        use golden::micro::isa::{state, state_name};
        let half = Fault {
            state: state::PRI_HALF,
            xor: 0x400,
        };
        for spec in [
            "PRI_HALF:0x400".to_string(),
            "pri_half:1024".to_string(),
            "ISA_ST_PRI_HALF:0X400".to_string(),
            format!(" {} : 0x0400 ", state::PRI_HALF),
        ] {
            assert_eq!(parse_fault(&spec), Ok(half), "{spec:?}");
        }
        let all = parse_fault("PRI_ITOF:0xffffffff").expect("every bit");
        assert_eq!(all.xor, u32::MAX);
        let unnamed = (0..=u16::MAX)
            .find(|&id| state_name(id).is_none())
            .expect("some id is no state");
        for (spec, message) in [
            ("PRI_HALF".to_string(), "expected STATE:XOR"),
            ("PRI_HALF:0".to_string(), "nonzero"),
            ("PRI_HALF:0x100000000".to_string(), "32-bit"),
            ("PRI_HALF:-1".to_string(), "\"-1\""),
            ("PRI_HALF:0x".to_string(), "\"0x\""),
            (
                "NO_SUCH_STATE:1".to_string(),
                "\"NO_SUCH_STATE\" is not a controller state",
            ),
            (format!("{unnamed}:1"), "is not a controller state"),
            ("70000:1".to_string(), "is not a controller state"),
        ] {
            let err = parse_fault(&spec).expect_err(&spec);
            assert!(err.contains(message), "{spec:?}: {err}");
        }
        // The refusal lists the states to choose from.
        let err = parse_fault("NOPE:1").expect_err("no such state");
        assert!(
            err.contains("PRI_HALF") && err.contains("PRI_ITOF"),
            "{err}"
        );
    }

    #[test]
    fn the_scene_help_lists_every_builtin_scene() {
        let cmd = Cli::command();
        for sub in ["render", "cosim"] {
            let sub = cmd.find_subcommand(sub).expect("subcommand");
            let scene = sub
                .get_arguments()
                .find(|a| a.get_id() == "scene")
                .expect("--scene");
            let help = scene.get_help().expect("documented").to_string();
            for name in Scene::builtin_names() {
                assert!(help.contains(name), "--scene help lacks {name}: {help}");
            }
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
