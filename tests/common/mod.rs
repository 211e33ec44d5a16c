//! Helpers shared by the integration tests.
// Each test crate uses its own part of this module.
#![allow(dead_code)]

pub mod icarus;

use golden::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

/// rtl/fp and rtl/pp: the include directories; and every Verilog source in
/// them and in rtl/ itself (the top module), sorted (as a reviewer would
/// read the tree).
pub fn rtl_tree() -> (Vec<PathBuf>, Vec<PathBuf>) {
    rtl_files(&["fp", "pp"], true)
}

/// The fast processor's tree so far: rtl/fast, rtl/fp (whose fp_lzc its
/// units use) and rtl/pp (the ISA and the opcode decoder its ALU uses),
/// include directories and every source, sorted.
pub fn fast_tree() -> (Vec<PathBuf>, Vec<PathBuf>) {
    rtl_files(&["fast", "fp", "pp"], false)
}

/// The whole tree, for a top of fast processors (rtl/top.v, FAST = 1).
pub fn fast_top_tree() -> (Vec<PathBuf>, Vec<PathBuf>) {
    rtl_files(&["fast", "fp", "pp"], true)
}

/// The directories `dirs` of rtl/ and their `*.v` files, with rtl/'s own
/// when `with_top`, sorted.
fn rtl_files(dirs: &[&str], with_top: bool) -> (Vec<PathBuf>, Vec<PathBuf>) {
    let rtl = Path::new(env!("CARGO_MANIFEST_DIR")).join("rtl");
    let dirs: Vec<PathBuf> = dirs.iter().map(|d| rtl.join(d)).collect();
    let verilog_in = |dir: &Path| -> Vec<PathBuf> {
        std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
            .map(|e| e.expect("listing rtl/").path())
            .filter(|p| p.extension().is_some_and(|x| x == "v"))
            .collect()
    };
    let mut files: Vec<PathBuf> = dirs.iter().flat_map(|d| verilog_in(d)).collect();
    if with_top {
        // The top module, rtl/top.v, beside the directories.
        files.extend(verilog_in(&rtl));
    }
    files.sort();
    (dirs, files)
}

/// Co-simulates `window` of `scene` on the compact processor alone, with
/// the scene's methods.
pub fn run_compact(
    scene: &Scene,
    window: golden::window::Window,
    options: &rtcosim::check::cosim::CosimOptions,
) -> Result<rtcosim::check::cosim::CosimReport, rtcosim::check::cosim::CosimError> {
    let design = rtcosim::design::Design::for_scene(
        rtcosim::design::processor::ProcessorKind::Compact,
        scene,
    );
    rtcosim::check::cosim::run(&design, scene, window, options, &|_| {})
}

/// A builtin scene at `width` x `height`.
pub fn builtin(name: &str, width: u32, height: u32) -> Scene {
    Scene::builtin(name)
        .unwrap_or_else(|| panic!("builtin scene {name}"))
        .resized(width, height, name)
        .expect("a smaller image of a valid scene is valid")
}

/// The pixels of a window, row by row.
pub fn window(x: u32, y: u32, width: u32, height: u32) -> Vec<(u32, u32)> {
    golden::window::Window {
        x,
        y,
        width,
        height,
    }
    .iter()
    .collect()
}

/// A builtin scene at the reduced size the RTL tests run it at (whole
/// frames in seconds, every silhouette, shadow edge and horizon in):
/// grazing at 96x72, light_touch at 64x48, box_room (about 1,400 cycles a
/// pixel) at 40x30, the others at 80x60.
pub fn reduced(name: &str) -> Scene {
    let (w, h) = match name {
        "grazing" => (96, 72),
        "light_touch" => (64, 48),
        "box_room" => (40, 30),
        _ => (80, 60),
    };
    builtin(name, w, h)
}

/// The weight cutoff of [`mirror_with_cutoff`]: every object of the mirror
/// scene reflects 0.8, so the child weights are 0.8, 0.64, 0.512, 0.4096
/// (f32 products); 0.6 refuses the last two, the rays of stack levels 3
/// and 4. (0.45, refusing level 4 alone, costs more cycles than it saves
/// at 80x60: few rays get that deep, and every push pays two checks.)
pub const MIRROR_CUTOFF: f32 = 0.6;

/// The mirror scene (reduced) with the weight cutoff [`MIRROR_CUTOFF`].
pub fn mirror_with_cutoff() -> Scene {
    let base = reduced("mirror");
    let render = golden::scene::RenderSettings {
        weight_cutoff: MIRROR_CUTOFF,
        ..base.render
    };
    base.with_render(render, "mirror with a cutoff")
        .expect("a cutoff in [0, 1] is valid")
}

/// Is `program` here (`program version_arg` succeeds)? If not, the test
/// fails when the environment variable `require` is 1 (CI sets it), and
/// otherwise says loudly that it did not run: install Debian's `package`.
pub fn tool_present(
    test: &str,
    program: &str,
    version_arg: &str,
    require: &str,
    package: &str,
) -> bool {
    let found = Command::new(program)
        .arg(version_arg)
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return true;
    }
    let required = std::env::var(require).is_ok_and(|v| v == "1");
    assert!(
        !required,
        "{test}: {program} is not on PATH and {require}=1 (apt-get install {package})"
    );
    // Straight to stderr: the test harness captures eprintln! of a test
    // that passes, and this line must be seen.
    use std::io::Write as _;
    let _ = writeln!(
        std::io::stderr(),
        "\n!!!! {test} DID NOT RUN: {program} is not on PATH (apt-get install {package}). !!!!\n"
    );
    false
}

/// Runs a tool that must succeed without a word on stderr (a compiler or a
/// linter: a warning fails too); `what` names the run in the failure.
pub fn run_silent(cmd: &mut Command, what: &str) {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot run {:?}: {e}", cmd.get_program()));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && stderr.trim().is_empty(),
        "{what}:\n{stderr}"
    );
}

/// Runs a binary of this package (`CARGO_BIN_EXE_<name>`) with `args`.
pub fn run_bin(bin: &str, args: &[&str]) -> std::process::Output {
    Command::new(bin)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("running {bin}: {e}"))
}

/// Runs the built `rtcosim` binary with `args`.
pub fn rtcosim(args: &[&str]) -> std::process::Output {
    run_bin(env!("CARGO_BIN_EXE_rtcosim"), args)
}

/// Output bytes as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A path as a command-line argument.
pub fn arg(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// A run's status, stdout and stderr, for a failure message.
pub fn both(out: &std::process::Output) -> String {
    format!(
        "status {:?}\n--- stdout\n{}--- stderr\n{}",
        out.status.code(),
        text(&out.stdout),
        text(&out.stderr)
    )
}

/// A fresh, empty scratch directory `<crate>-<test>` under the target's
/// temporary directory.
pub fn scratch(krate: &str, test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{krate}-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creating the scratch directory");
    dir
}

/// Runs `rtcosim` with `args` and checks that it refuses them as a bad
/// request: exit status 2, every one of `messages` on stderr, no panic, and
/// nothing on stdout (refused before any work).
pub fn assert_refused(args: &[&str], messages: &[&str]) {
    let out = rtcosim(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {}", both(&out));
    let stderr = text(&out.stderr);
    for m in messages {
        assert!(stderr.contains(m), "{args:?}: {m:?} in\n{stderr}");
    }
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert!(out.stdout.is_empty(), "{args:?}: {}", both(&out));
}

/// The text after `key` in `out` up to the next `,`, `)` or line end.
pub fn field<'a>(out: &'a str, key: &str) -> &'a str {
    let at = out
        .find(key)
        .unwrap_or_else(|| panic!("no {key:?} in\n{out}"))
        + key.len();
    let rest = &out[at..];
    rest[..rest.find([',', ')', '\n']).unwrap_or(rest.len())].trim()
}

/// The configuration `rtcosim tune` picked, as its RTL build line and
/// scene settings print it, on `scene`'s other settings.
pub fn tune_pick(stdout: &str, scene: &Scene) -> golden::scene::RenderSettings {
    use golden::fp::Method;
    let method = |m: &str| match m {
        "`FP_METHOD_EXACT" => Method::Exact,
        "`FP_METHOD_FAST" => Method::Fast,
        other => panic!("method {other:?}\n{stdout}"),
    };
    golden::scene::RenderSettings {
        max_depth: field(stdout, "max_depth = ").parse().expect("a depth"),
        recip: method(field(stdout, ".RECIP_METHOD(")),
        sqrt: method(field(stdout, ".SQRT_METHOD(")),
        weight_cutoff: field(stdout, "weight_cutoff = ").parse().expect("a cutoff"),
        ..scene.render
    }
}

/// The processor of `rtcosim tune`'s pick, by its RTL build line's module.
pub fn tune_processor(stdout: &str) -> rtcosim::design::processor::ProcessorKind {
    use rtcosim::design::processor::ProcessorKind;
    match field(stdout, "RTL build: ").split(' ').next() {
        Some("pixel_processor") => ProcessorKind::Compact,
        Some("fast_pp") => ProcessorKind::Fast,
        other => panic!("module {other:?}\n{stdout}"),
    }
}

/// `rtcosim tune` on the mirror scene at 4x3 for a largest error of 30,
/// on the compact processor (a frame in a fraction of a second).
pub const TUNE_MIRROR_4X3: [&str; 9] = [
    "tune",
    "--scene",
    "mirror",
    "--size",
    "4x3",
    "--max-error",
    "30",
    "--processor",
    "compact",
];

/// The builtin mirror scene at `w` x `h` (it meets all three speed-ups'
/// preconditions).
pub fn mirror(w: u32, h: u32) -> Scene {
    Scene::builtin("mirror")
        .expect("builtin")
        .resized(w, h, "test")
        .expect("valid")
}
