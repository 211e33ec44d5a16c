//! Trace files of a run: the header that says what was traced and by whom,
//! and the writers that stream a window's records into a file: the golden
//! micro-op model's ([`write_golden`]) and the RTL's ([`write_rtl`]), in the
//! same format, pixel by pixel in row order (see [`golden::trace`]).

use crate::pixel_proc::{Fault, PixelProcessor, PpError};
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

/// Writes the micro-op model's trace of the pixels in `window`, row by row,
/// left to right, to `path`, with `fault` injected (a self-test of a
/// checker); `progress` is called once per pixel. Returns the number of
/// events.
pub fn write_golden(
    scene: &Scene,
    scene_name: &str,
    window: Window,
    fault: Option<Fault>,
    path: &Path,
    progress: &dyn Fn(u64),
) -> Result<u64, TraceFileError> {
    let writer = with_fault("model=micro".to_string(), fault);
    let header = header(scene, scene_name, TraceSide::Golden, &writer, window);
    let mut file = TraceFile::create(path, &header)?;
    let proc = Processor::new(scene).with_fault(fault);
    let mut events = 0;
    for (x, y) in window.iter() {
        let mut failed = None;
        let r = proc.render_pixel(x, y, |e, _| {
            if failed.is_none() {
                failed = file.event(e).err();
            }
        });
        if let Some(e) = failed {
            return Err(e);
        }
        file.pixel_end(x, y, PixelOutcome::from(&r))?;
        events += r.ops.register_writes;
        progress(1);
    }
    file.finish()?;
    Ok(events)
}

/// Writes the verilated RTL's trace (its trace port) of the pixels in
/// `window`, row by row, left to right, to `path`, on a model of the
/// scene's methods with `fault` injected (a self-test) and the watchdog at
/// `timeout_cycles`; `progress` is called once per pixel. Returns the
/// number of events. One pixel's events are buffered at a time.
pub fn write_rtl(
    scene: &Scene,
    scene_name: &str,
    window: Window,
    fault: Option<Fault>,
    timeout_cycles: u64,
    path: &Path,
    progress: &dyn Fn(u64),
) -> Result<u64, TraceFileError> {
    let mut rtl = PixelProcessor::new(scene.render.recip, scene.render.sqrt)?;
    rtl.set_timeout_cycles(timeout_cycles);
    rtl.set_fault(fault);
    rtl.load_scene(scene)?;
    let writer = with_fault(
        format!(
            "model=pixel_processor simulator={}",
            one_word(crate::VERILATOR_VERSION)
        ),
        fault,
    );
    let header = header(scene, scene_name, TraceSide::Rtl, &writer, window);
    let mut file = TraceFile::create(path, &header)?;
    let mut buffer = Vec::new();
    let mut events = 0;
    for (x, y) in window.iter() {
        buffer.clear();
        let outcome = rtl.run_pixel(x, y, Some(&mut buffer))?;
        for e in &buffer {
            file.event(e)?;
        }
        file.pixel_end(x, y, outcome)?;
        events += outcome.events;
        progress(1);
    }
    file.finish()?;
    Ok(events)
}
