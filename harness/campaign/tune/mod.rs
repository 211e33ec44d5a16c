//! `rtcosim tune`: the cheapest configuration that renders a scene within
//! an error target, why, and its check on the RTL.
//!
//! The grid is the sweep's ([`Grid::tune`]): both processors (or one) x
//! stack depth 1..=[`MAX_DEPTH`] x reciprocal method x square-root method x
//! weight cutoff ([`CUTOFFS`](crate::campaign::sweep::CUTOFFS)), each with every
//! speed-up whose precondition the scene meets (they never change the
//! image, only the cycles: `golden::scene` validates that). Each
//! configuration is measured by the sweep ([`sweep::sweep_scene`]: the
//! golden micro-op model, whose colours are the RTL's bit for bit and
//! whose cycles are the compact processor's cycle for cycle and the fast
//! one's by its barrel rule, against the truth: the f64 reference renderer
//! at the deepest stack the hardware has and no cutoff) and priced on a
//! Virtex-6 LX760 ([`crate::output::device`]). The error is the largest or the mean
//! absolute channel difference on the 0..255 scale ([`Measure`]).
//!
//! "Cheapest" is [`Cost`]'s order ([`Cost::order`]): by device frames a
//! second, by area (processors on the device) or by cycles, each with
//! the same tie-breaks after it, so the answer is unique. The pick is then
//! co-simulated on the build it is priced as ([`sweep::RtlCheck`]) before
//! it is recommended.

pub mod report;
use crate::campaign::sweep::{self, Config, Grid, Row, SweepError, ECP5_CLOCK_HZ};
use crate::design::processor::ProcessorKind;
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

/// What "cheapest" means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Cost {
    /// The most frames a second from one Virtex-6 LX760 filled with
    /// processors of the configuration's build.
    DeviceFps,
    /// The least area: the most processors of the build on one LX760 (the
    /// build's share of its binding resource), then the fewest LUTs a
    /// processor.
    Area,
    /// The fewest cycles one processor takes for the frame.
    Cycles,
}

impl fmt::Display for Cost {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Cost::DeviceFps => "device frames/s",
            Cost::Area => "area",
            Cost::Cycles => "cycles",
        })
    }
}

impl Cost {
    /// "Cheaper first", a total order on the grid. First this cost: the
    /// higher device frames/s; or the more processors on the device, then
    /// the fewer LUTs a processor; or nothing more. Then, for every cost,
    /// the tie-breaks: fewer frame cycles, the smaller stack, the fast
    /// reciprocal, the fast square root (each the smaller unit:
    /// docs/accuracy.md, "Tuning", the area table), the compact processor
    /// (the smaller), the larger cutoff, the glass opaque (a build without
    /// refraction). Within one build device frames/s
    /// and cycles rank alike; the method tie-break is reached only by a
    /// scene that never divides or takes a root.
    pub fn order(self, a: &Row, b: &Row) -> Ordering {
        let first = match self {
            Cost::DeviceFps => b.device_fps.total_cmp(&a.device_fps),
            Cost::Area => b
                .device_processors
                .cmp(&a.device_processors)
                .then(a.luts_per_processor.cmp(&b.luts_per_processor)),
            Cost::Cycles => Ordering::Equal,
        };
        // Fast before exact, whatever the RTL's codes for them are; the
        // compact processor before the fast one.
        let hardware = |m: Method| match m {
            Method::Fast => 0u8,
            Method::Exact => 1,
        };
        let key = |r: &Row| {
            let c = r.config();
            (
                r.frame_cycles,
                c.depth,
                hardware(c.recip),
                hardware(c.sqrt),
                c.processor,
            )
        };
        first
            .then(key(a).cmp(&key(b)))
            .then(b.weight_cutoff.total_cmp(&a.weight_cutoff))
            .then(b.opaque_glass.cmp(&a.opaque_glass))
    }
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
    pub cost: Cost,
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

    /// The full build's row on the best's processor: the deepest stack,
    /// the correctly rounded units, no cutoff (with the speed-ups that
    /// hold).
    pub fn full(&self) -> Option<&Row> {
        let full = Config {
            processor: self.best()?.processor,
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

    /// Co-simulates the best configuration of `scene` (named `name`) on
    /// the RTL build it is priced as ([`sweep::RtlCheck`]: every pixel
    /// where its frame differs from the full configuration's, and
    /// `options.sample` more) and fills in its RTL columns. `total` is
    /// called first with the pixels to come, `progress` with pixels
    /// finished. None when nothing meets the target.
    pub fn confirm(
        &mut self,
        name: &str,
        scene: &Scene,
        options: &sweep::ConfirmOptions,
        total: &dyn Fn(u64),
        progress: &(dyn Fn(u64) + Sync),
    ) -> Result<Option<(sweep::RtlCheck, crate::check::compare::CompareReport)>, TuneError> {
        let Some(i) = self.best else {
            return Ok(None);
        };
        let full = sweep::full_frame(name, scene)?;
        let check = sweep::RtlCheck::plan(name, scene, &self.all[i].config(), &full, options)?;
        total(check.pixels.len() as u64);
        let report = check.run(name, options, progress)?;
        let row = &mut self.all[i];
        row.differs_from_full = Some(check.differing);
        row.rtl_pixels = Some(report.counts.pixels);
        row.rtl_confirmed = Some(report.passed());
        Ok(Some((check, report)))
    }
}

/// The grid [`tune`] runs on `scene`: [`Grid::tune`] with the speed-ups
/// that hold, on `processors` (empty: both).
pub fn grid(scene: &Scene, processors: &[ProcessorKind]) -> Grid {
    let mut grid = Grid::tune(speedups_that_hold(scene).0);
    if !processors.is_empty() {
        grid.processors = processors.to_vec();
    }
    grid
}

/// Runs [`grid`] on the current rayon pool and ranks it by `cost`;
/// `progress` is called once per configuration finished. `name` names the
/// scene in errors.
pub fn tune(
    name: &str,
    scene: &Scene,
    target: f64,
    measure: Measure,
    cost: Cost,
    processors: &[ProcessorKind],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Tuned, TuneError> {
    let target = check_target(target)?;
    let (speedups, refused) = speedups_that_hold(scene);
    let grid = grid(scene, processors);
    sweep::check_costs(name, scene, &grid)?;
    let truth = sweep::reference_frame(name, scene)?;
    // The front is not used: the cost ranks.
    let axis = sweep::Axis::DeviceFps;
    let swept = sweep::sweep_scene(name, scene, &truth, &grid, ECP5_CLOCK_HZ, axis, progress);
    if let Some(s) = swept.skipped.first() {
        // The speed-ups were checked above, so the scene accepts every
        // configuration; one it refuses is a bug to report, not to hide.
        return Err(TuneError::Refused {
            config: s.config.label(),
            reason: s.reason.clone(),
        });
    }
    let mut all = swept.rows;
    all.sort_by(|a, b| cost.order(a, b));
    let best = all.iter().position(|r| measure.of(r) <= target);
    Ok(Tuned {
        target,
        measure,
        cost,
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

    /// A row that differs only in what [`Cost::order`] reads; the rest is
    /// the same placeholder everywhere.
    fn row(frame_cycles: u64, depth: u32, recip: Method, sqrt: Method, cutoff: f32) -> Row {
        Row {
            scene: "s".into(),
            width: 1,
            height: 1,
            processor: ProcessorKind::Compact,
            recip: recip.name(),
            sqrt: sqrt.name(),
            depth,
            bounding_box: false,
            fast_plane: false,
            shadow_shortcut: false,
            weight_cutoff: cutoff,
            opaque_glass: false,
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

    /// A compact-processor row at `frame_cycles`, `processors` a device
    /// of `luts` LUTs each, drawing `fps` frames a second.
    fn priced(frame_cycles: u64, fps: f64, processors: u32, luts: u32) -> Row {
        Row {
            device_fps: fps,
            device_processors: processors,
            luts_per_processor: luts,
            ..row(frame_cycles, 8, Method::Exact, Method::Exact, 0.0)
        }
    }

    /// Sorts `cheapest_first` by `cost` from every rotation of it,
    /// reversed, and checks it comes back in its own order.
    fn assert_ranks(cost: Cost, cheapest_first: &[Row]) {
        let labels = |rows: &[Row]| -> Vec<String> {
            rows.iter()
                .map(|r| {
                    format!(
                        "{} cycles, {} fps, {} processors of {} LUTs, {}",
                        r.frame_cycles,
                        r.device_fps,
                        r.device_processors,
                        r.luts_per_processor,
                        r.config().label()
                    )
                })
                .collect()
        };
        for rotation in 0..cheapest_first.len() {
            let mut rows = cheapest_first.to_vec();
            rows.rotate_left(rotation);
            rows.reverse();
            rows.sort_by(|a, b| cost.order(a, b));
            assert_eq!(
                labels(&rows),
                labels(cheapest_first),
                "{cost}, rotated by {rotation}"
            );
        }
    }

    /// The documented rule (docs/accuracy.md, "Tuning") by cycles: fewest
    /// cycles, then the smaller STACK_DEPTH, then the fast methods (recip
    /// before sqrt), then the compact processor, then the larger cutoff.
    /// Each pair below ties on every key before the one it tests; the
    /// list is in the documented order and is shuffled before sorting.
    /// Every cost ends in these tie-breaks.
    #[test]
    fn cost_order_is_the_documented_tie_break() {
        use Method::{Exact, Fast};
        let on_fast = |r: Row| Row {
            processor: ProcessorKind::Fast,
            ..r
        };
        let cheapest_first = [
            row(100, 8, Exact, Exact, 0.0),        // fewer cycles beat everything
            row(101, 3, Exact, Exact, 0.0),        // then the smaller stack
            row(101, 4, Fast, Exact, 0.0),         // then the fast reciprocal
            row(101, 4, Exact, Fast, 1.0 / 4.0),   // then the fast square root
            row(101, 4, Exact, Exact, 1.0 / 64.0), // then the compact processor
            on_fast(row(101, 4, Exact, Exact, 1.0 / 2.0)), // then the larger cutoff
            on_fast(row(101, 4, Exact, Exact, 1.0 / 16.0)),
            Row {
                opaque_glass: true, // then the glass opaque
                ..on_fast(row(101, 4, Exact, Exact, 0.0))
            },
            on_fast(row(101, 4, Exact, Exact, 0.0)),
        ];
        for cost in [Cost::Cycles, Cost::DeviceFps, Cost::Area] {
            assert_ranks(cost, &cheapest_first);
        }
        // Fast before exact: the opposite of the RTL's codes (0 exact, 1
        // fast), which an order on the codes would follow.
        assert!(Exact.code() < Fast.code());
        let order = |a, b| Cost::Cycles.order(&a, &b);
        assert_eq!(
            order(row(7, 2, Fast, Fast, 0.0), row(7, 2, Exact, Fast, 0.0)),
            Ordering::Less
        );
        assert_eq!(
            order(row(7, 2, Fast, Fast, 0.0), row(7, 2, Fast, Exact, 0.0)),
            Ordering::Less
        );
    }

    /// Device frames/s first, then the cycles' tie-breaks; area: the more
    /// processors on the device, then the fewer LUTs, then the cycles'.
    #[test]
    fn device_fps_and_area_rank_before_the_tie_breaks() {
        assert_ranks(
            Cost::DeviceFps,
            &[
                priced(900, 30.0, 2, 9),  // the most frames/s, however many cycles
                priced(100, 20.0, 50, 1), // then fewer cycles break a tie
                priced(101, 20.0, 50, 1),
            ],
        );
        assert_ranks(
            Cost::Area,
            &[
                priced(900, 1.0, 50, 9),  // the most processors on the device
                priced(900, 1.0, 40, 1),  // then the fewest LUTs
                priced(100, 9.0, 40, 2),  // then fewer cycles
                priced(101, 99.0, 40, 2), // (frames/s do not count)
            ],
        );
        assert_ranks(
            Cost::Cycles,
            &[priced(100, 1.0, 1, 9), priced(101, 99.0, 99, 1)],
        );
    }

    #[test]
    fn the_tune_grid_has_both_processors_and_every_depth_method_pair_and_cutoff_once() {
        let grid = Grid::tune(Speedups::default());
        let opaque = Scene::reference();
        let glass = Scene::builtin("glass_room").expect("a builtin");
        for (scene, glasses) in [(&opaque, 1), (&glass, 2)] {
            let g = grid.configs_for(scene);
            // Per processor, depth 1: 4 method pairs, no cutoff; depths
            // 2..=8: 4 x 9; each with the glass as it is, and for a scene
            // with glass opaque too.
            assert_eq!(g.len(), 2 * (4 + 7 * 4 * sweep::CUTOFFS.len()) * glasses);
            for (i, a) in g.iter().enumerate() {
                assert!(!g[i + 1..].contains(a), "{a:?} twice");
            }
            for p in ProcessorKind::ALL {
                assert_eq!(g.iter().filter(|c| c.processor == p).count(), g.len() / 2);
            }
            assert_eq!(
                g.iter().filter(|c| c.opaque_glass).count(),
                g.len() * (glasses - 1) / 2
            );
        }
    }
}
