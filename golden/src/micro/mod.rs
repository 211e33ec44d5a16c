//! The micro-op model: the pixel processor as the RTL will be built,
//! instruction by instruction, in f32, through `golden::fp` only (thesis
//! 3.12: "one Verilog ALU instruction per line of code").
//!
//! - [`isa`]: opcodes, register addresses and FSM states, generated from
//!   `rtl/pp/isa.vh`, the single source of truth shared with the RTL; the
//!   typed [`Reg`](isa::Reg), [`State`](isa::State) and
//!   [`Lanes`](isa::Lanes) the instructions take, and the labels of all
//!   three.
//! - [`loader`]: what the scene port writes (the scene registers) and the
//!   controller's configuration.
//! - [`core`](mod@core): the core: register file, memory controller (CUR/PAR
//!   decoding through the stack pointer) and the ALU controller; one method
//!   per instruction, each emitting the trace event of its write.
//! - [`alu`]: the ALU: what each opcode computes, its internal register F,
//!   and the cycles each opcode takes.
//! - [`program`]: the controller FSM, the per-pixel program.
//! - [`stats`]: instruction and cycle counts per class.
//! - [`cover`]: the controller transitions and written value classes a
//!   run reaches, as the model predicts them (the guided fuzzer's feedback).
//! - [`barrel`]: the fast processor's cycle rule (K contexts taking turns),
//!   beside the compact processor's below.
//!
//! It computes the optics of [`crate::reference`] (which is their spec),
//! iteratively with the ray stack of thesis 3.6, with the scene's speed-ups
//! (thesis 3.10) switched as the scene says.
//!
//! # The cycle rule
//!
//! This is the contract the RTL controller is built to. A pixel takes
//!
//! ```text
//! cycles = sum over executed instructions of
//!            1                        every single-cycle instruction
//!            recip_latency(m) + 1     RECIP, RECIPY (issue with in_valid,
//!            sqrt_latency(m) + 1      SQRT           write when out_valid)
//!            max of the two + 1       ROOTS (both units at once)
//!            exp_latency() + 1        EXP (three fp_exp units at once)
//!        + 1                          PIX_DONE: raise done
//! ```
//!
//! counted from the cycle after the rising edge that takes `start` (which
//! latches px, py and clears sp: the IDLE state's next-state logic, no cycle
//! of its own) to the PIX_DONE cycle inclusive.
//!
//! and nothing else: every other cycle issues an instruction. The
//! controller's own work (loop counters, object exclusion, the stack
//! pointer, speed-up and material switches, and branches on the flags of the
//! value written in the same cycle) is next-state logic and costs no cycle.
//! A multi-cycle instruction stays in its state until out_valid. F writes
//! are not register-file writes and emit no trace event; every register-file
//! write emits exactly one, with the decoded (physical) address.

pub mod alu;
pub mod barrel;
pub mod core;
pub mod cover;
pub mod fault;
pub mod isa;
#[cfg(test)]
mod isa_parse;
pub mod loader;
pub mod program;
pub mod stats;

pub use stats::{OpClass, OpStats};

use self::core::{Core, LoadedImage};
use crate::frame::Frame;
use crate::scene::Scene;
use crate::trace::TraceEvent;
pub use fault::Fault;
use loader::Config;
use rayon::prelude::*;
use std::panic::Location;

/// Cycles of every pixel outside its instructions: PIX_DONE.
pub const FIXED_CYCLES: u64 = 1;

/// One pixel's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelResult {
    /// Linear RGB, STK0_COL when done.
    pub rgb: [f32; 3],
    /// The RTL cycles from the first instruction to PIX_DONE inclusive (see the cycle
    /// rule above): `ops.instruction_cycles() + FIXED_CYCLES`.
    pub cycles: u64,
    /// The instructions executed.
    pub ops: OpStats,
}

impl PixelResult {
    /// The result of a pixel whose run left `rgb` (STK0_COL's bits) after
    /// the instructions `ops`.
    fn of(rgb: [u32; 3], ops: OpStats) -> PixelResult {
        PixelResult {
            rgb: program::rgb_of(rgb),
            cycles: ops.instruction_cycles() + FIXED_CYCLES,
            ops,
        }
    }
}

/// A pixel processor with a scene loaded: the register image and the
/// controller's configuration, built once and shared by every pixel.
#[derive(Debug, Clone)]
pub struct Processor {
    image: LoadedImage,
    config: Config,
    width: u32,
    height: u32,
    fault: Option<Fault>,
}

impl Processor {
    pub fn new(scene: &Scene) -> Processor {
        Processor {
            image: LoadedImage::new(&loader::register_image(scene)),
            config: Config::new(scene),
            width: scene.camera.width,
            height: scene.camera.height,
            fault: None,
        }
    }

    /// The same processor with `fault` injected into every pixel (a
    /// checker's self-test; see [`Fault`]); `None` takes it out.
    pub fn with_fault(mut self, fault: Option<Fault>) -> Processor {
        self.fault = fault.filter(|f| f.xor != 0);
        self
    }

    /// Whether pixel (x, y) is in the scene's image.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        x < self.width && y < self.height
    }

    /// The controller's configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Runs pixel (px, py), calling `trace` for every register-file write
    /// with its event and the model's source line that issued it. The
    /// tracer is a type parameter, so a no-op closure costs nothing.
    ///
    /// Panics if (px, py) is outside the image.
    pub fn render_pixel<F>(&self, px: u32, py: u32, trace: F) -> PixelResult
    where
        F: FnMut(&TraceEvent, &'static Location<'static>),
    {
        let mut program = self.program(px, py, trace);
        let rgb = program.run();
        PixelResult::of(rgb, program.core.stats)
    }
}

impl Processor {
    /// [`Processor::render_pixel`], adding what the pixel reaches (its
    /// path through the controller's states and the classes of the values
    /// it writes) to `coverage`.
    ///
    /// Panics if (px, py) is outside the image.
    pub fn render_pixel_covered(
        &self,
        px: u32,
        py: u32,
        coverage: &mut cover::Coverage,
    ) -> PixelResult {
        let mut program = self.program(px, py, |e: &TraceEvent, _: &_| coverage.add_write(e));
        program.core.record_steps();
        let rgb = program.run();
        let (ops, steps) = (program.core.stats, program.core.take_steps());
        drop(program);
        coverage.add_path(&steps);
        PixelResult::of(rgb, ops)
    }

    /// What every pixel of `window` reaches.
    pub fn coverage(&self, window: crate::window::Window) -> cover::Coverage {
        let mut coverage = cover::Coverage::new();
        for (x, y) in window.iter() {
            self.render_pixel_covered(x, y, &mut coverage);
        }
        coverage
    }

    /// The colour of pixel (px, py) with its primary direction replaced by
    /// `nudge(direction)` (the perturbation study, `golden::stability`): a
    /// model-only path, untraced, not what the RTL computes.
    ///
    /// Panics if (px, py) is outside the image.
    pub fn render_pixel_nudged(
        &self,
        px: u32,
        py: u32,
        nudge: impl FnOnce(crate::scene::Vec3f) -> crate::scene::Vec3f,
    ) -> [f32; 3] {
        let mut program = self.program(px, py, |_, _| {});
        program::rgb_of(program.run_nudged(nudge))
    }

    /// The controller, ready to run pixel (px, py) on a fresh core.
    fn program<F>(&self, px: u32, py: u32, trace: F) -> program::Program<'_, F>
    where
        F: FnMut(&TraceEvent, &'static Location<'static>),
    {
        assert!(
            px < self.width && py < self.height,
            "pixel ({px}, {py}) outside {}x{}",
            self.width,
            self.height
        );
        let core = Core::loaded(
            &self.image,
            px,
            py,
            self.config.recip,
            self.config.sqrt,
            self.fault,
            trace,
        );
        program::Program::new(core, &self.config)
    }
}

/// Renders one pixel of `scene` (loading the scene first; to render many,
/// make a [`Processor`] once).
pub fn render_pixel<F>(scene: &Scene, px: u32, py: u32, trace: F) -> PixelResult
where
    F: FnMut(&TraceEvent, &'static Location<'static>),
{
    Processor::new(scene).render_pixel(px, py, trace)
}

/// Cycle and instruction statistics over a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameStats {
    pub pixels: u64,
    /// Sum of the pixels' cycles.
    pub cycles: u64,
    /// The slowest pixel's cycles, and the first such pixel (x, y) in row
    /// order.
    pub max_cycles: u64,
    pub max_pixel: (u32, u32),
    pub min_cycles: u64,
    /// Every pixel's instructions, summed.
    pub ops: OpStats,
}

impl FrameStats {
    /// Mean cycles per pixel (0 for no pixels).
    pub fn mean_cycles(&self) -> f64 {
        if self.pixels == 0 {
            0.0
        } else {
            self.cycles as f64 / self.pixels as f64
        }
    }

    fn add_pixel(&mut self, x: u32, y: u32, r: &PixelResult) {
        self.merge(&FrameStats {
            pixels: 1,
            cycles: r.cycles,
            max_cycles: r.cycles,
            max_pixel: (x, y),
            min_cycles: r.cycles,
            ops: r.ops,
        });
    }

    /// Adds `other` in; the result does not depend on the order of merges.
    pub fn merge(&mut self, other: &FrameStats) {
        if other.pixels == 0 {
            return;
        }
        if self.pixels == 0 {
            *self = *other;
            return;
        }
        let first = |a: (u32, u32), b: (u32, u32)| if (a.1, a.0) <= (b.1, b.0) { a } else { b };
        self.max_pixel = match self.max_cycles.cmp(&other.max_cycles) {
            std::cmp::Ordering::Less => other.max_pixel,
            std::cmp::Ordering::Greater => self.max_pixel,
            std::cmp::Ordering::Equal => first(self.max_pixel, other.max_pixel),
        };
        self.max_cycles = self.max_cycles.max(other.max_cycles);
        self.min_cycles = self.min_cycles.min(other.min_cycles);
        self.pixels += other.pixels;
        self.cycles += other.cycles;
        self.ops.merge(&other.ops);
    }
}

/// Renders the frame, rows in parallel on the current rayon pool, untraced.
/// Pixels are independent and the statistics add exactly, so the frame and
/// its statistics are the same whatever the number of threads. `progress`
/// is called with the number of pixels finished, once per row.
pub fn render(scene: &Scene, progress: &(dyn Fn(u64) + Sync)) -> (Frame, FrameStats) {
    let (frame, stats, _) = render_work(scene, progress);
    (frame, stats)
}

/// [`render`], with each pixel's work as the fast processor's barrel rule
/// reads it ([`barrel::PixelWork`]), in row order: `barrel::run` of them
/// gives the fast processor's cycles for the frame.
pub fn render_work(
    scene: &Scene,
    progress: &(dyn Fn(u64) + Sync),
) -> (Frame, FrameStats, Vec<barrel::PixelWork>) {
    let proc = Processor::new(scene);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let n = w as usize * h as usize;
    let mut pixels = vec![[0.0f64; 3]; n];
    let idle = barrel::PixelWork {
        instructions: 0,
        exp_at: None,
    };
    let mut work = vec![idle; n];
    let stats = pixels
        .par_chunks_mut(w as usize)
        .zip(work.par_chunks_mut(w as usize))
        .enumerate()
        .map(|(py, (row, row_work))| {
            let mut stats = FrameStats::default();
            for (px, (out, wk)) in row.iter_mut().zip(row_work.iter_mut()).enumerate() {
                let r = proc.render_pixel(px as u32, py as u32, |_, _| {});
                *out = r.rgb.map(f64::from);
                *wk = barrel::PixelWork::of(&r);
                stats.add_pixel(px as u32, py as u32, &r);
            }
            progress(u64::from(w));
            stats
        })
        .reduce(FrameStats::default, |mut a, b| {
            a.merge(&b);
            a
        });
    let frame = Frame {
        width: w,
        height: h,
        pixels,
    };
    (frame, stats, work)
}
