//! `rtcosim fuzz`: random scenes, each refused at load or co-simulated with
//! 0 divergences and finite colours.

use crate::args::{parse_fault, CoverageArgs, ShardArgs, ThreadsArgs, TimeoutArgs};
use crate::ui::{plural, progress_bar};
use anyhow::{Context, Result};
use golden::micro::isa;
use rtcosim::campaign::fuzz::chart;
use rtcosim::campaign::fuzz::guided::{self, GuidedOptions, GuidedReport, Strategy};
use rtcosim::campaign::fuzz::summary::{self, Campaign, Summary};
use rtcosim::campaign::fuzz::{self, FuzzOptions};
use rtcosim::campaign::shard::file::{self as shard_file, ShardFile};
use rtcosim::campaign::shard::Shard;
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::Fault;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct FuzzArgs {
    /// Scenes to generate.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true)]
    pub count: u64,
    /// Seed of the campaign: scene I of seed S is always the same file.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// The first scene index (to continue a campaign, or split it).
    #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
    pub first: u64,
    /// Where to write each failing scene, as seed-S-scene-I.toml (replay it
    /// with `rtcosim cosim --scene FILE`).
    #[arg(long, value_name = "DIR", default_value = "fuzz-failures")]
    pub failures: PathBuf,
    /// The pixel processor the scenes run on: compact or fast (as `cosim
    /// --processor`).
    #[arg(long, value_enum, default_value_t = ProcessorKind::default())]
    pub processor: ProcessorKind,
    #[command(flatten)]
    pub threads: ThreadsArgs,
    #[command(flatten)]
    pub shard: ShardArgs,
    /// Write the report to DIR/fuzz-report.txt (a shard: its
    /// fuzz-K-of-N.shard.json, for `rtcosim merge`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Self-test of the campaign: inject this fault (as `cosim --fault`)
    /// into the RTL of every scene, so the campaign must fail.
    #[arg(long, value_name = "STATE:XOR", value_parser = parse_fault)]
    pub fault: Option<Fault>,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
    #[command(flatten)]
    pub coverage: CoverageArgs,
    /// A guided campaign: keep in DIR every candidate that reaches a
    /// controller transition or a written value class no corpus scene
    /// reached (golden predicts both), and mutate the corpus for the next
    /// candidates. DIR starts with the builtin scenes at 16x12 and keeps
    /// whatever scene files it already holds; --count is the candidates.
    #[arg(long, value_name = "DIR")]
    pub corpus: Option<PathBuf>,
    /// With --corpus: mutate the corpus (guided), or draw fresh scenes only
    /// (random: the scenes of plain fuzz, measured the same way).
    #[arg(long, value_enum, default_value_t = Strategy::Guided, requires = "corpus")]
    pub strategy: Strategy,
    /// With --corpus: a candidate with more pixels is not run.
    #[arg(long, value_name = "N", default_value_t = 256, requires = "corpus")]
    pub max_pixels: u64,
    /// With --corpus: run no candidate, but copy into OUT the fewest
    /// corpus scenes that together reach every point the corpus reaches.
    #[arg(long, value_name = "OUT", requires = "corpus")]
    pub minimize_into: Option<PathBuf>,
    /// Run no candidate, but draw the coverage curves of these guided
    /// campaigns (the guided.json of `fuzz --corpus DIR --out OUT`) into
    /// --out DIR as coverage.svg and coverage.png: a guided and a random
    /// campaign from the same budget, compared.
    #[arg(long, value_name = "GUIDED_JSON", num_args = 1.., conflicts_with = "corpus")]
    pub chart: Vec<PathBuf>,
}

/// Returns whether every scene kept the promise (a shard's, its scenes).
pub fn run(args: FuzzArgs) -> Result<bool> {
    if !args.chart.is_empty() {
        return draw_chart(&args);
    }
    if let Some(corpus) = &args.corpus {
        return run_guided(&args, corpus);
    }
    if args.first.checked_add(args.count).is_none() {
        anyhow::bail!(
            "--first {} with --count {}: the scenes would run past the last index, {}",
            args.first,
            args.count,
            u64::MAX
        );
    }
    let shard = args.shard.resolve()?;
    if let (Some(shard), None) = (shard, &args.out) {
        anyhow::bail!("shard {shard}: a shard writes its shard file into --out DIR; give --out");
    }
    if let Some(out) = &args.out {
        std::fs::create_dir_all(out).with_context(|| format!("--out {}", out.display()))?;
    }
    args.coverage.enable()?;
    let campaign = Campaign {
        processor: args.processor.name().to_string(),
        seed: args.seed,
        first: args.first,
        count: args.count,
        timeout_cycles: args.timeout.cycles(args.processor),
        fault: args.fault.map(|f| f.to_string()),
        failures: args.failures.display().to_string(),
        verilator: rtcosim::VERILATOR_VERSION.into(),
    };
    let indices = campaign.indices(shard.unwrap_or(Shard::WHOLE));
    let pool = models_and_pool(&args)?;
    let threads = pool.current_num_threads();
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "rtcosim fuzz: {} scene{} from index {}, seed {}{}{}, {threads} thread{}, {}",
        args.count,
        plural(args.count),
        args.first,
        args.seed,
        shard.map_or(String::new(), |s| format!(
            ", shard {s} ({} scenes)",
            indices.len()
        )),
        // The default processor goes unnamed.
        if args.processor == ProcessorKind::default() {
            String::new()
        } else {
            format!(", {} processor", args.processor)
        },
        plural(threads as u64),
        rtcosim::VERILATOR_VERSION
    )?;
    writeln!(out)?;
    out.flush()?;
    let options = FuzzOptions {
        seed: args.seed,
        first: args.first,
        count: args.count,
        failures_dir: Some(args.failures.clone()),
        timeout_cycles: args.timeout.cycles(args.processor),
        fault: args.fault,
        processor: args.processor,
    };
    let bar = progress_bar(
        indices.len() as u64,
        "fuzzing",
        "{pos}/{len} scenes ({per_sec}, {eta})",
    )?;
    let start = Instant::now();
    let report = pool
        .install(|| fuzz::run_indices(&options, &indices, &|n| bar.inc(n)))
        .with_context(|| format!("writing failing scenes to {}", args.failures.display()))?;
    bar.finish_and_clear();
    let seconds = start.elapsed().as_secs_f64();
    let summary = Summary::from(&report);
    match (shard, &args.out) {
        (Some(shard), Some(dir)) => {
            report_text(&mut out, &summary)?;
            let file = ShardFile::new(
                summary::TOOL,
                shard_file::run_config(&campaign),
                shard,
                campaign.count,
                &summary,
            );
            writeln!(out, "wrote {}", file.write(dir)?.display())?;
        }
        _ => finish(&mut out, &summary, args.out.as_deref())?,
    }
    closing(&mut out, &args.coverage, summary.scenes, "scenes", seconds)?;
    Ok(summary.passed())
}

/// The end of a campaign's output: the coverage reports, if asked for,
/// and the rate (`N scenes in S s`).
fn closing(
    out: &mut impl Write,
    coverage: &CoverageArgs,
    count: u64,
    noun: &str,
    seconds: f64,
) -> Result<()> {
    coverage.finish(out)?;
    writeln!(
        out,
        "{count} {noun} in {seconds:.1} s ({:.1} {noun}/s)",
        count as f64 / seconds.max(1e-9)
    )?;
    Ok(())
}

/// Refuses a campaign whose models this build lacks (the scenes draw every
/// method pair), then makes the worker pool.
fn models_and_pool(args: &FuzzArgs) -> Result<rayon::ThreadPool> {
    rtcosim::campaign::fuzz::check_models(args.processor)
        .map_err(|e| anyhow::anyhow!("fuzz draws every method pair, and needs {e}"))?;
    args.threads.pool()
}

/// `refused by field: F N, ...`, the most refused first.
fn refused_line(
    out: &mut impl Write,
    by_field: &std::collections::BTreeMap<String, u64>,
) -> std::io::Result<()> {
    if by_field.is_empty() {
        return Ok(());
    }
    let mut by_count: Vec<(&String, &u64)> = by_field.iter().collect();
    by_count.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
    let list: Vec<String> = by_count.iter().map(|(f, n)| format!("{f} {n}")).collect();
    writeln!(out, "refused by field: {}", list.join(", "))
}

/// The guided campaign's report in --out.
pub const GUIDED_REPORT: &str = "guided.json";

/// `fuzz --corpus DIR`: the guided campaign (or its random baseline).
fn run_guided(args: &FuzzArgs, corpus: &Path) -> Result<bool> {
    if let Some(into) = &args.minimize_into {
        let (all, kept, points) = guided::minimize_into(corpus, into)?;
        println!(
            "{}: {all} scene{}, {points} points; the fewest that reach them all: {kept}, copied into {}",
            corpus.display(),
            plural(all as u64),
            into.display()
        );
        return Ok(true);
    }
    if args.shard.resolve()?.is_some() {
        anyhow::bail!(
            "--corpus: a guided campaign is one sequence (each candidate comes from the corpus \
             the earlier ones left); run it unsharded"
        );
    }
    if args.first != 0 {
        anyhow::bail!("--corpus: --first does not apply (candidates are numbered from 0)");
    }
    if args.max_pixels == 0 {
        anyhow::bail!("--max-pixels 0: no scene has fewer than one pixel");
    }
    if let Some(out) = &args.out {
        std::fs::create_dir_all(out).with_context(|| format!("--out {}", out.display()))?;
    }
    args.coverage.enable()?;
    let pool = models_and_pool(args)?;
    let threads = pool.current_num_threads();
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "rtcosim fuzz: {} campaign, {} candidate{}, seed {}, corpus {}, {} processor, {threads} thread{}, {}",
        match args.strategy {
            Strategy::Random => "random (fresh scenes only)",
            s => s.name(),
        },
        args.count,
        plural(args.count),
        args.seed,
        corpus.display(),
        args.processor,
        plural(threads as u64),
        rtcosim::VERILATOR_VERSION
    )?;
    writeln!(out)?;
    out.flush()?;
    let options = GuidedOptions {
        seed: args.seed,
        count: args.count,
        corpus: corpus.to_path_buf(),
        strategy: args.strategy,
        max_pixels: args.max_pixels,
        failures_dir: args.failures.clone(),
        timeout_cycles: args.timeout.cycles(args.processor),
        fault: args.fault,
        processor: args.processor,
    };
    let bar = progress_bar(
        args.count,
        "fuzzing",
        "{pos}/{len} candidates, {msg} ({per_sec}, {eta})",
    )?;
    let start = Instant::now();
    let report = pool.install(|| {
        guided::run(&options, &|p| {
            bar.set_position(p.candidates);
            bar.set_message(format!(
                "corpus {}, {} points, {} transitions",
                p.corpus, p.points, p.transitions
            ));
        })
    })?;
    bar.finish_and_clear();
    let seconds = start.elapsed().as_secs_f64();
    guided_text(&mut out, &report)?;
    if let Some(dir) = &args.out {
        let path = dir.join(GUIDED_REPORT);
        let json = serde_json::to_string_pretty(&report)?;
        std::fs::write(&path, json).with_context(|| format!("writing {}", path.display()))?;
        let (svg, png) = write_chart(dir, &[chart::Run::of(&report)])?;
        writeln!(
            out,
            "wrote {}, {} and {}",
            path.display(),
            svg.display(),
            png.display()
        )?;
    }
    closing(
        &mut out,
        &args.coverage,
        report.candidates,
        "candidates",
        seconds,
    )?;
    Ok(report.passed())
}

/// The chart of coverage against candidates, in --out.
pub const COVERAGE_CHART_SVG: &str = "coverage.svg";
pub const COVERAGE_CHART_PNG: &str = "coverage.png";

/// The chart of `runs` into `dir`; returns its two files.
fn write_chart(dir: &Path, runs: &[chart::Run]) -> Result<(PathBuf, PathBuf)> {
    let (svg, png) = (dir.join(COVERAGE_CHART_SVG), dir.join(COVERAGE_CHART_PNG));
    chart::write(runs, &svg, &png)?;
    Ok((svg, png))
}

/// `fuzz --chart`: the curves of finished campaigns in one chart.
fn draw_chart(args: &FuzzArgs) -> Result<bool> {
    let Some(dir) = &args.out else {
        anyhow::bail!("--chart: give --out DIR for coverage.svg and coverage.png");
    };
    let runs = args
        .chart
        .iter()
        .map(|p| chart::Run::read(p))
        .collect::<Result<Vec<_>, _>>()?;
    std::fs::create_dir_all(dir).with_context(|| format!("--out {}", dir.display()))?;
    let (svg, png) = write_chart(dir, &runs)?;
    for r in &runs {
        if let Some(&(candidates, points, transitions)) = r.curve.last() {
            println!(
                "{}: {candidates} candidates, {points} points, {transitions} of {} reachable transitions",
                r.label, r.reachable
            );
        }
    }
    println!("wrote {} and {}", svg.display(), png.display());
    Ok(true)
}

/// The guided campaign's report.
fn guided_text(out: &mut impl Write, r: &GuidedReport) -> std::io::Result<()> {
    let refused = r.candidates - r.ran - r.too_big;
    writeln!(
        out,
        "candidates: {}: {} co-simulated ({} pixels), {refused} refused at load, {} over the pixel budget; {} mutants refused and drawn again",
        r.candidates, r.ran, r.pixels, r.too_big, r.mutants_refused
    )?;
    refused_line(out, &r.refused)?;
    writeln!(
        out,
        "corpus: {} seed scenes, {} kept, {} now",
        r.seeds,
        r.kept.len(),
        r.corpus
    )?;
    writeln!(
        out,
        "coverage (golden's prediction): {} points, {} from the seeds; reachable ISA transitions {} of {}, {} from the seeds",
        r.points, r.seed_points, r.transitions, r.reachable_transitions, r.seed_transitions
    )?;
    if !r.missing_transitions.is_empty() {
        writeln!(
            out,
            "reachable ISA transitions never reached: {}",
            r.missing_transitions.join(", ")
        )?;
    }
    if !r.new_points.is_empty() {
        let shown: Vec<String> = r
            .new_points
            .iter()
            .take(6)
            .map(|(p, file)| format!("{p} ({file})"))
            .collect();
        writeln!(
            out,
            "newly reached: {} points: {}{}",
            r.new_points.len(),
            shown.join(", "),
            if r.new_points.len() > shown.len() {
                ", ..."
            } else {
                ""
            }
        )?;
    }
    writeln!(out)?;
    for f in &r.failures {
        writeln!(
            out,
            "FAILED: candidate {} (written to {p}; replay: rtcosim cosim --scene {p}): {}",
            f.candidate,
            f.message,
            p = f.file.display()
        )?;
    }
    if r.passed() {
        writeln!(
            out,
            "PASS: every candidate that loaded co-simulated with 0 divergences and finite colours"
        )?;
    } else {
        writeln!(
            out,
            "FAIL: {} candidates broke the promise",
            r.failures.len()
        )?;
    }
    Ok(())
}

/// The report's file name in --out.
pub const REPORT: &str = "fuzz-report.txt";

/// The report of a whole campaign: printed, and written to
/// `DIR/fuzz-report.txt` with `--out DIR`. The unsharded campaign and
/// `rtcosim merge` both end here.
pub fn finish(out: &mut impl Write, summary: &Summary, dir: Option<&Path>) -> Result<()> {
    let mut text = Vec::new();
    report_text(&mut text, summary)?;
    out.write_all(&text)?;
    if let Some(dir) = dir {
        let path = dir.join(REPORT);
        std::fs::write(&path, &text).with_context(|| format!("writing {}", path.display()))?;
        writeln!(out, "wrote {}", path.display())?;
    }
    Ok(())
}

fn percent(part: u64, whole: u64) -> f64 {
    100.0 * part as f64 / whole.max(1) as f64
}

/// The `q` quantile of `sorted` (ascending), nearest rank.
fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let i = ((sorted.len() as f64 * q).ceil() as usize).clamp(1, sorted.len()) - 1;
    sorted[i]
}

/// The report: what the campaign found, without how long it took (so
/// that a merge of shards prints it byte for byte).
fn report_text(out: &mut impl Write, r: &Summary) -> std::io::Result<()> {
    let refused = r.scenes - r.accepted;
    writeln!(
        out,
        "scenes: {} generated, {} accepted ({:.1}%), {refused} refused at load",
        r.scenes,
        r.accepted,
        percent(r.accepted, r.scenes)
    )?;
    writeln!(
        out,
        "inside the documented limits: {} generated, {} accepted ({:.1}%)",
        r.in_limits,
        r.in_limits_accepted,
        percent(r.in_limits_accepted, r.in_limits)
    )?;
    refused_line(out, &r.refused_by_field)?;
    let c = &r.counts;
    writeln!(
        out,
        "co-simulated: {} pixels, {} events compared, {} differ; {} divergent pixels; cycles RTL {}, golden {}",
        c.pixels, c.events_compared, c.event_mismatches, c.divergent_pixels, c.a_cycles, c.b_cycles
    )?;
    let never: Vec<&str> = isa::STATES
        .iter()
        .filter(|&&(_, id)| !r.reached(id))
        .map(|&(name, _)| name)
        .collect();
    writeln!(
        out,
        "state coverage: {} of {} controller states reached{}",
        r.states.len(),
        isa::STATES.len(),
        if never.is_empty() {
            String::new()
        } else {
            format!("; never: {}", never.join(", "))
        }
    )?;
    let errors = &r.max_errors;
    writeln!(
        out,
        "against the f64 reference (largest colour error per scene, 0..255): median {:.3e}, 90% {:.3e}, 99% {:.3e}, max {:.3e}; {} scenes over 0.5, {} over 1; {} non-finite channels",
        quantile(errors, 0.5),
        quantile(errors, 0.9),
        quantile(errors, 0.99),
        errors.last().copied().unwrap_or(0.0),
        errors.iter().filter(|&&e| e > 0.5).count(),
        errors.iter().filter(|&&e| e > 1.0).count(),
        r.nonfinite
    )?;
    writeln!(out)?;
    for f in &r.failures {
        writeln!(
            out,
            "FAILED: seed {} scene {}{}: {}",
            f.seed,
            f.index,
            f.file
                .as_ref()
                .map(|p| format!(" (written to {p}; replay: rtcosim cosim --scene {p})"))
                .unwrap_or_default(),
            f.what
        )?;
    }
    if r.passed() {
        writeln!(
            out,
            "PASS: every scene was refused at load or co-simulated with 0 divergences and finite colours"
        )?;
    } else {
        writeln!(
            out,
            "FAIL: {} of {} scenes broke the promise",
            r.failures.len(),
            r.scenes
        )?;
    }
    Ok(())
}
