//! The top module (rtl/top.v) co-simulated through its streams: N pixel
//! processors give the same frame and the same per-pixel cycles as one, and
//! as golden::micro; backpressure on the result stream loses and duplicates
//! nothing; bad requests are refused before the first cycle; a hung
//! processor is named by the watchdog; the fault self-test sees through the
//! top; the scene changes between two frames through the scene port.
//!
//! Expected values come from golden::micro and from the rules docs/rtl.md
//! gives the top (lowest free processor first), never from the driver.

mod common;

use golden::micro::isa::state;
use golden::micro::Processor;
use golden::scene::Scene;
use golden::window::Window;
use rtcosim::check::cosim::{self, CosimError, CosimOptions};
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::top::{Source, Stall, Top};
use rtcosim::design::Design;
use rtcosim::design::{Fault, HangKind, PpError, ProcessorId, SlotLayout};
use std::collections::BTreeMap;

fn builtin(name: &str, width: u32, height: u32) -> Scene {
    Scene::builtin(name)
        .unwrap_or_else(|| panic!("builtin scene {name}"))
        .resized(width, height, name)
        .expect("a smaller image of a valid scene is valid")
}

fn top(procs: u32, scene: &Scene) -> Top {
    let mut t =
        Top::open(&Design::compact(scene.render.recip, scene.render.sqrt).procs(Some(procs)))
            .unwrap_or_else(|e| panic!("{e}"));
    t.load_scene(scene).unwrap_or_else(|e| panic!("{e}"));
    t
}

/// One pixel as the top gave it: colour bits, its cycles, its events.
type Got = ([u32; 3], u64, u64);

/// Runs a frame and returns every result in the order it left, with the
/// processor that made it.
fn frame(t: &mut Top, source: Source<'_>) -> Vec<((u32, u32), u32, Got)> {
    let mut out = Vec::new();
    t.run_frame(source, &mut |p| {
        assert_eq!(p.events.len() as u64, p.outcome.events);
        assert!(p
            .events
            .iter()
            .all(|e| (e.x, e.y) == (p.x as u16, p.y as u16)));
        assert!(p.events.iter().enumerate().all(|(i, e)| e.seq == i as u32));
        out.push((
            (p.x, p.y),
            p.processor,
            (p.outcome.rgb, p.outcome.cycles, p.outcome.events),
        ));
    })
    .unwrap_or_else(|e| panic!("{e}"));
    out
}

/// golden::micro's colour bits, cycles and events for a pixel.
fn golden(g: &Processor, x: u32, y: u32) -> Got {
    let mut events = 0;
    let r = g.render_pixel(x, y, |_, _| events += 1);
    (r.rgb.map(f32::to_bits), r.cycles, events)
}

/// Asserts every pixel of `window` came back exactly once with golden's
/// colour, cycles and event count; returns them by pixel.
fn assert_golden(
    scene: &Scene,
    window: Window,
    got: &[((u32, u32), u32, Got)],
) -> BTreeMap<(u32, u32), Got> {
    let g = Processor::new(scene);
    let mut by_pixel = BTreeMap::new();
    for &(at, _, pixel) in got {
        assert!(
            by_pixel.insert(at, pixel).is_none(),
            "{at:?} came back twice"
        );
    }
    assert_eq!(by_pixel.len() as u64, window.pixels(), "pixels back");
    for (x, y) in window.iter() {
        assert_eq!(by_pixel[&(x, y)], golden(&g, x, y), "pixel ({x}, {y})");
    }
    by_pixel
}

#[test]
fn one_and_four_processors_give_the_same_frame_and_cycles_as_golden() {
    let scene = builtin("reference", 40, 30);
    let window = Window::full(&scene);
    let coords: Vec<_> = window.iter().collect();
    let mut frames = Vec::new();
    for procs in [1, 4] {
        let mut t = top(procs, &scene);
        let got = frame(&mut t, Source::Stream(&coords));
        let used: std::collections::BTreeSet<u32> = got.iter().map(|g| g.1).collect();
        assert_eq!(used.len() as u32, procs, "processors used: {used:?}");
        if procs > 1 {
            let order: Vec<_> = got.iter().map(|g| g.0).collect();
            assert_ne!(order, coords, "four processors finish out of order");
        }
        frames.push(assert_golden(&scene, window, &got));
    }
    assert_eq!(frames[0], frames[1]);
}

/// The co-simulation report through the top equals the bare pixel
/// processor's for N = 1 and 4 and for one and two threads; the top's own
/// costs do not depend on the threads.
#[test]
fn the_report_through_the_top_is_the_bare_processors_for_any_n_and_threads() {
    let scene = builtin("mirror", 40, 30);
    let window = Window::new(3, 2, 30, 11);
    let options = CosimOptions::default();
    let bare = common::run_compact(&scene, window, &options).expect("runs");
    assert!(bare.passed(), "{bare}");
    let mut tops = BTreeMap::new();
    for procs in [1, 4] {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a pool");
            let top = Design::for_scene(ProcessorKind::Compact, &scene).procs(Some(procs));
            let r = pool
                .install(|| cosim::run(&top, &scene, window, &options, &|_| {}))
                .unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(r.compare, bare.compare, "N = {procs}, {threads} threads");
            let t = r.top.expect("the top's report");
            assert_eq!(t.stats.pixels, window.pixels());
            assert_eq!(t.stats.pixel_cycles, bare.compare.counts.a_cycles);
            assert_eq!(*tops.entry(procs).or_insert(t), t, "{threads} threads");
        }
    }
    // Four processors take fewer frame cycles, each busy most of the time.
    let (one, four) = (tops[&1], tops[&4]);
    assert!(
        four.stats.frame_cycles * 3 < one.stats.frame_cycles,
        "{one:?} {four:?}"
    );
    assert!(one.idle_share() < 0.05, "{one:?}");
}

/// out_ready low in 99% of the cycles: every pixel of a stream with
/// repeats comes back as often as it went in, with golden's colour and
/// cycles, and the frame took longer than without backpressure.
#[test]
fn backpressure_on_the_result_stream_loses_and_duplicates_nothing() {
    let scene = builtin("reference", 40, 30);
    let g = Processor::new(&scene);
    let mut coords: Vec<(u32, u32)> = Window::new(4, 10, 30, 6).iter().collect();
    coords.extend_from_slice(&[(7, 12), (7, 12), (0, 0), (39, 29), (7, 12)]);
    let mut t = top(4, &scene);
    let mut cycles = Vec::new();
    for stall in [0, 99] {
        t.set_backpressure(11, Stall::percent(stall));
        let mut back: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        let stats = t
            .run_frame(Source::Stream(&coords), &mut |p| {
                *back.entry((p.x, p.y)).or_default() += 1;
                let want = golden(&g, p.x, p.y);
                assert_eq!(
                    (p.outcome.rgb, p.outcome.cycles, p.outcome.events),
                    want,
                    "pixel ({}, {}) with {stall}% stalls",
                    p.x,
                    p.y
                );
            })
            .unwrap_or_else(|e| panic!("{e}"));
        let mut sent: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        for &c in &coords {
            *sent.entry(c).or_default() += 1;
        }
        assert_eq!(back, sent, "with {stall}% stalls");
        cycles.push(stats.frame_cycles);
    }
    assert!(
        cycles[1] > cycles[0],
        "backpressure slowed nothing: {cycles:?}"
    );
}

/// Out-of-range coordinates and windows, scenes for another model and
/// frames without a scene are refused before a cycle runs: the top is not
/// left mid-frame, and the next good frame runs.
#[test]
fn bad_coordinates_and_scenes_are_refused_before_simulation() {
    let scene = builtin("reference", 40, 30);
    let mut t = Top::open(&Design::compact(scene.render.recip, scene.render.sqrt).procs(Some(4)))
        .expect("built");
    assert_eq!(
        t.run_frame(Source::Stream(&[(1, 1)]), &mut |_| {})
            .unwrap_err(),
        PpError::NoScene
    );
    t.load_scene(&scene).expect("loads");
    let outside = |x, y| PpError::OutsideImage {
        x,
        y,
        width: 40,
        height: 30,
    };
    let refused = |t: &mut Top, source| t.run_frame(source, &mut |_| panic!("a pixel ran"));
    assert_eq!(
        refused(&mut t, Source::Stream(&[(0, 0), (40, 3)])).unwrap_err(),
        outside(40, 3)
    );
    assert_eq!(
        refused(&mut t, Source::Stream(&[(2, 30)])).unwrap_err(),
        outside(2, 30)
    );
    assert_eq!(
        refused(&mut t, Source::Raster(Window::new(35, 20, 6, 2))).unwrap_err(),
        outside(40, 21)
    );
    let fast = rtcosim::scenes::with_methods(
        &scene,
        golden::fp::Method::Fast,
        golden::fp::Method::Exact,
        "fast recip",
    )
    .expect("valid");
    let err = t.change_scene(&fast).unwrap_err();
    assert!(matches!(err, PpError::MethodMismatch { .. }), "{err}");
    let err = t.load_scene(&fast).unwrap_err();
    assert!(matches!(err, PpError::MethodMismatch { .. }), "{err}");
    // Nothing ran and nothing was forgotten: the loaded scene renders.
    let got = frame(&mut t, Source::Stream(&[(5, 5), (6, 5)]));
    assert_golden(&scene, Window::new(5, 5, 2, 1), &got);

    // A variant that was not built, and a window outside the image, in the
    // co-simulation.
    let err = Top::open(&Design::compact(scene.render.recip, scene.render.sqrt).procs(Some(3)))
        .err()
        .expect("N = 3 is not built");
    assert!(err.to_string().contains("top of 3"), "{err}");
    let top = Design::for_scene(ProcessorKind::Compact, &scene).procs(Some(4));
    let r = cosim::run(
        &top,
        &scene,
        Window::new(30, 0, 11, 1),
        &CosimOptions::default(),
        &|_| panic!("a tile ran"),
    );
    assert!(matches!(r, Err(CosimError::Window(_))), "{r:?}");
}

/// A processor that spends longer than the timeout on its pixel stops the
/// run, named with its pixel and state. Four pixels go to four idle
/// processors in order (the lowest free processor first, docs/rtl.md);
/// only the third takes longer than the timeout, so processor 2 hangs.
#[test]
fn a_hung_processor_trips_the_watchdog_with_its_name() {
    let scene = builtin("reference", 40, 30);
    let g = Processor::new(&scene);
    let cycles = |(x, y): (u32, u32)| g.render_pixel(x, y, |_, _| {}).cycles;
    let pixels: Vec<(u32, u32)> = Window::full(&scene).iter().collect();
    let fastest = pixels.iter().map(|&p| cycles(p)).min().expect("pixels");
    let slow = *pixels
        .iter()
        .find(|&&p| cycles(p) > fastest + 40)
        .expect("a slower pixel");
    let fast: Vec<_> = pixels
        .iter()
        .filter(|&&p| cycles(p) == fastest)
        .take(3)
        .copied()
        .collect();
    let stream = [fast[0], fast[1], slow, fast[2]];
    // Room for a fast pixel and its start cycle, not for the slow one.
    let timeout = fastest + 20;
    let mut t = top(4, &scene);
    t.set_timeout_cycles(timeout);
    let err = t
        .run_frame(Source::Stream(&stream), &mut |_| {})
        .expect_err("the slow pixel hangs");
    let PpError::Hung {
        x,
        y,
        processor,
        kind,
        cycles: ran,
        last_state,
        ..
    } = err.clone()
    else {
        panic!("not a hang: {err}");
    };
    assert_eq!((x, y), slow);
    assert_eq!(
        processor,
        Some(ProcessorId {
            index: 2,
            procs: 4,
            layout: SlotLayout::Compact
        })
    );
    assert_eq!(kind, HangKind::Timeout);
    assert!(ran > timeout, "{err}");
    assert!(last_state.is_some(), "{err}");
    let text = err.to_string();
    assert!(
        text.contains(&format!(
            "at pixel ({}, {}) on processor 2 of 4 (top.g_pp[2].g_compact.u_pp)",
            slow.0, slow.1
        )) && text.contains("last state seen: "),
        "{text}"
    );
    assert_eq!(
        t.run_frame(Source::Stream(&stream), &mut |_| {}),
        Err(PpError::Poisoned)
    );
    t.set_timeout_cycles(rtcosim::design::DEFAULT_TIMEOUT_CYCLES);
    t.load_scene(&scene).expect("a reset and a reload recover");
    frame(&mut t, Source::Stream(&stream));
}

/// The fault self-test through the top: the same fault finds the same
/// first divergence as on the bare pixel processor, in every pixel.
#[test]
fn the_fault_self_test_works_through_the_top() {
    let scene = builtin("reference", 40, 30);
    let window = Window::new(0, 0, 40, 8);
    let options = CosimOptions {
        fault: Some(Fault {
            state: state::PRI_HALF,
            xor: 0x400,
        }),
        ..CosimOptions::default()
    };
    let bare = common::run_compact(&scene, window, &options).expect("runs");
    let top = Design::for_scene(ProcessorKind::Compact, &scene).procs(Some(4));
    let through = cosim::run(&top, &scene, window, &options, &|_| {}).expect("runs");
    assert!(!through.passed());
    assert_eq!(through.compare.counts.divergent_pixels, window.pixels());
    assert_eq!(through.compare, bare.compare);
}

/// Two frames through one top with the scene changed between them through
/// the scene port (no reset), each from the raster generator: both agree
/// with golden for their scene, and they differ; a third frame from the
/// stream after changing back gives the first frame again.
#[test]
fn two_frames_with_a_scene_change_between_them() {
    let first = builtin("reference", 40, 30);
    let second = builtin("mirror", 40, 30);
    let window = Window::new(2, 3, 33, 9);
    let mut t = top(4, &first);
    let a = frame(&mut t, Source::Raster(window));
    let a = assert_golden(&first, window, &a);
    t.change_scene(&second).expect("between frames");
    let b = frame(&mut t, Source::Raster(window));
    let b = assert_golden(&second, window, &b);
    assert_ne!(a, b, "the scene change changed nothing");
    t.change_scene(&first).expect("between frames");
    let coords: Vec<_> = window.iter().collect();
    let c = frame(&mut t, Source::Stream(&coords));
    assert_eq!(assert_golden(&first, window, &c), a);
}
