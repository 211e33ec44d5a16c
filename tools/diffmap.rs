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
use rtcosim::check::cosim::{self, CosimOptions};
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::Design;
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

/// One side of the comparison, as the command line names it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// A model, rendered here.
    Model(Renderer),
    /// A frame file.
    File(PathBuf),
}

/// What renders a model side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Renderer {
    /// A golden model.
    Golden(Model),
    /// The verilated pixel processor, co-simulated against micro.
    Rtl,
}

impl Renderer {
    fn name(self) -> &'static str {
        match self {
            Renderer::Golden(Model::Reference) => "reference",
            Renderer::Golden(Model::Micro) => "micro",
            Renderer::Rtl => "rtl",
        }
    }
}

/// A model name, else a frame file (which must exist or end in .exr, so a
/// misspelt model name is an error here, not a missing file later).
pub fn parse_source(s: &str) -> Result<Source, String> {
    match s {
        "reference" => return Ok(Source::Model(Renderer::Golden(Model::Reference))),
        "micro" => return Ok(Source::Model(Renderer::Golden(Model::Micro))),
        "rtl" => return Ok(Source::Model(Renderer::Rtl)),
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

/// A side ready to run: a frame read from its file, or a model and its scene.
enum Input {
    File(PathBuf, Frame),
    /// Boxed: a scene is far larger than a file side.
    Model(Renderer, Box<Scene>),
}

impl Input {
    fn size(&self) -> (u32, u32) {
        match self {
            Input::File(_, f) => (f.width, f.height),
            Input::Model(_, s) => (s.camera.width, s.camera.height),
        }
    }

    /// What this side is, for the table: the model and its scene, or the file.
    fn describe(&self, scene_name: &str) -> String {
        let (w, h) = self.size();
        match self {
            Input::File(path, _) => format!("file {} ({w}x{h})", path.display()),
            Input::Model(Renderer::Golden(Model::Reference), _) => {
                format!("reference (scene {scene_name} {w}x{h}, f64)")
            }
            Input::Model(renderer, scene) => format!(
                "{} (scene {scene_name} {w}x{h}, recip {}, sqrt {})",
                renderer.name(),
                scene.render.recip,
                scene.render.sqrt
            ),
        }
    }
}

impl Side<'_> {
    /// Reads this side's file, or loads the scene its model renders.
    fn input(&self, args: &SceneArgs) -> Result<Input> {
        match self.source {
            Source::Model(renderer) => {
                let mut args = args.clone();
                args.recip = self.recip.or(args.recip);
                args.sqrt = self.sqrt.or(args.sqrt);
                let scene = args.load()?;
                Ok(Input::Model(*renderer, Box::new(scene)))
            }
            Source::File(path) => {
                if self.recip.is_some() || self.sqrt.is_some() {
                    bail!(
                        "--{0}-recip/--{0}-sqrt set a model's methods, but {1} is the frame file {2}",
                        self.name.to_ascii_lowercase(),
                        self.name,
                        path.display()
                    );
                }
                let frame = Frame::load_exr(path).with_context(|| format!("side {}", self.name))?;
                Ok(Input::File(path.clone(), frame))
            }
        }
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
    let inputs = [sides[0].input(&args.scene)?, sides[1].input(&args.scene)?];
    let [(aw, ah), (bw, bh)] = [inputs[0].size(), inputs[1].size()];
    if (aw, ah) != (bw, bh) {
        let hint = if inputs.iter().any(|i| matches!(i, Input::File(..))) {
            " (--size WxH renders a model at the file's size)"
        } else {
            ""
        };
        bail!("A is {aw}x{ah} and B is {bw}x{bh}: the frames must have the same size{hint}");
    }
    prepare_out_dir(&args.out)?;
    let pool = args.threads.pool()?;
    let mut out = std::io::stdout().lock();
    let mut frames = Vec::new();
    for (side, input) in sides.iter().zip(inputs) {
        let described = input.describe(&args.scene.scene);
        let frame = match input {
            Input::File(_, frame) => frame,
            Input::Model(renderer, scene) => render(side.name, renderer, &scene, &pool, &mut out)?,
        };
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
    side: char,
    renderer: Renderer,
    scene: &Scene,
    pool: &rayon::ThreadPool,
    out: &mut impl Write,
) -> Result<Frame> {
    let label = format!("{side} {:<9}", renderer.name());
    let bar = progress_bar(scene.pixel_count(), &label, "{percent:>3}% ({eta})")?;
    let start = Instant::now();
    let progress = |n| bar.inc(n);
    let frame = match renderer {
        Renderer::Golden(model) => pool.install(|| model.render(scene, &progress).0),
        Renderer::Rtl => {
            let options = CosimOptions {
                keep_frames: true,
                ..Default::default()
            };
            let report = pool.install(|| {
                let design = Design::for_scene(ProcessorKind::default(), scene);
                cosim::run(&design, scene, Window::full(scene), &options, &progress)
            })?;
            bar.finish_and_clear();
            writeln!(
                out,
                "{}: rtl co-simulated against micro (recip {}, sqrt {}): {}",
                side,
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
    };
    bar.finish_and_clear();
    writeln!(
        out,
        "{}: {} rendered {}x{} in {:.1} s",
        side,
        renderer.name(),
        frame.width,
        frame.height,
        start.elapsed().as_secs_f64()
    )?;
    Ok(frame)
}
