//! Mutation testing, MCY-style: how many small faults planted in the RTL
//! would our checks notice (docs/mutation.md)?
//!
//! - The mutants: `rtl/mutate/pixel_processor.mutants`, sampled over every
//!   module of the pixel processor by Yosys' `mutate -list` (through
//!   `rtl/mutate/mutants.sh list`), numbered from 1, with the hash of the
//!   RTL they were listed on ([`List`]).
//! - The build: with the cargo feature `mutation`, build.rs has
//!   `mutants.sh netlist` write one netlist carrying every mutant behind
//!   the input `mutsel` and verilates it once;
//!   [`PixelProcessor::new_mutant`] selects one (0: the design as written).
//! - The judge ([`Judge`]): a fixed list of checks, each a co-simulation of
//!   a scene against golden's micro-op model, bit for bit and cycle for
//!   cycle ([`cosim::run_on`]): every builtin scene at a small size, then
//!   seeded fuzz scenes, all with the exact methods the netlist has. A
//!   mutant is killed by the first check that diverges or errs (a hang
//!   counts), and survives if none does.
//! - [`run`] judges mutants in parallel on the current rayon pool, a fresh
//!   model per mutant (nothing a previous mutant left in the register file
//!   can matter); its [`Summary`] merges across shards like a fuzz
//!   campaign's ([`crate::shard`]).
//! - [`prove_equivalent`] runs `mutants.sh equiv`: Yosys proves a
//!   survivor's module equal to the original, or fails to.

use crate::cosim::{self, CosimOptions};
use crate::fuzz::generate;
use crate::pixel_proc::{PixelProcessor, PpError};
use crate::scenes::with_methods;
use crate::shard::Shard;
use golden::fp::Method;
use golden::scene::Scene;
use golden::window::Window;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The committed mutant list, as the mutant netlist was built from it.
pub const LIST_TEXT: &str = include_str!("../rtl/mutate/pixel_processor.mutants");

/// The list's path in the checkout, for messages.
pub const LIST_PATH: &str = "rtl/mutate/pixel_processor.mutants";

/// The script that lists mutants, writes the netlist and proves survivors
/// equivalent.
pub fn script() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("rtl/mutate/mutants.sh")
}

/// The tool name in shard files.
pub const TOOL: &str = "mutate";

/// Whether this build carries the mutant netlist (cargo feature `mutation`).
pub const BUILT: bool = cfg!(feature = "mutation");

/// One mutant of the list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mutant {
    /// Its `mutsel` value, from 1.
    pub id: u16,
    /// Yosys' mutation mode: `inv`, `const0`, `const1`, `cnot0`, `cnot1`.
    pub mode: String,
    /// The module, without Yosys' parameter decoration (`fp_lzc`, not
    /// `$paramod$...\fp_lzc`).
    pub module: String,
    /// Where in the RTL: the first `-src` with a line, `rtl/pp/pp_ctrl.v:120`.
    pub location: String,
    /// The whole `mutate` command, as listed.
    pub command: String,
}

/// The mutant list: the RTL hash it was listed on, and its mutants.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct List {
    pub rtl_hash: String,
    pub mutants: Vec<Mutant>,
}

/// A line of the list that does not read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{LIST_PATH}:{line}: {message}")]
pub struct ListError {
    pub line: usize,
    pub message: String,
}

/// `$paramod$<hash>\fp_lzc` and `$paramod\memory\STACK_DEPTH=...` ->
/// `fp_lzc`, `memory`.
fn module_name(raw: &str) -> String {
    match raw.strip_prefix("$paramod") {
        Some(rest) => rest.split('\\').nth(1).unwrap_or(rest).to_string(),
        None => raw.trim_start_matches('\\').to_string(),
    }
}

impl List {
    /// The committed list.
    pub fn committed() -> Result<List, ListError> {
        List::parse(LIST_TEXT)
    }

    pub fn parse(text: &str) -> Result<List, ListError> {
        let mut rtl_hash = None;
        let mut mutants = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let error = |message: String| ListError {
                line: n + 1,
                message,
            };
            if let Some(h) = line.strip_prefix("# rtl fnv1a64 ") {
                rtl_hash = Some(h.trim().to_string());
            }
            if line.starts_with('#') || line.trim().is_empty() {
                continue;
            }
            let (id, command) = line
                .split_once(' ')
                .ok_or_else(|| error(format!("not `ID mutate ...`: {line}")))?;
            let id: u16 = id
                .parse()
                .map_err(|_| error(format!("mutant number {id:?} is not in 1..=65535")))?;
            if usize::from(id) != mutants.len() + 1 {
                return Err(error(format!(
                    "mutant {id} out of order: expected {}",
                    mutants.len() + 1
                )));
            }
            let words: Vec<&str> = command.split(' ').collect();
            if words.first() != Some(&"mutate") {
                return Err(error(format!("not a `mutate` command: {command}")));
            }
            let value = |flag: &str| {
                words
                    .windows(2)
                    .filter(|w| w[0] == flag)
                    .map(|w| w[1])
                    .collect::<Vec<_>>()
            };
            let (modes, modules) = (value("-mode"), value("-module"));
            let (Some(mode), Some(module)) = (modes.first(), modules.first()) else {
                return Err(error(format!("no -mode or -module: {command}")));
            };
            let location = value("-src")
                .iter()
                .filter_map(|src| {
                    let (file, at) = src.rsplit_once(':')?;
                    let line = at.split('.').next()?;
                    (line != "0").then(|| format!("{file}:{line}"))
                })
                .next()
                .unwrap_or_else(|| "(no source line)".to_string());
            mutants.push(Mutant {
                id,
                mode: mode.to_string(),
                module: module_name(module),
                location,
                command: command.to_string(),
            });
        }
        let rtl_hash = rtl_hash.ok_or(ListError {
            line: 1,
            message: "no `# rtl fnv1a64` line: not a list rtl/mutate/mutants.sh wrote".into(),
        })?;
        Ok(List { rtl_hash, mutants })
    }
}

/// One check of the judge: a scene co-simulated over a window.
#[derive(Debug, Clone)]
pub struct Check {
    /// `builtin reference 16x12`, `fuzz seed 1 scene 17`.
    pub name: String,
    pub scene: Scene,
    pub window: Window,
}

/// What the judge is made of: every builtin scene at `size`, then the
/// accepted scenes among `fuzz_count` fuzz scenes of `fuzz_seed`; all with
/// the exact methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct JudgeSpec {
    pub width: u32,
    pub height: u32,
    pub fuzz_seed: u64,
    pub fuzz_count: u64,
    pub timeout_cycles: u64,
}

/// The fixed list of checks every mutant faces, in order.
#[derive(Debug, Clone)]
pub struct Judge {
    pub spec: JudgeSpec,
    pub checks: Vec<Check>,
}

/// A judge that cannot be made (a builtin scene refused at the size).
#[derive(Debug, thiserror::Error)]
#[error("the judge's {what}: {message}")]
pub struct JudgeError {
    pub what: String,
    pub message: String,
}

impl Judge {
    pub fn new(spec: JudgeSpec) -> Result<Judge, JudgeError> {
        let exact = |scene: &Scene, what: &str| {
            with_methods(scene, Method::Exact, Method::Exact, what).map_err(|e| JudgeError {
                what: what.to_string(),
                message: e.to_string(),
            })
        };
        let mut checks = Vec::new();
        for name in Scene::builtin_names() {
            let what = format!("builtin {name} {}x{}", spec.width, spec.height);
            let scene = Scene::builtin(name)
                .ok_or_else(|| JudgeError {
                    what: what.clone(),
                    message: "not a builtin scene".into(),
                })?
                .resized(spec.width, spec.height, &what)
                .map_err(|e| JudgeError {
                    what: what.clone(),
                    message: e.to_string(),
                })?;
            let scene = exact(&scene, &what)?;
            checks.push(Check {
                name: what,
                window: Window::full(&scene),
                scene,
            });
        }
        for index in 0..spec.fuzz_count {
            let g = generate::scene(spec.fuzz_seed, index);
            let what = format!("fuzz seed {} scene {index}", spec.fuzz_seed);
            // Refused at load: not a check (the fuzzer's rule).
            let Ok(scene) = Scene::from_toml(&g.toml, &what) else {
                continue;
            };
            // A scene the exact methods would refuse is not a check either.
            let Ok(scene) = exact(&scene, &what) else {
                continue;
            };
            checks.push(Check {
                name: what,
                window: Window::full(&scene),
                scene,
            });
        }
        Ok(Judge { spec, checks })
    }

    /// The pixels one mutant faces if it survives.
    pub fn pixels(&self) -> u64 {
        self.checks.iter().map(|c| c.window.pixels()).sum()
    }
}

/// How a mutant fared.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum Verdict {
    /// `check` (its name) diverged or erred first; `how` says how.
    Killed { check: String, how: String },
    /// Every check passed.
    Survived,
}

/// One mutant's result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    pub id: u16,
    #[serde(flatten)]
    pub verdict: Verdict,
    /// Pixels co-simulated until the verdict.
    pub pixels: u64,
    /// Wall time of the judgement on one thread.
    pub seconds: f64,
}

/// Judges mutant `id` (0: the design as written) on a fresh model.
pub fn judge(id: u16, judge: &Judge) -> Result<Outcome, PpError> {
    let start = Instant::now();
    let mut rtl = PixelProcessor::new_mutant(id)?;
    let options = CosimOptions {
        timeout_cycles: judge.spec.timeout_cycles,
        ..CosimOptions::default()
    };
    let mut pixels = 0;
    if let Err(e) = rtl.reset() {
        return Ok(Outcome {
            id,
            verdict: Verdict::Killed {
                check: "reset".into(),
                how: e.to_string(),
            },
            pixels,
            seconds: start.elapsed().as_secs_f64(),
        });
    }
    let mut verdict = Verdict::Survived;
    for check in &judge.checks {
        let killed = |how: String| Verdict::Killed {
            check: check.name.clone(),
            how,
        };
        match cosim::run_on(&mut rtl, &check.scene, check.window, &options, &mut |_| {}) {
            Ok(report) => {
                pixels += report.compare.counts.pixels;
                if !report.passed() {
                    let how = match &report.compare.first_divergence {
                        Some(d) => d
                            .text(&report.compare.labels)
                            .to_string()
                            .lines()
                            .next()
                            .unwrap_or("diverges")
                            .trim()
                            .to_string(),
                        None => "no events compared".to_string(),
                    };
                    verdict = killed(how);
                    break;
                }
            }
            Err(e) => {
                verdict = killed(format!("the run failed: {e}"));
                break;
            }
        }
    }
    Ok(Outcome {
        id,
        verdict,
        pixels,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Judges `ids` in parallel on the current rayon pool; results in the
/// order of `ids`. `progress` is called once per mutant.
pub fn run(
    ids: &[u16],
    judge_: &Judge,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Outcome>, PpError> {
    ids.par_iter()
        .map(|&id| {
            let o = judge(id, judge_);
            progress(1);
            o
        })
        .collect()
}

/// A survivor's equivalence, as Yosys found it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Equivalence {
    /// Proved: no input and no register value tells the mutated module
    /// from the original.
    Equivalent,
    /// Some signal stands unproven: the mutant may differ, or differ only
    /// for register values no run reaches.
    NotProved,
    /// The proof took longer than its limit (MUTATE_EQUIV_SECONDS, 120 s).
    Timeout,
}

/// Runs `rtl/mutate/mutants.sh equiv` on `ids` (Yosys; seconds a mutant,
/// up to its time limit), with the design the build prepared.
pub fn prove_equivalent(ids: &[u16]) -> Result<BTreeMap<u16, Equivalence>, String> {
    if ids.is_empty() {
        return Ok(BTreeMap::new());
    }
    let script = script();
    let o = Command::new("bash")
        .arg(&script)
        .arg("equiv")
        .args(ids.iter().map(u16::to_string))
        .env("MUTATE_CACHE", Path::new(env!("OUT_DIR")).join("mutate"))
        .output()
        .map_err(|e| format!("running {}: {e}", script.display()))?;
    if !o.status.success() {
        return Err(format!(
            "{} equiv failed: {}",
            script.display(),
            String::from_utf8_lossy(&o.stderr).trim()
        ));
    }
    let mut found = BTreeMap::new();
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        let Some((id, verdict)) = line.split_once(' ') else {
            continue;
        };
        let Ok(id) = id.parse::<u16>() else { continue };
        let verdict = match verdict.trim() {
            "equivalent" => Equivalence::Equivalent,
            "not-proved" => Equivalence::NotProved,
            "timeout" => Equivalence::Timeout,
            other => {
                return Err(format!(
                    "{} equiv: mutant {id}: unknown verdict {other:?}",
                    script.display()
                ))
            }
        };
        found.insert(id, verdict);
    }
    if let Some(missing) = ids.iter().find(|id| !found.contains_key(id)) {
        return Err(format!(
            "{} equiv said nothing of mutant {missing}",
            script.display()
        ));
    }
    Ok(found)
}

/// Every option of a campaign that affects its results.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Campaign {
    pub judge: JudgeSpec,
    /// The mutants judged, in order (the work list).
    pub mutants: Vec<u16>,
    /// The list's RTL hash.
    pub rtl_hash: String,
    /// The Verilator that built the netlist.
    pub verilator: String,
}

impl Campaign {
    /// The mutants `shard` judges.
    pub fn ids(&self, shard: Shard) -> Vec<u16> {
        shard
            .positions(self.mutants.len() as u64)
            .into_iter()
            .map(|i| self.mutants[i as usize])
            .collect()
    }
}

/// A campaign's (or a shard's) results, as merged.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Checks in the judge, and the pixels a survivor faces.
    pub checks: u64,
    pub judge_pixels: u64,
    /// By mutant number.
    pub outcomes: Vec<Outcome>,
    /// Survivors' equivalence, where it was asked.
    pub equivalence: BTreeMap<u16, Equivalence>,
}

impl Summary {
    pub fn merge(&mut self, other: Summary) {
        self.outcomes.extend(other.outcomes);
        self.outcomes.sort_by_key(|o| o.id);
        self.equivalence.extend(other.equivalence);
    }

    pub fn killed(&self) -> usize {
        self.outcomes
            .iter()
            .filter(|o| matches!(o.verdict, Verdict::Killed { .. }))
            .count()
    }

    pub fn survivors(&self) -> Vec<u16> {
        self.outcomes
            .iter()
            .filter(|o| o.verdict == Verdict::Survived)
            .map(|o| o.id)
            .collect()
    }
}

/// Per module: (mutants, killed, proved equivalent).
fn per_module(list: &List, summary: &Summary) -> BTreeMap<String, (u64, u64, u64)> {
    let mut rows: BTreeMap<String, (u64, u64, u64)> = BTreeMap::new();
    for o in &summary.outcomes {
        let module = list
            .mutants
            .get(usize::from(o.id).wrapping_sub(1))
            .map_or("?", |m| m.module.as_str());
        let row = rows.entry(module.to_string()).or_default();
        row.0 += 1;
        row.1 += u64::from(matches!(o.verdict, Verdict::Killed { .. }));
        row.2 += u64::from(summary.equivalence.get(&o.id) == Some(&Equivalence::Equivalent));
    }
    rows
}

fn percent(part: u64, whole: u64) -> String {
    if whole == 0 {
        "-".into()
    } else {
        format!("{:.1}%", 100.0 * part as f64 / whole as f64)
    }
}

impl Summary {
    /// Whether every mutant was killed or proved equivalent.
    pub fn passed(&self) -> bool {
        self.survivors()
            .iter()
            .all(|id| self.equivalence.get(id) == Some(&Equivalence::Equivalent))
    }

    /// The report (Markdown): the score, per module, what killed the
    /// mutants first, the time per mutant, and every survivor.
    pub fn report(&self, list: &List) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let n = self.outcomes.len() as u64;
        let killed = self.killed() as u64;
        let survivors = self.survivors();
        let count = |e: Equivalence| {
            survivors
                .iter()
                .filter(|id| self.equivalence.get(id) == Some(&e))
                .count() as u64
        };
        let equivalent = count(Equivalence::Equivalent);
        let asked = survivors
            .iter()
            .filter(|id| self.equivalence.contains_key(id))
            .count() as u64;
        let _ = writeln!(
            s,
            "mutants: {n} judged, {killed} killed, {} survived; score {} of all, {} of those not proved equivalent",
            survivors.len(),
            percent(killed, n),
            percent(killed, n - equivalent)
        );
        let _ = writeln!(
            s,
            "survivors' equivalence (Yosys): {}",
            if asked == 0 {
                "not asked (--equiv)".to_string()
            } else {
                format!(
                    "{asked} asked: {equivalent} proved equivalent, {} not proved, {} timed out",
                    count(Equivalence::NotProved),
                    count(Equivalence::Timeout)
                )
            }
        );
        let _ = writeln!(
            s,
            "judge: {} checks, {} pixels for a mutant that survives them all",
            self.checks, self.judge_pixels
        );
        let mut times: Vec<f64> = self.outcomes.iter().map(|o| o.seconds).collect();
        times.sort_by(f64::total_cmp);
        if let Some(max) = times.last() {
            let mean = times.iter().sum::<f64>() / times.len() as f64;
            let _ = writeln!(
                s,
                "time per mutant on one thread: mean {mean:.2} s, median {:.2} s, max {max:.2} s",
                times[times.len() / 2]
            );
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "| module | mutants | killed | survived | proved equivalent | score | score of the not equivalent |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for (module, (m, k, e)) in per_module(list, self) {
            let _ = writeln!(
                s,
                "| {module} | {m} | {k} | {} | {e} | {} | {} |",
                m - k,
                percent(k, m),
                percent(k, m - e)
            );
        }
        let _ = writeln!(s);
        let mut first: BTreeMap<String, u64> = BTreeMap::new();
        for o in &self.outcomes {
            if let Verdict::Killed { check, .. } = &o.verdict {
                *first.entry(check.clone()).or_default() += 1;
            }
        }
        let mut first: Vec<(String, u64)> = first.into_iter().collect();
        first.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let _ = writeln!(s, "killed first by:");
        for (check, k) in &first {
            let _ = writeln!(s, "- {check}: {k}");
        }
        let _ = writeln!(s);
        let _ = writeln!(s, "survivors ({}):", survivors.len());
        if !survivors.is_empty() {
            let _ = writeln!(s);
            let _ = writeln!(s, "| mutant | module | where | mode | equivalence |");
            let _ = writeln!(s, "|---|---|---|---|---|");
        }
        for id in survivors {
            let (module, location, mode) = list
                .mutants
                .get(usize::from(id).wrapping_sub(1))
                .map_or(("?", "?", "?"), |m| {
                    (m.module.as_str(), m.location.as_str(), m.mode.as_str())
                });
            let equivalence = match self.equivalence.get(&id) {
                Some(Equivalence::Equivalent) => "proved equivalent",
                Some(Equivalence::NotProved) => "not proved",
                Some(Equivalence::Timeout) => "proof timed out",
                None => "not asked",
            };
            let _ = writeln!(
                s,
                "| {id} | {module} | {location} | {mode} | {equivalence} |"
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn module_names_lose_their_parameters() {
        assert_eq!(module_name("$paramod$dc0217be\\fp_lzc"), "fp_lzc");
        assert_eq!(
            module_name("$paramod\\memory\\STACK_DEPTH=s32'00000000000000000000000000001000"),
            "memory"
        );
        assert_eq!(module_name("pp_ctrl"), "pp_ctrl");
    }

    #[test]
    fn the_committed_list_reads_and_numbers_its_mutants_from_one() {
        let list = List::committed().unwrap();
        assert!(list.mutants.len() >= 1000, "{} mutants", list.mutants.len());
        for (i, m) in list.mutants.iter().enumerate() {
            assert_eq!(usize::from(m.id), i + 1);
            assert!(m.command.starts_with("mutate -mode "));
            assert!(
                m.location.starts_with("rtl/") || m.location == "(no source line)",
                "{m:?}"
            );
        }
        let modules: std::collections::BTreeSet<&str> =
            list.mutants.iter().map(|m| m.module.as_str()).collect();
        for m in ["pp_ctrl", "alu", "memory", "fp_add", "fp_recip"] {
            assert!(modules.contains(m), "no mutant of {m}: {modules:?}");
        }
    }

    #[test]
    fn a_list_out_of_order_or_without_its_hash_is_refused() {
        let head = "# rtl fnv1a64 0123\n";
        let line = "mutate -mode inv -module pp_ctrl -cell x -port Y -src rtl/pp/pp_ctrl.v:5.1-5.2";
        let ok = List::parse(&format!("{head}1 {line}\n2 {line}\n")).unwrap();
        assert_eq!(ok.mutants[1].location, "rtl/pp/pp_ctrl.v:5");
        let e = List::parse(&format!("{head}1 {line}\n3 {line}\n")).unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("expected 2"), "{e}");
        assert!(List::parse(&format!("1 {line}\n")).is_err());
        let e = List::parse(&format!("{head}1 mutant -mode inv\n")).unwrap_err();
        assert!(e.message.contains("not a `mutate` command"), "{e}");
    }
}
