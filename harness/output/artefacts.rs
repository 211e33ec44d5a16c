//! The files a co-simulation leaves in `rtcosim cosim --out DIR`, for
//! people and for CI systems:
//!
//! - `rtl.png`, `golden.png`: both sides' frames of the window (8-bit);
//! - `rtl.exr`, `golden.exr`: the same, lossless f32 (`rtcosim diffmap`
//!   reads them);
//! - `diffmap/`: the difference maps of the two frames and the thesis'
//!   table ([`golden::diffmap`]): all zero on a passing run;
//! - `report.json`: everything the text report says, keyed (serde_json):
//!   the run, cycles per pixel (mean, min, max, histogram), events, the
//!   ULP histogram, the divergences and the first one with its Verilog and
//!   Rust lines;
//! - `report.md`: the same for people, in Markdown;
//! - `junit.xml`: one test case for the scene and method pair (as cocotb's
//!   `results.xml`), failing with the first divergence.

use crate::check::cosim::CosimReport;
use golden::diffmap::{DiffMap, THESIS_THRESHOLDS};
use golden::scene::Scene;
use serde_json::json;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Errors writing the run's files; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum ArtefactError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Frame(#[from] golden::frame::FrameError),
    #[error(transparent)]
    DiffMap(#[from] golden::diffmap::DiffMapError),
    #[error("{}: {message}", path.display())]
    Junit { path: PathBuf, message: String },
}

/// What the report alone does not say about a run.
#[derive(Debug, Clone, Copy)]
pub struct Run<'a> {
    /// The scene as the user named it (a builtin or a file).
    pub scene_name: &'a str,
    pub scene: &'a Scene,
    pub threads: usize,
    pub seconds: f64,
    /// The RTL coverage of the run (`cosim --coverage`), summed with the
    /// earlier runs in its directory.
    pub coverage: Option<&'a crate::output::coverage::Summary>,
}

impl Run<'_> {
    /// `n` a second over the run's time; none for a run too short to time.
    fn per_second(&self, n: u64) -> Option<f64> {
        (self.seconds > 0.0).then(|| n as f64 / self.seconds)
    }

    /// The junit test case's name: the scene and the method pair.
    fn case_name(&self, report: &CosimReport) -> String {
        format!(
            "{} recip={} sqrt={}",
            self.scene_name, report.recip, report.sqrt
        )
    }
}

fn write_file(path: &Path, text: &str) -> Result<(), ArtefactError> {
    std::fs::write(path, text).map_err(|source| ArtefactError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes the run's files into `dir` (which must exist); returns their
/// paths.
pub fn write(dir: &Path, run: &Run, report: &CosimReport) -> Result<Vec<PathBuf>, ArtefactError> {
    let mut written = Vec::new();
    if let Some(frames) = &report.frames {
        for (name, frame) in [("rtl", &frames.rtl), ("golden", &frames.golden)] {
            let png = dir.join(format!("{name}.png"));
            frame.save_png(&png)?;
            written.push(png);
            let exr = dir.join(format!("{name}.exr"));
            frame.save_exr(&exr)?;
            written.push(exr);
        }
        let maps = dir.join("diffmap");
        std::fs::create_dir_all(&maps).map_err(|source| ArtefactError::Io {
            path: maps.clone(),
            source,
        })?;
        DiffMap::new(&frames.rtl, &frames.golden)?.write(
            &maps,
            "RTL",
            "golden",
            &THESIS_THRESHOLDS,
            1,
        )?;
        written.push(maps);
    }
    let json_path = dir.join("report.json");
    let text = serde_json::to_string_pretty(&to_json(run, report)).expect("JSON of plain values");
    write_file(&json_path, &(text + "\n"))?;
    written.push(json_path);
    let md = dir.join("report.md");
    write_file(&md, &to_markdown(run, report))?;
    written.push(md);
    let junit = dir.join("junit.xml");
    write_file(&junit, &to_junit(run, report, &junit)?)?;
    written.push(junit);
    Ok(written)
}

/// `report.json`.
pub fn to_json(run: &Run, report: &CosimReport) -> serde_json::Value {
    let s = run.scene;
    let r = &s.render;
    json!({
        "tool": format!("rtcosim {}", env!("CARGO_PKG_VERSION")),
        "simulator": crate::VERILATOR_VERSION,
        "scene": {
            "name": run.scene_name,
            "size": [s.camera.width, s.camera.height],
            "scene_hash": format!("{:016x}", s.render_hash()),
            "config_hash": format!("{:016x}", s.config_hash()),
            "depth": r.max_depth,
            "recip": report.recip.to_string(),
            "sqrt": report.sqrt.to_string(),
            "speedups": {
                "bounding_box": r.speedups.bounding_box,
                "fast_plane": r.speedups.fast_plane,
                "shadow_shortcut": r.speedups.shadow_shortcut,
            },
        },
        "window": report.window.to_string(),
        "fault": report.fault.map(|f| f.to_string()),
        "threads": run.threads,
        "seconds": run.seconds,
        "throughput": {
            "pixels_per_second": run.per_second(report.compare.counts.pixels),
            // Clock cycles simulated (the tiles' frame cycles) over the
            // wall time; the pixels' own cycles summed are not a speed.
            "simulated_cycles_per_second": run.per_second(report.stats.frame_cycles),
            "frame_cycles": report.stats.frame_cycles,
        },
        "top": report.top.map(|t| json!({
            "processor": report.design.processor.name(),
            "exp_unit": report.design.exp_unit,
            "processors": report.design.procs.unwrap_or(1),
            "through_top": report.design.procs.is_some(),
            "contexts": t.contexts,
            "tiles": t.tiles,
            "frame_cycles": t.stats.frame_cycles,
            "pixel_cycles": t.stats.pixel_cycles,
            "dispatcher_idle_share": t.idle_share(),
            "batches": t.stats.batches,
        })),
        "passed": report.passed(),
        "compare": report.compare.to_json(),
        "coverage": run.coverage.map(|c| {
            let all = c.to_json();
            json!({
                "kinds": all["kinds"],
                "states_missed": all["states_missed"],
                "transitions_missed": all["transitions_missed"],
            })
        }),
    })
}

/// `report.md`.
pub fn to_markdown(run: &Run, report: &CosimReport) -> String {
    let c = &report.compare.counts;
    let cycles = &report.compare.a_cycles;
    let verdict = if report.passed() { "PASS" } else { "FAIL" };
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# rtcosim cosim: {} — {verdict}\n",
        run.case_name(report)
    );
    let _ = writeln!(md, "| | |\n|---|---|");
    let _ = writeln!(
        md,
        "| scene | {} ({}x{}, stack depth {}) |",
        run.scene_name, run.scene.camera.width, run.scene.camera.height, run.scene.render.max_depth
    );
    let _ = writeln!(md, "| scene hash | `{:016x}` |", run.scene.render_hash());
    let _ = writeln!(
        md,
        "| window | {} ({} pixels) |",
        report.window.describe(),
        report.window.pixels()
    );
    let _ = writeln!(
        md,
        "| methods | recip {}, sqrt {} |",
        report.recip, report.sqrt
    );
    let _ = writeln!(md, "| simulator | {} |", crate::VERILATOR_VERSION);
    if let Some(f) = report.fault {
        let _ = writeln!(
            md,
            "| injected fault | `{f}` (self-test: the run must fail) |"
        );
    }
    let _ = writeln!(
        md,
        "| time | {:.2} s on {} threads: {:.0} pixels/s, {:.2} M simulated cycles/s ({} frame cycles) |",
        run.seconds,
        run.threads,
        run.per_second(c.pixels).unwrap_or(0.0),
        run.per_second(report.stats.frame_cycles).unwrap_or(0.0) / 1e6,
        report.stats.frame_cycles
    );
    if let Some(t) = &report.top {
        let _ = writeln!(
            md,
            "| top | {} processors ({} contexts), {} tiles: {} frame cycles, {:.1}% dispatcher idle |",
            report.design.procs.unwrap_or(1),
            t.contexts,
            t.tiles,
            t.stats.frame_cycles,
            100.0 * t.idle_share()
        );
    }
    let _ = writeln!(md, "\n## Results\n\n| | RTL | golden |\n|---|---:|---:|");
    let _ = writeln!(md, "| events | {} | {} |", c.a_events, c.b_events);
    let _ = writeln!(md, "| cycles | {} | {} |", c.a_cycles, c.b_cycles);
    let _ = writeln!(md, "\n- pixels compared: {}", c.pixels);
    let _ = writeln!(
        md,
        "- events compared: {}, differing: {}",
        c.events_compared, c.event_mismatches
    );
    let _ = writeln!(
        md,
        "- divergent pixels: {} ({} control-flow, {} numeric drift)",
        c.divergent_pixels, c.control_flow_pixels, c.numeric_drift_pixels
    );
    let _ = writeln!(
        md,
        "- RTL cycles per pixel: mean {:.2}, min {}, max {}",
        cycles.mean(),
        cycles.min().unwrap_or(0),
        cycles.max().unwrap_or(0)
    );
    let _ = writeln!(
        md,
        "\n## ULP distances of the lanes both sides wrote\n\n```\n{}\n```",
        report.compare.ulps
    );
    if let Some(d) = &report.compare.first_divergence {
        let _ = writeln!(
            md,
            "\n## First divergence\n\n```\n{}\n```",
            d.text(&report.compare.labels)
        );
    }
    if let Some(c) = run.coverage {
        let _ = writeln!(md, "\n## RTL coverage\n\n| kind | points hit |\n|---|---|");
        for (k, v) in &c.kinds {
            let _ = writeln!(
                md,
                "| {} | {}/{} ({:.1}%) |",
                k.name(),
                v.hit,
                v.total,
                v.percent()
            );
        }
        let _ = writeln!(
            md,
            "\nnever taken: {} states, {} transitions (summary.md in the coverage directory lists them)",
            c.states_missed.len(),
            c.transitions_missed.len()
        );
    }
    if report.frames.is_some() {
        let _ = writeln!(md, "\n## Frames\n\n| RTL | golden |\n|---|---|\n| ![RTL](rtl.png) | ![golden](golden.png) |");
    }
    md
}

/// `junit.xml`: one suite, one case for the scene and method pair.
pub fn to_junit(run: &Run, report: &CosimReport, path: &Path) -> Result<String, ArtefactError> {
    use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
    let mut case = TestCase::new(
        run.case_name(report),
        if report.passed() {
            TestCaseStatus::success()
        } else {
            let mut status = TestCaseStatus::non_success(NonSuccessKind::Failure);
            if let TestCaseStatus::NonSuccess {
                message,
                description,
                ..
            } = &mut status
            {
                let c = &report.compare.counts;
                *message = Some(
                    format!(
                        "{} of {} pixels diverge from golden::micro",
                        c.divergent_pixels, c.pixels
                    )
                    .into(),
                );
                *description = report
                    .compare
                    .first_divergence
                    .map(|d| d.text(&report.compare.labels).to_string().into());
            }
            status
        },
    );
    case.set_classname("rtcosim.cosim")
        .set_time(std::time::Duration::from_secs_f64(run.seconds.max(0.0)));
    let mut suite = TestSuite::new("rtcosim cosim");
    suite.add_test_case(case);
    let mut junit = Report::new("rtcosim");
    junit.add_test_suite(suite);
    junit.to_string().map_err(|e| ArtefactError::Junit {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}
