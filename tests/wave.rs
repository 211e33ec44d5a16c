//! The waveform window (`rtcosim::output::wave`, `rtcosim cosim --wave K`): a fault
//! injected through the fault port makes the RTL diverge; the window of the
//! first divergent pixel is read back with an independent FST reader
//! (`fst-reader`) and checked against what the co-simulation reported and
//! against the FST's own signals, not against numbers the wave module
//! computes. The command line (`--wave`, `--wave-out`) is run as the built
//! binary and its window held to golden's own trace of the pixel.

mod common;

use common::{arg, assert_refused, both, rtcosim, text};
use fst_reader::{FstFilter, FstHierarchyEntry, FstReader, FstSignalValue};
use golden::micro::isa;
use golden::scene::Scene;
use golden::window::Window;
use rtcosim::check::compare::Divergence;
use rtcosim::check::cosim::{self, CosimOptions};
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::top::Stall;
use rtcosim::design::Design;
use rtcosim::design::Fault;
use rtcosim::output::wave::{self, Replay, WaveError};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The builtin reference scene at 40x30.
/// The re-run of a compact processor's pixel: one pixel from reset.
fn compact_replay(scene: &Scene) -> Replay {
    Replay::pixel(&Design::for_scene(ProcessorKind::Compact, scene), 0, 0)
}

fn small_reference() -> Scene {
    Scene::builtin("reference")
        .expect("builtin reference")
        .resized(40, 30, "reference")
        .expect("a smaller image of a valid scene is valid")
}

/// A fresh directory of this test's own under cargo's scratch directory.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("wave-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// The co-simulation's first divergence with `fault` injected.
fn first_divergence(scene: &Scene, fault: Fault) -> Divergence {
    let options = CosimOptions {
        fault: Some(fault),
        ..CosimOptions::default()
    };
    let report = common::run_compact(scene, Window::full(scene), &options)
        .unwrap_or_else(|e| panic!("co-simulation failed: {e}"));
    report
        .compare
        .first_divergence
        .unwrap_or_else(|| panic!("the fault did not diverge:\n{report}"))
}

/// The scene, a fault in the pixel's second instruction (PRI_HALF), and the
/// first divergence it makes.
fn pri_half() -> (Scene, Fault, Divergence) {
    let scene = small_reference();
    let fault: Fault = "PRI_HALF:0x400".parse().expect("a fault");
    let d = first_divergence(&scene, fault);
    (scene, fault, d)
}

/// An FST file read back: its time range, its signals by full name
/// (`TOP.pixel_processor.u_ctrl.st_q[8:0]`, as GTKWave names them) with
/// their widths, and every value change.
struct Fst {
    /// The scope `signal` looks in: `TOP.pixel_processor` or `TOP.fast_pp`.
    scope: &'static str,
    start: u64,
    end: u64,
    timescale_exponent: i8,
    /// Name to (handle index, width).
    signals: HashMap<String, (usize, u32)>,
    changes: HashMap<usize, Vec<(u64, String)>>,
}

impl Fst {
    fn read(path: &Path) -> Fst {
        let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut reader = FstReader::open(std::io::BufReader::new(file))
            .unwrap_or_else(|e| panic!("{} is not a well-formed FST file: {e:?}", path.display()));
        let header = reader.get_header();
        let mut scopes: Vec<String> = Vec::new();
        let mut signals = HashMap::new();
        reader
            .read_hierarchy(|entry| match entry {
                FstHierarchyEntry::Scope { name, .. } => scopes.push(name),
                FstHierarchyEntry::UpScope => {
                    scopes.pop();
                }
                FstHierarchyEntry::Var {
                    name,
                    length,
                    handle,
                    ..
                } => {
                    // Verilator names a vector `st_q [8:0]`; GTKWave shows `st_q[8:0]`.
                    let name = name.replace(' ', "");
                    let full = format!("{}.{name}", scopes.join("."));
                    signals.insert(full, (handle.get_index(), length));
                }
                _ => {}
            })
            .expect("FST hierarchy");
        let mut changes: HashMap<usize, Vec<(u64, String)>> = HashMap::new();
        reader
            .read_signals(&FstFilter::all(), |time, handle, value| {
                if let FstSignalValue::String(bits) = value {
                    changes
                        .entry(handle.get_index())
                        .or_default()
                        .push((time, String::from_utf8_lossy(bits).into_owned()));
                }
                Ok::<(), ()>(())
            })
            .expect("FST value changes");
        Fst {
            scope: "TOP.pixel_processor",
            start: header.start_time,
            end: header.end_time,
            timescale_exponent: header.timescale_exponent,
            signals,
            changes,
        }
    }

    /// The same file, its signals looked up under the fast processor's scope.
    fn of_fast(self) -> Fst {
        Fst {
            scope: "TOP.fast_pp",
            ..self
        }
    }

    /// The signal named `name` (without its range) under the scope.
    fn signal(&self, name: &str) -> (usize, u32) {
        let prefix = format!("{}.{name}", self.scope);
        let found: Vec<_> = self
            .signals
            .iter()
            .filter(|(full, _)| {
                full.strip_prefix(&prefix)
                    .is_some_and(|rest| rest.is_empty() || rest.starts_with('['))
            })
            .collect();
        assert_eq!(found.len(), 1, "signal {prefix} in the FST: {found:?}");
        *found[0].1
    }

    /// The value of `name` at `time`, as a number.
    fn value_at(&self, name: &str, time: u64) -> u64 {
        let wide = self.wide_value_at(name, time);
        u64::try_from(wide).unwrap_or_else(|_| panic!("{name} = {wide:#x} at {time}"))
    }

    /// The value of `name` (up to 128 bits wide) at `time`.
    fn wide_value_at(&self, name: &str, time: u64) -> u128 {
        let (index, _) = self.signal(name);
        let changes = &self.changes[&index];
        let (_, bits) = changes
            .iter()
            .rev()
            .find(|(t, _)| *t <= time)
            .unwrap_or_else(|| panic!("{name} has no value at time {time}"));
        u128::from_str_radix(bits, 2).unwrap_or_else(|_| panic!("{name} = {bits:?} at {time}"))
    }

    /// The times at which `name` changes to a new value.
    fn times(&self, name: &str) -> Vec<u64> {
        let (index, _) = self.signal(name);
        self.changes[&index].iter().map(|&(t, _)| t).collect()
    }
}

/// The sample points (clk low) of the cycles in the file, read from the
/// clock itself: every falling edge (the file's first value is none).
fn sample_points(fst: &Fst) -> Vec<u64> {
    fst.times("clk")
        .into_iter()
        .filter(|&t| t > fst.start && fst.value_at("clk", t) == 0)
        .collect()
}

#[test]
fn a_window_spans_k_cycles_around_the_injected_fault() {
    let scene = small_reference();
    // A state deep inside a pixel: the shading of the first hit.
    let fault: Fault = "SH_POINT:0x400".parse().expect("a fault");
    let d = first_divergence(&scene, fault);
    let seq = d.seq().expect("an event diverged");
    let done_cycle = d.a.cycles;
    let dir = scratch("window");

    // K larger than the divergence cycle: the window starts at the start
    // cycle, so every event of the pixel before the divergent one is in it.
    let k_big = 10_000;
    let w = wave::write_divergence(
        &scene,
        Some(fault),
        &d,
        k_big,
        &dir.join("all.fst"),
        compact_replay(&scene),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(w.fst.is_file() && w.gtkw.is_file() && w.filter.is_file());
    let fst = Fst::read(&w.fst);
    assert_eq!(fst.timescale_exponent, -12, "1 ps time unit");
    // The pixel from its start cycle to the rising edge after done.
    assert_eq!(fst.start, 0);
    assert_eq!(fst.end, (done_cycle + 1) * 1000);
    assert_eq!(fst.value_at("done", done_cycle * 1000 + 500), 1);
    let samples = sample_points(&fst);
    // Events as the harness samples them: trace_valid high at a falling edge.
    let events: Vec<u64> = samples
        .iter()
        .copied()
        .filter(|&t| fst.value_at("trace_valid", t) == 1)
        .collect();
    assert_eq!(events.len() as u64, d.a.events, "the RTL's event count");
    let divergent = events[seq as usize];
    // The divergent event is the first write in the fault's state, in that
    // state on the controller's register and the trace port.
    let st = fault.state as u64;
    assert_eq!(fst.value_at("u_ctrl.st_q", divergent), st);
    assert_eq!(fst.value_at("trace_state", divergent), st);
    assert!(events[..seq as usize]
        .iter()
        .all(|&t| fst.value_at("trace_state", t) != st));
    // Cycle c is sampled at c ns + 500 ps.
    let cycle = (divergent - 500) / 1000;
    assert_eq!(divergent, cycle * 1000 + 500);
    assert_eq!(w.divergence_cycle, cycle);
    assert_eq!((w.first_cycle, w.last_cycle), (0, done_cycle));

    // A small K: exactly K cycles either side, from the rising edge that
    // begins the first to the one that ends the last.
    for k in [0, 3] {
        assert!(
            cycle > k && cycle + k < done_cycle,
            "the window is not clamped"
        );
        let w = wave::write_divergence(
            &scene,
            Some(fault),
            &d,
            k,
            &dir.join(format!("k{k}.fst")),
            compact_replay(&scene),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let fst = Fst::read(&w.fst);
        assert_eq!(
            (fst.start, fst.end),
            ((cycle - k) * 1000, (cycle + k + 1) * 1000),
            "K = {k}"
        );
        assert_eq!(sample_points(&fst).len() as u64, 2 * k + 1, "K = {k}");
        assert_eq!(fst.value_at("u_ctrl.st_q", cycle * 1000 + 500), st);
        assert_eq!(fst.value_at("trace_valid", cycle * 1000 + 500), 1);
        assert_eq!((w.first_cycle, w.last_cycle), (cycle - k, cycle + k));
    }
}

#[test]
fn the_save_file_shows_signals_of_the_fst_and_the_filter_names_states() {
    let (scene, fault, d) = pri_half();
    let dir = scratch("gtkw");
    let w = wave::write_window_in(&dir, &scene, Some(fault), &d, 20, compact_replay(&scene))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(w.fst, dir.join("wave.fst"));
    let fst = Fst::read(&w.fst);

    // Every signal line of the save file names a signal of the FST.
    let gtkw = std::fs::read_to_string(&w.gtkw).expect("save file");
    let names: Vec<&str> = gtkw.lines().filter(|l| l.starts_with("TOP.")).collect();
    assert!(names.len() >= 10, "{gtkw}");
    for name in &names {
        assert!(
            fst.signals.contains_key(*name),
            "{name} is not in the FST; it has e.g. {:?}",
            fst.signals
                .keys()
                .filter(|k| k.contains("st_q"))
                .collect::<Vec<_>>()
        );
    }
    // The controller state is shown through the filter file, in hex.
    let st_q = names
        .iter()
        .position(|n| n.starts_with("TOP.pixel_processor.u_ctrl.st_q["))
        .expect("st_q shown");
    let lines: Vec<&str> = gtkw.lines().collect();
    let at = lines.iter().position(|l| *l == names[st_q]).unwrap();
    let filter_line = format!("^1 {}", w.filter.display());
    assert!(lines[..at].contains(&filter_line.as_str()), "{gtkw}");
    let flags = lines[..at]
        .iter()
        .rev()
        .find_map(|l| l.strip_prefix('@'))
        .expect("flags before st_q");
    let flags = u64::from_str_radix(flags, 16).expect("hex flags");
    // GTKWave's analyzer.h: TR_HEX = 1 << 1, TR_FTRANSLATED = 1 << 13.
    assert_eq!(flags & (1 << 1 | 1 << 13), 1 << 1 | 1 << 13, "{gtkw}");

    // The filter: every state as GTKWave shows st_q in hex, all digits.
    let (_, width) = fst.signal("u_ctrl.st_q");
    let digits = width.div_ceil(4) as usize;
    let filter = std::fs::read_to_string(&w.filter).expect("filter file");
    let map: HashMap<&str, &str> = filter
        .lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split_once(' '))
        .collect();
    for &(name, code) in isa::STATES {
        let hex = format!("{code:0digits$X}");
        assert_eq!(map.get(hex.as_str()), Some(&name), "{hex} in\n{filter}");
        assert_eq!(map.get(format!("${hex}").as_str()), Some(&name));
    }
    // The state at the divergence, as the viewer would name it.
    let shown = fst.value_at("u_ctrl.st_q", w.divergence_cycle * 1000 + 500);
    assert_eq!(map[format!("{shown:0digits$X}").as_str()], "PRI_HALF");
}

#[test]
fn a_bad_path_is_a_clear_error() {
    let (scene, fault, d) = pri_half();
    let dir = scratch("bad-path");
    let missing = dir.join("no-such-dir").join("wave.fst");
    let e = wave::write_divergence(&scene, Some(fault), &d, 5, &missing, compact_replay(&scene))
        .unwrap_err();
    assert!(
        matches!(&e, WaveError::Io { path, .. } if *path == missing),
        "{e:?}"
    );
    let text = e.to_string();
    assert!(
        text.contains(&missing.display().to_string()) && text.contains("No such file"),
        "{text}"
    );
    let e = wave::write_divergence(&scene, Some(fault), &d, 5, &dir, compact_replay(&scene))
        .unwrap_err();
    assert!(matches!(e, WaveError::NotAFile { .. }), "{e:?}");
    assert!(e.to_string().contains("not a file name"), "{e}");
}

/// GTKWave itself, when it is installed (with `xvfb-run` for a display):
/// it loads the FST with the save file, shows every signal the save file
/// names, puts the marker on the divergence, and names the controller state
/// there through the filter. Without them the test says so and passes.
#[test]
fn gtkwave_shows_the_state_names() {
    let found = |tool: &str| {
        std::process::Command::new("sh")
            .args(["-c", &format!("command -v {tool}")])
            .output()
            .is_ok_and(|o| o.status.success())
    };
    if !(found("gtkwave") && found("xvfb-run")) {
        eprintln!("NOT RUN: gtkwave_shows_the_state_names needs gtkwave and xvfb-run (apt-get install gtkwave xvfb xauth)");
        return;
    }
    let scene = small_reference();
    let fault: Fault = "SH_POINT:0x400".parse().expect("a fault");
    let d = first_divergence(&scene, fault);
    let dir = scratch("gtkwave");
    let w = wave::write_window_in(&dir, &scene, Some(fault), &d, 3, compact_replay(&scene))
        .unwrap_or_else(|e| panic!("{e}"));
    let st_q = format!(
        "TOP.pixel_processor.u_ctrl.st_q[{}:0]",
        isa::dim::ST_BITS - 1
    );
    let script = dir.join("check.tcl");
    std::fs::write(
        &script,
        format!(
            "puts \"SHOWN [gtkwave::getDisplayedSignals]\"\n\
             puts \"MARKER [gtkwave::getMarker]\"\n\
             puts \"STATE [gtkwave::getTraceValueAtMarkerFromName {{{st_q}}}]\"\n\
             gtkwave::/File/Quit\n"
        ),
    )
    .expect("Tcl script");
    let out = std::process::Command::new("timeout")
        .arg("120")
        .args(["xvfb-run", "-a", "gtkwave", "-S"])
        .args([&script, &w.fst, &w.gtkw])
        .output()
        .expect("running gtkwave");
    let text = String::from_utf8_lossy(&out.stdout);
    let line = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(key))
            .unwrap_or_else(|| panic!("no {key} line from gtkwave:\n{text}"))
            .trim()
            .to_string()
    };
    let gtkw = std::fs::read_to_string(&w.gtkw).expect("save file");
    let named: Vec<&str> = gtkw.lines().filter(|l| l.starts_with("TOP.")).collect();
    let shown: Vec<String> = line("SHOWN ")
        .split_whitespace()
        .map(String::from)
        .collect();
    assert_eq!(shown, named, "{text}");
    // The marker on the divergent event's sample point (clk low, c ns + 500 ps).
    let marker: u64 = line("MARKER ").parse().expect("a time");
    assert_eq!(marker, w.divergence_cycle * 1000 + 500, "{text}");
    assert_eq!(line("STATE "), "SH_POINT", "{text}");
}

/// `rtcosim cosim --fault SH_POINT:0x400 --wave K --wave-out PATH`, run as
/// the built binary on a window of the 40x30 reference frame: the FST goes
/// where --wave-out says, with its companions beside it; the first
/// divergent pixel is the window's first (in row order) whose golden trace
/// has a write in SH_POINT; with K past both ends the file is that whole
/// pixel, and its trace port shows golden's events up to the divergence,
/// where lane x carries the fault's XOR; with K = 3 it is the 7 cycles
/// around that write.
#[test]
fn cosim_wave_writes_the_window_where_wave_out_says() {
    let scene = small_reference();
    let fault: Fault = "SH_POINT:0x400".parse().expect("a fault");
    let window = Window::new(0, 13, 40, 2);
    // Golden's account: the first pixel that writes in SH_POINT, its
    // events and cycles.
    let (x, y, events, cycles) = window
        .iter()
        .find_map(|(x, y)| {
            let mut events = Vec::new();
            let r = golden::micro::render_pixel(&scene, x, y, |e, _| events.push(*e));
            events
                .iter()
                .any(|e| e.state == fault.state)
                .then_some((x, y, events, r.cycles))
        })
        .expect("a pixel of the window reaches SH_POINT");
    let seq = events
        .iter()
        .position(|e| e.state == fault.state)
        .expect("an SH_POINT write");
    let dir = scratch("cli");
    let cosim = |k: &str, path: &Path| {
        rtcosim(&[
            "cosim",
            "--size",
            "40x30",
            "--window",
            "0,13,39,14",
            "--fault",
            "SH_POINT:0x400",
            "--threads",
            "2",
            "--wave",
            k,
            "--wave-out",
            arg(path),
        ])
    };

    // K past both ends (the largest there is): the whole pixel.
    let whole = dir.join("whole.fst");
    let out = cosim(&u64::MAX.to_string(), &whole);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(&format!("first divergence: pixel ({x}, {y}) event #{seq} ")),
        "{stdout}"
    );
    let fst = Fst::read(&whole);
    assert_eq!((fst.start, fst.end), (0, (cycles + 1) * 1000), "{stdout}");
    assert_eq!(fst.value_at("px", 500), u64::from(x));
    assert_eq!(fst.value_at("py", 500), u64::from(y));
    let writes: Vec<u64> = sample_points(&fst)
        .into_iter()
        .filter(|&t| fst.value_at("trace_valid", t) == 1)
        .collect();
    assert!(writes.len() > seq, "{} writes", writes.len());
    for (i, (&t, e)) in writes.iter().zip(&events).take(seq + 1).enumerate() {
        let value = fst.wide_value_at("trace_value", t);
        let lanes: [u32; 3] = std::array::from_fn(|l| (value >> (32 * l)) as u32);
        let mut want = e.values;
        if i == seq {
            want[0] ^= fault.xor;
        }
        assert_eq!(
            (fst.value_at("trace_state", t), fst.value_at("trace_dst", t)),
            (u64::from(e.state), u64::from(e.dst)),
            "write #{i}"
        );
        assert_eq!(lanes, want, "write #{i}: lanes x, y, z");
    }
    let c = (writes[seq] - 500) / 1000;
    let fst_path = std::path::absolute(&whole).expect("absolute");
    assert!(
        stdout.contains(&format!(
            "\nwaveform: pixel ({x}, {y}) re-run on the traced model; cycles 0..={cycles} \
             around the RTL's event #{seq} (SH_POINT ({})) in cycle {c} (cycle c starts at c ns) \
             in {}\n",
            fault.state,
            fst_path.display()
        )),
        "{stdout}"
    );
    assert!(dir.join("whole.gtkw").is_file() && dir.join("whole-states.txt").is_file());

    // K = 3, in a directory of its own: cycles c - 3 ..= c + 3.
    assert!(c > 3 && c + 3 < cycles, "the window is not clamped");
    let sub = dir.join("sub");
    std::fs::create_dir_all(&sub).expect("a subdirectory");
    let out = cosim("3", &sub.join("k3.fst"));
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    let fst = Fst::read(&sub.join("k3.fst"));
    assert_eq!((fst.start, fst.end), ((c - 3) * 1000, (c + 4) * 1000));
    assert_eq!(sample_points(&fst).len(), 7);
    let at = c * 1000 + 500;
    assert_eq!(fst.value_at("trace_valid", at), 1);
    assert_eq!(fst.value_at("u_ctrl.st_q", at), u64::from(fault.state));
    let mut names: Vec<String> = std::fs::read_dir(&sub)
        .expect("listing")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["k3-states.txt", "k3.fst", "k3.gtkw"]);
    assert!(
        text(&out.stdout).contains(&format!("cycles {}..={} around", c - 3, c + 3)),
        "{}",
        both(&out)
    );
}

/// A run that agrees writes no waveform, says so, and passes.
#[test]
fn cosim_wave_without_a_divergence_writes_nothing() {
    let dir = scratch("cli-clean");
    let fst = dir.join("w.fst");
    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--window",
        "5,5,8,6",
        "--wave",
        "4",
        "--wave-out",
        arg(&fst),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    assert!(
        text(&out.stdout).contains("\n--wave 4: no divergence, so no waveform was written\n"),
        "{}",
        both(&out)
    );
    assert_eq!(std::fs::read_dir(&dir).expect("listing").count(), 0);
}

/// Bad --wave and --wave-out values: exit 2 before anything runs (nothing
/// on stdout), the option named, no panic, no file written.
#[test]
fn cosim_wave_refuses_bad_values_with_exit_2() {
    let dir = scratch("cli-bad");
    let missing = dir.join("no-such-dir").join("w.fst");
    let (missing, here) = (arg(&missing).to_string(), arg(&dir).to_string());
    let fst = dir.join("w.fst");
    let fst = arg(&fst).to_string();
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec!["--wave", "x"],
            "invalid value 'x' for '--wave <K>': expected a number of cycles; got \"x\"".into(),
        ),
        (
            vec!["--wave", "-3"],
            "invalid value '-3' for '--wave <K>': expected a number of cycles; got \"-3\"".into(),
        ),
        (
            vec!["--wave", "18446744073709551616"],
            "invalid value '18446744073709551616' for '--wave <K>'".into(),
        ),
        (
            vec!["--wave-out", &fst],
            "the following required arguments were not provided:\n  --wave <K>".into(),
        ),
        (
            vec!["--wave", "3", "--wave-out", &missing],
            format!(
                "error: --wave-out {missing}: no such directory {}",
                arg(&dir.join("no-such-dir"))
            ),
        ),
        (
            vec!["--wave", "3", "--wave-out", &here],
            format!("error: --wave-out {here}: not a file name (expected e.g. wave.fst)"),
        ),
        (
            vec!["--wave", "3", "--wave-out", &fst, "--out", &here],
            "the argument '--wave-out <PATH>' cannot be used with '--out <DIR>'".into(),
        ),
    ];
    for (args, message) in cases {
        let mut all = vec![
            "cosim",
            "--size",
            "40x30",
            "--window",
            "0,0",
            "--fault",
            "PRI_HALF:0x400",
        ];
        all.extend(&args);
        assert_refused(&all, &[&message]);
    }
    assert_eq!(std::fs::read_dir(&dir).expect("listing").count(), 0);
}

/// The fast processor's window (a streamed [`Replay`]): the divergent pixel's tile
/// re-run on the fast processor verilated with --trace-fst, read back with
/// the FST reader and held to the co-simulation's own account of the pixel
/// (its RTL events, its cycles in the tile) and to the FST's signals: the
/// take of the pixel by a context, that context's writes on the trace port
/// (as many as the RTL wrote, the divergent one in the fault's state with
/// the faulty value), its done turn. Through the binary, `--wave` writes
/// it for `--processor fast`.
#[test]
fn the_fast_processors_window_is_its_tile_re_run_around_the_divergence() {
    let scene = small_reference();
    let fault: Fault = "SH_POINT:0x400".parse().expect("a fault");
    let window = Window::full(&scene);
    let options = CosimOptions {
        fault: Some(fault),
        ..CosimOptions::default()
    };
    let fast = Design::for_scene(ProcessorKind::Fast, &scene);
    let report =
        cosim::run(&fast, &scene, window, &options, &|_| {}).unwrap_or_else(|e| panic!("{e}"));
    let d = report.compare.first_divergence.expect("the fault diverged");
    let seq = d.seq().expect("an event diverged");
    let (rtl_event, _) = d.events();
    let rtl_event = rtl_event.expect("the RTL's divergent event");
    let replay = Replay::of(&fast, Stall::NONE, window, d.y);
    assert!(replay.streamed() && replay.tile.y <= d.y && d.y < replay.tile.y + replay.tile.height);
    let dir = scratch("fast");

    let w = wave::write_divergence(
        &scene,
        Some(fault),
        &d,
        1 << 30,
        &dir.join("all.fst"),
        replay,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let fst = Fst::read(&w.fst).of_fast();
    // The whole life of the pixel: from the cycle its context took it to
    // its done turn, whose cycle count is the co-simulation's for it.
    let (take, done) = (w.first_cycle, w.last_cycle);
    assert_eq!((fst.start, fst.end), (take * 1000, (done + 1) * 1000));
    assert_eq!(done - take, d.a.cycles, "the pixel's cycles in its tile");
    let sample = |c: u64| c * 1000 + 500;
    assert_eq!(fst.value_at("take", sample(take)), 1);
    let ctx = fst.value_at("turn_ctx", sample(take));
    assert_eq!(fst.value_at("done", sample(done)), 1);
    assert_eq!(fst.value_at("turn_ctx", sample(done)), ctx);
    // The context's writes, as the harness samples them.
    let writes: Vec<u64> = sample_points(&fst)
        .into_iter()
        .filter(|&t| fst.value_at("trace_valid", t) == 1 && fst.value_at("trace_ctx", t) == ctx)
        .collect();
    assert_eq!(writes.len() as u64, d.a.events, "the RTL's event count");
    let at = writes[seq as usize];
    assert_eq!(at, sample(w.divergence_cycle));
    let st = u64::from(fault.state);
    assert_eq!(fst.value_at("trace_state", at), st);
    assert!(writes[..seq as usize]
        .iter()
        .all(|&t| fst.value_at("trace_state", t) != st));
    let value = fst.wide_value_at("trace_value", at);
    assert_eq!(value as u32, rtl_event.values[0], "lane x, with the fault");
    assert_eq!(fst.value_at("fault_state", at), st);

    // K = 3: seven cycles around it; the save file names signals of the FST.
    let w = wave::write_divergence(&scene, Some(fault), &d, 3, &dir.join("k3.fst"), replay)
        .unwrap_or_else(|e| panic!("{e}"));
    let c = w.divergence_cycle;
    let fst = Fst::read(&w.fst).of_fast();
    assert_eq!((fst.start, fst.end), ((c - 3) * 1000, (c + 4) * 1000));
    assert_eq!(sample_points(&fst).len(), 7);
    let gtkw = std::fs::read_to_string(&w.gtkw).expect("save file");
    let names: Vec<&str> = gtkw.lines().filter(|l| l.starts_with("TOP.")).collect();
    assert!(names.len() >= 20, "{gtkw}");
    for name in &names {
        assert!(fst.signals.contains_key(*name), "{name} is not in the FST");
    }
    assert_eq!(
        names,
        wave::shown_signals(ProcessorKind::Fast)
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
    );

    // Through the binary: --wave on the fast processor.
    let out = rtcosim(&[
        "cosim",
        "--size",
        "40x30",
        "--processor",
        "fast",
        "--fault",
        "SH_POINT:0x400",
        "--wave",
        "3",
        "--wave-out",
        arg(&dir.join("cli.fst")),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(&format!(
            "waveform: pixel ({}, {}) re-run on the traced model of the fast processor, fed tile",
            d.x, d.y
        )),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!(
            "cycles {}..={} around the RTL's event #{seq} (SH_POINT",
            c - 3,
            c + 3
        )),
        "{stdout}"
    );
    assert!(Fst::read(&dir.join("cli.fst")).of_fast().start == (c - 3) * 1000);
}
