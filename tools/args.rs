//! Argument groups that several commands share, declared once and
//! flattened into each command (`#[command(flatten)]`), and their parsers.

use anyhow::{Context, Result};
use clap::ValueEnum;
use golden::fp::Method;
use golden::scene::{Scene, MAX_IMAGE_SIDE};
use golden::window::Window;
use rtcosim::campaign::shard::Shard;
use rtcosim::campaign::sweep::ConfirmOptions;
use rtcosim::check::cosim::CosimOptions;
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::{parse_number, Fault};
use rtcosim::scenes::{self, Overrides};
use std::path::Path;

/// The scene and what a command line may change in it.
#[derive(clap::Args, Debug, Clone, PartialEq, Eq)]
pub struct SceneArgs {
    /// A scene file (TOML), or the name of a builtin scene: reference,
    /// mirror, grazing, light_touch, parallel_plane, box_room, overexposed,
    /// glass_room, bubble, touching.
    #[arg(long, default_value = "reference")]
    pub scene: String,
    /// Image size WxH instead of the scene's; the image-plane distance
    /// scales with the width, so the horizontal field of view is kept.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<Size>,
    /// The reciprocal unit's method, overriding the scene's (in `cosim`,
    /// this picks the RTL variant verilated with it; golden follows).
    #[arg(long, value_enum)]
    pub recip: Option<MethodArg>,
    /// The square-root unit's method, overriding the scene's.
    #[arg(long, value_enum)]
    pub sqrt: Option<MethodArg>,
}

impl SceneArgs {
    /// The scene with the overrides applied.
    pub fn load(&self) -> Result<Scene> {
        let overrides = Overrides {
            size: self.size.map(|s| (s.width, s.height)),
            recip: self.recip.map(Method::from),
            sqrt: self.sqrt.map(Method::from),
        };
        Ok(scenes::load_with(&self.scene, overrides)?)
    }
}

/// Worker threads.
#[derive(clap::Args, Debug, Clone, Copy, PartialEq, Eq)]
pub struct ThreadsArgs {
    /// Worker threads, one verilated model each where a model runs
    /// (default: all cores). Results do not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    pub threads: Option<u16>,
}

impl ThreadsArgs {
    /// A rayon pool of that many workers (default: one per core).
    pub fn pool(&self) -> Result<rayon::ThreadPool> {
        let mut builder = rayon::ThreadPoolBuilder::new();
        if let Some(threads) = self.threads {
            builder = builder.num_threads(usize::from(threads));
        }
        builder.build().context("starting the worker threads")
    }
}

/// How a configuration is checked on the RTL (`sweep`: each front row;
/// `tune`: its pick).
#[derive(clap::Args, Debug, Clone, Copy, PartialEq)]
pub struct RtlCheckArgs {
    /// Random pixels a configuration is co-simulated on, besides every
    /// pixel where its frame differs from the full configuration's.
    #[arg(long, value_name = "N", default_value_t = 256)]
    pub sample: u64,
    /// Seed of that sample.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Self-test: inject a bit flip into the RTL's writes in state STATE
    /// (see `cosim --fault`), so the check must fail (exit 1).
    #[arg(long, value_name = "STATE:XOR", value_parser = parse_fault)]
    pub fault: Option<Fault>,
    #[command(flatten)]
    pub timeout: TimeoutArgs,
}

/// `--timeout-cycles`: when a pixel counts as hung.
#[derive(clap::Args, Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TimeoutArgs {
    /// Cycles a pixel may take before the RTL counts as hung: the run
    /// stops with an error naming the pixel and its last state. Default:
    /// 100,000 for each of the processor's pixel contexts, which take turns
    /// (compact 100,000; fast 3,200,000).
    #[arg(long, value_name = "CYCLES", value_parser = parse_cycles)]
    pub timeout_cycles: Option<u64>,
}

impl TimeoutArgs {
    /// The cycles a pixel of `processor` may take.
    pub fn cycles(&self, processor: ProcessorKind) -> u64 {
        self.timeout_cycles
            .unwrap_or_else(|| processor.row().default_timeout_cycles())
    }
}

impl RtlCheckArgs {
    pub fn options(&self) -> ConfirmOptions {
        ConfirmOptions {
            sample: self.sample,
            seed: self.seed,
            cosim: CosimOptions {
                fault: self.fault,
                timeout_cycles: self.timeout.timeout_cycles,
                ..CosimOptions::default()
            },
        }
    }
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum MethodArg {
    /// Correctly rounded.
    Exact,
    /// At most 1 ULP from correctly rounded, one cycle faster.
    Fast,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Method {
        match m {
            MethodArg::Exact => Method::Exact,
            MethodArg::Fast => Method::Fast,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

pub fn parse_size(s: &str) -> Result<Size, String> {
    let bad =
        || format!("expected WIDTHxHEIGHT, each 1..={MAX_IMAGE_SIDE}, e.g. 800x600; got {s:?}");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=MAX_IMAGE_SIDE).contains(n))
            .ok_or_else(bad)
    };
    Ok(Size {
        width: side(w)?,
        height: side(h)?,
    })
}

/// `X0,Y0,X1,Y1` or `X,Y` ([`Window`]'s own syntax).
pub fn parse_window(s: &str) -> Result<Window, String> {
    s.parse()
        .map_err(|e: golden::window::WindowError| e.to_string())
}

/// `X,Y`: one pixel.
pub fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected a pixel X,Y (column, row from 0), e.g. 17,11; got {s:?}");
    let (x, y) = s.split_once(',').ok_or_else(bad)?;
    let n = |v: &str| v.trim().parse::<u32>().map_err(|_| bad());
    Ok((n(x)?, n(y)?))
}

/// `STATE:XOR` ([`Fault`]'s own syntax).
pub fn parse_fault(s: &str) -> Result<Fault, String> {
    s.parse()
}

/// A weight cutoff: `1/N` or a number, in [0, 1] (`[render]
/// weight_cutoff`'s range; 0 is off).
pub fn parse_cutoff(s: &str) -> Result<f32, String> {
    let bad =
        || format!("expected a weight cutoff in [0, 1], as a number or 1/N, e.g. 1/256; got {s:?}");
    let t = s.trim();
    let c = match t.split_once('/') {
        Some((one, n)) if one.trim() == "1" => n
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|n| *n >= 1.0)
            .map(|n| 1.0 / n),
        Some(_) => None,
        None => t.parse::<f64>().ok(),
    };
    c.filter(|c| (0.0..=1.0).contains(c))
        .map(|c| c as f32)
        .ok_or_else(bad)
}

/// A number of cycles, at least 1, in decimal or hex.
pub fn parse_cycles(s: &str) -> Result<u64, String> {
    parse_number(s)
        .filter(|&n| n >= 1)
        .ok_or_else(|| format!("expected a number of cycles, at least 1; got {s:?}"))
}

/// Fails unless `window` lies inside the scene's image; `flag` names the
/// option in the message.
pub fn check_window(flag: &str, window: Window, scene: &Scene) -> Result<()> {
    window
        .check_inside(scene.camera.width, scene.camera.height)
        .map_err(|e| anyhow::anyhow!("{flag} {e}"))
}

/// Fails unless the directory `path` would be written into exists (before
/// a long run, not after it).
pub fn check_parent_dir(flag: &str, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            anyhow::bail!(
                "{flag} {}: no such directory {}",
                path.display(),
                dir.display()
            );
        }
    }
    Ok(())
}

/// Which shard of a run this process is (docs/scale.md).
#[derive(clap::Args, Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShardArgs {
    /// Run only shard K of N (K from 0: 0/4 .. 3/4) and write its shard
    /// file into --out, for `rtcosim merge`. Without it, the shard is read
    /// from a Slurm array task (SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN
    /// of SLURM_ARRAY_TASK_COUNT) or a Kubernetes Indexed Job
    /// (JOB_COMPLETION_INDEX of --shard-count or RTCOSIM_SHARD_COUNT); with
    /// neither, the whole run.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// The shard count that goes with a Kubernetes JOB_COMPLETION_INDEX
    /// (the Job's completions).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub shard_count: Option<u64>,
}

impl ShardArgs {
    /// The shard, from the flags or the environment; `None`: the whole run.
    pub fn resolve(&self) -> Result<Option<Shard>> {
        Ok(Shard::resolve(self.shard, self.shard_count)?)
    }
}

/// Coverage of the RTL over this run (a build with the cargo feature
/// `coverage`).
#[derive(clap::Args, Debug, Clone, PartialEq, Eq)]
pub struct CoverageArgs {
    /// Measure what the run exercises of the RTL (line, branch and toggle
    /// points, controller states and transitions) on the coverage models,
    /// and write it into DIR (created if missing): each model's counts in
    /// DIR/raw/, summed with earlier runs' into coverage.dat, coverage.info
    /// (lcov), html/ (with genhtml), summary.json and summary.md. Needs a
    /// build with `--features coverage`; the coverage models run slower.
    #[arg(long, value_name = "DIR")]
    pub coverage: Option<std::path::PathBuf>,
}

impl CoverageArgs {
    /// Switches the coverage models on for this process, before any model
    /// is built.
    pub fn enable(&self) -> Result<()> {
        if let Some(dir) = &self.coverage {
            rtcosim::output::coverage::enable(dir)
                .with_context(|| format!("--coverage {}", dir.display()))?;
        }
        Ok(())
    }

    /// After the run: the counts in DIR merged and reported (a line of
    /// figures, the files written); `None` without --coverage.
    pub fn finish(
        &self,
        out: &mut impl std::io::Write,
    ) -> Result<Option<rtcosim::output::coverage::Summary>> {
        let Some(dir) = &self.coverage else {
            return Ok(None);
        };
        let done = rtcosim::output::coverage::finish(std::slice::from_ref(dir), dir, true)
            .with_context(|| format!("--coverage {}", dir.display()))?;
        write!(out, "{}", done.report())?;
        Ok(Some(done.summary))
    }
}
