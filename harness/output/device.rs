//! What a build of the pixel processor costs in hardware, and how fast a
//! device filled with it draws a frame: the speed axis in hardware units.
//!
//! - [`Build`]: one distinct RTL build: the processor, the reciprocal's and
//!   the square root's methods, `STACK_DEPTH`, whether the fast processor
//!   has its exponential (the compact one always has), and whether the
//!   processor traces refraction.
//! - [`CostTable`]: each build's Virtex-6 resources and clock estimate, as
//!   `rtl/synth/costs.toml` records them (the committed results of
//!   synthesizing builds once: `rtl/synth/synth.sh xc6v ...` counted by
//!   `rtl/synth/report.py`, docs/rtl.md's method). Every entry says whether
//!   it was measured (with the command) or interpolated (with how);
//!   [`CostTable::cost`] refuses a build the table does not hold, by name.
//! - [`Device`]: a device's resources; [`Device::fill`]: how many processors
//!   of a cost fit and which resource binds; [`Filled::frames_per_second`]:
//!   the frames a second of the device filled with them at the build's
//!   clock, the frame split evenly between the processors.
//!
//! The top's own logic around the processors (`rtl/top.v`: the dispatcher
//! and the arbiter, about 1% of a device of fast processors, docs/rtl.md)
//! is left out of the fill, and the even split leaves out the top's
//! dispatch (1.6% over it for 34 fast processors on the reference frame:
//! `golden::micro::barrel::run_top`).

use crate::design::processor::ProcessorKind;
use crate::design::{Design, PpError};
use golden::fp::Method;
use golden::scene::Scene;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The committed cost table (`rtl/synth/costs.toml`).
pub const COSTS_TOML: &str = include_str!("../../rtl/synth/costs.toml");

/// One distinct RTL build of a pixel processor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Build {
    pub processor: ProcessorKind,
    #[serde(with = "method")]
    pub recip: Method,
    #[serde(with = "method")]
    pub sqrt: Method,
    /// `STACK_DEPTH`: ray-stack levels the register file holds.
    pub stack_depth: u32,
    /// Whether the exponential is built (`EXPOSURE`; always for compact).
    pub exposure: bool,
    /// Whether refraction is built (`REFRACTION`): transparent spheres.
    pub refraction: bool,
}

impl fmt::Display for Build {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} processor, recip {}, sqrt {}, STACK_DEPTH {}, {}, {}",
            self.processor,
            self.recip,
            self.sqrt,
            self.stack_depth,
            if self.exposure {
                "with the exponential"
            } else {
                "without the exponential"
            },
            if self.refraction {
                "with refraction"
            } else {
                "without refraction"
            }
        )
    }
}

impl Build {
    /// Its instance line in Verilog: the processor's module and the
    /// parameters that make this build.
    pub fn instance(&self) -> String {
        let method = |m: Method| match m {
            Method::Exact => "`FP_METHOD_EXACT",
            Method::Fast => "`FP_METHOD_FAST",
        };
        let (recip, sqrt, depth) = (method(self.recip), method(self.sqrt), self.stack_depth);
        let row = self.processor.row();
        let exposure = if row.exp_optional {
            format!(", .EXPOSURE({})", u8::from(self.exposure))
        } else {
            String::new()
        };
        format!(
            "{} #(.RECIP_METHOD({recip}), .SQRT_METHOD({sqrt}), .STACK_DEPTH({depth}){exposure}, \
             .REFRACTION({}))",
            row.models.module(),
            u8::from(self.refraction)
        )
    }

    /// The design under test that co-simulates this build: refused unless
    /// the harness verilates it (`STACK_DEPTH` [`BUILT_STACK_DEPTH`], and
    /// the model in this build). The models are verilated with refraction:
    /// a build without it runs scenes without glass only
    /// ([`Build::for_scene`]), on which it is the build with refraction
    /// state for state (its transparency bits are 0, so neither enters a
    /// refraction state), and is co-simulated as that one; tests/icarus.rs
    /// runs the build without refraction itself against golden.
    pub fn design(&self) -> Result<Design, PpError> {
        let design = Design::new(self.processor, self.recip, self.sqrt).exp_unit(self.exposure);
        if self.stack_depth != BUILT_STACK_DEPTH {
            return Err(PpError::NotBuilt {
                design: design.to_string(),
                why: format!("the models are verilated with STACK_DEPTH {BUILT_STACK_DEPTH} only"),
            });
        }
        design.check()?;
        Ok(design)
    }
}

/// Methods by their names in the table, `exact` or `fast`.
mod method {
    use golden::fp::Method;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(m: &Method, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(m.name())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Method, D::Error> {
        let name = String::deserialize(d)?;
        Method::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                serde::de::Error::custom(format!("method '{name}' is neither exact nor fast"))
            })
    }
}

/// A build's resources on Virtex-6 and its clock.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cost {
    #[serde(flatten)]
    pub build: Build,
    /// Slice LUTs, of which `lut_memory` are LUT RAM or shift registers.
    pub luts: u32,
    pub lut_memory: u32,
    pub flip_flops: u32,
    pub dsp48e1: u32,
    /// 36 Kb block RAMs (a RAMB18 counts a half).
    pub bram36: f64,
    /// The Virtex-6 clock estimate at 0.8 ns a net (`report.py`).
    pub fmax_mhz: f64,
    /// The clock after place and route on ECP5, where measured.
    pub ecp5_mhz: Option<f64>,
    /// How the figures were obtained.
    pub source: Source,
}

/// Where a cost's figures come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Source {
    /// Synthesized: the command that reproduces them.
    Measured(String),
    /// Derived from measured builds: how.
    Interpolated(String),
}

impl Source {
    /// `measured` or `interpolated`.
    pub fn kind(&self) -> &'static str {
        match self {
            Source::Measured(_) => "measured",
            Source::Interpolated(_) => "interpolated",
        }
    }
}

/// The table: the tools, and a cost per build.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostTable {
    /// The synthesis tool's version (`yosys -V`).
    pub yosys: String,
    /// The place-and-route tool's, for the ECP5 clocks.
    pub nextpnr: String,
    #[serde(rename = "build")]
    pub costs: Vec<Cost>,
}

/// Why a cost table cannot be read or does not answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CostError {
    #[error("rtl/synth/costs.toml: {0}")]
    Parse(String),
    #[error("rtl/synth/costs.toml lists {0} twice")]
    Duplicate(Build),
    #[error("rtl/synth/costs.toml: {build}: {what}")]
    Invalid { build: Build, what: String },
    #[error(
        "no cost for the {0}: rtl/synth/costs.toml holds the builds synthesized so far \
         (docs/rtl.md, \"Cost table\")"
    )]
    Missing(Build),
}

impl CostTable {
    /// The committed table.
    pub fn builtin() -> Result<CostTable, CostError> {
        CostTable::parse(COSTS_TOML)
    }

    /// The committed table, parsed once per process.
    pub fn builtin_ref() -> Result<&'static CostTable, CostError> {
        static TABLE: std::sync::OnceLock<Result<CostTable, CostError>> =
            std::sync::OnceLock::new();
        TABLE
            .get_or_init(CostTable::builtin)
            .as_ref()
            .map_err(Clone::clone)
    }

    /// A table from its TOML text, checked: each build once, every figure
    /// positive and finite.
    pub fn parse(text: &str) -> Result<CostTable, CostError> {
        let table: CostTable = toml::from_str(text).map_err(|e| CostError::Parse(e.to_string()))?;
        for (i, c) in table.costs.iter().enumerate() {
            if table.costs[..i].iter().any(|d| d.build == c.build) {
                return Err(CostError::Duplicate(c.build));
            }
            let invalid = |what: &str| CostError::Invalid {
                build: c.build,
                what: what.to_string(),
            };
            if let Some(why) = Design::new(c.build.processor, c.build.recip, c.build.sqrt)
                .exp_unit(c.build.exposure)
                .exp_unit_refusal()
            {
                return Err(invalid(&why));
            }
            if c.luts == 0 || c.flip_flops == 0 || c.lut_memory > c.luts {
                return Err(invalid(
                    "LUTs and flip-flops must be positive, LUT memory within the LUTs",
                ));
            }
            let finite = |x: f64| x.is_finite() && x > 0.0;
            if !finite(c.fmax_mhz)
                || c.ecp5_mhz.is_some_and(|f| !finite(f))
                || !(c.bram36.is_finite() && c.bram36 >= 0.0)
            {
                return Err(invalid("clocks must be positive, block RAM not negative"));
            }
        }
        Ok(table)
    }

    /// The cost of `build`.
    pub fn cost(&self, build: Build) -> Result<&Cost, CostError> {
        self.costs
            .iter()
            .find(|c| c.build == build)
            .ok_or(CostError::Missing(build))
    }
}

/// The `STACK_DEPTH` of every build the table holds and the harness
/// verilates: the RTL's default (`ISA_DIM_STK_COUNT`). A configuration of
/// a smaller depth runs on it (the scene's `max_depth` limits the stack a
/// pixel uses), and is costed as it.
pub const BUILT_STACK_DEPTH: u32 = 8;

/// A configuration on a device: the build it runs on, what that costs, the
/// device filled with it, and its frames a second.
#[derive(Debug, Clone, PartialEq)]
pub struct OnDevice {
    pub cost: Cost,
    pub filled: Filled,
    pub frames_per_second: f64,
}

impl Build {
    /// The build a configuration of `processor` with `recip` and `sqrt`
    /// runs `scene` on: [`BUILT_STACK_DEPTH`], the exponential if the scene
    /// has exposure, refraction if it has a transparent sphere.
    pub fn for_scene(
        processor: ProcessorKind,
        recip: Method,
        sqrt: Method,
        scene: &Scene,
    ) -> Build {
        Build {
            processor,
            recip,
            sqrt,
            stack_depth: BUILT_STACK_DEPTH,
            exposure: scene.render.exposure.is_some(),
            refraction: scene.refracts(),
        }
    }
}

impl CostTable {
    /// The cost of `want`, or for a build without the exponential or
    /// without refraction that the table does not hold, of the same build
    /// with them, the exponential added first (the compact processor
    /// always has the exponential; the other pairs are not synthesized
    /// without it or without refraction).
    pub fn build_for(&self, want: Build) -> Result<&Cost, CostError> {
        let candidates = [
            want,
            Build {
                exposure: true,
                ..want
            },
            Build {
                refraction: true,
                ..want
            },
            Build {
                exposure: true,
                refraction: true,
                ..want
            },
        ];
        candidates
            .iter()
            .find_map(|&b| self.cost(b).ok())
            .ok_or(CostError::Missing(want))
    }

    /// [`CostTable::build_for`] on `device`, filled, drawing a frame that
    /// one processor takes `frame_cycles` for.
    pub fn on_device(
        &self,
        device: &Device,
        want: Build,
        frame_cycles: u64,
    ) -> Result<OnDevice, CostError> {
        let cost = self.build_for(want)?;
        let filled = device.fill(cost);
        Ok(OnDevice {
            cost: cost.clone(),
            filled,
            frames_per_second: filled.frames_per_second(frame_cycles),
        })
    }
}

/// A device's resources.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Device {
    pub name: &'static str,
    pub luts: u32,
    /// LUTs that can be memory (SLICEM).
    pub lut_memory: u32,
    pub flip_flops: u32,
    pub dsp48e1: u32,
    pub bram36: u32,
}

impl Device {
    /// The thesis' FPGA, Virtex-6 XC6VLX760 (DS150): 118,560 slices of 4
    /// LUTs and 8 flip-flops, 8,280 Kb of distributed RAM (132,480 LUTs of
    /// 64 bits), 864 DSP48E1, 720 block RAMs of 36 Kb.
    pub const LX760: Device = Device {
        name: "Virtex-6 LX760",
        luts: 474_240,
        lut_memory: 132_480,
        flip_flops: 948_480,
        dsp48e1: 864,
        bram36: 720,
    };

    /// How many processors of `cost` fit, and the resource that binds.
    pub fn fill(&self, cost: &Cost) -> Filled {
        let fits = |have: f64, need: f64| {
            if need > 0.0 {
                (have / need).floor() as u32
            } else {
                u32::MAX
            }
        };
        let by = [
            (fits(self.luts.into(), cost.luts.into()), "LUTs"),
            (
                fits(self.lut_memory.into(), cost.lut_memory.into()),
                "LUT memory",
            ),
            (
                fits(self.flip_flops.into(), cost.flip_flops.into()),
                "flip-flops",
            ),
            (fits(self.dsp48e1.into(), cost.dsp48e1.into()), "DSP48E1"),
            (fits(self.bram36.into(), cost.bram36), "block RAM"),
        ];
        let (processors, binding) = by
            .into_iter()
            .min_by_key(|(n, _)| *n)
            .expect("five resources");
        Filled {
            processors,
            binding,
            clock_mhz: cost.fmax_mhz,
        }
    }
}

/// A device filled with processors of one build.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Filled {
    pub processors: u32,
    /// The resource that ran out first.
    pub binding: &'static str,
    /// The build's clock estimate.
    pub clock_mhz: f64,
}

impl Filled {
    /// Frames a second when one processor takes `frame_cycles` for the
    /// frame and the processors split it evenly.
    pub fn frames_per_second(&self, frame_cycles: u64) -> f64 {
        self.clock_mhz * 1e6 * f64::from(self.processors) / frame_cycles.max(1) as f64
    }
}
