//! Co-simulation of the verilated pixel processor (rtl/pp/pixel_processor.v)
//! against the golden micro-op model (golden::micro): every trace event, the
//! cycle count and the colour of every pixel, bit for bit.
//!
//! The frame tests run every builtin scene, reduced so the whole file stays
//! within about a minute, with whole frames (so every silhouette, shadow edge
//! and horizon of the scene is in): reference, mirror, parallel_plane and
//! overexposed (the exposure) at 80x60, grazing at its own 96x72, light_touch at 64x48 and box_room (about
//! 1460 cycles a pixel) at 40x30: about 6.3 million golden cycles per method
//! pair. `cargo test --release -- --ignored` adds the full 800x600 reference
//! frame.
//!
//! The tests marked "any design" hold for any pixel processor with the right
//! ports and protocol (they also pass on a placeholder); the others need the
//! real design. Lint lives in rtl_lint.rs.

mod common;

use golden::fp::{Method, UlpDistance};
use golden::micro::isa::{self, state};
use golden::scene::Scene;
use golden::trace::TraceEvent;
use golden::window::Window;
use rtcosim::check::compare::DivergenceKind;
use rtcosim::check::cosim::{self, CosimError, CosimOptions, CosimReport};
use rtcosim::design::pixel_proc::PixelProcessor;
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::Design;
use rtcosim::design::{Fault, HangKind, PpError};

/// The method pairs every scene is co-simulated with.
const METHODS: [(Method, Method); 2] =
    [(Method::Exact, Method::Exact), (Method::Fast, Method::Fast)];

/// `scene` with other recip and sqrt methods (validated again).
fn with_methods(scene: &Scene, recip: Method, sqrt: Method) -> Scene {
    rtcosim::scenes::with_methods(scene, recip, sqrt, "test scene")
        .expect("only the methods changed")
}

fn builtin(name: &str, width: u32, height: u32) -> Scene {
    Scene::builtin(name)
        .unwrap_or_else(|| panic!("builtin scene {name}"))
        .resized(width, height, name)
        .expect("a smaller image of a valid scene is valid")
}

fn cosim_all(scene: &Scene, window: Window) -> CosimReport {
    common::run_compact(scene, window, &CosimOptions::default())
        .unwrap_or_else(|e| panic!("co-simulation failed: {e}"))
}

/// The RTL is side A of the comparison, golden side B.
fn assert_agrees(report: &CosimReport, pixels: u64) {
    let c = &report.compare.counts;
    assert_eq!(c.pixels, pixels, "pixels run\n{report}");
    assert!(c.events_compared > 0, "no events compared\n{report}");
    assert!(
        c.divergent_pixels == 0 && report.compare.first_divergence.is_none(),
        "{report}"
    );
    assert_eq!(c.a_events, c.b_events, "{report}");
    assert_eq!(c.events_compared, c.b_events, "{report}");
    assert_eq!(c.a_cycles, c.b_cycles, "{report}");
    assert!(report.passed(), "{report}");
}

/// Whole (reduced) frames of a builtin scene agree with both method pairs.
fn frame_agrees(name: &str, width: u32, height: u32) {
    let base = builtin(name, width, height);
    for (recip, sqrt) in METHODS {
        let scene = with_methods(&base, recip, sqrt);
        let report = cosim_all(&scene, Window::full(&scene));
        assert_agrees(&report, u64::from(width) * u64::from(height));
    }
}

// ---------------------------------------------------------------------------
// The real design against golden
// ---------------------------------------------------------------------------

#[test]
fn reference_frame_agrees() {
    frame_agrees("reference", 80, 60);
}

#[test]
fn mirror_frame_agrees() {
    frame_agrees("mirror", 80, 60);
}

#[test]
fn grazing_frame_agrees() {
    frame_agrees("grazing", 96, 72);
}

#[test]
fn light_touch_frame_agrees() {
    frame_agrees("light_touch", 64, 48);
}

#[test]
fn parallel_plane_frame_agrees() {
    frame_agrees("parallel_plane", 80, 60);
}

#[test]
fn box_room_frame_agrees() {
    frame_agrees("box_room", 40, 30);
}

/// Refraction through the RTL: the glass scenes agree in every event,
/// colour and cycle with every method pair, and their pixels refract.
#[test]
fn glass_frames_agree() {
    for name in ["glass_room", "bubble", "touching"] {
        frame_agrees(name, 80, 60);
        let scene = builtin(name, 80, 60);
        let report = common::run_compact(&scene, Window::full(&scene), &CosimOptions::default())
            .expect("runs");
        assert!(report.compare.states.contains(state::RF_NSUB), "{name}");
        assert!(report.compare.states.contains(state::RF_CHILD_W), "{name}");
        // The bubble's rim reflects totally.
        assert_eq!(
            report.compare.states.contains(state::RF_TIR),
            name == "bubble",
            "{name}"
        );
    }
}

/// The exposure (thesis 3.7) through the RTL: the overexposed scene (colours
/// up to about 4.4 before it) agrees with golden in every event, colour
/// and cycle with both method pairs (frame_agrees), including the three
/// EXPO states of every pixel and the three fp_exp units of the ALU; and
/// the RTL's frame, which golden's equals bit for bit, lies in [0, 1).
#[test]
fn overexposed_frame_agrees() {
    frame_agrees("overexposed", 80, 60);
    let scene = builtin("overexposed", 80, 60);
    assert!(scene.render.exposure.is_some());
    let options = CosimOptions {
        keep_frames: true,
        ..CosimOptions::default()
    };
    let report = common::run_compact(&scene, Window::full(&scene), &options).expect("runs");
    let frames = report.frames.expect("kept");
    assert_eq!(frames.rtl.saturated_pixels(), 0);
    assert!(
        frames.rtl.max_channel() < 1.0,
        "{}",
        frames.rtl.max_channel()
    );
    assert!(report.compare.states.contains(state::EXPO_EXP));
}

/// The weight cutoff, co-simulated: the mirror scene with a cutoff that
/// refuses its two deepest levels' rays (tests/common: every weight is a
/// power of 0.8, and 0.8^3 < 0.6 < 0.8^2) agrees with golden in every event,
/// colour and cycle, with both method pairs; and it changes the frame
/// against the same scene without the cutoff, measured by golden alone:
/// fewer cycles, some colours.
#[test]
fn mirror_with_a_weight_cutoff_agrees() {
    let cut = common::mirror_with_cutoff();
    let off = builtin("mirror", 80, 60);
    assert_eq!(
        (
            cut.camera.width,
            cut.camera.height,
            off.render.weight_cutoff
        ),
        (80, 60, 0.0)
    );
    for (recip, sqrt) in METHODS {
        let scene = with_methods(&cut, recip, sqrt);
        assert_agrees(&cosim_all(&scene, Window::full(&scene)), 80 * 60);
    }
    let (f_cut, s_cut) = golden::micro::render(&cut, &|_| {});
    let (f_off, s_off) = golden::micro::render(&off, &|_| {});
    assert!(
        s_cut.cycles < s_off.cycles,
        "cycles with the cutoff {} vs without {}",
        s_cut.cycles,
        s_off.cycles
    );
    let diff = f_cut.compare(&f_off).expect("one size");
    let changed = diff.share_over(0.0);
    assert!(changed > 0.0, "the cutoff changed no colour");
    println!(
        "mirror 80x60, cutoff {}: {:.1} against {:.1} cycles/pixel; {:.2}% of channels change, largest by {:.3}/255",
        common::MIRROR_CUTOFF,
        s_cut.mean_cycles(),
        s_off.mean_cycles(),
        100.0 * changed,
        diff.max_abs_diff
    );
}

/// The cutoff where reflection values differ: the mirror scene with a dull
/// back wall (kr 0.25) and a cutoff of 0.5 refuses every ray the wall would
/// reflect (weight at most 0.25) and the fourth bounce between the spheres
/// and the floor (0.8^4 < 0.5), but keeps their first three: per object,
/// not a depth limit. The RTL agrees, and the cutoff changed the frame.
#[test]
fn a_per_object_weight_cutoff_agrees() {
    let base = builtin("mirror", 80, 60);
    // with_render validates the whole scene again, the changed wall too.
    let mut dull = base.clone();
    dull.planes[1].material.reflection = 0.25;
    let render = golden::scene::RenderSettings {
        weight_cutoff: 0.5,
        ..base.render
    };
    let scene = dull.with_render(render, "dull wall").expect("valid");
    assert_agrees(&cosim_all(&scene, Window::full(&scene)), 80 * 60);
    let (with, _) = golden::micro::render(&scene, &|_| {});
    let (without, _) = golden::micro::render(&dull, &|_| {});
    assert_ne!(with.pixels, without.pixels, "the cutoff refused nothing");
}

#[test]
fn every_builtin_scene_has_a_frame_test() {
    let tested = [
        "reference",
        "mirror",
        "grazing",
        "light_touch",
        "parallel_plane",
        "box_room",
        "overexposed",
        "glass_room",
        "bubble",
        "touching",
    ];
    for name in Scene::builtin_names() {
        assert!(tested.contains(name), "no frame test for builtin {name}");
    }
}

/// Mixed method pairs: catches RECIP_METHOD and SQRT_METHOD swapped on the
/// way down, which (exact, exact) and (fast, fast) cannot see.
#[test]
fn mixed_method_pairs_agree() {
    let base = builtin("reference", 40, 30);
    for (recip, sqrt) in [(Method::Exact, Method::Fast), (Method::Fast, Method::Exact)] {
        let scene = with_methods(&base, recip, sqrt);
        assert_agrees(&cosim_all(&scene, Window::full(&scene)), 1200);
    }
}

/// An injected fault is caught exactly where it is made: the first pixel of
/// the window, the golden event index of the state's first write, that
/// state on both sides, the golden source line of that write, and lane x
/// off by the flipped bit.
#[test]
fn an_injected_fault_is_reported_at_its_state_and_golden_line() {
    let scene = builtin("reference", 40, 30);
    let window = Window::new(17, 11, 6, 4);
    // A single-cycle and a multi-cycle state that every pixel visits.
    assert_faults_caught(&scene, window, &[state::PRI_HALF, state::NORM_ROOTS]);
}

/// The same for the exposure's three states (every pixel of a scene with
/// an exposure visits them): a wrong write in EXPO_MUL, EXPO_EXP (the
/// fp_exp units' result) or EXPO_SUB is caught there.
#[test]
fn a_fault_in_the_exposure_is_reported_at_its_state() {
    let scene = builtin("overexposed", 40, 30);
    let states = [state::EXPO_MUL, state::EXPO_EXP, state::EXPO_SUB];
    assert_faults_caught(&scene, Window::new(20, 8, 5, 4), &states);
}

/// For each state: a fault there (bit 10 of lane x flipped) is caught at
/// the window's first pixel, at the golden event index of the state's
/// first write, in that state on both sides, with golden's source line,
/// and in every pixel.
fn assert_faults_caught(scene: &Scene, window: Window, states: &[u16]) {
    let scene = scene.clone();
    for &fault_state in states {
        let xor = 1 << 10;
        let mut first = None;
        golden::micro::render_pixel(&scene, window.x, window.y, |e, at| {
            if e.state == fault_state && first.is_none() {
                first = Some((e.seq, at));
            }
        });
        let (seq, line) = first.expect("every pixel visits the state");
        let options = CosimOptions {
            fault: Some(Fault {
                state: fault_state,
                xor,
            }),
            ..CosimOptions::default()
        };
        let report = common::run_compact(&scene, window, &options).expect("runs");
        let name = isa::state_name(fault_state).expect("named");
        let d = report
            .compare
            .first_divergence
            .unwrap_or_else(|| panic!("a fault in {name} went unnoticed\n{report}"));
        assert_eq!((d.x, d.y), (window.x, window.y), "{report}");
        assert_eq!(d.seq(), Some(seq), "{report}");
        let DivergenceKind::Event { a: rtl, b: golden } = d.kind else {
            panic!("not an event divergence\n{report}");
        };
        assert_eq!((rtl.state, golden.state), (fault_state, fault_state));
        assert_eq!((rtl.dst, rtl.lanes), (golden.dst, golden.lanes));
        assert_eq!(rtl.values[0], golden.values[0] ^ xor, "{report}");
        assert_eq!(d.b_at, Some(line));
        assert!(
            d.max_distance().is_some_and(|u| u > UlpDistance::Ulps(0)),
            "{report}"
        );
        // Every pixel writes in that state.
        assert_eq!(
            report.compare.counts.divergent_pixels,
            window.pixels(),
            "{report}"
        );
        let text = report.to_string();
        let verilog = rtcosim::design::rtl_source::state_line(
            rtcosim::design::processor::ProcessorKind::Compact,
            fault_state,
        )
        .expect("mapped");
        assert!(
            text.contains(&format!("RTL    state {name} ({fault_state}) [{verilog}]")),
            "{text}"
        );
        assert!(
            text.contains(&format!("{}:{}", line.file(), line.line())),
            "{text}"
        );
    }
}

#[test]
#[ignore = "the full 800x600 reference frame, both method pairs: minutes"]
fn full_reference_frame_agrees() {
    for (recip, sqrt) in METHODS {
        let scene = with_methods(&Scene::reference(), recip, sqrt);
        let start = std::time::Instant::now();
        let report = cosim_all(&scene, Window::full(&scene));
        println!("{report}\n({:.1} s)", start.elapsed().as_secs_f64());
        assert_agrees(&report, 800 * 600);
    }
}

// ---------------------------------------------------------------------------
// Any design with the right ports and protocol
// ---------------------------------------------------------------------------

fn loaded(scene: &Scene) -> PixelProcessor {
    let mut pp = PixelProcessor::open(&Design::compact(scene.render.recip, scene.render.sqrt))
        .expect("model builds");
    pp.load_scene(scene).expect("scene loads");
    pp
}

/// Any design: events carry the pixel and their index, their count and the
/// cycles agree with the result, and tracing changes nothing.
#[test]
fn trace_events_are_numbered_and_counted() {
    let scene = builtin("reference", 40, 30);
    let mut pp = loaded(&scene);
    let mut events = Vec::new();
    let traced = pp.run_pixel(21, 13, Some(&mut events)).expect("runs");
    assert_eq!(traced.events, events.len() as u64);
    for (i, e) in events.iter().enumerate() {
        assert_eq!((e.x, e.y, e.seq), (21, 13, i as u32), "{e:?}");
        assert!(e.lanes != 0 && e.lanes <= 0b111, "{e:?}");
    }
    // PIX_DONE writes nothing; every write takes a cycle.
    assert!(traced.cycles > traced.events, "{traced:?}");
    assert_eq!(pp.run_pixel(21, 13, None).expect("runs"), traced);
}

/// Any design: a pixel's result does not depend on the pixels before it,
/// nor on a fault that was switched off again.
#[test]
fn pixels_do_not_depend_on_history() {
    let scene = builtin("reference", 40, 30);
    let mut pp = loaded(&scene);
    let run = |pp: &mut PixelProcessor, x, y| {
        let mut events: Vec<TraceEvent> = Vec::new();
        let r = pp.run_pixel(x, y, Some(&mut events)).expect("runs");
        (r, events)
    };
    let first = run(&mut pp, 20, 20);
    run(&mut pp, 3, 4);
    run(&mut pp, 39, 29);
    assert_eq!(run(&mut pp, 20, 20), first);
    pp.set_fault(Some(Fault {
        state: state::PRI_HALF,
        xor: 1 << 10,
    }));
    run(&mut pp, 20, 20);
    pp.set_fault(None);
    assert_eq!(run(&mut pp, 20, 20), first);
    assert_eq!(
        loaded(&scene).run_pixel(20, 20, None).expect("runs"),
        first.0
    );
}

/// Any design: the report is the same whatever the number of threads (with
/// a fault, so there are divergences to order).
#[test]
fn the_report_does_not_depend_on_the_thread_count() {
    let scene = builtin("reference", 40, 30);
    let window = Window::new(4, 3, 20, 12);
    let options = CosimOptions {
        fault: Some(Fault {
            state: state::NORM_SCALE,
            xor: 1 << 3,
        }),
        ..CosimOptions::default()
    };
    let with_threads = |n: usize| -> CosimReport {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("pool");
        let done = std::sync::atomic::AtomicU64::new(0);
        let report = pool
            .install(|| {
                cosim::run(
                    &Design::for_scene(ProcessorKind::Compact, &scene),
                    &scene,
                    window,
                    &options,
                    &|n| {
                        done.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
                    },
                )
            })
            .expect("runs");
        assert_eq!(done.into_inner(), window.pixels(), "progress adds up");
        report
    };
    let one = with_threads(1);
    assert_eq!(one.compare.counts.pixels, window.pixels());
    assert!(one.compare.first_divergence.is_some(), "{one}");
    assert_eq!(with_threads(3), one);
}

/// Any design: a pixel outside the image is an error, never a panic, and
/// leaves the model usable; so is a window outside the image.
#[test]
fn a_pixel_outside_the_image_is_an_error() {
    let scene = builtin("reference", 40, 30);
    let mut pp =
        PixelProcessor::open(&Design::compact(Method::Exact, Method::Exact)).expect("model builds");
    assert_eq!(pp.run_pixel(0, 0, None), Err(PpError::NoScene));
    pp.load_scene(&scene).expect("loads");
    for (x, y) in [(40, 0), (0, 30), (u32::MAX, u32::MAX)] {
        let err = pp.run_pixel(x, y, None).expect_err("outside");
        assert_eq!(
            err,
            PpError::OutsideImage {
                x,
                y,
                width: 40,
                height: 30
            }
        );
        assert!(
            err.to_string()
                .contains("outside the loaded scene's 40x30 image"),
            "{err}"
        );
    }
    pp.run_pixel(39, 29, None)
        .expect("the model is still usable");
    for window in [
        Window::new(30, 0, 11, 1),
        Window::new(0, 29, 1, 2),
        Window::new(0, 0, 0, 5),
    ] {
        let err =
            common::run_compact(&scene, window, &CosimOptions::default()).expect_err("outside");
        assert!(matches!(err, CosimError::Window(_)), "{err}");
    }
}

/// Any design: a scene for other float methods than the model's is refused,
/// naming both; every method pair is verilated.
#[test]
fn a_scene_with_other_methods_is_refused() {
    let exact = builtin("reference", 40, 30);
    assert_eq!(
        (exact.render.recip, exact.render.sqrt),
        (Method::Exact, Method::Exact)
    );
    for recip in Method::ALL {
        for sqrt in Method::ALL {
            let mut pp =
                PixelProcessor::open(&Design::compact(recip, sqrt)).expect("every pair is built");
            assert_eq!(pp.methods(), (recip, sqrt));
            let other = with_methods(&exact, recip, sqrt);
            pp.load_scene(&other).expect("its own methods load");
            for (r, s) in [(Method::Exact, Method::Exact), (Method::Fast, Method::Fast)] {
                if (r, s) == (recip, sqrt) {
                    continue;
                }
                let err = pp
                    .load_scene(&with_methods(&exact, r, s))
                    .expect_err("refused");
                assert!(matches!(err, PpError::MethodMismatch { .. }), "{err}");
                assert_eq!(
                    err.to_string(),
                    format!(
                        "the scene uses recip {r} and sqrt {s}, but this pixel processor was \
                         verilated with recip {recip} and sqrt {sqrt}"
                    )
                );
            }
        }
    }
}

/// Any design: a pixel that takes longer than the timeout is a "hung RTL"
/// error naming the pixel, the cycles and the last state; the model needs a
/// reset afterwards. (No design input can make a correct controller hang,
/// so the timeout is set below any pixel's cycle count: at least two
/// instructions and PIX_DONE.)
#[test]
fn a_pixel_over_the_timeout_is_a_hung_rtl_error() {
    let scene = builtin("reference", 40, 30);
    let mut pp = loaded(&scene);
    pp.set_timeout_cycles(2);
    let err = pp
        .run_pixel(7, 5, None)
        .expect_err("cannot finish in 2 cycles");
    let PpError::Hung {
        x, y, kind, cycles, ..
    } = err.clone()
    else {
        panic!("not a hang: {err}");
    };
    assert_eq!((x, y, kind, cycles), (7, 5, HangKind::Timeout, 2));
    let text = err.to_string();
    assert!(
        text.starts_with("hung RTL at pixel (7, 5): no done after 2 cycles; last state seen: "),
        "{text}"
    );
    assert_eq!(pp.run_pixel(7, 5, None), Err(PpError::Poisoned));
    pp.set_timeout_cycles(rtcosim::design::DEFAULT_TIMEOUT_CYCLES);
    pp.load_scene(&scene).expect("a reset and a reload recover");
    pp.run_pixel(7, 5, None).expect("runs");

    let options = CosimOptions {
        timeout_cycles: Some(2),
        ..CosimOptions::default()
    };
    let window = Window::new(3, 2, 4, 4);
    match common::run_compact(&scene, window, &options) {
        Err(CosimError::Rtl(PpError::Hung { x, y, .. })) => {
            assert_eq!(x, window.x, "the first pixel of its row");
            assert!((window.y..window.y + window.height).contains(&y));
        }
        other => panic!("expected a hung RTL error, got {other:?}"),
    }
}

/// Highlights only where the light reaches the surface: a sphere lit from
/// behind shows the camera only its dark side (n·l <= 0), where an ungated
/// Phong term would still put a highlight along the rim (r·l > 0 there: the
/// test checks that such pixels exist). The specular weight must change no
/// pixel in the f64 reference, in the micro-op model, or in the RTL, which
/// agrees with the micro-op model bit for bit.
#[test]
fn the_dark_side_of_a_lit_sphere_gets_no_highlight_in_any_model() {
    let scene_with = |ks: f32| {
        let text = format!(
            r#"
[camera]
eye = [0.0, 0.0, 0.0]
distance = 40.0
width = 48
height = 48
[light]
position = [0.0, 0.0, 40.0]
color = [1.0, 1.0, 1.0]
[[sphere]]
center = [0.0, 0.0, 12.0]
radius = 4.0
color = [1.0, 1.0, 1.0]
diffuse = 0.5
specular = {ks}
reflection = 0.0
[render]
max_depth = 1
"#
        );
        Scene::from_toml(&text, "dark side").expect("a valid scene")
    };
    let (shiny, matte) = (scene_with(0.9), scene_with(0.0));
    let light = glam::DVec3::new(0.0, 0.0, 40.0);
    let centre = glam::DVec3::new(0.0, 0.0, 12.0);
    let mut rim = 0;
    for y in 0..48 {
        for x in 0..48 {
            // Where the primary ray hits the sphere: is it a rim pixel that
            // an ungated highlight would light?
            let d = golden::reference::primary_direction(&shiny, x, y);
            if let Some((_, t)) = golden::reference::nearest_hit(&shiny, glam::DVec3::ZERO, d, None)
            {
                let p = t * d;
                let n = (p - centre).normalize();
                let l = (light - p).normalize();
                let r = d - 2.0 * d.dot(n) * n;
                assert!(n.dot(l) <= 0.0, "({x}, {y}) is on the lit side");
                rim += usize::from(r.dot(l) > 0.0);
            }
            assert_eq!(
                golden::reference::render_pixel(&shiny, x, y),
                golden::reference::render_pixel(&matte, x, y),
                "reference ({x}, {y})"
            );
            let micro = |s: &Scene| golden::micro::render_pixel(s, x, y, |_, _| {}).rgb;
            assert_eq!(micro(&shiny), micro(&matte), "micro ({x}, {y})");
        }
    }
    assert!(
        rim > 10,
        "only {rim} pixels where an ungated highlight would show"
    );
    // The RTL computes the same gated colours, bit for bit.
    assert_agrees(&cosim_all(&shiny, Window::full(&shiny)), 48 * 48);
}

/// The micro-op model's fault (Processor::with_fault) is the RTL's fault
/// port, bit for bit: with the same fault on both sides, every event,
/// colour and cycle count still agrees, though the fault changes them
/// (against a clean model it diverges on every pixel), including faults
/// that send a branch another way.
#[test]
fn the_golden_fault_is_the_rtl_fault_bit_for_bit() {
    use rtcosim::check::compare::{compare_pixel, Tolerance};
    let scene = builtin("reference", 40, 30);
    let window = Window::new(8, 6, 10, 8);
    let mut rtl = PixelProcessor::open(&Design::compact(scene.render.recip, scene.render.sqrt))
        .expect("model");
    rtl.load_scene(&scene).expect("loads");
    for fault in [
        Fault {
            state: state::PRI_HALF,
            xor: 1 << 12,
        },
        // The sign of the light vector's length: another branch.
        Fault {
            state: state::NORM_ROOTS,
            xor: 0x8000_0000,
        },
    ] {
        rtl.set_fault(Some(fault));
        let faulty = golden::micro::Processor::new(&scene).with_fault(Some(fault));
        let clean = golden::micro::Processor::new(&scene);
        let (mut events, mut apart_from_clean) = (Vec::new(), 0);
        for (x, y) in window.iter() {
            events.clear();
            let a = rtl.run_pixel(x, y, Some(&mut events)).expect("runs");
            for (golden, expect_same) in [(&faulty, true), (&clean, false)] {
                let v = compare_pixel(x, y, Tolerance::default(), &events, a, |sink| {
                    let r = golden.render_pixel(x, y, |e, at| sink(e, Some(at)));
                    golden::pixel::PixelOutcome::from(&r)
                });
                if expect_same {
                    assert!(
                        !v.diverged(),
                        "{fault:?}: {}",
                        v.first
                            .expect("diverged")
                            .text(&rtcosim::check::compare::Labels::rtl_golden())
                    );
                } else {
                    apart_from_clean += u64::from(v.diverged());
                }
            }
        }
        assert_eq!(
            apart_from_clean,
            window.pixels(),
            "{fault:?} changes every pixel"
        );
    }
}

/// `keep_frames` gives both sides' colours of the window, as frames of its
/// size; both equal the micro-op model's own render of those pixels.
#[test]
fn kept_frames_are_the_windows_colours() {
    let scene = builtin("mirror", 40, 30);
    let window = Window::new(5, 7, 12, 9);
    let options = CosimOptions {
        keep_frames: true,
        ..CosimOptions::default()
    };
    let report = common::run_compact(&scene, window, &options).expect("runs");
    let frames = report.frames.expect("kept");
    let (full, _) = golden::micro::render(&scene, &|_| {});
    for frame in [&frames.rtl, &frames.golden] {
        assert_eq!((frame.width, frame.height), (12, 9));
        for (x, y) in window.iter() {
            assert_eq!(
                frame.pixel(x - window.x, y - window.y),
                full.pixel(x, y),
                "pixel ({x}, {y})"
            );
        }
    }
    assert!(
        cosim_all(&scene, window).frames.is_none(),
        "only when asked"
    );
}

/// The bare clock loop (harness/design/cpp/bare.h, the baseline of benches/
/// overhead.rs) runs the same RTL cycles as golden predicts for each pixel,
/// pixel by pixel as the driver does, and refuses pixels outside the image
/// and a model without a scene.
#[test]
fn the_bare_clock_loop_runs_the_predicted_cycles() {
    let scene = builtin("mirror", 24, 18);
    let golden = golden::micro::Processor::new(&scene);
    let mut rtl = PixelProcessor::open(&Design::compact(scene.render.recip, scene.render.sqrt))
        .expect("model");
    assert!(matches!(rtl.run_bare(&[(0, 0)]), Err(PpError::NoScene)));
    rtl.load_scene(&scene).expect("scene");
    let pixels: Vec<(u32, u32)> = Window::full(&scene).iter().collect();
    let want: u64 = pixels
        .iter()
        .map(|&(x, y)| golden.render_pixel(x, y, |_, _| {}).cycles)
        .sum();
    assert_eq!(rtl.run_bare(&pixels).expect("bare loop"), want);
    // Each pixel alone, and the driver after the bare loop, agree too.
    for &(x, y) in pixels.iter().step_by(37) {
        let one = rtl.run_bare(&[(x, y)]).expect("one pixel");
        assert_eq!(
            one,
            golden.render_pixel(x, y, |_, _| {}).cycles,
            "({x}, {y})"
        );
        assert_eq!(
            rtl.run_pixel(x, y, None).expect("driver").cycles,
            one,
            "({x}, {y})"
        );
    }
    assert!(matches!(
        rtl.run_bare(&[(1, 1), (24, 0)]),
        Err(PpError::OutsideImage { x: 24, y: 0, .. })
    ));
}
