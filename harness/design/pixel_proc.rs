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
//! The C++ driver (`harness/design/cpp/pixel_proc.cpp`) runs a whole pixel per FFI
//! call. A pixel that does not finish (no `done` within the timeout, or
//! `ready` high again without `done`) comes back as a status rather than a
//! C++ exception, so that [`PpError::Hung`] can name the pixel, the cycles
//! and the last state with golden's state table; fatal errors inside the
//! model (`$stop`, `$fatal`) and port-protocol violations are exceptions
//! ([`PpError::Model`]).

use crate::design::bridge::ffi;
use crate::design::error::{check_scene, scene_port_writes, Fault, HangKind, PpError};
use crate::design::processor::Driver;
use crate::design::spec::Design;
use cxx::UniquePtr;
use golden::fp::Method;
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use std::path::PathBuf;

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
/// send::<rtcosim::design::pixel_proc::PixelProcessor>();
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
    /// A coverage model's directory ([`crate::output::coverage`]): its counts are
    /// written there when it is dropped.
    coverage: Option<PathBuf>,
}

impl PixelProcessor {
    /// Builds and resets the model of `design` (driven one pixel at a
    /// time: the compact processor alone), its coverage twin when coverage
    /// is on in this process ([`crate::design::counts::dir`]) and the
    /// design is plain. A mutant design starts with mutant 0 (the design as
    /// written) selected: [`PixelProcessor::set_mutant`].
    pub fn open(design: &Design) -> Result<PixelProcessor, PpError> {
        let (design, coverage) = design.with_coverage();
        design.check_driver(Driver::OnePixel)?;
        let inner =
            ffi::new_pixel_proc(&design.class()).map_err(|e| design.not_opened(e.what()))?;
        Ok(PixelProcessor {
            recip: design.recip,
            sqrt: design.sqrt,
            inner,
            scene: None,
            fault: None,
            timeout_cycles: design.default_timeout_cycles(),
            poisoned: false,
            scratch: Vec::new(),
            coverage,
        })
    }

    /// On a mutant model: selects mutant `id` (0: the design as written)
    /// from the next reset on. Reset next: a mutant may fail its reset.
    pub fn set_mutant(&mut self, id: u16) -> Result<(), PpError> {
        self.inner
            .pin_mut()
            .set_mutant(id)
            .map_err(|e| PpError::Model {
                pixel: None,
                message: e.what().to_string(),
            })
    }

    /// The model, for [`crate::output::wave`]'s calls to its waveform port.
    pub(crate) fn model(&mut self) -> std::pin::Pin<&mut ffi::PixelProc> {
        self.inner.pin_mut()
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
        check_scene(scene, self.recip, self.sqrt)?;
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
    /// (`harness/design/cpp/bare.h`: one FFI call, nothing read but ready and
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
        crate::design::counts::write_raw(&dir, |p| self.inner.pin_mut().write_coverage(p));
    }
}
