//! Scenes: the TOML scene file, its validation, and the constants derived
//! from it once for every model.
//!
//! A scene is a camera, one point light, up to [`MAX_SPHERES`] spheres and up
//! to [`MAX_PLANES`] axis-aligned planes, plus the render settings (ray stack
//! depth, the speed-ups of thesis section 3.10, the float unit methods).
//!
//! Numbers are read from TOML as f64 and rounded to f32 exactly once, here.
//! The f32 values *are* the scene: the RTL, the micro-op model and the f64
//! reference renderer (which widens them back, exactly) all see the same
//! numbers. Constants the hardware needs precomputed ([`Derived`]: 1/r, r²,
//! cos/sin of the camera angles, ...) are also computed once, here, so that no
//! two consumers can round them differently.
//!
//! ```toml
//! [camera]
//! eye = [0.0, 100.0, -400.0]
//! rotation = [0.0, 0.0, 0.0]   # degrees about x, then y, then z (optional)
//! distance = 600.0             # eye to image plane, in pixels
//! width = 800
//! height = 600
//!
//! [light]
//! position = [-300.0, 600.0, -300.0]
//! color = [1.0, 1.0, 1.0]
//!
//! [[sphere]]
//! center = [0.0, 100.0, 150.0]
//! radius = 100.0
//! color = [0.9, 0.3, 0.2]
//! diffuse = 0.5
//! specular = 0.5
//! reflection = 0.4
//!
//! [[plane]]
//! axis = "y"      # the plane is { p : p[axis] = offset }
//! facing = "+"    # normal = facing * unit(axis): the visible, lit side
//! offset = 0.0
//! color = [0.8, 0.8, 0.8]
//! diffuse = 0.5
//! specular = 0.0
//! reflection = 0.4
//!
//! [render]        # optional; these are the defaults
//! max_depth = 4
//! bounding_box = false
//! fast_plane = false
//! shadow_shortcut = false
//! recip = "exact"
//! sqrt = "exact"
//! ```
//!
//! Unknown keys are errors everywhere, and every error names the file and the
//! field (`scene.toml: sphere[1].radius: must be > 0, got -3`).

use crate::fp::Method;
use glam::DVec3;
use serde::Deserialize;
use std::fmt;
use std::path::{Path, PathBuf};

/// Spheres the RTL's scene memory holds.
pub const MAX_SPHERES: usize = 8;
/// Planes the RTL's scene memory holds.
pub const MAX_PLANES: usize = 6;
/// Deepest ray stack the RTL can be built with: generations of open-air rays
/// (1 = primary rays only, no reflections).
pub const MAX_DEPTH: u32 = 8;
/// Largest image width or height, in pixels (pixel coordinates are 12 bits).
pub const MAX_IMAGE_SIDE: u32 = 4096;

/// A point, direction or RGB colour as the hardware holds it.
pub type Vec3f = [f32; 3];

/// The eye and its image plane (thesis 3.5).
///
/// The ray through pixel (px, py), py = 0 at the top, has the camera-space
/// direction `(px - width/2, height/2 - py, distance)`, rotated by
/// `Rz * Ry * Rx` (angles `rotation_deg`, right-handed rotations as in the
/// thesis' equation 13), then normalized.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    /// Origin of every primary ray.
    pub eye: Vec3f,
    /// Rotation about x, then y, then z, in degrees.
    pub rotation_deg: Vec3f,
    /// Distance from the eye to the image plane, in pixels (> 0); sets the
    /// field of view.
    pub distance: f32,
    /// Image width in pixels, 1..=[`MAX_IMAGE_SIDE`].
    pub width: u32,
    /// Image height in pixels, 1..=[`MAX_IMAGE_SIDE`].
    pub height: u32,
}

/// The single point light (thesis 3.10.3: "infinitesimal").
#[derive(Debug, Clone, PartialEq)]
pub struct Light {
    pub position: Vec3f,
    /// RGB, each channel in [0, 1].
    pub color: Vec3f,
}

/// Surface properties (thesis 3.4): every value in [0, 1].
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// RGB; scales the diffuse term only (specular light has the light's colour).
    pub color: Vec3f,
    /// Weight of the diffuse term `n·l`.
    pub diffuse: f32,
    /// Weight of the specular term `(r·l)^20`.
    pub specular: f32,
    /// Weight of the reflected ray's colour.
    pub reflection: f32,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Sphere {
    pub center: Vec3f,
    /// > 0.
    pub radius: f32,
    pub material: Material,
}

/// A coordinate axis; planes are perpendicular to one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// 0, 1 or 2: the vector component this axis selects.
    pub const fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// "x", "y" or "z", as in scene files.
    pub const fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The infinite, one-sided plane `{ p : p[axis] = offset }`.
///
/// Its normal is `facing * unit(axis)`; only rays travelling against the
/// normal (coming from the normal side) hit it.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    pub axis: Axis,
    /// +1.0 or -1.0.
    pub facing: f32,
    pub offset: f32,
    pub material: Material,
}

/// The speed-ups of thesis 3.10. None of them may change the image: the
/// scene is validated against each one's precondition when it is switched on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Speedups {
    /// 3.10.1: test the spheres only if the ray hits the box around them.
    pub bounding_box: bool,
    /// 3.10.2: a plane is hit iff the ray's direction opposes its normal.
    pub fast_plane: bool,
    /// 3.10.3: shadow rays ignore planes, and any sphere hit at t > 0 blocks.
    pub shadow_shortcut: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderSettings {
    /// Ray stack depth: generations of open-air rays, 1..=[`MAX_DEPTH`].
    pub max_depth: u32,
    pub speedups: Speedups,
    /// Method of the RTL's reciprocal unit.
    pub recip: Method,
    /// Method of the RTL's square-root unit.
    pub sqrt: Method,
}

/// Constants derived from the scene, computed once here in f32 and shared by
/// every model and the RTL loader, so that none can round them differently.
#[derive(Debug, Clone, PartialEq)]
pub struct Derived {
    /// cos of the camera rotation angles: computed in f64, rounded to f32.
    pub cos: Vec3f,
    /// sin of the camera rotation angles: computed in f64, rounded to f32.
    pub sin: Vec3f,
    /// width / 2 (exact in f32).
    pub half_width: f32,
    /// height / 2 (exact in f32).
    pub half_height: f32,
    /// 1/r per sphere: `1.0f64 / r` rounded to f32 (which is the correctly
    /// rounded f32 reciprocal).
    pub inv_radius: Vec<f32>,
    /// r*r per sphere, in f32.
    pub radius_sq: Vec<f32>,
    /// `facing * unit(axis)` per plane (the other components are +0.0).
    pub plane_normal: Vec<Vec3f>,
    /// Lower corner of the axis-aligned box around all spheres: the exact
    /// `center - radius`, rounded down to f32 so the box never cuts a sphere.
    /// With no spheres the box is the single point at the origin (a ray that
    /// hits it then tests zero spheres, so the image does not change).
    pub bbox_min: Vec3f,
    /// Upper corner: the exact `center + radius`, rounded up to f32.
    pub bbox_max: Vec3f,
}

/// A validated scene. Build it with [`Scene::from_toml`], [`Scene::load`],
/// [`Scene::builtin`] or [`Scene::new`]: each checks every rule below, so a
/// `Scene` is always renderable by every model.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub camera: Camera,
    pub light: Light,
    pub spheres: Vec<Sphere>,
    pub planes: Vec<Plane>,
    pub render: RenderSettings,
    pub derived: Derived,
}

/// Why a scene was refused. Every variant names the file (`origin`).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{}: cannot read the scene file", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Not TOML, or TOML that does not have the shape of a scene (an unknown
    /// key, a missing one, a wrong type). `line` and `column` count from 1;
    /// `field` is the path of the offending key when it is known.
    #[error("{origin}:{line}:{column}: {}{message}", field_prefix(.field))]
    Syntax {
        origin: String,
        line: usize,
        column: usize,
        field: Option<String>,
        message: String,
    },
    /// Well-formed, but a value breaks a rule (a range, a limit of the RTL,
    /// the precondition of a speed-up).
    #[error("{origin}: {field}: {message}")]
    Invalid {
        origin: String,
        field: String,
        message: String,
    },
}

fn field_prefix(field: &Option<String>) -> String {
    field.as_ref().map_or(String::new(), |f| format!("{f}: "))
}

impl SceneError {
    /// The path of the offending field (`sphere[1].radius`), when known.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Io { .. } => None,
            SceneError::Syntax { field, .. } => field.as_deref(),
            SceneError::Invalid { field, .. } => Some(field),
        }
    }
}

// ---------------------------------------------------------------------------
// Builtin scenes
// ---------------------------------------------------------------------------

const BUILTIN_NAMES: &[&str] = &[
    "reference",
    "mirror",
    "grazing",
    "light_touch",
    "parallel_plane",
    "box_room",
];

fn builtin_text(name: &str) -> Option<&'static str> {
    Some(match name {
        "reference" => include_str!("../scenes/reference.toml"),
        "mirror" => include_str!("../scenes/mirror.toml"),
        "grazing" => include_str!("../scenes/grazing.toml"),
        "light_touch" => include_str!("../scenes/light_touch.toml"),
        "parallel_plane" => include_str!("../scenes/parallel_plane.toml"),
        "box_room" => include_str!("../scenes/box_room.toml"),
        _ => return None,
    })
}

impl Scene {
    /// Parses and validates a scene file's text. `origin` names the file in
    /// errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let de =
            toml::Deserializer::parse(text).map_err(|e| syntax_error(origin, text, None, &e))?;
        let raw: RawScene = serde_path_to_error::deserialize(de).map_err(|e| {
            let field = e.path().to_string();
            let field = (field != ".").then_some(field);
            syntax_error(origin, text, field, e.inner())
        })?;
        raw.into_scene(origin)
    }

    /// Reads, parses and validates a scene file; errors name `path`.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let bytes = std::fs::read(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let origin = path.display().to_string();
        let text = std::str::from_utf8(&bytes).map_err(|e| {
            let valid = std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default();
            let (line, column) = line_column(valid, valid.len());
            SceneError::Syntax {
                origin: origin.clone(),
                line,
                column,
                field: None,
                message: "not UTF-8 text".to_string(),
            }
        })?;
        Scene::from_toml(text, &origin)
    }

    /// A scene embedded in the binary: "reference", "mirror", or a stress
    /// scene by file stem (see [`Scene::builtin_names`]).
    pub fn builtin(name: &str) -> Option<Scene> {
        let text = builtin_text(name)?;
        Scene::from_toml(text, &format!("{name}.toml")).ok()
    }

    /// Names [`Scene::builtin`] accepts.
    pub fn builtin_names() -> &'static [&'static str] {
        BUILTIN_NAMES
    }

    /// The thesis' selected scene (800x600, two spheres, a floor and a back
    /// wall, stack depth 4, all speed-ups on).
    pub fn reference() -> Scene {
        Scene::builtin("reference")
            .expect("the embedded reference scene is valid (a test loads it)")
    }

    /// Validates a scene built in code and computes its [`Derived`]
    /// constants. `origin` names the scene in errors.
    pub fn new(
        origin: &str,
        camera: Camera,
        light: Light,
        spheres: Vec<Sphere>,
        planes: Vec<Plane>,
        render: RenderSettings,
    ) -> Result<Scene, SceneError> {
        let check = Check { origin };
        check.camera(&camera)?;
        check.light(&light)?;
        check.objects(&spheres, &planes)?;
        check.render(&render)?;
        if render.speedups.fast_plane {
            check.fast_plane(&camera, &light, &spheres, &planes)?;
        }
        if render.speedups.shadow_shortcut {
            check.shadow_shortcut(&light, &spheres, &planes)?;
        }
        let derived = Derived::compute(&camera, &spheres, &planes);
        Ok(Scene {
            camera,
            light,
            spheres,
            planes,
            render,
            derived,
        })
    }

    /// The same scene at another image size. The image-plane distance scales
    /// with the width (`distance * width / old width`, rounded to f32), so the
    /// horizontal field of view stays the same. `origin` names the request in
    /// errors (e.g. "--size").
    pub fn resized(&self, width: u32, height: u32, origin: &str) -> Result<Scene, SceneError> {
        let mut camera = self.camera.clone();
        camera.distance =
            (f64::from(camera.distance) * f64::from(width) / f64::from(camera.width)) as f32;
        camera.width = width;
        camera.height = height;
        Scene::new(
            origin,
            camera,
            self.light.clone(),
            self.spheres.clone(),
            self.planes.clone(),
            self.render,
        )
    }

    /// Total number of pixels.
    pub fn pixel_count(&self) -> u64 {
        u64::from(self.camera.width) * u64::from(self.camera.height)
    }

    /// A stable 64-bit FNV-1a hash of every number of the scene (the bits of
    /// the f32s, the integers, the settings) in a fixed order. Equal scenes
    /// hash equal on every platform and in every version that keeps the
    /// encoding tag; trace files record it to detect a foreign scene.
    pub fn content_hash(&self) -> u64 {
        let mut h = Fnv1a::new();
        h.bytes(b"rtcosim-scene-v1");
        let c = &self.camera;
        h.vec(c.eye);
        h.vec(c.rotation_deg);
        h.f32(c.distance);
        h.u32(c.width);
        h.u32(c.height);
        h.vec(self.light.position);
        h.vec(self.light.color);
        h.u32(self.spheres.len() as u32);
        for s in &self.spheres {
            h.vec(s.center);
            h.f32(s.radius);
            h.material(&s.material);
        }
        h.u32(self.planes.len() as u32);
        for p in &self.planes {
            h.u32(p.axis.index() as u32);
            h.f32(p.facing);
            h.f32(p.offset);
            h.material(&p.material);
        }
        let r = &self.render;
        h.u32(r.max_depth);
        h.bytes(&[
            u8::from(r.speedups.bounding_box),
            u8::from(r.speedups.fast_plane),
            u8::from(r.speedups.shadow_shortcut),
        ]);
        h.u32(r.recip.code());
        h.u32(r.sqrt.code());
        h.finish()
    }
}

impl Derived {
    fn compute(camera: &Camera, spheres: &[Sphere], planes: &[Plane]) -> Derived {
        let angle = |i: usize| f64::from(camera.rotation_deg[i]).to_radians();
        let cos = [0, 1, 2].map(|i| angle(i).cos() as f32);
        let sin = [0, 1, 2].map(|i| angle(i).sin() as f32);
        let (bbox_min, bbox_max) = if spheres.is_empty() {
            ([0.0; 3], [0.0; 3])
        } else {
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            for s in spheres {
                for i in 0..3 {
                    let c = f64::from(s.center[i]);
                    let r = f64::from(s.radius);
                    lo[i] = lo[i].min(round_down(c - r));
                    hi[i] = hi[i].max(round_up(c + r));
                }
            }
            (lo, hi)
        };
        Derived {
            cos,
            sin,
            half_width: camera.width as f32 / 2.0,
            half_height: camera.height as f32 / 2.0,
            inv_radius: spheres
                .iter()
                .map(|s| (1.0f64 / f64::from(s.radius)) as f32)
                .collect(),
            radius_sq: spheres.iter().map(|s| s.radius * s.radius).collect(),
            plane_normal: planes.iter().map(Plane::normal).collect(),
            bbox_min,
            bbox_max,
        }
    }
}

impl Plane {
    /// `facing * unit(axis)`, with +0.0 in the other components.
    pub fn normal(&self) -> Vec3f {
        let mut n = [0.0; 3];
        n[self.axis.index()] = self.facing;
        n
    }

    fn describe(&self, index: usize) -> String {
        format!(
            "plane[{index}] ({} = {}, facing {})",
            self.axis.name(),
            self.offset,
            if self.facing > 0.0 { "+" } else { "-" }
        )
    }

    /// Signed distance of `p` from the plane, positive on the normal side.
    fn height_of(&self, p: DVec3) -> f64 {
        f64::from(self.facing) * (p[self.axis.index()] - f64::from(self.offset))
    }
}

/// The largest f32 <= x (x finite and within the f32 range).
fn round_down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x {
        next_toward_neg_inf(y)
    } else {
        y
    }
}

/// The smallest f32 >= x (x finite and within the f32 range).
fn round_up(x: f64) -> f32 {
    -round_down(-x)
}

fn next_toward_neg_inf(y: f32) -> f32 {
    if y == 0.0 {
        -f32::from_bits(1)
    } else if y > 0.0 {
        f32::from_bits(y.to_bits() - 1)
    } else {
        f32::from_bits(y.to_bits() + 1)
    }
}

fn dvec(v: Vec3f) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}

/// Angle between two non-zero vectors, accurate also near 0 and pi.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

// ---------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------

struct Check<'a> {
    origin: &'a str,
}

impl Check<'_> {
    fn fail(&self, field: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            origin: self.origin.to_string(),
            field: field.into(),
            message: message.into(),
        }
    }

    fn finite(&self, field: &str, x: f32) -> Result<(), SceneError> {
        if x.is_finite() {
            Ok(())
        } else {
            Err(self.fail(field, format!("not a finite number, got {x}")))
        }
    }

    fn finite_vec(&self, field: &str, v: Vec3f) -> Result<(), SceneError> {
        for (i, &x) in v.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), x)?;
        }
        Ok(())
    }

    fn unit(&self, field: &str, x: f32) -> Result<(), SceneError> {
        self.finite(field, x)?;
        if (0.0..=1.0).contains(&x) {
            Ok(())
        } else {
            Err(self.fail(field, format!("must be in [0, 1], got {x}")))
        }
    }

    fn unit_vec(&self, field: &str, v: Vec3f) -> Result<(), SceneError> {
        for (i, &x) in v.iter().enumerate() {
            self.unit(&format!("{field}[{i}]"), x)?;
        }
        Ok(())
    }

    fn camera(&self, c: &Camera) -> Result<(), SceneError> {
        for (field, v) in [("camera.width", c.width), ("camera.height", c.height)] {
            if !(1..=MAX_IMAGE_SIDE).contains(&v) {
                return Err(self.fail(field, format!("must be 1..={MAX_IMAGE_SIDE}, got {v}")));
            }
        }
        self.finite_vec("camera.eye", c.eye)?;
        self.finite_vec("camera.rotation", c.rotation_deg)?;
        self.finite("camera.distance", c.distance)?;
        if c.distance <= 0.0 {
            return Err(self.fail(
                "camera.distance",
                format!("must be > 0, got {}", c.distance),
            ));
        }
        Ok(())
    }

    fn light(&self, l: &Light) -> Result<(), SceneError> {
        self.finite_vec("light.position", l.position)?;
        self.unit_vec("light.color", l.color)
    }

    fn material(&self, at: &str, m: &Material) -> Result<(), SceneError> {
        self.unit_vec(&format!("{at}.color"), m.color)?;
        self.unit(&format!("{at}.diffuse"), m.diffuse)?;
        self.unit(&format!("{at}.specular"), m.specular)?;
        self.unit(&format!("{at}.reflection"), m.reflection)
    }

    /// The RTL's scene memory has room for [`MAX_SPHERES`] and [`MAX_PLANES`].
    fn counts(&self, spheres: usize, planes: usize) -> Result<(), SceneError> {
        if spheres > MAX_SPHERES {
            return Err(self.fail(
                "sphere",
                format!("{spheres} spheres, but the RTL holds at most {MAX_SPHERES}"),
            ));
        }
        if planes > MAX_PLANES {
            return Err(self.fail(
                "plane",
                format!("{planes} planes, but the RTL holds at most {MAX_PLANES}"),
            ));
        }
        Ok(())
    }

    fn objects(&self, spheres: &[Sphere], planes: &[Plane]) -> Result<(), SceneError> {
        self.counts(spheres.len(), planes.len())?;
        if spheres.is_empty() && planes.is_empty() {
            return Err(self.fail(
                "sphere, plane",
                "the scene has no objects (add a [[sphere]] or a [[plane]])",
            ));
        }
        for (i, s) in spheres.iter().enumerate() {
            let at = format!("sphere[{i}]");
            self.finite_vec(&format!("{at}.center"), s.center)?;
            let field = format!("{at}.radius");
            self.finite(&field, s.radius)?;
            if s.radius <= 0.0 {
                return Err(self.fail(field, format!("must be > 0, got {}", s.radius)));
            }
            // The RTL holds r² and 1/r in f32: both must exist there.
            if !(s.radius * s.radius).is_finite() || !(1.0 / s.radius).is_finite() {
                return Err(self.fail(
                    field,
                    format!("r² and 1/r must be finite in f32, got r = {}", s.radius),
                ));
            }
            self.material(&at, &s.material)?;
        }
        for (i, p) in planes.iter().enumerate() {
            let at = format!("plane[{i}]");
            if p.facing != 1.0 && p.facing != -1.0 {
                return Err(self.fail(
                    format!("{at}.facing"),
                    format!("must be +1 or -1, got {}", p.facing),
                ));
            }
            self.finite(&format!("{at}.offset"), p.offset)?;
            self.material(&at, &p.material)?;
        }
        Ok(())
    }

    fn render(&self, r: &RenderSettings) -> Result<(), SceneError> {
        if !(1..=MAX_DEPTH).contains(&r.max_depth) {
            return Err(self.fail(
                "render.max_depth",
                format!("must be 1..={MAX_DEPTH}, got {}", r.max_depth),
            ));
        }
        Ok(())
    }

    /// Thesis 3.10.2: the RTL decides "hit" from the sign of one direction
    /// component alone, skipping the `t > 0` test. That is exact only if
    /// every ray origin lies strictly on the normal side of every plane. The
    /// origins are the eye and hit points; if the eye and every sphere lie
    /// inside the intersection of the planes' half-spaces (a convex region),
    /// the nearest hit of a ray from inside stays inside, and so does every
    /// origin after it. The light is required inside too, for 3.10.3 and
    /// because a scene whose light is behind a wall is a mistake.
    fn fast_plane(
        &self,
        camera: &Camera,
        light: &Light,
        spheres: &[Sphere],
        planes: &[Plane],
    ) -> Result<(), SceneError> {
        let field = "render.fast_plane";
        for (j, p) in planes.iter().enumerate() {
            let outside = |what: String| {
                self.fail(
                    field,
                    format!(
                        "{what} is not strictly on the normal side of {}: \
                         the fast plane test needs the planes to enclose the eye, \
                         the light and every sphere",
                        p.describe(j)
                    ),
                )
            };
            if p.height_of(dvec(camera.eye)) <= 0.0 {
                return Err(outside(format!("the eye {:?}", camera.eye)));
            }
            if p.height_of(dvec(light.position)) <= 0.0 {
                return Err(outside(format!("the light {:?}", light.position)));
            }
            for (i, s) in spheres.iter().enumerate() {
                if p.height_of(dvec(s.center)) <= f64::from(s.radius) {
                    return Err(outside(format!(
                        "sphere[{i}] (center {:?}, radius {})",
                        s.center, s.radius
                    )));
                }
            }
        }
        Ok(())
    }

    /// Thesis 3.10.3: shadow rays never test planes, and any sphere hit at
    /// `t > 0` along the shadow ray blocks the light, without comparing `t`
    /// with the distance to the light. This gives the reference's answer iff
    /// no plane ever lies between a surface point and the light, and no
    /// sphere is ever hit *beyond* the light. The test, in f64:
    ///
    /// - Planes are one-sided: a shadow ray is stopped by a plane only when
    ///   it crosses it from the normal side to the back. If the light is
    ///   strictly on the normal side, a ray towards it never does so before
    ///   reaching it. So: the light strictly on the normal side of every
    ///   plane.
    ///
    /// - A sphere S (centre c, radius r) beyond the light. Require the light
    ///   outside S, `|L - c| > r`. The shadow ray from p passes L in the
    ///   direction `u = (L - p)/|L - p|` and then hits S iff u lies in the
    ///   cone of directions from L towards S: `angle(u, c - L) <= θ` with
    ///   `θ = asin(r / |L - c|)`. Equivalently, p lies in the "anti-cone"
    ///   with apex L, axis `a = (L - c)/|L - c|` and half-angle θ. The
    ///   shortcut is exact if no surface point can lie in any anti-cone:
    ///   - a plane with normal n: every direction of the cone stays on the
    ///     normal side (parallel at worst) iff `angle(n, a) + θ <= 90°`, i.e.
    ///     `cos angle(n, a) >= sin θ`, i.e. `(L - c)·n >= r`;
    ///   - another sphere S' (c', r', with `|c' - L| > r'`) is seen from L
    ///     within `asin(r'/|c' - L|)` of the direction `c' - L`, so it stays
    ///     outside the anti-cone iff
    ///     `angle(c' - L, a) > θ + asin(r'/|c' - L|)`. (This is symmetric
    ///     in S and S': θ is also the angle S subtends at L. Two spheres on
    ///     opposite sides of the light can each shadow the other wrongly.)
    ///
    ///   S itself needs no test: seen from L it lies in the cone around
    ///   `c - L`, which is disjoint from the anti-cone (θ < 90°), and a ray
    ///   never tests the object it leaves from.
    ///
    /// The test is conservative: it refuses a scene when a surface merely
    /// *could* hold a wrongly shadowed point, whether or not a ray reaches it.
    fn shadow_shortcut(
        &self,
        light: &Light,
        spheres: &[Sphere],
        planes: &[Plane],
    ) -> Result<(), SceneError> {
        let field = "render.shadow_shortcut";
        let l = dvec(light.position);
        for (j, p) in planes.iter().enumerate() {
            if p.height_of(l) <= 0.0 {
                return Err(self.fail(
                    field,
                    format!(
                        "the light {:?} is not strictly on the normal side of {}: \
                         shadow rays would have to test that plane",
                        light.position,
                        p.describe(j)
                    ),
                ));
            }
        }
        for (i, s) in spheres.iter().enumerate() {
            let c = dvec(s.center);
            if (l - c).length() <= f64::from(s.radius) {
                return Err(self.fail(
                    field,
                    format!(
                        "the light {:?} is inside (or on) sphere[{i}] (center {:?}, radius {})",
                        light.position, s.center, s.radius
                    ),
                ));
            }
        }
        for (i, s) in spheres.iter().enumerate() {
            let c = dvec(s.center);
            let r = f64::from(s.radius);
            let to_light = l - c;
            let dist = to_light.length();
            let axis = to_light / dist;
            let theta = (r / dist).asin();
            let beyond = |victim: String| {
                self.fail(
                    field,
                    format!(
                        "sphere[{i}] lies beyond the light as seen from {victim}: \
                         the shortcut would shadow points there that the light reaches"
                    ),
                )
            };
            for (j, p) in planes.iter().enumerate() {
                let a = p.axis.index();
                if f64::from(p.facing) * (l[a] - c[a]) < r {
                    return Err(beyond(p.describe(j)));
                }
            }
            for (k, other) in spheres.iter().enumerate() {
                if k == i {
                    continue;
                }
                let to_other = dvec(other.center) - l;
                let d = to_other.length();
                let spread = (f64::from(other.radius) / d).asin();
                if angle_between(to_other, axis) <= theta + spread {
                    return Err(beyond(format!("sphere[{k}]")));
                }
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// The file format
// ---------------------------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    camera: RawCamera,
    light: RawLight,
    #[serde(default)]
    sphere: Vec<RawSphere>,
    #[serde(default)]
    plane: Vec<RawPlane>,
    #[serde(default)]
    render: RawRender,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    eye: [f64; 3],
    #[serde(default)]
    rotation: [f64; 3],
    distance: f64,
    // Wide integers, so that 0, -1 or 100000 reach the range check and get
    // its message rather than a type error.
    width: i64,
    height: i64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLight {
    position: [f64; 3],
    color: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSphere {
    center: [f64; 3],
    radius: f64,
    color: [f64; 3],
    diffuse: f64,
    specular: f64,
    reflection: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlane {
    axis: RawAxis,
    facing: RawFacing,
    offset: f64,
    color: [f64; 3],
    diffuse: f64,
    specular: f64,
    reflection: f64,
}

/// `axis = "x" | "y" | "z"`.
#[derive(Deserialize, Clone, Copy)]
#[serde(try_from = "String")]
struct RawAxis(Axis);

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

/// `facing = "+" | "-"`: +1.0 or -1.0.
#[derive(Deserialize, Clone, Copy)]
#[serde(try_from = "String")]
struct RawFacing(f32);

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

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum RawMethod {
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields, default)]
struct RawRender {
    max_depth: i64,
    bounding_box: bool,
    fast_plane: bool,
    shadow_shortcut: bool,
    recip: RawMethod,
    sqrt: RawMethod,
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
        }
    }
}

/// Rounds the file's f64 numbers to f32, naming the field of any number that
/// is not finite or does not fit.
struct Narrow<'a> {
    check: Check<'a>,
}

impl Narrow<'_> {
    fn num(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        if !x.is_finite() {
            return Err(self
                .check
                .fail(field, format!("not a finite number, got {x}")));
        }
        let y = x as f32;
        if !y.is_finite() {
            return Err(self
                .check
                .fail(field, format!("{x:e} is outside the range of f32")));
        }
        Ok(y)
    }

    fn vec(&self, field: &str, v: [f64; 3]) -> Result<Vec3f, SceneError> {
        Ok([
            self.num(&format!("{field}[0]"), v[0])?,
            self.num(&format!("{field}[1]"), v[1])?,
            self.num(&format!("{field}[2]"), v[2])?,
        ])
    }

    fn side(&self, field: &str, x: i64) -> Result<u32, SceneError> {
        match u32::try_from(x) {
            Ok(v) if (1..=MAX_IMAGE_SIDE).contains(&v) => Ok(v),
            _ => Err(self
                .check
                .fail(field, format!("must be 1..={MAX_IMAGE_SIDE}, got {x}"))),
        }
    }

    fn material(
        &self,
        at: &str,
        color: [f64; 3],
        diffuse: f64,
        specular: f64,
        reflection: f64,
    ) -> Result<Material, SceneError> {
        Ok(Material {
            color: self.vec(&format!("{at}.color"), color)?,
            diffuse: self.num(&format!("{at}.diffuse"), diffuse)?,
            specular: self.num(&format!("{at}.specular"), specular)?,
            reflection: self.num(&format!("{at}.reflection"), reflection)?,
        })
    }
}

impl RawScene {
    fn into_scene(self, origin: &str) -> Result<Scene, SceneError> {
        let n = Narrow {
            check: Check { origin },
        };
        // The limits are checked before anything is converted, so that a
        // file with a thousand spheres gets the message about the count.
        n.check.counts(self.sphere.len(), self.plane.len())?;
        let camera = Camera {
            eye: n.vec("camera.eye", self.camera.eye)?,
            rotation_deg: n.vec("camera.rotation", self.camera.rotation)?,
            distance: n.num("camera.distance", self.camera.distance)?,
            width: n.side("camera.width", self.camera.width)?,
            height: n.side("camera.height", self.camera.height)?,
        };
        let light = Light {
            position: n.vec("light.position", self.light.position)?,
            color: n.vec("light.color", self.light.color)?,
        };
        let spheres = self
            .sphere
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let at = format!("sphere[{i}]");
                Ok(Sphere {
                    center: n.vec(&format!("{at}.center"), s.center)?,
                    radius: n.num(&format!("{at}.radius"), s.radius)?,
                    material: n.material(&at, s.color, s.diffuse, s.specular, s.reflection)?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;
        let planes = self
            .plane
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let at = format!("plane[{i}]");
                Ok(Plane {
                    axis: p.axis.0,
                    facing: p.facing.0,
                    offset: n.num(&format!("{at}.offset"), p.offset)?,
                    material: n.material(&at, p.color, p.diffuse, p.specular, p.reflection)?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;
        let r = &self.render;
        let max_depth = u32::try_from(r.max_depth)
            .ok()
            .filter(|d| (1..=MAX_DEPTH).contains(d))
            .ok_or_else(|| {
                n.check.fail(
                    "render.max_depth",
                    format!("must be 1..={MAX_DEPTH}, got {}", r.max_depth),
                )
            })?;
        let render = RenderSettings {
            max_depth,
            speedups: Speedups {
                bounding_box: r.bounding_box,
                fast_plane: r.fast_plane,
                shadow_shortcut: r.shadow_shortcut,
            },
            recip: r.recip.into(),
            sqrt: r.sqrt.into(),
        };
        Scene::new(origin, camera, light, spheres, planes, render)
    }
}

/// Longest message quoted from the TOML parser: a hostile file can make it
/// quote megabytes of itself.
const MAX_MESSAGE_CHARS: usize = 240;

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

/// Longest field path quoted (a hostile key can be megabytes long).
const MAX_FIELD_CHARS: usize = 80;

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

// ---------------------------------------------------------------------------
// Hashing
// ---------------------------------------------------------------------------

struct Fnv1a(u64);

impl Fnv1a {
    fn new() -> Fnv1a {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn u32(&mut self, x: u32) {
        self.bytes(&x.to_le_bytes());
    }

    fn f32(&mut self, x: f32) {
        self.u32(x.to_bits());
    }

    fn vec(&mut self, v: Vec3f) {
        v.iter().for_each(|&x| self.f32(x));
    }

    fn material(&mut self, m: &Material) {
        self.vec(m.color);
        self.f32(m.diffuse);
        self.f32(m.specular);
        self.f32(m.reflection);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_outwards_brackets_the_exact_value() {
        let x = 0.1f64;
        assert!(f64::from(round_down(x)) <= x && f64::from(round_up(x)) >= x);
        assert_eq!(round_up(x).to_bits(), round_down(x).to_bits() + 1);
        // Exact values stay put, on both sides of zero.
        assert_eq!((round_down(-2.0), round_up(-2.0)), (-2.0, -2.0));
        assert_eq!((round_down(0.0), round_up(0.0)), (0.0, 0.0));
        // Below the smallest subnormal, towards zero from either side.
        assert_eq!(round_down(1e-50), 0.0);
        assert_eq!(round_up(1e-50), f32::from_bits(1));
        assert_eq!(round_down(-1e-50), -f32::from_bits(1));
    }

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

    #[test]
    fn the_angle_between_vectors_is_accurate_near_zero() {
        let a = DVec3::new(1.0, 0.0, 0.0);
        let b = DVec3::new(1.0, 1e-12, 0.0);
        assert!((angle_between(a, b) - 1e-12).abs() < 1e-24);
        assert!((angle_between(a, -a) - std::f64::consts::PI).abs() < 1e-15);
    }
}
