//! Golden-model frame rates on the built-in reference scene (800x600), all
//! cores: the f64 reference renderer, the micro-op model untraced, and the
//! micro-op model with every trace event collected.
//!
//! ```sh
//! cargo bench -p golden --bench frames                # 7 rounds
//! cargo bench -p golden --bench frames -- --rounds 15
//! # one renderer alone, without warm-up, e.g. under a profiler:
//! RAYON_NUM_THREADS=1 cargo bench -p golden --bench frames -- --only micro
//! ```
//!
//! The machine this runs on is usually shared and noisy, so the three
//! renderers take turns within each round and the report gives, per
//! renderer, the median and the best round, and the median of the per-round
//! ratios (docs/perf.md records the numbers). The warm-up checks that the
//! traced frame equals the untraced one, event count included.
//!
//! "Traced" means what a co-simulation needs: every `TraceEvent` with its
//! source `Location` is pushed into a per-thread buffer (reused, cleared at
//! each pixel, so a pixel's events exist together as they would when
//! compared against the RTL's), counted, and discarded.

use golden::frame::Frame;
use golden::micro::{self, FrameStats, Processor};
use golden::reference;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use rayon::prelude::*;
use std::panic::Location;
use std::time::Instant;

type Traced = (TraceEvent, &'static Location<'static>);

/// The micro-op model's frame with the trace collected: the frame and the
/// number of events (which must equal the statistics' register writes).
fn render_traced(scene: &Scene) -> (Frame, u64) {
    let proc = Processor::new(scene);
    let w = scene.camera.width as usize;
    let mut pixels = vec![[0.0f64; 3]; w * scene.camera.height as usize];
    let events = pixels
        .par_chunks_mut(w)
        .enumerate()
        .map_init(
            || Vec::<Traced>::with_capacity(1 << 12),
            |buf, (py, row)| {
                let mut events = 0;
                for (px, out) in row.iter_mut().enumerate() {
                    buf.clear();
                    let r = proc.render_pixel(px as u32, py as u32, |e, at| buf.push((*e, at)));
                    *out = r.rgb.map(f64::from);
                    events += buf.len() as u64;
                    std::hint::black_box(&buf);
                }
                events
            },
        )
        .sum();
    let frame = Frame {
        width: scene.camera.width,
        height: scene.camera.height,
        pixels,
    };
    (frame, events)
}

#[derive(Clone, Copy)]
enum Renderer {
    Reference,
    Micro,
    MicroTraced,
}

impl Renderer {
    const ALL: [Renderer; 3] = [Renderer::Reference, Renderer::Micro, Renderer::MicroTraced];

    fn label(self) -> &'static str {
        match self {
            Renderer::Reference => "reference (f64)",
            Renderer::Micro => "micro, untraced",
            Renderer::MicroTraced => "micro, traced",
        }
    }
}

fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

fn main() {
    // `cargo bench` passes `--bench`; the only option of ours is --rounds.
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rounds = args
        .iter()
        .position(|a| a == "--rounds")
        .map(|i| {
            args.get(i + 1)
                .and_then(|n| n.parse::<usize>().ok())
                .filter(|&n| n > 0)
                .expect("--rounds needs a positive number")
        })
        .unwrap_or(7);
    // --only reference|micro|traced: time one renderer (for profilers).
    let only = args.iter().position(|a| a == "--only").map(|i| {
        match args.get(i + 1).map(String::as_str) {
            Some("reference") => 0,
            Some("micro") => 1,
            Some("traced") => 2,
            _ => panic!("--only needs reference, micro or traced"),
        }
    });

    let scene = Scene::reference();
    let (w, h) = (scene.camera.width, scene.camera.height);
    println!(
        "golden frames: reference scene {w}x{h}, {} rayon threads on {} ({} logical cores), {rounds} rounds",
        rayon::current_num_threads(),
        cpu_model(),
        std::thread::available_parallelism().map_or(0, |n| n.get()),
    );

    // Warm up, and check that the traced run renders the same frame and
    // emits one event per register write.
    if only.is_none() {
        let (untraced, stats): (Frame, FrameStats) = micro::render(&scene, &|_| {});
        let (traced, events) = render_traced(&scene);
        assert!(
            untraced.pixels == traced.pixels,
            "tracing changed the frame"
        );
        assert_eq!(
            events, stats.ops.register_writes,
            "events != register writes"
        );
        let _ = reference::render(&scene, &|_| {});
        println!(
            "micro: {:.1} instructions/pixel, {:.1} trace events/pixel",
            stats.ops.instructions() as f64 / stats.pixels as f64,
            events as f64 / stats.pixels as f64
        );
    }

    let mut fps = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..rounds {
        for (i, r) in Renderer::ALL.into_iter().enumerate() {
            if only.is_some_and(|o| o != i) {
                continue;
            }
            let start = Instant::now();
            match r {
                Renderer::Reference => {
                    std::hint::black_box(reference::render(&scene, &|_| {}));
                }
                Renderer::Micro => {
                    std::hint::black_box(micro::render(&scene, &|_| {}));
                }
                Renderer::MicroTraced => {
                    std::hint::black_box(render_traced(&scene));
                }
            }
            fps[i].push(1.0 / start.elapsed().as_secs_f64());
        }
    }
    println!();
    println!(
        "{:<18} {:>14} {:>12}",
        "renderer", "median frames/s", "best"
    );
    for (i, r) in Renderer::ALL.into_iter().enumerate() {
        if fps[i].is_empty() {
            continue;
        }
        let best = fps[i].iter().copied().fold(0.0, f64::max);
        println!("{:<18} {:>15.2} {:>12.2}", r.label(), median(&fps[i]), best);
    }
    if only.is_some() {
        return;
    }
    let per_round = |a: usize, b: usize| -> Vec<f64> {
        fps[a].iter().zip(&fps[b]).map(|(x, y)| x / y).collect()
    };
    println!();
    println!(
        "micro untraced / reference: {:.3} (median of per-round ratios)",
        median(&per_round(1, 0))
    );
    println!(
        "micro traced / untraced:    {:.3}",
        median(&per_round(2, 1))
    );
}
