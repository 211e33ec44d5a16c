//! The live co-simulation: the verilated pixel processor against the golden
//! micro-op model ([`golden::micro`]), bit for bit and cycle for cycle.
//!
//! Every pixel of a window runs on both. The RTL's trace events of the pixel
//! are buffered (one pixel's worth, a few hundred), then the golden model
//! runs and [`compare`](crate::compare) pairs each of its events with the
//! RTL's at the same sequence number as it is produced. Nothing bigger than
//! a pixel is stored: a whole frame's trace is tens of millions of events.
//!
//! Rows run in parallel on the current rayon pool, one [`PixelProcessor`] per
//! worker (built lazily) sharing one golden [`Processor`] (immutable). The
//! per-row reports merge exactly (see [`CompareReport::merge`]), so the report
//! is the same whatever the number of threads.
//!
//! [`run_top`] is the second driver under the same engine: the window is
//! cut into tiles of [`TILE_ROWS`] rows (whatever the thread count), each
//! tile streamed through a [`Top`] of N processors (one per worker, reset
//! and loaded for every tile, so a tile's cycles do not depend on which
//! worker ran what before), and each pixel compared with golden as its
//! result leaves the top. The comparison is the same report as [`run`]'s for
//! any N and any thread count; [`TopReport`] adds what the top cost.

use crate::compare::{compare_pixel, CompareReport, Labels, PixelVerdict, Tolerance};
use crate::device::{Build, BUILT_STACK_DEPTH};
use crate::pixel_proc::{Fault, PixelProcessor, PpError, DEFAULT_TIMEOUT_CYCLES};
use crate::processor::ProcessorKind;
use crate::top::{FrameStats, Source, Stall, Top, FAST_CONTEXTS};
use golden::fp::Method;
use golden::frame::Frame;
use golden::micro::barrel::{self, PixelWork, TopStart};
use golden::micro::isa::state_label;
use golden::micro::Processor;
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use golden::window::{Window, WindowError};
use rayon::prelude::*;
use std::collections::HashMap;
use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};

/// How to run a co-simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CosimOptions {
    /// A fault injected into every worker's RTL (tests of the checker).
    pub fault: Option<Fault>,
    /// Cycles a pixel may take before the RTL counts as hung.
    pub timeout_cycles: u64,
    /// Keep both sides' colours of every pixel ([`CosimReport::frames`]).
    pub keep_frames: bool,
}

impl Default for CosimOptions {
    fn default() -> CosimOptions {
        CosimOptions {
            fault: None,
            timeout_cycles: DEFAULT_TIMEOUT_CYCLES,
            keep_frames: false,
        }
    }
}

/// What a co-simulation found: the comparison, and what was run.
#[derive(Debug, Clone, PartialEq)]
pub struct CosimReport {
    pub recip: Method,
    pub sqrt: Method,
    pub window: Window,
    pub fault: Option<Fault>,
    /// The RTL (side A) against golden (side B).
    pub compare: CompareReport,
    /// Both sides' colours of the window, when [`CosimOptions::keep_frames`]
    /// asked for them.
    pub frames: Option<Frames>,
    /// What the top cost, when the run went through it ([`run_top`]).
    pub top: Option<TopReport>,
}

/// How to drive the top in [`run_top`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopOptions {
    /// Which processor: compact ones (rtl/top.v with `procs` processors),
    /// or fast ones ([`FAST_CONTEXTS`] contexts each): through rtl/top.v
    /// with `procs` of them (`FAST = 1`), or one bare (`through_top`
    /// false, `procs` 1).
    pub processor: ProcessorKind,
    /// Pixel processors (a verilated variant of rtl/top.v).
    pub procs: u32,
    /// Whether rtl/top.v is around the processors (always for compact
    /// ones).
    pub through_top: bool,
    /// Whether the processors have their exponential: false only for the
    /// bare fast processor built without it (`EXPOSURE = 0`), which draws
    /// scenes without exposure only.
    pub exp_unit: bool,
    /// The result stream's backpressure (seeded per tile).
    pub stall: Stall,
}

impl TopOptions {
    /// The compact processor's top with `procs` processors, never stalled.
    pub fn compact(procs: u32) -> TopOptions {
        TopOptions {
            processor: ProcessorKind::Compact,
            procs,
            through_top: true,
            exp_unit: true,
            stall: Stall::NONE,
        }
    }

    /// The fast processor, bare (its own streams), never stalled.
    pub fn fast() -> TopOptions {
        TopOptions {
            processor: ProcessorKind::Fast,
            procs: 1,
            through_top: false,
            exp_unit: true,
            stall: Stall::NONE,
        }
    }

    /// The top of `procs` fast processors (rtl/top.v with `FAST = 1`),
    /// never stalled.
    pub fn fast_top(procs: u32) -> TopOptions {
        TopOptions {
            processor: ProcessorKind::Fast,
            procs,
            through_top: true,
            exp_unit: true,
            stall: Stall::NONE,
        }
    }

    /// Pixel contexts in all: a compact processor has one.
    pub fn contexts(&self) -> u32 {
        match self.processor {
            ProcessorKind::Compact => self.procs,
            ProcessorKind::Fast => self.procs * FAST_CONTEXTS,
        }
    }

    /// The verilated model these options name, for `scene`'s methods,
    /// with the options' timeout and fault.
    pub fn build_for(&self, scene: &Scene, options: &CosimOptions) -> Result<Top, PpError> {
        let (recip, sqrt) = (scene.render.recip, scene.render.sqrt);
        let mut t = match (self.processor, self.through_top) {
            (ProcessorKind::Compact, _) => Top::new(self.procs, recip, sqrt),
            (ProcessorKind::Fast, false) => Top::new_fast_variant(recip, sqrt, self.exp_unit),
            (ProcessorKind::Fast, true) => Top::new_fast_procs(self.procs, recip, sqrt),
        }?;
        t.set_timeout_cycles(options.timeout_cycles);
        t.set_fault(options.fault, u32::MAX);
        Ok(t)
    }
}

/// What the top cost over a window: its tiles run back to back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopReport {
    pub processor: ProcessorKind,
    /// Processors (1: the bare fast processor).
    pub procs: u32,
    /// Whether rtl/top.v was around them.
    pub through_top: bool,
    /// Whether they had their exponential ([`TopOptions::exp_unit`]).
    pub exp_unit: bool,
    /// Pixel contexts in all (a compact processor has one).
    pub contexts: u32,
    pub tiles: u64,
    /// The tiles' costs added up: frame cycles are the sum of each tile's
    /// first coordinate in to last result out.
    pub stats: FrameStats,
    /// Fast processors: the frame cycles their rule predicts for the tiles
    /// (bare: `golden::micro::barrel::run` + [`FAST_FRAME_OVERHEAD`] each;
    /// through the top: `golden::micro::barrel::run_top`), which
    /// `stats.frame_cycles` must equal.
    pub predicted_frame_cycles: Option<u64>,
}

impl TopReport {
    /// Whether the frame took the cycles predicted, where one was.
    pub fn frame_cycles_agree(&self) -> bool {
        self.predicted_frame_cycles
            .map_or(true, |p| p == self.stats.frame_cycles)
    }

    /// The share of context cycles without a pixel.
    pub fn idle_share(&self) -> f64 {
        self.stats.idle_share(self.contexts)
    }
}

/// One pixel's colour bits: the RTL's and golden's.
type Colours = ([u32; 3], [u32; 3]);

/// The colours both sides computed for a window, as frames of the window's
/// size (pixel (0, 0) is the window's top-left corner).
#[derive(Debug, Clone, PartialEq)]
pub struct Frames {
    /// The RTL's colours.
    pub rtl: Frame,
    /// The golden micro-op model's colours.
    pub golden: Frame,
}

impl Frames {
    /// Frames from row-major colour bits of `window`, RTL and golden.
    fn from_rows(window: Window, rows: Vec<Vec<Colours>>) -> Frames {
        let pixels: Vec<_> = rows.into_iter().flatten().collect();
        let frame = |side: fn(&Colours) -> [u32; 3]| {
            let pixels = pixels
                .iter()
                .map(|p| side(p).map(|c| f64::from(f32::from_bits(c))))
                .collect();
            Frame::from_pixels(window.width, window.height, pixels)
                .expect("one colour per pixel of the window")
        };
        Frames {
            rtl: frame(|p| p.0),
            golden: frame(|p| p.1),
        }
    }
}

impl CosimReport {
    /// True when pixels ran, events were compared, and nothing diverged.
    pub fn passed(&self) -> bool {
        self.compare.passed() && self.top.map_or(true, |t| t.frame_cycles_agree())
    }
}

impl fmt::Display for CosimReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let processor = self.top.map_or(ProcessorKind::Compact, |t| t.processor);
        write!(
            f,
            "{processor} pixel processor{} (recip {}, sqrt {}), window {}",
            if self.top.is_some_and(|t| !t.exp_unit) {
                " without its exponential"
            } else {
                ""
            },
            self.recip,
            self.sqrt,
            self.window.describe()
        )?;
        if let Some(fault) = self.fault {
            write!(
                f,
                ", fault {:#010x} injected in {}",
                fault.xor,
                state_label(fault.state)
            )?;
        }
        writeln!(f, ": {} pixels", self.compare.counts.pixels)?;
        if let Some(t) = self.top.filter(|t| t.processor == ProcessorKind::Fast) {
            let rule = if t.through_top {
                "the top's rule"
            } else {
                "the barrel rule"
            };
            writeln!(
                f,
                "  {}, {} tile{}: {} frame cycles (first coordinate in to last result \
                 out; {:.2} a pixel), {}; {:.1}% of context cycles without a pixel, {} batch{}",
                if t.through_top {
                    format!(
                        "top: {} processor{} of {FAST_CONTEXTS} contexts",
                        t.procs,
                        if t.procs == 1 { "" } else { "s" }
                    )
                } else {
                    format!("{} contexts", t.contexts)
                },
                t.tiles,
                if t.tiles == 1 { "" } else { "s" },
                t.stats.frame_cycles,
                t.stats.frame_cycles as f64 / t.stats.pixels.max(1) as f64,
                match t.predicted_frame_cycles {
                    Some(p) if p == t.stats.frame_cycles => format!("as {rule} predicts"),
                    Some(p) => format!("DIVERGENT: {rule} predicts {p}"),
                    None => "no prediction (the result stream was held back)".to_string(),
                },
                100.0 * t.idle_share(),
                t.stats.batches,
                if t.stats.batches == 1 { "" } else { "es" }
            )?;
        } else if let Some(t) = &self.top {
            writeln!(
                f,
                "  top: {} processor{}, {} tile{}: {} frame cycles (first coordinate in to last \
                 result out), {:.1}% dispatcher idle (processor cycles without a pixel), {} \
                 batch{}",
                t.procs,
                if t.procs == 1 { "" } else { "s" },
                t.tiles,
                if t.tiles == 1 { "" } else { "s" },
                t.stats.frame_cycles,
                100.0 * t.idle_share(),
                t.stats.batches,
                if t.stats.batches == 1 { "" } else { "es" }
            )?;
        }
        write!(f, "{}", self.compare)?;
        if let Some(d) = &self.compare.first_divergence {
            write!(f, "\nfirst divergence: {}", d.text(&self.compare.labels))?;
        }
        Ok(())
    }
}

/// Errors of a co-simulation run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CosimError {
    #[error("window {0}")]
    Window(#[from] WindowError),
    #[error(transparent)]
    Rtl(#[from] PpError),
    #[error("pixel ({x}, {y}) lies outside the {width}x{height} image")]
    Pixel {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
    #[error("pixel ({x}, {y}) is listed twice: the fast processor's pixels must be distinct")]
    Repeated { x: u32, y: u32 },
    #[error("the {build} is not a build the harness verilates for this scene: {why}")]
    NotBuilt { build: Build, why: String },
}

/// A worker's verilated model with the scene loaded, and its event buffer.
struct Worker {
    rtl: PixelProcessor,
    events: Vec<TraceEvent>,
}

impl Worker {
    fn new(scene: &Scene, options: &CosimOptions) -> Result<Worker, PpError> {
        let mut rtl = PixelProcessor::new(scene.render.recip, scene.render.sqrt)?;
        prepare(&mut rtl, scene, options)?;
        Ok(Worker {
            rtl,
            events: Vec::new(),
        })
    }
}

/// Sets `rtl` up for a run of `scene` with `options`: timeout, fault, and
/// the scene loaded (after a reset).
fn prepare(rtl: &mut PixelProcessor, scene: &Scene, options: &CosimOptions) -> Result<(), PpError> {
    rtl.set_timeout_cycles(options.timeout_cycles);
    rtl.set_fault(options.fault);
    rtl.load_scene(scene)
}

/// Runs pixel (x, y) on both sides and returns the verdict; `events` is
/// the RTL's event buffer.
fn compare_one(
    rtl: &mut PixelProcessor,
    events: &mut Vec<TraceEvent>,
    golden: &Processor,
    x: u32,
    y: u32,
) -> Result<PixelVerdict, PpError> {
    events.clear();
    let a = rtl.run_pixel(x, y, Some(events))?;
    Ok(compare_pixel(
        x,
        y,
        Tolerance::default(),
        events,
        a,
        |sink| {
            let result = golden.render_pixel(x, y, |e, at| sink(e, Some(at)));
            PixelOutcome::from(&result)
        },
    ))
}

/// Co-simulates `window` of `scene` on the calling thread, on a model the
/// caller owns (it must have the scene's methods; the scene is loaded into
/// it): for many small runs, such as a fuzz campaign, where building a
/// model per run would cost more than the run. `each` sees every pixel's
/// verdict.
pub fn run_on(
    rtl: &mut PixelProcessor,
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    each: &mut dyn FnMut(&PixelVerdict),
) -> Result<CosimReport, CosimError> {
    window.check_inside(scene.camera.width, scene.camera.height)?;
    prepare(rtl, scene, options)?;
    let golden = Processor::new(scene);
    let mut compare = CompareReport::new(Labels::rtl_golden());
    let mut events = Vec::new();
    let mut colours = Vec::new();
    for (x, y) in window.iter() {
        let verdict = compare_one(rtl, &mut events, &golden, x, y)?;
        each(&verdict);
        compare.add(&verdict);
        if options.keep_frames {
            colours.push((verdict.a.rgb, verdict.b.rgb));
        }
    }
    Ok(report(scene, window, options, compare, vec![colours]))
}

fn report(
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    compare: CompareReport,
    colours: Vec<Vec<Colours>>,
) -> CosimReport {
    CosimReport {
        recip: scene.render.recip,
        sqrt: scene.render.sqrt,
        window,
        fault: options.fault,
        compare,
        frames: options
            .keep_frames
            .then(|| Frames::from_rows(window, colours)),
        top: None,
    }
}

/// Runs `work` on every unit in parallel on the current rayon pool, each
/// worker thread with its own worker from `make` (built lazily, dropped
/// after an error: a model that failed mid-pixel is not used again);
/// `progress` gets the pixels of each unit done. After an error, units not
/// yet started are skipped; the error returned is the first in unit order
/// among those that ran, so the outcome does not depend on the threads.
fn par_units<U, W, T>(
    units: &[U],
    make: impl Fn() -> Result<W, PpError> + Sync + Send,
    work: impl Fn(&mut W, &U) -> Result<(T, u64), PpError> + Sync + Send,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<T>, PpError>
where
    U: Sync,
    T: Send,
{
    let failed = AtomicBool::new(false);
    let done: Vec<Result<Option<T>, PpError>> = units
        .par_iter()
        .map_init(
            || None::<W>,
            |worker, unit| {
                if failed.load(Ordering::Relaxed) {
                    return Ok(None);
                }
                let w = match worker {
                    Some(w) => w,
                    None => match make() {
                        Ok(w) => worker.insert(w),
                        Err(e) => {
                            failed.store(true, Ordering::Relaxed);
                            return Err(e);
                        }
                    },
                };
                match work(w, unit) {
                    Ok((t, pixels)) => {
                        progress(pixels);
                        Ok(Some(t))
                    }
                    Err(e) => {
                        failed.store(true, Ordering::Relaxed);
                        *worker = None;
                        Err(e)
                    }
                }
            },
        )
        .collect();
    let mut out = Vec::with_capacity(done.len());
    let mut skipped = false;
    for d in done {
        match d? {
            Some(t) => out.push(t),
            None => skipped = true,
        }
    }
    // Skipped units mean an error elsewhere, returned above.
    debug_assert!(!skipped);
    Ok(out)
}

/// Cycles a frame of the fast processor takes beyond the barrel rule's
/// (`rtl/fast/fast_pp.v`: one into the coordinate queue, two of the
/// register file's read, one into the result queue).
pub const FAST_FRAME_OVERHEAD: u64 = 4;

/// Rows of the window in a tile of [`run_top`]: a tile is this many rows
/// (fewer at the bottom) of the window's full width.
pub const TILE_ROWS: u32 = 4;

/// The tiles of `window`: bands of [`TILE_ROWS`] rows, top to bottom.
pub fn tiles(window: Window) -> Vec<Window> {
    window
        .rows()
        .step_by(TILE_ROWS as usize)
        .map(|y| {
            let rows = TILE_ROWS.min(window.y + window.height - y);
            Window::new(window.x, y, window.width, rows)
        })
        .collect()
}

/// Co-simulates `window` of `scene` through the top module with
/// `top.procs` processors (the variant with the scene's methods) against
/// [`golden::micro`]: tiles in parallel on the current rayon pool, each
/// tile's coordinates streamed into the top, each pixel compared as its
/// result comes out. `progress` is called with the pixels of each tile
/// done. The comparison is [`run`]'s, pixel for pixel; a hung processor
/// (or any model error) stops the run and is returned, the first in tile
/// order among the tiles that ran.
pub fn run_top(
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    top: &TopOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CosimReport, CosimError> {
    window.check_inside(scene.camera.width, scene.camera.height)?;
    let golden = Processor::new(scene);
    let tiles = tiles(window);
    let done: Vec<TileRun> = par_units(
        &tiles,
        || top.build_for(scene, options),
        |t: &mut Top, tile: &Window| {
            let coords: Vec<(u32, u32)> = tile.iter().collect();
            let run = run_tile(t, scene, &golden, &coords, options, top, &mut |_| {})?;
            Ok((run, tile.pixels()))
        },
        progress,
    )?;
    Ok(top_report(scene, window, options, top, done))
}

/// [`run_top`] on a model the caller keeps (built by
/// [`TopOptions::build_for`]), the tiles one after another on this thread,
/// `each` called with every pixel's verdict (a fuzz campaign's workers).
pub fn run_top_on(
    t: &mut Top,
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    top: &TopOptions,
    each: &mut dyn FnMut(&PixelVerdict),
) -> Result<CosimReport, CosimError> {
    window.check_inside(scene.camera.width, scene.camera.height)?;
    let golden = Processor::new(scene);
    let done = tiles(window)
        .into_iter()
        .map(|tile| {
            let coords: Vec<(u32, u32)> = tile.iter().collect();
            run_tile(t, scene, &golden, &coords, options, top, each)
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(top_report(scene, window, options, top, done))
}

/// The seed of the stalls a tile of [`run_top`] is run with (`--stall`):
/// its first pixel's row, + 1.
pub fn backpressure_seed(coords: &[(u32, u32)]) -> u64 {
    coords.first().map_or(1, |&(_, y)| u64::from(y) + 1)
}

/// What one tile cost and found.
struct TileRun {
    compare: CompareReport,
    colours: Vec<Colours>,
    stats: FrameStats,
    /// The fast processor: the frame cycles the barrel rule predicts
    /// (none with the result stream held back).
    predicted: Option<u64>,
}

/// Streams the pixels `coords` of `scene` (a tile: distinct, not empty)
/// through `t` (reset and loaded for the tile, so that its cycles are its
/// own) and compares every pixel with golden as its result leaves. The
/// fast processor's cycles are the barrel rule's for the tile's pixels in
/// the order they are fed.
fn run_tile(
    t: &mut Top,
    scene: &Scene,
    golden: &Processor,
    coords: &[(u32, u32)],
    options: &CosimOptions,
    top: &TopOptions,
    each: &mut dyn FnMut(&PixelVerdict),
) -> Result<TileRun, PpError> {
    let fast = top.processor == ProcessorKind::Fast;
    let seed = backpressure_seed(coords);
    let start = |t: &mut Top| -> Result<(), PpError> {
        t.load_scene(scene)?;
        t.set_backpressure(seed, top.stall);
        Ok(())
    };
    // With the result stream held back, a first run of the tile finds the
    // cycles the rule needs (the model and the stalls are deterministic,
    // so the second run is the same): for the bare fast processor, those in
    // which it refuses takes (2K pixels held, from the handshakes); for a
    // top of fast processors, those with out_ready low.
    let (mut refused, mut stalled) = (Vec::new(), Vec::new());
    if fast && top.stall.stalls() {
        start(t)?;
        t.run_frame(Source::Stream(coords), &mut |_| {})?;
        refused = t.refused_takes();
        stalled = t.stalled_cycles();
    }
    start(t)?;
    let (barrel_cycles, predicted) = if fast {
        let work: Vec<PixelWork> = coords
            .iter()
            .map(|&(x, y)| PixelWork::of(&golden.render_pixel(x, y, |_, _| {})))
            .collect();
        if top.through_top {
            // Every processor's ring turns together from reset; the arbiter
            // starts at processor 0 (load_scene resets).
            let start = TopStart {
                procs: top.procs,
                contexts: FAST_CONTEXTS,
                phase: t.turn_phase(),
                group: t.arb_group(),
                last_grant: 0,
            };
            let run = barrel::run_top(start, &work, &|c| stalled.binary_search(&c).is_err());
            let cycles = run.pixels.iter().map(|p| p.run.cycles()).collect();
            (cycles, Some(run.frame_cycles))
        } else {
            let run = barrel::run_gated(FAST_CONTEXTS, &work, &|c| {
                refused.binary_search(&c).is_err()
            });
            let cycles: Vec<u64> = run.pixels.iter().map(|p| p.cycles()).collect();
            // Results held back leave when the stream takes them: the
            // frame's end is the barrel's only with the stream always ready.
            let frame = (!top.stall.stalls()).then_some(run.cycles + FAST_FRAME_OVERHEAD);
            (cycles, frame)
        }
    } else {
        (Vec::new(), None)
    };
    // Where each pixel is in the tile (its cycles' index).
    let at: HashMap<(u32, u32), usize> = coords.iter().enumerate().map(|(i, &c)| (c, i)).collect();
    let mut compare = CompareReport::new(Labels::rtl_golden().on(top.processor));
    let mut colours = Vec::new();
    let stats = t.run_frame(Source::Stream(coords), &mut |p| {
        let v = compare_pixel(
            p.x,
            p.y,
            Tolerance::default(),
            p.events,
            p.outcome,
            |sink| {
                let result = golden.render_pixel(p.x, p.y, |e, at| sink(e, Some(at)));
                let mut outcome = PixelOutcome::from(&result);
                if fast {
                    outcome.cycles = barrel_cycles[at[&(p.x, p.y)]];
                }
                outcome
            },
        );
        each(&v);
        compare.add(&v);
        if options.keep_frames {
            colours.push(((p.y, p.x), (v.a.rgb, v.b.rgb)));
        }
    })?;
    colours.sort_by_key(|&(at, _)| at);
    Ok(TileRun {
        compare,
        colours: colours.into_iter().map(|(_, c)| c).collect(),
        stats,
        predicted,
    })
}

/// The tiles' runs, in tile order, as one report.
fn top_report(
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    top: &TopOptions,
    done: Vec<TileRun>,
) -> CosimReport {
    let fast = top.processor == ProcessorKind::Fast;
    let tiles = done.len() as u64;
    let mut compare = CompareReport::new(Labels::rtl_golden().on(top.processor));
    let mut colours = Vec::new();
    let mut stats = FrameStats::default();
    let mut predicted = Some(0);
    for tile in done {
        compare.merge(tile.compare);
        colours.push(tile.colours);
        stats.add(&tile.stats);
        predicted = predicted.zip(tile.predicted).map(|(a, b)| a + b);
    }
    let mut r = report(scene, window, options, compare, colours);
    r.top = Some(TopReport {
        processor: top.processor,
        procs: top.procs,
        through_top: top.through_top,
        exp_unit: top.exp_unit,
        contexts: top.contexts(),
        tiles,
        stats,
        predicted_frame_cycles: predicted.filter(|_| fast),
    });
    r
}

/// Co-simulates `window` of `scene` (the RTL variant with the scene's
/// methods) against [`golden::micro`], rows in parallel on the current rayon
/// pool. `progress` is called with the number of pixels finished, once per
/// row. A hung RTL (or any model error) stops the run and is returned, the
/// first in row order among the rows that ran.
pub fn run(
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CosimReport, CosimError> {
    window.check_inside(scene.camera.width, scene.camera.height)?;
    let golden = Processor::new(scene);
    let rows: Vec<u32> = window.rows().collect();
    let done = par_units(
        &rows,
        || Worker::new(scene, options),
        |w: &mut Worker, &y| {
            let mut report = CompareReport::new(Labels::rtl_golden());
            let mut colours = Vec::new();
            for x in window.columns() {
                let v = compare_one(&mut w.rtl, &mut w.events, &golden, x, y)?;
                report.add(&v);
                if options.keep_frames {
                    colours.push((v.a.rgb, v.b.rgb));
                }
            }
            Ok(((report, colours), u64::from(window.width)))
        },
        progress,
    )?;
    let mut compare = CompareReport::new(Labels::rtl_golden());
    let mut colours = Vec::new();
    for (report, row_colours) in done {
        compare.merge(report);
        colours.push(row_colours);
    }
    Ok(report(scene, window, options, compare, colours))
}

/// Co-simulates a list of pixels of `scene` (any order, any subset of the
/// image; the report counts them in the order given) on `build`, which must
/// be one the harness verilates for the scene (its methods the scene's,
/// [`BUILT_STACK_DEPTH`], without the exponential only on the fast
/// processor and for a scene without exposure), chunks in parallel on the current rayon pool with the same comparison
/// as [`run`] and [`run_top`]: for checking a sample of pixels rather than
/// a window. The compact processor runs them one by one; the fast one is
/// streamed each chunk as a tile, reset before it, its cycles the barrel
/// rule's for the chunk (the fast processor's pixels must be distinct).
/// `progress` is called with the number of pixels finished, once per chunk.
pub fn run_pixels(
    scene: &Scene,
    pixels: &[(u32, u32)],
    build: Build,
    options: &CosimOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CompareReport, CosimError> {
    let not_built = |why: &str| {
        Err(CosimError::NotBuilt {
            build,
            why: why.into(),
        })
    };
    if (build.recip, build.sqrt) != (scene.render.recip, scene.render.sqrt) {
        return not_built("its methods are not the scene's");
    }
    if build.stack_depth != BUILT_STACK_DEPTH {
        return not_built("build.rs verilates STACK_DEPTH 8 only");
    }
    if !build.exposure && build.processor == ProcessorKind::Compact {
        return not_built("the compact processor is built with its exponential only");
    }
    let processor = build.processor;
    let (width, height) = (scene.camera.width, scene.camera.height);
    if let Some(&(x, y)) = pixels.iter().find(|&&(x, y)| x >= width || y >= height) {
        return Err(CosimError::Pixel {
            x,
            y,
            width,
            height,
        });
    }
    let golden = Processor::new(scene);
    let labels = Labels::rtl_golden().on(processor);
    let done = match processor {
        ProcessorKind::Compact => {
            let chunks: Vec<&[(u32, u32)]> = pixels.chunks(PIXEL_CHUNK).collect();
            par_units(
                &chunks,
                || Worker::new(scene, options),
                |w: &mut Worker, chunk| {
                    let mut report = CompareReport::new(labels.clone());
                    for &(x, y) in *chunk {
                        report.add(&compare_one(&mut w.rtl, &mut w.events, &golden, x, y)?);
                    }
                    Ok((report, chunk.len() as u64))
                },
                progress,
            )?
        }
        ProcessorKind::Fast => {
            let mut seen = std::collections::HashSet::new();
            if let Some(&(x, y)) = pixels.iter().find(|&&p| !seen.insert(p)) {
                return Err(CosimError::Repeated { x, y });
            }
            let top = TopOptions {
                exp_unit: build.exposure,
                ..TopOptions::fast()
            };
            let chunks: Vec<&[(u32, u32)]> = pixels.chunks(FAST_PIXEL_CHUNK).collect();
            par_units(
                &chunks,
                || top.build_for(scene, options),
                |t: &mut Top, chunk| {
                    let run = run_tile(t, scene, &golden, chunk, options, &top, &mut |_| {})?;
                    Ok((run.compare, chunk.len() as u64))
                },
                progress,
            )?
        }
    };
    let mut compare = CompareReport::new(labels);
    for report in done {
        compare.merge(report);
    }
    Ok(compare)
}

/// Pixels the fast processor is streamed at a time by [`run_pixels`]:
/// enough to keep its contexts busy (a reference frame's tile of 4 rows is
/// 3,200).
const FAST_PIXEL_CHUNK: usize = 1024;

/// Pixels a worker of [`run_pixels`] takes at a time.
const PIXEL_CHUNK: usize = 64;
