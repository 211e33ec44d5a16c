//! A processor's mutant list (`rtl/mutate/*.mutants`) and the
//! classification of its survivors (`*.survivors`).

use super::*;

/// One mutant of the list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mutant {
    /// Its `mutsel` value, from 1.
    pub id: u16,
    /// Yosys' mutation mode: `inv`, `const0`, `const1`, `cnot0`, `cnot1`.
    pub mode: String,
    /// The module, without Yosys' parameter decoration (`fp_lzc`, not
    /// `$paramod$...\fp_lzc`).
    pub module: String,
    /// Where in the RTL: the first `-src` with a line, `rtl/pp/pp_ctrl.v:120`.
    pub location: String,
    /// The whole `mutate` command, as listed.
    pub command: String,
}

/// The mutant list: the RTL hash it was listed on, and its mutants.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct List {
    /// Where it was read from: the processor it mutates.
    pub files: Files,
    pub rtl_hash: String,
    pub mutants: Vec<Mutant>,
    /// The survivors' classification ([`Files::survivors_path`]), by
    /// mutant.
    pub classified: BTreeMap<u16, Classified>,
}

/// A line of the list (or of its survivors' classification) that does not
/// read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{path}:{line}: {message}")]
pub struct ListError {
    pub path: &'static str,
    pub line: usize,
    pub message: String,
}

/// What a survivor is, as classified by a reader of the RTL
/// (rtl/mutate/pixel_processor.survivors; docs/mutation.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Class {
    /// Yosys proved it equivalent (`--equiv`); the reason says what it does.
    Equivalent,
    /// It differs from the design only in states or inputs no run reaches;
    /// the reason names the invariant.
    Unreachable,
    /// A behaviour the judge misses; the reason says what would kill it.
    Hole,
    /// Not decided yet.
    Open,
}

impl Class {
    fn parse(word: &str) -> Option<Class> {
        Some(match word {
            "equivalent" => Class::Equivalent,
            "unreachable" => Class::Unreachable,
            "hole" => Class::Hole,
            "open" => Class::Open,
            _ => return None,
        })
    }

    /// Whether no run can tell the mutant from the design.
    pub fn is_equivalent(self) -> bool {
        matches!(self, Class::Equivalent | Class::Unreachable)
    }
}

impl std::fmt::Display for Class {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Class::Equivalent => "equivalent",
            Class::Unreachable => "unreachable",
            Class::Hole => "hole",
            Class::Open => "open",
        })
    }
}

/// A survivor's class and the reason for it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Classified {
    pub class: Class,
    pub reason: String,
}

/// Reads a classification: `ID CLASS reason`, one a line, `#` comments;
/// `path` names it in errors.
pub fn parse_classification(
    path: &'static str,
    text: &str,
) -> Result<BTreeMap<u16, Classified>, ListError> {
    let mut found = BTreeMap::new();
    for (n, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let error = |message: String| ListError {
            path,
            line: n + 1,
            message,
        };
        let mut words = line.splitn(3, ' ');
        let (Some(id), Some(class), Some(reason)) = (words.next(), words.next(), words.next())
        else {
            return Err(error(format!("not `ID CLASS reason`: {line}")));
        };
        let id: u16 = id
            .parse()
            .map_err(|_| error(format!("mutant number {id:?} is not in 1..=65535")))?;
        let class = Class::parse(class).ok_or_else(|| {
            error(format!(
                "class {class:?} is none of equivalent, unreachable, hole, open"
            ))
        })?;
        let classified = Classified {
            class,
            reason: reason.trim().to_string(),
        };
        if found.insert(id, classified).is_some() {
            return Err(error(format!("mutant {id} is classified twice")));
        }
    }
    Ok(found)
}

/// `$paramod$<hash>\fp_lzc` and `$paramod\memory\STACK_DEPTH=...` ->
/// `fp_lzc`, `memory`.
pub(super) fn module_name(raw: &str) -> String {
    match raw.strip_prefix("$paramod") {
        Some(rest) => rest.split('\\').nth(1).unwrap_or(rest).to_string(),
        None => raw.trim_start_matches('\\').to_string(),
    }
}

impl List {
    /// `processor`'s committed list and classification.
    pub fn committed(processor: ProcessorKind) -> Result<List, ListError> {
        let files = Files::of(processor);
        List::read(files, files.list_text, files.survivors_text)
    }

    /// The list `list_text` of `files` and its classification
    /// `survivors_text`, which must name the list's RTL hash.
    pub(super) fn read(
        files: Files,
        list_text: &str,
        survivors_text: &str,
    ) -> Result<List, ListError> {
        let mut list = List::parse(files, list_text)?;
        // A classification names the list it classifies by the list's RTL
        // hash: its IDs mean other mutants in another list.
        let classified_on = survivors_text
            .lines()
            .find_map(|l| l.strip_prefix("# rtl fnv1a64 "))
            .map(str::trim);
        if classified_on != Some(list.rtl_hash.as_str()) {
            return Err(ListError {
                path: files.survivors_path,
                line: 0,
                message: format!(
                    "it classifies the survivors of the list with {}, and {} is the list \
                     with rtl fnv1a64 {}: classify the new list's survivors (docs/mutation.md)",
                    classified_on.map_or("no `# rtl fnv1a64 HASH` line".to_string(), |h| {
                        format!("rtl fnv1a64 {h}")
                    }),
                    files.list_path,
                    list.rtl_hash
                ),
            });
        }
        list.classified = parse_classification(files.survivors_path, survivors_text)?;
        if let Some(&id) = list.classified.keys().find(|&&id| list.get(id).is_none()) {
            return Err(ListError {
                path: files.survivors_path,
                line: 0,
                message: format!("mutant {id} is not in {}", files.list_path),
            });
        }
        Ok(list)
    }

    /// Mutant `id`, if the list holds it.
    pub fn get(&self, id: u16) -> Option<&Mutant> {
        self.mutants.iter().find(|m| m.id == id)
    }

    /// Reads `text` as the list of `files` (whose path errors name).
    pub fn parse(files: Files, text: &str) -> Result<List, ListError> {
        let mut rtl_hash = None;
        let mut mutants = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let error = |message: String| ListError {
                path: files.list_path,
                line: n + 1,
                message,
            };
            if let Some(h) = line.strip_prefix("# rtl fnv1a64 ") {
                rtl_hash = Some(h.trim().to_string());
            }
            if line.starts_with('#') || line.trim().is_empty() {
                continue;
            }
            let (id, command) = line
                .split_once(' ')
                .ok_or_else(|| error(format!("not `ID mutate ...`: {line}")))?;
            let id: u16 = id
                .parse()
                .map_err(|_| error(format!("mutant number {id:?} is not in 1..=65535")))?;
            if usize::from(id) != mutants.len() + 1 {
                return Err(error(format!(
                    "mutant {id} out of order: expected {}",
                    mutants.len() + 1
                )));
            }
            let words: Vec<&str> = command.split(' ').collect();
            if words.first() != Some(&"mutate") {
                return Err(error(format!("not a `mutate` command: {command}")));
            }
            let value = |flag: &str| {
                words
                    .windows(2)
                    .filter(|w| w[0] == flag)
                    .map(|w| w[1])
                    .collect::<Vec<_>>()
            };
            let (modes, modules) = (value("-mode"), value("-module"));
            let (Some(mode), Some(module)) = (modes.first(), modules.first()) else {
                return Err(error(format!("no -mode or -module: {command}")));
            };
            let location = value("-src")
                .iter()
                .filter_map(|src| {
                    let (file, at) = src.rsplit_once(':')?;
                    let line = at.split('.').next()?;
                    (line != "0").then(|| format!("{file}:{line}"))
                })
                .next()
                .unwrap_or_else(|| "(no source line)".to_string());
            mutants.push(Mutant {
                id,
                mode: mode.to_string(),
                module: module_name(module),
                location,
                command: command.to_string(),
            });
        }
        let rtl_hash = rtl_hash.ok_or(ListError {
            path: files.list_path,
            line: 1,
            message: "no `# rtl fnv1a64` line: not a list rtl/mutate/mutants.sh wrote".into(),
        })?;
        Ok(List {
            files,
            rtl_hash,
            mutants,
            classified: BTreeMap::new(),
        })
    }
}

impl List {
    /// Whether mutant `id` faces the float-unit checks: a mutant of a
    /// module the units cut from the netlist may carry: the compact
    /// processor's float units (`rtl/fp/`, `fp_*`), or the fast one's
    /// (`fast_fp_*`, the `fp_*` they share and the `fast_delay`s their
    /// pipelines are built of, some of which are the controller's: a
    /// mutant no unit carries passes their checks). One the list does not
    /// hold faces every check.
    pub fn in_float_unit(&self, id: u16) -> bool {
        let in_unit = self.files.processor.row().in_float_unit;
        self.get(id).map_or(true, |m| in_unit(&m.module))
    }
}
