//! The vocabulary every driver shares: its errors, the fault it injects,
//! where in a top a pixel ran, how a scene goes through the scene port.

use crate::design::processor;
use golden::fp::Method;
use golden::micro::isa::state_label;
use golden::micro::loader::{self, Config};
use golden::scene::Scene;

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
    /// A design no build makes, or one this build did not make.
    #[error("{design}: not a model of this build: {why}")]
    NotBuilt { design: String, why: String },
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
                let k = processor::FAST_CONTEXTS;
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
pub(crate) fn check_scene(scene: &Scene, recip: Method, sqrt: Method) -> Result<(), PpError> {
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

/// Cycles a pixel may take before it counts as hung, on a processor that
/// runs one pixel at a time; a processor whose contexts take turns gives
/// each this many ([`crate::design::Processor::default_timeout_cycles`]).
/// The slowest pixel of any builtin scene takes well under 10,000 cycles
/// on the compact processor.
pub const DEFAULT_TIMEOUT_CYCLES: u64 = 100_000;
