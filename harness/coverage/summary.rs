//! The figures of a coverage database: points hit per kind and per file,
//! and what was never hit (states, transitions, untoggled bits).

use super::dat::{CoverageData, Kind};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// Points of one kind: how many, how many counted at least once.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KindSummary {
    pub hit: u64,
    pub total: u64,
}

impl KindSummary {
    fn add(&mut self, count: u64) {
        self.total += 1;
        if count > 0 {
            self.hit += 1;
        }
    }

    /// Hit points in percent (100 for no points).
    pub fn percent(&self) -> f64 {
        if self.total == 0 {
            100.0
        } else {
            100.0 * self.hit as f64 / self.total as f64
        }
    }

    fn to_json(self) -> Value {
        json!({ "hit": self.hit, "total": self.total, "percent": self.percent() })
    }

    fn cell(self) -> String {
        if self.total == 0 {
            "-".into()
        } else {
            format!("{}/{} ({:.1}%)", self.hit, self.total, self.percent())
        }
    }
}

/// One source file's line, branch and toggle points.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FileSummary {
    pub file: String,
    pub line: KindSummary,
    pub branch: KindSummary,
    pub toggle: KindSummary,
}

/// A coverage database summed up.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Summary {
    /// Per kind, in [`Kind::ALL`] order (kinds with no point left out).
    pub kinds: Vec<(Kind, KindSummary)>,
    /// Per source file, by name.
    pub files: Vec<FileSummary>,
    /// Controller states never entered.
    pub states_missed: Vec<String>,
    /// Possible transitions (rtl/cover/pp_ctrl.transitions) never taken:
    /// (from, to, the table's line).
    pub transitions_missed: Vec<(String, String, u32)>,
    /// Lines and branches never run: (file, line, what).
    pub lines_missed: Vec<(String, u32, String)>,
    /// Bits that never toggled, per module: (module, bits).
    pub untoggled: Vec<(String, Vec<String>)>,
}

impl Summary {
    pub fn of(data: &CoverageData) -> Summary {
        let mut kinds: BTreeMap<Kind, KindSummary> = BTreeMap::new();
        let mut files: BTreeMap<String, FileSummary> = BTreeMap::new();
        let mut s = Summary::default();
        let mut untoggled: BTreeMap<String, Vec<String>> = BTreeMap::new();
        for p in data.points() {
            kinds.entry(p.kind).or_default().add(p.count);
            let file = || FileSummary {
                file: p.file.to_string(),
                ..FileSummary::default()
            };
            match p.kind {
                Kind::Line | Kind::Branch | Kind::Toggle => {
                    let f = files.entry(p.file.to_string()).or_insert_with(file);
                    let k = match p.kind {
                        Kind::Line => &mut f.line,
                        Kind::Branch => &mut f.branch,
                        _ => &mut f.toggle,
                    };
                    k.add(p.count);
                }
                _ => {}
            }
            if p.count > 0 {
                continue;
            }
            match p.kind {
                Kind::State => s.states_missed.extend(p.state().map(str::to_string)),
                Kind::Transition => {
                    if let Some((a, b)) = p.transition() {
                        s.transitions_missed.push((a.into(), b.into(), p.line));
                    }
                }
                Kind::Line | Kind::Branch => {
                    s.lines_missed
                        .push((p.file.into(), p.line, p.comment.into()))
                }
                Kind::Toggle => untoggled
                    .entry(p.module.to_string())
                    .or_default()
                    .push(p.comment.to_string()),
                Kind::User => {}
            }
        }
        s.kinds = Kind::ALL
            .iter()
            .filter_map(|k| kinds.get(k).map(|v| (*k, *v)))
            .collect();
        s.files = files.into_values().collect();
        s.transitions_missed.sort_by_key(|t| t.2);
        s.lines_missed.sort();
        s.untoggled = untoggled.into_iter().collect();
        s
    }

    /// The summary of one kind (zero points if there are none).
    pub fn kind(&self, kind: Kind) -> KindSummary {
        self.kinds
            .iter()
            .find(|(k, _)| *k == kind)
            .map_or_else(KindSummary::default, |(_, v)| *v)
    }

    /// One line per kind, for the end of a run's text report.
    pub fn text(&self) -> String {
        let parts: Vec<String> = self
            .kinds
            .iter()
            .map(|(k, v)| format!("{} {}", k.name(), v.cell()))
            .collect();
        format!("coverage: {}", parts.join(", "))
    }

    pub fn to_json(&self) -> Value {
        let kinds: serde_json::Map<String, Value> = self
            .kinds
            .iter()
            .map(|(k, v)| (k.name().to_string(), v.to_json()))
            .collect();
        json!({
            "kinds": kinds,
            "files": self.files.iter().map(|f| json!({
                "file": f.file,
                "line": f.line.to_json(),
                "branch": f.branch.to_json(),
                "toggle": f.toggle.to_json(),
            })).collect::<Vec<_>>(),
            "states_missed": self.states_missed,
            "transitions_missed": self.transitions_missed.iter().map(|(a, b, l)| json!({
                "from": a, "to": b, "table_line": l,
            })).collect::<Vec<_>>(),
            "lines_missed": self.lines_missed.iter().map(|(f, l, what)| json!({
                "file": f, "line": l, "what": what,
            })).collect::<Vec<_>>(),
            "untoggled": self.untoggled.iter().map(|(m, bits)| json!({
                "module": m, "bits": bits,
            })).collect::<Vec<_>>(),
        })
    }

    pub fn to_markdown(&self) -> String {
        let mut md = String::from("# RTL coverage\n\n| kind | points hit |\n|---|---|\n");
        for (k, v) in &self.kinds {
            let _ = writeln!(md, "| {} | {} |", k.name(), v.cell());
        }
        md += "\n| file | line | branch | toggle |\n|---|---|---|---|\n";
        for f in &self.files {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} |",
                f.file,
                f.line.cell(),
                f.branch.cell(),
                f.toggle.cell()
            );
        }
        let _ = write!(
            md,
            "\n## States never entered ({})\n\n",
            self.states_missed.len()
        );
        for s in &self.states_missed {
            let _ = writeln!(md, "- {s}");
        }
        let _ = write!(
            md,
            "\n## Transitions never taken ({})\n\n",
            self.transitions_missed.len()
        );
        for (a, b, l) in &self.transitions_missed {
            let _ = writeln!(md, "- {a} -> {b} (rtl/cover/pp_ctrl.transitions:{l})");
        }
        let _ = write!(
            md,
            "\n## Lines and branches never run ({})\n\n",
            self.lines_missed.len()
        );
        for (f, l, what) in &self.lines_missed {
            let _ = writeln!(md, "- {f}:{l} ({what})");
        }
        md += "\n## Bits that never toggled, per module\n\n";
        for (m, bits) in &self.untoggled {
            let shown: Vec<&str> = bits.iter().take(12).map(String::as_str).collect();
            let more = if bits.len() > shown.len() {
                format!(", ... ({} in all)", bits.len())
            } else {
                String::new()
            };
            let _ = writeln!(md, "- {m}: {}{more}", shown.join(", "));
        }
        md
    }
}
