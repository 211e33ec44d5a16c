//! Co-simulation of the verilated pixel processor against the golden
//! micro-op model ([`golden::micro`]), bit for bit and cycle for cycle.
//!
//! Every pixel of a window runs on both. The RTL's trace events of the pixel
//! are buffered (one pixel's worth, a few hundred), then the golden model
//! runs and each of its events is compared with the RTL's event at the same
//! sequence number as it is produced: state, destination, lane mask, and
//! every written lane at ULP distance 0 (NaN equals NaN, +0 and -0 differ).
//! The pixel's cycle count, event count and final colour are compared too.
//! Nothing bigger than a pixel is stored: a whole frame's trace is tens of
//! millions of events.
//!
//! Rows run in parallel on the current rayon pool, one [`PixelProcessor`] per
//! worker (built lazily) sharing one golden [`Processor`] (immutable). Every
//! count adds exactly and the first divergence is the first in row order,
//! so the report is the same whatever the number of threads.

use crate::pixel_proc::{state_label, PixelProcessor, PpError, DEFAULT_TIMEOUT_CYCLES};
use golden::fp::{ulp_distance, Method, UlpDistance};
use golden::micro::{isa, Processor};
use golden::scene::Scene;
use golden::trace::TraceEvent;
use rayon::prelude::*;
use std::fmt;
use std::panic::Location;
use std::sync::atomic::{AtomicBool, Ordering};

/// A rectangle of pixels: columns `x..x + width`, rows `y..y + height`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Window {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Window {
    pub const fn new(x: u32, y: u32, width: u32, height: u32) -> Window {
        Window {
            x,
            y,
            width,
            height,
        }
    }

    /// The whole image of `scene`.
    pub fn full(scene: &Scene) -> Window {
        Window::new(0, 0, scene.camera.width, scene.camera.height)
    }

    /// Pixels in the window.
    pub fn pixels(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Whether the window is non-empty and inside a `width` x `height` image.
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.width > 0
            && self.height > 0
            && u64::from(self.x) + u64::from(self.width) <= u64::from(width)
            && u64::from(self.y) + u64::from(self.height) <= u64::from(height)
    }
}

impl fmt::Display for Window {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}x{} at ({}, {})",
            self.width, self.height, self.x, self.y
        )
    }
}

/// A fault to inject (see [`PixelProcessor::set_fault`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fault {
    /// FSM state id whose register writes are hit.
    pub state: u16,
    /// XORed into lane x of those writes.
    pub xor: u32,
}

/// How to run a co-simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CosimOptions {
    /// A fault injected into every worker's RTL (tests of the checker).
    pub fault: Option<Fault>,
    /// Cycles a pixel may take before the RTL counts as hung.
    pub timeout_cycles: u64,
}

impl Default for CosimOptions {
    fn default() -> CosimOptions {
        CosimOptions {
            fault: None,
            timeout_cycles: DEFAULT_TIMEOUT_CYCLES,
        }
    }
}

/// What one side returned for a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PixelOutcome {
    /// Raw f32 bits, lanes r, g, b.
    pub rgb: [u32; 3],
    pub cycles: u64,
    pub events: u64,
}

/// What diverged first in a pixel: the first event that differs (in
/// sequence order), else a missing or extra event, else the colour, else
/// the cycle count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DivergenceKind {
    /// Event `seq` differs in state, destination, lanes or a written value.
    Event {
        rtl: TraceEvent,
        golden: TraceEvent,
        /// The golden source line that issued the golden event.
        at: &'static Location<'static>,
    },
    /// The RTL wrote fewer events: golden's event at this seq has no
    /// counterpart.
    MissingEvent {
        golden: TraceEvent,
        at: &'static Location<'static>,
    },
    /// The RTL wrote more events: this one has no golden counterpart.
    ExtraEvent { rtl: TraceEvent },
    /// Every event agreed, but not the colour.
    Rgb,
    /// Events and colour agreed, but not the cycle count.
    Cycles,
}

/// The first divergence of a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Divergence {
    pub x: u32,
    pub y: u32,
    pub kind: DivergenceKind,
    pub rtl: PixelOutcome,
    pub golden: PixelOutcome,
}

/// ULP distance of lane `i` between two events, when both wrote it.
pub fn lane_distance(rtl: &TraceEvent, golden: &TraceEvent, i: usize) -> Option<UlpDistance> {
    (rtl.lanes >> i & 1 == 1 && golden.lanes >> i & 1 == 1).then(|| {
        ulp_distance(
            f32::from_bits(rtl.values[i]),
            f32::from_bits(golden.values[i]),
            false,
        )
    })
}

/// Whether the RTL's event differs from golden's (the pixel and seq are
/// not compared: the caller pairs them).
pub fn events_differ(rtl: &TraceEvent, golden: &TraceEvent) -> bool {
    rtl.state != golden.state
        || rtl.dst != golden.dst
        || rtl.lanes != golden.lanes
        || (0..3).any(|i| lane_distance(rtl, golden, i).is_some_and(|d| d != UlpDistance::Ulps(0)))
}

impl Divergence {
    /// The sequence number of the diverging event, if an event diverged.
    pub fn seq(&self) -> Option<u32> {
        match self.kind {
            DivergenceKind::Event { golden, .. } | DivergenceKind::MissingEvent { golden, .. } => {
                Some(golden.seq)
            }
            DivergenceKind::ExtraEvent { rtl } => Some(rtl.seq),
            DivergenceKind::Rgb | DivergenceKind::Cycles => None,
        }
    }

    /// The largest ULP distance over the lanes both events wrote (for an
    /// event divergence).
    pub fn max_distance(&self) -> Option<UlpDistance> {
        match &self.kind {
            DivergenceKind::Event { rtl, golden, .. } => {
                (0..3).filter_map(|i| lane_distance(rtl, golden, i)).max()
            }
            _ => None,
        }
    }
}

fn register_label(a: u8) -> String {
    isa::register_name(a).map_or_else(|| format!("r{a}"), str::to_string)
}

fn lanes_label(mask: u8) -> String {
    (0..3)
        .map(|i| {
            if mask >> i & 1 == 1 {
                ['x', 'y', 'z'][i]
            } else {
                '_'
            }
        })
        .collect()
}

fn value_label(bits: u32) -> String {
    format!("{bits:#010x} ({:e})", f32::from_bits(bits))
}

fn rgb_label(rgb: [u32; 3]) -> String {
    format!(
        "[{}, {}, {}]",
        value_label(rgb[0]),
        value_label(rgb[1]),
        value_label(rgb[2])
    )
}

impl fmt::Display for Divergence {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (x, y) = (self.x, self.y);
        match &self.kind {
            DivergenceKind::Event { rtl, golden, at } => {
                writeln!(
                    f,
                    "pixel ({x}, {y}) event #{}: RTL state {} vs golden {}, dst {} vs {}, lanes {} vs {}",
                    golden.seq,
                    state_label(rtl.state),
                    state_label(golden.state),
                    register_label(rtl.dst),
                    register_label(golden.dst),
                    lanes_label(rtl.lanes),
                    lanes_label(golden.lanes),
                )?;
                for i in 0..3 {
                    let (r, g) = (rtl.lanes >> i & 1 == 1, golden.lanes >> i & 1 == 1);
                    if !r && !g {
                        continue;
                    }
                    let side = |wrote: bool, bits: u32| {
                        if wrote {
                            value_label(bits)
                        } else {
                            "(not written)".to_string()
                        }
                    };
                    write!(
                        f,
                        "  lane {}: RTL {}, golden {}",
                        ['x', 'y', 'z'][i],
                        side(r, rtl.values[i]),
                        side(g, golden.values[i])
                    )?;
                    match lane_distance(rtl, golden, i) {
                        Some(d) => writeln!(f, ": {d}")?,
                        None => writeln!(f)?,
                    }
                }
                write!(f, "  golden source: {}:{}", at.file(), at.line())?;
            }
            DivergenceKind::MissingEvent { golden, at } => {
                writeln!(
                    f,
                    "pixel ({x}, {y}) event #{}: the RTL wrote only {} events; golden goes on with state {}, dst {}",
                    golden.seq,
                    self.rtl.events,
                    state_label(golden.state),
                    register_label(golden.dst),
                )?;
                write!(f, "  golden source: {}:{}", at.file(), at.line())?;
            }
            DivergenceKind::ExtraEvent { rtl } => {
                write!(
                    f,
                    "pixel ({x}, {y}) event #{}: golden wrote only {} events; the RTL goes on with state {}, dst {}",
                    rtl.seq,
                    self.golden.events,
                    state_label(rtl.state),
                    register_label(rtl.dst),
                )?;
            }
            DivergenceKind::Rgb => {
                write!(
                    f,
                    "pixel ({x}, {y}): every event agrees, but the colour does not: RTL {}, golden {}",
                    rgb_label(self.rtl.rgb),
                    rgb_label(self.golden.rgb)
                )?;
            }
            DivergenceKind::Cycles => {
                write!(
                    f,
                    "pixel ({x}, {y}): every event and the colour agree, but not the cycle count"
                )?;
            }
        }
        write!(
            f,
            "\n  cycles: RTL {}, golden {}; events: RTL {}, golden {}",
            self.rtl.cycles, self.golden.cycles, self.rtl.events, self.golden.events
        )
    }
}

/// What a co-simulation found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CosimReport {
    pub recip: Method,
    pub sqrt: Method,
    pub window: Window,
    pub fault: Option<Fault>,
    /// Pixels run on both sides.
    pub pixels: u64,
    /// Event pairs compared (per pixel, the events both sides wrote).
    pub events_compared: u64,
    /// Compared pairs that differ.
    pub event_mismatches: u64,
    pub rtl_events: u64,
    pub golden_events: u64,
    /// Pixels whose RTL wrote more or fewer events than golden.
    pub event_count_mismatches: u64,
    pub rtl_cycles: u64,
    pub golden_cycles: u64,
    /// Pixels whose cycle counts differ.
    pub cycle_mismatches: u64,
    /// Pixels whose final colours differ.
    pub rgb_mismatches: u64,
    /// Pixels with any divergence (events, counts, colour, cycles).
    pub divergent_pixels: u64,
    /// The first divergent pixel in row order, and what diverged first.
    pub first_divergence: Option<Divergence>,
}

impl CosimReport {
    fn empty(recip: Method, sqrt: Method, window: Window, fault: Option<Fault>) -> CosimReport {
        CosimReport {
            recip,
            sqrt,
            window,
            fault,
            pixels: 0,
            events_compared: 0,
            event_mismatches: 0,
            rtl_events: 0,
            golden_events: 0,
            event_count_mismatches: 0,
            rtl_cycles: 0,
            golden_cycles: 0,
            cycle_mismatches: 0,
            rgb_mismatches: 0,
            divergent_pixels: 0,
            first_divergence: None,
        }
    }

    /// Adds `other` in; the result does not depend on the order of merges.
    fn merge(&mut self, other: CosimReport) {
        self.pixels += other.pixels;
        self.events_compared += other.events_compared;
        self.event_mismatches += other.event_mismatches;
        self.rtl_events += other.rtl_events;
        self.golden_events += other.golden_events;
        self.event_count_mismatches += other.event_count_mismatches;
        self.rtl_cycles += other.rtl_cycles;
        self.golden_cycles += other.golden_cycles;
        self.cycle_mismatches += other.cycle_mismatches;
        self.rgb_mismatches += other.rgb_mismatches;
        self.divergent_pixels += other.divergent_pixels;
        self.first_divergence = match (self.first_divergence, other.first_divergence) {
            (Some(a), Some(b)) => Some(if (b.y, b.x) < (a.y, a.x) { b } else { a }),
            (a, b) => a.or(b),
        };
    }

    /// True when pixels ran, events were compared, and nothing diverged.
    pub fn passed(&self) -> bool {
        self.pixels > 0 && self.events_compared > 0 && self.divergent_pixels == 0
    }
}

impl fmt::Display for CosimReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "pixel processor (recip {}, sqrt {}), window {}",
            self.recip, self.sqrt, self.window
        )?;
        if let Some(fault) = self.fault {
            write!(
                f,
                ", fault {:#010x} injected in {}",
                fault.xor,
                state_label(fault.state)
            )?;
        }
        writeln!(f, ": {} pixels", self.pixels)?;
        writeln!(
            f,
            "  events: {} compared, {} differ; RTL wrote {}, golden {} ({} pixels with other counts)",
            self.events_compared,
            self.event_mismatches,
            self.rtl_events,
            self.golden_events,
            self.event_count_mismatches
        )?;
        writeln!(
            f,
            "  cycles: RTL {}, golden {} ({} pixels differ)",
            self.rtl_cycles, self.golden_cycles, self.cycle_mismatches
        )?;
        writeln!(f, "  colour: {} pixels differ", self.rgb_mismatches)?;
        write!(f, "  divergent pixels: {}", self.divergent_pixels)?;
        if let Some(d) = &self.first_divergence {
            write!(f, "\nfirst divergence: {d}")?;
        }
        Ok(())
    }
}

/// Errors of a co-simulation run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CosimError {
    #[error("window {window} is empty or not inside the scene's {width}x{height} image")]
    Window {
        window: Window,
        width: u32,
        height: u32,
    },
    #[error(transparent)]
    Rtl(#[from] PpError),
}

/// A worker's verilated model with the scene loaded, and its event buffer.
struct Worker {
    rtl: PixelProcessor,
    events: Vec<TraceEvent>,
}

impl Worker {
    fn new(scene: &Scene, options: &CosimOptions) -> Result<Worker, PpError> {
        let mut rtl = PixelProcessor::new(scene.render.recip, scene.render.sqrt)?;
        rtl.set_timeout_cycles(options.timeout_cycles);
        if let Some(fault) = options.fault {
            rtl.set_fault(fault.state, fault.xor);
        }
        rtl.load_scene(scene)?;
        Ok(Worker {
            rtl,
            events: Vec::new(),
        })
    }
}

/// Runs pixel (x, y) on both sides and compares them; a one-pixel report.
fn compare_pixel(
    worker: &mut Worker,
    golden: &Processor,
    report: &mut CosimReport,
    x: u32,
    y: u32,
) -> Result<(), PpError> {
    worker.events.clear();
    let rtl = worker.rtl.run_pixel(x, y, Some(&mut worker.events))?;
    let rtl_events = &worker.events;
    let mut seq = 0usize;
    let mut compared = 0u64;
    let mut mismatches = 0u64;
    let mut first: Option<DivergenceKind> = None;
    let result = golden.render_pixel(x, y, |g, at| {
        match rtl_events.get(seq) {
            Some(r) => {
                compared += 1;
                if events_differ(r, g) {
                    mismatches += 1;
                    first.get_or_insert(DivergenceKind::Event {
                        rtl: *r,
                        golden: *g,
                        at,
                    });
                }
            }
            None => {
                first.get_or_insert(DivergenceKind::MissingEvent { golden: *g, at });
            }
        }
        seq += 1;
    });
    let golden_events = seq as u64;
    if first.is_none() && rtl_events.len() > seq {
        first = Some(DivergenceKind::ExtraEvent {
            rtl: rtl_events[seq],
        });
    }
    let golden = PixelOutcome {
        rgb: result.rgb.map(f32::to_bits),
        cycles: result.cycles,
        events: golden_events,
    };
    let rtl = PixelOutcome {
        rgb: rtl.rgb,
        cycles: rtl.cycles,
        events: rtl_events.len() as u64,
    };
    let rgb_differs = (0..3).any(|i| {
        ulp_distance(
            f32::from_bits(rtl.rgb[i]),
            f32::from_bits(golden.rgb[i]),
            false,
        ) != UlpDistance::Ulps(0)
    });
    let cycles_differ = rtl.cycles != golden.cycles;
    if first.is_none() && rgb_differs {
        first = Some(DivergenceKind::Rgb);
    }
    if first.is_none() && cycles_differ {
        first = Some(DivergenceKind::Cycles);
    }

    report.pixels += 1;
    report.events_compared += compared;
    report.event_mismatches += mismatches;
    report.rtl_events += rtl.events;
    report.golden_events += golden.events;
    report.event_count_mismatches += u64::from(rtl.events != golden.events);
    report.rtl_cycles += rtl.cycles;
    report.golden_cycles += golden.cycles;
    report.cycle_mismatches += u64::from(cycles_differ);
    report.rgb_mismatches += u64::from(rgb_differs);
    if let Some(kind) = first {
        report.divergent_pixels += 1;
        if report.first_divergence.is_none() {
            report.first_divergence = Some(Divergence {
                x,
                y,
                kind,
                rtl,
                golden,
            });
        }
    }
    Ok(())
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
    let (width, height) = (scene.camera.width, scene.camera.height);
    if !window.fits(width, height) {
        return Err(CosimError::Window {
            window,
            width,
            height,
        });
    }
    let golden = Processor::new(scene);
    let (recip, sqrt) = (scene.render.recip, scene.render.sqrt);
    let empty = || CosimReport::empty(recip, sqrt, window, options.fault);
    let failed = AtomicBool::new(false);
    let rows: Vec<Result<CosimReport, PpError>> = (window.y..window.y + window.height)
        .into_par_iter()
        .map_init(
            || None::<Worker>,
            |worker, y| {
                let mut report = empty();
                if failed.load(Ordering::Relaxed) {
                    return Ok(report);
                }
                let row = (|| {
                    let w = match worker {
                        Some(w) => w,
                        None => worker.insert(Worker::new(scene, options)?),
                    };
                    for x in window.x..window.x + window.width {
                        compare_pixel(w, &golden, &mut report, x, y)?;
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
                Ok(report)
            },
        )
        .collect();
    let mut total = empty();
    for row in rows {
        total.merge(row?);
    }
    Ok(total)
}
