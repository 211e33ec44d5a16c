//! The Yosys steps of the build: the mutant netlists (feature `mutation`) and
//! the synthesized netlist (feature `synth-netlist`).

use crate::rtl::{files_in, fnv1a64};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `out` (about 3 minutes to prepare the compact one, 15 the fast one).
pub(crate) fn write_mutant_netlist(
    manifest: &Path,
    out: &Path,
    design: &str,
) -> Result<PathBuf, String> {
    let netlist = out.join(match design {
        "fast_pp" => "fast_pp_mutants.v",
        _ => "pp_mutants.v",
    });
    let script = manifest.join("rtl/mutate/mutants.sh");
    let o = Command::new("bash")
        .arg(&script)
        .arg("netlist")
        .arg(&netlist)
        .env("MUTATE_CACHE", out.join("mutate"))
        .env("MUTATE_DESIGN", design)
        .output()
        .map_err(|e| format!("running {}: {e}", script.display()))?;
    if !o.status.success() {
        return Err(format!(
            "the mutation build (cargo feature `mutation`) needs Yosys and python3 \
             (Debian: apt-get install yosys): {} netlist failed:\n{}",
            script.display(),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    Ok(netlist)
}

/// Runs `rtl/synth/synth.sh generic pp exact` (Yosys) into `out/synth` and
/// returns its `netlist.v`: the pixel processor as Yosys' generic gates.
/// Synthesis takes minutes, so the netlist is kept beside `rtl.hash` (the
/// FNV-1a 64 of the script and of every source it reads) and made again
/// only when they change.
pub(crate) fn write_synth_netlist(manifest: &Path, out: &Path) -> Result<PathBuf, String> {
    let dir = out.join("synth");
    let netlist = dir.join("netlist.v");
    let stamp = dir.join("rtl.hash");
    let script = manifest.join("rtl/synth/synth.sh");
    let mut inputs = vec![script.clone()];
    inputs.extend(files_in(
        &[&manifest.join("rtl/fp"), &manifest.join("rtl/pp")],
        |_| true,
    )?);
    let mut hashes = String::new();
    for input in &inputs {
        hashes += &format!("{} {}\n", fnv1a64(input)?, input.display());
    }
    if netlist.exists() && fs::read_to_string(&stamp).ok().as_deref() == Some(hashes.as_str()) {
        return Ok(netlist);
    }
    let o = Command::new("bash")
        .arg(&script)
        .args(["generic", "pp", "exact"])
        .current_dir(manifest)
        .env("SYNTH_DIR", &dir)
        .output()
        .map_err(|e| format!("running {}: {e}", script.display()))?;
    if !o.status.success() || !netlist.exists() {
        return Err(format!(
            "the synthesized netlist (cargo feature `synth-netlist`) needs Yosys \
             (Debian: apt-get install yosys): {} generic pp exact failed (log: {}):\n{}",
            script.display(),
            dir.join("yosys.log").display(),
            String::from_utf8_lossy(&o.stderr)
        ));
    }
    fs::write(&stamp, hashes).map_err(|e| format!("writing {}: {e}", stamp.display()))?;
    Ok(netlist)
}
