//! `rtcosim mutate`: mutants of a pixel processor judged against golden
//! (harness::mutation, docs/mutation.md).

use crate::args::{parse_size, ShardArgs, Size, ThreadsArgs, TimeoutArgs};
use crate::ui::{plural, progress_bar};
use anyhow::{Context, Result};
use rtcosim::campaign::mutation::{self, Campaign, Judge, JudgeSpec, List, Outcome, Summary};
use rtcosim::campaign::shard::file::{self as shard_file, ShardFile};
use rtcosim::campaign::shard::journal::Journal;
use rtcosim::campaign::shard::Shard;
use rtcosim::design::processor::ProcessorKind;
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct MutateArgs {
    /// Whose mutants: the compact processor's
    /// (rtl/mutate/pixel_processor.mutants) or the fast one's
    /// (rtl/mutate/fast_pp.mutants).
    #[arg(long, value_enum, default_value_t = ProcessorKind::default())]
    pub processor: ProcessorKind,
    /// The mutants to judge, by number in the processor's list: a
    /// comma-separated list of N and N-M (default: every one).
    #[arg(long, value_name = "LIST", value_parser = parse_ids)]
    pub mutants: Option<MutantIds>,
    /// The size the judge runs every builtin scene at.
    #[arg(long, value_name = "WxH", default_value = "16x12", value_parser = parse_size)]
    pub size: Size,
    /// Fuzz scenes in the judge after the builtins (those that load).
    #[arg(long, value_name = "N", default_value_t = 20)]
    pub fuzz: u64,
    /// The seed of the judge's fuzz scenes.
    #[arg(long, value_name = "SEED", default_value_t = 1)]
    pub fuzz_seed: u64,
    /// Seeded random operands (seed: --fuzz-seed) through each float unit,
    /// after its edge cases, for a mutant a float unit may carry.
    #[arg(long, value_name = "N", default_value_t = 10_000)]
    pub unit_operands: u64,
    /// Judge with the scene files of DIR (a guided campaign's corpus,
    /// `fuzz --corpus`, or its --minimize-into copy) in the place of the
    /// directed scenes of rtl/mutate/scenes/: each whole at its own size,
    /// with the exact methods (a file equal to a builtin check is left out).
    #[arg(long, value_name = "DIR")]
    pub corpus: Option<PathBuf>,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
    /// Ask Yosys (rtl/mutate/mutants.sh equiv) whether each survivor's
    /// module is equivalent to the original (needs yosys on PATH).
    #[arg(long)]
    pub equiv: bool,
    #[command(flatten)]
    pub threads: ThreadsArgs,
    #[command(flatten)]
    pub shard: ShardArgs,
    /// Write mutation-report.md and mutation.json into DIR (a shard: its
    /// mutate-K-of-N.shard.json, for `rtcosim merge`). Each verdict is
    /// journaled there as it comes (mutate[-K-of-N].journal.jsonl, removed
    /// at the end): run the same command again after a kill and it resumes.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Mutant numbers, ascending, each once (one clap value, not many).
#[derive(Clone, Debug)]
pub struct MutantIds(pub Vec<u16>);

/// `1-5,9` -> [1, 2, 3, 4, 5, 9]: ascending, each once.
fn parse_ids(s: &str) -> Result<MutantIds, String> {
    let bad = || {
        format!("expected mutant numbers N or N-M separated by commas, each 1..=65535, e.g. 1-100,205; got {s:?}")
    };
    let number = |t: &str| {
        t.trim()
            .parse::<u16>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(bad)
    };
    let mut ids = std::collections::BTreeSet::new();
    for part in s.split(',') {
        match part.split_once('-') {
            Some((a, b)) => {
                let (a, b) = (number(a)?, number(b)?);
                if a > b {
                    return Err(bad());
                }
                ids.extend(a..=b);
            }
            None => {
                ids.insert(number(part)?);
            }
        }
    }
    Ok(MutantIds(ids.into_iter().collect()))
}

/// Returns whether every mutant was killed or proved equivalent.
pub fn run(args: MutateArgs) -> Result<bool> {
    if !mutation::BUILT {
        anyhow::bail!(
            "this rtcosim was built without the mutant netlist: build it with the cargo feature \
             `mutation` (needs yosys): cargo run --release --features mutation -- mutate ..."
        );
    }
    let list = List::committed(args.processor)?;
    let total = list.mutants.len();
    let mutants: Vec<u16> = match &args.mutants {
        Some(MutantIds(ids)) => {
            if let Some(bad) = ids.iter().find(|&&id| usize::from(id) > total) {
                anyhow::bail!(
                    "--mutants: there is no mutant {bad}: {} lists 1..={total}",
                    list.files.list_path
                );
            }
            ids.clone()
        }
        None => list.mutants.iter().map(|m| m.id).collect(),
    };
    let shard = args.shard.resolve()?;
    if let (Some(shard), None) = (shard, &args.out) {
        anyhow::bail!("shard {shard}: a shard writes its shard file into --out DIR; give --out");
    }
    if let Some(out) = &args.out {
        std::fs::create_dir_all(out).with_context(|| format!("--out {}", out.display()))?;
    }
    let spec = JudgeSpec {
        width: args.size.width,
        height: args.size.height,
        fuzz_seed: args.fuzz_seed,
        fuzz_count: args.fuzz,
        unit_operands: args.unit_operands,
        timeout_cycles: args.timeout.cycles(args.processor),
        corpus: None,
    };
    let judge = match &args.corpus {
        Some(dir) => Judge::with_corpus(args.processor, spec, &mutation::Corpus::load(dir)?)?,
        None => Judge::new(args.processor, spec)?,
    };
    let spec = judge.spec;
    let campaign = Campaign {
        processor: args.processor,
        judge: spec,
        mutants,
        rtl_hash: list.rtl_hash.clone(),
        verilator: rtcosim::VERILATOR_VERSION.into(),
    };
    let ids = campaign.ids(shard.unwrap_or(Shard::WHOLE));
    // With --out, each verdict is journaled as it comes: a campaign killed
    // part way resumes where it stopped (a journal of another campaign is
    // refused before anything runs).
    let config = shard_file::run_config(&campaign);
    let (journal, mut outcomes, resumed_found) = match &args.out {
        Some(dir) => {
            let (journal, resumed) = Journal::open::<Outcome>(dir, mutation::TOOL, &config, shard)?;
            let wanted: BTreeSet<u16> = ids.iter().copied().collect();
            let mut earlier: Vec<Outcome> = resumed
                .items
                .into_iter()
                .filter(|o| wanted.contains(&o.id))
                .collect();
            earlier.sort_by_key(|o| o.id);
            earlier.dedup_by_key(|o| o.id);
            (Some(journal), earlier, resumed.found)
        }
        None => (None, Vec::new(), false),
    };
    let pool = args.threads.pool()?;
    let threads = pool.current_num_threads();
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "rtcosim mutate: {} of the {total} mutants of {}{}, {threads} thread{}, {}",
        campaign.mutants.len(),
        list.files.list_path,
        shard.map_or(String::new(), |s| format!(
            ", shard {s} ({} mutants)",
            ids.len()
        )),
        plural(threads as u64),
        rtcosim::VERILATOR_VERSION
    )?;
    let last = mutation::last_check(args.processor);
    let units = format!(
        "for a mutant a float unit may carry, its edge cases and {} random operands through each of the {} units \
         ({} operands); {last}",
        spec.unit_operands,
        mutation::units(args.processor).count(),
        judge.unit_operands(),
    );
    writeln!(
        out,
        "judge: {units}every builtin scene at {}x{}, the {} directed scenes of {}, and the {} of {} \
         fuzz scenes of seed {} that load: {} {} checks, {} pixels",
        spec.width,
        spec.height,
        judge.directed,
        judge.directed_from,
        judge.scenes() - golden::scene::Scene::builtin_names().len() - judge.directed,
        spec.fuzz_count,
        spec.fuzz_seed,
        judge.checks.len(),
        args.processor,
        judge.pixels()
    )?;
    out.flush()?;
    // The netlist with no mutant selected must pass, or nothing below means
    // anything.
    let start = Instant::now();
    let baseline = mutation::judge(0, true, &judge)?;
    if let mutation::Verdict::Killed { check, how } = &baseline.verdict {
        anyhow::bail!(
            "the netlist with no mutant selected (mutsel = 0) fails the judge at {check}: {how}"
        );
    }
    writeln!(
        out,
        "the netlist with no mutant selected passes the judge ({} pixels, {:.2} s)",
        baseline.pixels, baseline.seconds
    )?;
    writeln!(out)?;
    out.flush()?;
    if let Some(journal) = &journal {
        if resumed_found {
            writeln!(
                out,
                "resuming: {} of the {} mutants judged before, as {} recorded",
                outcomes.len(),
                ids.len(),
                journal.path().display()
            )?;
        }
    }
    let judged: BTreeSet<u16> = outcomes.iter().map(|o| o.id).collect();
    let todo: Vec<u16> = ids
        .iter()
        .copied()
        .filter(|id| !judged.contains(id))
        .collect();
    let bar = progress_bar(
        todo.len() as u64,
        "judging",
        "{pos}/{len} mutants ({per_sec}, {eta})",
    )?;
    let done = |o: &Outcome| {
        if let Some(j) = &journal {
            j.record(o);
        }
        bar.inc(1);
    };
    outcomes.extend(pool.install(|| mutation::run(&todo, &list, &judge, &done))?);
    bar.finish_and_clear();
    outcomes.sort_by_key(|o| o.id);
    let mut summary = Summary {
        checks: judge.checks.len() as u64,
        judge_pixels: judge.pixels(),
        outcomes,
        equivalence: Default::default(),
    };
    if args.equiv {
        let survivors = summary.survivors();
        writeln!(
            out,
            "asking Yosys whether the {} survivor{} are equivalent ...",
            survivors.len(),
            plural(survivors.len() as u64)
        )?;
        out.flush()?;
        summary.equivalence = mutation::prove_equivalent(args.processor, &survivors)
            .map_err(|e| anyhow::anyhow!("--equiv: {e}"))?;
    }
    match (shard, &args.out) {
        (Some(shard), Some(dir)) => {
            write!(out, "{}", summary.report(&list))?;
            let file = ShardFile::new(
                mutation::TOOL,
                config,
                shard,
                campaign.mutants.len() as u64,
                &summary,
            );
            writeln!(out, "wrote {}", file.write(dir)?.display())?;
        }
        _ => finish(&mut out, &summary, &list, args.out.as_deref())?,
    }
    if let Some(journal) = journal {
        let path = journal.path().to_path_buf();
        journal.finish().with_context(|| {
            format!(
                "the results are written, but the journal {} lost a verdict",
                path.display()
            )
        })?;
    }
    writeln!(
        out,
        "{} mutants in {:.1} s",
        summary.outcomes.len(),
        start.elapsed().as_secs_f64()
    )?;
    Ok(summary.passed())
}

/// The report's file names in --out.
pub const REPORT: &str = "mutation-report.md";
pub const JSON: &str = "mutation.json";

/// The report of a whole campaign: printed, and with `dir` written to
/// mutation-report.md and mutation.json. The unsharded campaign and
/// `rtcosim merge` both end here.
pub fn finish(
    out: &mut impl Write,
    summary: &Summary,
    list: &List,
    dir: Option<&Path>,
) -> Result<()> {
    let text = summary.report(list);
    out.write_all(text.as_bytes())?;
    if let Some(dir) = dir {
        let path = dir.join(REPORT);
        std::fs::write(&path, &text).with_context(|| format!("writing {}", path.display()))?;
        let json = dir.join(JSON);
        std::fs::write(&json, serde_json::to_string_pretty(summary)?)
            .with_context(|| format!("writing {}", json.display()))?;
        writeln!(out, "wrote {} and {}", path.display(), json.display())?;
    }
    Ok(())
}
