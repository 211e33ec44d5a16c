//! Mutation testing, MCY-style: how many small faults planted in the RTL
//! would our checks notice (docs/mutation.md)?
//!
//! - The mutants: `rtl/mutate/pixel_processor.mutants` (the compact
//!   processor) and `rtl/mutate/fast_pp.mutants` (the fast one), each
//!   sampled over every module of its processor by Yosys' `mutate -list`
//!   (through `rtl/mutate/mutants.sh list`), numbered from 1, with the hash
//!   of the RTL they were listed on ([`List`], [`Files`]).
//! - The build: with the cargo feature `mutation`, build.rs has
//!   `mutants.sh netlist` write one netlist per processor carrying every
//!   mutant behind the input `mutsel` and verilates each once;
//!   [`PixelProcessor::new_mutant`] and [`Top::new_fast_mutant`] select one
//!   (0: the design as written).
//! - The judge ([`Judge`]): a fixed list of checks, each a co-simulation of
//!   a scene against golden's micro-op model, bit for bit and cycle for
//!   cycle ([`cosim::run_on`]; the fast processor's through
//!   [`cosim::run_top_on`], its cycles the barrel rule's): every builtin
//!   scene at a small size, the directed scenes, then seeded fuzz scenes,
//!   all with the exact methods the netlist has; and, for a mutant of the
//!   compact processor's float units, those units cut from its netlist on
//!   their edge cases and random operands. A mutant is killed by the first
//!   check that diverges or errs (a hang counts), and survives if none
//!   does.
//! - [`run`] judges mutants in parallel on the current rayon pool, a fresh
//!   model per mutant (nothing a previous mutant left in the register file
//!   can matter); its [`Summary`] merges across shards like a fuzz
//!   campaign's ([`crate::campaign::shard`]).
//! - [`prove_equivalent`] runs `mutants.sh equiv`: Yosys proves a
//!   survivor's module equal to the original, or fails to.

use crate::check::cosim::{self, CosimOptions};
use crate::check::fp_check;
use crate::design::fp_unit::{FpUnit, UnitKind};
use crate::campaign::fuzz::generate;
use crate::check::operands;
use crate::design::pixel_proc::PixelProcessor;
use crate::design::processor::{Driver, ProcessorKind};
use crate::design::{Design, Flavour, PpError};
use crate::scenes::with_methods;
use crate::campaign::shard::Shard;
use crate::design::top::Stall;
use golden::fp::Method;
use golden::scene::Scene;
use golden::window::Window;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Where one processor's mutants are committed: the list the mutant
/// netlist is built from and its survivors' classification, as built into
/// this rtcosim, with their paths in the checkout for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Files {
    pub processor: ProcessorKind,
    pub list_path: &'static str,
    pub list_text: &'static str,
    pub survivors_path: &'static str,
    pub survivors_text: &'static str,
}

impl Files {
    /// `processor`'s files (its row's).
    pub fn of(processor: ProcessorKind) -> Files {
        let m = processor.row().mutants;
        Files {
            processor,
            list_path: m.list_path,
            list_text: m.list_text,
            survivors_path: m.survivors_path,
            survivors_text: m.survivors_text,
        }
    }

    /// `mutants.sh`'s name for the design (`MUTATE_DESIGN`).
    pub fn design(&self) -> &'static str {
        self.processor.row().mutant_design
    }
}

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
    /// Where it was read from: the processor it mutates.
    pub files: Files,
    pub rtl_hash: String,
    pub mutants: Vec<Mutant>,
    /// The survivors' classification ([`Files::survivors_path`]), by
    /// mutant.
    pub classified: BTreeMap<u16, Classified>,
}

/// A line of the list (or of its survivors' classification) that does not
/// read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}:{line}: {message}")]
pub struct ListError {
    pub path: &'static str,
    pub line: usize,
    pub message: String,
}

/// What a survivor is, as classified by a reader of the RTL
/// (rtl/mutate/pixel_processor.survivors; docs/mutation.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Class {
    /// Yosys proved it equivalent (`--equiv`); the reason says what it does.
    Equivalent,
    /// It differs from the design only in states or inputs no run reaches;
    /// the reason names the invariant.
    Unreachable,
    /// A behaviour the judge misses; the reason says what would kill it.
    Hole,
    /// Not decided yet.
    Open,
}

impl Class {
    fn parse(word: &str) -> Option<Class> {
        Some(match word {
            "equivalent" => Class::Equivalent,
            "unreachable" => Class::Unreachable,
            "hole" => Class::Hole,
            "open" => Class::Open,
            _ => return None,
        })
    }

    /// Whether no run can tell the mutant from the design.
    pub fn is_equivalent(self) -> bool {
        matches!(self, Class::Equivalent | Class::Unreachable)
    }
}

impl std::fmt::Display for Class {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Class::Equivalent => "equivalent",
            Class::Unreachable => "unreachable",
            Class::Hole => "hole",
            Class::Open => "open",
        })
    }
}

/// A survivor's class and the reason for it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Classified {
    pub class: Class,
    pub reason: String,
}

/// Reads a classification: `ID CLASS reason`, one a line, `#` comments;
/// `path` names it in errors.
pub fn parse_classification(
    path: &'static str,
    text: &str,
) -> Result<BTreeMap<u16, Classified>, ListError> {
    let mut found = BTreeMap::new();
    for (n, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let error = |message: String| ListError {
            path,
            line: n + 1,
            message,
        };
        let mut words = line.splitn(3, ' ');
        let (Some(id), Some(class), Some(reason)) = (words.next(), words.next(), words.next())
        else {
            return Err(error(format!("not `ID CLASS reason`: {line}")));
        };
        let id: u16 = id
            .parse()
            .map_err(|_| error(format!("mutant number {id:?} is not in 1..=65535")))?;
        let class = Class::parse(class).ok_or_else(|| {
            error(format!(
                "class {class:?} is none of equivalent, unreachable, hole, open"
            ))
        })?;
        let classified = Classified {
            class,
            reason: reason.trim().to_string(),
        };
        if found.insert(id, classified).is_some() {
            return Err(error(format!("mutant {id} is classified twice")));
        }
    }
    Ok(found)
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
    /// `processor`'s committed list and classification.
    pub fn committed(processor: ProcessorKind) -> Result<List, ListError> {
        let files = Files::of(processor);
        let mut list = List::parse(files, files.list_text)?;
        list.classified = parse_classification(files.survivors_path, files.survivors_text)?;
        if let Some(&id) = list.classified.keys().find(|&&id| list.get(id).is_none()) {
            return Err(ListError {
                path: files.survivors_path,
                line: 0,
                message: format!("mutant {id} is not in {}", files.list_path),
            });
        }
        Ok(list)
    }

    /// Mutant `id`, if the list holds it.
    pub fn get(&self, id: u16) -> Option<&Mutant> {
        self.mutants.iter().find(|m| m.id == id)
    }

    /// Reads `text` as the list of `files` (whose path errors name).
    pub fn parse(files: Files, text: &str) -> Result<List, ListError> {
        let mut rtl_hash = None;
        let mut mutants = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let error = |message: String| ListError {
                path: files.list_path,
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
            path: files.list_path,
            line: 1,
            message: "no `# rtl fnv1a64` line: not a list rtl/mutate/mutants.sh wrote".into(),
        })?;
        Ok(List {
            files,
            rtl_hash,
            mutants,
            classified: BTreeMap::new(),
        })
    }
}

/// One check of the judge.
#[derive(Debug, Clone)]
pub struct Check {
    /// `builtin reference 16x12`, `fuzz seed 1 scene 17`, `fp_add edge
    /// cases`.
    pub name: String,
    pub stimulus: Stimulus,
}

/// What a check runs.
#[derive(Debug, Clone)]
pub enum Stimulus {
    /// A scene co-simulated over a window on the processor.
    Scene { scene: Box<Scene>, window: Window },
    /// For each cut c in `cuts`: the window's first pixel started and the
    /// processor reset after c cycles (by the watchdog, mid-operation),
    /// then the window co-simulated from that reset: a reset at any cycle
    /// must leave nothing behind. The compact processor's only (the fast
    /// one's driver runs whole frames).
    ResetMidPixel {
        scene: Box<Scene>,
        window: Window,
        cuts: std::ops::RangeInclusive<u64>,
    },
    /// The scene co-simulated with the result stream held back (`out_ready`
    /// low) as `stall` says, so that the results queue up: the fast
    /// processor's only (its result queue; the compact processor's driver
    /// takes each result as it comes).
    Stalled {
        scene: Box<Scene>,
        window: Window,
        stall: Stall,
    },
    /// Operands through one float unit cut from the mutant netlist, each
    /// result against golden's bits and each operation's cycles against
    /// its latency ([`fp_check::check_batch`]; a pipelined unit is read at
    /// its latency). Only a mutant a float unit may carry faces these
    /// ([`List::in_float_unit`]).
    Unit {
        kind: UnitKind,
        a: Vec<u32>,
        b: Vec<u32>,
    },
}

/// The float units cut from `processor`'s mutant netlist, in the judge's
/// order (the cheapest kills first): every unit, with the exact methods the
/// netlist has; the fast processor's are its pipelines.
pub fn units(processor: ProcessorKind) -> impl Iterator<Item = UnitKind> {
    processor
        .row()
        .units
        .into_iter()
        .filter(|k| k.method().map_or(true, |m| m == Method::Exact))
}

impl List {
    /// Whether mutant `id` faces the float-unit checks: a mutant of a
    /// module the units cut from the netlist may carry: the compact
    /// processor's float units (`rtl/fp/`, `fp_*`), or the fast one's
    /// (`fast_fp_*`, the `fp_*` they share and the `fast_delay`s their
    /// pipelines are built of, some of which are the controller's: a
    /// mutant no unit carries passes their checks). One the list does not
    /// hold faces every check.
    pub fn in_float_unit(&self, id: u16) -> bool {
        let in_unit = self.files.processor.row().in_float_unit;
        self.get(id).map_or(true, |m| in_unit(&m.module))
    }
}

/// A directed scene of the judge: its file (`rtl/mutate/scenes/NAME.toml`),
/// the window judged (None: the whole image), and `framed_as`: the image
/// width whose field of view the file's camera `distance` was written
/// for, if not its own. Every file is judged as written; one with
/// `framed_as` is judged again, after all of them, with that field of
/// view at the file's own size (the distance scaled by width / framed_as,
/// as `Scene::resized` keeps it).
#[derive(Debug, Clone, Copy)]
pub struct Directed {
    pub name: &'static str,
    pub text: &'static str,
    pub window: Option<Window>,
    pub framed_as: Option<u32>,
}

/// A [`Directed`] scene from its file `rtl/mutate/scenes/NAME.toml`.
macro_rules! directed {
    ($name:literal, $window:expr, $framed_as:expr) => {
        Directed {
            name: $name,
            text: include_str!(concat!("../../rtl/mutate/scenes/", $name, ".toml")),
            window: $window,
            framed_as: $framed_as,
        }
    };
}

/// The judge's directed scenes (`rtl/mutate/scenes/`, docs/mutation.md):
/// written to kill survivors that the builtin and fuzz scenes miss, each
/// named in its file's header; judged whole at their own size, or on the
/// window given. Seven copy the 800-pixel reference layout's camera
/// distance into a 16x12 image, a field of view 50 times narrower than
/// meant (docs/mutation.md, "What stands"): each is judged as written
/// (what it kills stays killed) and framed as the reference frames its
/// 800 pixels, which shows the objects it was written for. The later ones
/// (level_above, green_minus_zero, mirror_corridor, mirror_corridor_lit,
/// six_planes, grazing_overflow, straight_up, and for the fast processor
/// six_planes_bare, planes_shortcut, cutoff_odd and pure_mirrors) are
/// written framed, and were checked to reach their states in golden's
/// trace (or to kill their mutants) before they joined.
pub const DIRECTED: &[Directed] = &[
    directed!("planes_z_first", None, None),
    directed!("planes_x_last", None, None),
    directed!("camera_roll", None, Some(800)),
    directed!("camera_level", None, Some(800)),
    directed!("shortcut_alone", None, Some(800)),
    directed!("materials", None, Some(800)),
    directed!("mirror_shallow", None, Some(800)),
    directed!("weight_cutoff", None, Some(800)),
    directed!("deep_mirrors", None, Some(800)),
    directed!("level_above", None, None),
    directed!("green_minus_zero", None, None),
    directed!("mirror_corridor", None, None),
    directed!("mirror_corridor_lit", None, None),
    directed!("six_planes", None, None),
    directed!("grazing_overflow", None, None),
    directed!("large_frame", Some(Window::new(126, 2046, 4, 4)), None),
    directed!("straight_up", Some(Window::new(1, 129, 1, 1)), None),
    directed!("six_planes_bare", None, None),
    directed!("planes_shortcut", None, None),
    directed!("cutoff_odd", None, None),
    directed!("pure_mirrors", None, None),
];

/// The judge's directed-scene checks: every file of [`DIRECTED`] as
/// written, and the framed ones again.
pub fn directed_checks() -> usize {
    DIRECTED.len() + DIRECTED.iter().filter(|d| d.framed_as.is_some()).count()
}

/// What the judge is made of: every float unit's edge cases and
/// `unit_operands` seeded random operands (seed `fuzz_seed`), every builtin
/// scene at `size`, then the accepted scenes among `fuzz_count` fuzz scenes
/// of `fuzz_seed`; all with the exact methods.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct JudgeSpec {
    pub width: u32,
    pub height: u32,
    pub fuzz_seed: u64,
    pub fuzz_count: u64,
    pub unit_operands: u64,
    pub timeout_cycles: u64,
}

/// The fixed list of checks every mutant of `processor` faces, in order.
#[derive(Debug, Clone)]
pub struct Judge {
    pub processor: ProcessorKind,
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
    /// The judge of `processor`'s mutants: its float units, the scenes,
    /// and (the compact processor's; the fast one's driver runs whole
    /// frames) the resets mid-pixel.
    pub fn new(processor: ProcessorKind, spec: JudgeSpec) -> Result<Judge, JudgeError> {
        let exact = |scene: &Scene, what: &str| {
            with_methods(scene, Method::Exact, Method::Exact, what).map_err(|e| JudgeError {
                what: what.to_string(),
                message: e.to_string(),
            })
        };
        let mut checks = Vec::new();
        for kind in units(processor) {
            let (a, b) = operands::edge_cases(kind);
            checks.push(Check {
                name: format!("{} edge cases", kind.module()),
                stimulus: Stimulus::Unit { kind, a, b },
            });
            if spec.unit_operands > 0 {
                let len = usize::try_from(spec.unit_operands).map_err(|_| JudgeError {
                    what: format!("{} random operands", kind.module()),
                    message: format!("{} operands do not fit in memory", spec.unit_operands),
                })?;
                let (a, b) = operands::random_chunk(kind, spec.fuzz_seed, 0, len);
                checks.push(Check {
                    name: format!(
                        "{} {} random operands of seed {}",
                        kind.module(),
                        spec.unit_operands,
                        spec.fuzz_seed
                    ),
                    stimulus: Stimulus::Unit { kind, a, b },
                });
            }
        }
        let mut scene_check = |name: String, scene: Scene, window: Window| {
            checks.push(Check {
                name,
                stimulus: Stimulus::Scene {
                    scene: Box::new(scene),
                    window,
                },
            })
        };
        // Judged after the fuzz scenes: the compact processor's resets
        // mid-pixel, the fast one's stalled results.
        let mut last = None;
        let builtin_at = |name: &str, width: u32, height: u32| {
            let what = format!("builtin {name} {width}x{height}");
            let scene = Scene::builtin(name)
                .ok_or_else(|| JudgeError {
                    what: what.clone(),
                    message: "not a builtin scene".into(),
                })?
                .resized(width, height, &what)
                .map_err(|e| JudgeError {
                    what: what.clone(),
                    message: e.to_string(),
                })?;
            let scene = exact(&scene, &what)?;
            Ok::<_, JudgeError>((what, scene))
        };
        for name in Scene::builtin_names() {
            let (what, scene) = builtin_at(name, spec.width, spec.height)?;
            let window = Window::full(&scene);
            // A pixel cut short by a reset needs a design driven one pixel
            // at a time.
            if *name == "reference" && mutant_design(processor).driver() == Driver::OnePixel {
                // Its middle pixel, cut short at every cycle of its start.
                let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
                last = Some(Check {
                    name: format!("reset mid-pixel: {what} pixel ({x}, {y}) cut after 1..={RESET_CUTS} cycles"),
                    stimulus: Stimulus::ResetMidPixel {
                        scene: Box::new(scene.clone()),
                        window: Window::new(x, y, 1, 1),
                        cuts: 1..=RESET_CUTS,
                    },
                });
            }
            scene_check(what, scene, window);
        }
        // A result stream to hold back, long enough to fill its queue.
        if mutant_design(processor).has_result_stream() {
            let (width, height) = STALLED_SIZE;
            let (what, scene) = builtin_at("reference", width, height)?;
            last = Some(Check {
                name: format!("{what} with the results {STALLS}"),
                stimulus: Stimulus::Stalled {
                    window: Window::full(&scene),
                    scene: Box::new(scene),
                    stall: STALLS,
                },
            });
        }
        // Every file as written, then the framed ones framed.
        let as_written = DIRECTED.iter().map(|d| (d, None));
        let framed = DIRECTED
            .iter()
            .filter_map(|d| d.framed_as.map(|w| (d, Some(w))));
        for (d, framed_as) in as_written.chain(framed) {
            let what = match framed_as {
                None => format!("directed {}", d.name),
                Some(w) => format!("directed {} framed as {w} wide", d.name),
            };
            let path = format!("rtl/mutate/scenes/{}.toml", d.name);
            let scene = Scene::from_toml(d.text, &path).map_err(|e| JudgeError {
                what: what.clone(),
                message: e.to_string(),
            })?;
            let scene = match framed_as {
                None => scene,
                Some(w) => scene.framed_as(w, &what).map_err(|e| JudgeError {
                    what: what.clone(),
                    message: e.to_string(),
                })?,
            };
            let scene = exact(&scene, &what)?;
            let window = d.window;
            let window = window.unwrap_or_else(|| Window::full(&scene));
            window
                .check_inside(scene.camera.width, scene.camera.height)
                .map_err(|e| JudgeError {
                    what: what.clone(),
                    message: e.to_string(),
                })?;
            scene_check(format!("{what} {}", window.describe()), scene, window);
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
            let window = Window::full(&scene);
            scene_check(what, scene, window);
        }
        checks.extend(last);
        Ok(Judge {
            processor,
            spec,
            checks,
        })
    }

    /// The scene checks (without the resets mid-pixel).
    pub fn scenes(&self) -> usize {
        self.checks
            .iter()
            .filter(|c| matches!(c.stimulus, Stimulus::Scene { .. }))
            .count()
    }

    /// The pixels one mutant faces if it survives.
    pub fn pixels(&self) -> u64 {
        self.checks
            .iter()
            .map(|c| match &c.stimulus {
                Stimulus::Scene { window, .. } | Stimulus::Stalled { window, .. } => {
                    window.pixels()
                }
                Stimulus::ResetMidPixel { window, cuts, .. } => {
                    window.pixels() * cuts.clone().count() as u64
                }
                Stimulus::Unit { .. } => 0,
            })
            .sum()
    }

    /// The float-unit operands a mutant of a float unit faces if it
    /// survives.
    pub fn unit_operands(&self) -> u64 {
        self.checks
            .iter()
            .map(|c| match &c.stimulus {
                Stimulus::Scene { .. }
                | Stimulus::ResetMidPixel { .. }
                | Stimulus::Stalled { .. } => 0,
                Stimulus::Unit { a, .. } => a.len() as u64,
            })
            .sum()
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

/// What one check says of a mutant: `None` if it passed, or how it failed.
fn unit_check(id: u16, kind: UnitKind, a: &[u32], b: &[u32]) -> Option<String> {
    let mut unit = match FpUnit::new_mutant(kind, id) {
        Ok(unit) => unit,
        Err(e) => return Some(e.to_string()),
    };
    let golden = |a, b| kind.golden(a, b);
    match fp_check::check_batch(&mut unit, &golden, a, b) {
        Err(e) => Some(e.to_string()),
        Ok(report) => {
            if let Some(m) = report.first_mismatches.first() {
                Some(format!("{} differs from golden: {m}", kind.module()))
            } else if report.latency_violations > 0 {
                Some(format!(
                    "{} of {} operations took other than the {} cycles golden promises (took {:?})",
                    report.latency_violations,
                    report.operands,
                    kind.latency(),
                    report.cycles
                ))
            } else {
                None
            }
        }
    }
}


/// Judges mutant `id` of the judge's processor's list (0: the design as
/// written) on fresh models: the float-unit checks if `in_float_unit` (see
/// [`List::in_float_unit`]), then the scenes on the processor.
pub fn judge(id: u16, in_float_unit: bool, judge: &Judge) -> Result<Outcome, PpError> {
    let start = Instant::now();
    let mut pixels = 0;
    let outcome = |verdict, pixels| Outcome {
        id,
        verdict,
        pixels,
        seconds: start.elapsed().as_secs_f64(),
    };
    for check in judge.checks.iter().filter(|_| in_float_unit) {
        let Stimulus::Unit { kind, a, b } = &check.stimulus else {
            continue;
        };
        if let Some(how) = unit_check(id, *kind, a, b) {
            let check = check.name.clone();
            return Ok(outcome(Verdict::Killed { check, how }, pixels));
        }
    }
    let options = CosimOptions {
        timeout_cycles: judge.spec.timeout_cycles,
        ..CosimOptions::default()
    };
    let mut dut = mutant_design(judge.processor).open()?;
    dut.set_mutant(id)?;
    dut.set_timeout_cycles(judge.spec.timeout_cycles);
    // One pixel at a time, a mutant that fails its reset is killed by it;
    // streamed, the model resets as each scene loads, and the first scene
    // kills it.
    if let Some(rtl) = dut.one_pixel() {
        if let Err(e) = rtl.reset() {
            let how = e.to_string();
            return Ok(outcome(
                Verdict::Killed {
                    check: "reset".into(),
                    how,
                },
                pixels,
            ));
        }
    }
    for check in &judge.checks {
        let killed = |how: String| Verdict::Killed {
            check: check.name.clone(),
            how,
        };
        // The first failing run kills: a reset check stops at its first
        // failing cut.
        let failed = match &check.stimulus {
            Stimulus::Unit { .. } => continue,
            Stimulus::Scene { scene, window } => failure(
                cosim::run_on(&mut dut, scene, *window, &options, &mut |_| {}),
                &mut pixels,
            ),
            Stimulus::ResetMidPixel {
                scene,
                window,
                cuts,
            } => {
                if dut.one_pixel().is_none() {
                    continue;
                }
                cuts.clone().find_map(|cut| {
                    let rtl = dut.one_pixel().expect("a one-pixel design");
                    let run = cut_short(rtl, scene, *window, cut, &options)
                        .and_then(|()| cosim::run_on(&mut dut, scene, *window, &options, &mut |_| {}));
                    failure(run, &mut pixels)
                })
            }
            Stimulus::Stalled {
                scene,
                window,
                stall,
            } => {
                let stalled = CosimOptions {
                    stall: *stall,
                    ..options
                };
                failure(
                    cosim::run_on(&mut dut, scene, *window, &stalled, &mut |_| {}),
                    &mut pixels,
                )
            }
        };
        if let Some(how) = failed {
            return Ok(outcome(killed(how), pixels));
        }
    }
    Ok(outcome(Verdict::Survived, pixels))
}

/// The judge's last check for `processor`'s mutants, in words: a reset in
/// the middle of a pixel (one pixel at a time), or the results held back
/// (a result stream).
pub fn last_check(processor: ProcessorKind) -> String {
    if mutant_design(processor).has_result_stream() {
        format!("the reference with its results (out_ready low) {STALLS}; ")
    } else {
        format!("the reference's middle pixel reset after each of its first {RESET_CUTS} cycles; ")
    }
}

/// The design a processor's mutants are judged on: its mutant netlist
/// (exact methods, with the exponential).
pub fn mutant_design(processor: ProcessorKind) -> Design {
    Design::new(processor, Method::Exact, Method::Exact).flavour(Flavour::Mutant)
}

/// How a scene run failed (its first divergence's line, or the error), or
/// `None` if it passed; counts its pixels.
fn failure(run: Result<cosim::CosimReport, cosim::CosimError>, pixels: &mut u64) -> Option<String> {
    match run {
        Ok(report) => {
            *pixels += report.compare.counts.pixels;
            (!report.passed()).then(|| match &report.compare.first_divergence {
                Some(d) => d
                    .text(&report.compare.labels)
                    .to_string()
                    .lines()
                    .next()
                    .unwrap_or("diverges")
                    .trim()
                    .to_string(),
                None => "no events compared".to_string(),
            })
        }
        Err(e) => Some(format!("the run failed: {e}")),
    }
}

/// How [`Stimulus::Stalled`] holds the results back: in stalls of up to
/// 40,000 cycles, many longer than the fast processor takes to finish
/// every pixel it holds, so that its result queue fills to 2K entries,
/// and short ready runs (up to 4,444 cycles) that drain it.
pub const STALLS: Stall = Stall {
    percent: 90,
    burst: 40_000,
};

/// The size of the reference [`Stimulus::Stalled`] runs at: the driver runs
/// a window a tile ([`cosim::TILE_ROWS`] rows) at a time and stops at the
/// tile's last result, so a queue of 2K results (64) is seen to drain right
/// only with pixels of the tile still to come; at 80 wide, a tile is 320
/// pixels, so that the queue fills several times in each.
pub const STALLED_SIZE: (u32, u32) = (80, 12);

/// The cycles [`Stimulus::ResetMidPixel`] cuts a pixel after: 1 to this.
pub const RESET_CUTS: u64 = 300;

/// Loads `scene` into `rtl`, starts `window`'s first pixel and lets the
/// watchdog stop it after `cut` cycles (a pixel done sooner is fine), then
/// restores the judge's timeout; the next run's load resets it.
fn cut_short(
    rtl: &mut PixelProcessor,
    scene: &Scene,
    window: Window,
    cut: u64,
    options: &CosimOptions,
) -> Result<(), cosim::CosimError> {
    rtl.load_scene(scene)?;
    rtl.set_timeout_cycles(cut);
    let (x, y) = window.iter().next().unwrap_or((0, 0));
    let run = rtl.run_pixel(x, y, None);
    rtl.set_timeout_cycles(options.timeout_cycles);
    match run {
        Ok(_) | Err(PpError::Hung { .. }) => Ok(()),
        Err(e) => Err(e.into()),
    }
}

/// Judges `ids` of `list` in parallel on the current rayon pool; results
/// in the order of `ids`. `done` is called with each outcome as it is
/// known (a journal, a progress bar). The list and the judge are one
/// processor's.
pub fn run(
    ids: &[u16],
    list: &List,
    judge_: &Judge,
    done: &(dyn Fn(&Outcome) + Sync),
) -> Result<Vec<Outcome>, PpError> {
    debug_assert_eq!(list.files.processor, judge_.processor);
    ids.par_iter()
        .map(|&id| {
            let o = judge(id, list.in_float_unit(id), judge_)?;
            done(&o);
            Ok(o)
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

/// Runs `rtl/mutate/mutants.sh equiv` on `ids` of `processor`'s list
/// (Yosys; seconds a mutant, up to its time limit), with the design the
/// build prepared.
pub fn prove_equivalent(
    processor: ProcessorKind,
    ids: &[u16],
) -> Result<BTreeMap<u16, Equivalence>, String> {
    if ids.is_empty() {
        return Ok(BTreeMap::new());
    }
    let script = script();
    let o = Command::new("bash")
        .arg(&script)
        .arg("equiv")
        .args(ids.iter().map(u16::to_string))
        .env("MUTATE_CACHE", Path::new(env!("OUT_DIR")).join("mutate"))
        .env("MUTATE_DESIGN", Files::of(processor).design())
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
    /// Whose mutants (shard files before the fast processor's: compact).
    #[serde(default)]
    pub processor: ProcessorKind,
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

/// Per module: (mutants, killed, survivors proved or argued equivalent).
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
        row.2 += u64::from(summary.is_equivalent(list, o.id));
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
    /// Whether survivor `id` is proved equivalent (Yosys, this run) or
    /// classified equivalent or unreachable ([`Files::survivors_path`]).
    pub fn is_equivalent(&self, list: &List, id: u16) -> bool {
        self.outcomes
            .iter()
            .any(|o| o.id == id && o.verdict == Verdict::Survived)
            && (self.equivalence.get(&id) == Some(&Equivalence::Equivalent)
                || list
                    .classified
                    .get(&id)
                    .is_some_and(|c| c.class.is_equivalent()))
    }

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
        let argued = survivors
            .iter()
            .filter(|&&id| self.is_equivalent(list, id))
            .count() as u64;
        let classes = |c: Class| {
            survivors
                .iter()
                .filter(|id| list.classified.get(id).map(|x| x.class) == Some(c))
                .count()
        };
        let _ = writeln!(
            s,
            "score of those neither proved nor argued equivalent: {} ({argued} survivors are; \
             {}: {} equivalent, {} unreachable, {} holes, {} open, {} not classified)",
            percent(killed, n - argued),
            list.files.survivors_path,
            classes(Class::Equivalent),
            classes(Class::Unreachable),
            classes(Class::Hole),
            classes(Class::Open),
            survivors
                .iter()
                .filter(|id| !list.classified.contains_key(id))
                .count()
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
            "| module | mutants | killed | survived | proved or argued equivalent | score | score of the not equivalent |"
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
            let _ = writeln!(
                s,
                "| mutant | module | where | mode | equivalence | classified |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|");
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
            let classified = list
                .classified
                .get(&id)
                .map_or("not classified".to_string(), |c| {
                    format!("{}: {}", c.class, c.reason.replace('|', "\\|"))
                });
            let _ = writeln!(
                s,
                "| {id} | {module} | {location} | {mode} | {equivalence} | {classified} |"
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_classification_reads_or_names_the_bad_line() {
        let ok = parse_classification(
            Files::of(ProcessorKind::Compact).survivors_path,
            "# c\n4 unreachable only when x | y\n9 hole a deeper scene\n",
        )
        .expect("reads");
        assert_eq!(ok[&4].class, Class::Unreachable);
        assert_eq!(ok[&4].reason, "only when x | y");
        assert!(ok[&4].class.is_equivalent() && !ok[&9].class.is_equivalent());
        for (bad, says) in [
            ("4 maybe why", "class \"maybe\""),
            ("x hole why", "mutant number"),
            ("4 hole", "not `ID CLASS reason`"),
            ("4 hole a\n4 open b", "classified twice"),
        ] {
            let e = parse_classification(Files::of(ProcessorKind::Fast).survivors_path, bad)
                .expect_err(bad)
                .to_string();
            assert!(
                e.starts_with(Files::of(ProcessorKind::Fast).survivors_path) && e.contains(says),
                "{bad}: {e}"
            );
        }
        for processor in [ProcessorKind::Compact, ProcessorKind::Fast] {
            List::committed(processor).expect("the committed list and classification read");
        }
    }

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
    fn the_committed_lists_read_and_number_their_mutants_from_one() {
        for (processor, some_modules) in [
            (
                ProcessorKind::Compact,
                ["pp_ctrl", "alu", "memory", "fp_add", "fp_recip"],
            ),
            (
                ProcessorKind::Fast,
                [
                    "fast_ctrl",
                    "fast_alu",
                    "fast_regfile",
                    "fast_fp_add",
                    "fast_fp_recip",
                ],
            ),
        ] {
            let list = List::committed(processor).unwrap();
            assert_eq!(list.files.processor, processor);
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
            for m in some_modules {
                assert!(
                    modules.contains(m),
                    "{processor}: no mutant of {m}: {modules:?}"
                );
            }
            // A float unit's mutant faces the unit checks, the
            // controller's does not.
            let of = |module: &str| {
                list.mutants
                    .iter()
                    .find(|m| m.module.ends_with(module))
                    .unwrap()
                    .id
            };
            let (unit, ctrl) = match processor {
                ProcessorKind::Compact => (of("fp_add"), of("pp_ctrl")),
                ProcessorKind::Fast => (of("fp_add"), of("fast_ctrl")),
            };
            assert!(list.in_float_unit(unit));
            assert!(!list.in_float_unit(ctrl));
        }
    }

    #[test]
    fn a_list_out_of_order_or_without_its_hash_is_refused() {
        let head = "# rtl fnv1a64 0123\n";
        let line = "mutate -mode inv -module pp_ctrl -cell x -port Y -src rtl/pp/pp_ctrl.v:5.1-5.2";
        let ok = List::parse(Files::of(ProcessorKind::Compact), &format!("{head}1 {line}\n2 {line}\n")).unwrap();
        assert_eq!(ok.mutants[1].location, "rtl/pp/pp_ctrl.v:5");
        let e = List::parse(Files::of(ProcessorKind::Compact), &format!("{head}1 {line}\n3 {line}\n")).unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("expected 2"), "{e}");
        assert!(List::parse(Files::of(ProcessorKind::Compact), &format!("1 {line}\n")).is_err());
        let e = List::parse(Files::of(ProcessorKind::Compact), &format!("{head}1 mutant -mode inv\n")).unwrap_err();
        assert!(e.message.contains("not a `mutate` command"), "{e}");
    }
}
