//! `rtcosim tune`: the cheapest configuration of the pixel processor that
//! renders a scene within an error target, and why.
//!
//! The grid is the sweep's ([`Grid::tune`]): stack depth 1..=[`MAX_DEPTH`] x
//! reciprocal method x square-root method x weight cutoff
//! ([`CUTOFFS`](crate::sweep::CUTOFFS)), each with every speed-up whose
//! precondition the scene meets (they never change the image, only the
//! cycles: `golden::scene` validates that). Each configuration is measured
//! by the sweep ([`sweep::sweep_scene`]: the golden micro-op model, whose
//! cycles are the RTL's, cycle for cycle, and whose colours are bit for
//! bit, against the truth: the f64 reference renderer at the deepest stack
//! the hardware has and no cutoff). The error is the largest or the mean
//! absolute channel difference on the 0..255 scale ([`Measure`]).
//!
//! "Cheapest" is [`cost_order`]: fewest cycles per pixel, then the smaller
//! stack (less hardware), then the fast methods (smaller units), then the
//! larger cutoff, so the answer is unique.

use crate::sweep::{self, Config, Grid, Row, SweepError, ECP5_CLOCK_HZ};
use golden::fp::Method;
use golden::scene::{RenderSettings, Scene, Speedups};
use std::cmp::Ordering;
use std::fmt;

/// How a frame's error against the truth is summarised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Measure {
    /// The largest absolute channel difference (0..255 scale).
    Max,
    /// The mean absolute channel difference (0..255 scale).
    Mean,
}

impl Measure {
    /// A sweep row's error in this measure.
    pub fn of(self, row: &Row) -> f64 {
        match self {
            Measure::Max => row.max_abs_error,
            Measure::Mean => row.mean_abs_error,
        }
    }
}

impl fmt::Display for Measure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Measure::Max => "largest",
            Measure::Mean => "mean",
        })
    }
}

/// "Cheaper first": fewer cycles, then the smaller stack (STACK_DEPTH), then
/// the fast reciprocal, then the fast square root (each the smaller unit:
/// docs/accuracy.md, "Tuning", the area table), then the larger cutoff; a
/// total order on the grid. Cycles decide almost always: the fast methods
/// take a cycle less per operation, so the method tie-break is reached
/// only by a scene that never divides or takes a root.
pub fn cost_order(a: &Row, b: &Row) -> Ordering {
    // Fast before exact, whatever the RTL's codes for them are.
    let hardware = |m: Method| match m {
        Method::Fast => 0u8,
        Method::Exact => 1,
    };
    let key = |r: &Row| {
        let c = r.config();
        (r.frame_cycles, c.depth, hardware(c.recip), hardware(c.sqrt))
    };
    key(a)
        .cmp(&key(b))
        .then(b.weight_cutoff.total_cmp(&a.weight_cutoff))
}

/// Why the tuner cannot run.
#[derive(Debug, thiserror::Error)]
pub enum TuneError {
    #[error("--max-error must be a number in (0, 255] (0..255 scale), got {0}")]
    Target(f64),
    #[error(transparent)]
    Sweep(#[from] SweepError),
    #[error("{config}: refused although its speed-ups were checked: {reason}")]
    Refused { config: String, reason: String },
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

/// The tuner's answer.
#[derive(Debug, Clone)]
pub struct Tuned {
    pub target: f64,
    pub measure: Measure,
    /// The speed-ups that hold (on in every configuration), and why the
    /// others are off.
    pub speedups: Speedups,
    pub refused: Vec<(&'static str, String)>,
    /// Every configuration of the grid, measured, cheapest first.
    pub all: Vec<Row>,
    /// Index into `all` of the cheapest meeting the target, if any.
    pub best: Option<usize>,
}

impl Tuned {
    pub fn best(&self) -> Option<&Row> {
        self.best.map(|i| &self.all[i])
    }

    /// This row's error in the tuner's measure.
    pub fn error(&self, row: &Row) -> f64 {
        self.measure.of(row)
    }

    /// The configuration equal to `best` but for `change`, if in the grid.
    pub fn neighbour(&self, change: impl Fn(&mut Config)) -> Option<&Row> {
        let mut c = self.best()?.config();
        change(&mut c);
        self.all.iter().find(|r| r.config() == c)
    }

    /// The full build's row: the deepest stack, the correctly rounded
    /// units, no cutoff (with the speed-ups that hold).
    pub fn full(&self) -> Option<&Row> {
        let full = Config {
            speedups: self.speedups,
            ..Config::full()
        };
        self.all.iter().find(|r| r.config() == full)
    }

    /// Among the configurations cheaper than the best, the most accurate
    /// (what the next saving would cost).
    pub fn best_cheaper(&self) -> Option<&Row> {
        let i = self.best?;
        self.all[..i]
            .iter()
            .min_by(|a, b| self.error(a).total_cmp(&self.error(b)))
    }

    /// The most accurate configuration of the grid.
    pub fn most_accurate(&self) -> Option<&Row> {
        self.all
            .iter()
            .min_by(|a, b| self.error(a).total_cmp(&self.error(b)))
    }
}

/// The grid [`tune`] runs on `scene` (for a progress bar's length).
pub fn grid(scene: &Scene) -> Grid {
    Grid::tune(speedups_that_hold(scene).0)
}

/// Runs the grid on the current rayon pool; `progress` is called once per
/// configuration finished. `name` names the scene in errors.
pub fn tune(
    name: &str,
    scene: &Scene,
    target: f64,
    measure: Measure,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Tuned, TuneError> {
    let target = check_target(target)?;
    let (speedups, refused) = speedups_that_hold(scene);
    sweep::check_costs(name, scene, &Grid::tune(speedups))?;
    let truth = sweep::reference_frame(name, scene)?;
    let swept = sweep::sweep_scene(
        name,
        scene,
        &truth,
        &Grid::tune(speedups),
        ECP5_CLOCK_HZ,
        progress,
    );
    if let Some(s) = swept.skipped.first() {
        // The speed-ups were checked above, so the scene accepts every
        // configuration; one it refuses is a bug to report, not to hide.
        return Err(TuneError::Refused {
            config: s.config.label(),
            reason: s.reason.clone(),
        });
    }
    let mut all = swept.rows;
    all.sort_by(cost_order);
    let best = all.iter().position(|r| measure.of(r) <= target);
    Ok(Tuned {
        target,
        measure,
        speedups,
        refused,
        all,
        best,
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

    /// A row that differs only in what `cost_order` reads; the rest is
    /// the same placeholder everywhere.
    fn row(frame_cycles: u64, depth: u32, recip: Method, sqrt: Method, cutoff: f32) -> Row {
        Row {
            scene: "s".into(),
            width: 1,
            height: 1,
            processor: crate::processor::ProcessorKind::Compact,
            recip: recip.name(),
            sqrt: sqrt.name(),
            depth,
            bounding_box: false,
            fast_plane: false,
            shadow_shortcut: false,
            weight_cutoff: cutoff,
            cycles_per_pixel: frame_cycles as f64,
            max_cycles: frame_cycles,
            frame_cycles,
            fps_at_clock_mhz: 1.0,
            clock_mhz: 1.0,
            device_processors: 1,
            device_binding: "LUTs".into(),
            device_clock_mhz: 1.0,
            device_fps: 1.0,
            luts_per_processor: 1,
            dsp_per_processor: 1,
            cost_source: "measured".into(),
            mean_abs_error: 0.0,
            max_abs_error: 0.0,
            share_pixels_over_half: 0.0,
            max_ulps: 0,
            nan_mismatches: 0,
            rtl_stack_depth: depth,
            rtl_recip_method: recip.code(),
            rtl_sqrt_method: sqrt.code(),
            pareto: false,
            differs_from_full: None,
            rtl_pixels: None,
            rtl_confirmed: None,
        }
    }

    /// The documented rule (docs/accuracy.md, "Tuning"): fewest cycles,
    /// then the smaller STACK_DEPTH, then the fast methods (recip before
    /// sqrt), then the larger cutoff. Each pair below ties on every key
    /// before the one it tests; the list is in the documented order and
    /// is shuffled before sorting.
    #[test]
    fn cost_order_is_the_documented_tie_break() {
        use Method::{Exact, Fast};
        let cheapest_first = [
            row(100, 8, Exact, Exact, 0.0),       // fewer cycles beat everything
            row(101, 3, Exact, Exact, 0.0),       // then the smaller stack
            row(101, 4, Fast, Exact, 0.0),        // then the fast reciprocal
            row(101, 4, Exact, Fast, 1.0 / 4.0),  // then the fast square root
            row(101, 4, Exact, Exact, 1.0 / 2.0), // then the larger cutoff
            row(101, 4, Exact, Exact, 1.0 / 16.0),
            row(101, 4, Exact, Exact, 0.0),
        ];
        let labels = |rows: &[Row]| -> Vec<String> {
            rows.iter()
                .map(|r| format!("{} cycles, {}", r.frame_cycles, r.config().label()))
                .collect()
        };
        for rotation in 0..cheapest_first.len() {
            let mut rows = cheapest_first.to_vec();
            rows.rotate_left(rotation);
            rows.reverse();
            rows.sort_by(cost_order);
            assert_eq!(
                labels(&rows),
                labels(&cheapest_first),
                "rotated by {rotation}"
            );
        }
        // Fast before exact: the opposite of the RTL's codes (0 exact, 1
        // fast), which an order on the codes would follow.
        assert!(Exact.code() < Fast.code());
        assert_eq!(
            cost_order(&row(7, 2, Fast, Fast, 0.0), &row(7, 2, Exact, Fast, 0.0)),
            Ordering::Less
        );
        assert_eq!(
            cost_order(&row(7, 2, Fast, Fast, 0.0), &row(7, 2, Fast, Exact, 0.0)),
            Ordering::Less
        );
    }

    #[test]
    fn the_tune_grid_has_every_depth_method_pair_and_cutoff_once() {
        let g = Grid::tune(Speedups::default()).configs();
        // Depth 1: 4 method pairs, no cutoff; depths 2..=8: 4 x 9.
        assert_eq!(g.len(), 4 + 7 * 4 * sweep::CUTOFFS.len());
        for (i, a) in g.iter().enumerate() {
            assert!(!g[i + 1..].contains(a), "{a:?} twice");
        }
    }
}
