//! The scene file format: TOML text to a [`RawScene`], the scene as written,
//! before any check.
//!
//! The raw types mirror the file (serde derives their shape, and
//! `deny_unknown_fields` refuses any key they do not name). Their numbers
//! are wide, f64 and i64, so that every value a file can spell (1e300, -1,
//! 100000) reaches the validation (`super::validate`) and gets its message
//! there, rather than a type error here. A scene built in code takes the
//! same path: [`RawScene::from_parts`] widens it, exactly.

use super::error::SceneError;
use super::types::{Axis, Camera, Light, Material, Plane, RenderSettings, Sphere, Vec3f};
use crate::fp::Method;
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScene {
    pub camera: RawCamera,
    pub light: RawLight,
    #[serde(default)]
    pub sphere: Vec<RawSphere>,
    #[serde(default)]
    pub plane: Vec<RawPlane>,
    #[serde(default)]
    pub render: RawRender,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    pub eye: [f64; 3],
    #[serde(default)]
    pub rotation: [f64; 3],
    pub distance: f64,
    pub width: i64,
    pub height: i64,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLight {
    pub position: [f64; 3],
    pub color: [f64; 3],
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSphere {
    pub center: [f64; 3],
    pub radius: f64,
    pub color: [f64; 3],
    pub diffuse: f64,
    pub specular: f64,
    pub reflection: f64,
    /// Absent means 0 (opaque), and is not written.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub transmission: f64,
    /// Absent means 1, and is not written.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub ior: f64,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPlane {
    pub axis: RawAxis,
    pub facing: RawFacing,
    pub offset: f64,
    pub color: [f64; 3],
    pub diffuse: f64,
    pub specular: f64,
    pub reflection: f64,
    /// Absent means 0 (opaque), and is not written.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub transmission: f64,
    /// Absent means 1, and is not written.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub ior: f64,
}

/// `axis = "x" | "y" | "z"`.
#[derive(Deserialize, Serialize, Clone, Copy)]
#[serde(try_from = "String", into = "String")]
pub(super) struct RawAxis(pub Axis);

impl From<RawAxis> for String {
    fn from(a: RawAxis) -> String {
        a.0.name().to_string()
    }
}

impl TryFrom<String> for RawAxis {
    type Error = String;

    fn try_from(s: String) -> Result<RawAxis, String> {
        match s.as_str() {
            "x" => Ok(RawAxis(Axis::X)),
            "y" => Ok(RawAxis(Axis::Y)),
            "z" => Ok(RawAxis(Axis::Z)),
            _ => Err(format!("expected \"x\", \"y\" or \"z\", got {s:?}")),
        }
    }
}

/// `facing = "+" | "-"`: +1.0 or -1.0. (From code, any f32: the
/// validation checks it is one of the two.)
#[derive(Deserialize, Serialize, Clone, Copy)]
#[serde(try_from = "String", into = "String")]
pub(super) struct RawFacing(pub f32);

impl From<RawFacing> for String {
    /// A valid scene's facing is +1 or -1 (validated before it is written).
    fn from(f: RawFacing) -> String {
        if f.0 < 0.0 { "-" } else { "+" }.to_string()
    }
}

impl TryFrom<String> for RawFacing {
    type Error = String;

    fn try_from(s: String) -> Result<RawFacing, String> {
        match s.as_str() {
            "+" => Ok(RawFacing(1.0)),
            "-" => Ok(RawFacing(-1.0)),
            _ => Err(format!("expected \"+\" or \"-\", got {s:?}")),
        }
    }
}

/// `recip` and `sqrt`: `"exact" | "fast"`.
#[derive(Deserialize, Serialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
pub(super) enum RawMethod {
    Exact,
    Fast,
}

impl From<RawMethod> for Method {
    fn from(m: RawMethod) -> Method {
        match m {
            RawMethod::Exact => Method::Exact,
            RawMethod::Fast => Method::Fast,
        }
    }
}

impl From<Method> for RawMethod {
    fn from(m: Method) -> RawMethod {
        match m {
            Method::Exact => RawMethod::Exact,
            Method::Fast => RawMethod::Fast,
        }
    }
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub(super) struct RawRender {
    pub max_depth: i64,
    pub bounding_box: bool,
    pub fast_plane: bool,
    pub shadow_shortcut: bool,
    pub recip: RawMethod,
    pub sqrt: RawMethod,
    /// Written only when on, so that scenes without it keep their text.
    #[serde(skip_serializing_if = "is_zero")]
    pub weight_cutoff: f64,
    /// Absent means off, and is not written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exposure: Option<f64>,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_one(x: &f64) -> bool {
    *x == 1.0
}

fn one() -> f64 {
    1.0
}

impl Default for RawRender {
    fn default() -> RawRender {
        RawRender {
            // The stack the thesis implemented in Verilog (3.8).
            max_depth: 4,
            bounding_box: false,
            fast_plane: false,
            shadow_shortcut: false,
            recip: RawMethod::Exact,
            sqrt: RawMethod::Exact,
            weight_cutoff: 0.0,
            exposure: None,
        }
    }
}

impl RawScene {
    /// Parses a scene file's text; `origin` names the file in errors.
    pub fn parse(text: &str, origin: &str) -> Result<RawScene, SceneError> {
        let de =
            toml::Deserializer::parse(text).map_err(|e| syntax_error(origin, text, None, &e))?;
        serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            let field = (field != ".").then_some(field);
            syntax_error(origin, text, field, e.inner())
        })
    }

    /// The scene file's text. Every number is written as the shortest
    /// decimal that reads back to the same f64, and the f64s hold the
    /// scene's f32s exactly, so [`RawScene::parse`] of the text gives the
    /// same scene, bit for bit.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a scene's numbers, arrays and strings are all TOML")
    }

    /// A scene built in code, in the file's shape: every number widened,
    /// exactly, so that it is validated as a file would be.
    pub fn from_parts(
        camera: &Camera,
        light: &Light,
        spheres: &[Sphere],
        planes: &[Plane],
        render: &RenderSettings,
    ) -> RawScene {
        let wide = |v: Vec3f| v.map(f64::from);
        let m = |m: &Material| {
            (
                wide(m.color),
                f64::from(m.diffuse),
                f64::from(m.specular),
                f64::from(m.reflection),
                f64::from(m.transmission),
                f64::from(m.ior),
            )
        };
        RawScene {
            camera: RawCamera {
                eye: wide(camera.eye),
                rotation: wide(camera.rotation_deg),
                distance: f64::from(camera.distance),
                width: i64::from(camera.width),
                height: i64::from(camera.height),
            },
            light: RawLight {
                position: wide(light.position),
                color: wide(light.color),
            },
            sphere: spheres
                .iter()
                .map(|s| {
                    let (color, diffuse, specular, reflection, transmission, ior) = m(&s.material);
                    RawSphere {
                        center: wide(s.center),
                        radius: f64::from(s.radius),
                        color,
                        diffuse,
                        specular,
                        reflection,
                        transmission,
                        ior,
                    }
                })
                .collect(),
            plane: planes
                .iter()
                .map(|p| {
                    let (color, diffuse, specular, reflection, transmission, ior) = m(&p.material);
                    RawPlane {
                        axis: RawAxis(p.axis),
                        facing: RawFacing(p.facing),
                        offset: f64::from(p.offset),
                        color,
                        diffuse,
                        specular,
                        reflection,
                        transmission,
                        ior,
                    }
                })
                .collect(),
            render: RawRender {
                max_depth: i64::from(render.max_depth),
                bounding_box: render.speedups.bounding_box,
                fast_plane: render.speedups.fast_plane,
                shadow_shortcut: render.speedups.shadow_shortcut,
                recip: render.recip.into(),
                sqrt: render.sqrt.into(),
                weight_cutoff: f64::from(render.weight_cutoff),
                exposure: render.exposure.map(f64::from),
            },
        }
    }
}

/// Reads a scene file as text; errors name `path`.
pub(super) fn read(path: &Path) -> Result<String, SceneError> {
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let valid_up_to = e.utf8_error().valid_up_to();
        let valid = std::str::from_utf8(&bytes[..valid_up_to]).unwrap_or_default();
        let (line, column) = line_column(valid, valid.len());
        SceneError::Syntax {
            origin: path.display().to_string(),
            line,
            column,
            field: None,
            message: "not UTF-8 text".to_string(),
        }
    })
}

/// Longest message quoted from the TOML parser: a hostile file can make it
/// quote megabytes of itself.
const MAX_MESSAGE_CHARS: usize = 240;

/// Longest field path quoted (a hostile key can be megabytes long).
const MAX_FIELD_CHARS: usize = 80;

fn syntax_error(
    origin: &str,
    text: &str,
    field: Option<String>,
    e: &toml::de::Error,
) -> SceneError {
    let (line, column) = match e.span() {
        Some(span) => line_column(text, span.start),
        None => (1, 1),
    };
    SceneError::Syntax {
        origin: origin.to_string(),
        line,
        column,
        field: field.map(|f| shorten(&f, MAX_FIELD_CHARS)),
        message: shorten(e.message().trim(), MAX_MESSAGE_CHARS),
    }
}

/// Cuts `s` to `max` characters on one line.
fn shorten(s: &str, max: usize) -> String {
    let one_line = s.replace('\n', "; ");
    if one_line.chars().count() <= max {
        one_line
    } else {
        let cut: String = one_line.chars().take(max).collect();
        format!("{cut}... ({} characters in all)", one_line.chars().count())
    }
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[line_start..].chars().count() + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_lines_and_characters_from_1() {
        let text = "ab\ncé\nxyz";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 3), (2, 1));
        // 'é' is two bytes; the byte after it is the third character.
        assert_eq!(line_column(text, 6), (2, 3));
        // Inside a character, or past the end: clamped, never a panic.
        assert_eq!(line_column(text, 5), (2, 2));
        assert_eq!(line_column(text, 999), (3, 4));
    }

    #[test]
    fn long_messages_are_cut_to_one_short_line() {
        assert_eq!(shorten("a\nb", 10), "a; b");
        let cut = shorten(&"x".repeat(1000), 5);
        assert_eq!(cut, "xxxxx... (1000 characters in all)");
    }
}
