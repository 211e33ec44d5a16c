//! The fast processor's cycles per pixel as golden's barrel rule predicts
//! them (`golden::micro::barrel`), beside the compact processor's, on a
//! builtin scene: every pixel through golden's micro-op model in raster
//! order, all waiting at cycle 0, through K contexts (docs/fast.md). With
//! a processor count P, also the frame through a top of P fast processors
//! of K contexts (`rtl/top.v` with FAST = 1, `golden::micro::barrel::
//! run_top`: the coordinates streamed in raster order, the results taken
//! every cycle).
//!
//!     cargo run --release --example barrel_cycles -- reference 800x600 32
//!     cargo run --release --example barrel_cycles -- reference 800x600 32 34

use anyhow::{bail, Context, Result};
use golden::micro::barrel::{self, PixelWork};
use golden::micro::Processor;
use rayon::prelude::*;
use rtcosim::scenes;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (scene, size, contexts, procs) = match args.as_slice() {
        [scene, size, contexts] => (scene, size, contexts, None),
        [scene, size, contexts, procs] => (scene, size, contexts, Some(procs)),
        _ => bail!("usage: barrel_cycles SCENE WxH CONTEXTS [PROCESSORS]"),
    };
    let procs: Option<u32> = procs
        .map(|p| {
            p.parse()
                .ok()
                .filter(|&n| n > 0)
                .with_context(|| format!("processors '{p}' is not a positive number"))
        })
        .transpose()?;
    let (w, h) = size
        .split_once('x')
        .with_context(|| format!("size '{size}' is not WxH"))?;
    let (w, h): (u32, u32) = (
        w.parse().with_context(|| format!("width '{w}'"))?,
        h.parse().with_context(|| format!("height '{h}'"))?,
    );
    let contexts: u32 = contexts
        .parse()
        .ok()
        .filter(|&k| k > 0)
        .with_context(|| format!("contexts '{contexts}' is not a positive number"))?;
    let scene = scenes::load(scene)?.resized(w, h, "size")?;
    let proc = Processor::new(&scene);
    let rows: Vec<Vec<(u64, PixelWork)>> = (0..h)
        .into_par_iter()
        .map(|y| {
            (0..w)
                .map(|x| {
                    let r = proc.render_pixel(x, y, |_, _| {});
                    (r.cycles, PixelWork::of(&r))
                })
                .collect()
        })
        .collect();
    let pixels: Vec<(u64, PixelWork)> = rows.into_iter().flatten().collect();
    let n = pixels.len() as f64;
    let compact: u64 = pixels.iter().map(|(c, _)| c).sum();
    let instructions: u64 = pixels.iter().map(|(_, p)| p.instructions).sum();
    let work: Vec<PixelWork> = pixels.iter().map(|(_, p)| *p).collect();
    let run = barrel::run(contexts, &work);
    let fast = run.cycles as f64 / n;
    println!("scene {} {w}x{h}, {} pixels", args[0], pixels.len());
    println!(
        "instructions per pixel            {:.2}",
        instructions as f64 / n
    );
    println!(
        "compact processor, cycles/pixel   {:.2}",
        compact as f64 / n
    );
    println!(
        "fast processor ({contexts} contexts), cycles/pixel {fast:.2} ({} cycles; {} EXP turns passed)",
        run.cycles, run.exp_waits
    );
    println!(
        "fast / compact                    {:.3}",
        fast / (compact as f64 / n)
    );
    if let Some(procs) = procs {
        let start = barrel::TopStart {
            procs,
            contexts,
            phase: 0,
            group: 6, // rtl/top.v's ARB_GROUP
            last_grant: 0,
        };
        let top = barrel::run_top(start, &work, &|_| true);
        let mut per_proc = vec![0u64; procs as usize];
        for p in &top.pixels {
            per_proc[p.proc as usize] += 1;
        }
        let (least, most) = (per_proc.iter().min(), per_proc.iter().max());
        println!(
            "top of {procs} fast processors: {} frame cycles ({:.3} a pixel; one processor's frame / {procs} = {:.0}, so {:.4} x); pixels a processor {}..{}",
            top.frame_cycles,
            top.frame_cycles as f64 / n,
            (run.cycles + 4) as f64 / procs as f64,
            top.frame_cycles as f64 / ((run.cycles + 4) as f64 / procs as f64),
            least.unwrap_or(&0),
            most.unwrap_or(&0)
        );
    }
    Ok(())
}
