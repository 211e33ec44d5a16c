//! Hand-built test scenes shared by the renderer tests; the values derived
//! from them by hand live with the tests that use them.

/// The eye at the origin looking along +z through a 4x4 image (so pixel
/// (2, 2) looks exactly along +z), the light at the eye with colour
/// (1, 0.5, 1), and a sphere of radius 2 at z = 10: the centre ray meets it
/// at (0, 0, 8), where n = l = r = (0, 0, -1).
///
/// Sphere material: C = (1, 0.5, 0.25), kd = 0.5, ks = 0.25, kr = 0.5.
pub const ONE_SPHERE: &str = r#"
[camera]
eye = [0.0, 0.0, 0.0]
distance = 1.0
width = 4
height = 4

[light]
position = [0.0, 0.0, 0.0]
color = [1.0, 0.5, 1.0]

[[sphere]]
center = [0.0, 0.0, 10.0]
radius = 2.0
color = [1.0, 0.5, 0.25]
diffuse = 0.5
specular = 0.25
reflection = 0.5
"#;

/// A wall behind the eye at z = -5, facing +z (towards the sphere), grey
/// 0.5, kd = 0.5, ks = 0, kr = 0.5. The sphere's reflected ray (0, 0, -1)
/// from (0, 0, 8) meets it at (0, 0, -5), where n = l = (0, 0, 1); the
/// sphere lies beyond the light, so it does not shadow the wall.
pub const WALL_BEHIND: &str = r#"
[[plane]]
axis = "z"
facing = "+"
offset = -5.0
color = [0.5, 0.5, 0.5]
diffuse = 0.5
specular = 0.0
reflection = 0.5
"#;
