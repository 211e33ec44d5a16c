//! [`Design`]: one verilated build of a processor, what no build makes
//! ([`Design::refusal`]), and what this build lacks ([`Design::check`]).

use crate::design::built::{how_to_build, BUILT};
use crate::design::counts;
use crate::design::error::{PpError, SlotLayout};
use crate::design::models::{self, Flavour};
use crate::design::processor::{Driver, Processor, ProcessorKind};
use golden::fp::Method;
use golden::scene::Scene;
use std::fmt;
use std::path::PathBuf;

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

    /// Cycles a pixel may take before the RTL counts as hung, unless told
    /// otherwise: its processor's [`Processor::default_timeout_cycles`].
    pub fn default_timeout_cycles(&self) -> u64 {
        self.row().default_timeout_cycles()
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
                return Some(format!(
                    "the tops are built plain only, not as {} models",
                    self.flavour.name()
                ));
            }
        }
        if self.flavour.is_yosys_netlist()
            && (self.recip, self.sqrt) != (Method::Exact, Method::Exact)
        {
            return Some(format!(
                "{} models are made with the exact methods only",
                self.flavour.name()
            ));
        }
        // A top of any N is made when asked for by name ([`Design::check`]).
        if self.procs.is_none() && !BUILT.iter().any(|(class, _, _)| *class == self.class()) {
            return Some(format!(
                "no {} model of the {} processor is made",
                self.flavour.name(),
                row.name
            ));
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
        Design::check_all([*self])
    }

    /// [`Design::check`] on every design of `designs`: the first refusal of
    /// a design no build makes, or, for those this build lacks, one error
    /// naming the first and every cargo feature they need together.
    pub fn check_all(designs: impl IntoIterator<Item = Design>) -> Result<(), PpError> {
        let mut lacking: Vec<Design> = Vec::new();
        let mut features: Vec<&str> = Vec::new();
        for design in designs {
            if let Some(why) = design.refusal() {
                return Err(PpError::NotBuilt {
                    design: design.to_string(),
                    why,
                });
            }
            match BUILT.iter().find(|(c, _, _)| *c == design.class()) {
                Some((_, _, true)) => {}
                Some((_, needs, false)) => {
                    lacking.push(design);
                    features.extend(needs.iter().copied());
                }
                // A top of an N not in the table: asked for by name at
                // build time.
                None => {
                    return Err(PpError::NotBuilt {
                        design: design.to_string(),
                        why: format!(
                            "build it by name: RTCOSIM_TOPS={}{}:{}:{} cargo build --release",
                            if design.row().contexts > 1 {
                                "fast:"
                            } else {
                                ""
                            },
                            design.procs.unwrap_or(1),
                            design.recip,
                            design.sqrt
                        ),
                    })
                }
            }
        }
        features.sort_unstable();
        features.dedup();
        match lacking.first() {
            None => Ok(()),
            Some(first) => Err(PpError::NotBuilt {
                design: match lacking.len() {
                    1 => first.to_string(),
                    n => format!(
                        "{first} and {} other design{}",
                        n - 1,
                        if n == 2 { "" } else { "s" }
                    ),
                },
                why: how_to_build(&features),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::built::require;
    use crate::design::models::FULL;
    use golden::fp::Method::{Exact, Fast};

    /// Every design a command can name is one row of the table, or one
    /// refusal: the table, the class names and the refusals agree.
    #[test]
    fn every_design_is_a_row_of_the_table_or_refused() {
        let mut rows = 0;
        for processor in ProcessorKind::ALL {
            for flavour in Flavour::ALL {
                for (recip, sqrt) in [(Exact, Exact), (Exact, Fast), (Fast, Exact), (Fast, Fast)] {
                    for exp_unit in [true, false] {
                        let d = Design::new(processor, recip, sqrt)
                            .exp_unit(exp_unit)
                            .flavour(flavour);
                        let in_table = BUILT.iter().any(|(c, _, _)| *c == d.class());
                        assert_eq!(d.refusal().is_none(), in_table, "{d}: {:?}", d.refusal());
                        rows += usize::from(in_table);
                    }
                }
            }
        }
        // Compact: 4 pairs x (plain, wave, coverage) + mutant + synth; fast:
        // 5 variants x (plain, wave, coverage) + mutant.
        assert_eq!(rows, 14 + 16);
        let classes: Vec<&str> = BUILT.iter().map(|(c, _, _)| *c).collect();
        let mut unique = classes.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), classes.len(), "a class twice in the table");
    }

    /// The table, the C++ drivers' lists and the harness agree: every
    /// design this build made opens (the bridge finds its class), and
    /// every float unit this build made builds.
    #[test]
    fn every_built_design_opens() {
        let mut opened = 0;
        for processor in ProcessorKind::ALL {
            for flavour in [Flavour::Plain, Flavour::Wave] {
                for (recip, sqrt) in [(Exact, Exact), (Exact, Fast), (Fast, Exact), (Fast, Fast)] {
                    for exp_unit in [true, false] {
                        let d = Design::new(processor, recip, sqrt)
                            .exp_unit(exp_unit)
                            .flavour(flavour);
                        if d.check().is_ok() {
                            d.open().unwrap_or_else(|e| panic!("{d}: {e}"));
                            opened += 1;
                        }
                    }
                }
            }
            let top = Design::new(processor, Exact, Exact).procs(Some(2));
            for d in [top, top.procs(Some(1)), top.procs(Some(4))] {
                if d.check().is_ok() {
                    d.open().unwrap_or_else(|e| panic!("{d}: {e}"));
                    opened += 1;
                }
            }
        }
        assert!(opened >= 1, "the default build's design opens");
        if cfg!(feature = "full") {
            // 8 + 10 alone and their waveform twins, 3 tops.
            assert_eq!(opened, 21);
        }
        for kind in crate::design::fp_unit::UnitKind::every() {
            if require(&kind.class()).is_ok() {
                crate::design::fp_unit::FpUnit::new(kind).unwrap_or_else(|e| panic!("{e}"));
            }
        }
    }

    /// What no build makes is refused, each for its reason.
    #[test]
    fn the_refusals_say_why() {
        let compact = Design::compact(Exact, Exact);
        let fast = Design::fast(Exact, Exact);
        let cases = [
            (compact.exp_unit(false), "always has its exponential"),
            (compact.procs(Some(9)), "has 1 to 8 of them"),
            (fast.procs(Some(65)), "has 1 to 64 of them"),
            (
                fast.procs(Some(2)).exp_unit(false),
                "with the exponential only",
            ),
            (compact.procs(Some(4)).flavour(Flavour::Wave), "plain only"),
            (
                Design::compact(Fast, Exact).flavour(Flavour::Mutant),
                "exact methods only",
            ),
            (fast.flavour(Flavour::Synth), "no synthesized netlist model"),
        ];
        for (design, why) in cases {
            let refusal = design
                .refusal()
                .unwrap_or_else(|| panic!("{design} is not refused"));
            assert!(refusal.contains(why), "{design}: {refusal}");
            let err = design.check().expect_err("refused").to_string();
            assert!(err.contains(why), "{err}");
        }
        // A top of an N outside the table is made by name.
        let e = compact
            .procs(Some(3))
            .check()
            .expect_err("not built")
            .to_string();
        assert!(
            e.contains("RTCOSIM_TOPS=3:exact:exact cargo build --release"),
            "{e}"
        );
    }

    /// Designs this build lacks are refused together, with every cargo
    /// feature they need; the default build's own design never is.
    #[test]
    fn lacking_designs_name_every_feature_they_need() {
        let exact = Design::compact(Exact, Exact);
        assert!(exact.check().is_ok(), "the default build's design");
        let flavours = [Flavour::Coverage, Flavour::Mutant, Flavour::Synth];
        let lacking: Vec<Design> = flavours
            .iter()
            .map(|&f| exact.flavour(f))
            .filter(|d| d.check().is_err())
            .collect();
        let mut want: Vec<&str> = lacking.iter().filter_map(|d| d.flavour.feature()).collect();
        want.sort_unstable();
        match Design::check_all(flavours.iter().map(|&f| exact.flavour(f))) {
            Ok(()) => assert!(lacking.is_empty()),
            Err(e) => {
                let e = e.to_string();
                assert!(e.contains(&format!("--features {}", want.join(","))), "{e}");
                assert!(e.starts_with(&lacking[0].to_string()), "{e}");
            }
        }
        // The features `full` turns on make every plain and waveform model.
        for (class, features, built) in BUILT {
            if features.iter().all(|f| FULL.contains(f)) && cfg!(feature = "full") {
                assert!(built, "{class} needs only {features:?} but is not built");
            }
        }
    }
}
