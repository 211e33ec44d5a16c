//! The pixel processor under a second simulator: Icarus Verilog (`iverilog
//! -g2005`, `vvp`) runs rtl/ with the testbench tests/icarus/pp_tb.v, loaded
//! through the scene port with golden's scene writes and configuration word
//! (as harness/design/pixel_proc.rs loads the verilated model), and every pixel's
//! RGB bits and cycle count must equal golden::micro's. Verilog whose meaning
//! depends on the simulator (a function reading signals that are not its
//! arguments, a combinational block whose reads hide in tasks) shows here as
//! pixels that Verilator gets right and Icarus does not.
//!
//! `cargo test` runs a sample of every builtin scene, including pixels of
//! the 80x60 reference frame that differed under Icarus before the RTL was
//! fixed (docs/rtl.md); `--ignored` adds whole reduced frames of every
//! builtin scene (RTCOSIM_ICARUS_SCENES=a,b picks some) and the builtin
//! scenes with their switches flipped (speed-ups off, fast methods, other
//! rotations and depths), which reach controller paths no builtin does.
//!
//! Without `iverilog` on PATH the tests print that they did not run and
//! pass, unless RTCOSIM_REQUIRE_ICARUS=1 (CI sets it), which fails them.

mod common;

use common::icarus::{
    compile, compile_fast_alu, compile_fast_pp, compile_fast_regfile, compile_fast_top,
    compile_fast_units, differences, fast_differences, fast_top_differences, icarus_present,
    pix_lines, run_fast_alu, run_fast_pp, run_fast_regfile, run_fast_units, run_vvp, scene_hex,
    simulate, simulate_with, vvp_pixels, work_dir, write_scene_hex, SimPixel,
};
use common::{builtin, reduced, window};
use golden::fp::Method;
use golden::scene::Scene;
use rtcosim::design::Design;

/// Every 12th of the 307 pixels of the 80x60 reference frame whose colour
/// Icarus computed differently from golden (and Verilator) on the RTL
/// before the fix (docs/rtl.md, "The RTL under Icarus Verilog"): sphere
/// silhouettes, shadow edges on the floor, reflections of two and three
/// levels.
const REFERENCE_FORMERLY_DIFFERENT: &[(u32, u32)] = &[
    (19, 22),
    (39, 24),
    (21, 26),
    (41, 28),
    (52, 29),
    (35, 31),
    (52, 33),
    (36, 35),
    (29, 37),
    (38, 38),
    (62, 40),
    (39, 42),
    (25, 43),
    (55, 43),
    (28, 44),
    (57, 44),
    (29, 45),
    (59, 45),
    (32, 46),
    (30, 47),
    (20, 49),
    (55, 50),
    (58, 51),
    (24, 54),
    (38, 55),
    (28, 57),
];

/// Every `step`-th pixel in both directions, offset so the image's corners
/// are not all that is sampled.
fn grid(scene: &Scene, step: u32) -> Vec<(u32, u32)> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    (step / 2..h)
        .step_by(step as usize)
        .flat_map(|y| (step / 3..w).step_by(step as usize).map(move |x| (x, y)))
        .collect()
}

/// Pixels of a scene to run, under a name that is also its work directory.
struct Run {
    name: String,
    scene: Scene,
    pixels: Vec<(u32, u32)>,
}

/// Runs every scene's pixels and fails, after all of them, if any pixel
/// differs from golden.
fn assert_same(runs: &[Run]) {
    let mut failures = Vec::new();
    for Run {
        name,
        scene,
        pixels,
    } in runs
    {
        let start = std::time::Instant::now();
        let got = simulate(name, scene, pixels);
        let diff = differences(scene, &got);
        println!(
            "{name} ({}x{}): {} of {} pixels differ under Icarus ({:.1} s)",
            scene.camera.width,
            scene.camera.height,
            diff.len(),
            pixels.len(),
            start.elapsed().as_secs_f64()
        );
        if !diff.is_empty() {
            failures.push(format!(
                "{name}: {} of {} pixels differ under Icarus:\n{}",
                diff.len(),
                pixels.len(),
                diff.join("\n")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn sampled_pixels_of_every_builtin_scene_agree_under_icarus() {
    if !icarus_present("sampled_pixels_of_every_builtin_scene_agree_under_icarus") {
        return;
    }
    let runs: Vec<_> = Scene::builtin_names()
        .iter()
        .map(|name| {
            let scene = reduced(name);
            let mut pixels = grid(&scene, if *name == "box_room" { 13 } else { 11 });
            if *name == "reference" {
                pixels.extend_from_slice(REFERENCE_FORMERLY_DIFFERENT);
            }
            Run {
                name: format!("sample_{name}"),
                scene,
                pixels,
            }
        })
        .collect();
    assert_same(&runs);
}

/// The glass scenes on the compact processor, through their glass:
/// refraction's states mean the same under Icarus.
#[test]
fn glass_scenes_agree_under_icarus() {
    if !icarus_present("glass_scenes_agree_under_icarus") {
        return;
    }
    let runs: Vec<_> = ["glass_room", "bubble", "touching"]
        .iter()
        .map(|name| {
            let scene = builtin(name, 80, 60);
            // Through the glass (x 32..51, y 26..45 of 80x60) and around it.
            let pixels = (24..48)
                .step_by(2)
                .flat_map(|y| (28..56).step_by(2).map(move |x| (x, y)))
                .collect();
            Run {
                name: format!("glass_{name}"),
                scene,
                pixels,
            }
        })
        .collect();
    assert_same(&runs);
}

/// Through the glass of glass_room at 80x60 (its sphere covers x 32..51,
/// y 26..45).
fn through_the_glass() -> Vec<(u32, u32)> {
    (30..42)
        .step_by(4)
        .flat_map(|y| (36..48).step_by(4).map(move |x| (x, y)))
        .collect()
}

/// The compact processor built without refraction (`REFRACTION = 0`): on
/// a scene without glass every pixel is golden's, colour and cycles (the
/// build with refraction's); on a glass scene it shows the glass opaque,
/// so every pixel through it differs from golden's, which is why a build
/// without refraction is refused a scene with glass.
#[test]
fn the_compact_processor_without_refraction_is_itself_without_glass() {
    if !icarus_present("the_compact_processor_without_refraction_is_itself_without_glass") {
        return;
    }
    let norefr = [("REFRACTION", 0)];
    let scene = reduced("reference");
    let pixels = grid(&scene, 11);
    let got = simulate_with("norefr_reference", &scene, &pixels, &norefr);
    let diff = differences(&scene, &got);
    println!(
        "reference without refraction: {} of {} pixels differ",
        diff.len(),
        pixels.len()
    );
    assert!(diff.is_empty(), "{}", diff.join("\n"));
    let glass = builtin("glass_room", 80, 60);
    let pixels = through_the_glass();
    let got = simulate_with("norefr_glass_room", &glass, &pixels, &norefr);
    let diff = differences(&glass, &got);
    println!(
        "glass_room without refraction: {} of {} pixels through the glass differ",
        diff.len(),
        pixels.len()
    );
    assert_eq!(diff.len(), pixels.len(), "{}", diff.join("\n"));
}

#[test]
#[ignore = "whole reduced frames of every builtin scene under Icarus: minutes"]
fn every_builtin_scene_agrees_under_icarus() {
    if !icarus_present("every_builtin_scene_agrees_under_icarus") {
        return;
    }
    let only = std::env::var("RTCOSIM_ICARUS_SCENES").ok();
    let runs: Vec<_> = Scene::builtin_names()
        .iter()
        .filter(|name| {
            only.as_deref()
                .map_or(true, |o| o.split(',').any(|n| n == **name))
        })
        .map(|name| {
            let scene = reduced(name);
            let (w, h) = (scene.camera.width, scene.camera.height);
            let pixels: Vec<(u32, u32)> =
                (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).collect();
            Run {
                name: format!("frame_{name}"),
                scene,
                pixels,
            }
        })
        .collect();
    assert_same(&runs);
}

/// `scene` with one of its switches flipped, if the scene still validates
/// (a shadow shortcut cannot be turned off where it is off already).
fn switched(scene: &Scene, switch: &str) -> Option<Scene> {
    let mut render = scene.render;
    let mut camera = scene.camera.clone();
    let s = &mut render.speedups;
    match switch {
        "no_speedups" => (s.bounding_box, s.fast_plane, s.shadow_shortcut) = (false, false, false),
        "no_bounding_box" => s.bounding_box = false,
        "no_fast_plane" => s.fast_plane = false,
        "no_shadow_shortcut" if s.shadow_shortcut => s.shadow_shortcut = false,
        "fast_methods" => (render.recip, render.sqrt) = (Method::Fast, Method::Fast),
        "rotated_y_z_depth_8" => {
            (camera.rotation_deg[1], camera.rotation_deg[2]) = (3.0, 7.0);
            render.max_depth = golden::scene::MAX_DEPTH;
        }
        "depth_1" => render.max_depth = 1,
        _ => return None,
    }
    let (light, spheres, planes) = (
        scene.light.clone(),
        scene.spheres.clone(),
        scene.planes.clone(),
    );
    Scene::new(switch, camera, light, spheres, planes, render).ok()
}

/// The builtin scenes all use the bounding box and the fast plane test and
/// never rotate about z: the paths of the controller they leave out, under
/// Icarus against golden, on a grid of each reduced frame.
#[test]
#[ignore = "every builtin scene with its switches flipped, under Icarus: minutes"]
fn builtin_scenes_with_other_switches_agree_under_icarus() {
    if !icarus_present("builtin_scenes_with_other_switches_agree_under_icarus") {
        return;
    }
    let switches = [
        "no_speedups",
        "no_bounding_box",
        "no_fast_plane",
        "no_shadow_shortcut",
        "fast_methods",
        "rotated_y_z_depth_8",
        "depth_1",
    ];
    let runs: Vec<_> = Scene::builtin_names()
        .iter()
        .flat_map(|name| {
            let base = reduced(name);
            switches.iter().filter_map(move |switch| {
                let scene = switched(&base, switch)?;
                let pixels = grid(&scene, 9);
                Some(Run {
                    name: format!("{name}_{switch}"),
                    scene,
                    pixels,
                })
            })
        })
        .collect();
    assert_same(&runs);
}

/// The top module (rtl/top.v) with two pixel processors under Icarus, fed
/// through its coordinate stream while the result stream is held back in
/// 99% of the cycles (tests/icarus/top_tb.v): every pixel comes back exactly
/// once, tagged with its coordinates, with golden's RGB bits and cycles, and
/// both processors did some of them. (A dispatcher that ignores a full
/// result slot loses 22 of these 71 pixels at 99%, none at 30% or 95%.)
#[test]
fn the_top_with_two_processors_agrees_under_icarus() {
    if !icarus_present("the_top_with_two_processors_agrees_under_icarus") {
        return;
    }
    let scene = reduced("reference");
    let mut pixels = grid(&scene, 9);
    pixels.extend_from_slice(&REFERENCE_FORMERLY_DIFFERENT[..8]);
    let dir = work_dir("top_n2");
    let vvp = compile(
        &dir,
        "top_tb",
        scene.render.recip,
        scene.render.sqrt,
        &[("N", 2)],
    );
    let stdout = vvp_pixels(
        &vvp,
        &write_scene_hex(&dir, &scene),
        scene_hex(&scene).1,
        &dir.join("pixels.hex"),
        &pixels,
        &["+seed=7", "+stall=99"],
    );
    let lines = pix_lines(&stdout);
    let mut back: Vec<(u32, u32)> = lines.iter().map(|(p, _)| (p.x, p.y)).collect();
    let in_order = back == pixels;
    back.sort();
    let mut want = pixels.clone();
    want.sort();
    assert_eq!(back, want, "each pixel exactly once");
    let procs: std::collections::BTreeSet<u64> = lines.iter().map(|(_, rest)| rest[0]).collect();
    assert_eq!(procs.len(), 2, "processors used: {procs:?}");
    let got: Vec<SimPixel> = lines.into_iter().map(|(p, _)| p).collect();
    let diff = differences(&scene, &got);
    println!(
        "top, N = 2, reference 80x60: {} of {} pixels differ under Icarus; results {}in order",
        diff.len(),
        pixels.len(),
        if in_order { "" } else { "out of " }
    );
    assert!(diff.is_empty(), "{}", diff.join("\n"));
}

/// The speed ratio of the two simulators (docs/perf.md, "Icarus against
/// Verilator"): the same pixels of the 80x60 reference frame on one thread,
/// under Icarus (one `vvp`, after compiling) and through the verilated
/// model's driver (after building and loading it). Both must agree with
/// golden on every pixel and so run the same RTL cycles; the test asserts
/// that and prints the times.
#[test]
#[ignore = "times Icarus against Verilator on 640 pixels: a minute"]
fn icarus_speed_against_verilator() {
    if !icarus_present("icarus_speed_against_verilator") {
        return;
    }
    let scene = reduced("reference");
    // Every pixel of every 8th row: 640 pixels, the whole range of paths.
    let pixels: Vec<(u32, u32)> = (0..scene.camera.height)
        .step_by(8)
        .flat_map(|y| (0..scene.camera.width).map(move |x| (x, y)))
        .collect();
    let dir = work_dir("speed");
    let vvp = compile(&dir, "pp_tb", scene.render.recip, scene.render.sqrt, &[]);
    let scene_file = write_scene_hex(&dir, &scene);
    let n_writes = scene_hex(&scene).1;
    let start = std::time::Instant::now();
    let got = run_vvp(
        &vvp,
        &scene_file,
        n_writes,
        &dir.join("pixels.hex"),
        &pixels,
    );
    let icarus = start.elapsed().as_secs_f64();
    let diff = differences(&scene, &got);
    assert!(diff.is_empty(), "{}", diff.join("\n"));
    let icarus_cycles: u64 = got.iter().map(|p| p.cycles).sum();

    let mut rtl = rtcosim::design::pixel_proc::PixelProcessor::open(&Design::compact(
        scene.render.recip,
        scene.render.sqrt,
    ))
    .expect("the verilated model");
    rtl.load_scene(&scene).expect("loading the scene");
    let start = std::time::Instant::now();
    let mut verilator_cycles = 0;
    for &(x, y) in &pixels {
        let outcome = rtl.run_pixel(x, y, None).expect("a verilated pixel");
        let sim = got
            .iter()
            .find(|p| (p.x, p.y) == (x, y))
            .expect("the pixel under Icarus");
        let bits = outcome.rgb.map(|c| format!("{c:08x}"));
        assert_eq!(bits, sim.rgb, "pixel ({x}, {y}): Verilator against Icarus");
        verilator_cycles += outcome.cycles;
    }
    let verilator = start.elapsed().as_secs_f64();
    assert_eq!(
        verilator_cycles, icarus_cycles,
        "RTL cycles, Verilator against Icarus"
    );
    println!(
        "reference 80x60, {} pixels, {icarus_cycles} RTL cycles, one thread: \
         Icarus {icarus:.2} s ({:.0} cycles/s), Verilator {verilator:.3} s ({:.0} cycles/s): \
         Verilator {:.0} times as fast",
        pixels.len(),
        icarus_cycles as f64 / icarus,
        verilator_cycles as f64 / verilator,
        icarus / verilator
    );
}

/// The fast processor's pipelined float units (rtl/fast) under Icarus, one
/// operation every cycle, back to back: every result equals golden::fp's
/// (the edge-case pairs and 20,000 seeded random pairs through the adder
/// and the multiplier, their first operands through itof, the exact
/// reciprocal and square root and the exponential, with the reciprocal's
/// and square root's correction edges, and the exponential's edges and
/// 10,000 of its own random operands). A golden value changed in one vector
/// of each unit is reported as exactly that one mismatch, so the
/// testbench's comparison can fail.
#[test]
fn pipelined_units_agree_with_golden() {
    if !icarus_present("pipelined_units_agree_with_golden") {
        return;
    }
    use rtcosim::check::operands;
    use rtcosim::design::fp_unit::UnitKind;
    let recip = UnitKind::FastRecip(Method::Exact);
    let (mut a, mut b) = operands::edge_cases(UnitKind::FastAdd);
    let (ra, rb) = operands::random_chunk(UnitKind::FastAdd, 0x2011_0607, 0, 20_000);
    a.extend(ra);
    b.extend(rb);
    let sqrt = UnitKind::FastSqrt(Method::Exact);
    // The reciprocal's and square root's own edges (every correction step)
    // as first operands.
    for unit in [recip, sqrt] {
        let (edges, _) = operands::edge_cases(unit);
        b.extend(edges.iter().map(|_| 0x3F80_0000));
        a.extend(edges);
    }
    // The exponential's edges (regime changes) and random operands.
    let exp = UnitKind::FastExp;
    let (mut exp_a, _) = operands::edge_cases(exp);
    exp_a.extend(operands::random_chunk(exp, 0x2011_0607, 0, 10_000).0);
    b.extend(exp_a.iter().map(|_| 0x3F80_0000));
    a.extend(exp_a);
    let vectors: Vec<[u32; 8]> = a
        .iter()
        .zip(&b)
        .map(|(&x, &y)| {
            [
                x,
                y,
                UnitKind::FastAdd.golden(x, y),
                UnitKind::FastMul.golden(x, y),
                UnitKind::FastItof.golden(x, 0),
                recip.golden(x, 0),
                sqrt.golden(x, 0),
                exp.golden(x, 0),
            ]
        })
        .collect();
    assert!(vectors.len() > 20_000);
    let dir = work_dir("fast_units");
    let vvp = compile_fast_units(&dir);
    let (bad, stdout) = run_fast_units(&vvp, &dir, "vectors", &vectors);
    assert_eq!(bad, [0; 6], "{stdout}");

    let mut faulty = vectors.clone();
    faulty[777][2] ^= 1;
    faulty[4321][3] ^= 0x8000_0000;
    faulty[999][4] ^= 2;
    faulty[12345][5] ^= 1;
    faulty[20001][6] ^= 0x10;
    let last = faulty.len() - 1;
    faulty[last - 4321][7] ^= 4;
    let (bad, stdout) = run_fast_units(&vvp, &dir, "faulty", &faulty);
    assert_eq!(bad, [1; 6], "{stdout}");
}

/// The fast processor's register file (rtl/fast/fast_regfile.v) under
/// Icarus against its testbench's model of the contract (every word
/// written, then 20,000 random cycles of two reads, a lane-masked write and
/// now and then a scene write, half the addresses at the tables' edges), at
/// stack depths 8, 3 and 1: every read two edges later is the model's. A
/// model value changed in one read is reported as exactly that mismatch.
#[test]
fn fast_register_file_agrees_with_its_model() {
    if !icarus_present("fast_register_file_agrees_with_its_model") {
        return;
    }
    let dir = work_dir("fast_regfile");
    for depth in [8, 3, 1] {
        let vvp = compile_fast_regfile(&dir, depth);
        let (reads, bad, stdout) = run_fast_regfile(&vvp, None);
        assert_eq!((reads, bad), (40_000, 0), "depth {depth}:\n{stdout}");
        if depth == 8 {
            let (_, bad, stdout) = run_fast_regfile(&vvp, Some(777));
            assert_eq!(bad, 1, "{stdout}");
            assert!(stdout.contains("mismatch"), "{stdout}");
        }
    }
}

/// The fast processor's ALU (rtl/fast/fast_alu.v) under Icarus, cycle by
/// cycle: a seeded schedule of 7 contexts' opcodes (every code, the F
/// chains, EXPs as close as allowed) with and without exposure, every
/// result, its context, write bit, defined lanes and flags, and exp_ready
/// in every cycle as golden and the contract say (the vectors are built
/// from the same `harness::check::alu_check::Schedule` the Verilator test runs). A
/// golden value changed in one result is reported as exactly that
/// mismatch.
#[test]
fn fast_alu_agrees_with_golden_under_icarus() {
    if !icarus_present("fast_alu_agrees_with_golden_under_icarus") {
        return;
    }
    use golden::micro::alu::fast_latency;
    use golden::micro::isa::op;
    use rtcosim::check::alu_check::{Plan, Schedule};
    let dir = work_dir("fast_alu");
    for exposure in [true, false] {
        let plan = Plan {
            bubbles: 20,
            exp_share: if exposure { 25 } else { 0 },
            ..Plan::new(7, 3_000, exposure)
        };
        let schedule = Schedule::random(plan, Method::Exact, Method::Exact, 0x2011_0607);
        let latency = fast_latency(exposure) as usize;
        let n = schedule.cycles.len() + latency + 1;
        let mut lines = vec![[0u32; 13]; n];
        let is_exp = |c: usize| {
            schedule
                .cycles
                .get(c)
                .is_some_and(|x| x.valid && x.op == op::EXP)
        };
        for (i, line) in lines.iter_mut().enumerate() {
            if let Some(x) = schedule.cycles.get(i) {
                line[0] = u32::from(x.valid) << 11 | u32::from(x.ctx) << 6 | u32::from(x.op);
                line[1..4].copy_from_slice(&x.a);
                line[4..7].copy_from_slice(&x.b);
                line[7] = x.ix;
                line[8] = x.iy;
            }
            let ready = !exposure || !((i >= 1 && is_exp(i - 1)) || (i >= 2 && is_exp(i - 2)));
            line[9] = u32::from(ready) << 19;
        }
        for e in &schedule.expected {
            let line = &mut lines[e.cycle as usize + latency];
            let (neg, pos, sign) = e.flags();
            line[9] |= 1 << 18
                | u32::from(e.ctx) << 13
                | u32::from(e.writes) << 12
                | u32::from(e.lanes.0) << 9
                | u32::from(neg) << 6
                | u32::from(pos) << 3
                | u32::from(sign);
            line[10..13].copy_from_slice(&e.y);
        }
        let vvp = compile_fast_alu(&dir, exposure);
        let (cycles, bad, stdout) = run_fast_alu(&vvp, &dir, "vectors", &lines);
        assert_eq!(
            (cycles, bad),
            (n as u64, 0),
            "exposure {exposure}:\n{stdout}"
        );
        if exposure {
            let mut faulty = lines.clone();
            let e = schedule
                .expected
                .iter()
                .rev()
                .find(|e| e.lanes.has(0))
                .expect("a result");
            faulty[e.cycle as usize + latency][10] ^= 1;
            let (_, bad, stdout) = run_fast_alu(&vvp, &dir, "faulty", &faulty);
            assert_eq!(bad, 1, "{stdout}");
        }
    }
}

/// The fast pixel processor (rtl/fast/fast_pp.v) under Icarus with its
/// trace port (tests/icarus/fast_pp_tb.v), fed a window of coordinates
/// every cycle with out_ready high, as the Verilator co-simulation
/// (tests/fast_pp.rs) feeds it: every pixel's register-file writes (state,
/// destination, lanes, values) are golden::micro's in order, its colour
/// bits are golden's, and its context and cycles, and the frame's cycles,
/// are the barrel rule's for the pixels in the order they were fed. At
/// 40x30: 48 pixels of the reference scene across its spheres (59 to 231
/// writes a pixel), and 40 of overexposed, the heaviest part of the mirror
/// scene (122 to 299 writes a pixel), every pixel through the exposure's
/// EXP, and 64 of glass_room through its glass sphere (refraction's
/// states). The checkers fail: a fault planted through the fault port (lane x
/// of every PRI_HALF write flipped) is a divergence of every pixel at that
/// write (and changes their colours), and a barrel of 31 contexts predicts
/// other cycles. The runs go in parallel: Icarus runs this design at under
/// 2,000 cycles a second.
#[test]
fn fast_processor_agrees_with_golden_under_icarus() {
    if !icarus_present("fast_processor_agrees_with_golden_under_icarus") {
        return;
    }
    use common::icarus::{FastRun, FAST_FRAME_OVERHEAD};
    use golden::micro::barrel::PixelWork;
    use golden::micro::isa::state;
    const CONTEXTS: u32 = 32; // fast_pp's CTX_BITS = 5
                              // (scene, pixels, a planted fault, REFRACTION)
    let cases = [
        ("reference", window(8, 10, 12, 4), None, true),
        ("overexposed", window(12, 15, 8, 5), None, true),
        // through the glass sphere (x 16..25, y 13..22 of 40x30)
        ("glass_room", window(16, 14, 8, 8), None, true),
        (
            "reference",
            window(8, 6, 4, 1),
            Some((state::PRI_HALF, 1 << 20)),
            true,
        ),
        // Built without refraction: itself on a scene without glass, and
        // the glass opaque (every pixel through it differs).
        ("reference", window(10, 12, 8, 2), None, false),
        ("glass_room", window(18, 16, 4, 2), None, false),
    ];
    let start = std::time::Instant::now();
    let runs: Vec<(Scene, FastRun, f64)> = std::thread::scope(|s| {
        let threads: Vec<_> = cases
            .iter()
            .map(|(name, pixels, fault, refraction)| {
                s.spawn(move || {
                    let scene = builtin(name, 40, 30);
                    let tag = match (fault.is_some(), refraction) {
                        (true, _) => "_fault",
                        (false, false) => "_norefr",
                        (false, true) => "",
                    };
                    let dir = work_dir(&format!("fast_pp_{name}{tag}"));
                    let vvp =
                        compile_fast_pp(&dir, scene.render.recip, scene.render.sqrt, *refraction);
                    let t = std::time::Instant::now();
                    let run = run_fast_pp(&vvp, &dir, &scene, pixels, *fault);
                    (scene, run, t.elapsed().as_secs_f64())
                })
            })
            .collect();
        threads
            .into_iter()
            .map(|t| t.join().expect("a vvp run panicked"))
            .collect()
    });
    let mut failures = Vec::new();
    for ((name, pixels, fault, refraction), (scene, run, secs)) in cases.iter().zip(&runs) {
        let (bad, writes) = fast_differences(scene, run, pixels, CONTEXTS);
        let golden = golden::micro::Processor::new(scene);
        let exp_pixels = pixels
            .iter()
            .filter(|&&(x, y)| {
                PixelWork::of(&golden.render_pixel(x, y, |_, _| {}))
                    .exp_at
                    .is_some()
            })
            .count();
        println!(
            "fast_pp under Icarus, {name} 40x30{}{}: {} pixels ({exp_pixels} with EXP), \
             {writes} writes compared, {} frame cycles, {} divergences ({secs:.1} s)",
            if fault.is_some() { " with a fault" } else { "" },
            if *refraction {
                ""
            } else {
                " without refraction"
            },
            run.pixels.len(),
            run.frame_cycles,
            bad.len()
        );
        if fault.is_some() {
            // Every pixel's write #1 (PRI_HALF) is hit, and nothing else
            // breaks before it.
            let hit = bad
                .iter()
                .filter(|b| b.contains("write #1: icarus"))
                .count();
            assert_eq!(hit, pixels.len(), "the planted fault:\n{}", bad.join("\n"));
            assert!(
                bad.iter().any(|b| b.contains("colour icarus")),
                "the planted fault:\n{}",
                bad.join("\n")
            );
            println!("  {}", bad.join("\n  "));
            continue;
        }
        if *name == "overexposed" {
            assert!(scene.render.exposure.is_some() && exp_pixels == pixels.len());
        }
        if *name == "glass_room" && !refraction {
            // The glass opaque: every pixel through it diverges.
            for &(x, y) in pixels {
                assert!(
                    bad.iter().any(|b| b.contains(&format!("({x}, {y})"))),
                    "({x}, {y}) through the glass does not diverge without refraction:\n{}",
                    bad.join("\n")
                );
            }
            continue;
        }
        if *name == "glass_room" {
            // Most of the window sees the glass: its pixels refract.
            let refracting = pixels
                .iter()
                .filter(|&&(x, y)| {
                    let mut rf = false;
                    golden.render_pixel(x, y, |e, _| rf |= e.state == state::RF_NSUB);
                    rf
                })
                .count();
            assert!(
                refracting * 2 > pixels.len(),
                "{refracting} of {} pixels refract",
                pixels.len()
            );
        }
        if !bad.is_empty() {
            failures.push(format!(
                "{name}: {} divergences:\n{}",
                bad.len(),
                bad[..bad.len().min(20)].join("\n")
            ));
        }
        if *name == "reference" && *refraction {
            // A barrel of the wrong size predicts other cycles.
            let (bad, _) = fast_differences(scene, run, pixels, CONTEXTS - 1);
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
            assert_eq!(FAST_FRAME_OVERHEAD, 4);
        }
    }
    println!("{:.1} s in all", start.elapsed().as_secs_f64());
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A top of three fast processors (rtl/top.v with FAST = 1) under Icarus
/// (tests/icarus/fast_top_tb.v), fed 96 pixels of the reference scene at
/// 40x30 every cycle with out_ready high: every pixel's register-file
/// writes and colour bits are golden::micro's, and its processor, context
/// and cycles and the frame's cycles are the top's rule's
/// (golden::micro::barrel::run_top: the stage, the dispatcher to the first
/// processor whose queue has room, each processor's barrel and queues, the
/// round-robin arbiter). The pixels fill processor 0's contexts and queue,
/// then processor 1's, and the rest go to processor 2, so all three run
/// and their results meet in two result groups (processors 0 and 1, and
/// 2: ARB_GROUP = 2) and at the arbiter over them. The checkers fail: a
/// planted fault (lane x of every PRI_HALF write flipped) is a divergence
/// of every pixel, and the rule for a top of two processors, or of 31
/// contexts, predicts other processors or cycles. (With the result stream
/// always ready, the groups' sizes change no pixel here: results seldom
/// meet in a group; tests/fast_pp.rs holds the stream back to see them.)
#[test]
fn fast_top_agrees_with_golden_under_icarus() {
    if !icarus_present("fast_top_agrees_with_golden_under_icarus") {
        return;
    }
    use golden::micro::isa::state;
    const PROCS: u32 = 3;
    const CONTEXTS: u32 = 32;
    const GROUP: u32 = 2; // two result groups: processors 0 and 1, and 2
    let pixels = window(4, 8, 24, 4);
    let fault_pixels = window(8, 6, 4, 1);
    let start = std::time::Instant::now();
    let scene = builtin("reference", 40, 30);
    let run = |pixels: &[(u32, u32)], fault: Option<(u16, u32)>, tag: &str| {
        let dir = work_dir(&format!("fast_top{tag}"));
        let vvp = compile_fast_top(&dir, PROCS, GROUP, scene.render.recip, scene.render.sqrt);
        run_fast_pp(&vvp, &dir, &scene, pixels, fault)
    };
    let (run, faulty) = std::thread::scope(|s| {
        let clean = s.spawn(|| run(&pixels, None, ""));
        let faulty = s.spawn(|| run(&fault_pixels, Some((state::PRI_HALF, 1 << 20)), "_fault"));
        (
            clean.join().expect("the vvp run"),
            faulty.join().expect("the faulty vvp run"),
        )
    });
    let (bad, writes) = fast_top_differences(&scene, &run, &pixels, PROCS, CONTEXTS, GROUP);
    let mut per_proc = [0usize; PROCS as usize];
    for p in &run.pixels {
        per_proc[(p.ctx / 32) as usize] += 1;
    }
    println!(
        "top of {PROCS} fast processors under Icarus, reference 40x30: {} pixels (per processor {per_proc:?}), \
         {writes} writes compared, {} frame cycles, {} divergences ({:.1} s)",
        run.pixels.len(),
        run.frame_cycles,
        bad.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(bad.is_empty(), "{}", bad.join("\n"));
    assert_eq!(run.pixels.len(), pixels.len());
    assert!(per_proc.iter().all(|&n| n > 0), "{per_proc:?}");

    // The checkers fail.
    let (bad, _) = fast_top_differences(&scene, &faulty, &fault_pixels, PROCS, CONTEXTS, GROUP);
    let hit = bad
        .iter()
        .filter(|b| b.contains("write #1: icarus"))
        .count();
    assert_eq!(hit, fault_pixels.len(), "{}", bad.join("\n"));
    for (procs, contexts, group) in [(PROCS - 1, CONTEXTS, GROUP), (PROCS, CONTEXTS - 1, GROUP)] {
        let (bad, _) = fast_top_differences(&scene, &run, &pixels, procs, contexts, group);
        assert!(
            bad.iter().any(|b| b.contains("top rule")),
            "a top of {procs} x {contexts} in groups of {group}: {}",
            bad.join("\n")
        );
    }
}
