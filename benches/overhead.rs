//! What the co-simulation harness costs on top of the simulation itself
//! (docs/perf.md, "What the harness costs").
//!
//! One thread, one verilated pixel processor, the same pixels every way, in
//! rounds that take each way in turn (so a drift of the shared machine's
//! speed spreads over all of them):
//!
//! - `bare`: the bare C++ clock loop (`harness/design/cpp/bare.h`), one FFI call,
//!   nothing read but ready and done;
//! - `driver`: the harness's driver, one FFI call a pixel, colour and
//!   status read, no trace;
//! - `traced`: the same with every trace event copied into Rust;
//! - `traced+golden`: and `golden::micro` run on the pixel with its trace;
//! - `cosim`: the whole co-simulation (`cosim::run_on`): tracing, golden,
//!   the event-by-event diff and its report.
//!
//! Every way must simulate the same RTL cycles; the bench fails otherwise.
//!
//!     cargo bench --bench overhead -- [--scene reference] [--size 200x150] [--rounds 5]

use anyhow::{bail, ensure, Context, Result};
use clap::Parser;
use golden::micro::Processor;
use golden::scene::Scene;
use golden::trace::TraceEvent;
use golden::window::Window;
use rtcosim::check::cosim::{self, CosimOptions};
use rtcosim::design::pixel_proc::PixelProcessor;
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::{Design, Dut};
use rtcosim::scenes;
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(about = "Time the co-simulation harness against a bare C++ clock loop (one thread)")]
struct Args {
    /// Builtin scene or scene file.
    #[arg(long, default_value = "reference")]
    scene: String,
    /// Image size WxH (the scene's field of view kept); every pixel runs.
    #[arg(long, default_value = "200x150", value_parser = parse_size)]
    size: (u32, u32),
    /// Rounds; each round runs every way once. The median is reported.
    #[arg(long, default_value_t = 5)]
    rounds: u32,
    /// `cargo bench` passes --bench; accepted and ignored.
    #[arg(long, hide = true)]
    bench: bool,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| format!("size '{s}' is not WxH"))?;
    let n = |v: &str| {
        v.parse::<u32>()
            .map_err(|_| format!("size '{s}': '{v}' is not a whole number"))
    };
    Ok((n(w)?, n(h)?))
}

/// The ways of running the pixels, cheapest first.
const WAYS: [&str; 5] = ["bare", "driver", "traced", "traced+golden", "cosim"];

fn run_way(
    way: &str,
    dut: &mut Dut,
    scene: &Scene,
    golden: &Processor,
    pixels: &[(u32, u32)],
) -> Result<u64> {
    let mut events: Vec<TraceEvent> = Vec::new();
    let mut golden_events: Vec<TraceEvent> = Vec::new();
    let mut cycles = 0;
    match way {
        "bare" => cycles = one_pixel(dut)?.run_bare(pixels)?,
        "driver" => {
            for &(x, y) in pixels {
                cycles += one_pixel(dut)?.run_pixel(x, y, None)?.cycles;
            }
        }
        "traced" | "traced+golden" => {
            for &(x, y) in pixels {
                events.clear();
                cycles += one_pixel(dut)?.run_pixel(x, y, Some(&mut events))?.cycles;
                if way == "traced+golden" {
                    golden_events.clear();
                    let g = golden.render_pixel(x, y, |e, _| golden_events.push(*e));
                    ensure!(
                        golden_events.len() == events.len(),
                        "pixel ({x}, {y}): golden wrote {} events, the RTL {}",
                        golden_events.len(),
                        events.len()
                    );
                    std::hint::black_box(g);
                }
            }
        }
        "cosim" => {
            let window = Window::full(scene);
            let report = cosim::run_on(dut, scene, window, &CosimOptions::default(), &mut |_| {})?;
            ensure!(
                report.passed(),
                "the co-simulation found divergences:\n{report}"
            );
            cycles = report.compare.counts.a_cycles;
        }
        _ => bail!("no way '{way}'"),
    }
    Ok(cycles)
}

/// The compact processor's one-pixel driver, which the ways but `cosim`
/// drive directly.
fn one_pixel(dut: &mut Dut) -> Result<&mut PixelProcessor> {
    dut.one_pixel()
        .context("the compact processor is driven one pixel at a time")
}

fn main() -> Result<()> {
    let args = Args::parse();
    ensure!(args.rounds > 0, "--rounds must be at least 1");
    let scene = scenes::load(&args.scene)?
        .resized(args.size.0, args.size.1, "--size")
        .context("resizing the scene")?;
    let mut rtl = Design::for_scene(ProcessorKind::Compact, &scene).open()?;
    rtl.load_scene(&scene)?;
    let golden = Processor::new(&scene);
    let pixels: Vec<(u32, u32)> = Window::full(&scene).iter().collect();

    let mut times: Vec<Vec<Duration>> = vec![Vec::new(); WAYS.len()];
    let mut expected = None;
    for round in 0..args.rounds {
        for (i, way) in WAYS.iter().enumerate() {
            let start = Instant::now();
            let cycles = run_way(way, &mut rtl, &scene, &golden, &pixels)
                .with_context(|| format!("round {round}, {way}"))?;
            times[i].push(start.elapsed());
            let want = *expected.get_or_insert(cycles);
            ensure!(
                cycles == want,
                "round {round}, {way}: {cycles} RTL cycles, the first way ran {want}"
            );
        }
        eprintln!("round {} of {} done", round + 1, args.rounds);
    }
    let cycles = expected.unwrap_or(0);
    let median = |t: &mut Vec<Duration>| {
        t.sort();
        t[t.len() / 2]
    };
    let medians: Vec<Duration> = times.iter_mut().map(median).collect();
    println!(
        "{} {}x{}: {} pixels, {cycles} RTL cycles a run; one thread, median of {} rounds",
        args.scene,
        args.size.0,
        args.size.1,
        pixels.len(),
        args.rounds
    );
    println!("| way | median | M RTL cycles/s | pixels/s | time / bare |");
    println!("|---|---|---|---|---|");
    let bare = medians[0].as_secs_f64();
    for (way, t) in WAYS.iter().zip(&medians) {
        let s = t.as_secs_f64();
        println!(
            "| {way} | {s:.3} s | {:.3} | {:.0} | {:.3} |",
            cycles as f64 / s / 1e6,
            pixels.len() as f64 / s,
            s / bare
        );
    }
    Ok(())
}
