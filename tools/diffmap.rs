//! `rtcosim diffmap A B --out DIR`: where two renders of a scene differ, as
//! heat maps, the thesis' masks (figure 17) and its table of differences
//! (section 4.11). A and B are each a frame file or a model rendered here;
//! the maps and the table are `golden::diffmap`'s.

use crate::args::{check_parent_dir, MethodArg, SceneArgs, ThreadsArgs};
use crate::render::Model;
use crate::ui::progress_bar;
use anyhow::{bail, Context, Result};
use golden::diffmap::DiffMap;
use golden::frame::Frame;
use golden::scene::Scene;
use golden::window::Window;
use rtcosim::cosim::{self, CosimOptions};
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

/// The sides' help, shared by A and B.
const SIDE_HELP: &str = "reference (the f64 reference renderer), micro (the golden \
micro-op model), rtl (the verilated pixel processor, co-simulated against micro), \
or a frame file (.exr, as `cosim --out` writes)";

#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  # The thesis' comparison: the RTL with the fast units against the model with exact ones.
  rtcosim diffmap rtl micro --a-recip fast --a-sqrt fast --out maps
  # The micro-op model against the f64 reference, at 80x60.
  rtcosim diffmap micro reference --size 80x60 --out maps
  # Two frame files.
  rtcosim diffmap run1/rtl.exr run2/rtl.exr --out maps

The models render --scene (with --size); --recip/--sqrt set the methods of both \
model sides, --a-recip/--a-sqrt/--b-recip/--b-sqrt one side's (the thesis compared an \
RTL and a model whose operators differed in accuracy).

Writes into DIR: heat-ulp.png and heat-abs.png (per pixel the largest channel \
difference, in ULPs of f32 and on the 0..255 scale, log colour scale with a legend; \
black: no difference), mask-<T>.png per threshold (black where a channel differs by \
more than T), table.md and table.json (per threshold: colour values over it, share, \
average difference; the three largest differences). The table is printed too. \
A reference frame read from a file was rounded to f32 (up to 0.76e-5 on the 0..255 \
scale): name the model to compare its f64 values exactly.")]
pub struct DiffMapArgs {
    #[arg(value_name = "A", value_parser = parse_source, help = format!("Side A: {SIDE_HELP}"))]
    pub a: Source,
    #[arg(value_name = "B", value_parser = parse_source, help = format!("Side B: {SIDE_HELP}"))]
    pub b: Source,
    /// The directory to write the maps and tables into (created if missing;
    /// its parent must exist).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    // The scene the models render (unused when A and B are both files);
    // --recip/--sqrt set both model sides' methods.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Side A's reciprocal method, overriding --recip and the scene's.
    #[arg(long, value_enum, value_name = "METHOD")]
    pub a_recip: Option<MethodArg>,
    /// Side A's square-root method, overriding --sqrt and the scene's.
    #[arg(long, value_enum, value_name = "METHOD")]
    pub a_sqrt: Option<MethodArg>,
    /// Side B's reciprocal method, overriding --recip and the scene's.
    #[arg(long, value_enum, value_name = "METHOD")]
    pub b_recip: Option<MethodArg>,
    /// Side B's square-root method, overriding --sqrt and the scene's.
    #[arg(long, value_enum, value_name = "METHOD")]
    pub b_sqrt: Option<MethodArg>,
    /// Thresholds on the 0..255 scale, comma-separated: a mask and a table
    /// row each ("over" is strictly greater).
    #[arg(
        long,
        value_name = "T,T,...",
        value_delimiter = ',',
        value_parser = parse_threshold,
        default_value = "0.00001,0.0001,0.5"
    )]
    pub thresholds: Vec<f64>,
    /// Draw the heat maps at 1/N of the frame's size, each map pixel the
    /// largest difference of an NxN block (the masks stay full size): for
    /// small files of large frames.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub block: u32,
    #[command(flatten)]
    pub threads: ThreadsArgs,
}

/// One side of the comparison.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// A golden model, rendered here.
    Golden(Model),
    /// The verilated pixel processor, co-simulated here.
    Rtl,
    /// A frame file.
    File(PathBuf),
}

/// A model name, else a frame file (which must exist or end in .exr, so a
/// misspelt model name is an error here, not a missing file later).
pub fn parse_source(s: &str) -> Result<Source, String> {
    match s {
        "reference" => return Ok(Source::Golden(Model::Reference)),
        "micro" => return Ok(Source::Golden(Model::Micro)),
        "rtl" => return Ok(Source::Rtl),
        _ => {}
    }
    let path = PathBuf::from(s);
    let exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if exr || path.exists() {
        Ok(Source::File(path))
    } else {
        Err(format!(
            "{s:?} is neither a model (reference, micro, rtl) nor a frame file (.exr)"
        ))
    }
}

/// A threshold on the 0..255 scale: a finite number, at least 0.
pub fn parse_threshold(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|t| t.is_finite() && *t >= 0.0)
        .ok_or_else(|| {
            format!("expected a threshold >= 0 on the 0..255 scale, e.g. 0.5; got {s:?}")
        })
}

/// A side with its method overrides, as the run needs it.
struct Side<'a> {
    name: char,
    source: &'a Source,
    recip: Option<MethodArg>,
    sqrt: Option<MethodArg>,
}

impl Side<'_> {
    /// The scene this side's model renders (`None` for a file).
    fn scene(&self, args: &SceneArgs) -> Result<Option<Scene>> {
        if let Source::File(path) = self.source {
            if self.recip.is_some() || self.sqrt.is_some() {
                bail!(
                    "--{0}-recip/--{0}-sqrt set a model's methods, but {1} is the frame file {2}",
                    self.name.to_ascii_lowercase(),
                    self.name,
                    path.display()
                );
            }
            return Ok(None);
        }
        let mut args = args.clone();
        args.recip = self.recip.or(args.recip);
        args.sqrt = self.sqrt.or(args.sqrt);
        Ok(Some(args.load()?))
    }

    /// What this side is, for the table: the model and its scene, or the file.
    fn describe(&self, scene_name: &str, scene: Option<&Scene>, frame: &Frame) -> String {
        match (self.source, scene) {
            (Source::File(path), _) => {
                format!("file {} ({}x{})", path.display(), frame.width, frame.height)
            }
            (Source::Golden(Model::Reference), Some(scene)) => format!(
                "reference (scene {scene_name} {}x{}, f64)",
                scene.camera.width, scene.camera.height
            ),
            (source, Some(scene)) => format!(
                "{} (scene {scene_name} {}x{}, recip {}, sqrt {})",
                model_name(source),
                scene.camera.width,
                scene.camera.height,
                scene.render.recip,
                scene.render.sqrt
            ),
            (source, None) => model_name(source).to_string(),
        }
    }
}

fn model_name(source: &Source) -> &'static str {
    match source {
        Source::Golden(Model::Reference) => "reference",
        Source::Golden(Model::Micro) => "micro",
        Source::Rtl => "rtl",
        Source::File(_) => "file",
    }
}

pub fn run(args: DiffMapArgs) -> Result<()> {
    // Everything that can be refused is refused before a long render.
    let sides = [
        Side {
            name: 'A',
            source: &args.a,
            recip: args.a_recip,
            sqrt: args.a_sqrt,
        },
        Side {
            name: 'B',
            source: &args.b,
            recip: args.b_recip,
            sqrt: args.b_sqrt,
        },
    ];
    let scenes = [sides[0].scene(&args.scene)?, sides[1].scene(&args.scene)?];
    let mut files = [None, None];
    for (file, side) in files.iter_mut().zip(&sides) {
        if let Source::File(path) = side.source {
            *file = Some(Frame::load_exr(path).with_context(|| format!("side {}", side.name))?);
        }
    }
    let size = |i: usize| match (&files[i], &scenes[i]) {
        (Some(f), _) => (f.width, f.height),
        (None, Some(s)) => (s.camera.width, s.camera.height),
        (None, None) => unreachable!("a side is a file or a model"),
    };
    if size(0) != size(1) {
        bail!(
            "A is {}x{} and B is {}x{}: the frames must have the same size{}",
            size(0).0,
            size(0).1,
            size(1).0,
            size(1).1,
            if files.iter().any(Option::is_some) {
                " (--size WxH renders a model at the file's size)"
            } else {
                ""
            }
        );
    }
    prepare_out_dir(&args.out)?;
    let pool = args.threads.pool()?;
    let mut out = std::io::stdout().lock();
    let mut frames = Vec::new();
    for ((side, scene), file) in sides.iter().zip(&scenes).zip(files) {
        let frame = match (file, scene) {
            (Some(frame), _) => frame,
            (None, Some(scene)) => render(side, scene, &pool, &mut out)?,
            (None, None) => unreachable!("a side is a file or a model"),
        };
        let described = side.describe(&args.scene.scene, scene.as_ref(), &frame);
        frames.push((frame, described));
    }
    let [(a, a_name), (b, b_name)] = <[_; 2]>::try_from(frames).expect("two sides");
    let map = DiffMap::new(&a, &b)?;
    let (written, table) = map.write(&args.out, &a_name, &b_name, &args.thresholds, args.block)?;
    write!(out, "\n{}", table.markdown())?;
    writeln!(
        out,
        "\nwrote {} files into {}: {}",
        written.len(),
        args.out.display(),
        written
            .iter()
            .filter_map(|p| p.file_name())
            .map(|n| n.to_string_lossy())
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    Ok(())
}

/// Creates `dir` if it is missing (its parent must exist); refuses a file.
fn prepare_out_dir(dir: &std::path::Path) -> Result<()> {
    if dir.is_dir() {
        return Ok(());
    }
    if dir.exists() {
        bail!("--out {}: not a directory", dir.display());
    }
    check_parent_dir("--out", dir)?;
    std::fs::create_dir(dir).with_context(|| format!("--out {}: cannot create", dir.display()))
}

/// Renders (or co-simulates) one side's frame, with a progress bar.
fn render(
    side: &Side,
    scene: &Scene,
    pool: &rayon::ThreadPool,
    out: &mut impl Write,
) -> Result<Frame> {
    let label = format!("{} {:<9}", side.name, model_name(side.source));
    let bar = progress_bar(scene.pixel_count(), &label, "{percent:>3}% ({eta})")?;
    let start = Instant::now();
    let progress = |n| bar.inc(n);
    let frame = match side.source {
        Source::Golden(model) => pool.install(|| model.render(scene, &progress).0),
        Source::Rtl => {
            let options = CosimOptions {
                keep_frames: true,
                ..Default::default()
            };
            let report =
                pool.install(|| cosim::run(scene, Window::full(scene), &options, &progress))?;
            bar.finish_and_clear();
            writeln!(
                out,
                "{}: rtl co-simulated against micro (recip {}, sqrt {}): {}",
                side.name,
                report.recip,
                report.sqrt,
                if report.passed() {
                    "agrees bit for bit".to_string()
                } else {
                    format!(
                        "{} divergent pixels (rtcosim cosim says where)",
                        report.compare.counts.divergent_pixels
                    )
                }
            )?;
            report
                .frames
                .context("the co-simulation kept no frames")?
                .rtl
        }
        Source::File(_) => unreachable!("files are read, not rendered"),
    };
    bar.finish_and_clear();
    writeln!(
        out,
        "{}: {} rendered {}x{} in {:.1} s",
        side.name,
        model_name(side.source),
        frame.width,
        frame.height,
        start.elapsed().as_secs_f64()
    )?;
    Ok(frame)
}
