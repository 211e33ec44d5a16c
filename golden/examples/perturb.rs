//! The perturbation study over the builtin scenes at full size
//! (docs/accuracy.md, "Stability"): each primary direction moved by ±1 ULP
//! in each lane in the micro-op model; the pixels whose colour changes by
//! more than 0.5/255, against the reference's geometric edge mask dilated by
//! one pixel. Prints a Markdown table and writes a flip map per scene
//! (`OUT/<scene>-flips.png`: black stable, grey edge mask, white unstable
//! on an edge, red unstable off the edges).
//!
//!     cargo run --release -p golden --example perturb -- OUT [SCENE...]
//!
//! Exits with status 1 if any unstable pixel lies off the edges.

use golden::scene::Scene;
use golden::stability;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(out) = args.next().map(PathBuf::from) else {
        eprintln!("usage: perturb OUT_DIR [SCENE...] (default: every builtin scene)");
        return ExitCode::from(2);
    };
    let names: Vec<String> = args.collect();
    let names: Vec<&str> = if names.is_empty() {
        Scene::builtin_names().to_vec()
    } else {
        names.iter().map(String::as_str).collect()
    };
    if let Err(e) = std::fs::create_dir_all(&out) {
        eprintln!("{}: cannot create the directory: {e}", out.display());
        return ExitCode::from(2);
    }
    println!("| scene | size | unstable pixels | unstable share | off the edges | edge mask share (dilated) | largest change off the edges (/255) | time |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut failed = false;
    for name in names {
        let Some(scene) = Scene::builtin(name) else {
            eprintln!(
                "{name}: not a builtin scene; the builtins: {}",
                Scene::builtin_names().join(", ")
            );
            return ExitCode::from(2);
        };
        let start = Instant::now();
        let p = stability::perturb(&scene, &|_| {});
        let off = p.unexplained();
        failed |= !off.is_empty();
        println!(
            "| {name} | {}x{} | {} | {:.3}% | {} | {:.1}% | {:.4} | {:.0} s |",
            scene.camera.width,
            scene.camera.height,
            p.unstable.count(),
            100.0 * p.unstable.share(),
            off.len(),
            100.0 * p.edges.share(),
            p.largest_change_off_edges(),
            start.elapsed().as_secs_f64()
        );
        if !off.is_empty() {
            eprintln!(
                "{name}: unstable off the edges, first {:?}",
                &off[..off.len().min(10)]
            );
        }
        let path = out.join(format!("{name}-flips.png"));
        if let Err(e) = p.flip_map().save(&path) {
            eprintln!("{}: cannot write the flip map: {e}", path.display());
            return ExitCode::from(2);
        }
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
