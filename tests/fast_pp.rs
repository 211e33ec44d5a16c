//! The fast pixel processor (rtl/fast/fast_pp.v) co-simulated through its
//! streams against golden: every pixel's register-file writes are
//! golden::micro's, in order, bit for bit, its colour is golden's, and its
//! cycles and context, and the frame's cycles, are the barrel rule's
//! (golden::micro::barrel) for the pixels in the order they were fed.
//! Each checker is shown to fail: a fault planted in the RTL's writes, and
//! a barrel of the wrong size, are reported. The same for a top of fast
//! processors (rtl/top.v with FAST = 1), whose pixels' processors, contexts
//! and cycles, and frames' cycles, are the top's rule's
//! (golden::micro::barrel::run_top).

use golden::micro::barrel::{self, PixelWork};
use golden::micro::fault::Fault;
use golden::micro::isa::state;
use golden::micro::Processor;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use golden::window::Window;
use rtcosim::design::processor::FAST_CONTEXTS;
use rtcosim::design::top::{Source, Stall, Top};

mod common;

use common::{builtin, window};
use golden::fp::Method;
use rtcosim::design::Design;

/// Cycles a frame takes beyond the barrel rule's (fast_pp.v: one into the
/// coordinate queue, two of the register file's read, one into the result
/// queue).
const FRAME_OVERHEAD: u64 = 4;

/// What differs between a pixel's writes in the RTL and golden's, if anything.
fn pixel_diff(rtl: &[TraceEvent], golden: &[TraceEvent]) -> Option<String> {
    for (i, (r, g)) in rtl.iter().zip(golden).enumerate() {
        if (r.state, r.dst, r.lanes, r.values) != (g.state, g.dst, g.lanes, g.values) {
            return Some(format!("write #{i}: rtl {r:?}, golden {g:?}"));
        }
    }
    (rtl.len() != golden.len()).then(|| format!("{} writes, golden {}", rtl.len(), golden.len()))
}

/// Runs `coords` (each once) of `scene` through the fast processor with
/// `fault` planted, and checks it against golden and a barrel of
/// `contexts`: the divergences found, one line each.
fn cosim(scene: &Scene, coords: &[(u32, u32)], fault: Option<Fault>, contexts: u32) -> Vec<String> {
    let g = Processor::new(scene);
    let mut t = Top::open(&Design::fast(scene.render.recip, scene.render.sqrt))
        .unwrap_or_else(|e| panic!("{e}"));
    t.load_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    t.set_fault(fault, u32::MAX);
    let mut bad = Vec::new();
    let mut got = Vec::new();
    let stats = t
        .run_frame(Source::Stream(coords), &mut |p| {
            let mut events = Vec::new();
            let r = g.render_pixel(p.x, p.y, |e, _| events.push(*e));
            if let Some(d) = pixel_diff(p.events, &events) {
                bad.push(format!("({}, {}): {d}", p.x, p.y));
            }
            if p.outcome.rgb != r.rgb.map(f32::to_bits) {
                bad.push(format!(
                    "({}, {}): colour {:?}, golden {:?}",
                    p.x, p.y, p.outcome.rgb, r.rgb
                ));
            }
            got.push(((p.x, p.y), p.processor, p.outcome.cycles));
        })
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(got.len(), coords.len(), "every pixel came back");
    // The barrel rule, for the pixels in the order they were fed; contexts
    // are numbered from the one that took the first pixel.
    let work: Vec<PixelWork> = coords
        .iter()
        .map(|&(x, y)| PixelWork::of(&g.render_pixel(x, y, |_, _| {})))
        .collect();
    let run = barrel::run(contexts, &work);
    let first = got
        .iter()
        .find(|(at, _, _)| *at == coords[0])
        .map_or(0, |g| g.1);
    for &(at, ctx, cycles) in &got {
        let i = coords.iter().position(|&c| c == at).expect("a pixel fed");
        let want = run.pixels[i];
        let context = (ctx + FAST_CONTEXTS - first) % FAST_CONTEXTS;
        if (cycles, context) != (want.cycles(), want.context) {
            bad.push(format!(
                "{at:?}: context {context}, {cycles} cycles; barrel: context {}, {} cycles",
                want.context,
                want.cycles()
            ));
        }
    }
    if stats.frame_cycles != run.cycles + FRAME_OVERHEAD {
        bad.push(format!(
            "the frame took {} cycles; barrel {} + {FRAME_OVERHEAD}",
            stats.frame_cycles, run.cycles
        ));
    }
    bad
}

fn assert_exact(bad: &[String]) {
    assert!(
        bad.is_empty(),
        "{} divergences:\n{}",
        bad.len(),
        bad[..bad.len().min(20)].join("\n")
    );
}

#[test]
fn fast_processor_draws_a_reference_window_as_golden_and_the_barrel() {
    let scene = builtin("reference", 40, 30);
    assert_exact(&cosim(&scene, &window(8, 6, 12, 8), None, FAST_CONTEXTS));
}

/// Fewer pixels than contexts (most contexts idle throughout), and one
/// pixel alone.
#[test]
fn fast_processor_is_exact_with_idle_contexts() {
    let scene = builtin("reference", 40, 30);
    assert_exact(&cosim(&scene, &window(20, 14, 5, 1), None, FAST_CONTEXTS));
    assert_exact(&cosim(&scene, &[(3, 4)], None, FAST_CONTEXTS));
}

/// The checkers fail: a fault in the RTL's writes is a divergence of the
/// pixels it touches, and a barrel of other than the RTL's contexts
/// predicts other cycles.
#[test]
fn fast_processor_checkers_fail_on_injected_faults() {
    let scene = builtin("reference", 40, 30);
    let coords = window(8, 6, 12, 8);
    let fault = Fault {
        state: state::PRI_HALF,
        xor: 1 << 20,
    };
    let bad = cosim(&scene, &coords, Some(fault), FAST_CONTEXTS);
    let written = bad.iter().filter(|b| b.contains("write #1: rtl")).count();
    assert_eq!(
        written,
        coords.len(),
        "every pixel's PRI_HALF write is hit:\n{}",
        bad.join("\n")
    );
    let bad = cosim(&scene, &coords, None, FAST_CONTEXTS - 1);
    assert!(
        bad.iter().any(|b| b.contains("cycles; barrel")),
        "{}",
        bad.join("\n")
    );
    assert!(
        bad.iter().any(|b| b.contains("the frame took")),
        "{}",
        bad.join("\n")
    );
}

/// Every builtin scene, a whole reduced frame, through the co-simulation
/// engine (`cosim::run`, tiles of 4 rows) on `top` (with each scene's
/// methods): every event,
/// colour and pixel cycle count, and each tile's frame cycles, as golden
/// and the processors' rule say.
/// A processor without its exponential (`top.exp_unit` false) runs the
/// scenes without exposure (at least one is left out).
fn assert_every_builtin_scene_agrees(top: &Design) {
    use rtcosim::check::cosim::{self, CosimOptions};
    let scenes: Vec<_> = Scene::builtin_names()
        .iter()
        .map(|&name| (name, builtin(name, 32, 24)))
        .filter(|(_, scene)| top.exp_unit || scene.render.exposure.is_none())
        .collect();
    assert!(
        top.exp_unit || scenes.len() < Scene::builtin_names().len(),
        "a builtin scene with exposure"
    );
    for (name, scene) in scenes {
        let window = Window::full(&scene);
        let design = top.methods_of(&scene);
        let r = cosim::run(&design, &scene, window, &CosimOptions::default(), &|_| {})
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let c = &r.compare.counts;
        assert_eq!(c.pixels, window.pixels(), "{name}\n{r}");
        assert!(
            c.events_compared > 0 && c.events_compared == c.b_events,
            "{name}\n{r}"
        );
        assert_eq!(c.a_cycles, c.b_cycles, "{name}\n{r}");
        let t = r.top.expect("the top's report");
        assert!(
            t.predicted_frame_cycles.is_some() && t.frame_cycles_agree(),
            "{name}\n{r}"
        );
        assert_eq!(
            (r.design.procs, t.contexts),
            (top.procs, top.contexts()),
            "{name}"
        );
        assert!(r.passed(), "{name}\n{r}");
    }
}

/// `cosim --processor fast`: the bare fast processor, the barrel rule.
#[test]
fn every_builtin_scene_agrees_on_the_fast_processor() {
    assert_every_builtin_scene_agrees(&Design::fast(Method::Exact, Method::Exact));
}

/// `cosim --processor fast --no-exp-unit`: the fast processor built
/// without its exponential (`EXPOSURE = 0`) on every builtin scene without
/// exposure; a fault planted in it is reported; it refuses a scene with
/// exposure when the scene is loaded, naming why.
#[test]
fn every_builtin_scene_without_exposure_agrees_on_the_fast_processor_without_exp() {
    use rtcosim::check::cosim::{self, CosimOptions};
    use rtcosim::design::PpError;
    let without = Design::fast(Method::Exact, Method::Exact).exp_unit(false);
    assert_every_builtin_scene_agrees(&without);

    let scene = builtin("reference", 32, 24);
    let options = CosimOptions {
        fault: Some(Fault {
            state: state::PRI_HALF,
            xor: 0x400,
        }),
        ..CosimOptions::default()
    };
    let r = cosim::run(&without, &scene, Window::full(&scene), &options, &|_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(!r.passed() && r.compare.counts.divergent_pixels > 0, "{r}");

    let overexposed = builtin("overexposed", 32, 24);
    let exposure = overexposed
        .render
        .exposure
        .expect("overexposed sets an exposure");
    let mut t =
        Top::open(&Design::fast(overexposed.render.recip, overexposed.render.sqrt).exp_unit(false))
            .unwrap_or_else(|e| panic!("{e}"));
    let refused = t.load_scene(&overexposed);
    assert_eq!(
        refused,
        Err(PpError::NoExpUnit {
            exposure_bits: exposure.to_bits()
        })
    );
    assert!(refused
        .unwrap_err()
        .to_string()
        .contains("built without its exponential (EXPOSURE = 0)"),);
    // The build with it draws the scene.
    t.load_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
}

/// Backpressure: the result stream held back in 99% of the cycles fills
/// the result queue, so the processor refuses takes (2K pixels held); every
/// pixel is still exact, and its cycles are the barrel rule's with those
/// takes refused (`run_gated`), which differ from the rule's without
/// refusals: the check sees the refusals.
#[test]
fn fast_processor_is_exact_under_backpressure() {
    let scene = builtin("overexposed", 40, 30);
    let (refused, cycles) = run_stalled(&scene, &window(0, 0, 40, 8), 7, Stall::percent(99));
    assert!(!refused.is_empty(), "the result queue never filled");
    let open = barrel::run(FAST_CONTEXTS, &cycles.work);
    assert!(
        cycles
            .got
            .iter()
            .enumerate()
            .any(|(i, &(_, c))| c != open.pixels[i].cycles()),
        "the refusals changed no pixel's cycles: the check would not see them"
    );
}

/// The mutation judge's stalled check (`mutation::STALLS` on the reference
/// at `STALLED_SIZE`, its first tile as `cosim` runs it) holds the stream
/// back long enough that every pixel held is finished and waits in the
/// result queue, 2K entries, with pixels of the tile still to come: a run
/// of refused takes (2K held, counted from the handshakes, up to 2 more
/// in the coordinate queue) outlasts two of the slowest pixels before the
/// tile's last 2K are taken. Held back a cycle at a time (99%), out_ready
/// is high every 100 cycles or so and the queue never fills: a mutant of
/// its count at 2K (454) survived that.
#[test]
fn bursts_of_backpressure_fill_the_result_queue() {
    let (width, height) = rtcosim::campaign::mutation::STALLED_SIZE;
    let scene = builtin("reference", width, height);
    let tile = rtcosim::check::cosim::tiles(Window::full(&scene))[0];
    let coords: Vec<(u32, u32)> = tile.iter().collect();
    let seed = rtcosim::check::cosim::backpressure_seed(&coords);
    let (refused, cycles) = run_stalled(&scene, &coords, seed, rtcosim::campaign::mutation::STALLS);
    let slowest = cycles.slowest();
    let longest = longest_run(&refused);
    assert!(
        longest > 2 * slowest,
        "the longest run of refused takes ({longest} cycles) does not outlast two of the \
         slowest pixel ({slowest} cycles): the queue may never have held 2K results"
    );
    let (refused, once) = run_stalled(&scene, &coords, seed, Stall::percent(99));
    let slowest = once.slowest();
    assert!(
        longest_run(&refused) <= slowest,
        "stalls drawn each cycle filled the queue: the bursts would not be needed"
    );
}

/// The longest run of consecutive cycles in `cycles` (sorted).
fn longest_run(cycles: &[u64]) -> u64 {
    let (mut longest, mut run, mut last) = (0, 0, None);
    for &c in cycles {
        run = if last == Some(c.wrapping_sub(1)) {
            run + 1
        } else {
            1
        };
        longest = longest.max(run);
        last = Some(c);
    }
    longest
}

/// The pixels of a stalled run: golden's work for each, and each result's
/// place and cycles.
struct StalledRun {
    work: Vec<PixelWork>,
    got: Vec<((u32, u32), u64)>,
}

impl StalledRun {
    /// The cycles of its slowest pixel.
    fn slowest(&self) -> u64 {
        self.got.iter().map(|&(_, c)| c).max().expect("pixels")
    }
}

/// Streams `coords` of `scene` through the bare fast processor with its
/// result stream held back by `stall` (seeded with `seed`); checks every
/// pixel against golden (writes, colour) and its cycles against the
/// barrel rule with the processor's refused takes (`run_gated`), in
/// coordinate order. The refused takes' cycles, and the run.
fn run_stalled(
    scene: &Scene,
    coords: &[(u32, u32)],
    seed: u64,
    stall: Stall,
) -> (Vec<u64>, StalledRun) {
    let g = Processor::new(scene);
    let mut t = Top::open(&Design::fast(scene.render.recip, scene.render.sqrt))
        .unwrap_or_else(|e| panic!("{e}"));
    t.load_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    t.set_backpressure(seed, stall);
    let mut bad = Vec::new();
    let mut cycles = Vec::new();
    t.run_frame(Source::Stream(coords), &mut |p| {
        let mut events = Vec::new();
        let r = g.render_pixel(p.x, p.y, |e, _| events.push(*e));
        if let Some(d) = pixel_diff(p.events, &events) {
            bad.push(format!("({}, {}): {d}", p.x, p.y));
        }
        if p.outcome.rgb != r.rgb.map(f32::to_bits) {
            bad.push(format!("({}, {}): colour", p.x, p.y));
        }
        cycles.push(((p.x, p.y), p.outcome.cycles));
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_exact(&bad);
    assert_eq!(
        cycles.len(),
        coords.len(),
        "every pixel came back ({stall})"
    );
    let refused = t.refused_takes();
    let work: Vec<PixelWork> = coords
        .iter()
        .map(|&(x, y)| PixelWork::of(&g.render_pixel(x, y, |_, _| {})))
        .collect();
    let gated = barrel::run_gated(FAST_CONTEXTS, &work, &|c| {
        refused.binary_search(&c).is_err()
    });
    // In coordinate order.
    let got: Vec<((u32, u32), u64)> = coords
        .iter()
        .map(|&at| {
            let &(_, c) = cycles.iter().find(|&&(p, _)| p == at).expect("came back");
            (at, c)
        })
        .collect();
    let wrong: Vec<_> = got
        .iter()
        .enumerate()
        .filter(|&(i, &(_, c))| c != gated.pixels[i].cycles())
        .collect();
    assert!(
        wrong.is_empty(),
        "{stall}: {} pixels' cycles differ from the gated rule: {wrong:?}",
        wrong.len()
    );
    (refused, StalledRun { work, got })
}

// ---------------------------------------------------------------------------
// A top of fast processors (rtl/top.v with FAST = 1)
// ---------------------------------------------------------------------------

/// Processors of the top of fast processors the default build verilates,
/// and its ARB_GROUP (each processor a result group of its own).
const TOP_PROCS: u32 = 2;
const TOP_GROUP: u32 = 1;

/// Runs `coords` (each once) of `scene` through the top of [`TOP_PROCS`]
/// fast processors with `fault` planted and out_ready low in
/// `stall_percent` % of the cycles, and checks it against golden and the
/// top's rule for `rule` = (processors, contexts, group), told of the stalled
/// cycles if `rule_sees_stalls`: every write and colour, each pixel's
/// processor, context and cycles, and the frame's cycles. The divergences
/// found, one line each.
fn cosim_top(
    scene: &Scene,
    coords: &[(u32, u32)],
    fault: Option<Fault>,
    stall_percent: u32,
    rule: (u32, u32, u32),
    rule_sees_stalls: bool,
) -> Vec<String> {
    let g = Processor::new(scene);
    let mut t =
        Top::open(&Design::fast(scene.render.recip, scene.render.sqrt).procs(Some(TOP_PROCS)))
            .unwrap_or_else(|e| panic!("{e}"));
    t.load_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    t.set_fault(fault, u32::MAX);
    t.set_backpressure(3, Stall::percent(stall_percent));
    assert_eq!(t.arb_group(), TOP_GROUP, "the model's ARB_GROUP");
    let phase = t.turn_phase();
    let mut bad = Vec::new();
    let mut got = Vec::new();
    let stats = t
        .run_frame(Source::Stream(coords), &mut |p| {
            let mut events = Vec::new();
            let r = g.render_pixel(p.x, p.y, |e, _| events.push(*e));
            if let Some(d) = pixel_diff(p.events, &events) {
                bad.push(format!("({}, {}): {d}", p.x, p.y));
            }
            if p.outcome.rgb != r.rgb.map(f32::to_bits) {
                bad.push(format!("({}, {}): colour", p.x, p.y));
            }
            got.push(((p.x, p.y), p.processor, p.outcome.cycles));
        })
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(got.len(), coords.len(), "every pixel came back");
    let stalled = t.stalled_cycles();
    assert_eq!(
        stalled.is_empty(),
        stall_percent == 0,
        "out_ready low in {} cycles at {stall_percent}%",
        stalled.len()
    );
    let work: Vec<PixelWork> = coords
        .iter()
        .map(|&(x, y)| PixelWork::of(&g.render_pixel(x, y, |_, _| {})))
        .collect();
    let start = barrel::TopStart {
        procs: rule.0,
        contexts: rule.1,
        phase: phase % rule.1,
        group: rule.2,
        last_grant: 0,
    };
    let run = barrel::run_top(start, &work, &|c| {
        !rule_sees_stalls || stalled.binary_search(&c).is_err()
    });
    for &(at, slot, cycles) in &got {
        let i = coords.iter().position(|&c| c == at).expect("a pixel fed");
        let want = run.pixels[i];
        let got = (slot / FAST_CONTEXTS, slot % FAST_CONTEXTS, cycles);
        let rule = (want.proc, want.run.context, want.run.cycles());
        if got != rule {
            bad.push(format!(
                "{at:?}: processor, context, cycles {got:?}; top rule {rule:?}"
            ));
        }
    }
    if stats.frame_cycles != run.frame_cycles {
        bad.push(format!(
            "the frame took {} cycles; the top rule {}",
            stats.frame_cycles, run.frame_cycles
        ));
    }
    bad
}

/// 144 pixels: processor 0's 32 contexts and queue fill first, the rest go
/// to processor 1, and their results meet at the arbiter.
#[test]
fn a_top_of_fast_processors_agrees_with_golden_and_its_rule() {
    let scene = builtin("reference", 40, 30);
    let coords = window(4, 6, 24, 6);
    assert_exact(&cosim_top(
        &scene,
        &coords,
        None,
        0,
        (TOP_PROCS, FAST_CONTEXTS, TOP_GROUP),
        true,
    ));
    // One pixel, and fewer pixels than one processor's contexts.
    assert_exact(&cosim_top(
        &scene,
        &[(3, 4)],
        None,
        0,
        (TOP_PROCS, FAST_CONTEXTS, TOP_GROUP),
        true,
    ));
    assert_exact(&cosim_top(
        &scene,
        &window(20, 14, 5, 1),
        None,
        0,
        (TOP_PROCS, FAST_CONTEXTS, TOP_GROUP),
        true,
    ));
}

/// The result stream held back: results wait in the out register and the
/// processors' result queues, the processors refuse takes when 2K pixels
/// are held, the stage and the queues fill; every pixel is exact and its
/// cycles, processor and context are still the rule's (with out_ready as
/// the run drew it), which differ from the rule's with out_ready always
/// high, and from the rule's with another result group size.
#[test]
fn a_top_of_fast_processors_is_exact_under_backpressure() {
    let scene = builtin("overexposed", 40, 30);
    let coords = window(0, 0, 40, 4);
    for stall in [60, 99] {
        assert_exact(&cosim_top(
            &scene,
            &coords,
            None,
            stall,
            (TOP_PROCS, FAST_CONTEXTS, TOP_GROUP),
            true,
        ));
    }
    // The same run against the rule without the stalls, and against the
    // rule with both processors in one result group: the check sees both.
    let bad = cosim_top(
        &scene,
        &coords,
        None,
        99,
        (TOP_PROCS, FAST_CONTEXTS, TOP_GROUP),
        false,
    );
    assert!(
        bad.iter().any(|b| b.contains("top rule")),
        "{}",
        bad.join("\n")
    );
    let bad = cosim_top(
        &scene,
        &coords,
        None,
        99,
        (TOP_PROCS, FAST_CONTEXTS, TOP_GROUP + 1),
        true,
    );
    assert!(
        bad.iter().any(|b| b.contains("top rule")),
        "{}",
        bad.join("\n")
    );
}

/// The checkers fail: a fault in the RTL's writes is a divergence of every
/// pixel it touches, and the rule for another number of processors or
/// contexts predicts other placements or cycles (another group size:
/// `a_top_of_fast_processors_is_exact_under_backpressure`).
#[test]
fn a_top_of_fast_processors_checkers_fail_on_injected_faults() {
    let scene = builtin("reference", 40, 30);
    let coords = window(4, 6, 24, 4);
    let fault = Fault {
        state: state::PRI_HALF,
        xor: 1 << 20,
    };
    let bad = cosim_top(
        &scene,
        &coords,
        Some(fault),
        0,
        (TOP_PROCS, FAST_CONTEXTS, TOP_GROUP),
        true,
    );
    let written = bad.iter().filter(|b| b.contains("write #1: rtl")).count();
    assert_eq!(written, coords.len(), "{}", bad.join("\n"));
    for rule in [
        (TOP_PROCS + 1, FAST_CONTEXTS, TOP_GROUP),
        (TOP_PROCS, FAST_CONTEXTS - 1, TOP_GROUP),
    ] {
        let bad = cosim_top(&scene, &coords, None, 0, rule, true);
        assert!(
            bad.iter().any(|b| b.contains("top rule")),
            "{rule:?}: {}",
            bad.join("\n")
        );
    }
}

/// `cosim --processor fast --procs 2`: the top of fast processors, the
/// top's rule.
#[test]
fn every_builtin_scene_agrees_on_a_top_of_fast_processors() {
    assert_every_builtin_scene_agrees(
        &Design::fast(Method::Exact, Method::Exact).procs(Some(TOP_PROCS)),
    );
}

/// `cosim::run_pixels` on the fast processor (the sweep's confirmation):
/// a scattered list of pixels, not a window, more than one chunk of 1,024,
/// streamed chunk by chunk and checked like a window (cycles by the barrel
/// rule for each chunk); a fault is seen; a pixel listed twice is refused
/// by name (results are matched to pixels by their coordinates).
#[test]
fn a_list_of_pixels_runs_on_the_fast_processor() {
    use rtcosim::check::cosim::{run_pixels, CosimError, CosimOptions};
    use rtcosim::design::processor::ProcessorKind;
    use rtcosim::output::device::Build;
    let scene = Scene::reference().resized(64, 48, "test").expect("resized");
    let (recip, sqrt) = (scene.render.recip, scene.render.sqrt);
    let build = Build::for_scene(ProcessorKind::Fast, recip, sqrt, &scene);
    let fast = build.design().unwrap_or_else(|e| panic!("{e}"));
    // Every other pixel, backwards (out of row order): 1,536, two chunks.
    let pixels: Vec<(u32, u32)> = (0..64 * 48)
        .rev()
        .step_by(2)
        .map(|i| (i % 64, i / 64))
        .collect();
    assert!(pixels.len() > 1024);
    let options = CosimOptions::default();
    let report =
        run_pixels(&fast, &scene, &pixels, &options, &|_| {}).unwrap_or_else(|e| panic!("{e}"));
    assert!(report.passed(), "{report}");
    assert_eq!(report.counts.pixels, pixels.len() as u64);
    let faulty = CosimOptions {
        fault: Some("PRI_HALF:0x400".parse().expect("a fault")),
        ..CosimOptions::default()
    };
    let report = run_pixels(&fast, &scene, &pixels[..40], &faulty, &|_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.counts.divergent_pixels, 40, "{report}");
    let twice = [(3, 4), (5, 6), (3, 4)];
    let err = run_pixels(&fast, &scene, &twice, &options, &|_| {}).expect_err("a repeated pixel");
    assert_eq!(err, CosimError::Repeated { x: 3, y: 4 });
    assert_eq!(
        err.to_string(),
        "pixel (3, 4) is listed twice: a tile's pixels must be distinct"
    );
    // A build the harness does not verilate is refused by name, and a
    // design of other methods than the scene's before any pixel runs.
    let other = |m: golden::fp::Method| golden::fp::Method::ALL.into_iter().find(|&n| n != m);
    let not_built = [
        (
            Build {
                stack_depth: 4,
                ..build
            },
            "the models are verilated with STACK_DEPTH 8 only",
        ),
        (
            Build {
                processor: ProcessorKind::Compact,
                exposure: false,
                ..build
            },
            "the compact processor always has its exponential",
        ),
    ];
    for (build, why) in not_built {
        let err = build.design().expect_err("a build not verilated");
        assert!(err.to_string().ends_with(why), "{err}");
    }
    let other_methods = Design::fast(other(recip).expect("two methods"), sqrt);
    let err = run_pixels(&other_methods, &scene, &pixels[..2], &options, &|_| {})
        .expect_err("other methods than the scene's");
    assert!(
        err.to_string().contains("but this pixel processor"),
        "{err}"
    );
}
