//! Refraction at the command line and on random glass scenes: golden's
//! models draw a glass sphere, and both processors trace it, co-simulated
//! exactly (golden/tests/refraction.rs has the optics).

mod common;

use common::{both, rtcosim};
use std::path::PathBuf;

/// The reference scene at 40x30 with its first sphere made of glass, as a
/// file under cargo's temporary directory.
fn glass_scene() -> PathBuf {
    let s = golden::scene::Scene::reference()
        .resized(40, 30, "test")
        .expect("smaller");
    let mut spheres = s.spheres.clone();
    spheres[0].material.transmission = 0.5;
    spheres[0].material.ior = 1.5;
    let glass = golden::scene::Scene::new(
        "glass",
        s.camera.clone(),
        s.light.clone(),
        spheres,
        s.planes.clone(),
        s.render,
    )
    .expect("the reference's first sphere may be glass");
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("glass.toml");
    std::fs::write(&path, glass.to_toml()).expect("writing the scene");
    path
}

#[test]
fn both_processors_trace_a_glass_scene_and_every_tool_draws_it() {
    let path = glass_scene();
    let scene = path.to_str().expect("utf-8");
    for processor in ["compact", "fast"] {
        let out = rtcosim(&["cosim", "--processor", processor, "--scene", scene]);
        assert_eq!(out.status.code(), Some(0), "{processor}: {}", both(&out));
        let stdout = common::text(&out.stdout);
        assert!(
            stdout.contains("divergent pixels: 0") && stdout.contains("PASS: "),
            "{processor}: {stdout}"
        );
    }
    let png = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("glass.png");
    let out_png = png.to_str().expect("utf-8");
    for model in ["reference", "micro"] {
        let _ = std::fs::remove_file(&png);
        let out = rtcosim(&[
            "render", "--model", model, "--scene", scene, "--out", out_png,
        ]);
        assert_eq!(out.status.code(), Some(0), "{model}: {}", both(&out));
        assert!(png.exists(), "{model}");
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("glass-maps");
    let dir = dir.to_str().expect("utf-8");
    for (a, b) in [("reference", "micro"), ("micro", "rtl")] {
        let out = rtcosim(&["diffmap", a, b, "--scene", scene, "--out", dir]);
        assert_eq!(out.status.code(), Some(0), "{a} {b}: {}", both(&out));
    }
}

/// Seeded random glass scenes, drawn where refraction is delicate (indices
/// near 1, below 1 near total internal reflection, up to 4; glass anywhere
/// in front of the camera, touching or apart), co-simulated on both
/// processors: each accepted one agrees with the micro-op model on every
/// event, colour and cycle; the refused ones are refused by name.
#[test]
fn random_glass_scenes_co_simulate_exactly_on_both_processors() {
    use golden::scene::{Camera, Light, Material, RenderSettings, Scene, Sphere};
    use golden::window::Window;
    use rand::{Rng, SeedableRng};
    use rtcosim::check::cosim::{self, CosimOptions};
    use rtcosim::design::processor::ProcessorKind;
    use rtcosim::design::Design;

    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(43);
    let (mut accepted, mut refused, mut tir) = (0, 0, 0);
    for case in 0..100 {
        let mut spheres = Vec::new();
        for _ in 0..rng.random_range(1..=4) {
            let mut m = Material::opaque(
                [rng.random(), rng.random(), rng.random()],
                rng.random_range(0.0..1.0),
                rng.random_range(0.0..1.0),
                if rng.random_bool(0.5) {
                    rng.random_range(0.0..0.6)
                } else {
                    0.0
                },
            );
            if rng.random_bool(0.7) {
                m.transmission = rng.random_range(0.05..1.0);
                m.ior = match rng.random_range(0..4) {
                    0 => 1.0 + rng.random_range(-1e-3..1e-3f32),
                    1 => rng.random_range(0.25..0.99),
                    2 => rng.random_range(1.01..2.5),
                    _ => rng.random_range(2.5..=4.0),
                };
                tir += usize::from(m.ior < 1.0);
            }
            spheres.push(Sphere {
                center: [
                    rng.random_range(-150.0..150.0),
                    rng.random_range(-100.0..100.0),
                    rng.random_range(100.0..600.0),
                ],
                radius: rng.random_range(10.0..120.0),
                material: m,
            });
        }
        let camera = Camera {
            eye: [0.0, 0.0, -300.0],
            rotation_deg: [0.0; 3],
            distance: 20.0,
            width: 16,
            height: 12,
        };
        let light = Light {
            position: [rng.random_range(-400.0..400.0), 500.0, -200.0],
            color: [1.0, 1.0, 1.0],
        };
        let render = RenderSettings {
            max_depth: rng.random_range(1..=8),
            weight_cutoff: if rng.random_bool(0.3) { 0.1 } else { 0.0 },
            ..Scene::reference().render
        };
        let render = RenderSettings {
            speedups: golden::scene::Speedups {
                bounding_box: rng.random_bool(0.5),
                fast_plane: rng.random_bool(0.5),
                shadow_shortcut: rng.random_bool(0.5),
            },
            ..render
        };
        // A floor below, now and then: glass may touch it, not cut it.
        let planes = if rng.random_bool(0.5) {
            let mut floor = Scene::reference().planes[0].clone();
            floor.offset = -150.0;
            vec![floor]
        } else {
            vec![]
        };
        let scene = match Scene::new("random glass", camera, light, spheres, planes, render) {
            Ok(s) => s,
            Err(e) => {
                let e = e.to_string();
                assert!(
                    e.contains("transparent")
                        || e.contains("render.fast_plane")
                        || e.contains("render.shadow_shortcut"),
                    "case {case}: {e}"
                );
                refused += 1;
                continue;
            }
        };
        accepted += 1;
        for kind in ProcessorKind::ALL {
            let design = Design::for_scene(kind, &scene);
            let report = cosim::run(
                &design,
                &scene,
                Window::full(&scene),
                &CosimOptions::default(),
                &|_| {},
            )
            .unwrap_or_else(|e| panic!("case {case}, {kind:?}: {e}"));
            assert!(
                report.passed(),
                "case {case}, {kind:?}:\n{}",
                scene.to_toml()
            );
        }
    }
    assert!(
        accepted >= 50 && refused > 0 && tir > 0,
        "{accepted} accepted, {refused} refused, {tir} below 1"
    );
}
