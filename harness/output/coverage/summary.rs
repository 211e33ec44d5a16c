//! The figures of a coverage database: points hit per kind and per file,
//! and what was never hit (states, transitions, untoggled bits), with the
//! transitions argued unreachable (`rtl/cover/pp_ctrl.unreachable`) apart.

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

/// The transitions no run from reset can take, each with the group of its
/// argument: `rtl/cover/pp_ctrl.unreachable` (docs/coverage.md).
pub const UNREACHABLE_PATH: &str = "rtl/cover/pp_ctrl.unreachable";
const UNREACHABLE_TEXT: &str = include_str!("../../../rtl/cover/pp_ctrl.unreachable");

/// The transitions of the compact controller's table that the fast
/// controller's ring cannot take, beyond [`UNREACHABLE_PATH`]'s (which hold
/// for both: they are invariants of the ISA's program that both implement):
/// `rtl/cover/fast_ctrl.unreachable`.
pub const FAST_UNREACHABLE_PATH: &str = "rtl/cover/fast_ctrl.unreachable";
const FAST_UNREACHABLE_TEXT: &str = include_str!("../../../rtl/cover/fast_ctrl.unreachable");

/// A transition argued unreachable: the controller (`pp_ctrl`,
/// `fast_ctrl`), from, to, the argument's group.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Argued {
    pub controller: String,
    pub from: String,
    pub to: String,
    pub group: String,
}

impl Argued {
    /// The same argument for `controller`.
    pub fn on(&self, controller: &str) -> Argued {
        Argued {
            controller: controller.into(),
            ..self.clone()
        }
    }
}

/// Parses a list of `controller`'s transitions argued unreachable (`FROM
/// TO GROUP` per line, `#` comments); an error names the line.
pub fn parse_unreachable(text: &str, controller: &str) -> Result<Vec<Argued>, (usize, String)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        match line.split_whitespace().collect::<Vec<_>>()[..] {
            [from, to, group] => out.push(Argued {
                controller: controller.into(),
                from: from.into(),
                to: to.into(),
                group: group.into(),
            }),
            _ => return Err((i + 1, format!("`{line}` is not FROM TO GROUP"))),
        }
    }
    Ok(out)
}

/// The committed lists: [`UNREACHABLE_PATH`]'s for both controllers and
/// [`FAST_UNREACHABLE_PATH`]'s for the fast one. An error names the file
/// and the line.
pub fn unreachable() -> Result<Vec<Argued>, (&'static str, usize, String)> {
    let named = |path| move |(line, message)| (path, line, message);
    let mut all =
        parse_unreachable(UNREACHABLE_TEXT, "pp_ctrl").map_err(named(UNREACHABLE_PATH))?;
    let both: Vec<Argued> = all.iter().map(|a| a.on("fast_ctrl")).collect();
    all.extend(both);
    all.extend(
        parse_unreachable(FAST_UNREACHABLE_TEXT, "fast_ctrl")
            .map_err(named(FAST_UNREACHABLE_PATH))?,
    );
    Ok(all)
}

/// The compact controller's possible transitions: `rtl/cover/pp_ctrl.transitions`
/// (Yosys SAT, one step with every other register free), every pair of ISA
/// states a cycle can take, by name.
pub const TRANSITIONS_PATH: &str = "rtl/cover/pp_ctrl.transitions";
const TRANSITIONS_TEXT: &str = include_str!("../../../rtl/cover/pp_ctrl.transitions");

/// The ISA's reachable transitions: [`TRANSITIONS_PATH`]'s pairs less those
/// argued unreachable for pp_ctrl ([`UNREACHABLE_PATH`]), by state name.
/// What golden's predicted paths (`golden::micro::cover`) are measured
/// against.
pub fn reachable_transitions() -> Result<Vec<(String, String)>, (&'static str, usize, String)> {
    let argued: Vec<(String, String)> = unreachable()?
        .into_iter()
        .filter(|a| a.controller == "pp_ctrl")
        .map(|a| (a.from, a.to))
        .collect();
    let mut out = Vec::new();
    for (i, line) in TRANSITIONS_TEXT.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let pair = match line.split_whitespace().collect::<Vec<_>>()[..] {
            [from, to] => (from.to_string(), to.to_string()),
            _ => return Err((TRANSITIONS_PATH, i + 1, format!("`{line}` is not FROM TO"))),
        };
        if !argued.contains(&pair) {
            out.push(pair);
        }
    }
    Ok(out)
}

/// A transition point of the coverage build: its controller, its states,
/// and the table line that names it.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct TransitionPoint {
    pub controller: String,
    pub from: String,
    pub to: String,
    pub table: String,
    pub line: u32,
}

impl TransitionPoint {
    fn of(p: &super::Point) -> Option<TransitionPoint> {
        let (from, to) = p.transition()?;
        Some(TransitionPoint {
            controller: controller_of(p.module).to_string(),
            from: from.into(),
            to: to.into(),
            table: p.file.into(),
            line: p.line,
        })
    }

    fn json(&self) -> Value {
        json!({
            "controller": self.controller, "from": self.from, "to": self.to,
            "table": self.table, "table_line": self.line,
        })
    }
}

impl std::fmt::Display for TransitionPoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} -> {} ({}:{})",
            self.controller, self.from, self.to, self.table, self.line
        )
    }
}

/// The controller a cover point's module belongs to: `pp_ctrl_cover` is
/// pp_ctrl's.
fn controller_of(module: &str) -> &str {
    module.strip_suffix("_cover").unwrap_or(module)
}

/// A coverage database summed up.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Summary {
    /// Per kind, in [`Kind::ALL`] order (kinds with no point left out).
    pub kinds: Vec<(Kind, KindSummary)>,
    /// Per source file, by name.
    pub files: Vec<FileSummary>,
    /// Controller states never entered (`controller: STATE`, the
    /// controller's name left out when only one was measured).
    pub states_missed: Vec<String>,
    /// Possible transitions (rtl/cover/pp_ctrl.transitions, and for the
    /// fast controller rtl/cover/fast_ctrl.transitions) never taken and
    /// not argued unreachable.
    pub transitions_missed: Vec<TransitionPoint>,
    /// Transitions never taken that are argued unreachable, with the
    /// argument's group.
    pub transitions_argued: Vec<(TransitionPoint, String)>,
    /// Transitions argued unreachable that a run took: the argument is
    /// wrong.
    pub argued_but_taken: Vec<TransitionPoint>,
    /// Lines and branches never run: (file, line, what).
    pub lines_missed: Vec<(String, u32, String)>,
    /// Bits that never toggled, per module: (module, bits).
    pub untoggled: Vec<(String, Vec<String>)>,
}

impl Summary {
    /// `data` summed up; `argued` ([`unreachable`]) sets transitions apart.
    pub fn of(data: &CoverageData, argued: &[Argued]) -> Summary {
        let argument = |t: &TransitionPoint| {
            argued
                .iter()
                .find(|a| a.controller == t.controller && a.from == t.from && a.to == t.to)
        };
        // One controller's states are named bare, two's with the controller.
        let controllers: std::collections::BTreeSet<&str> = data
            .points()
            .filter(|p| p.kind == Kind::State)
            .map(|p| controller_of(p.module))
            .collect();
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
                if let Some(t) = TransitionPoint::of(&p).filter(|t| argument(t).is_some()) {
                    s.argued_but_taken.push(t);
                }
                continue;
            }
            match p.kind {
                Kind::State => s.states_missed.extend(p.state().map(|st| {
                    if controllers.len() > 1 {
                        format!("{}: {st}", controller_of(p.module))
                    } else {
                        st.to_string()
                    }
                })),
                Kind::Transition => {
                    if let Some(t) = TransitionPoint::of(&p) {
                        match argument(&t) {
                            Some(a) => s.transitions_argued.push((t, a.group.clone())),
                            None => s.transitions_missed.push(t),
                        }
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
        s.transitions_missed.sort();
        s.transitions_argued.sort();
        s.argued_but_taken.sort();
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

    /// The transitions that can be taken, and those taken: every possible
    /// transition but the ones argued unreachable and never taken.
    pub fn reachable_transitions(&self) -> KindSummary {
        let all = self.kind(Kind::Transition);
        KindSummary {
            hit: all.hit,
            total: all.total - self.transitions_argued.len() as u64,
        }
    }

    /// One line per kind, for the end of a run's text report.
    pub fn text(&self) -> String {
        let parts: Vec<String> = self
            .kinds
            .iter()
            .map(|(k, v)| match k {
                Kind::Transition => format!(
                    "{} {} (reachable {})",
                    k.name(),
                    v.cell(),
                    self.reachable_transitions().cell()
                ),
                _ => format!("{} {}", k.name(), v.cell()),
            })
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
            "transitions_reachable": self.reachable_transitions().to_json(),
            "files": self.files.iter().map(|f| json!({
                "file": f.file,
                "line": f.line.to_json(),
                "branch": f.branch.to_json(),
                "toggle": f.toggle.to_json(),
            })).collect::<Vec<_>>(),
            "states_missed": self.states_missed,
            "transitions_missed": self.transitions_missed.iter().map(TransitionPoint::json)
                .collect::<Vec<_>>(),
            "transitions_argued_unreachable": self.transitions_argued.iter().map(|(t, group)| {
                let mut j = t.json();
                j["group"] = json!(group);
                j
            }).collect::<Vec<_>>(),
            "argued_unreachable_but_taken": self.argued_but_taken.iter().map(TransitionPoint::json)
                .collect::<Vec<_>>(),
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
            if *k == Kind::Transition {
                let _ = writeln!(
                    md,
                    "| transition, reachable | {} |",
                    self.reachable_transitions().cell()
                );
            }
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
        // A section of transitions, one line each with its table line.
        let transitions = |md: &mut String, heading: String, lines: Vec<String>| {
            let _ = write!(md, "\n## {heading} ({})\n\n", lines.len());
            for l in lines {
                let _ = writeln!(md, "- {l}");
            }
        };
        if !self.argued_but_taken.is_empty() {
            transitions(
                &mut md,
                format!(
                    "Argued unreachable ({UNREACHABLE_PATH}, {FAST_UNREACHABLE_PATH}) but taken: \
                     the argument is wrong"
                ),
                self.argued_but_taken
                    .iter()
                    .map(|t| t.to_string())
                    .collect(),
            );
        }
        transitions(
            &mut md,
            "Transitions never taken, not argued unreachable".into(),
            self.transitions_missed
                .iter()
                .map(|t| t.to_string())
                .collect(),
        );
        transitions(
            &mut md,
            format!(
                "Transitions never taken, argued unreachable (the groups' arguments: \
                 {UNREACHABLE_PATH}, {FAST_UNREACHABLE_PATH})"
            ),
            self.transitions_argued
                .iter()
                .map(|(t, group)| format!("{t}: {group}"))
                .collect(),
        );
        let _ = write!(
            md,
            "\n## Lines and branches never run ({})\n\n",
            self.lines_missed.len()
        );
        for (f, l, what) in &self.lines_missed {
            let _ = writeln!(md, "- {f}:{l} ({what})");
        }
        md += "\n## Bits that never toggled, per module (runs of bits as [high:low])\n\n";
        for (m, bits) in &self.untoggled {
            let _ = writeln!(
                md,
                "- {m} ({}): {}",
                bits.len(),
                bit_ranges(bits).join(", ")
            );
        }
        md
    }
}

/// Toggle points named `signal[i]` (or `array[j][i]`) as runs of
/// consecutive bits per signal, `signal[high:low]` (one bit: `signal[i]`),
/// signals in name order; names without a bit index as they are.
pub fn bit_ranges(bits: &[String]) -> Vec<String> {
    let mut signals: BTreeMap<&str, Vec<u32>> = BTreeMap::new();
    let mut plain = Vec::new();
    for b in bits {
        let bit = b
            .strip_suffix(']')
            .and_then(|s| s.rsplit_once('['))
            .and_then(|(name, i)| Some((name, i.parse::<u32>().ok()?)));
        match bit {
            Some((name, i)) => signals.entry(name).or_default().push(i),
            None => plain.push(b.as_str()),
        }
    }
    let mut out: Vec<(&str, String)> = plain.into_iter().map(|p| (p, p.to_string())).collect();
    for (name, mut idx) in signals {
        idx.sort_unstable();
        idx.dedup();
        let mut runs: Vec<(u32, u32)> = Vec::new();
        for i in idx {
            match runs.last_mut() {
                Some((_, hi)) if *hi + 1 == i => *hi = i,
                _ => runs.push((i, i)),
            }
        }
        for (lo, hi) in runs.into_iter().rev() {
            let text = if lo == hi {
                format!("{name}[{lo}]")
            } else {
                format!("{name}[{hi}:{lo}]")
            };
            out.push((name, text));
        }
    }
    out.sort_by(|a, b| a.0.cmp(b.0));
    out.into_iter().map(|(_, t)| t).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn untoggled_bits_are_listed_as_runs_per_signal() {
        let bits: Vec<String> = [
            "s1_ix[10]",
            "s1_ix[12]",
            "neg_a",
            "s1_ix[11]",
            "inq[1][4]",
            "s1_ix[31]",
            "inq[1][3]",
            "inq[0][3]",
            "a[0]",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(
            bit_ranges(&bits),
            [
                "a[0]",
                "inq[0][3]",
                "inq[1][4:3]",
                "neg_a",
                "s1_ix[31]",
                "s1_ix[12:10]"
            ]
        );
    }

    /// A transition point of the coverage build, counted `count` times.
    fn transition(from: &str, to: &str, line: u32, count: u64) -> String {
        format!(
            "C '\x01f\x02rtl/cover/pp_ctrl.transitions\x01l\x02{line}\x01n\x020\x01page\x02v_user/pp_ctrl_cover\x01o\x02t_{from}_to_{to}\x01S\x02{line}\x01h\x02TOP.pixel_processor.u_ctrl.u_cover.t_{from}_to_{to}' {count}\n"
        )
    }

    #[test]
    fn argued_transitions_leave_the_reachable_figure_and_one_taken_is_named() {
        let text = String::from("# SystemC::Coverage-3\n")
            + &transition("IDLE", "PRI_ITOF", 5, 7)
            + &transition("HIT_CMP", "PIX_DONE", 144, 0)
            + &transition("NORM_SCALE", "PIX_DONE", 39, 0)
            + &transition("POP_ADD", "ROOT_BLACK", 229, 2);
        let data = CoverageData::parse(&text, Path::new("t.dat")).expect("points");
        let argued = parse_unreachable(
            "# two arguments\nHIT_CMP PIX_DONE U4\nPOP_ADD ROOT_BLACK U8\n",
            "pp_ctrl",
        )
        .expect("a list");
        let s = Summary::of(&data, &argued);
        assert_eq!(s.kind(Kind::Transition), KindSummary { hit: 2, total: 4 });
        // HIT_CMP -> PIX_DONE is out of the reachable figure; POP_ADD ->
        // ROOT_BLACK was taken, so it counts, and is named.
        assert_eq!(s.reachable_transitions(), KindSummary { hit: 2, total: 3 });
        let named = |t: &TransitionPoint| (t.from.clone(), t.to.clone(), t.line);
        assert_eq!(
            s.transitions_missed.iter().map(named).collect::<Vec<_>>(),
            [("NORM_SCALE".to_string(), "PIX_DONE".to_string(), 39)]
        );
        assert_eq!(s.transitions_argued.len(), 1);
        assert_eq!(
            (
                s.transitions_argued[0].1.as_str(),
                s.transitions_argued[0].0.line
            ),
            ("U4", 144)
        );
        assert_eq!(
            s.argued_but_taken.iter().map(named).collect::<Vec<_>>(),
            [("POP_ADD".to_string(), "ROOT_BLACK".to_string(), 229)]
        );
        // An argument holds for its controller only.
        let fast_argued: Vec<Argued> = argued.iter().map(|a| a.on("fast_ctrl")).collect();
        assert_eq!(Summary::of(&data, &fast_argued).transitions_missed.len(), 2);
        let md = s.to_markdown();
        assert!(
            md.contains("the argument is wrong") && md.contains("HIT_CMP -> PIX_DONE"),
            "{md}"
        );
        assert!(s.text().contains("reachable 2/3 (66.7%)"), "{}", s.text());
        // Without arguments, every miss is open.
        let bare = Summary::of(&data, &[]);
        assert_eq!(bare.transitions_missed.len(), 2);
        assert_eq!(bare.reachable_transitions(), bare.kind(Kind::Transition));
    }

    #[test]
    fn the_committed_list_reads_and_a_bad_line_is_named() {
        let list = unreachable().expect("the lists read");
        let of = |c: &str| list.iter().filter(|a| a.controller == c).count();
        assert_eq!(of("pp_ctrl"), 57);
        assert_eq!(of("fast_ctrl"), 63);
        assert_eq!(
            parse_unreachable("# c\nA B U1\nA B\n", "pp_ctrl"),
            Err((3, "`A B` is not FROM TO GROUP".to_string()))
        );
    }
}
