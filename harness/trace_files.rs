//! Trace files of a run: the header that says what was traced and by whom,
//! and the writers that stream a window's events into a file.

use golden::micro::Processor;
use golden::scene::Scene;
use golden::trace::{TraceError, TraceHeader, TraceWriter};
use golden::window::Window;
use std::io::BufWriter;
use std::path::Path;

/// Errors writing a trace file.
#[derive(Debug, thiserror::Error)]
pub enum TraceFileError {
    #[error("{}: {source}", path.display())]
    Create {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    #[error("{}: {source}", path.display())]
    Write {
        path: std::path::PathBuf,
        source: TraceError,
    },
}

/// The header of a trace of `window` of `scene` (named `scene_name` by the
/// user) written by `model`: the scene hash and `key=value` pairs.
pub fn header(scene: &Scene, scene_name: &str, model: &str, window: Window) -> TraceHeader {
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
        scene_hash: scene.content_hash(),
        config: format!(
            "writer=rtcosim-{} model={model} scene={} size={}x{} depth={} recip={} sqrt={} speedups={} window={window}",
            env!("CARGO_PKG_VERSION"),
            scene_name.replace(char::is_whitespace, "_"),
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
    }
}

/// Writes the micro-op model's trace of the pixels in `window`, row by row,
/// left to right, to `path`; `progress` is called once per pixel. Returns
/// the number of events.
pub fn write_golden(
    scene: &Scene,
    scene_name: &str,
    window: Window,
    path: &Path,
    progress: &dyn Fn(u64),
) -> Result<u64, TraceFileError> {
    let write_err = |source| TraceFileError::Write {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::create(path).map_err(|source| TraceFileError::Create {
        path: path.to_path_buf(),
        source,
    })?;
    let header = header(scene, scene_name, "micro", window);
    let mut writer = TraceWriter::new(BufWriter::new(file), &header).map_err(write_err)?;
    let proc = Processor::new(scene);
    let mut events = 0;
    for (x, y) in window.iter() {
        let mut failed = None;
        let r = proc.render_pixel(x, y, |e, _| {
            if failed.is_none() {
                failed = writer.write(e).err();
            }
        });
        if let Some(e) = failed {
            return Err(write_err(e));
        }
        events += r.ops.register_writes;
        progress(1);
    }
    writer.finish().map_err(write_err)?;
    Ok(events)
}
