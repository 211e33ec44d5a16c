//! Prints the scene-port writes that load a scene, one a line:
//! `cfg addr x y z` (cfg 0 or 1, addr decimal, the three lanes in hex), in
//! the order the harness writes them. For driving the RTL without the
//! harness, as benches/levers/levers.sh does.
//!
//!     cargo run --release --example scene_writes -- reference 200x150 > writes.txt

use anyhow::{bail, Context, Result};
use rtcosim::design::scene_port_writes;
use rtcosim::scenes;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene, size] = args.as_slice() else {
        bail!("usage: scene_writes SCENE WxH");
    };
    let (w, h) = size
        .split_once('x')
        .with_context(|| format!("size '{size}' is not WxH"))?;
    let (w, h) = (
        w.parse().with_context(|| format!("width '{w}'"))?,
        h.parse().with_context(|| format!("height '{h}'"))?,
    );
    let scene = scenes::load(scene)?.resized(w, h, "size")?;
    for (cfg, addr, [x, y, z]) in scene_port_writes(&scene) {
        println!("{} {addr} {x:08x} {y:08x} {z:08x}", u8::from(cfg));
    }
    Ok(())
}
