//! Icarus Verilog under the tests (tests/icarus.rs, tests/mutation.rs):
//! compiling rtl/ (or a mutant netlist) with a testbench of tests/icarus/,
//! the scene and pixel files the testbenches read, running `vvp`, and
//! golden's verdict on what came back.

use golden::fp::Method;
use golden::micro::loader::{self, Config};
use golden::micro::Processor;
use golden::scene::Scene;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Is `iverilog` here? If not, fails under RTCOSIM_REQUIRE_ICARUS=1, else
/// says loudly that the test did not run.
pub fn icarus_present(test: &str) -> bool {
    super::tool_present(test, "iverilog", "-V", "RTCOSIM_REQUIRE_ICARUS", "iverilog")
}

/// One pixel as Icarus computed it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimPixel {
    pub x: u32,
    pub y: u32,
    /// `rgb` lanes r, g, b as Icarus printed them: 8 hex digits, or with
    /// x/z digits where the value is unknown.
    pub rgb: [String; 3],
    pub cycles: u64,
}

/// A work directory for one test under cargo's temporary directory.
pub fn work_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("icarus")
        .join(name);
    // A previous run's files are overwritten, never read.
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// Compiles rtl/ and the testbench `tb` (tests/icarus/<tb>.v) for the
/// scene's float methods and the testbench parameters `params`.
pub fn compile(
    dir: &Path,
    tb: &str,
    recip: Method,
    sqrt: Method,
    params: &[(&str, u32)],
) -> PathBuf {
    let (includes, sources) = super::rtl_tree();
    let params: Vec<(&str, u32)> = [("RECIP_METHOD", recip.code()), ("SQRT_METHOD", sqrt.code())]
        .into_iter()
        .chain(params.iter().copied())
        .collect();
    let vvp = dir.join(format!("{tb}_{recip}_{sqrt}.vvp"));
    iverilog(&vvp, tb, &includes, &sources, &[], &params);
    vvp
}

/// Compiles a mutant netlist of `rtl/mutate/mutants.sh netlist` (one
/// flattened module, `pixel_processor`, with `mutsel`) under pp_tb with
/// `MUTANTS` defined, beside the float units' RTL (rtl/fp/*.v) for the
/// modules the list left as black boxes: the testbench drives `mutsel` from
/// `+mutsel=N`.
pub fn compile_mutants(dir: &Path, netlist: &Path) -> PathBuf {
    let (includes, sources) = super::rtl_tree();
    let float_units = sources
        .iter()
        .filter(|p| p.starts_with(&includes[0]))
        .cloned();
    let sources: Vec<PathBuf> = std::iter::once(netlist.to_path_buf())
        .chain(float_units)
        .collect();
    let vvp = dir.join("pp_tb_mutants.vvp");
    iverilog(&vvp, "pp_tb", &includes, &sources, &["MUTANTS"], &[]);
    vvp
}

/// Compiles the fast processor's pipelined units (rtl/fast, rtl/fp) with
/// tests/icarus/fast_fp_tb.v.
pub fn compile_fast_units(dir: &Path) -> PathBuf {
    let (includes, sources) = super::fast_tree();
    let vvp = dir.join("fast_fp_tb.vvp");
    iverilog(&vvp, "fast_fp_tb", &includes, &sources, &[], &[]);
    vvp
}

/// Runs fast_fp_tb on the vectors (a, b, golden's a + b, a * b, itof(a),
/// 1 / a, sqrt(a), e^a), written to `dir`/`name`.hex: the mismatches it
/// counted per unit (add, mul, itof, recip, sqrt, exp), and its whole
/// stdout.
pub fn run_fast_units(
    vvp: &Path,
    dir: &Path,
    name: &str,
    vectors: &[[u32; 8]],
) -> ([u64; 6], String) {
    let stdout = run_vectors(vvp, dir, name, vectors);
    let summary = stdout
        .lines()
        .find_map(|l| l.strip_prefix("fast_fp_tb: "))
        .unwrap_or_else(|| panic!("no summary from fast_fp_tb:\n{stdout}"));
    let words: Vec<&str> = summary.split_whitespace().collect();
    // "N vectors, add mismatches A, mul mismatches M, itof mismatches I,
    // recip mismatches R, sqrt mismatches S, exp mismatches E"
    assert_eq!(
        words[0],
        vectors.len().to_string(),
        "vectors read: {summary}"
    );
    let count = |i: usize| -> u64 {
        words[i]
            .trim_end_matches(',')
            .parse()
            .unwrap_or_else(|_| panic!("{summary}"))
    };
    (
        [
            count(4),
            count(7),
            count(10),
            count(13),
            count(16),
            count(19),
        ],
        stdout,
    )
}

/// Compiles the fast processor's register file (rtl/fast/fast_regfile.v)
/// with tests/icarus/fast_regfile_tb.v at `STACK_DEPTH`.
pub fn compile_fast_regfile(dir: &Path, stack_depth: u32) -> PathBuf {
    let (includes, sources) = super::fast_tree();
    let vvp = dir.join(format!("fast_regfile_tb_{stack_depth}.vvp"));
    iverilog(
        &vvp,
        "fast_regfile_tb",
        &includes,
        &sources,
        &[],
        &[("STACK_DEPTH", stack_depth)],
    );
    vvp
}

/// Runs fast_regfile_tb (with `+fault=N` when `fault`): the reads it
/// checked and the mismatches it counted, and its whole stdout.
pub fn run_fast_regfile(vvp: &Path, fault: Option<u64>) -> (u64, u64, String) {
    let stdout = run_tb(vvp, fault.map(|n| format!("+fault={n}")));
    let summary: Vec<u64> = stdout
        .lines()
        .find_map(|l| l.strip_prefix("done "))
        .map(|l| {
            l.split_whitespace()
                .filter_map(|w| w.parse().ok())
                .collect()
        })
        .unwrap_or_else(|| panic!("no summary from fast_regfile_tb:\n{stdout}"));
    assert_eq!(summary.len(), 2, "{stdout}");
    (summary[0], summary[1], stdout)
}

/// Compiles the fast processor's ALU (rtl/fast/fast_alu.v, exact methods)
/// with tests/icarus/fast_alu_tb.v, with or without exposure.
pub fn compile_fast_alu(dir: &Path, exposure: bool) -> PathBuf {
    let (includes, sources) = super::fast_tree();
    let vvp = dir.join(format!("fast_alu_tb_{}.vvp", u8::from(exposure)));
    iverilog(
        &vvp,
        "fast_alu_tb",
        &includes,
        &sources,
        &[],
        &[("EXPOSURE", u32::from(exposure))],
    );
    vvp
}

/// Runs fast_alu_tb on `lines` (its vector format, 13 words a cycle),
/// written to `dir`/`name`.hex: the cycles it read, the mismatches it
/// counted, and its whole stdout.
pub fn run_fast_alu(vvp: &Path, dir: &Path, name: &str, lines: &[[u32; 13]]) -> (u64, u64, String) {
    let stdout = run_vectors(vvp, dir, name, lines);
    let counts: Vec<u64> = stdout
        .lines()
        .find_map(|l| l.strip_prefix("fast_alu_tb: "))
        .map(|l| {
            l.split_whitespace()
                .filter_map(|w| w.trim_end_matches(',').parse().ok())
                .collect()
        })
        .unwrap_or_else(|| panic!("no summary from fast_alu_tb:\n{stdout}"));
    assert_eq!(counts.len(), 2, "{stdout}");
    (counts[0], counts[1], stdout)
}

/// Writes `rows` (32-bit words, hex, a row a line) to `dir`/`name`.hex and
/// runs `vvp` on it (`+vectors=`): its stdout.
fn run_vectors<const N: usize>(vvp: &Path, dir: &Path, name: &str, rows: &[[u32; N]]) -> String {
    let file = dir.join(format!("{name}.hex"));
    let mut text = String::new();
    for row in rows {
        for w in row {
            write!(text, "{w:08x}").expect("string");
        }
        text.push('\n');
    }
    std::fs::write(&file, text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    run_tb(vvp, Some(format!("+vectors={}", file.display())))
}

/// Runs a compiled testbench with the plusargs `args`: its stdout, which
/// must come with success.
fn run_tb(vvp: &Path, args: impl IntoIterator<Item = String>) -> String {
    let out = Command::new("vvp")
        .arg("-n")
        .arg(vvp)
        .args(args)
        .output()
        .expect("running vvp");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "vvp failed:\n{stdout}");
    stdout
}

/// `iverilog -g2005 -Wall` of `sources` and tests/icarus/<tb>.v into `vvp`.
fn iverilog(
    vvp: &Path,
    tb: &str,
    includes: &[PathBuf],
    sources: &[PathBuf],
    defines: &[&str],
    params: &[(&str, u32)],
) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    super::run_silent(
        Command::new("iverilog")
            .args(["-g2005", "-Wall", "-s", tb, "-o"])
            .arg(vvp)
            .args(includes.iter().map(|d| format!("-I{}", d.display())))
            .arg(format!("-I{}/tests/icarus", root.display()))
            .args(defines.iter().map(|d| format!("-D{d}")))
            .args(
                params
                    .iter()
                    .map(|(name, value)| format!("-P{tb}.{name}={value}")),
            )
            .args(sources)
            .arg(root.join(format!("tests/icarus/{tb}.v"))),
        "iverilog",
    );
}

/// The scene-port writes of `scene` for the testbench: every scene register
/// (`loader::scene_writes`), then the configuration word, as the verilated
/// model is loaded.
pub fn scene_hex(scene: &Scene) -> (String, usize) {
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
pub fn write_scene_hex(dir: &Path, scene: &Scene) -> PathBuf {
    let scene_file = dir.join("scene.hex");
    std::fs::write(&scene_file, scene_hex(scene).0).expect("writing the scene");
    scene_file
}

/// Writes `pixels` for `$readmemh` into `file`.
pub fn write_pixel_hex(file: &Path, pixels: &[(u32, u32)]) {
    let mut list = String::new();
    for (x, y) in pixels {
        writeln!(list, "{x:04x}{y:04x}").expect("string");
    }
    std::fs::write(file, list).expect("writing the pixels");
}

/// The `PIX` lines of a testbench's output: x, y, the rgb lanes, the cycles
/// and the fields after them (the top's processor).
pub fn pix_lines(stdout: &str) -> Vec<(SimPixel, Vec<u64>)> {
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
pub fn simulate(name: &str, scene: &Scene, pixels: &[(u32, u32)]) -> Vec<SimPixel> {
    simulate_with(name, scene, pixels, &[])
}

/// [`simulate`] with the processor's parameters `params` (pp_tb passes
/// `STACK_DEPTH` and `REFRACTION` on).
pub fn simulate_with(
    name: &str,
    scene: &Scene,
    pixels: &[(u32, u32)],
    params: &[(&str, u32)],
) -> Vec<SimPixel> {
    let dir = work_dir(name);
    let vvp = compile(&dir, "pp_tb", scene.render.recip, scene.render.sqrt, params);
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
pub fn run_vvp(
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
pub fn vvp_pixels(
    vvp: &Path,
    scene_file: &Path,
    n_writes: usize,
    pixel_file: &Path,
    pixels: &[(u32, u32)],
    extra: &[&str],
) -> String {
    let stdout = vvp_run(vvp, scene_file, n_writes, pixel_file, pixels, extra);
    assert!(
        stdout.lines().any(|l| l == "END"),
        "vvp did not finish:\n{stdout}"
    );
    stdout
}

/// [`vvp_pixels`] that also accepts a run the testbench stopped at a hung
/// pixel (`HUNG x y cycles`, no `END`): a mutant may hang.
pub fn vvp_run(
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
        out.status.success() && stdout.lines().any(|l| l == "END" || l.starts_with("HUNG ")),
        "vvp did not finish:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// The pixels whose RGB bits or cycles under Icarus differ from golden's,
/// as report lines.
pub fn differences(scene: &Scene, got: &[SimPixel]) -> Vec<String> {
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

/// Compiles the fast pixel processor (rtl/fast/fast_pp.v, with the
/// exponential and its trace port: `PP_TRACE`) with
/// tests/icarus/fast_pp_tb.v for the scene's float methods, with or
/// without refraction (`REFRACTION`).
pub fn compile_fast_pp(dir: &Path, recip: Method, sqrt: Method, refraction: bool) -> PathBuf {
    let (includes, sources) = super::fast_tree();
    let vvp = dir.join(format!("fast_pp_tb_{recip}_{sqrt}.vvp"));
    iverilog(
        &vvp,
        "fast_pp_tb",
        &includes,
        &sources,
        &["PP_TRACE"],
        &[
            ("RECIP_METHOD", recip.code()),
            ("SQRT_METHOD", sqrt.code()),
            ("REFRACTION", u32::from(refraction)),
        ],
    );
    vvp
}

/// fast_top_tb (a top of `procs` fast processors, `group` a result group)
/// compiled for these methods, in `dir`.
pub fn compile_fast_top(
    dir: &Path,
    procs: u32,
    group: u32,
    recip: Method,
    sqrt: Method,
) -> PathBuf {
    let (includes, sources) = super::fast_top_tree();
    let vvp = dir.join(format!("fast_top_tb_{procs}_{group}_{recip}_{sqrt}.vvp"));
    iverilog(
        &vvp,
        "fast_top_tb",
        &includes,
        &sources,
        &["PP_TRACE"],
        &[
            ("N", procs),
            ("ARB_GROUP", group),
            ("RECIP_METHOD", recip.code()),
            ("SQRT_METHOD", sqrt.code()),
        ],
    );
    vvp
}

/// One pixel as the fast processor gave it under Icarus.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FastPixel {
    pub x: u32,
    pub y: u32,
    /// The context that computed it.
    pub ctx: u32,
    /// As [`SimPixel::rgb`].
    pub rgb: [String; 3],
    pub cycles: u64,
    /// Its register-file writes in order, as fast_pp_tb printed them:
    /// `state dst lanes vx vy vz` (decimal, then hex; x/z where unknown).
    pub writes: Vec<String>,
}

/// A frame of the fast processor under Icarus.
#[derive(Debug, Clone, Default)]
pub struct FastRun {
    /// In the order the takes came.
    pub taken: Vec<(u32, u32)>,
    /// In the order the results left.
    pub pixels: Vec<FastPixel>,
    /// top.cpp's frame_cycles: from the cycle that took the first
    /// coordinate to the one that gave the last result, both counted.
    pub frame_cycles: u64,
    /// The turn's context in the cycle that took the first coordinate
    /// (fast_top_tb's PHASE line; None from fast_pp_tb).
    pub phase: Option<u32>,
    /// Trace lines that break the port's contract (a write tagged with a
    /// pixel other than its context's, a result of a context with no such
    /// pixel), as report lines.
    pub protocol: Vec<String>,
}

/// Runs fast_pp_tb (`vvp`) on `scene` and `pixels` (written to `dir`),
/// with the fault port at `fault` (state, xor) if any: every take, write
/// and result it printed, each write given to its context's pixel.
pub fn run_fast_pp(
    vvp: &Path,
    dir: &Path,
    scene: &Scene,
    pixels: &[(u32, u32)],
    fault: Option<(u16, u32)>,
) -> FastRun {
    let scene_file = write_scene_hex(dir, scene);
    let extra: Vec<String> = fault
        .map(|(state, xor)| {
            vec![
                format!("+fault_state={state}"),
                format!("+fault_xor={xor:x}"),
            ]
        })
        .unwrap_or_default();
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let stdout = vvp_pixels(
        vvp,
        &scene_file,
        scene_hex(scene).1,
        &dir.join("pixels.hex"),
        pixels,
        &extra,
    );
    parse_fast_pp(&stdout)
}

/// fast_pp_tb's output as a [`FastRun`].
fn parse_fast_pp(stdout: &str) -> FastRun {
    /// A pixel taken: coordinates, context, writes, and whether its result
    /// has left.
    struct Taken {
        at: (u32, u32),
        ctx: u32,
        writes: Vec<String>,
        out: bool,
    }
    let mut run = FastRun::default();
    let mut taken: Vec<Taken> = Vec::new();
    // Per context, the take of its current pixel.
    let mut current: std::collections::HashMap<u32, usize> = Default::default();
    let mut frame = None;
    for line in stdout.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let dec = |s: &str| -> u32 { s.parse().unwrap_or_else(|e| panic!("{line:?}: {e}")) };
        match f.first().copied() {
            Some("TAKE") => {
                assert_eq!(f.len(), 4, "{line:?}");
                let (ctx, at) = (dec(f[1]), (dec(f[2]), dec(f[3])));
                current.insert(ctx, taken.len());
                taken.push(Taken {
                    at,
                    ctx,
                    writes: Vec::new(),
                    out: false,
                });
                run.taken.push(at);
            }
            Some("EV") => {
                assert_eq!(f.len(), 10, "{line:?}");
                let (ctx, at) = (dec(f[1]), (dec(f[2]), dec(f[3])));
                match current.get(&ctx).map(|&i| &mut taken[i]) {
                    Some(t) if t.at == at && !t.out => t.writes.push(f[4..].join(" ")),
                    _ => run.protocol.push(format!(
                        "a write of context {ctx} tagged {at:?}, not its current pixel: {line:?}"
                    )),
                }
            }
            Some("PIX") => {
                assert_eq!(f.len(), 8, "{line:?}");
                let (at, ctx) = ((dec(f[1]), dec(f[2])), dec(f[7]));
                // A context's results leave in the order it took its pixels.
                let Some(t) = taken.iter_mut().find(|t| t.ctx == ctx && !t.out) else {
                    run.protocol.push(format!(
                        "a result of context {ctx}, which has no pixel: {line:?}"
                    ));
                    continue;
                };
                t.out = true;
                if t.at != at {
                    run.protocol.push(format!(
                        "context {ctx}'s result is tagged {at:?}, its pixel is {:?}",
                        t.at
                    ));
                }
                run.pixels.push(FastPixel {
                    x: at.0,
                    y: at.1,
                    ctx,
                    rgb: [f[3], f[4], f[5]].map(str::to_string),
                    cycles: u64::from(dec(f[6])),
                    writes: std::mem::take(&mut t.writes),
                });
            }
            Some("FRAME") => frame = f.get(1).map(|s| dec(s)),
            Some("PHASE") => run.phase = f.get(1).map(|s| dec(s)),
            _ => {}
        }
    }
    run.frame_cycles = u64::from(frame.unwrap_or_else(|| panic!("no FRAME line:\n{stdout}")));
    run
}

/// Cycles a frame of the fast processor takes beyond the barrel rule's
/// (fast_pp.v: one into the coordinate queue, two of the register file's
/// read, one into the result queue).
pub const FAST_FRAME_OVERHEAD: u64 = 4;

/// Where the pixels of a frame of fast processors under Icarus differ from
/// golden, for `pixels` fed (each once): each pixel's writes in order
/// (state, destination, lanes, values) and colour bits against
/// `golden::micro`'s, and the trace port's contract. The report lines, the
/// number of writes compared, and each pixel's work for a cycle rule.
fn fast_pixel_differences(
    scene: &Scene,
    run: &FastRun,
    pixels: &[(u32, u32)],
) -> (Vec<String>, usize, Vec<golden::micro::barrel::PixelWork>) {
    use golden::micro::barrel::PixelWork;
    use golden::micro::isa::state_label;
    let golden = Processor::new(scene);
    let mut bad = run.protocol.clone();
    let mut back: Vec<(u32, u32)> = run.pixels.iter().map(|p| (p.x, p.y)).collect();
    back.sort_unstable();
    let mut want: Vec<(u32, u32)> = pixels.to_vec();
    want.sort_unstable();
    if back != want {
        bad.push(format!(
            "{} results for {} pixels fed: not each pixel once",
            back.len(),
            want.len()
        ));
    }
    let mut compared = 0;
    let mut work = Vec::new();
    for &(x, y) in pixels {
        let mut events = Vec::new();
        let result = golden.render_pixel(x, y, |e, _| events.push(*e));
        work.push(PixelWork::of(&result));
        let Some(p) = run.pixels.iter().find(|p| (p.x, p.y) == (x, y)) else {
            continue;
        };
        let expected: Vec<String> = events
            .iter()
            .map(|e| {
                let [a, b, c] = e.values;
                format!("{} {} {} {a:08x} {b:08x} {c:08x}", e.state, e.dst, e.lanes)
            })
            .collect();
        let common = p.writes.len().min(expected.len());
        let first_bad = (0..common).find(|&i| p.writes[i] != expected[i]);
        compared += first_bad.map_or(common, |i| i + 1);
        if let Some(i) = first_bad {
            bad.push(format!(
                "({x}, {y}): write #{i}: icarus {}, golden {} ({})",
                p.writes[i],
                expected[i],
                state_label(events[i].state)
            ));
        } else if p.writes.len() != expected.len() {
            bad.push(format!(
                "({x}, {y}): {} writes, golden {}",
                p.writes.len(),
                expected.len()
            ));
        }
        let rgb = result.rgb.map(|c| format!("{:08x}", c.to_bits()));
        if rgb != p.rgb {
            bad.push(format!(
                "({x}, {y}): colour icarus {}, golden {}",
                p.rgb.join(" "),
                rgb.join(" ")
            ));
        }
    }
    (bad, compared, work)
}

/// Where a frame of the fast processor under Icarus differs from golden,
/// for `pixels` fed in that order (each once) and a barrel of `contexts`:
/// the takes' order, each pixel's writes and colour
/// ([`fast_pixel_differences`]), and each pixel's context and cycles and
/// the frame's cycles against the barrel rule's. The report lines, and the
/// number of writes compared.
pub fn fast_differences(
    scene: &Scene,
    run: &FastRun,
    pixels: &[(u32, u32)],
    contexts: u32,
) -> (Vec<String>, usize) {
    use golden::micro::barrel;
    let (mut bad, compared, work) = fast_pixel_differences(scene, run, pixels);
    if run.taken != pixels {
        bad.push(format!(
            "takes {:?}, fed {pixels:?}",
            &run.taken[..run.taken.len().min(8)]
        ));
    }
    // The barrel rule for the pixels in the order they were fed; contexts
    // numbered from the one that took the first pixel.
    let barrel = barrel::run(contexts, &work);
    let first = run
        .pixels
        .iter()
        .find(|p| (p.x, p.y) == pixels[0])
        .map_or(0, |p| p.ctx);
    let k = 1 << 5; // fast_pp's CTX_BITS
    for p in &run.pixels {
        let Some(i) = pixels.iter().position(|&c| c == (p.x, p.y)) else {
            continue;
        };
        let w = barrel.pixels[i];
        let context = (p.ctx + k - first) % k;
        if (p.cycles, context) != (w.cycles(), w.context) {
            bad.push(format!(
                "({}, {}): context {context}, {} cycles; barrel: context {}, {} cycles",
                p.x,
                p.y,
                p.cycles,
                w.context,
                w.cycles()
            ));
        }
    }
    if run.frame_cycles != barrel.cycles + FAST_FRAME_OVERHEAD {
        bad.push(format!(
            "the frame took {} cycles; barrel {} + {FAST_FRAME_OVERHEAD}",
            run.frame_cycles, barrel.cycles
        ));
    }
    (bad, compared)
}

/// [`fast_differences`] for a top of `procs` fast processors of `contexts`
/// contexts each, `group` a result group (fast_top_tb, a context named
/// proc * 32 + ctx): each
/// pixel's writes and colour, and its processor, context and cycles and
/// the frame's cycles against the top's rule (`golden::micro::barrel::
/// run_top`, from the phase the run printed and the arbiter as reset left
/// it).
pub fn fast_top_differences(
    scene: &Scene,
    run: &FastRun,
    pixels: &[(u32, u32)],
    procs: u32,
    contexts: u32,
    group: u32,
) -> (Vec<String>, usize) {
    use golden::micro::barrel::{self, TopStart};
    let (mut bad, compared, work) = fast_pixel_differences(scene, run, pixels);
    let k = 1 << 5; // fast_pp's CTX_BITS, as fast_top_tb names contexts
    let start = TopStart {
        procs,
        contexts,
        phase: run.phase.expect("a PHASE line") % contexts,
        group,
        last_grant: 0,
    };
    let top = barrel::run_top(start, &work, &|_| true);
    for p in &run.pixels {
        let Some(i) = pixels.iter().position(|&c| c == (p.x, p.y)) else {
            continue;
        };
        let w = top.pixels[i];
        let got = (p.ctx / k, p.ctx % k, p.cycles);
        let want = (w.proc, w.run.context, w.run.cycles());
        if got != want {
            bad.push(format!(
                "({}, {}): processor {}, context {}, {} cycles; top rule: processor {}, context {}, {} cycles",
                p.x, p.y, got.0, got.1, got.2, want.0, want.1, want.2
            ));
        }
    }
    if run.frame_cycles != top.frame_cycles {
        bad.push(format!(
            "the frame took {} cycles; the top rule {}",
            run.frame_cycles, top.frame_cycles
        ));
    }
    (bad, compared)
}
