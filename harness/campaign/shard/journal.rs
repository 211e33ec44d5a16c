//! A run's journal: each item's result appended to
//! `DIR/<tool>[-K-of-N].journal.jsonl` as soon as it is known (one JSON
//! line, flushed), so that a run killed part way (a crash, a cluster's time
//! limit, Ctrl-C) keeps what it did: run again with the same options and
//! `--out`, it reads the journal, skips the items recorded there and does
//! the rest. The first line names the run ([`super::file::config_hash`] of
//! its configuration, and its shard); a journal of another run is refused,
//! never mixed in. A last line cut short by the kill is dropped. The journal
//! is removed once the run's own results are written.

use super::file::{config_hash, MergeError};
use super::Shard;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The journal's name suffix.
pub const SUFFIX: &str = ".journal.jsonl";

/// The first line: whose journal it is.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
struct Header {
    journal_of: String,
    config_hash: String,
    shard: Shard,
}

/// An open journal, appending.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: Mutex<File>,
    /// The first failed write: the items after it are not journaled.
    lost: Mutex<Option<std::io::Error>>,
}

/// What an earlier run recorded.
#[derive(Debug)]
pub struct Resumed<R> {
    pub items: Vec<R>,
    /// Whether a journal was there (even one with no item yet).
    pub found: bool,
}

impl Journal {
    /// `dir`'s journal of the run of `tool` with `config` (as
    /// [`super::file::run_config`] makes it), shard `shard`: opened to
    /// append, with the items an earlier run of the same configuration and
    /// shard recorded; created if there is none.
    pub fn open<R: DeserializeOwned>(
        dir: &Path,
        tool: &str,
        config: &Value,
        shard: Option<Shard>,
    ) -> Result<(Journal, Resumed<R>), MergeError> {
        let name = match shard {
            Some(s) => format!("{tool}-{}-of-{}{SUFFIX}", s.index, s.count),
            None => format!("{tool}{SUFFIX}"),
        };
        let path = dir.join(name);
        let io = |source| MergeError::Io {
            path: path.clone(),
            source,
        };
        let header = Header {
            journal_of: tool.into(),
            config_hash: config_hash(config),
            shard: shard.unwrap_or(Shard::WHOLE),
        };
        let mut items = Vec::new();
        let found = path.exists();
        let mut keep = 0;
        if found {
            let text = std::fs::read_to_string(&path).map_err(io)?;
            // Whole lines only: a last line without its newline was cut
            // short by the kill.
            let whole = text.rfind('\n').map_or(0, |i| i + 1);
            let mut lines = text[..whole].lines().enumerate();
            let corrupt = |line: usize, reason: String| MergeError::Corrupt {
                path: path.clone(),
                reason: format!("line {}: {reason}", line + 1),
            };
            match lines.next() {
                None => {}
                Some((n, first)) => {
                    let got: Header = serde_json::from_str(first)
                        .map_err(|e| corrupt(n, format!("not a journal's header: {e}")))?;
                    if got != header {
                        return Err(MergeError::Foreign {
                            path: path.clone(),
                            reason: format!(
                                "it is the journal of another run ({} shard {}, configuration {}; this run: \
                                 {} shard {}, configuration {}): delete it to start afresh, or give another \
                                 output directory",
                                got.journal_of,
                                got.shard,
                                got.config_hash,
                                header.journal_of,
                                header.shard,
                                header.config_hash
                            ),
                        });
                    }
                    for (n, line) in lines {
                        items.push(
                            serde_json::from_str(line).map_err(|e| corrupt(n, e.to_string()))?,
                        );
                    }
                    keep = whole;
                }
            }
        }
        let mut file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .map_err(io)?;
        // Drop what is not whole lines (or everything, header too, if the
        // header itself was cut short), then write the header if it is not
        // there.
        file.set_len(keep as u64).map_err(io)?;
        if keep == 0 {
            let line = serde_json::to_string(&header).expect("a header is plain data");
            writeln!(file, "{line}")
                .and_then(|()| file.flush())
                .map_err(io)?;
        }
        let journal = Journal {
            path,
            file: Mutex::new(file),
            lost: Mutex::new(None),
        };
        Ok((journal, Resumed { items, found }))
    }

    /// The journal's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends `item` (one line, flushed). A failed write is kept for
    /// [`Journal::finish`]: the run goes on, its results are in memory.
    pub fn record<R: Serialize>(&self, item: &R) {
        let line = serde_json::to_string(item).expect("a journal's item is plain data") + "\n";
        let mut file = self.file.lock().unwrap_or_else(|p| p.into_inner());
        if let Err(e) = file.write_all(line.as_bytes()).and_then(|()| file.flush()) {
            let mut lost = self.lost.lock().unwrap_or_else(|p| p.into_inner());
            lost.get_or_insert(e);
        }
    }

    /// Called once the run's results are written: removes the journal, or
    /// says which write failed (the journal is then left as it is).
    pub fn finish(self) -> Result<(), MergeError> {
        let io = |source| MergeError::Io {
            path: self.path.clone(),
            source,
        };
        if let Some(e) = self.lost.into_inner().unwrap_or_else(|p| p.into_inner()) {
            return Err(io(e));
        }
        drop(self.file);
        std::fs::remove_file(&self.path).map_err(io)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("rtcosim-journal-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("scratch dir");
        d
    }

    #[test]
    fn a_journal_resumes_its_run_and_drops_a_line_cut_short() {
        let d = dir("resume");
        let config = json!({"seed": 1});
        let shard = Some(Shard::new(1, 4, "test").expect("shard"));
        let (j, r) = Journal::open::<u32>(&d, "mutate", &config, shard).expect("open");
        assert!(!r.found && r.items.is_empty());
        assert!(j.path().ends_with("mutate-1-of-4.journal.jsonl"));
        j.record(&7u32);
        j.record(&9u32);
        let path = j.path().to_path_buf();
        drop(j);
        // Killed in the middle of a line.
        let mut f = OpenOptions::new().append(true).open(&path).expect("reopen");
        write!(f, "1").expect("partial line");
        drop(f);
        let (j, r) = Journal::open::<u32>(&d, "mutate", &config, shard).expect("resume");
        assert!(r.found);
        assert_eq!(r.items, vec![7, 9]);
        j.record(&11u32);
        drop(j);
        let (j, r) = Journal::open::<u32>(&d, "mutate", &config, shard).expect("resume again");
        assert_eq!(r.items, vec![7, 9, 11]);
        j.finish().expect("finish");
        assert!(
            !path.exists(),
            "the journal is removed once the results are written"
        );
    }

    #[test]
    fn another_runs_or_a_damaged_journal_is_refused_by_name() {
        let d = dir("refuse");
        let (j, _) = Journal::open::<u32>(&d, "mutate", &json!({"seed": 1}), None).expect("open");
        j.record(&1u32);
        let path = j.path().to_path_buf();
        drop(j);
        let err =
            Journal::open::<u32>(&d, "mutate", &json!({"seed": 2}), None).expect_err("another run");
        let text = err.to_string();
        assert!(
            text.contains("mutate.journal.jsonl")
                && text.contains("another run")
                && text.contains("delete it"),
            "{text}"
        );
        std::fs::write(
            &path,
            std::fs::read_to_string(&path).expect("read") + "{\"no\n",
        )
        .expect("damage");
        let err =
            Journal::open::<u32>(&d, "mutate", &json!({"seed": 1}), None).expect_err("damaged");
        assert!(err.to_string().contains("line 3"), "{err}");
    }
}
