//! What the build reads of rtl/: the float methods, the controllers' state
//! lines, the Verilog sources, file hashes.

use std::fs;
use std::path::{Path, PathBuf};

/// `FP_METHOD_<NAME> <code>` lines of fp_defs.vh, lower-cased names.
/// `tests/rtl_lint.rs` checks them against golden::fp::Method, so the two
/// sides cannot drift; the check is a test rather than a build step so that
/// this script does not depend on `golden`, and editing golden does not
/// re-verilate the RTL.
pub(crate) fn read_methods(path: &Path) -> Result<Vec<(String, u32)>, String> {
    let text = fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let mut methods = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        if let (Some("`define"), Some(name), Some(code)) =
            (words.next(), words.next(), words.next())
        {
            if let Some(name) = name.strip_prefix("FP_METHOD_") {
                let code = code
                    .parse()
                    .map_err(|_| format!("{}: `{name}` has a non-numeric code", path.display()))?;
                methods.push((name.to_lowercase(), code));
            }
        }
    }
    if methods.is_empty() {
        return Err(format!("{} defines no FP_METHOD_*", path.display()));
    }
    Ok(methods)
}

/// The value of `` `define ISA_DIM_<name> <n> `` in the ISA header `path`.
pub(crate) fn read_dim(path: &Path, name: &str) -> Result<u32, String> {
    let text = fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let key = format!("ISA_DIM_{name}");
    text.lines()
        .find_map(|line| {
            let mut words = line.split_whitespace();
            match (words.next(), words.next(), words.next()) {
                (Some("`define"), Some(k), Some(v)) if k == key => v.parse().ok(),
                _ => None,
            }
        })
        .ok_or_else(|| format!("{} defines no numeric `{key}`", path.display()))
}

/// Every `*.v` of `dirs`, sorted within each directory.
/// Writes `$OUT_DIR/rtl_state_lines.rs`: for each controller, the line of
/// every item of its `case` on the state (pp_ctrl's `case (st_dec)`, the fast
/// controller's `case (st)` in its `plan` function), by state name (the
/// item's `` `ISA_ST_<NAME> `` labels), so that reports can name the
/// Verilog line that decodes a state. A `case` that cannot be found is an
/// error.
pub(crate) fn write_state_lines(
    controllers: &[(&Path, &str, &str)],
    out: &Path,
) -> Result<(), String> {
    let mut code = String::new();
    for &(file, head, name) in controllers {
        let items = state_lines(file, head)?;
        code += &format!(
            "/// (state name, line) of every item of `{head}` in {}.\n\
             pub const {name}: &[(&str, u32)] = &[\n{items}];\n",
            file.strip_prefix(env!("CARGO_MANIFEST_DIR"))
                .unwrap_or(file)
                .display()
        );
    }
    fs::write(out, code).map_err(|e| format!("{}: {e}", out.display()))
}

/// The `(name, line),` items of the first `case` of `file` whose line starts
/// with `head`.
fn state_lines(file: &Path, head: &str) -> Result<String, String> {
    let text =
        fs::read_to_string(file).map_err(|e| format!("{}: cannot read: {e}", file.display()))?;
    let lines: Vec<&str> = text.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.trim_start().starts_with(head))
        .ok_or_else(|| format!("{}: no `{head}` to map states to lines", file.display()))?;
    let indent = |l: &str| l.len() - l.trim_start().len();
    let case_indent = indent(lines[start]);
    let mut items = String::new();
    for (i, line) in lines.iter().enumerate().skip(start + 1) {
        let code = line.split("//").next().unwrap_or_default();
        if code.trim() == "endcase" && indent(line) == case_indent {
            break;
        }
        // An item: `ISA_ST_A, `ISA_ST_B: ... at the start of the line.
        let Some(labels) = code.trim_start().strip_prefix('`').and_then(|c| {
            let colon = c.find(':')?;
            Some(&c[..colon])
        }) else {
            continue;
        };
        for label in format!("`{labels}").split(',') {
            if let Some(name) = label.trim().strip_prefix("`ISA_ST_") {
                items += &format!("    ({name:?}, {}),\n", i + 1);
            }
        }
    }
    Ok(items)
}

pub(crate) fn verilog_sources(dirs: &[&Path]) -> Result<Vec<PathBuf>, String> {
    files_in(dirs, |p| p.extension().is_some_and(|x| x == "v"))
}

/// The files of `dirs` that `keep`, sorted per directory, directory by
/// directory.
pub(crate) fn files_in(
    dirs: &[&Path],
    keep: impl Fn(&Path) -> bool,
) -> Result<Vec<PathBuf>, String> {
    let mut all = Vec::new();
    for dir in dirs {
        let mut files: Vec<PathBuf> = fs::read_dir(dir)
            .map_err(|e| format!("reading {}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| keep(p))
            .collect();
        files.sort();
        all.extend(files);
    }
    Ok(all)
}

/// The FNV-1a 64 hash of a file, as rtl/cover/transitions.sh writes it
/// into the transition table: a table made from another pp_ctrl.v is stale.
pub(crate) fn fnv1a64(path: &Path) -> Result<String, String> {
    use std::hash::Hasher;
    let bytes = fs::read(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let mut h = fnv::FnvHasher::default();
    h.write(&bytes);
    Ok(format!("{:016x}", h.finish()))
}
