//! Trace files of a run: the header that says what was traced and by whom,
//! and the writers that stream a window's records into a file: the golden
//! micro-op model's ([`write_golden`]) and the RTL's ([`write_rtl`]), in the
//! same format, pixel by pixel in row order (see [`golden::trace`]), for
//! either processor (the header's `processor=` says whose cycles the
//! pixels carry).

use crate::check::cosim;
use crate::design::processor::{CycleRule, ProcessorKind};
use crate::design::{Design, Fault, PpError};
use clap::ValueEnum;
use golden::micro::barrel::{self, PixelWork};
use golden::micro::Processor;
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::trace::{TraceError, TraceEvent, TraceHeader, TraceRecord, TraceSide, TraceWriter};
use golden::window::Window;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Errors writing a trace file.
#[derive(Debug, thiserror::Error)]
pub enum TraceFileError {
    #[error("{}: {source}", path.display())]
    Create {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: {source}", path.display())]
    Write { path: PathBuf, source: TraceError },
    #[error("{}: pixel ({x}, {y}) took {cycles} cycles; a trace file records at most {} per pixel", path.display(), u32::MAX)]
    TooManyCycles {
        path: PathBuf,
        x: u32,
        y: u32,
        cycles: u64,
    },
    #[error("tracing the RTL: {0}")]
    Rtl(#[from] PpError),
}

/// The header of a trace of `window` of `scene` (named `scene_name` by the
/// user) written by `side`; `writer` names the model or simulator
/// (`key=value` pairs, e.g. `model=micro` or
/// `model=pixel_processor simulator=Verilator_5.006`).
pub fn header(
    scene: &Scene,
    scene_name: &str,
    side: TraceSide,
    writer: &str,
    window: Window,
) -> TraceHeader {
    let r = &scene.render;
    let speedups: Vec<&str> = [
        (r.speedups.bounding_box, "bounding_box"),
        (r.speedups.fast_plane, "fast_plane"),
        (r.speedups.shadow_shortcut, "shadow_shortcut"),
    ]
    .into_iter()
    .filter_map(|(on, name)| on.then_some(name))
    .collect();
    TraceHeader {
        side,
        scene_hash: scene.render_hash(),
        config_hash: scene.config_hash(),
        config: format!(
            "writer=rtcosim-{} side={} {writer} scene={} size={}x{} depth={} recip={} sqrt={} speedups={} window={window}",
            env!("CARGO_PKG_VERSION"),
            side.key(),
            one_word(scene_name),
            scene.camera.width,
            scene.camera.height,
            r.max_depth,
            r.recip,
            r.sqrt,
            if speedups.is_empty() {
                "none".to_string()
            } else {
                speedups.join(",")
            },
        ),
        scene: scene.to_toml(),
    }
}

/// `s` as one `key=value` word: whitespace becomes `_`.
fn one_word(s: &str) -> String {
    s.replace(char::is_whitespace, "_")
}

/// A trace file being written; errors name the file.
struct TraceFile {
    path: PathBuf,
    writer: TraceWriter<BufWriter<File>>,
}

impl TraceFile {
    fn create(path: &Path, header: &TraceHeader) -> Result<TraceFile, TraceFileError> {
        let file = File::create(path).map_err(|source| TraceFileError::Create {
            path: path.to_path_buf(),
            source,
        })?;
        let writer = TraceWriter::new(BufWriter::new(file), header)
            .map_err(|source| write_error(path, source))?;
        Ok(TraceFile {
            path: path.to_path_buf(),
            writer,
        })
    }

    fn event(&mut self, e: &TraceEvent) -> Result<(), TraceFileError> {
        self.writer
            .write(e)
            .map_err(|source| write_error(&self.path, source))
    }

    /// Ends pixel (x, y) with its colour and cycles.
    fn pixel_end(&mut self, x: u32, y: u32, outcome: PixelOutcome) -> Result<(), TraceFileError> {
        let cycles = u32::try_from(outcome.cycles).map_err(|_| TraceFileError::TooManyCycles {
            path: self.path.clone(),
            x,
            y,
            cycles: outcome.cycles,
        })?;
        // Both fit: scenes are at most MAX_IMAGE_SIDE = 4096 wide and high.
        let record = TraceRecord::PixelEnd {
            x: x as u16,
            y: y as u16,
            rgb: outcome.rgb,
            cycles,
        };
        self.writer
            .record(record)
            .map_err(|source| write_error(&self.path, source))
    }

    fn finish(self) -> Result<(), TraceFileError> {
        let path = self.path;
        self.writer
            .finish()
            .map(drop)
            .map_err(|source| write_error(&path, source))
    }
}

fn write_error(path: &Path, source: TraceError) -> TraceFileError {
    TraceFileError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// The `key=value` words of a writer with an injected fault.
fn with_fault(writer: String, fault: Option<Fault>) -> String {
    match fault {
        Some(f) => format!("{writer} fault={f}"),
        None => writer,
    }
}

/// The processor whose cycle rule a trace's pixel ends carry, from its
/// header's `processor=` key; `None` when the header names none (traces
/// written before the key existed are the compact processor's) or names an
/// unknown one.
pub fn processor_of(header: &TraceHeader) -> Option<ProcessorKind> {
    header
        .config_value("processor")
        .and_then(|name| ProcessorKind::from_str(name, true).ok())
}

/// One pixel of a trace, buffered: its events and its outcome.
type TracedPixel = (Vec<TraceEvent>, PixelOutcome);

/// Writes `window`'s pixels to `file` in tiles, each tile's pixels (row
/// order) from `tile_pixels`; the window goes in the tiles the fast
/// processor is run in ([`cosim::tiles`]) on either processor.
fn write_tiles(
    file: &mut TraceFile,
    window: Window,
    progress: &dyn Fn(u64),
    tile_pixels: &mut dyn FnMut(Window) -> Result<Vec<TracedPixel>, TraceFileError>,
) -> Result<u64, TraceFileError> {
    let mut events = 0;
    for tile in cosim::tiles(window) {
        let pixels = tile_pixels(tile)?;
        for ((x, y), (buffer, outcome)) in tile.iter().zip(pixels) {
            for e in &buffer {
                file.event(e)?;
            }
            file.pixel_end(x, y, outcome)?;
            events += buffer.len() as u64;
            progress(1);
        }
    }
    Ok(events)
}

/// Writes the micro-op model's trace of the pixels in `window`, row by row,
/// left to right, to `path`, with `fault` injected (a self-test of a
/// checker); `progress` is called once per pixel. Each pixel's cycles are
/// those `processor` takes: the compact processor's rule
/// (golden::micro's), or the fast processor's barrel rule for the window
/// streamed in tiles of [`cosim::TILE_ROWS`] rows into a fresh processor,
/// as `cosim --processor fast` (and its `--trace`) runs them. Returns the
/// number of events.
pub fn write_golden(
    scene: &Scene,
    scene_name: &str,
    window: Window,
    processor: ProcessorKind,
    fault: Option<Fault>,
    path: &Path,
    progress: &dyn Fn(u64),
) -> Result<u64, TraceFileError> {
    let writer = with_fault(format!("model=micro processor={processor}"), fault);
    let header = header(scene, scene_name, TraceSide::Golden, &writer, window);
    let mut file = TraceFile::create(path, &header)?;
    let proc = Processor::new(scene).with_fault(fault);
    let events = write_tiles(&mut file, window, progress, &mut |tile| {
        let mut work = Vec::new();
        let mut pixels: Vec<TracedPixel> = tile
            .iter()
            .map(|(x, y)| {
                let mut buffer = Vec::new();
                let r = proc.render_pixel(x, y, |e, _| buffer.push(*e));
                work.push(PixelWork::of(&r));
                (buffer, PixelOutcome::from(&r))
            })
            .collect();
        if let CycleRule::Barrel { contexts, .. } = processor.row().cycle_rule {
            let run = barrel::run(contexts, &work);
            for ((_, outcome), p) in pixels.iter_mut().zip(&run.pixels) {
                outcome.cycles = p.cycles();
            }
        }
        Ok(pixels)
    })?;
    file.finish()?;
    Ok(events)
}

/// Writes the verilated RTL's trace (its trace port) of the pixels in
/// `window`, row by row, left to right, to `path`, from `design` (with the
/// scene's methods) with `fault` injected (a self-test) and the watchdog
/// at `timeout_cycles`; `progress` is called once per pixel. The window is
/// fed in tiles of [`cosim::TILE_ROWS`] rows, the model reset before each,
/// and the results, which a streamed design gives in the order they
/// finish, are put back in row order. Returns the number of events. One
/// tile's events are buffered at a time.
#[allow(clippy::too_many_arguments)]
pub fn write_rtl(
    scene: &Scene,
    scene_name: &str,
    window: Window,
    design: &Design,
    fault: Option<Fault>,
    timeout_cycles: u64,
    path: &Path,
    progress: &dyn Fn(u64),
) -> Result<u64, TraceFileError> {
    let writer = with_fault(
        format!(
            "model={}{} processor={} simulator={}",
            design.row().models.module(),
            if design.exp_unit { "" } else { "_without_exp" },
            design.processor,
            one_word(crate::VERILATOR_VERSION)
        ),
        fault,
    );
    let header = header(scene, scene_name, TraceSide::Rtl, &writer, window);
    let mut rtl = design.open()?;
    rtl.set_timeout_cycles(timeout_cycles);
    rtl.set_fault(fault);
    let mut file = TraceFile::create(path, &header)?;
    let events = write_tiles(&mut file, window, progress, &mut |tile| {
        rtl.load_scene(scene)?;
        let coords: Vec<(u32, u32)> = tile.iter().collect();
        let mut pixels: Vec<Option<TracedPixel>> = vec![None; coords.len()];
        rtl.run(&coords, &mut |p| {
            // The tile's pixels are distinct, fed row by row.
            let i = (p.y - tile.y) * tile.width + (p.x - tile.x);
            pixels[i as usize] = Some((p.events.to_vec(), p.outcome));
        })?;
        pixels
            .into_iter()
            .zip(&coords)
            .map(|(p, &(x, y))| {
                p.ok_or_else(|| {
                    TraceFileError::Rtl(PpError::Model {
                        pixel: Some((x, y)),
                        message: "no result left the processor for this pixel".into(),
                    })
                })
            })
            .collect()
    })?;
    file.finish()?;
    Ok(events)
}
