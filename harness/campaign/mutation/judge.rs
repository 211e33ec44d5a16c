//! The judge: the fixed list of checks every mutant of a processor faces,
//! and the verdict of each mutant.

use super::*;

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
            text: include_str!(concat!("../../../rtl/mutate/scenes/", $name, ".toml")),
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
/// trace (or to kill their mutants) before they joined; so are the glass
/// scenes (glass_deep ... glass_owed), the last two found rather than
/// written: scenes of a family drawn at random, each traced by golden,
/// the first whose trace shows the order of events its mutant needs kept.
/// large_frame is judged on two windows, one where each coordinate's high
/// bits move.
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
    directed!("large_frame", Some(Window::new(2046, 126, 4, 4)), None),
    directed!("straight_up", Some(Window::new(1, 129, 1, 1)), None),
    directed!("six_planes_bare", None, None),
    directed!("planes_shortcut", None, None),
    directed!("cutoff_odd", None, None),
    directed!("pure_mirrors", None, None),
    directed!("glass_deep", None, None),
    directed!("glass_shortcut", None, None),
    directed!("glass_corridor", None, None),
    directed!("glass_escape", None, None),
    directed!("glass_owed", None, None),
    directed!("pitch_subnormal", None, None),
];

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
    /// The hash of the [`Corpus`] that takes the directed scenes' place,
    /// if one does ([`Judge::with_corpus`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corpus: Option<u64>,
}

/// A folder of scene files (a guided campaign's corpus, `fuzz --corpus`)
/// that takes the place of the written directed scenes in a judge: each
/// file judged whole at its own size, with the exact methods, in the order
/// of their names; a file equal to a builtin check is left out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Corpus {
    /// The folder, for the judge's description.
    pub dir: std::path::PathBuf,
    /// (file name, text), sorted by name.
    pub files: Vec<(String, String)>,
    /// FNV-1a 64 of the names and texts: what the campaign records.
    pub hash: u64,
}

impl Corpus {
    /// Every `*.toml` of `dir`.
    pub fn load(dir: &std::path::Path) -> Result<Corpus, JudgeError> {
        let fail = |message: String| JudgeError {
            what: format!("corpus {}", dir.display()),
            message,
        };
        let mut files = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(|e| fail(e.to_string()))? {
            let path = entry.map_err(|e| fail(e.to_string()))?.path();
            if path.extension().is_some_and(|e| e == "toml") {
                let text = std::fs::read_to_string(&path)
                    .map_err(|e| fail(format!("{}: {e}", path.display())))?;
                let name = path
                    .file_name()
                    .map_or(String::new(), |n| n.to_string_lossy().into());
                files.push((name, text));
            }
        }
        if files.is_empty() {
            return Err(fail("no scene files (*.toml) in it".into()));
        }
        files.sort();
        let mut h = fnv::FnvHasher::default();
        for (name, text) in &files {
            std::hash::Hasher::write(&mut h, name.as_bytes());
            std::hash::Hasher::write(&mut h, &[0]);
            std::hash::Hasher::write(&mut h, text.as_bytes());
            std::hash::Hasher::write(&mut h, &[0]);
        }
        Ok(Corpus {
            dir: dir.to_path_buf(),
            files,
            hash: std::hash::Hasher::finish(&h),
        })
    }
}

/// The fixed list of checks every mutant of `processor` faces, in order.
#[derive(Debug, Clone)]
pub struct Judge {
    pub processor: ProcessorKind,
    pub spec: JudgeSpec,
    pub checks: Vec<Check>,
    /// The directed checks (or the corpus' scenes in their place), and
    /// where they come from, in words.
    pub directed: usize,
    pub directed_from: String,
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
        Judge::build(processor, spec, None)
    }

    /// The judge of `processor`'s mutants with the scenes of `corpus` in
    /// the place of the directed scenes (the proof that a guided campaign
    /// finds what was written by hand: docs/mutation.md).
    pub fn with_corpus(
        processor: ProcessorKind,
        spec: JudgeSpec,
        corpus: &Corpus,
    ) -> Result<Judge, JudgeError> {
        let spec = JudgeSpec {
            corpus: Some(corpus.hash),
            ..spec
        };
        Judge::build(processor, spec, Some(corpus))
    }

    fn build(
        processor: ProcessorKind,
        spec: JudgeSpec,
        corpus: Option<&Corpus>,
    ) -> Result<Judge, JudgeError> {
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
        let mut builtin_scenes = Vec::new();
        let mut directed = 0;
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
            builtin_scenes.push(scene.clone());
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
        // The corpus' scenes in the place of the directed ones.
        for (name, text) in corpus.map_or(&[][..], |c| &c.files[..]) {
            let what = format!("corpus {name}");
            let scene = Scene::from_toml(text, &what).map_err(|e| JudgeError {
                what: what.clone(),
                message: e.to_string(),
            })?;
            let scene = exact(&scene, &what)?;
            if builtin_scenes.contains(&scene) {
                continue;
            }
            let window = Window::full(&scene);
            directed += 1;
            scene_check(format!("{what} {}", window.describe()), scene, window);
        }
        // Every file as written, then the framed ones framed.
        let as_written = DIRECTED
            .iter()
            .filter(|_| corpus.is_none())
            .map(|d| (d, None));
        let framed = DIRECTED
            .iter()
            .filter(|_| corpus.is_none())
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
            directed += 1;
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
            directed,
            directed_from: corpus.map_or("rtl/mutate/scenes/".to_string(), |c| {
                format!("corpus {}", c.dir.display())
            }),
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
        timeout_cycles: Some(judge.spec.timeout_cycles),
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
                    let run = cut_short(rtl, scene, *window, cut).and_then(|()| {
                        cosim::run_on(&mut dut, scene, *window, &options, &mut |_| {})
                    });
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
/// restores the timeout it had; the next run's load resets it.
fn cut_short(
    rtl: &mut PixelProcessor,
    scene: &Scene,
    window: Window,
    cut: u64,
) -> Result<(), cosim::CosimError> {
    rtl.load_scene(scene)?;
    let timeout = rtl.timeout_cycles();
    rtl.set_timeout_cycles(cut);
    let (x, y) = window.iter().next().unwrap_or((0, 0));
    let run = rtl.run_pixel(x, y, None);
    rtl.set_timeout_cycles(timeout);
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
