//! The verilated models: one table, read by the build script (which
//! verilates and compiles the rows whose cargo features are on, and lists
//! them for the C++ drivers) and by the harness (which names the row a
//! design needs and, when this build lacks it, the feature that builds
//! it). Plain Rust with no dependencies: `build/main.rs` includes this file
//! as a module of its own.
//!
//! A row's class is the prefix Verilator gives its generated C++
//! (`V<module>...`); the C++ drivers find a model by that name.

/// What a model is verilated for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Flavour {
    /// The co-simulation models.
    Plain,
    /// With `--trace-fst`: the waveform window's twin of a plain model.
    Wave,
    /// With Verilator's line, toggle and user coverage and the
    /// controller's cover points (`PP_COVER`).
    Coverage,
    /// Yosys' netlist with every listed mutant behind `mutsel`.
    Mutant,
    /// Yosys' generic synthesis (gates and flip-flops).
    Synth,
}

impl Flavour {
    /// Every flavour, plain first.
    pub const ALL: [Flavour; 5] = [
        Flavour::Plain,
        Flavour::Wave,
        Flavour::Coverage,
        Flavour::Mutant,
        Flavour::Synth,
    ];

    /// Its part of a class name (`Vpixel_processor_wave_exact_exact`).
    pub fn suffix(self) -> &'static str {
        match self {
            Flavour::Plain => "",
            Flavour::Wave => "_wave",
            Flavour::Coverage => "_cov",
            Flavour::Mutant => "_mut",
            Flavour::Synth => "_synth",
        }
    }

    /// Its name in reports and errors.
    pub fn name(self) -> &'static str {
        match self {
            Flavour::Plain => "plain",
            Flavour::Wave => "waveform",
            Flavour::Coverage => "coverage",
            Flavour::Mutant => "mutant",
            Flavour::Synth => "synthesized netlist",
        }
    }

    /// The cargo feature that builds models of this flavour, if any.
    pub fn feature(self) -> Option<&'static str> {
        match self {
            Flavour::Plain => None,
            Flavour::Wave => Some("waves"),
            Flavour::Coverage => Some("coverage"),
            Flavour::Mutant => Some("mutation"),
            Flavour::Synth => Some("synth-netlist"),
        }
    }

    /// Verilated from a netlist Yosys wrote, elaborated there: defines,
    /// parameters and methods are in; the exact pair only.
    pub fn is_yosys_netlist(self) -> bool {
        matches!(self, Flavour::Mutant | Flavour::Synth)
    }
}

/// The two processors' RTL as the build knows them: the top module and
/// the class name's base. (The harness's rows of facts are
/// `design::processor`.)
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rtl {
    /// `rtl/pp/pixel_processor.v`.
    Compact,
    /// `rtl/fast/fast_pp.v`.
    Fast,
}

impl Rtl {
    /// The processor's top module.
    pub fn module(self) -> &'static str {
        match self {
            Rtl::Compact => "pixel_processor",
            Rtl::Fast => "fast_pp",
        }
    }

    /// The cargo feature its models need beyond the default build.
    fn feature(self) -> Option<&'static str> {
        match self {
            Rtl::Compact => None,
            Rtl::Fast => Some("fast"),
        }
    }
}

/// The top of `rtl/top.v` with N processors of one kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TopShape {
    pub procs: u32,
    /// `ARB_GROUP`: processors per result group (1 for compact ones).
    pub group: u32,
}

/// What one model is.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum What {
    /// A float unit alone: its module and its `METHOD`, if it has one.
    Unit {
        module: &'static str,
        method: Option<String>,
    },
    /// A float unit cut from a processor's mutant netlist, which is built
    /// with the exact methods: `method` is `exact` for a unit that has
    /// methods, None for one that has none.
    MutantUnit {
        module: &'static str,
        method: Option<&'static str>,
    },
    /// The fast processor's ALU (`rtl/fast/fast_alu.v`).
    FastAlu {
        recip: String,
        sqrt: String,
        exposure: bool,
    },
    /// A pixel processor alone (`top` None) or N of them in `rtl/top.v`.
    Processor {
        rtl: Rtl,
        recip: String,
        sqrt: String,
        exposure: bool,
        top: Option<TopShape>,
    },
}

/// One row of the table.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Model {
    /// Verilator's `--prefix`: the generated class.
    pub class: String,
    pub what: What,
    pub flavour: Flavour,
    /// The cargo features that must all be on for the default build to
    /// make it (none: always built).
    pub features: Vec<&'static str>,
}

/// The class of a processor model (`what`'s [`What::Processor`] fields).
pub fn processor_class(
    rtl: Rtl,
    flavour: Flavour,
    recip: &str,
    sqrt: &str,
    exposure: bool,
    top: Option<TopShape>,
) -> String {
    match top {
        Some(t) => {
            let kind = match rtl {
                Rtl::Compact => "",
                Rtl::Fast => "fast_",
            };
            format!("Vtop_{kind}{}_{recip}_{sqrt}", t.procs)
        }
        None => {
            let noexp = if exposure { "" } else { "_noexp" };
            format!(
                "V{}{}_{recip}_{sqrt}{noexp}",
                rtl.module(),
                flavour.suffix()
            )
        }
    }
}

/// The class of a float unit alone (`fp_recip` with `exact`:
/// `Vfp_recip_exact`).
pub fn unit_class(module: &str, method: Option<&str>) -> String {
    match method {
        Some(m) => format!("V{module}_{m}"),
        None => format!("V{module}"),
    }
}

/// The class of a float unit cut from a mutant netlist.
pub fn mutant_unit_class(module: &str) -> String {
    format!("V{module}_mut")
}

/// The class of the fast ALU.
pub fn fast_alu_class(recip: &str, sqrt: &str, exposure: bool) -> String {
    let noexp = if exposure { "" } else { "_noexp" };
    format!("Vfast_alu_{recip}_{sqrt}{noexp}")
}

/// The float units of each processor: (module, has a METHOD), the compact
/// processor's in `rtl/fp`, the fast one's in `rtl/fast`.
pub const UNITS: [(Rtl, [(&str, bool); 6]); 2] = [
    (
        Rtl::Compact,
        [
            ("fp_add", false),
            ("fp_mul", false),
            ("fp_itof", false),
            ("fp_exp", false),
            ("fp_recip", true),
            ("fp_sqrt", true),
        ],
    ),
    (
        Rtl::Fast,
        [
            ("fast_fp_add", false),
            ("fast_fp_mul", false),
            ("fast_fp_itof", false),
            ("fast_fp_exp", false),
            ("fast_fp_recip", true),
            ("fast_fp_sqrt", true),
        ],
    ),
];

/// The exact method pair: the only one the Yosys netlists are made with,
/// and the one the default build verilates.
pub const EXACT: &str = "exact";

/// The tops every build with the feature `tops` verilates: (processor, N,
/// ARB_GROUP), exact methods. The top of 2 fast processors puts each in a
/// group of its own, so the tests see both the groups' registers and the
/// arbiter over them.
pub const TOPS: [(Rtl, u32, u32); 3] = [
    (Rtl::Compact, 1, 1),
    (Rtl::Compact, 4, 1),
    (Rtl::Fast, 2, 1),
];

/// `ARB_GROUP` of the tops of fast processors asked for by name
/// (`RTCOSIM_TOPS`): the RTL's default.
pub const FAST_TOP_GROUP: u32 = 6;

/// The largest N of a top: compact processors, fast ones.
pub const MAX_TOP_N: (u32, u32) = (8, 64);

/// Every model the project can verilate, given the method names of
/// `rtl/fp/fp_defs.vh` and the extra tops asked for by name
/// (`RTCOSIM_TOPS`: processor, N, recip, sqrt; built whatever the
/// features).
pub fn table(methods: &[&str], extra_tops: &[(Rtl, u32, String, String)]) -> Vec<Model> {
    let mut rows = Vec::new();
    // A model with methods other than the exact pair needs `methods`.
    let methods_feature = |recip: &str, sqrt: &str| -> Option<&'static str> {
        ((recip, sqrt) != (EXACT, EXACT)).then_some("methods")
    };
    let needs = |parts: &[Option<&'static str>]| -> Vec<&'static str> {
        let mut f: Vec<&'static str> = parts.iter().flatten().copied().collect();
        f.sort_unstable();
        f.dedup();
        f
    };
    // The float units alone (every method: they are small).
    for (rtl, units) in UNITS {
        for (module, has_method) in units {
            let unit_methods: Vec<Option<&str>> = if has_method {
                methods.iter().map(|m| Some(*m)).collect()
            } else {
                vec![None]
            };
            for method in unit_methods {
                rows.push(Model {
                    class: unit_class(module, method),
                    what: What::Unit {
                        module,
                        method: method.map(str::to_string),
                    },
                    flavour: Flavour::Plain,
                    features: needs(&[rtl.feature()]),
                });
            }
            rows.push(Model {
                class: mutant_unit_class(module),
                what: What::MutantUnit {
                    module,
                    method: has_method.then_some(EXACT),
                },
                flavour: Flavour::Mutant,
                features: needs(&[Flavour::Mutant.feature()]),
            });
        }
    }
    // The fast ALU: the variants tests/fast_alu.rs co-simulates.
    for (recip, sqrt, exposure) in [
        (EXACT, EXACT, true),
        ("fast", "fast", true),
        (EXACT, EXACT, false),
    ] {
        if !methods.contains(&recip) {
            continue;
        }
        rows.push(Model {
            class: fast_alu_class(recip, sqrt, exposure),
            what: What::FastAlu {
                recip: recip.into(),
                sqrt: sqrt.into(),
                exposure,
            },
            flavour: Flavour::Plain,
            features: needs(&[Rtl::Fast.feature(), methods_feature(recip, sqrt)]),
        });
    }
    // The processors alone: every method pair, every flavour; the fast one
    // also without its exponential (exact pair; not as a netlist).
    for rtl in [Rtl::Compact, Rtl::Fast] {
        for flavour in Flavour::ALL {
            if rtl == Rtl::Fast && flavour == Flavour::Synth {
                continue;
            }
            for &recip in methods {
                for &sqrt in methods {
                    if flavour.is_yosys_netlist() && (recip, sqrt) != (EXACT, EXACT) {
                        continue;
                    }
                    let mut variants = vec![true];
                    if rtl == Rtl::Fast
                        && (recip, sqrt) == (EXACT, EXACT)
                        && !flavour.is_yosys_netlist()
                    {
                        variants.push(false);
                    }
                    for exposure in variants {
                        rows.push(Model {
                            class: processor_class(rtl, flavour, recip, sqrt, exposure, None),
                            what: What::Processor {
                                rtl,
                                recip: recip.into(),
                                sqrt: sqrt.into(),
                                exposure,
                                top: None,
                            },
                            flavour,
                            features: needs(&[
                                rtl.feature(),
                                flavour.feature(),
                                methods_feature(recip, sqrt),
                            ]),
                        });
                    }
                }
            }
        }
    }
    // The tops: the standard ones (`tops`), then the ones asked for.
    let standard = TOPS
        .iter()
        .map(|&(rtl, n, group)| (rtl, n, EXACT.to_string(), EXACT.to_string(), group, true));
    let asked = extra_tops.iter().map(|(rtl, n, r, s)| {
        let group = match rtl {
            Rtl::Compact => 1,
            Rtl::Fast => FAST_TOP_GROUP,
        };
        (*rtl, *n, r.clone(), s.clone(), group, false)
    });
    for (rtl, procs, recip, sqrt, group, standard) in standard.chain(asked) {
        let top = Some(TopShape { procs, group });
        let class = processor_class(rtl, Flavour::Plain, &recip, &sqrt, true, top);
        if rows.iter().any(|m| m.class == class) {
            continue;
        }
        let features = if standard {
            needs(&[Some("tops"), rtl.feature()])
        } else {
            Vec::new()
        };
        rows.push(Model {
            class,
            what: What::Processor {
                rtl,
                recip,
                sqrt,
                exposure: true,
                top,
            },
            flavour: Flavour::Plain,
            features,
        });
    }
    rows
}

/// The cargo features `full` turns on: every plain model and waveform
/// twin, the ones the test suite runs.
pub const FULL: [&str; 4] = ["fast", "methods", "tops", "waves"];

#[cfg(test)]
mod tests {
    use super::*;

    /// A float unit cut from a mutant netlist is checked against the golden
    /// model of the same unit alone (the C++ driver names it by module and
    /// method, `FpModel::RecipExact`, `FpModel::Add`): each mutant unit's
    /// module and method are those of a unit row.
    #[test]
    fn every_mutant_unit_is_checked_as_a_unit_of_the_table() {
        let rows = table(&[EXACT, "fast"], &[]);
        let units: Vec<(&str, Option<&str>)> = rows
            .iter()
            .filter_map(|m| match &m.what {
                What::Unit { module, method } => Some((*module, method.as_deref())),
                _ => None,
            })
            .collect();
        let mutants: Vec<(&str, Option<&str>)> = rows
            .iter()
            .filter_map(|m| match &m.what {
                What::MutantUnit { module, method } => Some((*module, *method)),
                _ => None,
            })
            .collect();
        assert_eq!(mutants.len(), 12, "{mutants:?}");
        for m in &mutants {
            assert!(units.contains(m), "mutant unit {m:?} is no unit row");
        }
        assert!(mutants.contains(&("fp_add", None)));
        assert!(mutants.contains(&("fast_fp_sqrt", Some(EXACT))));
    }
}
