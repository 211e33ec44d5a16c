//! `rtcosim tune`: the cheapest configuration of the pixel processor that
//! renders a scene within an error target, and why.
//!
//! The grid: stack depth 1..=[`MAX_DEPTH`] x reciprocal method x
//! square-root method x weight cutoff ([`CUTOFFS`]), each with every
//! speed-up whose precondition the scene meets (they never change the image,
//! only the cycles: `golden::scene` validates that). Every configuration is
//! rendered with the golden micro-op model (its cycles are the RTL's, cycle
//! for cycle, and its colours bit for bit) and compared with the truth: the
//! f64 reference renderer at the deepest stack the hardware has
//! ([`MAX_DEPTH`]) and no cutoff. The error is the largest or the mean
//! absolute channel difference on the 0..255 scale ([`Measure`]).
//!
//! "Cheapest" is [`cost_order`]: fewest cycles per pixel, then the smaller
//! stack (less hardware), then the rest in a fixed order, so the answer is
//! unique.

use golden::fp::Method;
use golden::frame::Frame;
use golden::scene::{RenderSettings, Scene, SceneError, Speedups, MAX_DEPTH};
use rayon::prelude::*;
use std::cmp::Ordering;
use std::fmt;

/// The weight cutoffs tried: off, and the powers of two 2^-8 (a weight that
/// can move a channel by at most one 8-bit step) to 2^-1. Exact in f32 and
/// f64, so both models compare against the same number.
pub const CUTOFFS: [f32; 9] = [
    0.0,
    1.0 / 256.0,
    1.0 / 128.0,
    1.0 / 64.0,
    1.0 / 32.0,
    1.0 / 16.0,
    1.0 / 8.0,
    1.0 / 4.0,
    1.0 / 2.0,
];

/// How a frame's error against the truth is summarised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Measure {
    /// The largest absolute channel difference (0..255 scale).
    Max,
    /// The mean absolute channel difference (0..255 scale).
    Mean,
}

impl fmt::Display for Measure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Measure::Max => "largest",
            Measure::Mean => "mean",
        })
    }
}

/// One configuration, rendered and measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluated {
    pub render: RenderSettings,
    /// The frame's cycles (golden micro, = the RTL's) and pixels.
    pub cycles: u64,
    pub pixels: u64,
    /// Against the truth, 0..255 scale.
    pub max_error: f64,
    pub mean_error: f64,
}

impl Evaluated {
    pub fn cycles_per_pixel(&self) -> f64 {
        self.cycles as f64 / self.pixels as f64
    }

    pub fn error(&self, m: Measure) -> f64 {
        match m {
            Measure::Max => self.max_error,
            Measure::Mean => self.mean_error,
        }
    }
}

/// "Cheaper first": fewer cycles, then the smaller stack (STACK_DEPTH), then
/// the fast methods (fewer cycles already decided the rest), then the
/// larger cutoff; a total order on the grid.
pub fn cost_order(a: &Evaluated, b: &Evaluated) -> Ordering {
    let key = |e: &Evaluated| {
        (
            e.cycles,
            e.render.max_depth,
            e.render.recip.code(),
            e.render.sqrt.code(),
        )
    };
    key(a)
        .cmp(&key(b))
        .then(b.render.weight_cutoff.total_cmp(&a.render.weight_cutoff))
}

/// Why the tuner cannot run.
#[derive(Debug, thiserror::Error)]
pub enum TuneError {
    #[error("--max-error must be a number in (0, 255] (0..255 scale), got {0}")]
    Target(f64),
    #[error(transparent)]
    Scene(#[from] SceneError),
}

/// The error target, checked: finite, above 0 (no f32 frame equals the f64
/// truth exactly), at most 255 (the whole scale).
pub fn check_target(e: f64) -> Result<f64, TuneError> {
    if e.is_finite() && e > 0.0 && e <= 255.0 {
        Ok(e)
    } else {
        Err(TuneError::Target(e))
    }
}

/// The speed-ups whose preconditions `scene` meets (each checked alone,
/// then together), and for each refused one the validator's reason.
pub fn speedups_that_hold(scene: &Scene) -> (Speedups, Vec<(&'static str, String)>) {
    let base = RenderSettings {
        speedups: Speedups::default(),
        ..scene.render
    };
    let mut on = Speedups::default();
    let mut refused = Vec::new();
    type Switch = fn(&mut Speedups);
    let tries: [(&str, Switch); 3] = [
        ("bounding_box", |s| s.bounding_box = true),
        ("fast_plane", |s| s.fast_plane = true),
        ("shadow_shortcut", |s| s.shadow_shortcut = true),
    ];
    for (name, set) in tries {
        let mut r = base;
        set(&mut r.speedups);
        match scene.with_render(r, "tune") {
            Ok(_) => set(&mut on),
            Err(e) => refused.push((name, e.to_string())),
        }
    }
    (on, refused)
}

/// The configurations of the grid for `scene` (its image, its speed-ups
/// that hold): depth 1 has no reflection to cut, so only cutoff 0.
pub fn grid(speedups: Speedups) -> Vec<RenderSettings> {
    let methods = [Method::Exact, Method::Fast];
    let mut out = Vec::new();
    for max_depth in 1..=MAX_DEPTH {
        for recip in methods {
            for sqrt in methods {
                for &weight_cutoff in CUTOFFS.iter().filter(|&&c| max_depth > 1 || c == 0.0) {
                    out.push(RenderSettings {
                        max_depth,
                        speedups,
                        recip,
                        sqrt,
                        weight_cutoff,
                        // Part of the picture, not a configuration: each
                        // evaluation keeps the scene's (`evaluate`).
                        exposure: None,
                    });
                }
            }
        }
    }
    out
}

/// Renders `scene` with `render` (golden micro) and measures it.
pub fn evaluate(
    scene: &Scene,
    render: RenderSettings,
    truth: &Frame,
) -> Result<Evaluated, SceneError> {
    let picture = RenderSettings {
        exposure: scene.render.exposure,
        ..render
    };
    let s = scene.with_render(picture, "tune")?;
    let (frame, stats) = golden::micro::render(&s, &|_| {});
    let diff = frame
        .compare(truth)
        .expect("the same scene's frames have one size");
    Ok(Evaluated {
        render,
        cycles: stats.cycles,
        pixels: stats.pixels,
        max_error: diff.max_abs_diff,
        mean_error: diff.mean(),
    })
}

/// The tuner's answer.
#[derive(Debug, Clone)]
pub struct Tuned {
    pub target: f64,
    pub measure: Measure,
    /// The speed-ups that hold (on in every configuration), and why the
    /// others are off.
    pub speedups: Speedups,
    pub refused: Vec<(&'static str, String)>,
    /// Every configuration of the grid, cheapest first.
    pub all: Vec<Evaluated>,
    /// Index into `all` of the cheapest meeting the target, if any.
    pub best: Option<usize>,
}

impl Tuned {
    pub fn best(&self) -> Option<&Evaluated> {
        self.best.map(|i| &self.all[i])
    }

    /// The configuration equal to `best` but for `change`, if in the grid.
    pub fn neighbour(&self, change: impl Fn(&mut RenderSettings)) -> Option<&Evaluated> {
        let mut r = self.best()?.render;
        change(&mut r);
        self.all.iter().find(|e| e.render == r)
    }

    /// Among the configurations cheaper than the best, the most accurate
    /// (what the next saving would cost).
    pub fn best_cheaper(&self) -> Option<&Evaluated> {
        let i = self.best?;
        self.all[..i]
            .iter()
            .min_by(|a, b| a.error(self.measure).total_cmp(&b.error(self.measure)))
    }
}

/// Runs the grid on the current rayon pool; `progress` is called once per
/// configuration finished.
pub fn tune(
    scene: &Scene,
    target: f64,
    measure: Measure,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Tuned, TuneError> {
    let target = check_target(target)?;
    let (speedups, refused) = speedups_that_hold(scene);
    let truth = golden::reference::truth(scene, &|_| {})?;
    let mut all = grid(speedups)
        .into_par_iter()
        .map(|r| {
            let e = evaluate(scene, r, &truth);
            progress(1);
            e
        })
        .collect::<Result<Vec<_>, _>>()?;
    all.sort_by(cost_order);
    let best = all.iter().position(|e| e.error(measure) <= target);
    Ok(Tuned {
        target,
        measure,
        speedups,
        refused,
        all,
        best,
    })
}

/// How many configurations [`tune`] evaluates (for a progress bar).
pub fn grid_len(scene: &Scene) -> u64 {
    grid(speedups_that_hold(scene).0).len() as u64
}

/// A configuration in a line: `depth 4, recip fast, sqrt exact, cutoff 1/64`.
pub fn describe(r: &RenderSettings) -> String {
    let cut = if r.weight_cutoff == 0.0 {
        "no cutoff".to_string()
    } else {
        format!("cutoff 1/{}", (1.0 / r.weight_cutoff).round())
    };
    format!(
        "depth {}, recip {}, sqrt {}, {cut}",
        r.max_depth,
        r.recip.name(),
        r.sqrt.name()
    )
}

/// The register file's size in a build: what STACK_DEPTH changes.
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

/// Why the area could not be measured.
#[derive(Debug, thiserror::Error)]
pub enum AreaError {
    #[error("running yosys (is it installed? --area needs it): {0}")]
    Spawn(std::io::Error),
    #[error("yosys failed on {what}:\n{stderr}")]
    Failed { what: String, stderr: String },
    #[error("yosys printed no {0:?} line")]
    Parse(&'static str),
}

/// The number after `label` in yosys' `stat` output (the last such line).
fn stat_number(out: &str, label: &'static str) -> Result<u64, AreaError> {
    out.lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix(label))
        .and_then(|rest| rest.trim().parse().ok())
        .ok_or(AreaError::Parse(label))
}

/// The register file of a build with `stack_depth` levels, measured with
/// yosys (`read_verilog memory.v mem_ctrl.v; hierarchy -chparam
/// STACK_DEPTH; proc; opt; stat`, a fraction of a second each): the part of
/// the design that STACK_DEPTH sizes. The float units, whose area the
/// methods change, are not measured here: `proc` alone on fp_recip takes
/// minutes (its seed table).
pub fn register_file_area(
    rtl_pp: &std::path::Path,
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
        let out = std::process::Command::new("yosys")
            .args(["-q", "-p", &format!("{script}; tee -o /dev/stdout stat")])
            .output()
            .map_err(AreaError::Spawn)?;
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        if !out.status.success() {
            return Err(AreaError::Failed {
                what: format!("{top} with STACK_DEPTH {stack_depth}"),
                stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
            });
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_targets_are_refused() {
        for e in [0.0, -1.0, f64::NAN, f64::INFINITY, 255.5] {
            assert!(check_target(e).is_err(), "{e}");
        }
        for e in [1e-9, 0.5, 255.0] {
            assert_eq!(check_target(e).ok(), Some(e));
        }
    }

    #[test]
    fn the_grid_has_every_depth_method_pair_and_cutoff_once() {
        let g = grid(Speedups::default());
        // Depth 1: 4 method pairs, no cutoff; depths 2..=8: 4 x 9.
        assert_eq!(g.len(), 4 + 7 * 4 * CUTOFFS.len());
        for (i, a) in g.iter().enumerate() {
            assert!(!g[i + 1..].contains(a), "{a:?} twice");
        }
    }
}
