//! The shard result file: what one shard of a run did, in a form that
//! `rtcosim merge` checks and combines.
//!
//! A JSON document (`<tool>-<K>-of-<N>.shard.json`):
//!
//! - `format`: [`FORMAT`]; another number is refused, not guessed at.
//! - `tool`: the command that wrote it (`sweep`, `fuzz`).
//! - `config`: every option of the run that affects its results (the
//!   scenes themselves, as scene-file text, not their paths), and the
//!   rtcosim version; `config_hash`: FNV-1a 64 of `config`'s JSON text
//!   (keys sorted), so an edited or damaged configuration is caught, and
//!   two runs are told apart at a glance.
//! - `shard`: `{index, count}`; `total_items`: the run's work-list length;
//!   `items`: the positions this shard did ([`Shard::positions`]).
//! - `result`: the tool's results for those items.
//!
//! [`load_set`] reads a set of them and refuses, naming the files, any set
//! that is not exactly one run: foreign or damaged files, different
//! configurations (naming the first differing key), shards of different
//! counts, a shard twice, shards missing.

use super::Shard;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The format number this rtcosim writes and reads.
pub const FORMAT: u32 = 1;

/// The file name ending that marks a shard file in a directory.
pub const SUFFIX: &str = ".shard.json";

/// A shard result file, `result` of type `R` (a [`Value`] while unchecked).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShardFile<R> {
    pub format: u32,
    pub tool: String,
    pub config: Value,
    pub config_hash: String,
    pub shard: Shard,
    pub total_items: u64,
    pub items: Vec<u64>,
    pub result: R,
}

/// Why a set of shard files is not one run.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: not a shard file of rtcosim: {reason}", path.display())]
    Foreign { path: PathBuf, reason: String },
    #[error("{}: damaged: {reason}", path.display())]
    Corrupt { path: PathBuf, reason: String },
    #[error("{}: no shard files (*{SUFFIX}) in it", path.display())]
    Empty { path: PathBuf },
    #[error("{} and {} are shards of different runs: {reason}", a.display(), b.display())]
    Different {
        a: PathBuf,
        b: PathBuf,
        reason: String,
    },
    #[error("shard {shard} twice: {} and {}", a.display(), b.display())]
    Duplicate {
        shard: Shard,
        a: PathBuf,
        b: PathBuf,
    },
    #[error("missing shard{} {} of {count} (found {})", if missing.len() == 1 { "" } else { "s" },
            list(missing), list(found))]
    Missing {
        missing: Vec<u64>,
        found: Vec<u64>,
        count: u64,
    },
}

fn list(v: &[u64]) -> String {
    let s: Vec<String> = v.iter().map(u64::to_string).collect();
    if s.is_empty() {
        "none".into()
    } else {
        s.join(", ")
    }
}

/// FNV-1a 64 (the `fnv` crate) of `config`'s JSON text (serde_json's
/// maps keep keys sorted), in hex.
pub fn config_hash(config: &Value) -> String {
    use std::hash::Hasher;
    let mut h = fnv::FnvHasher::default();
    h.write(config.to_string().as_bytes());
    format!("{:016x}", h.finish())
}

/// The configuration of a run of `tool`: `options` (every option that
/// affects results) and the rtcosim version.
pub fn run_config(options: &impl Serialize) -> Value {
    let mut config = serde_json::to_value(options).expect("options are plain data");
    if let Value::Object(map) = &mut config {
        map.insert(
            "rtcosim_version".into(),
            Value::String(env!("CARGO_PKG_VERSION").into()),
        );
    }
    config
}

impl<R: Serialize> ShardFile<R> {
    /// The file of `shard` of a run of `tool` with `config`
    /// ([`run_config`]) over `total_items` items.
    pub fn new(tool: &str, config: Value, shard: Shard, total_items: u64, result: R) -> Self {
        ShardFile {
            format: FORMAT,
            tool: tool.into(),
            config_hash: config_hash(&config),
            config,
            shard,
            total_items,
            items: shard.positions(total_items),
            result,
        }
    }

    /// Its name in an output directory: `sweep-2-of-4.shard.json`.
    pub fn file_name(&self) -> String {
        format!(
            "{}-{}-of-{}{SUFFIX}",
            self.tool, self.shard.index, self.shard.count
        )
    }

    /// Writes it into `dir` and returns the path.
    pub fn write(&self, dir: &Path) -> Result<PathBuf, MergeError> {
        let path = dir.join(self.file_name());
        let text = serde_json::to_string(self).expect("a shard file is plain data");
        std::fs::write(&path, text + "\n").map_err(|source| MergeError::Io {
            path: path.clone(),
            source,
        })?;
        Ok(path)
    }
}

/// The shard files `args` name: each a shard file, or a directory whose
/// `*.shard.json` files are taken (sorted by name).
pub fn shard_files(args: &[PathBuf]) -> Result<Vec<PathBuf>, MergeError> {
    let mut files = Vec::new();
    for arg in args {
        let io = |source| MergeError::Io {
            path: arg.clone(),
            source,
        };
        if arg.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(arg)
                .map_err(io)?
                .map(|e| e.map(|e| e.path()).map_err(io))
                .collect::<Result<_, _>>()?;
            found.retain(|p| {
                p.is_file()
                    && p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| n.ends_with(SUFFIX))
            });
            if found.is_empty() {
                return Err(MergeError::Empty { path: arg.clone() });
            }
            found.sort();
            files.extend(found);
        } else {
            std::fs::metadata(arg).map_err(io)?;
            files.push(arg.clone());
        }
    }
    Ok(files)
}

/// Reads one shard file, checking it against itself: the format, its
/// configuration against its hash, its items against its shard.
pub fn read(path: &Path) -> Result<ShardFile<Value>, MergeError> {
    let text = std::fs::read_to_string(path).map_err(|source| MergeError::Io {
        path: path.into(),
        source,
    })?;
    let foreign = |reason: String| MergeError::Foreign {
        path: path.into(),
        reason,
    };
    let value: Value = serde_json::from_str(&text).map_err(|e| foreign(format!("{e}")))?;
    match value.get("format").and_then(Value::as_u64) {
        Some(f) if f == u64::from(FORMAT) => {}
        Some(f) => {
            return Err(foreign(format!(
                "format {f}, this rtcosim reads format {FORMAT}"
            )))
        }
        None => return Err(foreign("no \"format\" number".into())),
    }
    let file: ShardFile<Value> =
        serde_json::from_value(value).map_err(|e| foreign(format!("{e}")))?;
    let corrupt = |reason: String| MergeError::Corrupt {
        path: path.into(),
        reason,
    };
    let hash = config_hash(&file.config);
    if hash != file.config_hash {
        return Err(corrupt(format!(
            "its configuration hashes to {hash}, not to the config_hash {} it records",
            file.config_hash
        )));
    }
    let shard = Shard::new(file.shard.index, file.shard.count, "its shard")
        .map_err(|e| corrupt(e.to_string()))?;
    let expected = shard.positions(file.total_items);
    if file.items != expected {
        let at = expected
            .iter()
            .zip(&file.items)
            .position(|(a, b)| a != b)
            .unwrap_or(expected.len().min(file.items.len()));
        return Err(corrupt(format!(
            "shard {shard} of {} items holds {} items, not {}; first difference at entry {at}",
            file.total_items,
            file.items.len(),
            expected.len()
        )));
    }
    Ok(file)
}

/// A checked set of shard files: one run, every shard once.
#[derive(Debug)]
pub struct ShardSet {
    pub tool: String,
    pub config: Value,
    /// The files, by shard index.
    pub files: Vec<(PathBuf, ShardFile<Value>)>,
}

/// Reads `paths` ([`shard_files`]) and checks they are the shards of one
/// run, every one exactly once.
pub fn load_set(paths: &[PathBuf]) -> Result<ShardSet, MergeError> {
    let mut by_index: BTreeMap<u64, (PathBuf, ShardFile<Value>)> = BTreeMap::new();
    let mut first: Option<(PathBuf, ShardFile<Value>)> = None;
    for path in paths {
        let file = read(path)?;
        if let Some((p0, f0)) = &first {
            let different = |reason: String| MergeError::Different {
                a: p0.clone(),
                b: path.clone(),
                reason,
            };
            if file.tool != f0.tool {
                return Err(different(format!(
                    "the first is a {} shard, the second a {} shard",
                    f0.tool, file.tool
                )));
            }
            if let Some(reason) = difference("config", &f0.config, &file.config) {
                return Err(different(reason));
            }
            if file.shard.count != f0.shard.count {
                return Err(different(format!(
                    "split into {} and into {} shards",
                    f0.shard.count, file.shard.count
                )));
            }
        } else {
            first = Some((path.clone(), file.clone()));
        }
        if let Some((other, _)) = by_index.get(&file.shard.index) {
            return Err(MergeError::Duplicate {
                shard: file.shard,
                a: other.clone(),
                b: path.clone(),
            });
        }
        by_index.insert(file.shard.index, (path.clone(), file));
    }
    let Some((_, f0)) = first else {
        return Err(MergeError::Missing {
            missing: Vec::new(),
            found: Vec::new(),
            count: 0,
        });
    };
    let count = f0.shard.count;
    let missing: Vec<u64> = (0..count).filter(|i| !by_index.contains_key(i)).collect();
    if !missing.is_empty() {
        return Err(MergeError::Missing {
            missing,
            found: by_index.keys().copied().collect(),
            count,
        });
    }
    Ok(ShardSet {
        tool: f0.tool,
        config: f0.config,
        files: by_index.into_values().collect(),
    })
}

/// The first key where `a` and `b` differ, as `path is A in the first, B
/// in the second`; `None` when equal.
fn difference(path: &str, a: &Value, b: &Value) -> Option<String> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            keys.into_iter().find_map(|k| {
                let p = format!("{path}.{k}");
                match (x.get(k), y.get(k)) {
                    (Some(u), Some(v)) => difference(&p, u, v),
                    (u, v) => Some(format!(
                        "{p} is {} in the first, {} in the second",
                        show(u),
                        show(v)
                    )),
                }
            })
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (u, v))| difference(&format!("{path}[{i}]"), u, v)),
        _ if a == b => None,
        _ => Some(format!(
            "{path} is {} in the first, {} in the second",
            show(Some(a)),
            show(Some(b))
        )),
    }
}

/// A value for a message: its JSON, cut to 60 characters.
fn show(v: Option<&Value>) -> String {
    match v {
        None => "absent".into(),
        Some(v) => {
            let s = v.to_string();
            if s.chars().count() > 60 {
                format!("{}...", s.chars().take(60).collect::<String>())
            } else {
                s
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_first_differing_key_is_named() {
        let a = json!({"seed": 1, "scenes": [{"name": "a"}, {"name": "b"}]});
        let b = json!({"seed": 1, "scenes": [{"name": "a"}, {"name": "c"}]});
        assert_eq!(
            difference("config", &a, &b).as_deref(),
            Some("config.scenes[1].name is \"b\" in the first, \"c\" in the second")
        );
        let c = json!({"seed": 1});
        assert_eq!(
            difference("config", &a, &c).as_deref(),
            Some("config.scenes is [{\"name\":\"a\"},{\"name\":\"b\"}] in the first, absent in the second")
        );
        assert_eq!(difference("config", &a, &a.clone()), None);
    }
}
