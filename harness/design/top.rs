//! The verilated top module (`rtl/top.v`): N pixel processors behind one
//! broadcast scene port, a coordinate stream (or the raster generator) in
//! and a tagged result stream out, verilated with every processor's trace
//! port (`PP_TRACE`) for the N and method pairs of `build.rs`
//! (`TOP_VARIANTS`: N = 1 and 4, exact methods, and a top of 2 fast
//! processors; more with `RTCOSIM_TOPS`). The bare fast processor and a
//! top of fast ones are driven the same way, their contexts in the place
//! of the processors ([`Top::new_fast`], [`Top::new_fast_procs`]).
//!
//! # The streamed driver
//!
//! The C++ side (`harness/design/cpp/top.cpp`) runs the clock loop: it offers the
//! frame's coordinates on the in stream, drives `out_ready` (always high, or
//! low in a seeded share of cycles: [`Top::set_backpressure`]), and appends
//! every result and every trace event (tagged with its processor and the
//! pixel that processor was given) to vectors Rust owns, until
//! [`RESULTS_PER_BATCH`] results or [`EVENTS_PER_BATCH`] events are
//! buffered, the frame drains, or a watchdog trips: one FFI call per batch,
//! never one per edge or pixel. Rust splits the events by processor and by
//! the pixel's number among that processor's pixels (counted by the C++
//! where the processor's `busy` rises): a processor may start its next
//! pixel while its last result waits in the out register, but its results
//! leave in the order it computed them, so its k-th result is its k-th
//! pixel, and the events' (x, y) tag must agree. Each result records how
//! many events were buffered before it left, so all of its pixel's events
//! are in by then. Each pixel is handed to the caller as its result
//! arrives, with its events numbered from 0, as
//! [`crate::design::pixel_proc::PixelProcessor::run_pixel`] gives them.
//!
//! The pixel's cycles are the top's own count (`out_cycles`: every cycle
//! with the processor's `ready` low, from the one after the start edge to
//! the done cycle), the count the bare pixel processor's driver makes. A
//! processor that spends more than the timeout on one pixel stops the run
//! with [`PpError::Hung`] naming the processor ([`ProcessorId`]), the
//! pixel and its state; a top that takes no coordinate and gives no result
//! for twice as long stops it with [`PpError::Model`].

use crate::design::bridge::ffi;
use crate::design::error::{
    check_scene, scene_port_writes, Fault, HangKind, PpError, ProcessorId, SlotLayout,
};
use crate::design::processor::Driver;
use crate::design::spec::Design;
use cxx::UniquePtr;
use golden::fp::Method;
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use golden::window::Window;
use std::collections::{HashMap, VecDeque};
use std::fmt;
use std::path::PathBuf;

/// Results buffered on the C++ side before a batch returns to Rust.
pub const RESULTS_PER_BATCH: u64 = 1024;
/// Trace events buffered on the C++ side before a batch returns to Rust.
pub const EVENTS_PER_BATCH: u64 = 1 << 16;

/// Where a frame's coordinates come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source<'a> {
    /// The coordinate stream, in this order (repeats allowed).
    Stream(&'a [(u32, u32)]),
    /// The top's raster generator, row by row over the window.
    Raster(Window),
}

/// One pixel as it left the top.
#[derive(Debug, Clone, Copy)]
pub struct TopPixel<'a> {
    pub x: u32,
    pub y: u32,
    /// The processor that computed it.
    pub processor: u32,
    /// Its colour, its own cycle count, and the number of its events.
    pub outcome: PixelOutcome,
    /// Its trace events, `seq` from 0.
    pub events: &'a [TraceEvent],
}

/// What a frame cost the top.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameStats {
    pub pixels: u64,
    /// From the cycle that took the first coordinate (or started the
    /// raster) to the one that gave the last result, both counted.
    pub frame_cycles: u64,
    /// The pixels' own cycles, summed.
    pub pixel_cycles: u64,
    pub events: u64,
    /// FFI calls of the clock loop.
    pub batches: u64,
}

impl FrameStats {
    /// Adds another frame's (a tile's) costs.
    pub fn add(&mut self, other: &FrameStats) {
        self.pixels += other.pixels;
        self.frame_cycles += other.frame_cycles;
        self.pixel_cycles += other.pixel_cycles;
        self.events += other.events;
        self.batches += other.batches;
    }

    /// The share of processor cycles (`procs` x frame cycles) in which a
    /// processor had no pixel: what the dispatcher, the result stream and
    /// the frame's start and end leave idle.
    pub fn idle_share(&self, procs: u32) -> f64 {
        let capacity = u64::from(procs) * self.frame_cycles;
        if capacity == 0 {
            return 0.0;
        }
        1.0 - self.pixel_cycles as f64 / capacity as f64
    }
}

#[derive(Debug, Clone, Copy)]
struct Loaded {
    width: u32,
    height: u32,
}

/// One verilated top with its own `VerilatedContext`. Not `Send`: a model
/// stays on the thread that built it.
///
/// ```compile_fail
/// fn send<T: Send>() {}
/// send::<rtcosim::design::top::Top>();
/// ```
pub struct Top {
    procs: u32,
    layout: SlotLayout,
    recip: Method,
    sqrt: Method,
    /// Whether the processors have their exponential (`EXPOSURE = 1`).
    exp_unit: bool,
    inner: UniquePtr<ffi::TopSim>,
    scene: Option<Loaded>,
    poisoned: bool,
    results: Vec<ffi::TopResult>,
    events: Vec<ffi::TopEvent>,
    /// Per processor: the pixels it started whose results have not come,
    /// by number, with their events.
    pending: Vec<VecDeque<(u32, Vec<TraceEvent>)>>,
    /// Per processor: the results it has given since reset.
    given: Vec<u32>,
    /// A coverage model's directory ([`crate::output::coverage`]): its counts are
    /// written there when it is dropped.
    coverage: Option<PathBuf>,
}

impl Top {
    /// Builds and resets the model of `design` (driven through streams:
    /// a top of rtl/top.v, or the fast processor alone), its coverage twin
    /// when coverage is on in this process ([`crate::design::counts::dir`])
    /// and the design is plain. Its slots are the design's contexts
    /// ([`Design::slot_layout`]). A mutant design starts with mutant 0
    /// selected: [`Top::set_mutant`].
    pub fn open(design: &Design) -> Result<Top, PpError> {
        let (design, coverage) = design.with_coverage();
        design.check_driver(Driver::Streams)?;
        let inner = ffi::new_top(&design.class()).map_err(|e| design.not_opened(e.what()))?;
        let procs = design.contexts();
        let mut top = Top {
            procs,
            layout: design.slot_layout(),
            recip: design.recip,
            sqrt: design.sqrt,
            exp_unit: design.exp_unit,
            inner,
            scene: None,
            poisoned: false,
            results: Vec::new(),
            events: Vec::new(),
            pending: vec![VecDeque::new(); procs as usize],
            given: vec![0; procs as usize],
            coverage,
        };
        top.set_timeout_cycles(design.default_timeout_cycles());
        Ok(top)
    }

    /// On a mutant model: drives `mutsel = id` from now on and at every
    /// reset (0: the design as written); [`Top::load_scene`] resets it
    /// with the mutant in place (a mutant may fail its reset).
    pub fn set_mutant(&mut self, id: u16) -> Result<(), PpError> {
        self.inner
            .pin_mut()
            .set_mutant(id)
            .map_err(|e| model_error(None, e.what()))
    }

    /// On a waveform model, once: dumps the cycles `first..=last` of the
    /// next frame (counted from 0, the cycle whose rising edge takes its
    /// first coordinate) into the FST file `path`.
    pub(crate) fn open_wave(&mut self, path: &str, first: u64, last: u64) -> Result<(), String> {
        self.inner
            .pin_mut()
            .open_wave(path, first, last)
            .map_err(|e| e.what().to_string())
    }

    /// Finishes and closes the FST file, if one is open.
    pub(crate) fn close_wave(&mut self) -> Result<(), String> {
        self.inner
            .pin_mut()
            .close_wave()
            .map_err(|e| e.what().to_string())
    }

    /// On a waveform model: pixel (x, y) of the last frame, the cycles (as
    /// [`Top::open_wave`] counts them) of its take, of its done turn, and
    /// of each of its trace events; `None` for a pixel the frame did not
    /// run.
    pub(crate) fn wave_cycles(&self, x: u32, y: u32) -> Option<(u64, u64, Vec<u64>)> {
        let mut out = Vec::new();
        self.inner.wave_cycles(x as u16, y as u16, &mut out);
        match out.as_slice() {
            [taken, done, events @ ..] => Some((*taken, *done, events.to_vec())),
            _ => None,
        }
    }

    /// The number of pixel processors.
    pub fn procs(&self) -> u32 {
        self.procs
    }

    /// Cycles a processor may spend on one pixel before the run stops as
    /// hung (at least 1); the top may go twice as long without taking a
    /// coordinate or giving a result.
    pub fn set_timeout_cycles(&mut self, cycles: u64) {
        self.inner.pin_mut().set_timeout(cycles.max(1));
    }

    /// From the next cycle on, injects `fault` (see [`Fault`]) into the
    /// processors whose bit is set in `procs_mask`; `None` switches it off.
    pub fn set_fault(&mut self, fault: Option<Fault>, procs_mask: u32) {
        let (state, xor) = fault.map_or((0, 0), |f| (f.state, f.xor));
        self.inner.pin_mut().set_fault(state, xor, procs_mask);
    }

    /// Holds `out_ready` low as `stall` says (in a share of the cycles, in
    /// runs), drawn from a generator seeded with `seed`.
    pub fn set_backpressure(&mut self, seed: u64, stall: Stall) {
        self.inner
            .pin_mut()
            .set_backpressure(seed, stall.percent.min(100), stall.burst.max(1));
    }

    /// Refuses `scene` unless the model can draw it: its float methods,
    /// and an exponential if it sets an exposure.
    fn check_scene(&self, scene: &Scene) -> Result<(), PpError> {
        check_scene(scene, self.recip, self.sqrt)?;
        match scene.render.exposure {
            Some(exposure) if !self.exp_unit => Err(PpError::NoExpUnit {
                exposure_bits: exposure.to_bits(),
            }),
            _ => Ok(()),
        }
    }

    /// Resets the top (every processor) and loads `scene` through the
    /// broadcast scene port. Refuses a scene it cannot draw (see
    /// [`Top::check_scene`]) before touching the model.
    pub fn load_scene(&mut self, scene: &Scene) -> Result<(), PpError> {
        self.check_scene(scene)?;
        self.scene = None;
        self.poisoned = true;
        self.inner
            .pin_mut()
            .reset()
            .map_err(|e| model_error(None, e))?;
        for p in &mut self.pending {
            p.clear();
        }
        self.given.fill(0);
        self.write_scene(scene)
    }

    /// Changes the scene between two frames, without a reset: every scene
    /// register and the configuration word through the scene port, which
    /// the top takes while no processor has a pixel (thesis, future work:
    /// "make the scene dynamic").
    pub fn change_scene(&mut self, scene: &Scene) -> Result<(), PpError> {
        self.check_scene(scene)?;
        if self.poisoned {
            return Err(PpError::Poisoned);
        }
        self.poisoned = true;
        self.write_scene(scene)
    }

    fn write_scene(&mut self, scene: &Scene) -> Result<(), PpError> {
        for (cfg, addr, [x, y, z]) in scene_port_writes(scene) {
            self.inner
                .pin_mut()
                .write_scene(cfg, addr, x, y, z)
                .map_err(|e| model_error(None, e))?;
        }
        self.poisoned = false;
        self.scene = Some(Loaded {
            width: scene.camera.width,
            height: scene.camera.height,
        });
        Ok(())
    }

    /// Runs a frame of the loaded scene from `source` through the top,
    /// calling `each` with every pixel as its result arrives (in the order
    /// results leave the top). Every coordinate is checked against the
    /// scene's image before the first cycle.
    pub fn run_frame(
        &mut self,
        source: Source<'_>,
        each: &mut dyn FnMut(TopPixel<'_>),
    ) -> Result<FrameStats, PpError> {
        if self.poisoned {
            return Err(PpError::Poisoned);
        }
        let loaded = self.scene.ok_or(PpError::NoScene)?;
        let outside = |(x, y): (u32, u32)| {
            (x >= loaded.width || y >= loaded.height).then_some(PpError::OutsideImage {
                x,
                y,
                width: loaded.width,
                height: loaded.height,
            })
        };
        // The pixels the frame feeds, each to come out once.
        let mut fed = Fed::new(&source);
        match source {
            Source::Stream(pixels) => {
                if let Some(e) = pixels.iter().find_map(|&p| outside(p)) {
                    return Err(e);
                }
                // Both fit 16 bits: scenes are at most 4096 wide and high.
                let coords: Vec<u32> = pixels.iter().map(|&(x, y)| x | y << 16).collect();
                self.poisoned = true;
                self.inner
                    .pin_mut()
                    .feed(&coords)
                    .map_err(|e| model_error(None, e))?;
            }
            Source::Raster(w) => {
                let last = (w.x + w.width.max(1) - 1, w.y + w.height.max(1) - 1);
                if let Some(e) = outside((w.x, w.y)).or(outside(last)) {
                    return Err(e);
                }
                self.poisoned = true;
                self.inner
                    .pin_mut()
                    .start_raster(w.x as u16, w.y as u16, last.0 as u16, last.1 as u16)
                    .map_err(|e| model_error(None, e))?;
            }
        }
        let mut stats = FrameStats::default();
        loop {
            self.results.clear();
            self.events.clear();
            let run = self
                .inner
                .pin_mut()
                .run(
                    &mut self.results,
                    &mut self.events,
                    RESULTS_PER_BATCH,
                    EVENTS_PER_BATCH,
                    u64::MAX,
                )
                .map_err(|e| model_error(None, e))?;
            stats.batches += 1;
            stats.events += self.events.len() as u64;
            self.deliver(&mut stats, &mut fed, each)?;
            match run.status {
                ffi::TopStatus::Drained => {
                    stats.frame_cycles = run.frame_cycles;
                    break;
                }
                ffi::TopStatus::Batch | ffi::TopStatus::CycleLimit => {}
                ffi::TopStatus::Watchdog => {
                    return Err(PpError::Hung {
                        x: u32::from(run.x),
                        y: u32::from(run.y),
                        processor: Some(ProcessorId {
                            index: u32::from(run.proc),
                            procs: self.procs,
                            layout: self.layout,
                        }),
                        kind: HangKind::Timeout,
                        // The C++ counts the start cycle too; a pixel's
                        // cycles begin after the start edge.
                        cycles: run.cycles.saturating_sub(1),
                        last_state: run
                            .has_last_state
                            .then_some((run.last_state, run.last_state_cycle.saturating_sub(1))),
                        state_port: run.state_port,
                    });
                }
                ffi::TopStatus::Stalled => {
                    return Err(model_error(
                        None,
                        format!(
                            "the top stalled: no coordinate in and no result out for {} cycles, \
                             {} of the frame's pixels out",
                            run.cycles, stats.pixels
                        ),
                    ))
                }
                other => {
                    return Err(model_error(
                        None,
                        format!("unknown batch status {}", other.repr),
                    ))
                }
            }
        }
        self.poisoned = false;
        Ok(stats)
    }

    /// The fast processor: the cycles of the last frame, counted from its
    /// first take, in which it held 2K pixels (taken, results not yet out:
    /// counted from the stream handshakes, not read from the RTL), so that
    /// the barrel rule refuses a take there (`golden::micro::barrel::
    /// run_gated`). Empty for the top, and without backpressure.
    pub fn refused_takes(&self) -> Vec<u64> {
        let mut out = Vec::new();
        self.inner.refused_takes(&mut out);
        out
    }

    /// The cycles of the last frame, counted from the one that took its
    /// first coordinate, in which out_ready was low (the backpressure
    /// [`Top::set_backpressure`] drew).
    pub fn stalled_cycles(&self) -> Vec<u64> {
        let mut out = Vec::new();
        self.inner.stalled_cycles(&mut out);
        out
    }

    /// Fast processors: the context whose turn the next cycle is (every
    /// processor's ring turns together), read from the model with no edge;
    /// 0 for compact processors.
    pub fn turn_phase(&mut self) -> u32 {
        self.inner.pin_mut().turn_phase()
    }

    /// A top of fast processors: processors per result group (`ARB_GROUP`
    /// of `rtl/top.v`, as this model was verilated); 1 for the others.
    pub fn arb_group(&self) -> u32 {
        self.inner.arb_group()
    }

    /// Splits this batch's events by processor and hands every result to
    /// `each` with its pixel's events.
    fn deliver(
        &mut self,
        stats: &mut FrameStats,
        fed: &mut Fed,
        each: &mut dyn FnMut(TopPixel<'_>),
    ) -> Result<(), PpError> {
        let mut consumed = 0;
        for r in &self.results {
            let upto = (r.events_before as usize).min(self.events.len());
            demux(&mut self.pending, &self.events[consumed..upto]);
            consumed = upto;
            let (x, y) = (u32::from(r.x), u32::from(r.y));
            // A result for a pixel the frame did not feed, or gave already,
            // is the RTL's error (a fault, a mutant), not the harness's.
            if !fed.take((x, y)) {
                return Err(model_error(
                    Some((x, y)),
                    format!(
                        "processor {} gave a result for pixel ({x}, {y}), which this frame did not feed or had already given",
                        r.proc
                    ),
                ));
            }
            let p = usize::from(r.proc);
            let (Some(pending), Some(given)) = (self.pending.get_mut(p), self.given.get_mut(p))
            else {
                return Err(model_error(
                    Some((x, y)),
                    format!("a result from processor {} of {}", r.proc, self.procs),
                ));
            };
            let number = *given;
            *given += 1;
            // A pixel without events has no entry.
            let events = match pending.front() {
                Some((n, _)) if *n == number => pending.pop_front().map(|(_, e)| e),
                Some((n, _)) if *n < number => {
                    return Err(model_error(
                        Some((x, y)),
                        format!(
                            "processor {} started pixel #{n} and gave no result for it",
                            r.proc
                        ),
                    ))
                }
                _ => None,
            }
            .unwrap_or_default();
            if let Some(e) = events.iter().find(|e| (e.x, e.y) != (r.x, r.y)) {
                return Err(model_error(
                    Some((x, y)),
                    format!(
                        "processor {}'s pixel #{number} has an event of pixel ({}, {})",
                        r.proc, e.x, e.y
                    ),
                ));
            }
            stats.pixels += 1;
            stats.pixel_cycles += u64::from(r.cycles);
            each(TopPixel {
                x,
                y,
                processor: u32::from(r.proc),
                outcome: PixelOutcome {
                    rgb: r.rgb,
                    cycles: u64::from(r.cycles),
                    events: events.len() as u64,
                },
                events: &events,
            });
        }
        demux(&mut self.pending, &self.events[consumed..]);
        Ok(())
    }
}

/// Appends each event to its processor's pixel, numbered on.
/// The pixels a frame feeds, each to be given as often as it was fed: a
/// window's once each, a stream's by count (a stream may repeat one).
enum Fed {
    Window { window: Window, given: Vec<bool> },
    Stream(HashMap<(u32, u32), u32>),
}

impl Fed {
    fn new(source: &Source<'_>) -> Fed {
        match source {
            Source::Stream(pixels) => {
                let mut left = HashMap::new();
                for &p in pixels.iter() {
                    *left.entry(p).or_insert(0) += 1;
                }
                Fed::Stream(left)
            }
            Source::Raster(w) => Fed::Window {
                window: *w,
                given: vec![false; w.pixels() as usize],
            },
        }
    }

    /// Whether `(x, y)` was fed and is still owed; counts it given.
    fn take(&mut self, (x, y): (u32, u32)) -> bool {
        match self {
            Fed::Window { window: w, given } => {
                let inside = x >= w.x && y >= w.y && x - w.x < w.width && y - w.y < w.height;
                let slot = inside
                    .then(|| ((y - w.y) * w.width + (x - w.x)) as usize)
                    .and_then(|i| given.get_mut(i));
                match slot {
                    Some(g) if !*g => {
                        *g = true;
                        true
                    }
                    _ => false,
                }
            }
            Fed::Stream(left) => match left.get_mut(&(x, y)) {
                Some(n) if *n > 0 => {
                    *n -= 1;
                    true
                }
                _ => false,
            },
        }
    }
}

fn demux(pending: &mut [VecDeque<(u32, Vec<TraceEvent>)>], events: &[ffi::TopEvent]) {
    for e in events {
        if let Some(q) = pending.get_mut(usize::from(e.proc)) {
            if q.back().map(|(n, _)| *n) != Some(e.pixel) {
                q.push_back((e.pixel, Vec::new()));
            }
            let Some((_, p)) = q.back_mut() else {
                continue;
            };
            p.push(TraceEvent {
                x: e.x,
                y: e.y,
                seq: p.len() as u32,
                state: e.event.state,
                dst: e.event.dst,
                lanes: e.event.lanes,
                values: e.event.values,
            });
        }
    }
}

fn model_error(pixel: Option<(u32, u32)>, message: impl ToString) -> PpError {
    PpError::Model {
        pixel,
        message: message.to_string(),
    }
}

impl Drop for Top {
    /// A coverage model writes its counts into its directory's `raw/`
    /// ([`crate::output::coverage::write_raw`]).
    fn drop(&mut self) {
        if let Some(dir) = self.coverage.take() {
            crate::design::counts::write_raw(&dir, |p| self.inner.pin_mut().write_coverage(p));
        }
    }
}

/// Backpressure on a result stream: `out_ready` low in `percent` % of the
/// cycles, drawn from a seeded generator. Burst 1 draws every cycle on its
/// own, so long runs of stalls are rare (at 99%, out_ready is high every
/// 100 cycles or so). A longer burst holds the stream back in stalls of 1
/// to `burst` cycles (uniform), the first run a stall, each followed by a
/// ready run of 1 to `burst * (100 - percent) / percent` cycles: stalls of
/// thousands of cycles let a result queue fill up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stall {
    pub percent: u32,
    pub burst: u32,
}

impl Stall {
    /// Always ready.
    pub const NONE: Stall = Stall {
        percent: 0,
        burst: 1,
    };

    /// Low in `percent` % of the cycles, each cycle drawn on its own.
    pub fn percent(percent: u32) -> Stall {
        Stall { percent, burst: 1 }
    }

    /// Whether `out_ready` is ever low.
    pub fn stalls(&self) -> bool {
        self.percent > 0
    }
}

impl fmt::Display for Stall {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "held back {}% of cycles", self.percent)?;
        if self.burst > 1 {
            write!(f, ", in stalls of 1 to {} cycles", self.burst)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_owes_each_fed_pixel_as_often_as_it_was_fed() {
        // A window: each of its pixels once; none outside it.
        let mut fed = Fed::new(&Source::Raster(Window::new(2, 3, 2, 2)));
        for p in [(2, 3), (3, 3), (2, 4), (3, 4)] {
            assert!(fed.take(p), "{p:?} was fed");
        }
        for p in [(2, 3), (4, 3), (1, 3), (2, 5), (4096, 1024)] {
            assert!(!fed.take(p), "{p:?} is not owed");
        }
        // A stream: by count, repeats included.
        let pixels = [(5, 5), (1, 0), (5, 5)];
        let mut fed = Fed::new(&Source::Stream(&pixels));
        assert!(fed.take((5, 5)) && fed.take((1, 0)) && fed.take((5, 5)));
        assert!(!fed.take((5, 5)) && !fed.take((1, 0)) && !fed.take((0, 1)));
    }
}
