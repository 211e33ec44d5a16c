//! Yosys' equivalence check of a survivor (`mutants.sh equiv`).

use super::*;

/// A survivor's equivalence, as Yosys found it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Equivalence {
    /// Proved: no input and no register value tells the mutated module
    /// from the original.
    Equivalent,
    /// Some signal stands unproven: the mutant may differ, or differ only
    /// for register values no run reaches.
    NotProved,
    /// The proof took longer than its limit (MUTATE_EQUIV_SECONDS, 120 s).
    Timeout,
}

/// Runs `rtl/mutate/mutants.sh equiv` on `ids` of `processor`'s list
/// (Yosys; seconds a mutant, up to its time limit), with the design the
/// build prepared.
pub fn prove_equivalent(
    processor: ProcessorKind,
    ids: &[u16],
) -> Result<BTreeMap<u16, Equivalence>, String> {
    if ids.is_empty() {
        return Ok(BTreeMap::new());
    }
    let script = script();
    let o = Command::new("bash")
        .arg(&script)
        .arg("equiv")
        .args(ids.iter().map(u16::to_string))
        .env("MUTATE_CACHE", Path::new(env!("OUT_DIR")).join("mutate"))
        .env("MUTATE_DESIGN", Files::of(processor).design)
        .output()
        .map_err(|e| format!("running {}: {e}", script.display()))?;
    if !o.status.success() {
        return Err(format!(
            "{} equiv failed: {}",
            script.display(),
            String::from_utf8_lossy(&o.stderr).trim()
        ));
    }
    let mut found = BTreeMap::new();
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        let Some((id, verdict)) = line.split_once(' ') else {
            continue;
        };
        let Ok(id) = id.parse::<u16>() else { continue };
        let verdict = match verdict.trim() {
            "equivalent" => Equivalence::Equivalent,
            "not-proved" => Equivalence::NotProved,
            "timeout" => Equivalence::Timeout,
            other => {
                return Err(format!(
                    "{} equiv: mutant {id}: unknown verdict {other:?}",
                    script.display()
                ))
            }
        };
        found.insert(id, verdict);
    }
    if let Some(missing) = ids.iter().find(|id| !found.contains_key(id)) {
        return Err(format!(
            "{} equiv said nothing of mutant {missing}",
            script.display()
        ));
    }
    Ok(found)
}
