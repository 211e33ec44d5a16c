//! The designs under test, and the one door through which every tool
//! drives them.
//!
//! A [`Design`] names one verilated build: which processor (a row of
//! facts, [`processor::Processor`]), its float methods, whether it has
//! its exponential unit, how many processors sit in `rtl/top.v` (none:
//! the processor alone), and the flavour of the model (plain, waveform,
//! coverage, mutant, synthesized netlist; [`Flavour`]). Its
//! [`Design::open`] gives a [`Dut`]: load a scene, stream pixels into a
//! sink of results and trace events ([`TopPixel`]), inject a fault, set
//! the watchdog. What a design cannot be is said once, by
//! [`Design::refusal`], and a design this build lacks is refused with the
//! cargo feature that builds it ([`Design::check`]).
//!
//! - [`models`]: the table of verilated models, shared with the build
//!   script.
//! - [`processor`]: the processors' rows.
//! - [`pixel_proc`], [`top`]: the two drivers (one pixel at a time;
//!   streams), and [`fast_alu`], [`fp_unit`]: the units verilated alone.
//! - [`rtl_source`]: the Verilog line that decodes each controller state.
//! - [`counts`]: where coverage models write their counts.
//! - `bridge`: the cxx bridge to the C++ drivers (`harness/design/cpp/`).

pub(crate) mod bridge;
pub mod counts;
pub mod fast_alu;
pub mod fp_unit;
pub mod models;
pub mod pixel_proc;
pub mod processor;
pub mod rtl_source;
pub mod top;

pub use models::Flavour;

use golden::fp::Method;
use golden::micro::isa::state_label;
use golden::micro::loader::{self, Config};
use golden::scene::Scene;
use pixel_proc::PixelProcessor;
use processor::{Driver, Processor, ProcessorKind};
use std::fmt;
use std::path::PathBuf;
use top::{FrameStats, Source, Stall, Top, TopPixel};

include!(concat!(env!("OUT_DIR"), "/models_built.rs"));

/// One verilated build of a processor: everything that picks its model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Design {
    pub processor: ProcessorKind,
    pub recip: Method,
    pub sqrt: Method,
    /// Whether the processors have their exponential unit (`EXPOSURE`);
    /// only a processor whose row says `exp_optional` is built without.
    pub exp_unit: bool,
    /// Processors in `rtl/top.v`; `None`: the processor alone.
    pub procs: Option<u32>,
    pub flavour: Flavour,
}

impl Design {
    /// `processor` alone with these methods, its exponential, plain.
    pub fn new(processor: ProcessorKind, recip: Method, sqrt: Method) -> Design {
        Design {
            processor,
            recip,
            sqrt,
            exp_unit: true,
            procs: None,
            flavour: Flavour::Plain,
        }
    }

    /// The compact processor alone with these methods.
    pub fn compact(recip: Method, sqrt: Method) -> Design {
        Design::new(ProcessorKind::Compact, recip, sqrt)
    }

    /// The fast processor alone with these methods.
    pub fn fast(recip: Method, sqrt: Method) -> Design {
        Design::new(ProcessorKind::Fast, recip, sqrt)
    }

    /// `processor` alone with `scene`'s methods.
    pub fn for_scene(processor: ProcessorKind, scene: &Scene) -> Design {
        Design::new(processor, scene.render.recip, scene.render.sqrt)
    }

    /// The same with N processors in `rtl/top.v` (`None`: alone).
    pub fn procs(self, procs: Option<u32>) -> Design {
        Design { procs, ..self }
    }

    /// The same with or without the exponential unit.
    pub fn exp_unit(self, exp_unit: bool) -> Design {
        Design { exp_unit, ..self }
    }

    /// The same in another flavour.
    pub fn flavour(self, flavour: Flavour) -> Design {
        Design { flavour, ..self }
    }

    /// The same with `scene`'s methods.
    pub fn methods_of(self, scene: &Scene) -> Design {
        Design {
            recip: scene.render.recip,
            sqrt: scene.render.sqrt,
            ..self
        }
    }

    /// Its processor's row.
    pub fn row(&self) -> &'static Processor {
        self.processor.row()
    }

    /// How it is driven: every top through its streams, a processor alone
    /// as its row says.
    pub fn driver(&self) -> Driver {
        match self.procs {
            Some(_) => Driver::Streams,
            None => self.row().alone,
        }
    }

    /// Pixel contexts in all (slots of its streams).
    pub fn contexts(&self) -> u32 {
        self.procs.unwrap_or(1) * self.row().contexts
    }

    /// What its slots are.
    pub fn slot_layout(&self) -> SlotLayout {
        match (self.procs, self.row().contexts) {
            (_, 1) => SlotLayout::Compact,
            (None, _) => SlotLayout::FastContexts,
            (Some(_), _) => SlotLayout::FastProcessors,
        }
    }

    /// Whether its results leave through a stream that can be held back
    /// (`--stall`).
    pub fn has_result_stream(&self) -> bool {
        self.driver() == Driver::Streams
    }

    /// Its class in the model table.
    pub fn class(&self) -> String {
        models::processor_class(
            self.row().models,
            self.flavour,
            self.recip.name(),
            self.sqrt.name(),
            self.exp_unit,
            self.procs.map(|procs| models::TopShape { procs, group: 0 }),
        )
    }

    /// Why no build makes this design, if none does: the one place that
    /// says what a design cannot be.
    pub fn refusal(&self) -> Option<String> {
        let row = self.row();
        if let Some(why) = self.exp_unit_refusal() {
            return Some(why);
        }
        if let Some(n) = self.procs {
            if !(1..=row.max_procs).contains(&n) {
                return Some(format!(
                    "a top of {} processors has 1 to {} of them",
                    row.name, row.max_procs
                ));
            }
            if !self.exp_unit {
                return Some(format!(
                    "the tops of {} processors are built with the exponential only",
                    row.name
                ));
            }
            if self.flavour != Flavour::Plain {
                return Some(format!("the tops are built plain only, not as {} models", self.flavour.name()));
            }
        }
        if self.flavour.is_yosys_netlist() && (self.recip, self.sqrt) != (Method::Exact, Method::Exact) {
            return Some(format!("{} models are made with the exact methods only", self.flavour.name()));
        }
        if !BUILT.iter().any(|(class, _, _)| *class == self.class()) {
            return Some(format!("no {} model of the {} processor is made", self.flavour.name(), row.name));
        }
        None
    }

    /// Why its processor cannot go without its exponential, if it cannot.
    pub fn exp_unit_refusal(&self) -> Option<String> {
        let row = self.row();
        (!self.exp_unit && !row.exp_optional)
            .then(|| format!("the {} processor always has its exponential", row.name))
    }

    /// Refuses a design no build makes ([`Design::refusal`]), or one this
    /// build did not make, naming the cargo features that make it.
    pub fn check(&self) -> Result<(), PpError> {
        if let Some(why) = self.refusal() {
            return Err(PpError::NotBuilt {
                design: self.to_string(),
                why,
            });
        }
        let class = self.class();
        match BUILT.iter().find(|(c, _, _)| *c == class) {
            Some((_, _, true)) => Ok(()),
            Some((_, features, false)) => Err(PpError::NotBuilt {
                design: self.to_string(),
                why: how_to_build(features),
            }),
            // A top of an N not in the table: asked for by name at build time.
            None => Err(PpError::NotBuilt {
                design: self.to_string(),
                why: format!(
                    "build it by name: RTCOSIM_TOPS={}{}:{}:{} cargo build --release",
                    if self.row().contexts > 1 { "fast:" } else { "" },
                    self.procs.unwrap_or(1),
                    self.recip,
                    self.sqrt
                ),
            }),
        }
    }

    /// [`Design::check`], and that the design is driven by `driver`.
    pub(crate) fn check_driver(&self, driver: Driver) -> Result<(), PpError> {
        self.check()?;
        if self.driver() != driver {
            return Err(PpError::NotBuilt {
                design: self.to_string(),
                why: format!("it is driven {driver:?}, not {:?}", self.driver()),
            });
        }
        Ok(())
    }

    /// The error of a model the C++ could not build.
    pub(crate) fn not_opened(&self, message: &str) -> PpError {
        PpError::NotBuilt {
            design: self.to_string(),
            why: message.to_string(),
        }
    }

    /// The design to build when coverage is on in this process (its
    /// coverage twin, if it is plain), and the directory its counts go to.
    pub(crate) fn with_coverage(&self) -> (Design, Option<PathBuf>) {
        match counts::dir() {
            Some(dir) if self.flavour == Flavour::Plain && self.procs.is_none() => {
                (self.flavour(Flavour::Coverage), Some(dir))
            }
            _ => (*self, None),
        }
    }

    /// Builds and resets its model, driven as its row says.
    pub fn open(&self) -> Result<Dut, PpError> {
        let model = match self.driver() {
            Driver::OnePixel => Model::OnePixel(PixelProcessor::open(self)?),
            Driver::Streams => Model::Streams(Top::open(self)?),
        };
        Ok(Dut {
            design: *self,
            model,
        })
    }
}

/// Refuses a model class this build did not make, naming the cargo
/// features that make it (the units and the ALU; a [`Design`] says more
/// through [`Design::check`]).
pub(crate) fn require(class: &str) -> Result<(), String> {
    match BUILT.iter().find(|(c, _, _)| *c == class) {
        Some((_, _, true)) => Ok(()),
        Some((_, features, false)) => Err(how_to_build(features)),
        None => Err(format!("{class} is not a model of the table (harness/design/models.rs)")),
    }
}

/// The cargo features that build a model, as a command: this command
/// again, when it is the CLI.
fn how_to_build(features: &[&str]) -> String {
    let features = features.join(",");
    let args: Vec<String> = std::env::args().collect();
    let cli = args
        .first()
        .and_then(|a| std::path::Path::new(a).file_stem()?.to_str().map(String::from));
    let again = match cli.as_deref() {
        Some("rtcosim") => args[1..].join(" "),
        _ => "...".to_string(),
    };
    format!(
        "this build lacks it; build it with the cargo feature{} `{features}`: cargo run --release \
         --features {features} -- {again}",
        if features.contains(',') { "s" } else { "" }
    )
}

impl fmt::Display for Design {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.procs {
            Some(n) => write!(f, "top of {n} {} pixel processors", self.processor)?,
            None => write!(f, "{} pixel processor", self.processor)?,
        }
        if !self.exp_unit {
            write!(f, " without its exponential")?;
        }
        write!(f, " (recip {}, sqrt {}", self.recip, self.sqrt)?;
        if self.flavour != Flavour::Plain {
            write!(f, ", {} model", self.flavour.name())?;
        }
        write!(f, ")")
    }
}

/// A design under test, built: whichever driver its design needs, behind
/// one interface.
pub struct Dut {
    design: Design,
    model: Model,
}

/// The driver a [`Dut`] has.
enum Model {
    OnePixel(PixelProcessor),
    Streams(Top),
}

impl Dut {
    /// The design it was built from.
    pub fn design(&self) -> Design {
        self.design
    }

    /// Resets the model and loads `scene`; refuses a scene it cannot draw
    /// (other methods, an exposure without the exponential).
    pub fn load_scene(&mut self, scene: &Scene) -> Result<(), PpError> {
        match &mut self.model {
            Model::OnePixel(p) => p.load_scene(scene),
            Model::Streams(t) => t.load_scene(scene),
        }
    }

    /// From now on, injects `fault` into every processor's register
    /// writes (`None`: off).
    pub fn set_fault(&mut self, fault: Option<Fault>) {
        match &mut self.model {
            Model::OnePixel(p) => p.set_fault(fault),
            Model::Streams(t) => t.set_fault(fault, u32::MAX),
        }
    }

    /// Cycles a pixel may take before the run stops as hung.
    pub fn set_timeout_cycles(&mut self, cycles: u64) {
        match &mut self.model {
            Model::OnePixel(p) => p.set_timeout_cycles(cycles),
            Model::Streams(t) => t.set_timeout_cycles(cycles),
        }
    }

    /// Holds the result stream back as `stall` says, seeded with `seed`;
    /// nothing for a design without a result stream.
    pub fn set_stall(&mut self, seed: u64, stall: Stall) {
        if let Model::Streams(t) = &mut self.model {
            t.set_backpressure(seed, stall);
        }
    }

    /// On a mutant model: selects mutant `id` from the next reset on.
    pub fn set_mutant(&mut self, id: u16) -> Result<(), PpError> {
        match &mut self.model {
            Model::OnePixel(p) => p.set_mutant(id),
            Model::Streams(t) => t.set_mutant(id),
        }
    }

    /// Runs the pixels `coords` (distinct, in the loaded scene) and hands
    /// each to `sink` as its result arrives, with its trace events: in
    /// order one pixel at a time, or as a streamed frame leaves. The
    /// frame cycles of one pixel at a time are the pixels' cycles back to
    /// back.
    pub fn run(
        &mut self,
        coords: &[(u32, u32)],
        sink: &mut dyn FnMut(TopPixel<'_>),
    ) -> Result<FrameStats, PpError> {
        match &mut self.model {
            Model::Streams(t) => t.run_frame(Source::Stream(coords), sink),
            Model::OnePixel(p) => {
                let mut stats = FrameStats::default();
                let mut events = Vec::new();
                for &(x, y) in coords {
                    events.clear();
                    let outcome = p.run_pixel(x, y, Some(&mut events))?;
                    stats.pixels += 1;
                    stats.pixel_cycles += outcome.cycles;
                    stats.frame_cycles += outcome.cycles;
                    stats.events += events.len() as u64;
                    stats.batches += 1;
                    sink(TopPixel {
                        x,
                        y,
                        processor: 0,
                        outcome,
                        events: &events,
                    });
                }
                Ok(stats)
            }
        }
    }

    /// The streamed driver, for what only streams have (the turn, the
    /// refused takes, the waveform window's cycles).
    pub fn streams(&mut self) -> Option<&mut Top> {
        match &mut self.model {
            Model::Streams(t) => Some(t),
            Model::OnePixel(_) => None,
        }
    }

    /// The one-pixel driver.
    pub fn one_pixel(&mut self) -> Option<&mut PixelProcessor> {
        match &mut self.model {
            Model::OnePixel(p) => Some(p),
            Model::Streams(_) => None,
        }
    }
}

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
