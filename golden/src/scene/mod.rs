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
//! # transmission = 0.0  # weight of the refracted ray (0 = opaque; spheres only)
//! # ior = 1.0           # index of refraction inside relative to outside, in [0.25, 4]
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
//! weight_cutoff = 0.0  # spawn no reflected ray of weight < this (0 = off)
//! # exposure = -1.0    # colour = 1 - e^(exposure * colour), in [-100, 0) (absent = off)
//! ```
//!
//! Unknown keys are errors everywhere, and every error names the file and the
//! field (`scene.toml: sphere[1].radius: must be > 0, got -3`).
//!
//! By job:
//!
//! - [`Scene`] (here): the validated scene and every way to make one.
//! - `types`: its parts ([`Camera`], [`Light`], [`Sphere`], [`Plane`],
//!   [`Material`], [`RenderSettings`]), [`Object`], [`Vec3f`] and the RTL's
//!   limits.
//! - `file`: the file format, TOML text to the unchecked raw scene.
//! - `validate`: the one path from an unchecked scene, read from a file or
//!   built in code, to a [`Scene`]; every rule is checked there, once.
//! - `builtin`: the scenes embedded in the binary.
//! - `derived`: the constants computed once from a valid scene ([`Derived`]).
//! - `hash`: [`Scene::render_hash`] and [`Scene::config_hash`], the
//!   identities trace files record.
//! - `error`: [`SceneError`].

mod builtin;
mod derived;
mod error;
mod file;
mod hash;
mod types;
mod validate;

pub use derived::Derived;
pub(crate) use derived::{round_down, round_up};
pub use error::SceneError;
pub(crate) use types::dvec;
pub use types::{
    Axis, Camera, Light, Material, Object, Plane, RenderSettings, Speedups, Sphere, Vec3f,
    MAX_COORD, MAX_DEPTH, MAX_DISTANCE, MAX_EXPOSURE, MAX_IMAGE_SIDE, MAX_IOR, MAX_PLANES,
    MAX_RADIUS, MAX_SPHERES, MIN_DISTANCE, MIN_IOR, MIN_RADIUS, MIN_RADIUS_OF_EXTENT,
};
pub use validate::Extent;

use file::RawScene;
use std::path::Path;

/// A validated scene. Build it with [`Scene::from_toml`], [`Scene::load`],
/// [`Scene::builtin`] or [`Scene::new`]: each checks every rule of
/// `validate`, so a `Scene` is always renderable by every model.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub camera: Camera,
    pub light: Light,
    pub spheres: Vec<Sphere>,
    pub planes: Vec<Plane>,
    pub render: RenderSettings,
    pub derived: Derived,
}

impl Scene {
    /// Whether any of its objects is transparent: a refracted child ray
    /// (only a sphere can be; docs/scenes.md, "Refraction").
    pub fn refracts(&self) -> bool {
        self.spheres.iter().any(|s| s.material.transparent())
    }

    /// Parses and validates a scene file's text. `origin` names the file in
    /// errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scene, SceneError> {
        validate::scene(&RawScene::parse(text, origin)?, origin)
    }

    /// Reads, parses and validates a scene file; errors name `path`.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = file::read(path)?;
        Scene::from_toml(&text, &path.display().to_string())
    }

    /// A scene embedded in the binary: "reference", "mirror", or a stress
    /// scene by file stem (see [`Scene::builtin_names`]).
    pub fn builtin(name: &str) -> Option<Scene> {
        let text = builtin::text(name)?;
        Scene::from_toml(text, &format!("{name}.toml")).ok()
    }

    /// Names [`Scene::builtin`] accepts.
    pub fn builtin_names() -> &'static [&'static str] {
        &builtin::NAMES
    }

    /// The thesis' selected scene (800x600, two spheres, a floor and a back
    /// wall, stack depth 4, all speed-ups on).
    pub fn reference() -> Scene {
        Scene::builtin("reference")
            .expect("the embedded reference scene is valid (a test loads it)")
    }

    /// Validates a scene built in code, exactly as a file with these
    /// numbers would be, and computes its [`Derived`] constants. `origin`
    /// names the scene in errors.
    pub fn new(
        origin: &str,
        camera: Camera,
        light: Light,
        spheres: Vec<Sphere>,
        planes: Vec<Plane>,
        render: RenderSettings,
    ) -> Result<Scene, SceneError> {
        let raw = RawScene::from_parts(&camera, &light, &spheres, &planes, &render);
        validate::scene(&raw, origin)
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
        self.with_camera(camera, origin)
    }

    /// The same image size with the field of view that the camera's
    /// `distance` gives an image `layout_width` pixels wide: the distance
    /// scaled by width / `layout_width`, as [`Scene::resized`] from that
    /// width would keep it. For a scene file whose distance was written
    /// for another image width. `origin` names the request in errors.
    pub fn framed_as(&self, layout_width: u32, origin: &str) -> Result<Scene, SceneError> {
        let mut camera = self.camera.clone();
        camera.distance = (f64::from(camera.distance) * f64::from(camera.width)
            / f64::from(layout_width.max(1))) as f32;
        self.with_camera(camera, origin)
    }

    /// The same scene with its glass opaque: every sphere's transmission
    /// 0, so that nothing refracts (the index of refraction stays and means
    /// nothing). A picture that a processor built without refraction
    /// draws; the sweep's and tune's knob (`opaque_glass`). `origin` names
    /// the request in errors.
    pub fn with_opaque_glass(&self, origin: &str) -> Result<Scene, SceneError> {
        let mut spheres = self.spheres.clone();
        for s in &mut spheres {
            s.material.transmission = 0.0;
        }
        Scene::new(
            origin,
            self.camera.clone(),
            self.light.clone(),
            spheres,
            self.planes.clone(),
            self.render,
        )
    }

    /// This scene with another camera, validated again.
    fn with_camera(&self, camera: Camera, origin: &str) -> Result<Scene, SceneError> {
        Scene::new(
            origin,
            camera,
            self.light.clone(),
            self.spheres.clone(),
            self.planes.clone(),
            self.render,
        )
    }

    /// The same picture computed another way: other render settings (stack
    /// depth, speed-ups, methods, weight cutoff), validated again (a
    /// speed-up's precondition may not hold). `origin` names the request in
    /// errors.
    pub fn with_render(&self, render: RenderSettings, origin: &str) -> Result<Scene, SceneError> {
        Scene::new(
            origin,
            self.camera.clone(),
            self.light.clone(),
            self.spheres.clone(),
            self.planes.clone(),
            render,
        )
    }

    /// Total number of pixels.
    pub fn pixel_count(&self) -> u64 {
        u64::from(self.camera.width) * u64::from(self.camera.height)
    }

    /// A stable 64-bit FNV-1a hash of what is rendered: the camera and the
    /// image size, the light, the exposure if any, the objects and their
    /// materials (the bits of the f32s, the integers) in a fixed order, and not how it is computed
    /// (see [`Scene::config_hash`]). Equal pictures hash equal on every
    /// platform and in every version that keeps the encoding tag; trace
    /// files record it, and traces of different scenes are not compared.
    pub fn render_hash(&self) -> u64 {
        hash::render_hash(self)
    }

    /// A stable 64-bit FNV-1a hash of how the scene is computed: the stack
    /// depth, the speed-ups and the methods. Traces of one scene under two
    /// configurations are compared (their differences printed first).
    pub fn config_hash(&self) -> u64 {
        hash::config_hash(self)
    }

    /// The scene as a scene file's text: [`Scene::from_toml`] of it gives
    /// this scene back, bit for bit. Trace files carry it, so that a trace
    /// says exactly what it traced.
    pub fn to_toml(&self) -> String {
        RawScene::from_parts(
            &self.camera,
            &self.light,
            &self.spheres,
            &self.planes,
            &self.render,
        )
        .to_toml()
    }
}
