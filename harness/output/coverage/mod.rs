//! Coverage of the RTL: what the co-simulation runs exercised.
//!
//! Built with the cargo feature `coverage`, every pixel processor is
//! verilated once more with Verilator's line, branch, toggle and user
//! coverage, and with a cover point per controller state and per possible
//! state transition (`PP_COVER`: `rtl/cover/`, build.rs). [`enable`] (the
//! CLI's `--coverage DIR`) or the environment variable [`ENV`] (for
//! `cargo test`) makes every [`PixelProcessor`](crate::design::pixel_proc::PixelProcessor)
//! built afterwards in this process a coverage model, which writes its
//! counts into `DIR/raw/` when dropped; [`finish`] merges a directory's (or
//! several shards') counts into:
//!
//! - `coverage.dat`: Verilator's format, the sum of every run;
//! - `coverage.info`: lcov, by `verilator_coverage --write-info`;
//! - `html/`: the annotated sources, by `genhtml` (Debian: `lcov`);
//! - `summary.json`, `summary.md`: points hit per kind and per file, the
//!   states and transitions never taken, the bits that never toggled.

pub mod dat;
mod summary;

pub use dat::{CoverageData, Kind, Point};
pub use summary::{
    reachable_transitions, unreachable, Argued, FileSummary, KindSummary, Summary, TransitionPoint,
    FAST_UNREACHABLE_PATH, TRANSITIONS_PATH, UNREACHABLE_PATH,
};

use std::path::{Path, PathBuf};
use std::process::Command;

pub use crate::design::counts::ENV;

/// The binary was built with the coverage models (cargo feature `coverage`).
pub const BUILT: bool = cfg!(feature = "coverage");

/// How to get a build that has them.
pub const HOW_TO_BUILD: &str =
    "coverage needs the coverage models: build with the cargo feature `coverage`, \
     e.g. `cargo run --release --features coverage -- cosim --coverage DIR`";

/// Errors of coverage collection and reports; each names its file.
#[derive(Debug, thiserror::Error)]
pub enum CoverageError {
    #[error("{HOW_TO_BUILD}")]
    NotBuilt,
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}:{line}: {message}", path.display())]
    Format {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{}: no coverage counts (no .dat file in {}, and no coverage.dat)", path.display(), path.join(RAW).display())]
    Empty { path: PathBuf },
    #[error("{tool}: {message}")]
    Tool { tool: String, message: String },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> CoverageError + '_ {
    move |source| CoverageError::Io {
        path: path.to_path_buf(),
        source,
    }
}

pub use crate::design::counts::{dir, RAW};

/// Makes every pixel processor built from now on in this process a
/// coverage model writing into `dir` (created, with `dir/raw/`). Refused
/// by a binary built without the coverage models.
pub fn enable(dir: &Path) -> Result<(), CoverageError> {
    if !BUILT {
        return Err(CoverageError::NotBuilt);
    }
    let raw = dir.join(RAW);
    std::fs::create_dir_all(&raw).map_err(io(&raw))?;
    crate::design::counts::set_dir(dir);
    Ok(())
}

/// The counts under `path`: a coverage.dat file, or a directory's
/// `raw/*.dat` (every model's counts), or, without those, its coverage.dat.
pub fn collect(path: &Path) -> Result<CoverageData, CoverageError> {
    if path.is_file() {
        return CoverageData::read(path);
    }
    let raw = path.join(RAW);
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&raw) {
        Ok(entries) => entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "dat"))
            .collect(),
        Err(_) => Vec::new(),
    };
    files.sort();
    if files.is_empty() {
        let merged = path.join("coverage.dat");
        if merged.is_file() {
            return CoverageData::read(&merged);
        }
        return Err(CoverageError::Empty {
            path: path.to_path_buf(),
        });
    }
    let mut data = CoverageData::default();
    for f in &files {
        data.merge(&CoverageData::read(f)?);
    }
    Ok(data)
}

/// What [`finish`] wrote.
#[derive(Debug, Clone)]
pub struct Finished {
    pub summary: Summary,
    pub files: Vec<PathBuf>,
    /// What could not be made and why (a missing `verilator_coverage` or
    /// `genhtml`): the rest is written all the same.
    pub notes: Vec<String>,
}

impl Finished {
    /// For people: the figures per kind, what was never taken, the files
    /// written, what could not be made.
    pub fn report(&self) -> String {
        let s = &self.summary;
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let mut text = format!(
            "{}\n  never taken: {} state{}, {} transition{} (and {} argued unreachable), {} line or \
             branch point{}\n",
            s.text(),
            s.states_missed.len(),
            plural(s.states_missed.len()),
            s.transitions_missed.len(),
            plural(s.transitions_missed.len()),
            s.transitions_argued.len(),
            s.lines_missed.len(),
            plural(s.lines_missed.len()),
        );
        for t in &s.argued_but_taken {
            text += &format!(
                "  warning: {t} was taken, but {UNREACHABLE_PATH} or {FAST_UNREACHABLE_PATH} \
                 argues it unreachable: the argument is wrong\n"
            );
        }
        for f in &self.files {
            text += &format!("  wrote {}\n", f.display());
        }
        for n in &self.notes {
            text += &format!("  note: {n}\n");
        }
        text
    }
}

/// `verilator_coverage`: beside the `verilator` that built the models,
/// else on PATH.
fn verilator_coverage() -> Command {
    let bin = Path::new(env!("RTCOSIM_VERILATOR_BIN"));
    let sibling = bin.with_file_name("verilator_coverage");
    let mut cmd = if bin.is_absolute() && sibling.exists() {
        Command::new(sibling)
    } else {
        Command::new("verilator_coverage")
    };
    let root = env!("RTCOSIM_VERILATOR_ROOT");
    if !root.is_empty() {
        cmd.env("VERILATOR_ROOT", root);
    }
    cmd
}

fn run_tool(mut cmd: Command, tool: &str) -> Result<(), CoverageError> {
    let o = cmd.output().map_err(|e| CoverageError::Tool {
        tool: tool.into(),
        message: format!("cannot run it ({e})"),
    })?;
    if !o.status.success() {
        return Err(CoverageError::Tool {
            tool: tool.into(),
            message: String::from_utf8_lossy(&o.stderr).trim().to_string(),
        });
    }
    Ok(())
}

/// The checkout the sources are read from for the HTML report (the paths
/// in coverage.dat are relative to it).
pub fn source_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Merges `inputs` (directories or coverage.dat files, e.g. the shards of
/// a campaign) into `out`: coverage.dat, coverage.info, html/ (with
/// `html`), summary.json and summary.md.
pub fn finish(inputs: &[PathBuf], out: &Path, html: bool) -> Result<Finished, CoverageError> {
    let mut data = CoverageData::default();
    for input in inputs {
        data.merge(&collect(input)?);
    }
    std::fs::create_dir_all(out).map_err(io(out))?;
    let mut files = Vec::new();
    let mut notes = Vec::new();
    let dat = out.join("coverage.dat");
    std::fs::write(&dat, data.to_text()).map_err(io(&dat))?;
    files.push(dat.clone());

    let argued = summary::unreachable().map_err(|(path, line, message)| CoverageError::Format {
        path: source_root().join(path),
        line,
        message,
    })?;
    let summary = Summary::of(&data, &argued);
    let json = out.join("summary.json");
    let text = serde_json::to_string_pretty(&summary.to_json()).unwrap_or_default() + "\n";
    std::fs::write(&json, text).map_err(io(&json))?;
    files.push(json);
    let md = out.join("summary.md");
    std::fs::write(&md, summary.to_markdown()).map_err(io(&md))?;
    files.push(md);

    let info = out.join("coverage.info");
    let mut cmd = verilator_coverage();
    cmd.arg("--write-info").arg(&info).arg(&dat);
    match run_tool(cmd, "verilator_coverage") {
        Ok(()) => files.push(info.clone()),
        Err(e) => notes.push(format!("no coverage.info: {e}")),
    }
    if html && info.exists() {
        let dir = out.join("html");
        let mut cmd = Command::new("genhtml");
        cmd.current_dir(source_root())
            .arg("--quiet")
            .arg("--output-directory")
            .arg(std::path::absolute(&dir).map_err(io(&dir))?)
            .arg(std::path::absolute(&info).map_err(io(&info))?);
        match run_tool(cmd, "genhtml") {
            Ok(()) => files.push(dir.join("index.html")),
            Err(e) => notes.push(format!(
                "no html/: {e} (genhtml is in Debian's package lcov: apt-get install lcov)"
            )),
        }
    }
    Ok(Finished {
        summary,
        files,
        notes,
    })
}
