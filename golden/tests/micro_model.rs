//! The micro-op model against the reference renderer, its speed-ups against
//! each other, its trace and its cycle contract.
//!
//! Sizes are reduced (80x60, 160x120) so that `cargo test` stays fast; the
//! full-size runs are `#[ignore]`d (`cargo test --release -p golden --test
//! micro_model -- --ignored --nocapture`).

mod common;

use common::{ONE_SPHERE, WALL_BEHIND};
use golden::frame::Frame;
use golden::micro::isa::{self, reg, RayField};
use golden::micro::{self, OpClass, PixelResult, Processor, FIXED_CYCLES};
use golden::reference;
use golden::scene::{Scene, Speedups};
use golden::trace::TraceEvent;
use std::collections::HashSet;
use std::error::Error;
use std::panic::Location;

type TestResult = Result<(), Box<dyn Error>>;

fn builtin(name: &str) -> Scene {
    Scene::builtin(name).unwrap_or_else(|| panic!("builtin scene {name}"))
}

fn sized(name: &str, w: u32, h: u32) -> Result<Scene, Box<dyn Error>> {
    Ok(builtin(name).resized(w, h, "test")?)
}

fn micro_frame(scene: &Scene) -> Frame {
    micro::render(scene, &|_| {}).0
}

/// Number of pixels whose f32 channels differ in any bit.
fn pixels_differing(a: &Frame, b: &Frame) -> usize {
    a.pixels
        .iter()
        .zip(&b.pixels)
        .filter(|(p, q)| (0..3).any(|c| p[c].to_bits() != q[c].to_bits()))
        .count()
}

fn mean_abs_diff_255(a: &Frame, b: &Frame) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .sum();
    255.0 * sum / (3 * a.pixels.len()) as f64
}

// ---------------------------------------------------------------------------
// Accuracy against the f64 reference
// ---------------------------------------------------------------------------

/// Largest channel difference (0..255) and share of channels > 0.5/255;
/// prints the thesis' finer thresholds too.
fn accuracy(scene: &Scene) -> Result<(f64, f64), Box<dyn Error>> {
    let (micro, reference) = (micro_frame(scene), reference::render(scene, &|_| {}));
    let d = micro.compare(&reference)?;
    // What the PNGs show: 8-bit channels that differ.
    let png_channels = micro
        .to_rgb8()
        .iter()
        .zip(reference.to_rgb8())
        .filter(|(a, b)| *a != b)
        .count();
    println!(
        "  channels > 1e-5/255: {:.2}%, > 1e-4/255: {:.2}%, > 1e-3/255: {:.3}%; \
         8-bit channels differing: {png_channels}",
        100.0 * d.share_over(1e-5),
        100.0 * d.share_over(1e-4),
        100.0 * d.share_over(1e-3)
    );
    Ok((d.max_abs_diff, d.share_over(0.5)))
}

fn with_methods(scene: &Scene, method: golden::fp::Method) -> Scene {
    let mut s = scene.clone();
    s.render.recip = method;
    s.render.sqrt = method;
    s
}

/// Prints and bounds the accuracy of both methods on `scene`.
fn check_accuracy(scene: &Scene, label: &str) -> TestResult {
    for method in golden::fp::Method::ALL {
        let (max, share) = accuracy(&with_methods(scene, method))?;
        println!(
            "{label}, {method} recip/sqrt: largest channel difference {max:.4}/255, \
             {:.5}% of channels > 0.5/255",
            100.0 * share
        );
        assert!(max < 0.25, "{label} {method}: largest difference {max}/255");
        assert_eq!(share, 0.0, "{label} {method}: channels over 0.5/255");
    }
    Ok(())
}

#[test]
fn micro_matches_the_reference_on_the_reference_and_mirror_scenes() -> TestResult {
    for name in ["reference", "mirror"] {
        check_accuracy(&sized(name, 160, 120)?, &format!("{name} 160x120"))?;
    }
    Ok(())
}

#[test]
#[ignore = "full size: run with --release"]
fn micro_matches_the_reference_at_full_size() -> TestResult {
    for name in ["reference", "mirror"] {
        check_accuracy(&builtin(name), &format!("{name} 800x600"))?;
    }
    Ok(())
}

fn toml_scene(text: &str, depth: u32, methods: &str) -> Scene {
    let text = format!("{text}\n[render]\nmax_depth = {depth}\n{methods}\n");
    Scene::from_toml(&text, "test.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The centre pixel of `golden/tests/reference_render.rs`'s hand-worked
/// scenes: every value is a small binary fraction, so f32 is exact too.
#[test]
fn hand_worked_pixels_come_out_exactly() {
    let sphere = toml_scene(ONE_SPHERE, 1, "");
    let r = micro::render_pixel(&sphere, 2, 2, |_, _| {});
    assert_eq!(r.rgb, [0.75, 0.25, 0.375]);
    let with_wall = format!("{ONE_SPHERE}{WALL_BEHIND}");
    for (depth, rgb) in [
        (1, [0.75, 0.25, 0.375]),
        (2, [0.875, 0.3125, 0.5]),
        (3, [1.0625, 0.375, 0.59375]),
    ] {
        let s = toml_scene(&with_wall, depth, "");
        assert_eq!(
            micro::render_pixel(&s, 2, 2, |_, _| {}).rgb,
            rgb,
            "depth {depth}"
        );
        assert_eq!(reference::render_pixel(&s, 2, 2), rgb.map(f64::from));
    }
    // Directions (-2, 2, 1)/3 miss everything: exactly black.
    assert_eq!(micro::render_pixel(&sphere, 0, 0, |_, _| {}).rgb, [0.0; 3]);
}

// ---------------------------------------------------------------------------
// The cycle contract
// ---------------------------------------------------------------------------

/// ONE_SPHERE's centre pixel at depth 1, no speed-ups, counted by hand from
/// the program (sqrt s cycles = latency + 1; ROOTS q = the later of the
/// sqrt and the recip + 1, which is s for every method pair):
///
/// ```text
/// primary: ITOF, HALF (no rotation), normalize (dot 3, ROOTS,
///          INV, SCALE); CUR_O, CUR_W at level 0 are EYE, ONE    7 + q
/// sphere:  V, dot b, BD, W, ISECT x4 (disc), SQRT, T             11 + s
/// shade:   OFFSET, POINT, NORMAL x2, LIGHT_VEC, normalize        10 + q
///          (no other object: the shadow test is free)
///          diffuse: dot, KD, CL, DIFFUSE                         6
///          reflected r: dot, K (MUL2X), REFL                     5
///          specular: dot, POW x5, KS, SPEC                       10
///          LOCAL, COLOUR                                         2
/// done                                                          1
/// ```
///
/// = 52 + 2 q + s: 52 + 16 + 8 = 76 exact, 52 + 14 + 7 = 73 fast.
#[test]
fn a_lit_sphere_pixel_takes_the_hand_counted_cycles() {
    for (methods, cycles, s) in [("", 76, 8), ("recip = \"fast\"\nsqrt = \"fast\"", 73, 7)] {
        let scene = toml_scene(ONE_SPHERE, 1, methods);
        let px = micro::render_pixel(&scene, 2, 2, |_, _| {});
        assert_eq!(px.cycles, cycles, "{methods:?}");
        assert_eq!(px.ops.count_of(OpClass::Sqrt), 1);
        assert_eq!(px.ops.count_of(OpClass::Recip), 0);
        assert_eq!(px.ops.count_of(OpClass::Roots), 2);
        assert_eq!(px.ops.cycles_of(OpClass::Sqrt), s);
        assert_eq!(px.ops.cycles_of(OpClass::Roots), 2 * s);
        assert_eq!(px.ops.count_of(OpClass::Isect), 4);
    }
}

/// cycles = FIXED_CYCLES + every instruction's cycles, recomputed from the counts.
fn check_cycle_rule(scene: &Scene, r: &PixelResult) {
    let ops = &r.ops;
    let (recip, sqrt) = (ops.count_of(OpClass::Recip), ops.count_of(OpClass::Sqrt));
    let roots = ops.count_of(OpClass::Roots);
    let single = ops.instructions() - recip - sqrt - roots;
    let (rl, sl) = (
        golden::fp::recip_latency(scene.render.recip),
        golden::fp::sqrt_latency(scene.render.sqrt),
    );
    let expected = FIXED_CYCLES
        + single
        + recip * u64::from(rl + 1)
        + sqrt * u64::from(sl + 1)
        + roots * u64::from(rl.max(sl) + 1);
    assert_eq!(r.cycles, expected);
    assert_eq!(r.cycles, ops.instruction_cycles() + FIXED_CYCLES);
}

#[test]
fn cycles_are_deterministic_and_follow_the_cycle_rule() -> TestResult {
    for name in ["reference", "mirror"] {
        let mut scene = sized(name, 80, 60)?;
        for method in golden::fp::Method::ALL {
            scene.render.recip = method;
            scene.render.sqrt = method;
            let proc = Processor::new(&scene);
            let mut sum = 0;
            for (x, y) in [(0, 0), (40, 30), (22, 25), (60, 41), (79, 59)] {
                let a = proc.render_pixel(x, y, |_, _| {});
                let b = micro::render_pixel(&scene, x, y, |_, _| {});
                assert_eq!(a, b);
                check_cycle_rule(&scene, &a);
                sum += a.cycles;
            }
            assert!(sum > 0);
        }
        // The frame's statistics are the sum over its pixels.
        let (frame, stats) = micro::render(&scene, &|_| {});
        let proc = Processor::new(&scene);
        let mut total = 0;
        let mut max = 0;
        for y in 0..60 {
            for x in 0..80 {
                let r = proc.render_pixel(x, y, |_, _| {});
                assert_eq!(frame.pixel(x, y), r.rgb.map(f64::from));
                total += r.cycles;
                max = max.max(r.cycles);
            }
        }
        assert_eq!(stats.pixels, 80 * 60);
        assert_eq!(stats.cycles, total);
        assert_eq!(stats.max_cycles, max);
        assert_eq!(
            stats.cycles,
            stats.ops.instruction_cycles() + FIXED_CYCLES * stats.pixels
        );
    }
    Ok(())
}

#[test]
fn one_and_two_threads_give_the_same_frame_and_statistics() -> TestResult {
    let scene = sized("mirror", 80, 60)?;
    let run = |threads| -> Result<_, Box<dyn Error>> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        Ok(pool.install(|| micro::render(&scene, &|_| {})))
    };
    let (f1, s1) = run(1)?;
    let (f2, s2) = run(2)?;
    assert_eq!(pixels_differing(&f1, &f2), 0);
    assert_eq!(s1, s2);
    Ok(())
}

// ---------------------------------------------------------------------------
// The trace
// ---------------------------------------------------------------------------

#[test]
fn the_trace_has_one_named_event_per_register_write_in_sequence() -> TestResult {
    let scene = sized("reference", 40, 30)?;
    let proc = Processor::new(&scene);
    let root_col = isa::stack(0, RayField::Col);
    let mut states = HashSet::new();
    for y in 0..30 {
        for x in 0..40 {
            let mut events: Vec<(TraceEvent, &'static Location<'static>)> = Vec::new();
            let r = proc.render_pixel(x, y, |e: &TraceEvent, at: &'static Location<'static>| {
                events.push((*e, at))
            });
            for (i, (e, at)) in events.iter().enumerate() {
                assert_eq!(e.seq, i as u32, "pixel ({x}, {y})");
                assert_eq!((e.x, e.y), (x as u16, y as u16));
                let dst = isa::register_name(e.dst);
                assert!(dst.is_some(), "unnamed register {} at {at}", e.dst);
                assert!(
                    !isa::is_stack_relative(isa::Reg(e.dst)),
                    "undecoded {dst:?} at {at}"
                );
                assert!(e.dst >= reg::T0, "scene register {dst:?} written at {at}");
                assert!(
                    isa::state_name(e.state).is_some(),
                    "state {} at {at}",
                    e.state
                );
                assert!((1..=7).contains(&e.lanes));
                for lane in 0..3 {
                    if e.lanes >> lane & 1 == 0 {
                        assert_eq!(e.values[lane], 0);
                    }
                }
                assert!(
                    at.file().ends_with("program.rs"),
                    "an instruction issued outside the controller: {at}"
                );
                states.insert(e.state);
            }
            // Every register-file write is one event; DOT1, DOT2, ISECT1 and
            // ISECT3 write only F.
            let ops = &r.ops;
            let writes = ops.instructions()
                - ops.count_of(OpClass::Dot) * 2 / 3
                - ops.count_of(OpClass::Isect) / 2;
            assert_eq!(events.len() as u64, writes);
            assert_eq!(events.len() as u64, ops.register_writes);
            // The last write to the root's colour is the pixel's colour.
            let (last, _) = events
                .iter()
                .rev()
                .find(|(e, _)| isa::Reg(e.dst) == root_col)
                .expect("the root colour is written");
            assert_eq!(last.lanes, 0b111);
            assert_eq!(last.values, r.rgb.map(f32::to_bits));
        }
    }
    println!("{} distinct states wrote registers", states.len());
    Ok(())
}

/// Tracing observes and changes nothing: a traced pixel computes exactly
/// what an untraced one does (colour, cycles, every instruction count), and
/// the frame `micro::render` draws untraced is the traced pixels' colours.
/// (The model is inlined into each tracer's monomorphization separately, so
/// this is not a tautology.)
#[test]
fn a_traced_render_equals_an_untraced_one() -> TestResult {
    for name in ["reference", "mirror"] {
        let scene = sized(name, 40, 30)?;
        let proc = Processor::new(&scene);
        let (frame, stats) = micro::render(&scene, &|_| {});
        let mut traced = FrameStatsSum::default();
        for y in 0..30 {
            for x in 0..40 {
                let mut events = 0u64;
                let t = proc.render_pixel(x, y, |_: &TraceEvent, _: &_| events += 1);
                let u = proc.render_pixel(x, y, |_, _| {});
                assert_eq!(t, u, "{name} ({x}, {y})");
                assert_eq!(events, t.ops.register_writes);
                assert_eq!(frame.pixel(x, y), t.rgb.map(f64::from));
                traced.add(&t, events);
            }
        }
        assert_eq!(traced.cycles, stats.cycles);
        assert_eq!(traced.ops, stats.ops);
        assert_eq!(traced.events, stats.ops.register_writes);
    }
    Ok(())
}

#[derive(Default)]
struct FrameStatsSum {
    cycles: u64,
    ops: golden::micro::OpStats,
    events: u64,
}

impl FrameStatsSum {
    fn add(&mut self, r: &PixelResult, events: u64) {
        self.cycles += r.cycles;
        self.ops.merge(&r.ops);
        self.events += events;
    }
}

// ---------------------------------------------------------------------------
// Speed-ups (thesis 3.10): "without changing the end result"
// ---------------------------------------------------------------------------

fn with_speedups(scene: &Scene, speedups: Speedups) -> Scene {
    let mut s = scene.clone();
    s.render.speedups = speedups;
    s
}

/// Every single speed-up off, and all off, against the scene's own setting
/// (all three on for reference and mirror): bit-identical frames.
fn assert_speedups_change_nothing(scene: &Scene) -> Vec<(String, f64)> {
    let on = scene.render.speedups;
    assert_eq!(
        on,
        Speedups {
            bounding_box: true,
            fast_plane: true,
            shadow_shortcut: true
        }
    );
    let (base, base_stats) = micro::render(scene, &|_| {});
    let mut means = vec![("all three".to_string(), base_stats.mean_cycles())];
    let variants = [
        (
            "no bounding_box",
            Speedups {
                bounding_box: false,
                ..on
            },
        ),
        (
            "no fast_plane",
            Speedups {
                fast_plane: false,
                ..on
            },
        ),
        (
            "no shadow_shortcut",
            Speedups {
                shadow_shortcut: false,
                ..on
            },
        ),
        ("none", Speedups::default()),
    ];
    for (what, speedups) in variants {
        let (frame, stats) = micro::render(&with_speedups(scene, speedups), &|_| {});
        assert_eq!(pixels_differing(&base, &frame), 0, "{what} changes pixels");
        means.push((what.to_string(), stats.mean_cycles()));
    }
    means
}

#[test]
fn no_speed_up_changes_a_bit_of_the_reference_or_mirror_scene() -> TestResult {
    for name in ["reference", "mirror"] {
        let means = assert_speedups_change_nothing(&sized(name, 160, 120)?);
        println!("{name} 160x120 mean cycles/pixel: {means:?}");
        // Each speed-up pays for itself.
        assert!(means[1..].iter().all(|(_, m)| *m > means[0].1));
    }
    Ok(())
}

#[test]
#[ignore = "full size: run with --release"]
fn no_speed_up_changes_a_bit_of_the_full_size_scenes() {
    for name in ["reference", "mirror"] {
        let means = assert_speedups_change_nothing(&builtin(name));
        println!("{name} 800x600 mean cycles/pixel: {means:?}");
    }
}

/// How a speed-up forced on against its precondition changes a frame.
fn damage(ok: &Scene, forced: &Scene) -> Result<(usize, f64), Box<dyn Error>> {
    let (a, b) = (micro_frame(ok), micro_frame(forced));
    Ok((pixels_differing(&a, &b), a.compare(&b)?.max_abs_diff))
}

fn assert_visibly_wrong(what: &str, pixels: usize, max: f64, total: u64) {
    println!("{what}: {pixels} of {total} pixels change, by up to {max:.1}/255",);
    assert!(
        pixels as u64 * 20 > total,
        "{what}: only {pixels} pixels change"
    );
    assert!(max > 50.0, "{what}: at most {max}/255");
}

#[test]
fn a_bounding_box_that_misses_the_spheres_hides_them() -> TestResult {
    let ok = with_speedups(&sized("reference", 80, 60)?, Speedups::default());
    // The precondition is the derived box: make it a point at its corner.
    let mut forced = ok.clone();
    forced.derived.bbox_max = forced.derived.bbox_min;
    let (pixels, max) = damage(&ok, &forced)?;
    assert_eq!(pixels, 0, "the box is unused with the speed-up off");
    forced.render.speedups.bounding_box = true;
    let (pixels, max2) = damage(&ok, &forced)?;
    assert_visibly_wrong(
        "bounding_box, box shrunk to a corner",
        pixels,
        max.max(max2),
        ok.pixel_count(),
    );
    Ok(())
}

#[test]
fn the_fast_plane_test_sees_a_plane_from_behind_the_eye() -> TestResult {
    // The reference scene with the floor flipped: the eye (and everything)
    // is behind it. Scene::new accepts it with fast_plane off.
    let r = sized("reference", 80, 60)?;
    let mut planes = r.planes.clone();
    planes[0].facing = -1.0;
    let ok = Scene::new(
        "flipped floor",
        r.camera.clone(),
        r.light.clone(),
        r.spheres.clone(),
        planes,
        golden::scene::RenderSettings {
            speedups: Speedups::default(),
            ..r.render
        },
    )?;
    let mut forced = ok.clone();
    forced.render.speedups.fast_plane = true;
    assert!(
        Scene::new(
            "check",
            forced.camera.clone(),
            forced.light.clone(),
            forced.spheres.clone(),
            forced.planes.clone(),
            forced.render
        )
        .is_err(),
        "validation refuses fast_plane here"
    );
    let (pixels, max) = damage(&ok, &forced)?;
    assert_visibly_wrong(
        "fast_plane, eye behind the floor",
        pixels,
        max,
        ok.pixel_count(),
    );
    Ok(())
}

#[test]
fn the_shadow_shortcut_shadows_wrongly_when_a_sphere_lies_beyond_the_light() -> TestResult {
    // light_touch: the light between the spheres and close to them; its
    // validation refuses shadow_shortcut.
    let ok = sized("light_touch", 80, 60)?;
    assert!(!ok.render.speedups.shadow_shortcut);
    let mut forced = ok.clone();
    forced.render.speedups.shadow_shortcut = true;
    let (pixels, max) = damage(&ok, &forced)?;
    assert_visibly_wrong(
        "shadow_shortcut in light_touch",
        pixels,
        max,
        ok.pixel_count(),
    );
    Ok(())
}

// ---------------------------------------------------------------------------
// Stack depth (thesis figures 9 and 10)
// ---------------------------------------------------------------------------

/// The mirror scene at stack depths 1..=7 against the reference renderer at
/// the deepest stack the RTL has (8): the error is the light the missing
/// generations would add, so it shrinks with every level.
fn depth_sweep(w: u32, h: u32) -> TestResult {
    let mut deep = sized("mirror", w, h)?;
    deep.render.max_depth = golden::scene::MAX_DEPTH;
    let target = reference::render(&deep, &|_| {});
    let mut errors = Vec::new();
    for depth in 1..=7 {
        let mut s = deep.clone();
        s.render.max_depth = depth;
        let (frame, stats) = micro::render(&s, &|_| {});
        let d = frame.compare(&target)?;
        let mean = mean_abs_diff_255(&frame, &target);
        println!(
            "mirror {w}x{h} depth {depth}: mean error {mean:.4}/255, largest {:.2}/255, \
             {:.2}% of channels > 0.5/255, {:.1} cycles/pixel",
            d.max_abs_diff,
            100.0 * d.share_over(0.5),
            stats.mean_cycles()
        );
        errors.push(mean);
    }
    for w in errors.windows(2) {
        assert!(w[1] < w[0], "error does not decrease: {errors:?}");
    }
    assert!(errors[6] < errors[0] / 20.0, "{errors:?}");
    Ok(())
}

#[test]
fn deeper_stacks_approach_the_deepest_image_on_the_mirror_scene() -> TestResult {
    depth_sweep(80, 60)
}

#[test]
#[ignore = "full size: run with --release"]
fn deeper_stacks_approach_the_deepest_image_at_full_size() -> TestResult {
    depth_sweep(800, 600)
}

// ---------------------------------------------------------------------------
// Every builtin scene
// ---------------------------------------------------------------------------

#[test]
fn every_builtin_scene_renders_close_to_the_reference() -> TestResult {
    for &name in Scene::builtin_names() {
        let scene = sized(name, 80, 60)?;
        let (frame, stats) = micro::render(&scene, &|_| {});
        assert!(frame.pixels.iter().flatten().all(|c| c.is_finite()));
        let d = frame.compare(&reference::render(&scene, &|_| {}))?;
        println!(
            "{name} 80x60: largest difference {:.4}/255, {:.3}% > 0.5/255, {:.1} cycles/pixel (max {})",
            d.max_abs_diff,
            100.0 * d.share_over(0.5),
            stats.mean_cycles(),
            stats.max_cycles
        );
        assert!(d.share_over(0.5) < 0.001, "{name}");
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Random scenes: every path of the program
// ---------------------------------------------------------------------------

/// Random valid scenes (materials with zero terms, every depth, both
/// methods, each speed-up on whenever the scene allows it): the model's
/// invariants hold on every path (no panic: every register read was loaded
/// or written), colours stay finite, and the picture is the reference's.
#[test]
fn random_scenes_keep_the_invariants_and_follow_the_reference() -> TestResult {
    use golden::fp::Method;
    use golden::scene::{Axis, Camera, Light, Material, Plane, RenderSettings, Sphere};
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let unit = |rng: &mut rand_chacha::ChaCha8Rng| -> f32 {
        // A zero term now and then, to take the branches that skip it.
        if rng.random_bool(0.2) {
            0.0
        } else {
            rng.random_range(0.05..1.0)
        }
    };
    let mut worst = 0.0f64;
    let mut over = 0usize;
    let mut rendered = [0usize; 4];
    for case in 0..64 {
        let material = |rng: &mut rand_chacha::ChaCha8Rng| {
            Material::opaque(
                [0, 1, 2].map(|_| rng.random_range(0.1..1.0)),
                unit(rng),
                unit(rng),
                unit(rng),
            )
        };
        let spheres = (0..rng.random_range(0..=4))
            .map(|_| Sphere {
                center: [
                    rng.random_range(-200.0..200.0),
                    rng.random_range(20.0..250.0),
                    rng.random_range(100.0..500.0),
                ],
                radius: rng.random_range(10.0..80.0),
                material: material(&mut rng),
            })
            .collect::<Vec<_>>();
        let mut planes = vec![Plane {
            axis: Axis::Y,
            facing: 1.0,
            offset: -rng.random_range(0.0..50.0),
            material: material(&mut rng),
        }];
        if spheres.is_empty() || rng.random_bool(0.5) {
            planes.push(Plane {
                axis: Axis::Z,
                facing: -1.0,
                offset: 900.0,
                material: material(&mut rng),
            });
        }
        let camera = Camera {
            eye: [rng.random_range(-50.0..50.0), 150.0, -500.0],
            rotation_deg: [
                rng.random_range(-10.0..10.0),
                rng.random_range(-10.0..10.0),
                if rng.random_bool(0.5) { 0.0 } else { 5.0 },
            ],
            distance: 60.0,
            width: 32,
            height: 24,
        };
        let light = Light {
            position: [rng.random_range(-400.0..400.0), 800.0, -300.0],
            color: [1.0, rng.random_range(0.5..1.0), 1.0],
        };
        let method = if case % 2 == 0 {
            Method::Exact
        } else {
            Method::Fast
        };
        let mut settings = RenderSettings {
            max_depth: rng.random_range(1..=8),
            speedups: Speedups::default(),
            recip: method,
            sqrt: method,
            weight_cutoff: 0.0,
            exposure: None,
        };
        let build = |settings: RenderSettings| {
            Scene::new(
                "random",
                camera.clone(),
                light.clone(),
                spheres.clone(),
                planes.clone(),
                settings,
            )
        };
        let Ok(mut scene) = build(settings) else {
            continue;
        };
        for flag in 0..3 {
            let mut trial = settings;
            let on = rng.random_bool(0.7);
            match flag {
                0 => trial.speedups.bounding_box = on,
                1 => trial.speedups.fast_plane = on,
                _ => trial.speedups.shadow_shortcut = on,
            }
            if let Ok(s) = build(trial) {
                settings = trial;
                scene = s;
            }
        }
        let (frame, stats) = micro::render(&scene, &|_| {});
        let sp = settings.speedups;
        rendered[0] += 1;
        rendered[1] += usize::from(sp.bounding_box);
        rendered[2] += usize::from(sp.fast_plane);
        rendered[3] += usize::from(sp.shadow_shortcut);
        assert!(frame.pixels.iter().flatten().all(|c| c.is_finite()));
        assert!(stats.min_cycles > FIXED_CYCLES);
        let d = frame.compare(&reference::render(&scene, &|_| {}))?;
        worst = worst.max(d.max_abs_diff);
        over += (d.share_over(0.5) * d.channels() as f64).round() as usize;
        // Bit-identical with the speed-ups off.
        let plain = micro_frame(&with_speedups(&scene, Speedups::default()));
        assert_eq!(
            pixels_differing(&frame, &plain),
            0,
            "case {case}: speed-ups {:?} change pixels",
            settings.speedups
        );
    }
    println!(
        "{} random scenes ({} with bounding_box, {} fast_plane, {} shadow_shortcut): \
         largest difference {worst:.3}/255, {over} channels > 0.5/255",
        rendered[0], rendered[1], rendered[2], rendered[3]
    );
    assert!(
        rendered.iter().all(|&n| n >= 10),
        "too few cases: {rendered:?}"
    );
    assert!(over <= 3, "{over} channels over 0.5/255");
    Ok(())
}
