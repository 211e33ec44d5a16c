//! The exposure (`[render] exposure`, thesis 3.7:
//! `colour = 1 - e^(exposure * colour)`) in the scene file and both golden models: its validation, its
//! place in the text and the hashes, the cycles it costs, and the frames it
//! makes against the f64 reference. (Its stability test, colour over 1
//! detected without it and prevented with it, is in stability.rs.)

use golden::micro::FIXED_CYCLES;
use golden::scene::{RenderSettings, Scene, SceneError};

fn overexposed(w: u32, h: u32) -> Scene {
    Scene::builtin("overexposed")
        .expect("builtin")
        .resized(w, h, "test")
        .expect("valid")
}

fn with_exposure(scene: &Scene, exposure: Option<f32>) -> Scene {
    let r = RenderSettings {
        exposure,
        ..scene.render
    };
    scene.with_render(r, "test").expect("valid")
}

fn text(exposure: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 0.0, 0.0]\nrotation = [0.0, 0.0, 0.0]\ndistance = 100.0\n\
         width = 4\nheight = 4\n[light]\nposition = [0.0, 50.0, 0.0]\ncolor = [1.0, 1.0, 1.0]\n\
         [[sphere]]\ncenter = [0.0, 0.0, 50.0]\nradius = 10.0\ncolor = [1.0, 1.0, 1.0]\n\
         diffuse = 0.5\nspecular = 0.0\nreflection = 0.5\n[render]\nexposure = {exposure}\n"
    )
}

#[test]
fn bad_exposures_are_refused_naming_file_field_and_limit() {
    // 0 and -0 (every pixel black), positive, NaN, infinities, past -100.
    for bad in [
        "0.0",
        "-0.0",
        "0.5",
        "nan",
        "inf",
        "-inf",
        "-100.00001",
        "-1e300",
    ] {
        match Scene::from_toml(&text(bad), "exp.toml") {
            Err(e @ SceneError::Invalid { .. }) => {
                let msg = e.to_string();
                assert!(
                    msg.starts_with("exp.toml: render.exposure: "),
                    "{bad}: {msg}"
                );
                // The range in words, unless the number is not one at all.
                if !["nan", "inf", "-inf", "-1e300"].contains(&bad) {
                    assert!(msg.contains("[-100, 0)"), "{bad}: {msg}");
                }
            }
            other => panic!("{bad}: expected a refusal, got {other:?}"),
        }
    }
    for (good, want) in [("-100.0", -100.0f32), ("-1.0", -1.0), ("-1e-30", -1e-30)] {
        let s = Scene::from_toml(&text(good), "exp.toml").unwrap_or_else(|e| panic!("{good}: {e}"));
        assert_eq!(s.render.exposure.map(f32::to_bits), Some(want.to_bits()));
    }
    let s = Scene::from_toml(&text("-1.0").replace("exposure = -1.0\n", ""), "exp.toml")
        .expect("valid");
    assert_eq!(s.render.exposure, None, "absent = off");
}

/// The exposure is written only when set, reads back bit for bit, and is
/// part of the picture: it changes the render hash, not the configuration
/// hash, and a scene without it keeps both hashes (the pins of
/// scene_files.rs, whose scenes have none, hold).
#[test]
fn the_exposure_is_in_the_text_and_the_render_hash_only_when_set() {
    let on = overexposed(40, 30);
    assert_eq!(on.render.exposure, Some(-1.5));
    let off = with_exposure(&on, None);
    assert!(on.to_toml().contains("exposure = -1.5"), "{}", on.to_toml());
    assert!(!off.to_toml().contains("exposure"), "{}", off.to_toml());
    for s in [&on, &off] {
        assert_eq!(&Scene::from_toml(&s.to_toml(), "w.toml").expect("valid"), s);
    }
    assert_ne!(on.render_hash(), off.render_hash());
    assert_eq!(on.config_hash(), off.config_hash());
    let other = with_exposure(&on, Some(-0.5));
    assert_ne!(on.render_hash(), other.render_hash());
    // Off is off: the same hashes as the same scene read from a text
    // without the key.
    let text = Scene::builtin("overexposed")
        .expect("builtin")
        .to_toml()
        .replace("exposure = -1.5\n", "");
    let plain = Scene::from_toml(&text, "plain.toml")
        .expect("valid")
        .resized(40, 30, "test")
        .expect("valid");
    assert_eq!(plain.render.exposure, None);
    assert_eq!(plain.render_hash(), off.render_hash());
    assert_eq!(plain.config_hash(), off.config_hash());
}

/// The cycle rule (golden.md): EXPO_MUL (1), EXPO_EXP (fp_exp latency 5,
/// plus 1) and EXPO_SUB (1): 8 cycles and 3 register writes more per pixel,
/// whatever the pixel; everything before them is unchanged.
#[test]
fn the_exposure_costs_eight_cycles_and_three_writes_a_pixel() {
    let on = overexposed(24, 18);
    let off = with_exposure(&on, None);
    let (_, s_on) = golden::micro::render(&on, &|_| {});
    let (_, s_off) = golden::micro::render(&off, &|_| {});
    let pixels = 24 * 18;
    assert_eq!(s_on.cycles, s_off.cycles + 8 * pixels);
    assert_eq!(s_on.min_cycles, s_off.min_cycles + 8);
    assert_eq!(s_on.max_cycles, s_off.max_cycles + 8);
    assert_eq!(
        s_on.ops.register_writes,
        s_off.ops.register_writes + 3 * pixels
    );
    assert!(s_off.min_cycles > FIXED_CYCLES);
}

/// Both models apply 1 - e^(exposure * c) to the colour they computed
/// without it: the micro-op model in f32 through fp_exp, the reference in
/// f64. Pixel by pixel, the exposed f32 colour is within a few f32 ULPs of
/// 1 - e^(e * c) of the unexposed f32 colour c (the mapping is contractive,
/// slope e^(e c) |e| <= 1 here), and every channel lies in [0, 1).
#[test]
fn the_micro_op_model_exposes_its_own_colour() {
    let on = overexposed(32, 24);
    let off = with_exposure(&on, None);
    let (f_on, _) = golden::micro::render(&on, &|_| {});
    let (f_off, _) = golden::micro::render(&off, &|_| {});
    let e = f64::from(on.render.exposure.expect("set"));
    let mut worst = 0.0f64;
    for (a, b) in f_on.pixels.iter().zip(&f_off.pixels) {
        for ch in 0..3 {
            assert!((0.0..1.0).contains(&a[ch]), "{a:?}");
            let want = 1.0 - (e * b[ch]).exp();
            worst = worst.max((a[ch] - want).abs());
        }
    }
    // f32 steps near 1 are 2^-24; MULX, fp_exp (1 ULP) and the SUB round
    // once each.
    assert!(worst < 4.0 * 2f64.powi(-24), "worst {worst:e}");
    assert!(
        f_off.saturated_pixels() > 0,
        "the scene does go over 1 without the exposure"
    );
}

/// The exposure's three instructions come after everything else of a
/// pixel, EXP second to last: with it on, every pixel runs the same
/// instructions as with it off (the same writes, in order) and then
/// exactly EXPO_MUL, EXPO_EXP, EXPO_SUB. The fast processor's cycle rule
/// (`golden::micro::barrel::PixelWork::of`) places EXP there.
#[test]
fn the_exposure_ends_every_pixel_with_exp_second_to_last() {
    use golden::micro::barrel::PixelWork;
    use golden::micro::isa::State;
    let on = golden::micro::Processor::new(&overexposed(16, 12));
    let off = golden::micro::Processor::new(&with_exposure(&overexposed(16, 12), None));
    for (x, y) in (0..12).flat_map(|y| (0..16).map(move |x| (x, y))) {
        let (mut e_on, mut e_off) = (Vec::new(), Vec::new());
        let r_on = on.render_pixel(x, y, |e, _| e_on.push(e.state));
        let r_off = off.render_pixel(x, y, |e, _| e_off.push(e.state));
        assert_eq!(r_on.ops.instructions(), r_off.ops.instructions() + 3);
        let tail = [State::EXPO_MUL.0, State::EXPO_EXP.0, State::EXPO_SUB.0];
        assert_eq!(e_on[..e_off.len()], e_off[..], "pixel ({x}, {y})");
        assert_eq!(e_on[e_off.len()..], tail, "pixel ({x}, {y})");
        let work = PixelWork::of(&r_on);
        assert_eq!(work.exp_at, Some(r_on.ops.instructions() - 2));
        assert_eq!(PixelWork::of(&r_off).exp_at, None);
    }
}
