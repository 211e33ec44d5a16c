//! The pixel processor under a second simulator: Icarus Verilog (`iverilog
//! -g2005`, `vvp`) runs rtl/ with the testbench tests/icarus/pp_tb.v, loaded
//! through the scene port with golden's scene writes and configuration word
//! (as harness/pixel_proc.rs loads the verilated model), and every pixel's
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

use common::reduced;
use golden::fp::Method;
use golden::micro::loader::{self, Config};
use golden::micro::Processor;
use golden::scene::Scene;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

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

/// Is `iverilog` here? If not, fails under RTCOSIM_REQUIRE_ICARUS=1, else
/// says loudly that the test did not run.
fn icarus_present(test: &str) -> bool {
    let found = Command::new("iverilog")
        .arg("-V")
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return true;
    }
    let required = std::env::var("RTCOSIM_REQUIRE_ICARUS").is_ok_and(|v| v == "1");
    assert!(
        !required,
        "{test}: iverilog is not on PATH and RTCOSIM_REQUIRE_ICARUS=1 (apt-get install iverilog)"
    );
    // Straight to stderr: the test harness captures eprintln! of a test
    // that passes, and this line must be seen.
    let _ = writeln!(
        std::io::stderr(),
        "\n!!!! {test} DID NOT RUN: iverilog is not on PATH. Install Icarus Verilog \
         (apt-get install iverilog) to run the RTL under a second simulator. !!!!\n"
    );
    false
}

/// One pixel as Icarus computed it.
#[derive(Debug, Clone, PartialEq, Eq)]
struct SimPixel {
    x: u32,
    y: u32,
    /// `rgb` lanes r, g, b as Icarus printed them: 8 hex digits, or with
    /// x/z digits where the value is unknown.
    rgb: [String; 3],
    cycles: u64,
}

/// A work directory for one test under cargo's temporary directory.
fn work_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("icarus")
        .join(name);
    // A previous run's files are overwritten, never read.
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// Compiles rtl/ and the testbench `tb` (tests/icarus/<tb>.v) for the
/// scene's float methods and the testbench parameters `params`.
fn compile(dir: &Path, tb: &str, recip: Method, sqrt: Method, params: &[(&str, u32)]) -> PathBuf {
    let (includes, mut sources) = common::rtl_tree();
    sources.push(Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/icarus/{tb}.v")));
    let vvp = dir.join(format!("{tb}_{recip}_{sqrt}.vvp"));
    let params = [("RECIP_METHOD", recip.code()), ("SQRT_METHOD", sqrt.code())]
        .into_iter()
        .chain(params.iter().copied());
    common::run_silent(
        Command::new("iverilog")
            .args(["-g2005", "-Wall", "-s", tb, "-o"])
            .arg(&vvp)
            .args(includes.iter().map(|d| format!("-I{}", d.display())))
            .arg(format!("-I{}/tests/icarus", env!("CARGO_MANIFEST_DIR")))
            .args(params.map(|(name, value)| format!("-P{tb}.{name}={value}")))
            .args(&sources),
        "iverilog",
    );
    vvp
}

/// The scene-port writes of `scene` for the testbench: every scene register
/// (`loader::scene_writes`), then the configuration word, as the verilated
/// model is loaded.
fn scene_hex(scene: &Scene) -> (String, usize) {
    let mut writes: Vec<(bool, u8, [u32; 3])> = loader::scene_writes(scene)
        .into_iter()
        .map(|(addr, v)| (false, addr, v))
        .collect();
    writes.push((true, 0, Config::new(scene).word()));
    let mut text = String::new();
    for (cfg, addr, [x, y, z]) in &writes {
        writeln!(
            text,
            "{:02x}{addr:02x}{z:08x}{y:08x}{x:08x}",
            u8::from(*cfg)
        )
        .expect("string");
    }
    (text, writes.len())
}

/// Writes `scene`'s scene-port writes into `dir`/scene.hex.
fn write_scene_hex(dir: &Path, scene: &Scene) -> PathBuf {
    let scene_file = dir.join("scene.hex");
    std::fs::write(&scene_file, scene_hex(scene).0).expect("writing the scene");
    scene_file
}

/// Writes `pixels` for `$readmemh` into `file`.
fn write_pixel_hex(file: &Path, pixels: &[(u32, u32)]) {
    let mut list = String::new();
    for (x, y) in pixels {
        writeln!(list, "{x:04x}{y:04x}").expect("string");
    }
    std::fs::write(file, list).expect("writing the pixels");
}

/// The `PIX` lines of a testbench's output: x, y, the rgb lanes, the cycles
/// and the fields after them (the top's processor).
fn pix_lines(stdout: &str) -> Vec<(SimPixel, Vec<u64>)> {
    stdout
        .lines()
        .filter_map(|l| l.strip_prefix("PIX "))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let dec = |s: &str| s.parse::<u64>().unwrap_or_else(|e| panic!("{l:?}: {e}"));
            assert!(f.len() >= 6, "{l:?}");
            let pixel = SimPixel {
                x: dec(f[0]) as u32,
                y: dec(f[1]) as u32,
                rgb: [f[2], f[3], f[4]].map(str::to_string),
                cycles: dec(f[5]),
            };
            (pixel, f[6..].iter().map(|s| dec(s)).collect())
        })
        .collect()
}

/// Runs `pixels` of `scene` under Icarus, split over one `vvp` per core.
fn simulate(name: &str, scene: &Scene, pixels: &[(u32, u32)]) -> Vec<SimPixel> {
    let dir = work_dir(name);
    let vvp = compile(&dir, "pp_tb", scene.render.recip, scene.render.sqrt, &[]);
    let scene_file = write_scene_hex(&dir, scene);
    let n_writes = scene_hex(scene).1;
    let shards = std::thread::available_parallelism().map_or(1, |n| n.get());
    let per_shard = pixels.len().div_ceil(shards).max(1);
    std::thread::scope(|s| {
        let threads: Vec<_> = pixels
            .chunks(per_shard)
            .enumerate()
            .map(|(i, chunk)| {
                let (vvp, scene_file, dir) = (&vvp, &scene_file, &dir);
                s.spawn(move || {
                    run_vvp(
                        vvp,
                        scene_file,
                        n_writes,
                        &dir.join(format!("pixels{i}.hex")),
                        chunk,
                    )
                })
            })
            .collect();
        threads
            .into_iter()
            .flat_map(|t| t.join().expect("a vvp shard panicked"))
            .collect()
    })
}

/// One `vvp` run: the scene writes, then `pixels` in order.
fn run_vvp(
    vvp: &Path,
    scene_file: &Path,
    n_writes: usize,
    pixel_file: &Path,
    pixels: &[(u32, u32)],
) -> Vec<SimPixel> {
    let stdout = vvp_pixels(vvp, scene_file, n_writes, pixel_file, pixels, &[]);
    let got: Vec<SimPixel> = pix_lines(&stdout).into_iter().map(|(p, _)| p).collect();
    let back: Vec<(u32, u32)> = got.iter().map(|p| (p.x, p.y)).collect();
    assert_eq!(back, pixels, "pixels back from vvp");
    got
}

/// Runs a testbench's `vvp` on the scene writes and `pixels` (written to
/// `pixel_file`) with more plusargs `extra`; its stdout, which must end the
/// run with `END`.
fn vvp_pixels(
    vvp: &Path,
    scene_file: &Path,
    n_writes: usize,
    pixel_file: &Path,
    pixels: &[(u32, u32)],
    extra: &[&str],
) -> String {
    write_pixel_hex(pixel_file, pixels);
    let out = Command::new("vvp")
        .arg("-n")
        .arg(vvp)
        .arg(format!("+scene={}", scene_file.display()))
        .arg(format!("+writes={n_writes}"))
        .arg(format!("+pixels={}", pixel_file.display()))
        .arg(format!("+count={}", pixels.len()))
        .args(extra)
        .output()
        .expect("running vvp");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success() && stdout.lines().any(|l| l == "END"),
        "vvp did not finish:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// The pixels whose RGB bits or cycles under Icarus differ from golden's,
/// as report lines.
fn differences(scene: &Scene, got: &[SimPixel]) -> Vec<String> {
    let golden = Processor::new(scene);
    got.iter()
        .filter_map(|p| {
            let want = golden.render_pixel(p.x, p.y, |_, _| {});
            let rgb = want.rgb.map(|c| format!("{:08x}", c.to_bits()));
            (rgb != p.rgb || want.cycles != p.cycles).then(|| {
                format!(
                    "({}, {}): icarus rgb {} cycles {}, golden rgb {} cycles {}",
                    p.x,
                    p.y,
                    p.rgb.join(" "),
                    p.cycles,
                    rgb.join(" "),
                    want.cycles
                )
            })
        })
        .collect()
}

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

    let mut rtl = rtcosim::pixel_proc::PixelProcessor::new(scene.render.recip, scene.render.sqrt)
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
