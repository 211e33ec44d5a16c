//! The weight cutoff (`[render] weight_cutoff`, thesis 3.8 end) in both
//! golden models: its validation, and its comparison, `w * kr < c` strict,
//! shown on the boundary where the child's weight equals the cutoff.
//!
//! The mirror scene has one reflection value, kr = 0.8f32, on every object,
//! so the weights are known without either model: the first reflected
//! ray's weight is 1 * 0.8f32 = 0.8f32 exactly (in f32 and in f64), the
//! second's 0.8f32^2 < 0.8f32. A cutoff of exactly 0.8f32 must keep the
//! first and refuse the second, which is the image at max_depth 2; one ULP
//! more refuses the first too, which is the image at max_depth 1. These
//! expectations come from renders without any cutoff at other depths.

use golden::scene::{RenderSettings, Scene, SceneError};

fn mirror() -> Scene {
    Scene::builtin("mirror")
        .expect("builtin")
        .resized(40, 30, "test")
        .expect("valid")
}

fn with(scene: &Scene, change: impl Fn(&mut RenderSettings)) -> Scene {
    let mut r = scene.render;
    change(&mut r);
    scene.with_render(r, "test").expect("valid")
}

fn micro(scene: &Scene) -> (Vec<[f64; 3]>, u64) {
    let (frame, stats) = golden::micro::render(scene, &|_| {});
    (frame.pixels, stats.cycles)
}

fn reference(scene: &Scene) -> Vec<[f64; 3]> {
    golden::reference::render(scene, &|_| {}).pixels
}

#[test]
fn a_cutoff_equal_to_the_weight_keeps_the_ray_and_one_ulp_more_refuses_it() {
    let base = mirror();
    let kr = base.spheres[0].material.reflection;
    assert!(
        base.spheres.iter().all(|s| s.material.reflection == kr)
            && base.planes.iter().all(|p| p.material.reflection == kr),
        "the mirror scene has one reflection value"
    );
    assert!(base.render.max_depth >= 3);
    let at = with(&base, |r| r.weight_cutoff = kr);
    let above = with(&base, |r| {
        r.weight_cutoff = f32::from_bits(kr.to_bits() + 1)
    });
    let depth2 = with(&base, |r| r.max_depth = 2);
    let depth1 = with(&base, |r| r.max_depth = 1);

    // Both models: colours.
    assert_eq!(micro(&at).0, micro(&depth2).0, "micro, cutoff = kr");
    assert_eq!(
        micro(&above).0,
        micro(&depth1).0,
        "micro, cutoff = kr + 1 ulp"
    );
    assert_eq!(reference(&at), reference(&depth2), "reference, cutoff = kr");
    assert_eq!(
        reference(&above),
        reference(&depth1),
        "reference, cutoff = kr + 1 ulp"
    );
    // And the cutoff changes the frame (it is not an image the depth-5 scene
    // already had).
    assert_ne!(micro(&at).0, micro(&base).0);

    // Cycles: the two checks (CUT_W, CUT_CMP) cost more than the depth limit
    // alone, and far less than the rays they save.
    let (c_at, c_base, c_d2) = (micro(&at).1, micro(&base).1, micro(&depth2).1);
    assert!(c_d2 < c_at && c_at < c_base, "{c_d2} < {c_at} < {c_base}");
}

#[test]
fn a_zero_cutoff_changes_nothing_not_even_a_cycle() {
    let base = mirror();
    let zero = with(&base, |r| r.weight_cutoff = 0.0);
    assert_eq!(zero, base);
    assert_eq!(zero.config_hash(), base.config_hash());
    let on = with(&base, |r| r.weight_cutoff = 1.0 / 256.0);
    assert_ne!(on.config_hash(), base.config_hash());
    // The smallest cutoff refuses nothing here (no weight is that small at
    // depth 5: 0.8^4 > 1/256), so only the checks' cycles differ.
    let (f_on, c_on) = micro(&on);
    let (f_base, c_base) = micro(&base);
    assert_eq!(f_on, f_base);
    assert!(c_on > c_base);
}

#[test]
fn the_cutoff_survives_the_scene_file() {
    let on = with(&mirror(), |r| r.weight_cutoff = 0.3);
    let text = on.to_toml();
    assert!(text.contains("weight_cutoff"), "{text}");
    assert_eq!(Scene::from_toml(&text, "round trip").expect("valid"), on);
    // Off, it is not written: scene files without it keep their text.
    assert!(!mirror().to_toml().contains("weight_cutoff"));
}

#[test]
fn bad_cutoffs_are_refused_naming_the_field() {
    let text = |c: &str| {
        format!(
            "[camera]\neye = [0.0, 0.0, 0.0]\nrotation = [0.0, 0.0, 0.0]\ndistance = 100.0\n\
             width = 4\nheight = 4\n[light]\nposition = [0.0, 50.0, 0.0]\ncolor = [1.0, 1.0, 1.0]\n\
             [[sphere]]\ncenter = [0.0, 0.0, 50.0]\nradius = 10.0\ncolor = [1.0, 1.0, 1.0]\n\
             diffuse = 0.5\nspecular = 0.0\nreflection = 0.5\n[render]\nweight_cutoff = {c}\n"
        )
    };
    for bad in ["-0.5", "1.5", "nan", "inf", "-inf", "1e300"] {
        match Scene::from_toml(&text(bad), "cut.toml") {
            Err(SceneError::Invalid { field, message, .. }) => {
                assert_eq!(field, "render.weight_cutoff", "{bad}: {message}")
            }
            other => panic!("{bad}: expected a refusal, got {other:?}"),
        }
    }
    for (good, want) in [("0.0", 0.0f32), ("-0.0", 0.0), ("1.0", 1.0), ("0.25", 0.25)] {
        let s = Scene::from_toml(&text(good), "cut.toml").unwrap_or_else(|e| panic!("{good}: {e}"));
        assert_eq!(s.render.weight_cutoff.to_bits(), want.to_bits(), "{good}");
    }
}
