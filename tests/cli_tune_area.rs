//! `rtcosim tune --area`, run as the built binary.
//!
//! --area runs yosys, which CI does not install, and the float units'
//! synthesis takes minutes. So the binary runs against a stand-in `yosys`
//! first on PATH: a shell script that logs the script it is given and
//! answers `stat` with figures this test makes up from it, with the cache in
//! a directory of the test's own (RTCOSIM_AREA_CACHE, so that made-up
//! figures never reach the real cache). That pins what --area asks yosys,
//! what it prints from the answers and what it caches. With the real yosys
//! installed, the register file is measured by it (a fraction of a second)
//! and held to its storage bits from first principles. Without any yosys,
//! --area is a clear error with exit 2.

mod common;

use common::{arg, both, mirror, scratch, text, tune_pick};
use golden::fp::Method;
use golden::micro::isa;
use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the built `rtcosim` with `args` and these environment variables.
fn rtcosim_env(args: &[&str], env: &[(&str, &OsStr)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rtcosim"));
    cmd.args(args);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("running rtcosim")
}

/// The stand-in yosys. It appends its `-p` script to $FAKE_YOSYS_LOG, then
/// fails ($FAKE_YOSYS_MODE=fail), prints nothing (=silent), or answers
/// `stat` with made-up figures (see [`Figures`]). Scripts that are not a
/// float unit's synthesis go to $REAL_YOSYS when it is set.
const FAKE_YOSYS: &str = r#"#!/bin/sh
script="$3"
printf '%s\n' "$script" >> "$FAKE_YOSYS_LOG"
case "$FAKE_YOSYS_MODE" in
  fail) echo "ERROR: the stand-in yosys fails" >&2; exit 1 ;;
  silent) exit 0 ;;
esac
num() { printf '%s\n' "$script" | sed -n "s/.*-chparam $1 \([0-9]*\).*/\1/p"; }
case "$script" in
  *"synth -flatten -top fp_recip"*) unit=1 ;;
  *"synth -flatten -top fp_sqrt"*) unit=2 ;;
  *)
    if [ -n "$REAL_YOSYS" ]; then exec "$REAL_YOSYS" "$@"; fi
    d=$(num STACK_DEPTH)
    case "$script" in
      *"-top memory "*) echo "   Number of memory bits:   $((1000 * d + 7))"
                        echo "   Number of cells:         $((10 * d + 1))" ;;
      *"-top mem_ctrl "*) echo "   Number of cells:         $((100 + d))" ;;
      *) echo "unexpected script" >&2; exit 1 ;;
    esac
    exit 0 ;;
esac
m=$(num METHOD)
echo "   Number of cells:         $((5000 * unit + 300 * m))"
echo "     \$_AND_                   50"
echo "     \$_DFF_P_                 $((20 + m))"
echo "     \$_SDFFE_PP0P_            $((3 * unit))"
"#;

/// The stand-in's figures, as the test computes them.
struct Figures;

impl Figures {
    fn memory_bits(depth: u32) -> u64 {
        1000 * u64::from(depth) + 7
    }
    /// `memory` and `mem_ctrl` together.
    fn register_file_cells(depth: u32) -> u64 {
        (10 * u64::from(depth) + 1) + (100 + u64::from(depth))
    }
    /// 1 for the reciprocal, 2 for the square root.
    fn unit_cells(unit: u64, m: Method) -> u64 {
        5000 * unit + 300 * u64::from(m.code())
    }
    fn unit_flip_flops(unit: u64, m: Method) -> u64 {
        20 + u64::from(m.code()) + 3 * unit
    }
}

/// A directory with the stand-in as `yosys`, its log, and a cache.
struct Stand {
    dir: PathBuf,
}

impl Stand {
    fn new(test: &str) -> Stand {
        let dir = scratch("cli_tune_area", test);
        let bin = dir.join("bin");
        std::fs::create_dir_all(&bin).expect("bin dir");
        let yosys = bin.join("yosys");
        std::fs::write(&yosys, FAKE_YOSYS).expect("the stand-in");
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&yosys, std::fs::Permissions::from_mode(0o755))
            .expect("executable");
        Stand { dir }
    }

    fn cache(&self) -> PathBuf {
        self.dir.join("cache")
    }

    fn log(&self) -> PathBuf {
        self.dir.join("yosys.log")
    }

    /// The scripts yosys was given since the last call.
    fn take_scripts(&self) -> Vec<String> {
        let text = std::fs::read_to_string(self.log()).unwrap_or_default();
        let _ = std::fs::remove_file(self.log());
        text.lines().map(String::from).collect()
    }

    /// `tune --area` on the mirror scene at 4x3 with the stand-in first on
    /// PATH; `extra` environment on top.
    fn tune_area(&self, extra: &[(&str, &OsStr)]) -> Output {
        let path = std::env::join_paths(std::iter::once(self.dir.join("bin")).chain(
            std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
        ))
        .expect("PATH");
        let (cache, log) = (self.cache(), self.log());
        let mut env: Vec<(&str, &OsStr)> = vec![
            ("PATH", path.as_os_str()),
            ("RTCOSIM_AREA_CACHE", cache.as_os_str()),
            ("FAKE_YOSYS_LOG", log.as_os_str()),
        ];
        env.extend_from_slice(extra);
        rtcosim_env(&tune_area_args(), &env)
    }
}

/// `tune --area` on the mirror scene at 4x3.
fn tune_area_args() -> Vec<&'static str> {
    let mut args = common::TUNE_MIRROR_4X3.to_vec();
    args.push("--area");
    args
}

/// The line of `stdout` that starts with `prefix`.
fn line<'a>(stdout: &'a str, prefix: &str) -> &'a str {
    stdout
        .lines()
        .find(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no line starting {prefix:?} in\n{stdout}"))
}

#[test]
fn area_asks_yosys_prints_its_figures_and_caches_the_float_units() {
    let stand = Stand::new("stand-in");
    let out = stand.tune_area(&[]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    let pick = tune_pick(&stdout, &mirror(4, 3));
    let d = pick.max_depth;

    // The register file: memory and mem_ctrl at the pick's depth and at 8.
    let rf = line(&stdout, "area, register file ");
    let pct = 100.0 * Figures::memory_bits(d) as f64 / Figures::memory_bits(8) as f64;
    for want in [
        format!(
            ": {} storage bits and {} cells at STACK_DEPTH {d}, ",
            Figures::memory_bits(d),
            Figures::register_file_cells(d)
        ),
        format!(
            "against {} bits and {} cells at 8 ({pct:.1}% of the storage)",
            Figures::memory_bits(8),
            Figures::register_file_cells(8)
        ),
    ] {
        assert!(rf.contains(&want), "{want:?} in {rf:?}");
    }
    // Each float unit in the pick's method against the exact one.
    for (unit, module, method) in [(1, "fp_recip", pick.recip), (2, "fp_sqrt", pick.sqrt)] {
        let l = line(&stdout, &format!("area, {module} "));
        let (cells, exact) = (
            Figures::unit_cells(unit, method),
            Figures::unit_cells(unit, Method::Exact),
        );
        let mut want = format!(
            ": {cells} cells and {} flip-flops ({}), against {exact} cells and {} flip-flops (exact)",
            Figures::unit_flip_flops(unit, method),
            method.name(),
            Figures::unit_flip_flops(unit, Method::Exact)
        );
        if method == Method::Fast {
            want += &format!(": {:.1}% of the cells", 100.0 * cells as f64 / exact as f64);
        }
        assert!(l.ends_with(&want), "{want:?} at the end of {l:?}");
    }

    // What yosys was asked: the register file at both depths, each float
    // unit once per method (the exact one from the cache if the pick is
    // exact too).
    let scripts = stand.take_scripts();
    let count = |pat: &str| scripts.iter().filter(|s| s.contains(pat)).count();
    for depth in [d, 8] {
        for top in ["memory", "mem_ctrl"] {
            let pat = format!("hierarchy -top {top} -chparam STACK_DEPTH {depth};");
            assert_eq!(
                count(&pat),
                if d == 8 { 2 } else { 1 },
                "{pat}: {scripts:#?}"
            );
        }
    }
    let mut jobs = Vec::new();
    for (module, method) in [("fp_recip", pick.recip), ("fp_sqrt", pick.sqrt)] {
        for m in [method, Method::Exact] {
            if !jobs.contains(&(module, m)) {
                jobs.push((module, m));
            }
        }
    }
    for &(module, m) in &jobs {
        let pat = format!(
            "hierarchy -top {module} -chparam METHOD {}; synth -flatten -top {module}",
            m.code()
        );
        assert_eq!(count(&pat), 1, "{pat}: {scripts:#?}");
    }
    assert_eq!(scripts.len(), 4 + jobs.len(), "{scripts:#?}");
    // The cache holds one file per job, with yosys' answer.
    let mut cached: Vec<String> = std::fs::read_dir(stand.cache())
        .expect("the cache was written")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    cached.sort();
    let mut want: Vec<String> = jobs
        .iter()
        .map(|(module, m)| format!("{module}-{}-", m.name()))
        .collect();
    want.sort();
    assert_eq!(cached.len(), want.len(), "{cached:?}");
    for (file, prefix) in cached.iter().zip(&want) {
        assert!(
            file.starts_with(prefix.as_str()) && file.ends_with(".stat"),
            "{file}"
        );
    }

    // Again: the float units come from the cache, yosys is asked only for
    // the register file, and the report is the same.
    let again = stand.tune_area(&[]);
    assert_eq!(again.status.code(), Some(0), "{}", both(&again));
    assert_eq!(text(&again.stdout), stdout);
    let scripts = stand.take_scripts();
    assert_eq!(scripts.len(), 4, "{scripts:#?}");
    assert!(scripts.iter().all(|s| !s.contains("synth")), "{scripts:#?}");
}

/// yosys missing, failing, answering without figures, and a cache that
/// cannot be written: exit 2, after the tuner's answer, with a message
/// that says what went wrong; never a panic.
#[test]
fn area_errors_say_what_went_wrong() {
    let stand = Stand::new("errors");
    let expect_error = |out: &Output, message: &str| {
        assert_eq!(out.status.code(), Some(2), "{}", both(out));
        let stderr = text(&out.stderr);
        assert!(stderr.contains(message), "{message:?} in\n{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        // The OS's reason, if any, once.
        assert!(stderr.matches("(os error").count() <= 1, "{stderr}");
        assert!(text(&out.stdout).contains("\ncheapest: "), "{}", both(out));
    };

    // No yosys anywhere on PATH (an empty directory: an unset PATH would
    // fall back to the system's).
    let empty = stand.dir.join("empty");
    std::fs::create_dir_all(&empty).expect("empty dir");
    let cache = stand.cache();
    let out = rtcosim_env(
        &tune_area_args(),
        &[
            ("PATH", empty.as_os_str()),
            ("RTCOSIM_AREA_CACHE", cache.as_os_str()),
        ],
    );
    expect_error(
        &out,
        "error: running yosys (is yosys installed? --area needs it): No such file or directory \
         (os error 2)\n",
    );

    let out = stand.tune_area(&[("FAKE_YOSYS_MODE", OsStr::new("fail"))]);
    // The first job, the register file at the pick's depth, fails.
    let d = tune_pick(&text(&out.stdout), &mirror(4, 3)).max_depth;
    expect_error(
        &out,
        &format!(
            "error: yosys failed on memory with STACK_DEPTH {d}:\nERROR: the stand-in yosys fails\n"
        ),
    );

    let out = stand.tune_area(&[("FAKE_YOSYS_MODE", OsStr::new("silent"))]);
    expect_error(&out, "error: yosys printed no \"Number of cells:\" line");

    // The cache under a regular file: it cannot be created.
    let file = stand.dir.join("a-file");
    std::fs::write(&file, "not a directory").expect("a file");
    let under = file.join("cache");
    let out = stand.tune_area(&[("RTCOSIM_AREA_CACHE", under.as_os_str())]);
    expect_error(
        &out,
        &format!(
            "error: cannot write the area cache {} (set RTCOSIM_AREA_CACHE to keep it elsewhere): \
             Not a directory (os error 20)\n",
            arg(&under)
        ),
    );
}

/// The real yosys measures the register file (the float units still come
/// from the stand-in: their synthesis takes minutes): its storage is 96
/// bits for each register below the current ray's (the ISA's CUR_O) and
/// for each of the STACK_DEPTH levels' STK_STRIDE registers, at the pick's
/// depth and at 8. Without yosys on PATH the test says loudly that it did
/// not run.
#[test]
fn area_measures_the_register_file_with_the_real_yosys() {
    let real = std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())
        .map(|d| d.join("yosys"))
        .find(|p| p.is_file());
    let Some(real) = real else {
        eprintln!(
            "NOT RUN: area_measures_the_register_file_with_the_real_yosys needs yosys on PATH"
        );
        return;
    };
    let stand = Stand::new("real");
    let out = stand.tune_area(&[("REAL_YOSYS", real.as_os_str())]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    let d = tune_pick(&stdout, &mirror(4, 3)).max_depth;
    let rf = line(&stdout, "area, register file ");
    // "...: T storage bits and C cells at STACK_DEPTH d, against F bits and ..."
    let words: Vec<&str> = rf.split_whitespace().collect();
    let number_at = |i: usize| -> u64 {
        words[i]
            .parse()
            .unwrap_or_else(|_| panic!("word {i} of {rf:?}"))
    };
    let storage = words.iter().position(|&w| w == "storage").expect("storage");
    let against = words.iter().position(|&w| w == "against").expect("against");
    let (tuned, full) = (number_at(storage - 1), number_at(against + 1));
    // Registers 0 up to the current ray's (the scene, the constants, the
    // temporaries; rtl/pp/memory.v's REG_WORDS), the stack levels, and the
    // refraction bank (TRN, memory.v's REFRACTION = 1).
    let words = |depth: u32| {
        u64::from(isa::reg::CUR_O)
            + u64::from(depth) * isa::dim::STK_STRIDE as u64
            + isa::dim::TRN_COUNT as u64
    };
    assert_eq!((tuned, full), (96 * words(d), 96 * words(8)), "{rf}");
    let scripts = stand.take_scripts();
    assert_eq!(
        scripts.iter().filter(|s| s.contains("STACK_DEPTH")).count(),
        4,
        "{scripts:#?}"
    );
}
