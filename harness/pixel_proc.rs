//! The verilated pixel processor (`rtl/pp/pixel_processor.v`), one model per
//! (recip, sqrt) method pair, verilated with its trace and fault ports
//! (`PP_TRACE`).
//!
//! The trace port (`trace_valid`, `trace_state`, `trace_dst`, `trace_lanes`,
//! `trace_value`) shows every register-file write; the fault port
//! (`fault_state`, `fault_xor`) flips bits of chosen writes ([`Fault`]).
//!
//! # The cycle contract
//!
//! After reset (rst_n low for two rising edges) `ready` is high. A scene is
//! loaded by writing every `(addr, bits)` of
//! [`golden::micro::loader::scene_writes`] with `scene_cfg = 0`, then
//! [`Config::word`](golden::micro::loader::Config::word) with `scene_cfg = 1`,
//! each at a rising edge with `scene_we` high while ready. A pixel starts at
//! the rising edge where `start && ready`; from there, every cycle with
//! `ready` low, up to and including the one with `done` high, is one of the
//! pixel's cycles, which must equal golden's
//! [`PixelResult::cycles`](golden::micro::PixelResult::cycles). Outputs
//! (`done`, `rgb`, the trace port) are sampled with clk low, before each
//! rising edge: one trace event per `trace_valid` cycle, in order.
//!
//! The C++ driver (`harness/cpp/pixel_proc.cpp`) runs a whole pixel per FFI
//! call. A pixel that does not finish (no `done` within the timeout, or
//! `ready` high again without `done`) comes back as a status rather than a
//! C++ exception, so that [`PpError::Hung`] can name the pixel, the cycles
//! and the last state with golden's state table; fatal errors inside the
//! model (`$stop`, `$fatal`) and port-protocol violations are exceptions
//! ([`PpError::Model`]).

use crate::bridge::ffi;
use cxx::UniquePtr;
use golden::fp::Method;
use golden::micro::isa::state_label;
use golden::micro::loader::{self, Config};
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use std::path::PathBuf;

pub use golden::micro::fault::{parse_number, Fault};

/// Why the pixel processor did not finish a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HangKind {
    /// No `done` within the timeout.
    Timeout,
    /// `ready` rose (the controller went back to IDLE) without `done`.
    IdleWithoutDone,
}

/// Errors from the verilated pixel processor.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PpError {
    /// The model could not be built (e.g. that method pair was not verilated).
    #[error("cannot build the verilated pixel processor (recip {recip}, sqrt {sqrt}): {message}")]
    Build {
        recip: Method,
        sqrt: Method,
        message: String,
    },
    /// The scene was made for other float methods than the model's.
    #[error(
        "the scene uses recip {scene_recip} and sqrt {scene_sqrt}, but this pixel processor \
         was verilated with recip {recip} and sqrt {sqrt}"
    )]
    MethodMismatch {
        scene_recip: Method,
        scene_sqrt: Method,
        recip: Method,
        sqrt: Method,
    },
    /// A scene with exposure for a processor built without its exponential.
    #[error(
        "the scene sets an exposure (render.exposure = {}), but this fast processor was built \
         without its exponential (EXPOSURE = 0): it draws scenes without exposure only",
        f32::from_bits(*exposure_bits)
    )]
    NoExpUnit {
        /// The scene's exposure, as bits (the error is `Eq`).
        exposure_bits: u32,
    },
    /// A pixel before any scene was loaded.
    #[error("no scene is loaded into the pixel processor")]
    NoScene,
    /// A pixel outside the loaded scene's image.
    #[error("pixel ({x}, {y}) is outside the loaded scene's {width}x{height} image")]
    OutsideImage {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
    /// The RTL did not finish a pixel.
    #[error(
        "hung RTL at pixel ({x}, {y}){}: {} after {cycles} cycles; last state seen: {}; \
         trace_state in the last cycle: {}",
        match processor {
            Some(p) => format!(" on {p}"),
            None => String::new(),
        },
        match kind {
            HangKind::Timeout => "no done",
            HangKind::IdleWithoutDone => "the controller went back to IDLE without done",
        },
        match last_state {
            Some((s, at)) => format!("{} (an event in cycle {at})", state_label(*s)),
            None => "none (no trace event)".to_string(),
        },
        state_label(*state_port)
    )]
    Hung {
        x: u32,
        y: u32,
        /// The processor of the top that hung (`None`: the bare pixel
        /// processor).
        processor: Option<ProcessorId>,
        kind: HangKind,
        /// Cycles simulated after the start edge.
        cycles: u64,
        /// The state of the last trace event and the cycle it came in.
        last_state: Option<(u16, u64)>,
        /// `trace_state` in the last cycle simulated.
        state_port: u16,
    },
    /// The model failed: a fatal error inside it, or a port protocol
    /// violation (not ready when it must be).
    #[error("verilated pixel processor failed{}: {message}", match pixel {
        Some((x, y)) => format!(" at pixel ({x}, {y})"),
        None => String::new(),
    })]
    Model {
        pixel: Option<(u32, u32)>,
        message: String,
    },
    /// An earlier error left the model mid-pixel.
    #[error(
        "an earlier error left the pixel processor in an unknown state; reset it and load the scene again"
    )]
    Poisoned,
}

/// Where in the top a pixel ran: slot `index` of `procs`. In a top of
/// compact processors a slot is a processor, the instance
/// `top.g_pp[index].g_compact.u_pp` of rtl/top.v; for the fast processor
/// driven alone a slot is one of its contexts; in a top of fast processors
/// slot `index` is context `index mod 32` of processor `index / 32`,
/// `top.g_pp[index / 32].g_fast.u_pp`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ProcessorId {
    pub index: u32,
    pub procs: u32,
    pub layout: SlotLayout,
}

/// What the slots of a top are (see [`ProcessorId`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SlotLayout {
    /// Compact processors, one a slot.
    #[default]
    Compact,
    /// The contexts of one fast processor.
    FastContexts,
    /// The contexts of several fast processors, processor by processor.
    FastProcessors,
}

impl std::fmt::Display for ProcessorId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (i, n) = (self.index, self.procs);
        match self.layout {
            SlotLayout::Compact => write!(f, "processor {i} of {n} (top.g_pp[{i}].g_compact.u_pp)"),
            SlotLayout::FastContexts => write!(f, "context {i} of {n} of the fast processor"),
            SlotLayout::FastProcessors => {
                let k = crate::top::FAST_CONTEXTS;
                write!(
                    f,
                    "processor {} of {}, context {} (top.g_pp[{}].g_fast.u_pp)",
                    i / k,
                    n / k,
                    i % k,
                    i / k
                )
            }
        }
    }
}

/// Refuses `scene` unless it uses the float methods a model was verilated
/// with.
pub(crate) fn check_methods(scene: &Scene, recip: Method, sqrt: Method) -> Result<(), PpError> {
    let r = &scene.render;
    if (r.recip, r.sqrt) != (recip, sqrt) {
        return Err(PpError::MethodMismatch {
            scene_recip: r.recip,
            scene_sqrt: r.sqrt,
            recip,
            sqrt,
        });
    }
    Ok(())
}

/// The scene-port writes that load `scene`, in order: `(cfg, addr, lanes)`
/// for every scene register ([`loader::scene_writes`], `cfg` false), then
/// the configuration word (`cfg` true). The pixel processor and the top
/// load a scene the same way.
pub fn scene_port_writes(scene: &Scene) -> Vec<(bool, u8, [u32; 3])> {
    let mut writes: Vec<_> = loader::scene_writes(scene)
        .into_iter()
        .map(|(addr, lanes)| (false, addr, lanes))
        .collect();
    writes.push((true, 0, Config::new(scene).word()));
    writes
}

/// Cycles a pixel may take before it counts as hung. The slowest pixel of
/// any builtin scene takes well under 10,000.
pub const DEFAULT_TIMEOUT_CYCLES: u64 = 100_000;

#[derive(Debug, Clone, Copy)]
struct Loaded {
    width: u32,
    height: u32,
}

/// One verilated pixel processor with its own `VerilatedContext`. Not
/// `Send`: a model stays on the thread that built it.
///
/// ```compile_fail
/// fn send<T: Send>() {}
/// send::<rtcosim::pixel_proc::PixelProcessor>();
/// ```
pub struct PixelProcessor {
    recip: Method,
    sqrt: Method,
    inner: UniquePtr<ffi::PixelProc>,
    scene: Option<Loaded>,
    fault: Option<Fault>,
    timeout_cycles: u64,
    poisoned: bool,
    scratch: Vec<ffi::PpEvent>,
    /// A coverage model's directory ([`crate::coverage`]): its counts are
    /// written there when it is dropped.
    coverage: Option<PathBuf>,
}

impl PixelProcessor {
    /// Builds and resets the variant verilated with `RECIP_METHOD = recip`
    /// and `SQRT_METHOD = sqrt`: its coverage model when coverage is on in
    /// this process ([`crate::coverage::dir`]).
    pub fn new(recip: Method, sqrt: Method) -> Result<PixelProcessor, PpError> {
        match crate::coverage::dir() {
            None => Self::build(recip, sqrt, ffi::new_pixel_proc),
            Some(dir) => {
                let mut pp = Self::build(recip, sqrt, ffi::new_pixel_proc_cov)?;
                pp.coverage = Some(dir);
                Ok(pp)
            }
        }
    }

    /// The mutant netlist (cargo feature `mutation`; exact methods) with
    /// mutant `id` selected (0: the design as written), for
    /// [`crate::mutation`]. Reset it next: a mutant may fail its reset.
    pub fn new_mutant(id: u16) -> Result<PixelProcessor, PpError> {
        let mut pp = Self::build(Method::Exact, Method::Exact, |_, _| {
            ffi::new_pixel_proc_mut()
        })?;
        pp.inner
            .pin_mut()
            .set_mutant(id)
            .map_err(|e| PpError::Model {
                pixel: None,
                message: e.what().to_string(),
            })?;
        Ok(pp)
    }

    /// Yosys' generic synthesis of the processor (`rtl/synth/synth.sh
    /// generic`: gates and flip-flops, exact methods; cargo feature
    /// `synth-netlist`), built and reset: the netlist that would be built,
    /// driven through the same ports as the RTL.
    pub fn new_synth() -> Result<PixelProcessor, PpError> {
        Self::build(Method::Exact, Method::Exact, |_, _| {
            ffi::new_pixel_proc_synth()
        })
    }

    /// The same variant verilated with `--trace-fst`, for [`crate::wave`].
    pub(crate) fn new_wave(recip: Method, sqrt: Method) -> Result<PixelProcessor, PpError> {
        Self::build(recip, sqrt, ffi::new_pixel_proc_wave)
    }

    /// The model, for [`crate::wave`]'s calls to its waveform port.
    pub(crate) fn model(&mut self) -> std::pin::Pin<&mut ffi::PixelProc> {
        self.inner.pin_mut()
    }

    fn build(
        recip: Method,
        sqrt: Method,
        new: fn(u32, u32) -> Result<UniquePtr<ffi::PixelProc>, cxx::Exception>,
    ) -> Result<PixelProcessor, PpError> {
        let inner = new(recip.code(), sqrt.code()).map_err(|e| PpError::Build {
            recip,
            sqrt,
            message: e.what().to_string(),
        })?;
        Ok(PixelProcessor {
            recip,
            sqrt,
            inner,
            scene: None,
            fault: None,
            timeout_cycles: DEFAULT_TIMEOUT_CYCLES,
            poisoned: false,
            scratch: Vec::new(),
            coverage: None,
        })
    }

    /// The methods the model was verilated with: (recip, sqrt).
    pub fn methods(&self) -> (Method, Method) {
        (self.recip, self.sqrt)
    }

    /// Cycles a pixel may take before [`PpError::Hung`].
    pub fn timeout_cycles(&self) -> u64 {
        self.timeout_cycles
    }

    /// Sets the cycles a pixel may take before [`PpError::Hung`] (at least 1).
    pub fn set_timeout_cycles(&mut self, cycles: u64) {
        self.timeout_cycles = cycles.max(1);
    }

    /// Resets the model (rst_n low for two edges). The scene is forgotten:
    /// load one again. Clears the state an error left behind. The fault
    /// setting is kept.
    pub fn reset(&mut self) -> Result<(), PpError> {
        self.scene = None;
        self.poisoned = true;
        self.inner.pin_mut().reset().map_err(|e| PpError::Model {
            pixel: None,
            message: e.what().to_string(),
        })?;
        self.poisoned = false;
        Ok(())
    }

    /// Resets the model and loads `scene` through the scene port. Refuses a
    /// scene whose recip/sqrt methods are not the model's.
    pub fn load_scene(&mut self, scene: &Scene) -> Result<(), PpError> {
        check_methods(scene, self.recip, self.sqrt)?;
        self.reset()?;
        self.poisoned = true;
        for (cfg, addr, [x, y, z]) in scene_port_writes(scene) {
            self.inner
                .pin_mut()
                .write_scene(cfg, addr, x, y, z)
                .map_err(|e| PpError::Model {
                    pixel: None,
                    message: e.what().to_string(),
                })?;
        }
        self.poisoned = false;
        self.scene = Some(Loaded {
            width: scene.camera.width,
            height: scene.camera.height,
        });
        Ok(())
    }

    /// From the next pixel on, injects `fault` (see [`Fault`]); `None`
    /// switches it off.
    pub fn set_fault(&mut self, fault: Option<Fault>) {
        let fault = fault.filter(|f| f.xor != 0);
        let (state, xor) = fault.map_or((0, 0), |f| (f.state, f.xor));
        self.fault = fault;
        self.inner.pin_mut().set_fault(state, xor);
    }

    /// The fault set by [`PixelProcessor::set_fault`].
    pub fn fault(&self) -> Option<Fault> {
        self.fault
    }

    /// Runs pixel (px, py) of the loaded scene. With `trace`, appends the
    /// pixel's events (x, y = the pixel, seq from 0).
    pub fn run_pixel(
        &mut self,
        px: u32,
        py: u32,
        trace: Option<&mut Vec<TraceEvent>>,
    ) -> Result<PixelOutcome, PpError> {
        if self.poisoned {
            return Err(PpError::Poisoned);
        }
        self.check_pixel(px, py)?;
        self.scratch.clear();
        // Both fit: scenes are at most MAX_IMAGE_SIDE = 4096 wide and high.
        let (x, y) = (px as u16, py as u16);
        self.poisoned = true;
        let run = self
            .inner
            .pin_mut()
            .run_pixel(
                x,
                y,
                trace.is_some(),
                &mut self.scratch,
                self.timeout_cycles,
            )
            .map_err(|e| PpError::Model {
                pixel: Some((px, py)),
                message: e.what().to_string(),
            })?;
        let hung = |kind| PpError::Hung {
            x: px,
            y: py,
            processor: None,
            kind,
            cycles: run.edges,
            last_state: run
                .has_last_state
                .then_some((run.last_state, run.last_state_cycle)),
            state_port: run.state_port,
        };
        match run.status {
            ffi::PpStatus::Done => {}
            // Mid-pixel: stays poisoned until a reset.
            ffi::PpStatus::Timeout => return Err(hung(HangKind::Timeout)),
            // Idle again: the next pixel can start.
            ffi::PpStatus::Idle => {
                self.poisoned = false;
                return Err(hung(HangKind::IdleWithoutDone));
            }
            other => {
                return Err(PpError::Model {
                    pixel: Some((px, py)),
                    message: format!("unknown pixel status {}", other.repr),
                })
            }
        }
        self.poisoned = false;
        if let Some(out) = trace {
            out.extend(self.scratch.iter().enumerate().map(|(seq, e)| TraceEvent {
                x,
                y,
                seq: seq as u32,
                state: e.state,
                dst: e.dst,
                lanes: e.lanes,
                values: e.values,
            }));
        }
        Ok(PixelOutcome {
            rgb: run.rgb,
            cycles: run.cycles,
            events: run.events,
        })
    }

    /// A scene is loaded and (x, y) is inside its image.
    fn check_pixel(&self, x: u32, y: u32) -> Result<(), PpError> {
        let loaded = self.scene.ok_or(PpError::NoScene)?;
        if x >= loaded.width || y >= loaded.height {
            return Err(PpError::OutsideImage {
                x,
                y,
                width: loaded.width,
                height: loaded.height,
            });
        }
        Ok(())
    }

    /// Runs `pixels` of the loaded scene through the bare clock loop
    /// (`harness/cpp/bare.h`: one FFI call, nothing read but ready and
    /// done) and returns the sum of their cycles: the baseline the
    /// harness's overhead is measured against (`benches/overhead.rs`).
    pub fn run_bare(&mut self, pixels: &[(u32, u32)]) -> Result<u64, PpError> {
        if self.poisoned {
            return Err(PpError::Poisoned);
        }
        let mut coords = Vec::with_capacity(pixels.len());
        for &(x, y) in pixels {
            self.check_pixel(x, y)?;
            coords.push(x | y << 16);
        }
        self.poisoned = true;
        let cycles = self
            .inner
            .pin_mut()
            .run_bare(&coords, self.timeout_cycles)
            .map_err(|e| PpError::Model {
                pixel: None,
                message: e.what().to_string(),
            })?;
        self.poisoned = false;
        Ok(cycles)
    }
}

impl Drop for PixelProcessor {
    /// A coverage model writes its counts into its directory's `raw/`; a
    /// failure cannot be returned from here, so it is reported on stderr.
    fn drop(&mut self) {
        let Some(dir) = self.coverage.take() else {
            return;
        };
        crate::coverage::write_raw(&dir, |p| self.inner.pin_mut().write_coverage(p));
    }
}
