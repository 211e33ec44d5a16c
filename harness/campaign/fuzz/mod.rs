//! A scene-fuzzing campaign: every generated scene ends one of two ways,
//! refused at load with a clear error, or co-simulated (RTL against
//! golden::micro, every pixel) with 0 divergences, and its colours checked
//! against the f64 reference (finite, and how far apart).
//!
//! Scenes run in parallel on the current rayon pool, each on one thread,
//! on verilated models the thread keeps (one per method pair), so a
//! campaign of thousands of tiny scenes does not build thousands of models.
//! The report is in scene order and does not depend on the thread count.

pub mod chart;
pub mod generate;
pub mod guided;
pub mod mutator;
pub mod shrink;
pub mod summary;

use crate::check::compare::{CompareReport, Labels, StateSet};
use crate::check::cosim::{self, CosimError, CosimOptions};
use crate::design::processor::ProcessorKind;
use crate::design::top::Stall;
use crate::design::{Design, Dut, Fault, PpError};
use generate::Generated;
use golden::scene::Scene;
use golden::window::Window;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What happened to one scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Fate {
    /// Refused at load: the field and the whole message.
    Refused { field: String, message: String },
    /// Co-simulated.
    Ran(Box<Ran>),
    /// The run itself failed (a hung RTL, a model error).
    Error(String),
}

/// A co-simulated scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Ran {
    /// The RTL against golden::micro.
    pub compare: CompareReport,
    /// The largest |micro - reference| over the image's channels, on the
    /// 0..255 scale.
    pub max_error: f64,
    /// Channels that are NaN or infinite in the micro-op model or the f64
    /// reference.
    pub nonfinite: u64,
}

/// One scene's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneOutcome {
    pub scene: Generated,
    pub fate: Fate,
}

impl SceneOutcome {
    /// Whether the scene broke the promise: a divergence, a non-finite
    /// colour, or a run that failed. A refusal keeps it.
    pub fn failed(&self) -> bool {
        match &self.fate {
            Fate::Refused { .. } => false,
            Fate::Ran(r) => !r.compare.passed() || r.nonfinite > 0,
            Fate::Error(_) => true,
        }
    }
}

/// What a campaign found.
#[derive(Debug, Clone, PartialEq)]
pub struct FuzzReport {
    pub seed: u64,
    pub scenes: u64,
    /// Scenes generated inside the documented limits, and of those accepted.
    pub in_limits: u64,
    pub in_limits_accepted: u64,
    /// Refusals by field (`camera.distance`, `render.fast_plane`, ...).
    pub refused_by_field: BTreeMap<String, u64>,
    pub accepted: u64,
    /// Every co-simulated pixel, all scenes together.
    pub compare: CompareReport,
    /// Each accepted scene's largest colour error against the f64
    /// reference, 0..255 scale, in scene order.
    pub max_errors: Vec<f64>,
    pub nonfinite: u64,
    /// The scenes that broke the promise, with where they were written.
    pub failures: Vec<(SceneOutcome, Option<PathBuf>)>,
}

impl FuzzReport {
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }

    /// The states the accepted scenes reached.
    pub fn states(&self) -> &StateSet {
        &self.compare.states
    }

    fn add(&mut self, o: SceneOutcome, failure_path: Option<PathBuf>) {
        self.scenes += 1;
        let accepted = !matches!(o.fate, Fate::Refused { .. });
        if o.scene.in_limits {
            self.in_limits += 1;
            self.in_limits_accepted += u64::from(accepted);
        }
        match &o.fate {
            Fate::Refused { field, .. } => {
                *self.refused_by_field.entry(field.clone()).or_default() += 1;
            }
            Fate::Ran(r) => {
                self.accepted += 1;
                self.compare.merge(r.compare.clone());
                self.max_errors.push(r.max_error);
                self.nonfinite += r.nonfinite;
            }
            Fate::Error(_) => self.accepted += 1,
        }
        if o.failed() {
            self.failures.push((o, failure_path));
        }
    }
}

/// How to run a campaign.
#[derive(Debug, Clone)]
pub struct FuzzOptions {
    pub seed: u64,
    /// Scenes `first..first + count`.
    pub first: u64,
    pub count: u64,
    /// Where failing scenes are written (`seed-S-scene-I.toml`), if anywhere.
    pub failures_dir: Option<PathBuf>,
    pub timeout_cycles: u64,
    /// A fault injected into the RTL of every scene (a self-test: every
    /// accepted scene whose pixels write in that state must fail).
    pub fault: Option<Fault>,
    /// The pixel processor the scenes run on.
    pub processor: ProcessorKind,
}

/// Refuses, before any scene runs, a campaign on `processor` that would
/// need a model this build lacks: the generator draws every method pair.
pub fn check_models(processor: ProcessorKind) -> Result<(), PpError> {
    let all = golden::fp::Method::ALL;
    Design::check_all(
        all.into_iter()
            .flat_map(|recip| all.map(|sqrt| Design::new(processor, recip, sqrt))),
    )
}

/// A worker's models, one per design (the campaign's processor with each
/// method pair the scenes draw), built when first needed.
pub(super) type Models = Vec<(Design, Dut)>;

/// The model of `design` in `models`, built (with `options`' timeout and
/// fault) if missing.
fn model_of<'m>(
    models: &'m mut Models,
    design: Design,
    options: &CosimOptions,
) -> Result<&'m mut Dut, PpError> {
    let i = match models.iter().position(|(d, _)| *d == design) {
        Some(i) => i,
        None => {
            models.push((design, cosim::open(&design, options)?));
            models.len() - 1
        }
    };
    Ok(&mut models[i].1)
}

/// Loads, co-simulates and checks one generated scene.
fn run_scene(
    models: &mut Models,
    g: Generated,
    options: &CosimOptions,
    processor: ProcessorKind,
) -> SceneOutcome {
    let scene = match Scene::from_toml(&g.toml, &format!("fuzz scene {}", g.index)) {
        Ok(s) => s,
        Err(e) => {
            return SceneOutcome {
                fate: Fate::Refused {
                    field: field_kind(e.field().unwrap_or("(file)")),
                    message: e.to_string(),
                },
                scene: g,
            }
        }
    };
    let fate = match check(models, &scene, options, processor) {
        Ok(r) => Fate::Ran(Box::new(r)),
        Err(e) => Fate::Error(e.to_string()),
    };
    SceneOutcome { scene: g, fate }
}

/// A field path without its indices: `sphere[2].center[0]` ->
/// `sphere.center`, so refusals count by kind of field.
pub(super) fn field_kind(field: &str) -> String {
    let mut out = String::with_capacity(field.len());
    let mut depth = 0;
    for c in field.chars() {
        match c {
            '[' => depth += 1,
            ']' => depth -= 1,
            c if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

/// Co-simulates every pixel of `scene` on `processor` (a model of
/// `models`, built if missing) and checks its colours against the f64
/// reference.
pub(super) fn check(
    models: &mut Models,
    scene: &Scene,
    options: &CosimOptions,
    processor: ProcessorKind,
) -> Result<Ran, CosimError> {
    let mut max_error = 0.0f64;
    let mut nonfinite = 0;
    let mut each = |v: &crate::check::compare::PixelVerdict| {
        let micro = v.b.rgb.map(|bits| f64::from(f32::from_bits(bits)));
        let reference = golden::reference::render_pixel(scene, v.x, v.y);
        for ch in 0..3 {
            if !micro[ch].is_finite() || !reference[ch].is_finite() {
                nonfinite += 1;
            } else {
                max_error = max_error.max((micro[ch] - reference[ch]).abs() * 255.0);
            }
        }
    };
    let window = Window::full(scene);
    let dut = model_of(models, Design::for_scene(processor, scene), options)?;
    let report = cosim::run_on(dut, scene, window, options, &mut each)?;
    if !report.passed() && report.compare.passed() {
        return Err(CosimError::Rtl(PpError::Model {
            pixel: None,
            message: format!(
                "every pixel agreed, but the frame's cycles are not the barrel rule's: {}",
                report.top.map_or(String::new(), |t| format!(
                    "{} against {:?}",
                    t.stats.frame_cycles, t.predicted_frame_cycles
                ))
            ),
        }));
    }
    Ok(Ran {
        compare: report.compare,
        max_error,
        nonfinite,
    })
}

/// The file a failing scene is written to.
pub fn failure_file(dir: &Path, g: &Generated) -> PathBuf {
    dir.join(format!("seed-{}-scene-{}.toml", g.seed, g.index))
}

/// Runs the campaign; `progress` is called once per scene.
pub fn run(
    options: &FuzzOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<FuzzReport, std::io::Error> {
    let indices: Vec<u64> = (options.first..options.first + options.count).collect();
    run_indices(options, &indices, progress)
}

/// Runs the scenes `indices` of the campaign (a shard's, [`summary`]),
/// reported in that order; `options.first` and `count` are not used.
pub fn run_indices(
    options: &FuzzOptions,
    indices: &[u64],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<FuzzReport, std::io::Error> {
    let cosim_options = CosimOptions {
        fault: options.fault,
        timeout_cycles: Some(options.timeout_cycles),
        keep_frames: false,
        stall: Stall::NONE,
    };
    let outcomes: Vec<SceneOutcome> = indices
        .par_iter()
        .map_init(Models::new, |models, &index| {
            let outcome = run_scene(
                models,
                generate::scene(options.seed, index),
                &cosim_options,
                options.processor,
            );
            if matches!(outcome.fate, Fate::Error(_)) {
                // A model that failed mid-pixel is not used again.
                *models = Models::new();
            }
            progress(1);
            outcome
        })
        .collect();
    let mut report = FuzzReport {
        seed: options.seed,
        scenes: 0,
        in_limits: 0,
        in_limits_accepted: 0,
        refused_by_field: BTreeMap::new(),
        accepted: 0,
        compare: CompareReport::new(Labels::rtl_golden().on(options.processor)),
        max_errors: Vec::new(),
        nonfinite: 0,
        failures: Vec::new(),
    };
    for o in outcomes {
        let path = match (&options.failures_dir, o.failed()) {
            (Some(dir), true) => {
                std::fs::create_dir_all(dir)?;
                let path = failure_file(dir, &o.scene);
                std::fs::write(&path, &o.scene.toml)?;
                Some(path)
            }
            _ => None,
        };
        report.add(o, path);
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    #[test]
    fn refusals_count_by_kind_of_field() {
        assert_eq!(super::field_kind("sphere[2].center[0]"), "sphere.center");
        assert_eq!(super::field_kind("camera.distance"), "camera.distance");
        assert_eq!(super::field_kind("sphere, plane"), "sphere, plane");
    }
}
