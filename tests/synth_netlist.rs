//! The synthesized netlist co-simulated (issue 23 item 3, docs/rtl.md "The
//! synthesized netlist co-simulated"): the pixel processor as Yosys'
//! generic `synth` writes it (`rtl/synth/synth.sh generic pp exact`: gates
//! and flip-flops, memories and the seed tables as logic, the trace and
//! fault ports kept), verilated with the cargo feature `synth-netlist`,
//! driven through the same ports as the RTL and compared with golden bit
//! for bit and cycle for cycle. It shows that synthesis read the RTL as
//! the simulators do: the seed tables' contents, the reset, the widths.
//!
//!     cargo test --release --features synth-netlist --test synth_netlist -- --ignored
//!
//! Without the feature, only the clear error of a missing netlist runs.

use golden::scene::Scene;
#[cfg(feature = "synth-netlist")]
use golden::{fp::Method, micro::Fault, window::Window};
#[cfg(feature = "synth-netlist")]
use rtcosim::check::cosim::{self, CosimOptions, CosimReport};
use rtcosim::design::pixel_proc::PixelProcessor;
use rtcosim::design::Design;
use rtcosim::design::Flavour;

/// Every builtin scene, with the exact methods (the netlist's).
fn builtins_exact() -> Vec<(String, Scene)> {
    Scene::builtin_names()
        .iter()
        .map(|name| {
            let scene = Scene::builtin(name).expect("a builtin");
            let mut render = scene.render;
            render.recip = golden::fp::Method::Exact;
            render.sqrt = golden::fp::Method::Exact;
            let what = format!("builtin {name}, exact methods");
            let scene = scene
                .with_render(render, &what)
                .expect("exact methods load");
            (what, scene)
        })
        .collect()
}

#[cfg(not(feature = "synth-netlist"))]
#[test]
fn without_the_feature_the_netlist_is_a_clear_error() {
    let exact = golden::fp::Method::Exact;
    let e = PixelProcessor::open(&Design::compact(exact, exact).flavour(Flavour::Synth))
        .err()
        .expect("no netlist was built");
    let text = e.to_string();
    assert!(
        text.contains("synthesized netlist model") && text.contains("--features synth-netlist"),
        "{text}"
    );
    // The scenes the ignored test runs all take the exact methods.
    assert_eq!(builtins_exact().len(), Scene::builtin_names().len());
}

/// The windows of a scene the netlist runs: 32x4 pixels about the centre
/// (objects, shadows, reflections), and the bottom-right 4x2 corner (the
/// coordinates' high bits).
#[cfg(feature = "synth-netlist")]
fn windows(scene: &Scene) -> [Window; 2] {
    let (w, h) = (scene.camera.width, scene.camera.height);
    [
        Window::new(w / 2 - 16, h / 2 - 2, 32, 4),
        Window::new(w - 4, h - 2, 4, 2),
    ]
}

/// Co-simulates `window` of `scene` on a fresh netlist model.
#[cfg(feature = "synth-netlist")]
fn run(scene: &Scene, window: Window, options: &CosimOptions) -> CosimReport {
    let design = Design::compact(Method::Exact, Method::Exact).flavour(Flavour::Synth);
    let mut rtl = design.open().expect("the netlist was built");
    assert_eq!(rtl.design(), design);
    cosim::run_on(&mut rtl, scene, window, options, &mut |_| {}).expect("the run completes")
}

#[cfg(feature = "synth-netlist")]
#[test]
#[ignore = "minutes: the netlist is Yosys' gates (docs/rtl.md)"]
fn the_synthesized_netlist_agrees_with_golden_on_a_window_of_every_builtin_scene() {
    use rayon::prelude::*;
    let runs: Vec<(String, Scene, Window)> = builtins_exact()
        .into_iter()
        .flat_map(|(what, scene)| {
            windows(&scene)
                .into_iter()
                .map(move |w| (what.clone(), scene.clone(), w))
        })
        .collect();
    let started = std::time::Instant::now();
    let reports: Vec<(String, Window, CosimReport)> = runs
        .par_iter()
        .map(|(what, scene, window)| {
            (
                what.clone(),
                *window,
                run(scene, *window, &CosimOptions::default()),
            )
        })
        .collect();
    let (mut pixels, mut cycles, mut events) = (0, 0, 0);
    for (what, window, report) in &reports {
        let c = &report.compare.counts;
        assert_eq!(c.pixels, window.pixels(), "{what} {}", window.describe());
        assert_eq!(
            c.divergent_pixels,
            0,
            "{what} {}: the netlist diverges from golden\n{report}",
            window.describe()
        );
        // Real work was compared: events written and cycles run.
        assert!(c.events_compared > 0 && c.a_cycles == c.b_cycles, "{what}");
        pixels += c.pixels;
        cycles += c.a_cycles;
        events += c.events_compared;
    }
    eprintln!(
        "synthesized netlist: {} scenes, {pixels} pixels, {events} events, {cycles} cycles, \
         0 divergences, {:.1} s",
        reports.len() / 2,
        started.elapsed().as_secs_f64()
    );
}

/// The checker can fail on the netlist: a fault through the netlist's
/// fault port (every write in PRI_HALF gets bit 10 of lane x flipped; the
/// port went through synthesis like the rest) must make pixels diverge.
#[cfg(feature = "synth-netlist")]
#[test]
#[ignore = "a minute: the netlist is Yosys' gates (docs/rtl.md)"]
fn a_fault_injected_into_the_netlist_is_caught() {
    let (what, scene) = builtins_exact().remove(0);
    let fault: Fault = "PRI_HALF:0x400".parse().expect("a fault");
    let options = CosimOptions {
        fault: Some(fault),
        ..CosimOptions::default()
    };
    let window = Window::new(scene.camera.width / 2, scene.camera.height / 2, 4, 1);
    let report = run(&scene, window, &options);
    let c = &report.compare.counts;
    assert_eq!(c.pixels, 4, "{what}");
    assert_eq!(
        c.divergent_pixels, 4,
        "{what}: the fault went unseen\n{report}"
    );
    // Without the fault the same pixels agree.
    let clean = run(&scene, window, &CosimOptions::default());
    assert_eq!(clean.compare.counts.divergent_pixels, 0, "{clean}");
}
