//! A campaign's options, its summary (merged across shards) and its
//! report.

use super::*;

/// Every option of a campaign that affects its results.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Campaign {
    /// Whose mutants (shard files before the fast processor's: compact).
    #[serde(default)]
    pub processor: ProcessorKind,
    pub judge: JudgeSpec,
    /// The mutants judged, in order (the work list).
    pub mutants: Vec<u16>,
    /// The list's RTL hash.
    pub rtl_hash: String,
    /// The Verilator that built the netlist.
    pub verilator: String,
}

impl Campaign {
    /// The mutants `shard` judges.
    pub fn ids(&self, shard: Shard) -> Vec<u16> {
        shard
            .positions(self.mutants.len() as u64)
            .into_iter()
            .map(|i| self.mutants[i as usize])
            .collect()
    }
}

/// A campaign's (or a shard's) results, as merged.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Checks in the judge, and the pixels a survivor faces.
    pub checks: u64,
    pub judge_pixels: u64,
    /// By mutant number.
    pub outcomes: Vec<Outcome>,
    /// Survivors' equivalence, where it was asked.
    pub equivalence: BTreeMap<u16, Equivalence>,
}

impl Summary {
    pub fn merge(&mut self, other: Summary) {
        self.outcomes.extend(other.outcomes);
        self.outcomes.sort_by_key(|o| o.id);
        self.equivalence.extend(other.equivalence);
    }

    pub fn killed(&self) -> usize {
        self.outcomes
            .iter()
            .filter(|o| matches!(o.verdict, Verdict::Killed { .. }))
            .count()
    }

    pub fn survivors(&self) -> Vec<u16> {
        self.outcomes
            .iter()
            .filter(|o| o.verdict == Verdict::Survived)
            .map(|o| o.id)
            .collect()
    }
}

/// Per module: (mutants, killed, survivors proved or argued equivalent).
fn per_module(list: &List, summary: &Summary) -> BTreeMap<String, (u64, u64, u64)> {
    let mut rows: BTreeMap<String, (u64, u64, u64)> = BTreeMap::new();
    for o in &summary.outcomes {
        let module = list
            .mutants
            .get(usize::from(o.id).wrapping_sub(1))
            .map_or("?", |m| m.module.as_str());
        let row = rows.entry(module.to_string()).or_default();
        row.0 += 1;
        row.1 += u64::from(matches!(o.verdict, Verdict::Killed { .. }));
        row.2 += u64::from(summary.is_equivalent(list, o.id));
    }
    rows
}

fn percent(part: u64, whole: u64) -> String {
    if whole == 0 {
        "-".into()
    } else {
        format!("{:.1}%", 100.0 * part as f64 / whole as f64)
    }
}

impl Summary {
    /// Whether survivor `id` is proved equivalent (Yosys, this run) or
    /// classified equivalent or unreachable ([`Files::survivors_path`]).
    pub fn is_equivalent(&self, list: &List, id: u16) -> bool {
        self.outcomes
            .iter()
            .any(|o| o.id == id && o.verdict == Verdict::Survived)
            && (self.equivalence.get(&id) == Some(&Equivalence::Equivalent)
                || list
                    .classified
                    .get(&id)
                    .is_some_and(|c| c.class.is_equivalent()))
    }

    /// Whether every mutant was killed or proved equivalent.
    pub fn passed(&self) -> bool {
        self.survivors()
            .iter()
            .all(|id| self.equivalence.get(id) == Some(&Equivalence::Equivalent))
    }

    /// The report (Markdown): the score, per module, what killed the
    /// mutants first, the time per mutant, and every survivor.
    pub fn report(&self, list: &List) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let n = self.outcomes.len() as u64;
        let killed = self.killed() as u64;
        let survivors = self.survivors();
        let count = |e: Equivalence| {
            survivors
                .iter()
                .filter(|id| self.equivalence.get(id) == Some(&e))
                .count() as u64
        };
        let equivalent = count(Equivalence::Equivalent);
        let asked = survivors
            .iter()
            .filter(|id| self.equivalence.contains_key(id))
            .count() as u64;
        let _ = writeln!(
            s,
            "mutants: {n} judged, {killed} killed, {} survived; score {} of all, {} of those not proved equivalent",
            survivors.len(),
            percent(killed, n),
            percent(killed, n - equivalent)
        );
        let argued = survivors
            .iter()
            .filter(|&&id| self.is_equivalent(list, id))
            .count() as u64;
        let classes = |c: Class| {
            survivors
                .iter()
                .filter(|id| list.classified.get(id).map(|x| x.class) == Some(c))
                .count()
        };
        let _ = writeln!(
            s,
            "score of those neither proved nor argued equivalent: {} ({argued} survivors are; \
             {}: {} equivalent, {} unreachable, {} holes, {} open, {} not classified)",
            percent(killed, n - argued),
            list.files.survivors_path,
            classes(Class::Equivalent),
            classes(Class::Unreachable),
            classes(Class::Hole),
            classes(Class::Open),
            survivors
                .iter()
                .filter(|id| !list.classified.contains_key(id))
                .count()
        );
        let _ = writeln!(
            s,
            "survivors' equivalence (Yosys): {}",
            if asked == 0 {
                "not asked (--equiv)".to_string()
            } else {
                format!(
                    "{asked} asked: {equivalent} proved equivalent, {} not proved, {} timed out",
                    count(Equivalence::NotProved),
                    count(Equivalence::Timeout)
                )
            }
        );
        let _ = writeln!(
            s,
            "judge: {} checks, {} pixels for a mutant that survives them all",
            self.checks, self.judge_pixels
        );
        let mut times: Vec<f64> = self.outcomes.iter().map(|o| o.seconds).collect();
        times.sort_by(f64::total_cmp);
        if let Some(max) = times.last() {
            let mean = times.iter().sum::<f64>() / times.len() as f64;
            let _ = writeln!(
                s,
                "time per mutant on one thread: mean {mean:.2} s, median {:.2} s, max {max:.2} s",
                times[times.len() / 2]
            );
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "| module | mutants | killed | survived | proved or argued equivalent | score | score of the not equivalent |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|");
        for (module, (m, k, e)) in per_module(list, self) {
            let _ = writeln!(
                s,
                "| {module} | {m} | {k} | {} | {e} | {} | {} |",
                m - k,
                percent(k, m),
                percent(k, m - e)
            );
        }
        let _ = writeln!(s);
        let mut first: BTreeMap<String, u64> = BTreeMap::new();
        for o in &self.outcomes {
            if let Verdict::Killed { check, .. } = &o.verdict {
                *first.entry(check.clone()).or_default() += 1;
            }
        }
        let mut first: Vec<(String, u64)> = first.into_iter().collect();
        first.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let _ = writeln!(s, "killed first by:");
        for (check, k) in &first {
            let _ = writeln!(s, "- {check}: {k}");
        }
        let _ = writeln!(s);
        let _ = writeln!(s, "survivors ({}):", survivors.len());
        if !survivors.is_empty() {
            let _ = writeln!(s);
            let _ = writeln!(
                s,
                "| mutant | module | where | mode | equivalence | classified |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|");
        }
        for id in survivors {
            let (module, location, mode) = list
                .mutants
                .get(usize::from(id).wrapping_sub(1))
                .map_or(("?", "?", "?"), |m| {
                    (m.module.as_str(), m.location.as_str(), m.mode.as_str())
                });
            let equivalence = match self.equivalence.get(&id) {
                Some(Equivalence::Equivalent) => "proved equivalent",
                Some(Equivalence::NotProved) => "not proved",
                Some(Equivalence::Timeout) => "proof timed out",
                None => "not asked",
            };
            let classified = list
                .classified
                .get(&id)
                .map_or("not classified".to_string(), |c| {
                    format!("{}: {}", c.class, c.reason.replace('|', "\\|"))
                });
            let _ = writeln!(
                s,
                "| {id} | {module} | {location} | {mode} | {equivalence} | {classified} |"
            );
        }
        s
    }
}
