//! Speed against accuracy: a grid of render configurations of a scene, each
//! measured for speed (the micro-op model's cycles, which are the RTL's,
//! cycle for cycle) and for accuracy (against the f64 reference renderer),
//! the Pareto front of the two, and the front confirmed through the RTL.
//!
//! - [`Config`]: one point of the grid (methods, stack depth, speed-ups,
//!   weight cutoff); [`Grid`]: the lists it is the product of.
//! - [`sweep_scene`]: renders every configuration the scene accepts with
//!   [`golden::micro`] and measures it against [`golden::reference`];
//!   configurations the scene refuses (a speed-up whose precondition it
//!   breaks) are skipped and counted.
//! - [`pareto_front`]: which rows no other row beats in both speed (or area:
//!   [`Axis`]) and error.
//! - [`confirm`]: each front configuration co-simulated on the RTL
//!   ([`crate::check::cosim::run_pixels`]) on every pixel where its frame differs
//!   from the [full](Config::full) configuration's, plus a seeded sample.
//! - [`write_csv`], [`write_json`]: the rows, machine-readable;
//!   [`chart`]: the chart, SVG and PNG.
//!
//! One RTL build serves every depth: the verilated pixel processor has the
//! full [`MAX_DEPTH`]-level stack (`STACK_DEPTH` defaults to
//! `ISA_DIM_STK_COUNT` = 8 in rtl/pp/pixel_processor.v and build.rs does not
//! override it), and the scene's `max_depth`, loaded into the configuration
//! word, limits how much of it a pixel uses. The methods pick one of the
//! four verilated variants. A row's `rtl_stack_depth` is what a build *for
//! that configuration* needs, not what was co-simulated.

pub mod chart;
pub mod run;

use crate::check::compare::CompareReport;
use crate::check::cosim::{self, CosimError, CosimOptions};
use crate::design::processor::{CycleRule, ProcessorKind};
use crate::output::device::Build;
use golden::diffmap::DiffMap;
use golden::fp::Method;
use golden::frame::Frame;
use golden::scene::{RenderSettings, Scene, SceneError, Speedups, MAX_DEPTH};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The clock frames per second are stated at by default: our own pixel
/// processor's maximum frequency after place and route, measured with
/// nextpnr-ecp5 on an ECP5 LFE5U-85F, speed grade 6 (exact methods,
/// `STACK_DEPTH` 8, no `PP_TRACE`; docs/rtl.md, "Synthesis", "Measured
/// (ECP5)": `Max frequency for clock ...: 8.94 MHz`). A clock this RTL
/// reaches, unlike [`THESIS_CLOCK_HZ`].
pub const ECP5_CLOCK_HZ: f64 = 8.94e6;

/// The thesis' clock: the largest frequency Xilinx ISE reported for *its*
/// pixel processor on the Virtex-6 LX760, thesis section 5.2 ("1 Pixel
/// Processor ... Maximum frequency 34.740MHz"; its 148,655,803 cycles a
/// frame at that clock are the table's 4.279 s). Our processor does not
/// reach it (its float units sit inside the branch cycle, docs/rtl.md);
/// `sweep --clock-mhz 34.74` states frames/s at it for comparison.
pub const THESIS_CLOCK_HZ: f64 = 34.740e6;

/// The thesis' own hardware on its Virtex-6 LX760: two pixel processors
/// at 28.86 MHz, the most that routed (thesis section 5.2; one routed at
/// 34.74 MHz), 148,655,803 cycles for its 800x600 reference frame
/// (docs/rtl.md, "Frames per second and processors per LX760"). The
/// chart's thesis point: [`ThesisDevice::frames_per_second`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThesisDevice {
    pub processors: u32,
    pub clock_hz: f64,
    pub frame_cycles: u64,
    pub frame_pixels: u64,
}

pub const THESIS_DEVICE: ThesisDevice = ThesisDevice {
    processors: 2,
    clock_hz: 28.86e6,
    frame_cycles: 148_655_803,
    frame_pixels: 800 * 600,
};

impl ThesisDevice {
    /// Frames a second of a frame of `pixels` at the reference frame's
    /// cycles per pixel (exact for the reference frame at 800x600; for
    /// other scenes and sizes, a scaling: the thesis' cycles per pixel
    /// were measured on that frame only). 0.388 for the reference.
    pub fn frames_per_second(&self, pixels: u32) -> f64 {
        let per_pixel = self.frame_cycles as f64 / self.frame_pixels as f64;
        f64::from(self.processors) * self.clock_hz / (per_pixel * f64::from(pixels.max(1)))
    }
}

/// What a frames/s figure at `clock_mhz` is: a header for tables, `frames/s
/// at 8.94 MHz`.
pub fn fps_header(clock_mhz: f64) -> String {
    format!("frames/s at {clock_mhz} MHz")
}

/// Where a clock of `clock_mhz` comes from, for a report's line: the
/// default's source, or "given with --clock-mhz".
pub fn clock_source(clock_mhz: f64) -> &'static str {
    if clock_mhz == ECP5_CLOCK_HZ / 1e6 {
        "our pixel processor's post-route clock on ECP5 (docs/rtl.md, Synthesis)"
    } else if clock_mhz == THESIS_CLOCK_HZ / 1e6 {
        "the thesis' Virtex-6 clock, which our processor does not reach (given with --clock-mhz)"
    } else {
        "given with --clock-mhz"
    }
}

/// The share of pixels reported is of those off by more than this on the
/// 0..255 scale: the thesis' own bound (section 4.11: "a difference less
/// than 0.5 would be acceptable").
pub const VISIBLE: f64 = 0.5;

/// The weight cutoffs `tune` tries: off, and the powers of two 2^-8 (a
/// weight that can move a channel by at most one 8-bit step) to 2^-1. Exact
/// in f32 and f64, so both models compare against the same number.
pub const CUTOFFS: [f32; 9] = [
    0.0,
    1.0 / 256.0,
    1.0 / 128.0,
    1.0 / 64.0,
    1.0 / 32.0,
    1.0 / 16.0,
    1.0 / 8.0,
    1.0 / 4.0,
    1.0 / 2.0,
];

/// The cutoffs of the default sweep: off, one 8-bit step (2^-8) and 2^-4,
/// three points of [`CUTOFFS`] that keep the grid at 1,408 configurations.
pub const SWEEP_CUTOFFS: [f32; 3] = [0.0, 1.0 / 256.0, 1.0 / 16.0];

/// What the front and the chart's x axis weigh a configuration's error
/// against: its speed in hardware units, or its area.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Axis {
    /// Frames a second of one Virtex-6 LX760 filled with the row's
    /// processors (more is better; log scale).
    #[default]
    DeviceFps,
    /// Slice LUTs of one processor of the row's build (fewer is better).
    Luts,
    /// DSP48E1 slices of one processor of the row's build (fewer is
    /// better).
    Dsp,
}

impl Axis {
    /// The row's value on this axis.
    pub fn value(self, r: &Row) -> f64 {
        match self {
            Axis::DeviceFps => r.device_fps,
            Axis::Luts => f64::from(r.luts_per_processor),
            Axis::Dsp => f64::from(r.dsp_per_processor),
        }
    }

    /// The row's value, oriented so that more is better.
    pub fn gain(self, r: &Row) -> f64 {
        match self {
            Axis::DeviceFps => self.value(r),
            Axis::Luts | Axis::Dsp => -self.value(r),
        }
    }

    /// Its name on the command line and in sweep.json.
    pub fn name(self) -> &'static str {
        match self {
            Axis::DeviceFps => "device-fps",
            Axis::Luts => "luts",
            Axis::Dsp => "dsp",
        }
    }
}

/// One render configuration: what the grid varies. Everything else (the
/// camera, the objects, any render setting this type does not name) is the
/// scene's own: [`Config::apply`] replaces only these fields; the
/// processor draws the same picture, at its own speed and cost.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    pub processor: ProcessorKind,
    pub recip: Method,
    pub sqrt: Method,
    /// Ray stack depth, 1..=[`MAX_DEPTH`].
    pub depth: u32,
    pub speedups: Speedups,
    /// `[render] weight_cutoff`: no reflection ray is spawned whose weight
    /// is below it (0: off).
    pub cutoff: f32,
    /// The scene's glass drawn opaque (every transmission 0,
    /// [`Scene::with_opaque_glass`]): nothing refracts, and the build has
    /// no refraction. Only a scene with glass takes it
    /// ([`Grid::configs_for`]).
    pub opaque_glass: bool,
}

impl Config {
    /// The full configuration, the one every other is checked against on
    /// the RTL: the deepest stack, the correctly rounded units, no
    /// speed-ups (nothing skipped, nothing approximated).
    pub fn full() -> Config {
        Config {
            processor: ProcessorKind::default(),
            recip: Method::Exact,
            sqrt: Method::Exact,
            depth: MAX_DEPTH,
            speedups: Speedups::default(),
            cutoff: 0.0,
            opaque_glass: false,
        }
    }

    /// The thesis' Verilog configuration: stack depth 4 (section 3.8) and
    /// two of the three speed-ups, fast plane checks and the shadow
    /// shortcut, without the bounding box (section 3.10.5). Its float units
    /// were Xilinx IP cores of unknown rounding; the correctly rounded
    /// methods stand for them here.
    pub fn thesis() -> Config {
        Config {
            processor: ProcessorKind::default(),
            recip: Method::Exact,
            sqrt: Method::Exact,
            depth: 4,
            speedups: Speedups {
                bounding_box: false,
                fast_plane: true,
                shadow_shortcut: true,
            },
            cutoff: 0.0,
            opaque_glass: false,
        }
    }

    /// `scene` with this configuration, validated again: a speed-up whose
    /// precondition the scene breaks is refused here, in the scene's words.
    pub fn apply(&self, scene: &Scene, origin: &str) -> Result<Scene, SceneError> {
        // The update keeps every setting this type does not name (the
        // exposure: part of the picture, not of the configuration).
        let render = RenderSettings {
            max_depth: self.depth,
            speedups: self.speedups,
            recip: self.recip,
            sqrt: self.sqrt,
            weight_cutoff: self.cutoff,
            ..scene.render
        };
        if self.opaque_glass {
            scene.with_opaque_glass(origin)?.with_render(render, origin)
        } else {
            scene.with_render(render, origin)
        }
    }

    /// The RTL build this configuration of `scene` runs on (and is priced
    /// as): its processor and methods, [`crate::output::device::BUILT_STACK_DEPTH`],
    /// the exponential if the scene has exposure, refraction if it has glass.
    pub fn build(&self, scene: &Scene) -> Build {
        Build::for_scene(self.processor, self.recip, self.sqrt, scene)
    }

    /// A short name: `compact, depth 4, recip exact, sqrt fast, fp+ss,
    /// cutoff 1/256`, and `, opaque glass` with the glass opaque.
    pub fn label(&self) -> String {
        format!(
            "{}, depth {}, recip {}, sqrt {}, {}, {}{}",
            self.processor,
            self.depth,
            self.recip,
            self.sqrt,
            speedup_label(self.speedups),
            cutoff_label(self.cutoff),
            if self.opaque_glass {
                ", opaque glass"
            } else {
                ""
            }
        )
    }
}

/// `cutoff 1/256` for a power-of-two cutoff, `cutoff 0.3` otherwise, `no
/// cutoff` for 0.
pub fn cutoff_label(c: f32) -> String {
    let inverse = 1.0 / f64::from(c);
    if c == 0.0 {
        "no cutoff".into()
    } else if inverse.fract() == 0.0 {
        format!("cutoff 1/{inverse}")
    } else {
        format!("cutoff {c}")
    }
}

/// `bb+fp+ss` for the speed-ups on, `none` for none.
pub fn speedup_label(s: Speedups) -> String {
    let on: Vec<&str> = [
        (s.bounding_box, "bb"),
        (s.fast_plane, "fp"),
        (s.shadow_shortcut, "ss"),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .map(|(_, name)| *name)
    .collect();
    if on.is_empty() {
        "none".into()
    } else {
        on.join("+")
    }
}

/// The grid: the product of these lists, in this order (processor, recip,
/// sqrt, depth, speed-ups, cutoff, opaque glass), which is the order of the
/// CSV's rows. Depth 1 spawns no reflection, so it takes only cutoff 0 (the
/// others would be the same configuration); a scene without glass takes
/// only its glass as it is ([`Grid::configs_for`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub processors: Vec<ProcessorKind>,
    pub recips: Vec<Method>,
    pub sqrts: Vec<Method>,
    pub depths: Vec<u32>,
    pub speedups: Vec<Speedups>,
    pub cutoffs: Vec<f32>,
    /// Whether the glass is drawn opaque ([`Config::opaque_glass`]).
    pub opaque_glass: Vec<bool>,
}

impl Grid {
    /// The sweep's grid: both processors, both methods of each unit, every
    /// depth 1..=8, each speed-up on and off (8 combinations), the cutoffs
    /// of [`SWEEP_CUTOFFS`]: 2 x 4 x 8 x (1 + 7 x 3) = 1,408 configurations;
    /// for a scene with glass, each with its glass as it is and opaque.
    pub fn full() -> Grid {
        Grid {
            speedups: (0..8u8)
                .map(|bits| Speedups {
                    bounding_box: bits & 4 != 0,
                    fast_plane: bits & 2 != 0,
                    shadow_shortcut: bits & 1 != 0,
                })
                .collect(),
            cutoffs: SWEEP_CUTOFFS.to_vec(),
            ..Grid::tune(Speedups::default())
        }
    }

    /// `tune`'s grid: both processors, both methods of each unit, every
    /// depth, every cutoff of [`CUTOFFS`], the glass as it is and opaque,
    /// and the one set of speed-ups given (those whose preconditions the
    /// scene meets: they change only the cycles, never the image):
    /// 2 x 4 x (1 + 7 x 9) = 512 configurations, twice that for a scene
    /// with glass.
    pub fn tune(speedups: Speedups) -> Grid {
        let both = vec![Method::Exact, Method::Fast];
        Grid {
            processors: ProcessorKind::ALL.to_vec(),
            recips: both.clone(),
            sqrts: both,
            depths: (1..=MAX_DEPTH).collect(),
            speedups: vec![speedups],
            cutoffs: CUTOFFS.to_vec(),
            opaque_glass: vec![false, true],
        }
    }

    /// Every configuration `scene` takes, in row order: [`Grid::configs`]
    /// but, for a scene without glass, none with the glass opaque (the
    /// same picture as with it as it is).
    pub fn configs_for(&self, scene: &Scene) -> Vec<Config> {
        let glass = scene.refracts();
        self.configs()
            .into_iter()
            .filter(|c| glass || !c.opaque_glass)
            .collect()
    }

    /// Every configuration, in row order.
    pub fn configs(&self) -> Vec<Config> {
        let mut out = Vec::new();
        for &processor in &self.processors {
            for &recip in &self.recips {
                for &sqrt in &self.sqrts {
                    for &depth in &self.depths {
                        for &speedups in &self.speedups {
                            for &cutoff in self.cutoffs.iter().filter(|&&c| depth > 1 || c == 0.0) {
                                for &opaque_glass in &self.opaque_glass {
                                    out.push(Config {
                                        processor,
                                        recip,
                                        sqrt,
                                        depth,
                                        speedups,
                                        cutoff,
                                        opaque_glass,
                                    });
                                }
                            }
                        }
                    }
                }
            }
        }
        out
    }
}

/// One configuration of one scene, measured: a row of the CSV. The field
/// order is the column order (docs/accuracy.md, "Speed against accuracy",
/// documents each column). Shard files carry rows as CSV cells and read
/// them back ([`run`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// The pixel processor: compact or fast.
    pub processor: ProcessorKind,
    #[serde(deserialize_with = "method_name")]
    pub recip: MethodName,
    #[serde(deserialize_with = "method_name")]
    pub sqrt: MethodName,
    pub depth: u32,
    pub bounding_box: bool,
    pub fast_plane: bool,
    pub shadow_shortcut: bool,
    /// `[render] weight_cutoff` (0: off).
    pub weight_cutoff: f32,
    /// The glass drawn opaque (every transmission 0): a build without
    /// refraction. Absent (false) in the CSV of an older rtcosim.
    #[serde(default)]
    pub opaque_glass: bool,
    /// Mean cycles per pixel (the micro-op model's = the RTL's): a pixel's
    /// cycles from its start to its end; on the fast processor, from the
    /// turn that took it to its done turn, 32 pixels in flight.
    pub cycles_per_pixel: f64,
    /// The slowest pixel's cycles.
    pub max_cycles: u64,
    /// Cycles of the whole frame on one pixel processor (the fast one's by
    /// its barrel rule, `golden::micro::barrel`, as co-simulation checks).
    pub frame_cycles: u64,
    /// Frames per second of one pixel processor at `clock_mhz` (not a
    /// device's: one processor, no top, at the clock the run states).
    pub fps_at_clock_mhz: f64,
    /// The clock `fps_at_clock_mhz` is at: by default [`ECP5_CLOCK_HZ`].
    pub clock_mhz: f64,
    /// The speed axis in hardware units ([`crate::output::device`]): processors of
    /// this build that fit one Virtex-6 LX760, the resource that binds,
    /// the build's clock estimate, and the device's frames per second, the
    /// frame split evenly between its processors.
    pub device_processors: u32,
    pub device_binding: String,
    pub device_clock_mhz: f64,
    pub device_fps: f64,
    /// One processor of the build: slice LUTs and DSP48E1s (the area axis).
    pub luts_per_processor: u32,
    pub dsp_per_processor: u32,
    /// Whether the build's cost was measured or interpolated
    /// (`rtl/synth/costs.toml`).
    pub cost_source: String,
    /// Mean |micro - reference| over every colour value, 0..255 scale.
    pub mean_abs_error: f64,
    /// Largest |micro - reference| of any colour value, 0..255 scale.
    pub max_abs_error: f64,
    /// Share (0..=1) of pixels with a channel off by more than [`VISIBLE`].
    pub share_pixels_over_half: f64,
    /// Largest ULP distance of a colour value (the reference rounded to f32).
    pub max_ulps: u32,
    /// Colour values NaN on one side only.
    pub nan_mismatches: u64,
    /// The RTL build this configuration needs.
    pub rtl_stack_depth: u32,
    pub rtl_recip_method: u32,
    pub rtl_sqrt_method: u32,
    /// On the Pareto front of (cycles per pixel, mean abs error).
    pub pareto: bool,
    /// Front rows only: pixels whose colour differs from the full
    /// configuration's, pixels co-simulated (those plus the sample), and
    /// whether the RTL agreed on every one, bit and cycle.
    pub differs_from_full: Option<u64>,
    pub rtl_pixels: Option<u64>,
    pub rtl_confirmed: Option<bool>,
}

impl Row {
    /// The configuration this row measured.
    pub fn config(&self) -> Config {
        let method = |name: &str| {
            if name == Method::Fast.name() {
                Method::Fast
            } else {
                Method::Exact
            }
        };
        Config {
            processor: self.processor,
            recip: method(self.recip),
            sqrt: method(self.sqrt),
            depth: self.depth,
            speedups: Speedups {
                bounding_box: self.bounding_box,
                fast_plane: self.fast_plane,
                shadow_shortcut: self.shadow_shortcut,
            },
            cutoff: self.weight_cutoff,
            opaque_glass: self.opaque_glass,
        }
    }
}

/// [`Method::name`]. (An alias, so that serde's derive does not take the
/// field for text borrowed from the input: [`method_name`] reads it.)
pub type MethodName = &'static str;

/// A method's name read back ([`Method::name`]), refusing any other text.
fn method_name<'de, D: serde::Deserializer<'de>>(d: D) -> Result<&'static str, D::Error> {
    let text = String::deserialize(d)?;
    [Method::Exact, Method::Fast]
        .into_iter()
        .map(Method::name)
        .find(|n| *n == text)
        .ok_or_else(|| serde::de::Error::custom(format!("no method {text:?} (exact, fast)")))
}

/// A configuration the scene refused, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Skipped {
    pub config: Config,
    pub reason: String,
}

/// A scene's sweep.
#[derive(Debug, Clone)]
pub struct SceneSweep {
    /// As the user named it.
    pub name: String,
    pub scene: Scene,
    pub rows: Vec<Row>,
    pub skipped: Vec<Skipped>,
    /// The axis its front is on (and its chart's x).
    pub axis: Axis,
}

impl SceneSweep {
    /// The row of the thesis' configuration, if the grid has it and the
    /// scene accepts it.
    pub fn thesis(&self) -> Option<&Row> {
        self.rows.iter().find(|r| r.config() == Config::thesis())
    }
}

/// Why a sweep cannot run or be written.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error("{scene}: the reference configuration (depth {MAX_DEPTH}): {source}")]
    Reference {
        scene: String,
        #[source]
        source: Box<SceneError>,
    },
    #[error("{scene}: {config}: co-simulation: {source}")]
    Cosim {
        scene: String,
        config: String,
        #[source]
        source: Box<CosimError>,
    },
    #[error("{scene}: {config}: {source}")]
    Config {
        scene: String,
        config: String,
        #[source]
        source: Box<SceneError>,
    },
    #[error("{}: cannot write", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: cannot write the CSV", path.display())]
    Csv {
        path: PathBuf,
        #[source]
        source: csv::Error,
    },
    #[error("{}: cannot draw the chart: {reason}", path.display())]
    Chart { path: PathBuf, reason: String },
    #[error("{scene}: {source}")]
    Cost {
        scene: String,
        #[source]
        source: crate::output::device::CostError,
    },
}

/// Refuses a sweep of `scene` over `grid` before it runs if the cost table
/// cannot price a build the grid needs (every processor and method pair,
/// with the exponential and refraction as the scene needs them), naming the
/// build.
pub fn check_costs(name: &str, scene: &Scene, grid: &Grid) -> Result<(), SweepError> {
    let cost = |source| SweepError::Cost {
        scene: name.into(),
        source,
    };
    let table = crate::output::device::CostTable::builtin_ref().map_err(cost)?;
    for &p in &grid.processors {
        for &r in &grid.recips {
            for &q in &grid.sqrts {
                let build = Build::for_scene(p, r, q, scene);
                table.build_for(build).map_err(|e| cost(e.clone()))?;
            }
        }
    }
    Ok(())
}

/// The f64 reference frame the sweep measures against
/// ([`golden::reference::truth`]: the deepest stack, no cutoff).
pub fn reference_frame(name: &str, scene: &Scene) -> Result<Frame, SweepError> {
    golden::reference::truth(scene, &|_| {}).map_err(|source| SweepError::Reference {
        scene: name.into(),
        source: Box::new(source),
    })
}

/// Renders every configuration of `grid` that `scene` accepts with the
/// micro-op model, in parallel on the current rayon pool, and measures each
/// against `reference` ([`reference_frame`]). `progress` is called once per
/// configuration finished. The rows' Pareto marks are set; the RTL columns
/// are left empty for [`confirm`].
pub fn sweep_scene(
    name: &str,
    scene: &Scene,
    reference: &Frame,
    grid: &Grid,
    clock_hz: f64,
    axis: Axis,
    progress: &(dyn Fn(u64) + Sync),
) -> SceneSweep {
    let results: Vec<Result<Row, Skipped>> = grid
        .configs_for(scene)
        .par_iter()
        .map(|config| {
            let result = measure_config(name, config, scene, reference, clock_hz);
            progress(1);
            result
        })
        .collect();
    SceneSweep::assemble(name, scene, results, axis)
}

impl SceneSweep {
    /// A scene's sweep from its configurations' rows and refusals
    /// ([`measure_config`]), in grid order; marks the rows' Pareto front
    /// on `axis`.
    pub fn assemble(
        name: &str,
        scene: &Scene,
        results: Vec<Result<Row, Skipped>>,
        axis: Axis,
    ) -> Self {
        let (mut rows, mut skipped) = (Vec::new(), Vec::new());
        for result in results {
            match result {
                Ok(row) => rows.push(row),
                Err(s) => skipped.push(s),
            }
        }
        let front = pareto_front(&rows, axis);
        for (row, on) in rows.iter_mut().zip(front) {
            row.pareto = on;
        }
        SceneSweep {
            name: name.into(),
            scene: scene.clone(),
            rows,
            skipped,
            axis,
        }
    }
}

/// One configuration of `scene`: its row (RTL columns empty, not on the
/// front yet), or why the scene refuses it.
pub fn measure_config(
    name: &str,
    config: &Config,
    scene: &Scene,
    reference: &Frame,
    clock_hz: f64,
) -> Result<Row, Skipped> {
    let skip = |reason: String| Skipped {
        config: *config,
        reason,
    };
    let s = config.apply(scene, name).map_err(|e| skip(e.to_string()))?;
    measure(name, config, &s, reference, clock_hz).map_err(|e| skip(e.to_string()))
}

/// The frame cycles of one `processor` for the frame whose pixels did
/// `work` (in row order) and took `stats`: the compact processor's are the
/// sum of its pixels' cycles; the fast one's, its barrel rule's from the
/// first take to the last done turn, plus the cycles from the stream's
/// first coordinate to the first take and from the last done turn to the
/// result (the rule's overhead), as co-simulation checks them.
pub fn frame_cycles(
    processor: ProcessorKind,
    stats: &golden::micro::FrameStats,
    work: &[golden::micro::barrel::PixelWork],
) -> (u64, f64, u64) {
    match processor.row().cycle_rule {
        CycleRule::Micro => (stats.cycles, stats.mean_cycles(), stats.max_cycles),
        CycleRule::Barrel { contexts, overhead } => {
            let run = golden::micro::barrel::run(contexts, work);
            let n = run.pixels.len().max(1) as f64;
            let each: Vec<u64> = run.pixels.iter().map(|p| p.cycles()).collect();
            (
                run.cycles + overhead,
                each.iter().sum::<u64>() as f64 / n,
                each.iter().copied().max().unwrap_or(0),
            )
        }
    }
}

/// One configuration's row (RTL columns empty, not on the front yet), or
/// why the cost table cannot price its build.
fn measure(
    name: &str,
    config: &Config,
    scene: &Scene,
    reference: &Frame,
    clock_hz: f64,
) -> Result<Row, crate::output::device::CostError> {
    let (frame, stats, work) = golden::micro::render_work(scene, &|_| {});
    let (frame_cycles, cycles_per_pixel, max_cycles) =
        self::frame_cycles(config.processor, &stats, &work);
    let on = crate::output::device::CostTable::builtin_ref()?.on_device(
        &crate::output::device::Device::LX760,
        config.build(scene),
        frame_cycles,
    )?;
    let map = DiffMap::new(&frame, reference).expect("the reference has the scene's size");
    let table = map.table("micro", "reference", &[0.0]);
    // Over 0 is every nonzero difference, so their sum is the sum of all.
    let nonzero = &table.rows[0];
    let mean_abs_error =
        nonzero.mean_over.unwrap_or(0.0) * nonzero.over as f64 / table.channels.max(1) as f64;
    let mask = map.mask(VISIBLE);
    let over = mask.pixels().filter(|p| p.0[0] == 0).count();
    Ok(Row {
        scene: name.into(),
        width: scene.camera.width,
        height: scene.camera.height,
        processor: config.processor,
        recip: config.recip.name(),
        sqrt: config.sqrt.name(),
        depth: config.depth,
        bounding_box: config.speedups.bounding_box,
        fast_plane: config.speedups.fast_plane,
        shadow_shortcut: config.speedups.shadow_shortcut,
        weight_cutoff: config.cutoff,
        opaque_glass: config.opaque_glass,
        cycles_per_pixel,
        max_cycles,
        frame_cycles,
        fps_at_clock_mhz: clock_hz / frame_cycles as f64,
        clock_mhz: clock_hz / 1e6,
        device_processors: on.filled.processors,
        device_binding: on.filled.binding.into(),
        device_clock_mhz: on.filled.clock_mhz,
        device_fps: on.frames_per_second,
        luts_per_processor: on.cost.luts,
        dsp_per_processor: on.cost.dsp48e1,
        cost_source: on.cost.source.kind().into(),
        mean_abs_error,
        max_abs_error: table.largest.first().map_or(0.0, |l| l.value),
        share_pixels_over_half: over as f64 / scene.pixel_count() as f64,
        max_ulps: table.max_ulps,
        nan_mismatches: table.nan_mismatches,
        rtl_stack_depth: config.depth,
        rtl_recip_method: config.recip.code(),
        rtl_sqrt_method: config.sqrt.code(),
        pareto: false,
        differs_from_full: None,
        rtl_pixels: None,
        rtl_confirmed: None,
    })
}

/// For each row, whether it is on the Pareto front of (`axis`, best
/// direction: the most device frames per second, or the fewest LUTs or
/// DSPs a processor; mean abs error, minimized): no other row is at least
/// as good on the axis and at most as wrong, and strictly better in one.
/// On an area axis, where every speed-up set of a configuration ties in
/// both, a row equal to another in both is beaten by it if the other has
/// more device frames/s; otherwise rows equal in both are all on it. NaN
/// errors count as worse than any number.
pub fn pareto_front(rows: &[Row], axis: Axis) -> Vec<bool> {
    let key = |r: &Row| {
        let tie = match axis {
            Axis::DeviceFps => 0.0,
            Axis::Luts | Axis::Dsp => r.device_fps,
        };
        (axis.gain(r), r.mean_abs_error, tie)
    };
    rows.iter()
        .map(|r| {
            let (f, e, t) = key(r);
            !rows.iter().any(|o| {
                let (of, oe, ot) = key(o);
                let no_worse = of.total_cmp(&f).is_ge() && oe.total_cmp(&e).is_le();
                let better = of.total_cmp(&f).is_gt()
                    || oe.total_cmp(&e).is_lt()
                    || ot.total_cmp(&t).is_gt();
                no_worse && better
            })
        })
        .collect()
}

/// How the front is checked on the RTL (each row on its own processor).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConfirmOptions {
    /// Random pixels co-simulated besides those that differ from the full
    /// configuration's frame.
    pub sample: u64,
    pub seed: u64,
    pub cosim: CosimOptions,
}

/// The pixels a front configuration is checked on: every pixel where
/// `frame` differs from `full` in any channel's bits, and `sample` pixels
/// drawn from a ChaCha8 stream of `seed` (without repetition); sorted in
/// row order, no duplicates. Also returns how many differ.
pub fn check_pixels(frame: &Frame, full: &Frame, sample: u64, seed: u64) -> (Vec<(u32, u32)>, u64) {
    let w = frame.width as usize;
    let at = |i: usize| ((i % w) as u32, (i / w) as u32);
    let mut picked: Vec<usize> = frame
        .pixels
        .iter()
        .zip(&full.pixels)
        .enumerate()
        .filter(|(_, (a, b))| {
            a.iter()
                .zip(b.iter())
                .any(|(p, q)| p.to_bits() != q.to_bits())
        })
        .map(|(i, _)| i)
        .collect();
    let differing = picked.len() as u64;
    let n = frame.pixels.len();
    let k = usize::try_from(sample).unwrap_or(usize::MAX).min(n);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    picked.extend(rand::seq::index::sample(&mut rng, n, k));
    picked.sort_unstable();
    picked.dedup();
    (picked.into_iter().map(at).collect(), differing)
}

/// A configuration's check on the RTL: the scene as the configuration
/// draws it, the build it is priced as and runs on, the pixels it is
/// checked on ([`check_pixels`]) and how many of them differ from the full
/// configuration's frame.
#[derive(Debug, Clone)]
pub struct RtlCheck {
    pub config: Config,
    pub scene: Scene,
    pub build: Build,
    pub pixels: Vec<(u32, u32)>,
    pub differing: u64,
}

/// The full configuration's frame of `scene` ([`Config::full`]), which
/// [`RtlCheck::plan`] picks the pixels that differ from.
pub fn full_frame(name: &str, scene: &Scene) -> Result<Frame, SweepError> {
    let full = Config::full().apply_named(scene, name)?;
    Ok(golden::micro::render(&full, &|_| {}).0)
}

impl Config {
    /// [`Config::apply`], its refusal named by scene and configuration.
    fn apply_named(&self, scene: &Scene, name: &str) -> Result<Scene, SweepError> {
        self.apply(scene, name)
            .map_err(|source| SweepError::Config {
                scene: name.into(),
                config: self.label(),
                source: Box::new(source),
            })
    }
}

/// Refuses, before anything is measured, a run whose RTL confirmation
/// would need a model this build lacks: the build each of `configs` of each
/// of `scenes` is priced as (and so co-simulated on) must be a design of
/// this build ([`crate::output::device::Build::design`]).
pub fn check_rtl_models(
    configs: &[Config],
    scenes: &[Scene],
) -> Result<(), crate::design::PpError> {
    let table = crate::output::device::CostTable::builtin_ref().ok();
    let mut designs = Vec::new();
    for scene in scenes {
        for config in configs {
            let build = config.build(scene);
            let priced = table
                .and_then(|t| t.build_for(build).ok())
                .map_or(build, |cost| cost.build);
            let design = crate::design::Design::new(priced.processor, priced.recip, priced.sqrt)
                .exp_unit(priced.exposure);
            if !designs.contains(&design) {
                designs.push(design);
            }
        }
    }
    crate::design::Design::check_all(designs)
}

impl RtlCheck {
    /// How `config` of the scene `name` is checked on the RTL: on the
    /// build the cost table prices it as (so that what is co-simulated is
    /// what is priced), on every pixel where its frame differs from `full`
    /// ([`full_frame`]) and `options.sample` more.
    pub fn plan(
        name: &str,
        base: &Scene,
        config: &Config,
        full: &Frame,
        options: &ConfirmOptions,
    ) -> Result<RtlCheck, SweepError> {
        let scene = config.apply_named(base, name)?;
        let build = crate::output::device::CostTable::builtin_ref()
            .and_then(|t| t.build_for(config.build(&scene)))
            .map_err(|source| SweepError::Cost {
                scene: name.into(),
                source,
            })?
            .build;
        let (frame, _) = golden::micro::render(&scene, &|_| {});
        let (pixels, differing) = check_pixels(&frame, full, options.sample, options.seed);
        Ok(RtlCheck {
            config: *config,
            scene,
            build,
            pixels,
            differing,
        })
    }

    /// Co-simulates the check's pixels on its build; `progress` is called
    /// with pixels finished.
    pub fn run(
        &self,
        name: &str,
        options: &ConfirmOptions,
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<CompareReport, SweepError> {
        let design = self.build.design().map_err(|why| SweepError::Cosim {
            scene: name.into(),
            config: self.config.label(),
            source: Box::new(CosimError::Rtl(why)),
        })?;
        cosim::run_pixels(&design, &self.scene, &self.pixels, &options.cosim, progress).map_err(
            |source| SweepError::Cosim {
                scene: name.into(),
                config: self.config.label(),
                source: Box::new(source),
            },
        )
    }
}

/// Co-simulates each front row's configuration on the RTL ([`RtlCheck`])
/// and fills in its RTL columns. `progress` is called with pixels
/// finished; `total` (called first) with the number to come.
pub fn confirm(
    sweep: &mut SceneSweep,
    options: &ConfirmOptions,
    total: &dyn Fn(u64),
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<CompareReport>, SweepError> {
    let full = full_frame(&sweep.name, &sweep.scene)?;
    let mut plans = Vec::new();
    for (i, row) in sweep.rows.iter().enumerate().filter(|(_, r)| r.pareto) {
        let check = RtlCheck::plan(&sweep.name, &sweep.scene, &row.config(), &full, options)?;
        plans.push((i, check));
    }
    total(plans.iter().map(|(_, c)| c.pixels.len() as u64).sum());
    let mut reports = Vec::new();
    for (i, check) in plans {
        let report = check.run(&sweep.name, options, progress)?;
        let row = &mut sweep.rows[i];
        row.differs_from_full = Some(check.differing);
        row.rtl_pixels = Some(report.counts.pixels);
        row.rtl_confirmed = Some(report.passed());
        reports.push(report);
    }
    Ok(reports)
}

/// Writes `rows` as CSV to `path`: a header of the [`Row`] field names,
/// one row per scene and configuration; empty cells for the RTL columns of
/// rows off the front.
pub fn write_csv(path: &Path, rows: &[Row]) -> Result<(), SweepError> {
    let err = |source| SweepError::Csv {
        path: path.to_path_buf(),
        source,
    };
    let mut out = csv::Writer::from_path(path).map_err(err)?;
    for row in rows {
        out.serialize(row).map_err(err)?;
    }
    out.flush().map_err(|source| SweepError::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// The JSON document of a sweep: the settings, the skipped configurations
/// and the rows.
#[derive(Debug, Serialize)]
struct Document<'a> {
    /// The clock of every row's `fps_at_clock_mhz`, and where it comes from.
    clock_mhz: f64,
    clock_source: &'static str,
    /// Whether the front was co-simulated (each row on its processor).
    rtl: bool,
    /// The device of the `device_*` columns, and the cost table's tools.
    device: &'static str,
    yosys: String,
    reference_depth: u32,
    visible_threshold: f64,
    scenes: Vec<SceneDocument<'a>>,
}

#[derive(Debug, Serialize)]
struct SceneDocument<'a> {
    scene: &'a str,
    /// The axis of its front (`pareto`).
    axis: Axis,
    configurations: usize,
    skipped: Vec<SkippedDocument>,
    rows: &'a [Row],
}

#[derive(Debug, Serialize)]
struct SkippedDocument {
    config: String,
    reason: String,
}

/// Writes the sweeps as JSON to `path`.
pub fn write_json(
    path: &Path,
    sweeps: &[SceneSweep],
    clock_hz: f64,
    rtl: bool,
) -> Result<(), SweepError> {
    let doc = Document {
        clock_mhz: clock_hz / 1e6,
        clock_source: clock_source(clock_hz / 1e6),
        rtl,
        device: crate::output::device::Device::LX760.name,
        yosys: crate::output::device::CostTable::builtin_ref()
            .map(|t| t.yosys.clone())
            .unwrap_or_default(),
        reference_depth: MAX_DEPTH,
        visible_threshold: VISIBLE,
        scenes: sweeps
            .iter()
            .map(|s| SceneDocument {
                scene: &s.name,
                axis: s.axis,
                configurations: s.rows.len() + s.skipped.len(),
                skipped: s
                    .skipped
                    .iter()
                    .map(|k| SkippedDocument {
                        config: k.config.label(),
                        reason: k.reason.clone(),
                    })
                    .collect(),
                rows: &s.rows,
            })
            .collect(),
    };
    let text = serde_json::to_string_pretty(&doc).expect("rows are plain numbers and strings");
    std::fs::write(path, text + "\n").map_err(|source| SweepError::Write {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_per_second_say_their_clock_and_where_it_comes_from() {
        assert_eq!(fps_header(8.94), "frames/s at 8.94 MHz");
        assert_eq!(fps_header(34.74), "frames/s at 34.74 MHz");
        // The constants as the command line spells them (MHz).
        assert_eq!(fps_header(ECP5_CLOCK_HZ / 1e6), "frames/s at 8.94 MHz");
        assert_eq!(fps_header(THESIS_CLOCK_HZ / 1e6), "frames/s at 34.74 MHz");
        assert!(clock_source(8.94).contains("post-route clock on ECP5"));
        assert!(clock_source(34.74).contains("does not reach"));
        assert_eq!(clock_source(50.0), "given with --clock-mhz");
    }
}
