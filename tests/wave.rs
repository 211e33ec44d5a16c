//! The waveform window (`rtcosim::wave`, `rtcosim cosim --wave K`): a fault
//! injected through the fault port makes the RTL diverge; the window of the
//! first divergent pixel is read back with an independent FST reader
//! (`fst-reader`) and checked against what the co-simulation reported and
//! against the FST's own signals, not against numbers the wave module
//! computes.

use fst_reader::{FstFilter, FstHierarchyEntry, FstReader, FstSignalValue};
use golden::micro::isa;
use golden::scene::Scene;
use golden::window::Window;
use rtcosim::compare::Divergence;
use rtcosim::cosim::{self, CosimOptions};
use rtcosim::pixel_proc::Fault;
use rtcosim::wave::{self, WaveError};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The builtin reference scene at 40x30.
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
    let report = cosim::run(scene, Window::full(scene), &options, &|_| {})
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
            start: header.start_time,
            end: header.end_time,
            timescale_exponent: header.timescale_exponent,
            signals,
            changes,
        }
    }

    /// The signal named `name` (without its range) under TOP.pixel_processor.
    fn signal(&self, name: &str) -> (usize, u32) {
        let prefix = format!("TOP.pixel_processor.{name}");
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
        let (index, _) = self.signal(name);
        let changes = &self.changes[&index];
        let (_, bits) = changes
            .iter()
            .rev()
            .find(|(t, _)| *t <= time)
            .unwrap_or_else(|| panic!("{name} has no value at time {time}"));
        u64::from_str_radix(bits, 2).unwrap_or_else(|_| panic!("{name} = {bits:?} at {time}"))
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
    let w = wave::write_divergence(&scene, Some(fault), &d, k_big, &dir.join("all.fst"))
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
        let w = wave::write_divergence(&scene, Some(fault), &d, k, &dir.join(format!("k{k}.fst")))
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
    let w =
        wave::write_window_in(&dir, &scene, Some(fault), &d, 20).unwrap_or_else(|e| panic!("{e}"));
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
    let e = wave::write_divergence(&scene, Some(fault), &d, 5, &missing).unwrap_err();
    assert!(
        matches!(&e, WaveError::Io { path, .. } if *path == missing),
        "{e:?}"
    );
    let text = e.to_string();
    assert!(
        text.contains(&missing.display().to_string()) && text.contains("No such file"),
        "{text}"
    );
    let e = wave::write_divergence(&scene, Some(fault), &d, 5, &dir).unwrap_err();
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
    let w =
        wave::write_window_in(&dir, &scene, Some(fault), &d, 3).unwrap_or_else(|e| panic!("{e}"));
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
