//! The guided campaign (`rtcosim fuzz --corpus DIR`): scenes that reach
//! something new are kept and mutated further.
//!
//! A corpus is a folder of scene files, plain TOML a user can read and
//! `cosim`. It starts from every builtin scene at 16x12 and whatever files
//! the folder already holds. Each candidate is a corpus scene changed by
//! [`mutator`] (or, one time in ten, a fresh scene of [`generate`]); it is
//! loaded and validated as any file, and if it loads within the pixel
//! budget, golden predicts what it reaches ([`golden::micro::cover`]: the
//! controller's transitions and the classes of the values each state
//! writes) and the RTL co-simulates it exactly as `fuzz` does. A candidate
//! that reaches a point no corpus scene reached is written into the corpus
//! with a header saying where it came from and what it reached first.
//!
//! `Strategy::Random` draws fresh scenes only (the scenes of plain `fuzz`
//! with the same seed) and measures them the same way: the baseline the
//! guided campaign is compared against.
//!
//! Candidates are drawn in batches of [`BATCH`] from the corpus as it
//! stood before the batch, each from its own ChaCha stream (seed,
//! candidate index), run in parallel, and taken into the corpus in
//! candidate order: the campaign does not depend on the thread count.

use super::mutator;
use super::{check, field_kind, generate, Models};
use crate::check::cosim::CosimOptions;
use crate::design::processor::ProcessorKind;
use crate::design::top::Stall;
use crate::design::Fault;
use golden::micro::cover::{Coverage, Point};
use golden::scene::Scene;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use toml::Table;

/// Candidates drawn from one state of the corpus.
pub const BATCH: u64 = 16;

/// The image size the builtin seeds are put at.
pub const SEED_SIZE: (u32, u32) = (16, 12);

/// How candidates are made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// Mutate corpus scenes that reached something new (a fresh scene one
    /// time in ten).
    Guided,
    /// Fresh scenes only, as plain `fuzz` draws them: the baseline.
    Random,
}

impl Strategy {
    /// As `--strategy` spells it.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Guided => "guided",
            Strategy::Random => "random",
        }
    }
}

/// How to run a guided campaign.
#[derive(Debug, Clone)]
pub struct GuidedOptions {
    pub seed: u64,
    /// Candidates to run.
    pub count: u64,
    pub corpus: PathBuf,
    pub strategy: Strategy,
    /// Candidates with more pixels are not run (counted as too big).
    pub max_pixels: u64,
    /// Where failing candidates are written.
    pub failures_dir: PathBuf,
    pub timeout_cycles: u64,
    pub fault: Option<Fault>,
    pub processor: ProcessorKind,
}

/// A scene of the corpus.
#[derive(Debug, Clone)]
pub struct Entry {
    /// Its file name in the corpus folder.
    pub name: String,
    pub table: Table,
    pub coverage: Coverage,
    /// Its image's pixels: what co-simulating it costs.
    pub pixels: u64,
}

/// An error that stops the campaign before or while it runs: a corpus file
/// that does not load, a folder that cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum GuidedError {
    #[error("corpus file {path}: {message}")]
    CorpusFile { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> GuidedError + '_ {
    move |source| GuidedError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Coverage after some candidates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
pub struct CurvePoint {
    pub candidates: u64,
    pub corpus: usize,
    pub points: usize,
    pub transitions: usize,
}

/// A candidate that broke the promise.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Failure {
    pub candidate: u64,
    pub message: String,
    /// The scene, written to the failures folder.
    pub file: PathBuf,
}

/// What a guided campaign did.
#[derive(Debug, Clone, Serialize)]
pub struct GuidedReport {
    pub seed: u64,
    pub strategy: Strategy,
    pub processor: String,
    /// Corpus scenes before the first candidate (builtins and files).
    pub seeds: usize,
    pub candidates: u64,
    /// Refusals at load, by kind of field: of candidates, and of the
    /// mutants drawn again before a candidate ([`ATTEMPTS`]).
    pub refused: BTreeMap<String, u64>,
    /// Mutants refused and drawn again.
    pub mutants_refused: u64,
    /// Loaded, but over the pixel budget.
    pub too_big: u64,
    /// Co-simulated.
    pub ran: u64,
    pub pixels: u64,
    /// The files the campaign added to the corpus.
    pub kept: Vec<String>,
    /// Points the seeds reached, and all reached at the end.
    pub seed_points: usize,
    pub points: usize,
    /// Reachable ISA transitions (rtl/cover/pp_ctrl.transitions less those
    /// argued unreachable) reached at the start and at the end, of how many.
    pub seed_transitions: usize,
    pub transitions: usize,
    pub reachable_transitions: usize,
    /// The reachable transitions no scene reached.
    pub missing_transitions: Vec<String>,
    /// The points no seed reached, by the candidate that reached each first.
    pub new_points: Vec<(String, String)>,
    pub curve: Vec<CurvePoint>,
    pub failures: Vec<Failure>,
    /// Corpus scenes at the end.
    pub corpus: usize,
}

impl GuidedReport {
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }
}

/// The reachable ISA transitions as golden names them, less IDLE -> IDLE:
/// the cycles a processor waits between pixels, which golden's pixel
/// paths do not hold (every campaign's RTL takes it).
fn reachable() -> Vec<Point> {
    use golden::micro::isa::{state_code, State};
    crate::output::coverage::reachable_transitions()
        .unwrap_or_default()
        .iter()
        .filter_map(|(a, b)| {
            Some(Point::Transition(
                State(state_code(a)?),
                State(state_code(b)?),
            ))
        })
        .filter(|&p| p != Point::Transition(State::IDLE, State::IDLE))
        .collect()
}

fn transitions_in(c: &Coverage, reachable: &[Point]) -> usize {
    reachable.iter().filter(|&&p| c.contains(p)).count()
}

/// The corpus: the builtins at [`SEED_SIZE`] (written into the folder if
/// missing) and every `*.toml` the folder holds, in name order.
pub fn load_corpus(dir: &Path) -> Result<Vec<Entry>, GuidedError> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    for name in Scene::builtin_names() {
        let path = dir.join(format!("builtin-{name}.toml"));
        if path.exists() {
            continue;
        }
        let scene = Scene::builtin(name)
            .and_then(|s| s.resized(SEED_SIZE.0, SEED_SIZE.1, name).ok())
            .ok_or_else(|| GuidedError::CorpusFile {
                path: path.clone(),
                message: format!("the builtin {name} does not load at 16x12"),
            })?;
        let text = format!(
            "# rtcosim fuzz --corpus: the builtin scene {name} at {}x{}, a seed\n\n{}",
            SEED_SIZE.0,
            SEED_SIZE.1,
            scene.to_toml()
        );
        std::fs::write(&path, text).map_err(io(&path))?;
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(io(dir))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let bad = |message: String| GuidedError::CorpusFile {
                path: path.clone(),
                message,
            };
            let text = std::fs::read_to_string(&path).map_err(io(&path))?;
            let scene = Scene::from_toml(&text, &path.display().to_string())
                .map_err(|e| bad(e.to_string()))?;
            let table = text.parse::<Table>().map_err(|e| bad(e.to_string()))?;
            let coverage = golden::micro::Processor::new(&scene)
                .coverage(golden::window::Window::full(&scene));
            Ok(Entry {
                name: path
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                table,
                coverage,
                pixels: scene.pixel_count(),
            })
        })
        .collect()
}

/// The smallest set of entries (found greedily: the entry that adds the
/// most points not yet covered, the one with fewer pixels on a tie, then
/// the earlier) whose points together are all of `entries`' points; their
/// indices, in `entries`' order.
pub fn minimize(entries: &[Entry]) -> Vec<usize> {
    let mut covered = Coverage::new();
    let mut chosen = Vec::new();
    loop {
        let best = entries
            .iter()
            .enumerate()
            .map(|(i, e)| {
                (
                    covered.new_in(&e.coverage),
                    std::cmp::Reverse(e.pixels),
                    std::cmp::Reverse(i),
                )
            })
            .filter(|&(new, _, _)| new > 0)
            .max();
        let Some((_, _, std::cmp::Reverse(i))) = best else {
            break;
        };
        covered.merge(&entries[i].coverage);
        chosen.push(i);
    }
    chosen.sort_unstable();
    chosen
}

/// `fuzz --corpus DIR --minimize-into OUT`: copies the files of
/// [`minimize`]'s set from `dir` into `out`; returns (files in `dir`,
/// files copied, points).
pub fn minimize_into(dir: &Path, out: &Path) -> Result<(usize, usize, usize), GuidedError> {
    let entries = load_corpus(dir)?;
    let chosen = minimize(&entries);
    std::fs::create_dir_all(out).map_err(io(out))?;
    let mut points = Coverage::new();
    for &i in &chosen {
        let (from, to) = (dir.join(&entries[i].name), out.join(&entries[i].name));
        std::fs::copy(&from, &to).map_err(io(&to))?;
        points.merge(&entries[i].coverage);
    }
    Ok((entries.len(), chosen.len(), points.len()))
}

/// A candidate scene file and how it was made.
struct Candidate {
    index: u64,
    text: String,
    origin: String,
    /// The fields that refused the mutants drawn before this one.
    refused: Vec<String>,
}

/// Each corpus scene's rarity: the sum, over the points it reaches, of one
/// over the number of corpus scenes that reach the point. A scene alone in
/// reaching something weighs at least 1; the parent of a third of the
/// mutants is drawn in proportion to it (the rare-branch focus of
/// FairFuzz, on golden's points), so that what one scene alone reaches is
/// mutated further.
fn rarity(corpus: &[Entry]) -> Vec<f64> {
    let mut reach: std::collections::HashMap<Point, u32> = std::collections::HashMap::new();
    for e in corpus {
        for p in e.coverage.points() {
            *reach.entry(p).or_default() += 1;
        }
    }
    corpus
        .iter()
        .map(|e| {
            e.coverage
                .points()
                .map(|p| 1.0 / f64::from(reach[&p]))
                .sum()
        })
        .collect()
}

/// Candidate `index`: a fresh scene, or a corpus scene mutated.
fn candidate(options: &GuidedOptions, corpus: &[Entry], rarity: &[f64], index: u64) -> Candidate {
    // A stream of its own, apart from generate's streams of the same seed.
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed ^ 0x6775_6964_6564);
    rng.set_stream(index);
    let fresh = options.strategy == Strategy::Random || corpus.is_empty() || rng.random_bool(0.1);
    if fresh {
        let g = generate::scene(options.seed, index);
        return Candidate {
            index,
            text: g.toml,
            origin: format!("fresh scene {index} of seed {}", options.seed),
            refused: Vec::new(),
        };
    }
    // A third of the time a recent find: what was just kept is the
    // likeliest to lead further; a third a scene by its rarity; a third
    // any scene.
    let n = corpus.len();
    let recent = n.min(16);
    let i = match rng.random_range(0..3) {
        0 => n - 1 - rng.random_range(0..recent),
        1 => match rand::distr::weighted::WeightedIndex::new(rarity) {
            Ok(w) => rng.sample(w),
            Err(_) => rng.random_range(0..n),
        },
        _ => rng.random_range(0..n),
    };
    let parent = &corpus[i];
    // Crossover material: three corpus scenes and a fresh one, which
    // brings the keys no corpus scene has yet (a weight cutoff, an
    // exposure, glass) into the corpus' scenes.
    let fresh_donor = generate::scene(options.seed, u64::MAX - index)
        .toml
        .parse::<Table>()
        .unwrap_or_default();
    let mut donors: Vec<&Table> = (0..3)
        .map(|_| &corpus[rng.random_range(0..n)].table)
        .collect();
    donors.push(&fresh_donor);
    // A mutant the loader refuses costs a parse, not a run: draw again,
    // up to ATTEMPTS times, and run the last if every one is refused.
    let mut refused = Vec::new();
    loop {
        let mut table = parent.table.clone();
        let changes = mutator::mutate(&mut table, &donors, &mut rng);
        let text = toml::to_string(&table).unwrap_or_default();
        let origin = format!("{}; {}", parent.name, changes.join("; "));
        match Scene::from_toml(&text, "a mutant") {
            Err(e) if refused.len() + 1 < ATTEMPTS => {
                refused.push(field_kind(e.field().unwrap_or("(file)")))
            }
            _ => {
                return Candidate {
                    index,
                    text,
                    origin,
                    refused,
                }
            }
        }
    }
}

/// Mutants drawn for one candidate until one loads.
pub const ATTEMPTS: usize = 8;

/// What running a candidate gave.
enum Outcome {
    Refused(String),
    TooBig,
    Ran {
        coverage: Coverage,
        pixels: u64,
        /// Why it broke the promise, if it did.
        failure: Option<String>,
    },
}

fn evaluate(
    models: &mut Models,
    c: &Candidate,
    options: &GuidedOptions,
    cosim: &CosimOptions,
) -> Outcome {
    let scene = match Scene::from_toml(&c.text, &format!("candidate {}", c.index)) {
        Ok(s) => s,
        Err(e) => return Outcome::Refused(field_kind(e.field().unwrap_or("(file)"))),
    };
    if scene.pixel_count() > options.max_pixels {
        return Outcome::TooBig;
    }
    let window = golden::window::Window::full(&scene);
    let coverage = golden::micro::Processor::new(&scene).coverage(window);
    let failure = match check(models, &scene, cosim, options.processor) {
        Ok(r) if r.compare.passed() && r.nonfinite == 0 => None,
        Ok(r) if r.nonfinite > 0 => Some(format!("{} non-finite colour channels", r.nonfinite)),
        Ok(r) => Some(format!("diverged:\n{}", r.compare)),
        Err(e) => {
            // A model that failed mid-pixel is not used again.
            *models = Models::new();
            Some(e.to_string())
        }
    };
    Outcome::Ran {
        coverage,
        pixels: window.pixels(),
        failure,
    }
}

/// Runs the campaign; `progress` is called after each batch with the
/// curve's newest point.
pub fn run(
    options: &GuidedOptions,
    progress: &(dyn Fn(&CurvePoint) + Sync),
) -> Result<GuidedReport, GuidedError> {
    let mut corpus = load_corpus(&options.corpus)?;
    let reachable = reachable();
    let mut total = Coverage::new();
    for e in &corpus {
        total.merge(&e.coverage);
    }
    let seed_coverage = total.clone();
    let mut report = GuidedReport {
        seed: options.seed,
        strategy: options.strategy,
        processor: options.processor.name().to_string(),
        seeds: corpus.len(),
        candidates: 0,
        refused: BTreeMap::new(),
        mutants_refused: 0,
        too_big: 0,
        ran: 0,
        pixels: 0,
        kept: Vec::new(),
        seed_points: total.len(),
        points: total.len(),
        seed_transitions: transitions_in(&total, &reachable),
        transitions: transitions_in(&total, &reachable),
        reachable_transitions: reachable.len(),
        missing_transitions: Vec::new(),
        new_points: Vec::new(),
        curve: Vec::new(),
        failures: Vec::new(),
        corpus: corpus.len(),
    };
    let cosim = CosimOptions {
        fault: options.fault,
        timeout_cycles: Some(options.timeout_cycles),
        keep_frames: false,
        stall: Stall::NONE,
    };
    let mut next = 0;
    while next < options.count {
        let end = (next + BATCH).min(options.count);
        let rarity = rarity(&corpus);
        let batch: Vec<Candidate> = (next..end)
            .map(|i| candidate(options, &corpus, &rarity, i))
            .collect();
        let outcomes: Vec<Outcome> = batch
            .par_iter()
            .map_init(Models::new, |models, c| {
                evaluate(models, c, options, &cosim)
            })
            .collect();
        for (c, outcome) in batch.into_iter().zip(outcomes) {
            report.candidates += 1;
            report.mutants_refused += c.refused.len() as u64;
            for field in &c.refused {
                *report.refused.entry(field.clone()).or_default() += 1;
            }
            match outcome {
                Outcome::Refused(field) => *report.refused.entry(field).or_default() += 1,
                Outcome::TooBig => report.too_big += 1,
                Outcome::Ran {
                    coverage,
                    pixels,
                    failure,
                } => {
                    report.ran += 1;
                    report.pixels += pixels;
                    if let Some(message) = failure {
                        std::fs::create_dir_all(&options.failures_dir)
                            .map_err(io(&options.failures_dir))?;
                        let file = options.failures_dir.join(format!(
                            "guided-seed-{}-candidate-{}.toml",
                            options.seed, c.index
                        ));
                        let text = format!("# {}\n{}", c.origin, c.text);
                        std::fs::write(&file, text).map_err(io(&file))?;
                        report.failures.push(Failure {
                            candidate: c.index,
                            message,
                            file,
                        });
                    }
                    if total.new_in(&coverage) > 0 {
                        let firsts: Vec<Point> =
                            coverage.points().filter(|&p| !total.contains(p)).collect();
                        total.merge(&coverage);
                        // Kept as the smallest centred crop that reaches
                        // what is new (shrink.rs), if smaller.
                        let (text, coverage, pixels, cropped) =
                            match super::shrink::shrink(&c.text, &firsts) {
                                Some(k) => {
                                    let note = format!(
                                        "\n# cropped from {}x{} to {}x{}: the pixels that reach it",
                                        k.from.0, k.from.1, k.to.0, k.to.1
                                    );
                                    (k.text, k.coverage, k.pixels, note)
                                }
                                None => (c.text.clone(), coverage, pixels, String::new()),
                            };
                        let name = format!("seed-{}-candidate-{:06}.toml", options.seed, c.index);
                        let listed: Vec<String> =
                            firsts.iter().take(8).map(|p| p.to_string()).collect();
                        let more = firsts.len().saturating_sub(listed.len());
                        let header = format!(
                            "# rtcosim fuzz --corpus: candidate {} of seed {} ({})\n# from: {}\n# first to reach: {}{}{cropped}\n\n",
                            c.index,
                            options.seed,
                            options.strategy.name(),
                            c.origin,
                            listed.join(", "),
                            if more > 0 { format!(" (and {more} more)") } else { String::new() }
                        );
                        let path = options.corpus.join(&name);
                        std::fs::write(&path, header + &text).map_err(io(&path))?;
                        for p in &firsts {
                            if !seed_coverage.contains(*p) {
                                report.new_points.push((p.to_string(), name.clone()));
                            }
                        }
                        let table = text.parse::<Table>().unwrap_or_default();
                        report.kept.push(name.clone());
                        corpus.push(Entry {
                            name,
                            table,
                            coverage,
                            pixels,
                        });
                    }
                }
            }
        }
        next = end;
        let point = CurvePoint {
            candidates: report.candidates,
            corpus: corpus.len(),
            points: total.len(),
            transitions: transitions_in(&total, &reachable),
        };
        report.curve.push(point);
        progress(&point);
    }
    report.points = total.len();
    report.transitions = transitions_in(&total, &reachable);
    report.missing_transitions = reachable
        .iter()
        .filter(|&&p| !total.contains(p))
        .map(|p| p.to_string())
        .collect();
    report.corpus = corpus.len();
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use golden::micro::isa::State;

    fn entry(name: &str, pixels: u64, points: &[(u16, u16)]) -> Entry {
        let mut coverage = Coverage::new();
        for &(a, b) in points {
            coverage.insert(Point::Transition(State(a), State(b)));
        }
        Entry {
            name: name.into(),
            table: Table::new(),
            coverage,
            pixels,
        }
    }

    #[test]
    fn minimizing_keeps_every_point_with_fewer_scenes() {
        let entries = [
            entry("a", 10, &[(1, 2)]),
            entry("b", 10, &[(1, 2), (2, 3)]),
            entry("c", 50, &[(3, 4), (4, 5)]),
            entry("d", 5, &[(3, 4), (4, 5)]),
            entry("e", 10, &[]),
        ];
        // b covers a; d is c's points at fewer pixels; e adds nothing.
        assert_eq!(minimize(&entries), vec![1, 3]);
        assert_eq!(minimize(&[]), Vec::<usize>::new());
    }
}
