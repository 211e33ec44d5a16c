//! The live co-simulation: a design under test against the golden micro-op
//! model ([`golden::micro`]), bit for bit and cycle for cycle.
//!
//! Every pixel of a window runs on both. The window is cut into tiles of
//! [`TILE_ROWS`] rows (whatever the thread count); each tile runs on one
//! worker's [`Dut`] (built lazily per rayon worker, reset and loaded for
//! every tile, so a tile's cycles do not depend on which worker ran what
//! before), and each pixel is compared with golden as its result leaves:
//! the RTL's trace events of the pixel are buffered (one pixel's worth),
//! then the golden model runs and [`compare`](crate::check::compare) pairs
//! each of its events with the RTL's at the same sequence number as it is
//! produced. Nothing bigger than a tile is stored. The per-tile reports
//! merge exactly (see [`CompareReport::merge`]), so the report is the same
//! whatever the number of threads.
//!
//! The design's cycle rule ([`CycleRule`]) says what golden predicts: each
//! pixel's own count (golden::micro), or, for a barrel of contexts, each
//! pixel's and the tile's cycles from `golden::micro::barrel` for the
//! pixels in the order they are fed.

use crate::check::compare::{compare_pixel, CompareReport, Labels, PixelVerdict, Tolerance};
use crate::design::processor::{CycleRule, Driver};
use crate::design::top::{FrameStats, Stall};
use crate::design::{Design, Dut, Fault, PpError};
use golden::fp::Method;
use golden::frame::Frame;
use golden::micro::barrel::{self, PixelWork, TopStart};
use golden::micro::isa::state_label;
use golden::micro::Processor;
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
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
    /// Cycles a pixel may take before the RTL counts as hung; `None`: the
    /// design's [`Design::default_timeout_cycles`].
    pub timeout_cycles: Option<u64>,
    /// Keep both sides' colours of every pixel ([`CosimReport::frames`]).
    pub keep_frames: bool,
    /// The result stream's backpressure, seeded per tile (a design
    /// without a result stream ignores it).
    pub stall: Stall,
}

impl CosimOptions {
    /// The cycles a pixel of `design` may take: `timeout_cycles`, or the
    /// design's default.
    pub fn timeout_for(&self, design: &Design) -> u64 {
        self.timeout_cycles
            .unwrap_or_else(|| design.default_timeout_cycles())
    }
}

impl Default for CosimOptions {
    fn default() -> CosimOptions {
        CosimOptions {
            fault: None,
            timeout_cycles: None,
            keep_frames: false,
            stall: Stall::NONE,
        }
    }
}

/// What a co-simulation found: the comparison, and what was run.
#[derive(Debug, Clone, PartialEq)]
pub struct CosimReport {
    /// The design under test.
    pub design: Design,
    pub recip: Method,
    pub sqrt: Method,
    pub window: Window,
    pub fault: Option<Fault>,
    /// The RTL (side A) against golden (side B).
    pub compare: CompareReport,
    /// Both sides' colours of the window, when [`CosimOptions::keep_frames`]
    /// asked for them.
    pub frames: Option<Frames>,
    /// What the streams cost, for a design driven through them.
    pub top: Option<TopReport>,
    /// The tiles' costs added up: its frame cycles are the clock cycles the
    /// run simulated (one pixel at a time: the pixels' cycles back to
    /// back).
    pub stats: FrameStats,
}

/// What the top cost over a window: its tiles run back to back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopReport {
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
        let d = &self.design;
        write!(
            f,
            "{} pixel processor{} (recip {}, sqrt {}), window {}",
            d.processor,
            if !d.exp_unit {
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
        let barrel = matches!(d.row().cycle_rule, CycleRule::Barrel { .. });
        if let Some(t) = self.top.filter(|_| barrel) {
            let rule = if d.procs.is_some() {
                "the top's rule"
            } else {
                "the barrel rule"
            };
            writeln!(
                f,
                "  {}, {} tile{}: {} frame cycles (first coordinate in to last result \
                 out; {:.2} a pixel), {}; {:.1}% of context cycles without a pixel, {} batch{}",
                if let Some(n) = d.procs {
                    format!(
                        "top: {n} processor{} of {} contexts",
                        if n == 1 { "" } else { "s" },
                        d.row().contexts
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
                d.procs.unwrap_or(1),
                if d.procs == Some(1) { "" } else { "s" },
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
    #[error("pixel ({x}, {y}) is listed twice: a tile's pixels must be distinct")]
    Repeated { x: u32, y: u32 },
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

/// Rows of the window in a tile: a tile is this many rows (fewer at the
/// bottom) of the window's full width.
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

/// Builds `design`'s model with `options`' timeout and fault.
pub fn open(design: &Design, options: &CosimOptions) -> Result<Dut, PpError> {
    let mut dut = design.open()?;
    dut.set_timeout_cycles(options.timeout_for(design));
    dut.set_fault(options.fault);
    Ok(dut)
}

/// Whether a tile of `dut` starts from reset with the scene loaded again:
/// a streamed tile does, so that its frame cycles are its own; one pixel
/// at a time, a pixel's cycles are its own whatever ran before, and the
/// scene is loaded once a run ([`load_once`]).
fn reloads_per_tile(dut: &Dut) -> bool {
    dut.design().driver() == Driver::Streams
}

/// Loads `scene` into `dut` at the start of a run, where tiles do not.
fn load_once(dut: &mut Dut, scene: &Scene) -> Result<(), PpError> {
    if reloads_per_tile(dut) {
        Ok(())
    } else {
        dut.load_scene(scene)
    }
}

/// [`open`], and [`load_once`]: a worker's model for a run.
fn open_for(design: &Design, scene: &Scene, options: &CosimOptions) -> Result<Dut, PpError> {
    let mut dut = open(design, options)?;
    load_once(&mut dut, scene)?;
    Ok(dut)
}

/// Co-simulates `window` of `scene` on `design` (which must have the
/// scene's methods) against [`golden::micro`]: tiles in parallel on the
/// current rayon pool, each pixel compared as its result comes out.
/// `progress` is called with the pixels of each tile done. A hung
/// processor (or any model error) stops the run and is returned, the first
/// in tile order among the tiles that ran.
pub fn run(
    design: &Design,
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CosimReport, CosimError> {
    window.check_inside(scene.camera.width, scene.camera.height)?;
    design.check()?;
    let golden = Processor::new(scene);
    let tiles = tiles(window);
    let done: Vec<TileRun> = par_units(
        &tiles,
        || open_for(design, scene, options),
        |dut: &mut Dut, tile: &Window| {
            let coords: Vec<(u32, u32)> = tile.iter().collect();
            let run = run_tile(dut, scene, &golden, &coords, options, &mut |_| {})?;
            Ok((run, tile.pixels()))
        },
        progress,
    )?;
    Ok(report(design, scene, window, options, done))
}

/// [`run`] on a model the caller keeps (built by [`open`]), the tiles one
/// after another on this thread, `each` called with every pixel's verdict:
/// for many small runs, such as a fuzz campaign's, where building a model
/// per run would cost more than the run.
pub fn run_on(
    dut: &mut Dut,
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    each: &mut dyn FnMut(&PixelVerdict),
) -> Result<CosimReport, CosimError> {
    window.check_inside(scene.camera.width, scene.camera.height)?;
    dut.set_timeout_cycles(options.timeout_for(&dut.design()));
    dut.set_fault(options.fault);
    load_once(dut, scene)?;
    let golden = Processor::new(scene);
    let done = tiles(window)
        .into_iter()
        .map(|tile| {
            let coords: Vec<(u32, u32)> = tile.iter().collect();
            run_tile(dut, scene, &golden, &coords, options, each)
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(report(&dut.design(), scene, window, options, done))
}

/// The seed of the stalls a tile is run with (`--stall`): its first
/// pixel's row, + 1.
pub fn backpressure_seed(coords: &[(u32, u32)]) -> u64 {
    coords.first().map_or(1, |&(_, y)| u64::from(y) + 1)
}

/// What one tile cost and found.
struct TileRun {
    compare: CompareReport,
    colours: Vec<Colours>,
    stats: FrameStats,
    /// A barrel's frame cycles as its rule predicts (none with the result
    /// stream held back, or for a design without the rule).
    predicted: Option<u64>,
}

/// Streams the pixels `coords` of `scene` (a tile: distinct, not empty)
/// through `dut` (reset and loaded for the tile, so that its cycles are its
/// own) and compares every pixel with golden as its result leaves, its
/// cycles those of the design's cycle rule.
fn run_tile(
    dut: &mut Dut,
    scene: &Scene,
    golden: &Processor,
    coords: &[(u32, u32)],
    options: &CosimOptions,
    each: &mut dyn FnMut(&PixelVerdict),
) -> Result<TileRun, PpError> {
    let design = dut.design();
    let seed = backpressure_seed(coords);
    let start = |dut: &mut Dut| -> Result<(), PpError> {
        if reloads_per_tile(dut) {
            dut.load_scene(scene)?;
            dut.set_stall(seed, options.stall);
        }
        Ok(())
    };
    let (barrel_cycles, predicted) = match design.row().cycle_rule {
        CycleRule::Micro => {
            start(dut)?;
            (Vec::new(), None)
        }
        CycleRule::Barrel { contexts, overhead } => predict_barrel(
            dut,
            golden,
            coords,
            options.stall,
            contexts,
            overhead,
            &start,
        )?,
    };
    // Where each pixel is in the tile (its cycles' index).
    let at: HashMap<(u32, u32), usize> = coords.iter().enumerate().map(|(i, &c)| (c, i)).collect();
    let mut compare = CompareReport::new(Labels::rtl_golden().on(design.processor));
    let mut colours = Vec::new();
    let stats = dut.run(coords, &mut |p| {
        let v = compare_pixel(
            p.x,
            p.y,
            Tolerance::default(),
            p.events,
            p.outcome,
            |sink| {
                let result = golden.render_pixel(p.x, p.y, |e, at| sink(e, Some(at)));
                let mut outcome = PixelOutcome::from(&result);
                if let Some(&cycles) = barrel_cycles.get(at[&(p.x, p.y)]) {
                    outcome.cycles = cycles;
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

/// The barrel rule's cycles for each pixel of a tile, and the tile's frame
/// cycles where the rule predicts them; leaves `dut` started for the run.
/// With the result stream held back, a first run of the tile finds the
/// cycles the rule needs (the model and the stalls are deterministic, so
/// the second run is the same): for a processor alone, those in which it
/// refuses takes (2K pixels held, from the handshakes); for a top, those
/// with out_ready low.
#[allow(clippy::too_many_arguments)]
fn predict_barrel(
    dut: &mut Dut,
    golden: &Processor,
    coords: &[(u32, u32)],
    stall: Stall,
    contexts: u32,
    overhead: u64,
    start: &dyn Fn(&mut Dut) -> Result<(), PpError>,
) -> Result<(Vec<u64>, Option<u64>), PpError> {
    let design = dut.design();
    let (mut refused, mut stalled) = (Vec::new(), Vec::new());
    if stall.stalls() {
        start(dut)?;
        dut.run(coords, &mut |_| {})?;
        let t = dut.streams().ok_or_else(|| not_streamed(&design))?;
        refused = t.refused_takes();
        stalled = t.stalled_cycles();
    }
    start(dut)?;
    let work: Vec<PixelWork> = coords
        .iter()
        .map(|&(x, y)| PixelWork::of(&golden.render_pixel(x, y, |_, _| {})))
        .collect();
    let t = dut.streams().ok_or_else(|| not_streamed(&design))?;
    Ok(match design.procs {
        Some(procs) => {
            // Every processor's ring turns together from reset; the arbiter
            // starts at processor 0 (load_scene resets).
            let start = TopStart {
                procs,
                contexts,
                phase: t.turn_phase(),
                group: t.arb_group(),
                last_grant: 0,
            };
            let run = barrel::run_top(start, &work, &|c| stalled.binary_search(&c).is_err());
            let cycles = run.pixels.iter().map(|p| p.run.cycles()).collect();
            (cycles, Some(run.frame_cycles))
        }
        None => {
            let run = barrel::run_gated(contexts, &work, &|c| refused.binary_search(&c).is_err());
            let cycles: Vec<u64> = run.pixels.iter().map(|p| p.cycles()).collect();
            // Results held back leave when the stream takes them: the
            // frame's end is the barrel's only with the stream always ready.
            (cycles, (!stall.stalls()).then_some(run.cycles + overhead))
        }
    })
}

/// A barrel without streams: no row says so today.
fn not_streamed(design: &Design) -> PpError {
    PpError::NotBuilt {
        design: design.to_string(),
        why: "the barrel rule needs a design driven through its streams".into(),
    }
}

/// The tiles' runs, in tile order, as one report.
fn report(
    design: &Design,
    scene: &Scene,
    window: Window,
    options: &CosimOptions,
    done: Vec<TileRun>,
) -> CosimReport {
    let tiles = done.len() as u64;
    let mut compare = CompareReport::new(Labels::rtl_golden().on(design.processor));
    let mut colours = Vec::new();
    let mut stats = FrameStats::default();
    let mut predicted = Some(0);
    for tile in done {
        compare.merge(tile.compare);
        colours.push(tile.colours);
        stats.add(&tile.stats);
        predicted = predicted.zip(tile.predicted).map(|(a, b)| a + b);
    }
    let barrel = matches!(design.row().cycle_rule, CycleRule::Barrel { .. });
    CosimReport {
        design: *design,
        recip: scene.render.recip,
        sqrt: scene.render.sqrt,
        window,
        fault: options.fault,
        compare,
        frames: options
            .keep_frames
            .then(|| Frames::from_rows(window, colours)),
        top: design.has_result_stream().then_some(TopReport {
            contexts: design.contexts(),
            tiles,
            stats,
            predicted_frame_cycles: predicted.filter(|_| barrel),
        }),
        stats,
    }
}

/// Co-simulates a list of pixels of `scene` (any order, any subset of the
/// image; distinct; the report counts them in the order given) on `design`
/// (which must have the scene's methods), chunks in parallel on the
/// current rayon pool with the same comparison as [`run`]: for checking a
/// sample of pixels rather than a window. Each chunk runs as a tile.
/// `progress` is called with the number of pixels finished, once per chunk.
pub fn run_pixels(
    design: &Design,
    scene: &Scene,
    pixels: &[(u32, u32)],
    options: &CosimOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CompareReport, CosimError> {
    design.check()?;
    let (width, height) = (scene.camera.width, scene.camera.height);
    if let Some(&(x, y)) = pixels.iter().find(|&&(x, y)| x >= width || y >= height) {
        return Err(CosimError::Pixel {
            x,
            y,
            width,
            height,
        });
    }
    let mut seen = std::collections::HashSet::new();
    if let Some(&(x, y)) = pixels.iter().find(|&&p| !seen.insert(p)) {
        return Err(CosimError::Repeated { x, y });
    }
    let golden = Processor::new(scene);
    let chunks: Vec<&[(u32, u32)]> = pixels.chunks(PIXEL_CHUNK).collect();
    let done = par_units(
        &chunks,
        || open_for(design, scene, options),
        |dut: &mut Dut, chunk| {
            let run = run_tile(dut, scene, &golden, chunk, options, &mut |_| {})?;
            Ok((run.compare, chunk.len() as u64))
        },
        progress,
    )?;
    let mut compare = CompareReport::new(Labels::rtl_golden().on(design.processor));
    for report in done {
        compare.merge(report);
    }
    Ok(compare)
}

/// Pixels [`run_pixels`] runs as one tile: enough to keep a barrel's
/// contexts busy (a reference frame's tile of 4 rows is 3,200).
const PIXEL_CHUNK: usize = 1024;
