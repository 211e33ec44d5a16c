//! The hardware a configuration needs, measured with yosys: what `tune
//! --area` reports for the tuned build against the full build.
//!
//! Two parts of the pixel processor change with a configuration:
//! - the register file, sized by `STACK_DEPTH` ([`register_file_area`]:
//!   `memory` + `mem_ctrl` after `proc; opt`, a fraction of a second);
//! - the reciprocal and square-root units, chosen by their `METHOD`
//!   ([`float_unit_area`]: generic `synth -flatten` of the unit alone, cells
//!   and flip-flops after techmap). That synthesis takes minutes (the seed
//!   tables), so its `stat` is cached under a key of the script and the
//!   bytes of every source file it reads: a changed RTL file is
//!   synthesized again, an unchanged one never.
//!
//! Everything else (the controller, the ALU, the adders and multipliers) is
//! in every build.

use golden::fp::Method;
use std::hash::Hasher;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Why an area could not be measured.
#[derive(Debug, thiserror::Error)]
pub enum AreaError {
    #[error("running {program} (is yosys installed? --area needs it): {source}")]
    Spawn {
        program: String,
        #[source]
        source: std::io::Error,
    },
    #[error("yosys failed on {what}:\n{stderr}")]
    Failed { what: String, stderr: String },
    #[error("yosys printed no {0:?} line")]
    Parse(&'static str),
    #[error(
        "cannot write the area cache {} (set {CACHE_ENV} to keep it elsewhere): {source}",
        path.display()
    )]
    Cache {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// The environment variable that moves the cache of [`Yosys::new`]
/// elsewhere (a CI cache directory; a test's own, so that a stand-in yosys
/// never writes figures into the real cache).
pub const CACHE_ENV: &str = "RTCOSIM_AREA_CACHE";

/// How to run yosys: the program, and where synthesized units' `stat`
/// outputs are kept.
#[derive(Debug, Clone)]
pub struct Yosys {
    pub program: PathBuf,
    pub cache: PathBuf,
}

impl Yosys {
    /// `yosys` from `PATH`, caching in `target/rtcosim-area/` of this
    /// checkout (beside the Verilator that build.rs may install there), or
    /// in the directory [`CACHE_ENV`] names.
    pub fn new() -> Yosys {
        let cache = std::env::var_os(CACHE_ENV)
            .filter(|d| !d.is_empty())
            .map(PathBuf::from)
            .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/rtcosim-area"));
        Yosys {
            program: "yosys".into(),
            cache,
        }
    }

    /// Runs `script` (yosys -q -p) and returns what `stat` printed.
    fn stat(&self, script: &str, what: &str) -> Result<String, AreaError> {
        let out = Command::new(&self.program)
            .args(["-q", "-p", &format!("{script}; tee -o /dev/stdout stat")])
            .output()
            .map_err(|source| AreaError::Spawn {
                program: self.program.display().to_string(),
                source,
            })?;
        if !out.status.success() {
            return Err(AreaError::Failed {
                what: what.into(),
                stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            });
        }
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    }
}

impl Default for Yosys {
    fn default() -> Yosys {
        Yosys::new()
    }
}

/// The number after `label` in yosys' `stat` output (the last such line).
fn stat_number(out: &str, label: &'static str) -> Result<u64, AreaError> {
    out.lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix(label))
        .and_then(|rest| rest.trim().parse().ok())
        .ok_or(AreaError::Parse(label))
}

/// The flip-flops in a `stat` output after techmap: the counts of the
/// cell types yosys names `$_..DFF.._` (every flavour of enable, reset and
/// set), one bit each.
fn flip_flops(out: &str) -> u64 {
    out.lines()
        .filter_map(|l| {
            let mut words = l.split_whitespace();
            let cell = words.next()?;
            let n = words.next()?.parse::<u64>().ok()?;
            (cell.starts_with("$_") && cell.contains("DFF") && words.next().is_none()).then_some(n)
        })
        .sum()
}

/// The register file of a build with `stack_depth` levels: the part of the
/// design that STACK_DEPTH sizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RegisterFileArea {
    pub stack_depth: u32,
    /// Storage bits of the register file (`memory`: the scene registers,
    /// constants and temporaries, plus STACK_DEPTH levels of 4 registers of
    /// 96 bits): yosys' "Number of memory bits".
    pub memory_bits: u64,
    /// yosys cells of `memory` and `mem_ctrl` after `proc; opt`, before
    /// techmap (word-level cells: comparators, muxes, memory ports).
    pub cells: u64,
}

/// The register file with `stack_depth` levels, measured with yosys
/// (`read_verilog memory.v mem_ctrl.v; hierarchy -chparam STACK_DEPTH;
/// proc; opt; stat`, a fraction of a second each).
pub fn register_file_area(
    yosys: &Yosys,
    rtl_pp: &Path,
    stack_depth: u32,
) -> Result<RegisterFileArea, AreaError> {
    let mut bits = 0;
    let mut cells = 0;
    for top in ["memory", "mem_ctrl"] {
        let script = format!(
            "read_verilog -I{dir} {dir}/memory.v {dir}/mem_ctrl.v; \
             hierarchy -top {top} -chparam STACK_DEPTH {stack_depth}; proc; opt",
            dir = rtl_pp.display()
        );
        let text = yosys.stat(&script, &format!("{top} with STACK_DEPTH {stack_depth}"))?;
        cells += stat_number(&text, "Number of cells:")?;
        if top == "memory" {
            bits = stat_number(&text, "Number of memory bits:")?;
        }
    }
    Ok(RegisterFileArea {
        stack_depth,
        memory_bits: bits,
        cells,
    })
}

/// The two float units whose method a build chooses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FloatUnit {
    Recip,
    Sqrt,
}

impl FloatUnit {
    /// The Verilog module (and file stem).
    pub fn module(self) -> &'static str {
        match self {
            FloatUnit::Recip => "fp_recip",
            FloatUnit::Sqrt => "fp_sqrt",
        }
    }
}

/// One float unit in one method, after generic synthesis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnitArea {
    pub unit: FloatUnit,
    pub method: Method,
    /// Gate-level cells (`synth -flatten`, yosys' internal cell library).
    pub cells: u64,
    /// Flip-flop bits among them.
    pub flip_flops: u64,
    /// Whether the figures came from the cache rather than a run now.
    pub cached: bool,
}

/// The yosys script that synthesizes `unit` in `method` from the Verilog
/// files of `rtl_fp`, and the cache file of its `stat`: named by a key of
/// the script's location-independent words and every source file's name
/// and bytes.
fn unit_job(
    yosys: &Yosys,
    rtl_fp: &Path,
    unit: FloatUnit,
    method: Method,
) -> Result<(String, PathBuf), AreaError> {
    let sources = unit_sources(rtl_fp, unit)?;
    let verilog: Vec<String> = sources
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "v"))
        .map(|p| p.display().to_string())
        .collect();
    let top = unit.module();
    let script = format!(
        "read_verilog -I{dir} {files}; hierarchy -top {top} -chparam METHOD {code}; \
         synth -flatten -top {top}",
        dir = rtl_fp.display(),
        files = verilog.join(" "),
        code = method.code(),
    );
    let mut key = fnv::FnvHasher::default();
    key.write(format!("{top} METHOD {} synth -flatten", method.code()).as_bytes());
    for p in &sources {
        key.write(p.file_name().map_or(&[][..], |n| n.as_encoded_bytes()));
        key.write(&std::fs::read(p).map_err(io_error(p))?);
    }
    let file = yosys.cache.join(format!(
        "{top}-{}-{:016x}.stat",
        method.name(),
        key.finish()
    ));
    Ok((script, file))
}

/// The files `unit` is built from: its own `<module>.v`, and transitively
/// every file of `rtl_fp` whose stem (a module: one module per file, named
/// after it) or name (an `include`) appears as a word in the code (not the
/// `//` comments) of one of them. A word scan, so it may take a file too
/// many but never one too few (the RTL has no block comments); files
/// the unit does not use (another unit added beside it) do not change its
/// cache key. Sorted by path.
pub fn unit_sources(rtl_fp: &Path, unit: FloatUnit) -> Result<Vec<PathBuf>, AreaError> {
    let mut found = std::collections::BTreeSet::new();
    let mut todo = vec![rtl_fp.join(format!("{}.v", unit.module()))];
    while let Some(file) = todo.pop() {
        if !found.insert(file.clone()) {
            continue;
        }
        let text = std::fs::read_to_string(&file).map_err(io_error(&file))?;
        // Code only: a comment naming another unit is not a use of it.
        let code: String = text
            .lines()
            .map(|l| l.split("//").next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join("\n");
        let words = code.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.'));
        for w in words.filter(|w| w.starts_with("fp_")) {
            for name in [format!("{w}.v"), w.to_string()] {
                let candidate = rtl_fp.join(&name);
                let verilog = name.ends_with(".v") || name.ends_with(".vh");
                if verilog && candidate.is_file() && !found.contains(&candidate) {
                    todo.push(candidate);
                }
            }
        }
    }
    Ok(found.into_iter().collect())
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> AreaError {
    let path = path.to_path_buf();
    move |source| AreaError::Io { path, source }
}

/// `unit` in `method`, synthesized alone from the Verilog files of `rtl_fp`
/// (`read_verilog` of every `.v` there; `hierarchy -top <unit> -chparam
/// METHOD <code>; synth -flatten; stat`), or its cached `stat` if the
/// script and every source byte are unchanged. Minutes per unit the first
/// time.
pub fn float_unit_area(
    yosys: &Yosys,
    rtl_fp: &Path,
    unit: FloatUnit,
    method: Method,
) -> Result<UnitArea, AreaError> {
    let (script, cached) = unit_job(yosys, rtl_fp, unit, method)?;
    let (text, hit) = match std::fs::read_to_string(&cached) {
        Ok(text) => (text, true),
        Err(_) => {
            let what = format!("{} with METHOD {}", unit.module(), method.name());
            let text = yosys.stat(&script, &what)?;
            let cache_error = |path: &Path| {
                let path = path.to_path_buf();
                move |source| AreaError::Cache { path, source }
            };
            std::fs::create_dir_all(&yosys.cache).map_err(cache_error(&yosys.cache))?;
            let tmp = cached.with_extension("tmp");
            std::fs::write(&tmp, &text).map_err(cache_error(&tmp))?;
            std::fs::rename(&tmp, &cached).map_err(cache_error(&cached))?;
            (text, false)
        }
    };
    Ok(UnitArea {
        unit,
        method,
        cells: stat_number(&text, "Number of cells:")?,
        flip_flops: flip_flops(&text),
        cached: hit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tail of a real `stat` of fp_recip (exact) after `synth -flatten`.
    const STAT: &str = "
   Number of wires:               9391
   Number of wire bits:          29781
   Number of cells:              28754
     $_ANDNOT_                    6376
     $_AND_                       1633
     $_DFFE_PN0P_                   35
     $_DFFE_PP_                    136
     $_DFF_PN0_                      1
     $_MUX_                        550
     $_OR_                       15257
     $_SDFFCE_PP0P_                  1
     $_SDFFCE_PP1P_                  4
     $_XOR_                       1772
";

    #[test]
    fn stat_numbers_and_flip_flops_are_read_from_yosys_output() {
        assert_eq!(stat_number(STAT, "Number of cells:").ok(), Some(28754));
        assert!(matches!(
            stat_number(STAT, "Number of memory bits:"),
            Err(AreaError::Parse(_))
        ));
        assert_eq!(flip_flops(STAT), 35 + 136 + 1 + 1 + 4);
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("rtcosim-area-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch dir");
        dir
    }

    #[test]
    fn a_unit_is_built_from_the_files_it_names_and_no_others() {
        let fp = Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl/fp");
        let names = |u| -> Vec<String> {
            unit_sources(&fp, u)
                .expect("rtl/fp")
                .iter()
                .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
                .collect()
        };
        let recip = names(FloatUnit::Recip);
        assert!(recip.contains(&"fp_recip.v".into()) && recip.contains(&"fp_defs.vh".into()));
        assert!(!recip.contains(&"fp_sqrt.v".into()) && !recip.contains(&"fp_add.v".into()));
        assert!(names(FloatUnit::Sqrt).contains(&"fp_sqrt.v".into()));
    }

    #[test]
    fn a_cached_unit_is_not_synthesized_again_and_a_changed_source_is() {
        let dir = scratch("cache");
        let rtl = dir.join("rtl");
        std::fs::create_dir_all(&rtl).expect("rtl dir");
        std::fs::write(rtl.join("fp_recip.v"), "module fp_recip; endmodule\n").expect("write");
        std::fs::write(rtl.join("fp_other.v"), "module fp_other; endmodule\n").expect("write");
        // A yosys that does not exist: any run is an error.
        let yosys = Yosys {
            program: dir.join("no-such-yosys"),
            cache: dir.join("cache"),
        };
        let run = || float_unit_area(&yosys, &rtl, FloatUnit::Recip, Method::Fast);
        assert!(matches!(run(), Err(AreaError::Spawn { .. })));
        // Seed the cache file of this source: found, not run.
        let (_, file) = unit_job(&yosys, &rtl, FloatUnit::Recip, Method::Fast).expect("a job");
        std::fs::create_dir_all(&yosys.cache).expect("cache dir");
        std::fs::write(&file, STAT).expect("seed");
        let a = run().expect("from the cache");
        assert_eq!((a.cells, a.flip_flops, a.cached), (28754, 177, true));
        // A file the unit does not use changes: still cached.
        std::fs::write(
            rtl.join("fp_other.v"),
            "module fp_other; wire w; endmodule\n",
        )
        .expect("write");
        assert!(run().is_ok_and(|a| a.cached));
        // One byte of the source changed: the key changes, yosys must run.
        std::fs::write(rtl.join("fp_recip.v"), "module fp_recip;  endmodule\n").expect("write");
        assert!(matches!(run(), Err(AreaError::Spawn { .. })));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Synthesizes both methods of both units (minutes each, on the first
    /// run of an RTL version): the exact methods, with their remainder
    /// step, are larger.
    #[test]
    #[ignore = "yosys synthesis of four float units, minutes each"]
    fn the_exact_methods_cost_more_than_the_fast_ones() {
        let yosys = Yosys::new();
        let fp = Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl/fp");
        for unit in [FloatUnit::Recip, FloatUnit::Sqrt] {
            let exact = float_unit_area(&yosys, &fp, unit, Method::Exact).expect("yosys");
            let fast = float_unit_area(&yosys, &fp, unit, Method::Fast).expect("yosys");
            println!("{unit:?}: exact {exact:?}, fast {fast:?}");
            assert!(fast.flip_flops > 0 && fast.cells > 0);
            assert!(exact.cells > fast.cells, "{exact:?} vs {fast:?}");
        }
    }
}
