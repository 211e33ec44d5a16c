//! Refraction at the command line: golden's models and the compact
//! processor draw a glass sphere (co-simulated exactly), and every command
//! that would run the fast processor, which does not trace refraction yet,
//! refuses the scene by the field that makes it transparent before it
//! starts (golden/tests/refraction.rs has the optics).

mod common;

use common::{assert_refused, both, rtcosim};
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
fn the_compact_processor_traces_a_glass_scene_and_the_fast_one_refuses_it_by_name() {
    let path = glass_scene();
    let scene = path.to_str().expect("utf-8");
    // The compact processor co-simulates it exactly.
    let out = rtcosim(&["cosim", "--scene", scene]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = common::text(&out.stdout);
    assert!(
        stdout.contains("divergent pixels: 0") && stdout.contains("PASS: "),
        "{stdout}"
    );
    // The fast one, and every command that would run it, refuse it up front.
    let why = "sphere[0].transmission = 0.5: the fast processor traces no refraction yet";
    assert_refused(
        &["cosim", "--processor", "fast", "--scene", scene],
        &[&format!("--scene {scene}: {why}")],
    );
    assert_refused(&["tune", "--scene", scene, "--max-error", "1"], &[why]);
    let sweep = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("glass-sweep");
    assert_refused(
        &[
            "sweep",
            "--scene",
            scene,
            "--out",
            sweep.to_str().expect("utf-8"),
        ],
        &[why],
    );
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
