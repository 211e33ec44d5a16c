//! Running `verilator --cc` for one model and reading back the C++ files it
//! wrote (from the generated `V<class>_classes.mk`, never guessed names).

use crate::models::Flavour;
use crate::verilator::Verilator;
use std::env;
use std::fs;
use std::path::{Path, PathBuf};

/// One model as Verilator is asked for it: its class, top module,
/// parameter overrides, preprocessor defines, include directories and
/// the Verilog it is built from.
pub(crate) struct Job {
    pub(crate) class: String,
    pub(crate) top: &'static str,
    pub(crate) params: Vec<(&'static str, u32)>,
    pub(crate) defines: Vec<&'static str>,
    pub(crate) includes: Vec<PathBuf>,
    pub(crate) sources: Vec<PathBuf>,
    pub(crate) flavour: Flavour,
}

/// One C++ file a model needs, and whether Verilator files it as slow code
/// (constructors, initial and settle evaluation: run once per model).
pub(crate) struct CppFile {
    pub(crate) path: PathBuf,
    pub(crate) slow: bool,
}

/// Runs `verilator --cc` for one model and returns the C++ files to compile
/// (model classes and the runtime files it asks for).
pub(crate) fn verilate(v: &Verilator, m: &Job, out: &Path) -> Result<Vec<CppFile>, String> {
    let mdir = out.join(&m.class);
    let _ = fs::remove_dir_all(&mdir);
    let o = command(v, m, &mdir)?
        .output()
        .map_err(|e| format!("running {}: {e}", v.bin.display()))?;
    if !o.status.success() {
        return Err(format!(
            "verilator failed on {} ({}):\n{}",
            m.class,
            m.top,
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    classes_mk(v, &mdir.join(format!("{}_classes.mk", m.class)), &mdir)
}

/// The `verilator --cc` command of `m`, into `mdir`.
fn command(v: &Verilator, m: &Job, mdir: &Path) -> Result<std::process::Command, String> {
    let mut cmd = v.command();
    cmd.args([
        "--cc",
        "-O3",
        "--x-assign",
        "fast",
        "--x-initial",
        "fast",
        "--no-timing",
    ])
    .arg("--top-module")
    .arg(m.top)
    .arg("--prefix")
    .arg(&m.class)
    .arg("-Mdir")
    .arg(mdir);
    for inc in &m.includes {
        cmd.arg(format!("-I{}", inc.display()));
    }
    for define in &m.defines {
        cmd.arg(format!("-D{define}"));
    }
    if m.flavour == Flavour::Coverage {
        // Relative source names (the model's sources and includes are
        // relative to the package), so that coverage.dat says rtl/...
        cmd.current_dir(env::var("CARGO_MANIFEST_DIR").map_err(|e| e.to_string())?);
        cmd.args(["--coverage-line", "--coverage-toggle", "--coverage-user"]);
    }
    if m.flavour == Flavour::Wave {
        // Three levels: pixel_processor, u_ctrl and u_core with everything
        // in them, and the ports of the units below (the ALU, the register
        // file, the float units). All levels would triple the generated trace
        // code (2.3 MB of C++ instead of 0.77 MB).
        cmd.args(["--trace-fst", "--trace-depth", "3"]);
        // Verilator 5.048 keeps functions' locals as signals when tracing
        // and then warns that several calls drive them (MULTIDRIVEN); the
        // untraced models of the same RTL lint clean (tests/rtl_lint.rs).
        cmd.arg("-Wno-MULTIDRIVEN");
    }
    if m.flavour.is_yosys_netlist() {
        // Yosys' netlist: widths it leaves implicit, overlapping case items
        // of its muxes, and multi-bit wires Verilator cannot order bit by bit
        // (it iterates them); none is a fault of the netlist.
        cmd.args(["-Wno-WIDTH", "-Wno-CASEOVERLAP", "-Wno-UNOPTFLAT"]);
    }
    if m.flavour == Flavour::Synth {
        // Verilator 5.006's bit-op-tree optimization (V3Const) computes some
        // XOR trees of Yosys' gate netlist wrongly: fp_sqrt's remainder came
        // out with its sign flipped, 1 ULP off, where Icarus on the same
        // netlist agrees with golden (docs/rtl.md, "The synthesized netlist
        // co-simulated"). Without that one optimization the netlist agrees.
        cmd.arg("-fno-const-bit-op-tree");
    }
    for (name, value) in &m.params {
        cmd.arg(format!("-G{name}={value}"));
    }
    cmd.args(&m.sources);
    Ok(cmd)
}

/// The C++ files the generated `V<class>_classes.mk` lists: the model's
/// classes (in `mdir`) and the runtime files it asks for.
fn classes_mk(v: &Verilator, mk: &Path, mdir: &Path) -> Result<Vec<CppFile>, String> {
    let text = fs::read_to_string(mk).map_err(|e| format!("reading {}: {e}", mk.display()))?;
    let mut files = Vec::new();
    let mut current = None;
    for line in text.lines() {
        let line = line.trim();
        if let Some((var, _)) = line.split_once("+=") {
            current = Some(var.trim().to_string());
            continue;
        }
        if line.is_empty() || line.starts_with('#') {
            current = None;
            continue;
        }
        let name = line.trim_end_matches('\\').trim();
        let var = current.as_deref().unwrap_or("");
        let slow = var.ends_with("_SLOW");
        match var {
            "VM_CLASSES_FAST" | "VM_CLASSES_SLOW" | "VM_SUPPORT_FAST" | "VM_SUPPORT_SLOW" => files
                .push(CppFile {
                    path: mdir.join(format!("{name}.cpp")),
                    slow,
                }),
            "VM_GLOBAL_FAST" | "VM_GLOBAL_SLOW" => files.push(CppFile {
                path: v.root.join("include").join(format!("{name}.cpp")),
                slow,
            }),
            _ => {}
        }
        if !line.ends_with('\\') {
            current = None;
        }
    }
    if files.is_empty() {
        return Err(format!("{} lists no C++ files", mk.display()));
    }
    Ok(files)
}
