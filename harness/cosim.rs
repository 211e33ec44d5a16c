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

use crate::compare::{compare_pixel, CompareReport, Labels, PixelVerdict, Tolerance};
use crate::pixel_proc::{Fault, PixelProcessor, PpError, DEFAULT_TIMEOUT_CYCLES};
use golden::fp::Method;
use golden::frame::Frame;
use golden::micro::isa::state_label;
use golden::micro::Processor;
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use golden::window::{Window, WindowError};
use rayon::prelude::*;
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
        self.compare.passed()
    }
}

impl fmt::Display for CosimReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "pixel processor (recip {}, sqrt {}), window {}",
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
    }
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
    let empty = || CompareReport::new(Labels::rtl_golden());
    let failed = AtomicBool::new(false);
    type Row = (CompareReport, Vec<Colours>);
    let rows: Vec<Result<Row, PpError>> = window
        .rows()
        .into_par_iter()
        .map_init(
            || None::<Worker>,
            |worker, y| {
                let mut report = empty();
                let mut colours = Vec::new();
                if failed.load(Ordering::Relaxed) {
                    return Ok((report, colours));
                }
                let row = (|| {
                    let w = match worker {
                        Some(w) => w,
                        None => worker.insert(Worker::new(scene, options)?),
                    };
                    for x in window.columns() {
                        let v = compare_one(&mut w.rtl, &mut w.events, &golden, x, y)?;
                        report.add(&v);
                        if options.keep_frames {
                            colours.push((v.a.rgb, v.b.rgb));
                        }
                    }
                    Ok(())
                })();
                if let Err(e) = row {
                    failed.store(true, Ordering::Relaxed);
                    // A model that failed mid-pixel is not used again.
                    *worker = None;
                    return Err(e);
                }
                progress(u64::from(window.width));
                Ok((report, colours))
            },
        )
        .collect();
    let mut compare = empty();
    let mut colours = Vec::new();
    for row in rows {
        let (report, row_colours) = row?;
        compare.merge(report);
        colours.push(row_colours);
    }
    Ok(report(scene, window, options, compare, colours))
}

/// Co-simulates a list of pixels of `scene` (any order, any subset of the
/// image; the report counts them in the order given), chunks in parallel on
/// the current rayon pool with the same workers and comparison as [`run`]:
/// for checking a sample of pixels rather than a window. `progress` is
/// called with the number of pixels finished, once per chunk.
pub fn run_pixels(
    scene: &Scene,
    pixels: &[(u32, u32)],
    options: &CosimOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CompareReport, CosimError> {
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
    let empty = || CompareReport::new(Labels::rtl_golden());
    let chunks: Vec<Result<CompareReport, PpError>> = pixels
        .par_chunks(PIXEL_CHUNK)
        .map_init(
            || None::<Worker>,
            |worker, chunk| {
                let mut report = empty();
                let w = match worker {
                    Some(w) => w,
                    None => worker.insert(Worker::new(scene, options)?),
                };
                for &(x, y) in chunk {
                    match compare_one(&mut w.rtl, &mut w.events, &golden, x, y) {
                        Ok(v) => report.add(&v),
                        Err(e) => {
                            // A model that failed mid-pixel is not used again.
                            *worker = None;
                            return Err(e);
                        }
                    }
                }
                progress(chunk.len() as u64);
                Ok(report)
            },
        )
        .collect();
    let mut compare = empty();
    for chunk in chunks {
        compare.merge(chunk?);
    }
    Ok(compare)
}

/// Pixels a worker of [`run_pixels`] takes at a time.
const PIXEL_CHUNK: usize = 64;
