//! Scene files: what loads, what is refused and how the refusal reads, and
//! the constants derived once for every model.

use golden::fp::Method;
use golden::scene::{Axis, Scene, SceneError, MAX_DEPTH, MAX_IMAGE_SIDE, MAX_PLANES, MAX_SPHERES};
use std::error::Error;
use std::path::Path;

type TestResult = Result<(), Box<dyn Error>>;

/// A small valid scene: one sphere above a floor, nothing switched on.
const BASE: &str = r#"
[camera]
eye = [0.0, 1.0, -10.0]
distance = 100.0
width = 64
height = 48

[light]
position = [0.0, 10.0, -10.0]
color = [1.0, 1.0, 1.0]

[[sphere]]
center = [0.0, 1.0, 0.0]
radius = 1.0
color = [1.0, 0.5, 0.25]
diffuse = 0.5
specular = 0.5
reflection = 0.0

[[plane]]
axis = "y"
facing = "+"
offset = -1.0
color = [1.0, 1.0, 1.0]
diffuse = 0.5
specular = 0.0
reflection = 0.5
"#;

const SPHERE: &str = r#"
[[sphere]]
center = [0.0, 1.0, 5.0]
radius = 1.0
color = [1.0, 1.0, 1.0]
diffuse = 0.5
specular = 0.5
reflection = 0.0
"#;

const PLANE: &str = r#"
[[plane]]
axis = "z"
facing = "-"
offset = 50.0
color = [1.0, 1.0, 1.0]
diffuse = 0.5
specular = 0.0
reflection = 0.5
"#;

/// `text` with `from` replaced by `to`; `from` must occur exactly once.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "{from:?} must occur once");
    text.replacen(from, to, 1)
}

/// The error `text` is refused with (the test fails if it loads).
fn refusal(text: &str) -> SceneError {
    match Scene::from_toml(text, "t.toml") {
        Ok(_) => panic!("the scene loaded, but should have been refused:\n{text}"),
        Err(e) => e,
    }
}

/// The whole error chain on one line, as the CLI prints it.
fn chain(e: &dyn Error) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(c) = source {
        s.push_str(": ");
        s.push_str(&c.to_string());
        source = c.source();
    }
    s
}

fn with_render(text: &str, render: &str) -> String {
    format!("{text}\n[render]\n{render}\n")
}

// ---------------------------------------------------------------------------
// What loads
// ---------------------------------------------------------------------------

#[test]
fn every_builtin_scene_loads() {
    for name in Scene::builtin_names() {
        assert!(
            Scene::builtin(name).is_some(),
            "builtin scene {name} does not load"
        );
    }
    assert!(Scene::builtin("no-such-scene").is_none());
}

#[test]
fn every_file_in_the_scenes_directory_is_a_builtin_and_loads_from_disk() -> TestResult {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut stems = Vec::new();
    for entry in std::fs::read_dir(&dir)? {
        let path = entry?.path();
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .ok_or("odd file name")?
            .to_string();
        let from_disk = Scene::load(&path)?;
        let builtin = Scene::builtin(&stem).ok_or(format!("{stem} is not a builtin"))?;
        assert_eq!(from_disk, builtin, "{stem}");
        stems.push(stem);
    }
    stems.sort();
    let mut names: Vec<String> = Scene::builtin_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    names.sort();
    assert_eq!(stems, names);
    Ok(())
}

#[test]
fn the_reference_scene_is_the_thesis_selected_scene() {
    let s = Scene::reference();
    assert_eq!((s.camera.width, s.camera.height), (800, 600));
    assert_eq!((s.spheres.len(), s.planes.len()), (2, 2));
    // "the planes and spheres has a diffuse value of 0.5 and a reflection value of 0.4"
    let materials = s
        .spheres
        .iter()
        .map(|x| &x.material)
        .chain(s.planes.iter().map(|p| &p.material));
    for m in materials {
        assert_eq!((m.diffuse, m.reflection), (0.5, 0.4));
    }
    assert_eq!(s.render.max_depth, 4);
    let sp = s.render.speedups;
    assert!(sp.bounding_box && sp.fast_plane && sp.shadow_shortcut);
    assert_eq!(
        (s.render.recip, s.render.sqrt),
        (Method::Exact, Method::Exact)
    );
    // A floor, and a back wall facing the camera (normal <0, 0, -1>).
    assert_eq!(
        s.derived.plane_normal,
        vec![[0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]
    );
}

#[test]
fn the_mirror_scene_is_figure_9() {
    let s = Scene::builtin("mirror").expect("builtin");
    let r = Scene::reference();
    for (m, rm) in s
        .spheres
        .iter()
        .map(|x| &x.material)
        .zip(r.spheres.iter().map(|x| &x.material))
    {
        assert_eq!((m.diffuse, m.reflection), (0.3, 0.8));
        assert_eq!(m.color, rm.color);
    }
    assert_eq!(s.render.max_depth, 5);
    assert_eq!(s.camera, r.camera);
    assert_eq!(s.light, r.light);
}

#[test]
fn the_box_room_fills_the_rtl() {
    let s = Scene::builtin("box_room").expect("builtin");
    assert_eq!((s.spheres.len(), s.planes.len()), (MAX_SPHERES, MAX_PLANES));
}

#[test]
fn the_render_section_is_optional_with_the_thesis_defaults() -> TestResult {
    let s = Scene::from_toml(BASE, "t.toml")?;
    assert_eq!(s.render.max_depth, 4);
    assert_eq!(s.render.speedups, Default::default());
    assert_eq!(
        (s.render.recip, s.render.sqrt),
        (Method::Exact, Method::Exact)
    );
    assert_eq!(s.camera.rotation_deg, [0.0; 3]);
    Ok(())
}

#[test]
fn render_settings_are_read() -> TestResult {
    let text = with_render(
        BASE,
        "max_depth = 8\nbounding_box = true\nrecip = \"fast\"\nsqrt = \"fast\"",
    );
    let s = Scene::from_toml(&text, "t.toml")?;
    assert_eq!(s.render.max_depth, MAX_DEPTH);
    assert!(s.render.speedups.bounding_box);
    assert_eq!(
        (s.render.recip, s.render.sqrt),
        (Method::Fast, Method::Fast)
    );
    Ok(())
}

#[test]
fn integers_are_accepted_where_numbers_are_expected() -> TestResult {
    let s = Scene::from_toml(&edit(BASE, "radius = 1.0", "radius = 2"), "t.toml")?;
    assert_eq!(s.spheres[0].radius, 2.0);
    Ok(())
}

#[test]
fn numbers_are_rounded_to_f32_once() -> TestResult {
    let s = Scene::from_toml(&edit(BASE, "offset = -1.0", "offset = -0.1"), "t.toml")?;
    assert_eq!(s.planes[0].offset, -0.1f32);
    assert_eq!(s.planes[0].axis, Axis::Y);
    assert_eq!(s.planes[0].facing, 1.0);
    Ok(())
}

#[test]
fn a_missing_file_is_an_io_error_naming_the_path() {
    let path = Path::new("/no/such/dir/scene.toml");
    let err = Scene::load(path).expect_err("no such file");
    assert!(matches!(err, SceneError::Io { .. }));
    let msg = chain(&err);
    assert!(
        msg.contains("/no/such/dir/scene.toml") && msg.contains("No such file"),
        "{msg}"
    );
}

#[test]
fn binary_garbage_on_disk_is_refused_as_not_utf8() -> TestResult {
    let dir = std::env::temp_dir().join(format!("golden-scene-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let path = dir.join("garbage.toml");
    std::fs::write(&path, b"[camera]\neye = [\xff\xfe\x00\x81garbage\x00")?;
    let err = Scene::load(&path).expect_err("not UTF-8");
    let msg = err.to_string();
    assert!(
        msg.contains("garbage.toml:2:") && msg.contains("not UTF-8"),
        "{msg}"
    );
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

// ---------------------------------------------------------------------------
// What is refused, and how the refusal reads
// ---------------------------------------------------------------------------

/// Asserts that `text` is refused with an error naming `field` and saying
/// `words`.
fn assert_refused(text: &str, field: &str, words: &str) {
    let err = refusal(text);
    let msg = err.to_string();
    assert_eq!(err.field(), Some(field), "{msg}");
    assert!(msg.starts_with("t.toml:"), "{msg}");
    assert!(msg.contains(&format!("{field}: ")), "{msg}");
    assert!(msg.contains(words), "expected {words:?} in: {msg}");
    assert!(msg.len() < 600, "a message of {} bytes", msg.len());
}

#[test]
fn a_negative_radius_is_refused_in_the_documented_words() {
    let text = format!("{BASE}{}", edit(SPHERE, "radius = 1.0", "radius = -3"));
    assert_eq!(
        refusal(&text).to_string(),
        "t.toml: sphere[1].radius: must be > 0, got -3"
    );
}

#[test]
fn a_zero_radius_is_refused() {
    assert_refused(
        &edit(BASE, "radius = 1.0", "radius = 0.0"),
        "sphere[0].radius",
        "must be > 0",
    );
    // 1e-50 is a positive f64 but rounds to 0 in f32.
    assert_refused(
        &edit(BASE, "radius = 1.0", "radius = 1e-50"),
        "sphere[0].radius",
        "must be > 0",
    );
}

#[test]
fn a_radius_whose_square_overflows_f32_is_refused() {
    assert_refused(
        &edit(BASE, "radius = 1.0", "radius = 1e20"),
        "sphere[0].radius",
        "MAX_RADIUS = 2^60",
    );
}

/// The magnitude limits (docs/scenes.md): each boundary is accepted, the
/// next f32 past it is refused, naming the file, the field and the limit.
#[test]
fn magnitudes_past_the_limits_are_refused_naming_field_and_limit() {
    let max = (1u64 << 60) as f64;
    let past_max = 1.1529216e18; // the next f32 above 2^60
    let min = 8.673617379884035e-19; // 2^-60
    let below_min = 8.673616e-19; // the f32 below 2^-60
    let cases: [(&str, &str, &str, &str); 6] = [
        (
            "eye = [0.0, 1.0, -10.0]",
            "eye = [0.0, {}, -10.0]",
            "camera.eye[1]",
            "MAX_COORD",
        ),
        (
            "center = [0.0, 1.0, 0.0]",
            "center = [{}, 1.0, 0.0]",
            "sphere[0].center[0]",
            "MAX_COORD",
        ),
        (
            "position = [0.0, 10.0, -10.0]",
            "position = [0.0, 10.0, {}]",
            "light.position[2]",
            "MAX_COORD",
        ),
        (
            "radius = 1.0",
            "radius = {}",
            "sphere[0].radius",
            "MAX_RADIUS",
        ),
        (
            "distance = 100.0",
            "distance = {}",
            "camera.distance",
            "MAX_DISTANCE",
        ),
        (
            "offset = -1.0",
            "offset = -{}",
            "plane[0].offset",
            "MAX_COORD",
        ),
    ];
    // A coordinate at 2^60 makes the scene's extent 2^60: the sphere then
    // needs a radius of 2^44 (MIN_RADIUS_OF_EXTENT; tested below).
    let big = edit(BASE, "radius = 1.0", "radius = 1.7592186044416e13");
    for (from, to, field, limit) in cases {
        assert!(BASE.contains(from), "{from}");
        let base = if from.starts_with("radius") {
            BASE
        } else {
            &big
        };
        let at = |v: f64| edit(base, from, &to.replace("{}", &format!("{v:e}")));
        Scene::from_toml(&at(max), "t.toml")
            .unwrap_or_else(|e| panic!("{field} = 2^60 is accepted: {e}"));
        assert_refused(&at(past_max), field, limit);
    }
    for (base, from, to, field, limit) in [
        (
            TINY,
            "radius = 1.0",
            "radius = {}",
            "sphere[0].radius",
            "MIN_RADIUS",
        ),
        (
            BASE,
            "distance = 100.0",
            "distance = {}",
            "camera.distance",
            "MIN_DISTANCE",
        ),
    ] {
        assert!(base.contains(from), "{from}");
        let at = |v: f64| edit(base, from, &to.replace("{}", &format!("{v:e}")));
        Scene::from_toml(&at(min), "t.toml")
            .unwrap_or_else(|e| panic!("{field} = 2^-60 is accepted: {e}"));
        assert_refused(&at(below_min), field, limit);
    }
    // The issue's example: an image plane at 1e-38 would underflow the
    // centre pixel's normalization.
    let err = refusal(&edit(BASE, "distance = 100.0", "distance = 1e-38"));
    assert_eq!(
        err.to_string(),
        "t.toml: camera.distance: must be in [8.6736174e-19, 1.1529215e18] \
         (MIN_DISTANCE = 2^-60 to MAX_DISTANCE = 2^60: docs/scenes.md), got 1e-38"
    );
}

/// A scene of extent 2^-46 (eye at z = -2^-46), where a sphere of radius
/// 2^-60 is more than 2^-16 of the extent.
const TINY: &str = r#"
[camera]
eye = [0.0, 0.0, -1.4210854715202004e-14]
distance = 8.0
width = 8
height = 8

[light]
position = [0.0, 1.4210854715202004e-14, -1.4210854715202004e-14]
color = [1.0, 1.0, 1.0]

[[sphere]]
center = [0.0, 0.0, 0.0]
radius = 1.0
color = [1.0, 1.0, 1.0]
diffuse = 0.5
specular = 0.5
reflection = 0.0
"#;

/// MIN_RADIUS_OF_EXTENT: a sphere of exactly 2^-16 of the scene's extent
/// loads, one f32 smaller is refused, naming the radius, the extent and the
/// field that sets it; the extent counts the eye, every sphere centre and
/// every plane offset, not the light.
#[test]
fn a_sphere_below_2_to_the_minus_16_of_the_extent_is_refused() {
    // BASE: extent 10 (camera.eye[2]); 10 * 2^-16 = 1.52587890625e-4.
    let least = 10.0 * 2f64.powi(-16);
    let at = |r: f64| edit(BASE, "radius = 1.0", &format!("radius = {r:e}"));
    Scene::from_toml(&at(least), "t.toml").expect("2^-16 of the extent loads");
    let below = f64::from(f32::from_bits((least as f32).to_bits() - 1));
    let msg = refusal(&at(below)).to_string();
    assert_eq!(
        msg,
        format!(
            "t.toml: sphere[0].radius: must be at least 1.52587890625e-4, 2^-16 of the \
             scene's extent 1e1 (at camera.eye[2]), got {:e}: f32 places a point to \
             2^-24 of its magnitude, so a smaller sphere's hit points and normals are \
             rounding noise (MIN_RADIUS_OF_EXTENT: docs/scenes.md)",
            below as f32
        )
    );
    // Each kind of coordinate sets the extent: a far second sphere, a far
    // plane; the light does not.
    let far_sphere = format!(
        "{BASE}{}",
        edit(SPHERE, "[0.0, 1.0, 5.0]", "[0.0, 1.0, 7e4]")
    );
    assert_refused(
        &far_sphere,
        "sphere[0].radius",
        "extent 7e4 (at sphere[1].center[2])",
    );
    let far_plane = edit(BASE, "offset = -1.0", "offset = -7e4");
    assert_refused(
        &far_plane,
        "sphere[0].radius",
        "extent 7e4 (at plane[0].offset)",
    );
    let far_light = edit(BASE, "[0.0, 10.0, -10.0]", "[0.0, 10.0, -7e10]");
    Scene::from_toml(&far_light, "t.toml").expect("a far light does not refuse the sphere");
}

#[test]
fn unknown_keys_are_refused_everywhere() {
    assert_refused(
        &format!("bogus = 1\n{BASE}"),
        "bogus",
        "unknown field `bogus`",
    );
    assert_refused(
        &edit(BASE, "radius = 1.0", "radius = 1.0\nradious = 2.0"),
        "sphere[0].radious",
        "unknown field",
    );
    assert_refused(
        &edit(BASE, "width = 64", "width = 64\nfov = 60"),
        "camera.fov",
        "unknown field",
    );
    assert_refused(
        &with_render(BASE, "fast_planes = true"),
        "render.fast_planes",
        "unknown field",
    );
    assert_refused(
        &format!("{BASE}\n[[cube]]\nsize = 1\n"),
        "cube",
        "unknown field `cube`",
    );
}

#[test]
fn syntax_errors_give_line_and_column() {
    let err = refusal(&edit(BASE, "radius = 1.0", "radius = \"big\""));
    assert_eq!(
        err.to_string(),
        "t.toml:14:10: sphere[0].radius: invalid type: string \"big\", expected f64"
    );
    match err {
        SceneError::Syntax { line, column, .. } => assert_eq!((line, column), (14, 10)),
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

#[test]
fn nan_and_infinity_literals_are_refused() {
    let nan = edit(
        BASE,
        "color = [1.0, 1.0, 1.0]\n\n[[sphere]]",
        "color = [1.0, 1.0, nan]\n\n[[sphere]]",
    );
    assert_refused(&nan, "light.color[2]", "not a finite number");
    assert_refused(
        &edit(BASE, "distance = 100.0", "distance = inf"),
        "camera.distance",
        "not a finite number",
    );
    assert_refused(
        &edit(BASE, "eye = [0.0, 1.0, -10.0]", "eye = [0.0, -inf, -10.0]"),
        "camera.eye[1]",
        "not a finite number",
    );
    assert_refused(
        &edit(BASE, "offset = -1.0", "offset = -nan"),
        "plane[0].offset",
        "not a finite number",
    );
}

#[test]
fn numbers_outside_the_f32_range_are_refused() {
    assert_refused(
        &edit(BASE, "distance = 100.0", "distance = 1e300"),
        "camera.distance",
        "1e300 is outside the range of f32",
    );
}

#[test]
fn image_sides_must_be_1_to_4096() {
    assert_refused(
        &edit(BASE, "width = 64", "width = 0"),
        "camera.width",
        "must be 1..=4096, got 0",
    );
    assert_refused(
        &edit(BASE, "width = 64", "width = 100000"),
        "camera.width",
        "must be 1..=4096, got 100000",
    );
    assert_refused(
        &edit(BASE, "height = 48", "height = -1"),
        "camera.height",
        "must be 1..=4096, got -1",
    );
    assert_refused(
        &edit(BASE, "width = 64", "width = 64.0"),
        "camera.width",
        "invalid type",
    );
    let max = format!("width = {MAX_IMAGE_SIDE}");
    assert!(Scene::from_toml(&edit(BASE, "width = 64", &max), "t.toml").is_ok());
}

#[test]
fn the_distance_must_be_positive() {
    assert_refused(
        &edit(BASE, "distance = 100.0", "distance = 0.0"),
        "camera.distance",
        "must be > 0",
    );
}

#[test]
fn material_values_must_lie_in_0_to_1() {
    assert_refused(
        &edit(
            BASE,
            "diffuse = 0.5\nspecular = 0.5",
            "diffuse = 1.5\nspecular = 0.5",
        ),
        "sphere[0].diffuse",
        "must be in [0, 1], got 1.5",
    );
    assert_refused(
        &edit(BASE, "reflection = 0.5", "reflection = -0.25"),
        "plane[0].reflection",
        "must be in [0, 1], got -0.25",
    );
    assert_refused(
        &edit(BASE, "color = [1.0, 0.5, 0.25]", "color = [1.0, 0.5, 1.01]"),
        "sphere[0].color[2]",
        "must be in [0, 1]",
    );
    assert_refused(
        &edit(
            BASE,
            "color = [1.0, 1.0, 1.0]\n\n[[sphere]]",
            "color = [2.0, 1.0, 1.0]\n\n[[sphere]]",
        ),
        "light.color[0]",
        "must be in [0, 1]",
    );
}

#[test]
fn nine_spheres_are_more_than_the_rtl_holds() {
    let text = format!("{BASE}{}", SPHERE.repeat(MAX_SPHERES));
    assert_eq!(
        refusal(&text).to_string(),
        "t.toml: sphere: 9 spheres, but the RTL holds at most 8"
    );
    let text = format!("{BASE}{}", SPHERE.repeat(MAX_SPHERES - 1));
    assert!(Scene::from_toml(&text, "t.toml").is_ok());
}

#[test]
fn seven_planes_are_more_than_the_rtl_holds() {
    let text = format!("{BASE}{}", PLANE.repeat(MAX_PLANES));
    assert_eq!(
        refusal(&text).to_string(),
        "t.toml: plane: 7 planes, but the RTL holds at most 6"
    );
}

#[test]
fn a_scene_needs_an_object() {
    let start = BASE.find("[[sphere]]").expect("BASE has a sphere");
    assert_refused(&BASE[..start], "sphere, plane", "no objects");
}

#[test]
fn the_stack_depth_must_be_1_to_max_depth() {
    assert_refused(
        &with_render(BASE, "max_depth = 0"),
        "render.max_depth",
        "must be 1..=8, got 0",
    );
    assert_refused(
        &with_render(BASE, "max_depth = 9"),
        "render.max_depth",
        "must be 1..=8, got 9",
    );
}

#[test]
fn wrong_types_and_choices_are_refused() {
    assert_refused(
        &edit(BASE, "axis = \"y\"", "axis = \"w\""),
        "plane[0].axis",
        "expected \"x\", \"y\" or \"z\", got \"w\"",
    );
    assert_refused(
        &edit(BASE, "facing = \"+\"", "facing = 1"),
        "plane[0].facing",
        "invalid type",
    );
    assert_refused(
        &edit(BASE, "facing = \"+\"", "facing = \"up\""),
        "plane[0].facing",
        "expected \"+\" or \"-\"",
    );
    assert_refused(
        &with_render(BASE, "recip = \"slow\""),
        "render.recip",
        "unknown variant `slow`",
    );
    assert_refused(
        &with_render(BASE, "fast_plane = 1"),
        "render.fast_plane",
        "invalid type",
    );
    assert_refused(
        &edit(BASE, "eye = [0.0, 1.0, -10.0]", "eye = [0.0, 1.0]"),
        "camera.eye",
        "invalid length 2",
    );
    assert_refused(
        &edit(BASE, "distance = 100.0\n", ""),
        "camera",
        "missing field `distance`",
    );
}

#[test]
fn a_truncated_file_is_a_syntax_error_with_a_position() {
    for cut in ["diffuse = 0.5", "[[plane]]", "color = [1.0, 0.5"] {
        let end = BASE.find(cut).expect("in BASE") + cut.len() - 3;
        let err = refusal(&BASE[..end]);
        assert!(matches!(err, SceneError::Syntax { .. }), "{err}");
        assert!(err.to_string().starts_with("t.toml:"), "{err}");
    }
    // Cut between two keys: well-formed, but the sphere lacks its fields.
    let end = BASE.find("color = [1.0, 0.5").expect("in BASE");
    assert_refused(&BASE[..end], "sphere[0]", "missing field `color`");
}

#[test]
fn an_empty_file_lacks_the_camera() {
    let err = refusal("");
    assert_eq!(err.to_string(), "t.toml:1:1: missing field `camera`");
}

#[test]
fn text_garbage_is_a_syntax_error() {
    let err = refusal("\u{0}\u{1}\u{7f}\u{fffd}{{{{ ]]]] ===");
    assert!(matches!(err, SceneError::Syntax { line: 1, .. }), "{err}");
}

#[test]
fn a_10_mb_string_gives_a_short_message_naming_the_field() {
    let big = "a".repeat(10 << 20);
    let err = refusal(&edit(BASE, "radius = 1.0", &format!("radius = \"{big}\"")));
    let msg = err.to_string();
    assert_eq!(err.field(), Some("sphere[0].radius"));
    assert!(
        msg.contains("invalid type: string") && msg.len() < 400,
        "{} bytes",
        msg.len()
    );
    // And as a key: the message quotes only its start.
    let err = refusal(&edit(
        BASE,
        "radius = 1.0",
        &format!("radius = 1.0\n{big} = 1"),
    ));
    assert!(
        err.to_string().len() < 600,
        "{} bytes",
        err.to_string().len()
    );
}

// ---------------------------------------------------------------------------
// Speed-up preconditions
// ---------------------------------------------------------------------------

#[test]
fn fast_plane_refuses_a_sphere_poking_through_a_wall() {
    // Sphere 1 (z = 5, r = 1) pokes through a back wall at z = 5.5.
    let wall = edit(PLANE, "offset = 50.0", "offset = 5.5");
    let text = with_render(&format!("{BASE}{SPHERE}{wall}"), "fast_plane = true");
    let err = refusal(&text);
    let msg = err.to_string();
    assert_eq!(err.field(), Some("render.fast_plane"));
    assert!(
        msg.contains("sphere[1]") && msg.contains("plane[1] (z = 5.5, facing -)"),
        "{msg}"
    );
    // Moved back to 6.5 it fits, with room to spare.
    let wall = edit(PLANE, "offset = 50.0", "offset = 6.5");
    assert!(Scene::from_toml(
        &with_render(&format!("{BASE}{SPHERE}{wall}"), "fast_plane = true"),
        "t.toml"
    )
    .is_ok());
}

#[test]
fn fast_plane_refuses_a_sphere_touching_a_plane() {
    // BASE's sphere (y = 1, r = 1) would rest on a floor at y = 0.
    let text = with_render(
        &edit(BASE, "offset = -1.0", "offset = 0.0"),
        "fast_plane = true",
    );
    let msg = refusal(&text).to_string();
    assert!(
        msg.contains("sphere[0]") && msg.contains("plane[0] (y = 0, facing +)"),
        "{msg}"
    );
}

#[test]
fn fast_plane_refuses_an_eye_or_light_behind_a_plane() {
    let text = with_render(
        &edit(BASE, "eye = [0.0, 1.0, -10.0]", "eye = [0.0, -2.0, -10.0]"),
        "fast_plane = true",
    );
    let msg = refusal(&text).to_string();
    assert!(msg.contains("the eye") && msg.contains("plane[0]"), "{msg}");
    let text = with_render(
        &edit(
            BASE,
            "position = [0.0, 10.0, -10.0]",
            "position = [0.0, -10.0, -10.0]",
        ),
        "fast_plane = true",
    );
    let msg = refusal(&text).to_string();
    assert!(
        msg.contains("the light") && msg.contains("plane[0]"),
        "{msg}"
    );
}

#[test]
fn shadow_shortcut_refuses_a_light_behind_a_plane() {
    let text = with_render(
        &edit(
            BASE,
            "position = [0.0, 10.0, -10.0]",
            "position = [0.0, -10.0, -10.0]",
        ),
        "shadow_shortcut = true",
    );
    let err = refusal(&text);
    let msg = err.to_string();
    assert_eq!(err.field(), Some("render.shadow_shortcut"));
    assert!(msg.contains("the light [0.0, -10.0, -10.0] is not strictly on the normal side of plane[0] (y = -1, facing +)"), "{msg}");
}

#[test]
fn shadow_shortcut_refuses_a_sphere_beyond_the_light_over_a_floor() {
    // A sphere 10 above the light, which is 11 above the floor: floor points
    // right below the light see it, and the shortcut would let that sphere
    // block them.
    let above = edit(
        SPHERE,
        "center = [0.0, 1.0, 5.0]",
        "center = [0.0, 20.0, -10.0]",
    );
    let text = with_render(&format!("{BASE}{above}"), "shadow_shortcut = true");
    let msg = refusal(&text).to_string();
    assert!(msg.ends_with("render.shadow_shortcut: sphere[1] lies beyond the light as seen from plane[0] (y = -1, facing +): the shortcut would shadow points there that the light reaches"), "{msg}");
}

#[test]
fn shadow_shortcut_names_the_sphere_that_would_be_shadowed_wrongly() {
    // No planes: only the sphere-sphere cone test can refuse.
    let start = BASE.find("[[plane]]").expect("BASE has a plane");
    let lone = &BASE[..start];
    // Light at (0, 10, -10); sphere 0 at (0, 1, 0) r 1. A sphere straight
    // beyond the light on the line from sphere 0 (direction (0, 9, -10)).
    let beyond = edit(
        SPHERE,
        "center = [0.0, 1.0, 5.0]",
        "center = [0.0, 19.0, -20.0]",
    );
    let msg = refusal(&with_render(
        &format!("{lone}{beyond}"),
        "shadow_shortcut = true",
    ))
    .to_string();
    // The sphere-sphere test is symmetric (each sphere is seen from the light
    // as large as its anti-cone is wide), and sphere 0 is checked first.
    assert!(
        msg.ends_with("render.shadow_shortcut: sphere[0] lies beyond the light as seen from sphere[1]: the shortcut would shadow points there that the light reaches"),
        "{msg}"
    );
    // Well off to the side it is fine.
    let aside = edit(
        SPHERE,
        "center = [0.0, 1.0, 5.0]",
        "center = [10.0, 1.0, 0.0]",
    );
    assert!(Scene::from_toml(
        &with_render(&format!("{lone}{aside}"), "shadow_shortcut = true"),
        "t.toml"
    )
    .is_ok());
}

#[test]
fn shadow_shortcut_refuses_a_light_inside_a_sphere() {
    let text = with_render(
        &edit(
            BASE,
            "position = [0.0, 10.0, -10.0]",
            "position = [0.0, 1.5, 0.0]",
        ),
        "shadow_shortcut = true",
    );
    let msg = refusal(&text).to_string();
    assert!(msg.contains("inside (or on) sphere[0]"), "{msg}");
}

#[test]
fn shadow_shortcut_accepts_the_base_scene() {
    let text = with_render(
        BASE,
        "shadow_shortcut = true\nfast_plane = true\nbounding_box = true",
    );
    assert!(Scene::from_toml(&text, "t.toml").is_ok());
}

#[test]
fn the_box_room_cannot_take_the_shadow_shortcut() -> TestResult {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/box_room.toml"),
    )?;
    let text = edit(&text, "shadow_shortcut = false", "shadow_shortcut = true");
    let msg = refusal(&text).to_string();
    assert!(
        msg.contains("render.shadow_shortcut: sphere[0] lies beyond the light"),
        "{msg}"
    );
    Ok(())
}

// ---------------------------------------------------------------------------
// Derived constants
// ---------------------------------------------------------------------------

#[test]
fn derived_constants_are_pinned() -> TestResult {
    let text = edit(BASE, "radius = 1.0", "radius = 4.0");
    let text = edit(
        &text,
        "center = [0.0, 1.0, 0.0]",
        "center = [0.0, 5.0, 0.0]",
    );
    let text = edit(
        &text,
        "distance = 100.0",
        "rotation = [90.0, 30.0, 0.0]\ndistance = 100.0",
    );
    let text = edit(&text, "width = 64", "width = 65");
    let d = Scene::from_toml(&text, "t.toml")?.derived;
    assert_eq!(d.inv_radius, vec![0.25]);
    assert_eq!(d.radius_sq, vec![16.0]);
    // cos 90° is not 0: it is the f32 nearest cos(pi/2) in f64, 6.1e-17.
    assert_eq!(d.cos[0], std::f64::consts::FRAC_PI_2.cos() as f32);
    assert_eq!(d.cos[0].to_bits(), 0x248d_3132);
    assert_eq!(d.sin[0], 1.0);
    // sin 30° is 0.49999999999999994 in f64, one ULP below 0.5; in f32, 0.5.
    assert_eq!(d.sin[1], 0.5);
    assert_eq!((d.cos[2], d.sin[2]), (1.0, 0.0));
    assert_eq!((d.half_width, d.half_height), (32.5, 24.0));
    assert_eq!(d.plane_normal, vec![[0.0, 1.0, 0.0]]);
    assert_eq!(
        (d.bbox_min, d.bbox_max),
        ([-4.0, 1.0, -4.0], [4.0, 9.0, 4.0])
    );
    Ok(())
}

#[test]
fn inverse_radius_is_the_correctly_rounded_f32_reciprocal() -> TestResult {
    let text = edit(BASE, "radius = 1.0", "radius = 3.0");
    let text = edit(
        &text,
        "center = [0.0, 1.0, 0.0]",
        "center = [0.0, 5.0, 0.0]",
    );
    let d = Scene::from_toml(&text, "t.toml")?.derived;
    // 1/3 = 0.0101...b; f32 0x3eaaaaab is the nearest.
    assert_eq!(d.inv_radius[0].to_bits(), 0x3eaa_aaab);
    assert_eq!(d.radius_sq, vec![9.0]);
    Ok(())
}

#[test]
fn a_facing_minus_normal_has_positive_zeros() -> TestResult {
    let s = Scene::from_toml(&format!("{BASE}{PLANE}"), "t.toml")?;
    let n = s.derived.plane_normal[1];
    assert_eq!(n, [0.0, 0.0, -1.0]);
    assert!(n[0].is_sign_positive() && n[1].is_sign_positive());
    Ok(())
}

#[test]
fn the_bounding_box_is_rounded_outwards() -> TestResult {
    // 0.1 - 0.3 and 0.1 + 0.3 are not f32 numbers: the box must still hold
    // the exact sphere.
    let text = edit(BASE, "center = [0.0, 1.0, 0.0]", "center = [0.1, 1.0, 0.1]");
    let text = edit(&text, "radius = 1.0", "radius = 0.3");
    let s = Scene::from_toml(&text, "t.toml")?;
    let (c, r) = (
        f64::from(s.spheres[0].center[0]),
        f64::from(s.spheres[0].radius),
    );
    let (lo, hi) = (
        f64::from(s.derived.bbox_min[0]),
        f64::from(s.derived.bbox_max[0]),
    );
    assert!(lo <= c - r && hi >= c + r);
    // ... and is the tightest such f32 box.
    assert!(f64::from(f32::from_bits(s.derived.bbox_min[0].to_bits() - 1)) > c - r);
    Ok(())
}

#[test]
fn the_bounding_box_spans_all_spheres() -> TestResult {
    let s = Scene::from_toml(&format!("{BASE}{SPHERE}"), "t.toml")?;
    assert_eq!(
        (s.derived.bbox_min, s.derived.bbox_max),
        ([-1.0, 0.0, -1.0], [1.0, 2.0, 6.0])
    );
    Ok(())
}

#[test]
fn with_no_spheres_the_bounding_box_is_the_origin() -> TestResult {
    let start = BASE.find("[[sphere]]").expect("sphere");
    let end = BASE.find("[[plane]]").expect("plane");
    let text = format!("{}{}", &BASE[..start], &BASE[end..]);
    let s = Scene::from_toml(&text, "t.toml")?;
    assert_eq!(
        (s.derived.bbox_min, s.derived.bbox_max),
        ([0.0; 3], [0.0; 3])
    );
    Ok(())
}

// ---------------------------------------------------------------------------
// Resizing and hashing
// ---------------------------------------------------------------------------

#[test]
fn resizing_scales_the_image_plane_distance_with_the_width() -> TestResult {
    let s = Scene::reference().resized(200, 100, "--size")?;
    assert_eq!(
        (s.camera.width, s.camera.height, s.camera.distance),
        (200, 100, 150.0)
    );
    assert_eq!((s.derived.half_width, s.derived.half_height), (100.0, 50.0));
    let err = Scene::reference()
        .resized(0, 100, "--size")
        .expect_err("width 0");
    assert_eq!(
        err.to_string(),
        "--size: camera.width: must be 1..=4096, got 0"
    );
    Ok(())
}

#[test]
fn the_hashes_are_stable_and_split_picture_from_configuration() -> TestResult {
    let a = Scene::from_toml(BASE, "a.toml")?;
    let b = Scene::from_toml(BASE, "b.toml")?;
    assert_eq!(a.render_hash(), b.render_hash());
    assert_eq!(a.config_hash(), b.config_hash());
    // Pinned: the hashes are recorded in trace files, so they must not drift.
    assert_eq!(a.render_hash(), 0x9191_595d_c3e9_c0cf);
    assert_eq!(a.config_hash(), 0xb001_20a8_9f5a_016b);
    // One ULP in one number changes the picture's hash, not the
    // configuration's.
    let c = Scene::from_toml(&edit(BASE, "radius = 1.0", "radius = 1.0000001"), "c.toml")?;
    assert_eq!(c.spheres[0].radius.to_bits(), 1.0f32.to_bits() + 1);
    assert_ne!(a.render_hash(), c.render_hash());
    assert_eq!(a.config_hash(), c.config_hash());
    // So does the image size.
    let s = a.resized(a.camera.width, a.camera.height + 1, "--size")?;
    assert_ne!(a.render_hash(), s.render_hash());
    // Each setting changes the configuration's hash, not the picture's.
    for setting in [
        "sqrt = \"fast\"",
        "recip = \"fast\"",
        "max_depth = 3",
        "bounding_box = true",
        "fast_plane = true",
        "shadow_shortcut = true",
    ] {
        let d = Scene::from_toml(&with_render(BASE, setting), "d.toml")?;
        assert_eq!(a.render_hash(), d.render_hash(), "{setting}");
        assert_ne!(a.config_hash(), d.config_hash(), "{setting}");
    }
    Ok(())
}

#[test]
fn a_scene_written_as_toml_reads_back_bit_for_bit() -> TestResult {
    for name in Scene::builtin_names() {
        let scene = Scene::builtin(name).ok_or("builtin")?;
        let text = scene.to_toml();
        let back = Scene::from_toml(&text, "written.toml")?;
        assert_eq!(back, scene, "{name}:\n{text}");
    }
    // Numbers no decimal literal of a hand-written file would pick.
    let odd = edit(BASE, "radius = 1.0", "radius = 1.0000001");
    let scene = Scene::from_toml(&with_render(&odd, "max_depth = 7"), "odd.toml")?;
    assert_eq!(Scene::from_toml(&scene.to_toml(), "w.toml")?, scene);
    Ok(())
}

/// `framed_as`: a scene file whose camera distance was written for an
/// 800-pixel image but whose image is 16x12 (a field of view 50 times
/// narrower) is the reference resized to 16x12 once framed as 800 wide;
/// framing as its own width changes nothing; a wider layout halves the
/// distance.
#[test]
fn framed_as_gives_the_field_of_view_of_the_layout_width() -> TestResult {
    let reference = Scene::reference();
    let text = edit(
        &edit(&reference.to_toml(), "width = 800", "width = 16"),
        "height = 600",
        "height = 12",
    );
    let narrow = Scene::from_toml(&text, "narrow")?;
    assert_eq!(narrow.camera.distance, reference.camera.distance);
    let framed = narrow.framed_as(800, "framed")?;
    assert_eq!(framed.camera, reference.resized(16, 12, "small")?.camera);
    assert_eq!(framed.framed_as(16, "same")?.camera, framed.camera);
    assert_eq!(
        reference.framed_as(1600, "wide")?.camera.distance,
        reference.camera.distance / 2.0
    );
    Ok(())
}
