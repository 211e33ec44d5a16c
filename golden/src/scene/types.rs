//! The parts of a scene, as every model sees them: f32 numbers (the values
//! the hardware holds), already validated when they sit in a
//! [`Scene`](super::Scene).

use crate::fp::Method;
use glam::DVec3;
use std::fmt;

/// Spheres the RTL's scene memory holds.
pub const MAX_SPHERES: usize = 8;
/// Planes the RTL's scene memory holds.
pub const MAX_PLANES: usize = 6;
/// Deepest ray stack the RTL can be built with: generations of open-air rays
/// (1 = primary rays only, no reflections).
pub const MAX_DEPTH: u32 = 8;
/// Largest magnitude of `render.exposure`: at -100 every channel above 0.17
/// is already 1 - e^-17, which is 1.0 in f32, so larger magnitudes only
/// make the picture two-tone.
pub const MAX_EXPOSURE: f32 = 100.0;
/// Largest image width or height, in pixels (pixel coordinates are 12 bits).
pub const MAX_IMAGE_SIDE: u32 = 4096;

/// Largest magnitude of a coordinate: every component of the eye, the
/// light and the sphere centres, and every plane offset, is in
/// `[-MAX_COORD, MAX_COORD]`, 2^60 (about 1.15e18). With sphere radii up
/// to [`MAX_RADIUS`], every point the program subtracts lies within 2^61 of
/// the origin, every difference within 2^62, and the largest dot product,
/// `v·v` of such a difference, below 3 * 2^124 < 2^128: it cannot overflow
/// f32. docs/scenes.md has the derivation.
pub const MAX_COORD: f32 = (1u64 << 60) as f32;
/// Largest sphere radius, 2^60: `r²` <= 2^120.
pub const MAX_RADIUS: f32 = (1u64 << 60) as f32;
/// Smallest sphere radius, 2^-60 (about 8.7e-19): `r²` >= 2^-120 is a
/// normal f32, so the sphere test's `r² - w·w` keeps its precision, and
/// `1/r` <= 2^60.
pub const MIN_RADIUS: f32 = 1.0 / (1u64 << 60) as f32;
/// Smallest sphere radius against the scene's extent (the largest
/// coordinate magnitude of the eye, the sphere centres and the plane
/// offsets, [`Scene::extent`](super::Scene::extent)), 2^-16. f32 places a
/// point to 2^-24 of its magnitude, so a hit point `o + t·d` on a sphere
/// carries an error of a few units of 2^-24 of the scene's extent, and
/// the normal `(p - c)/r` that error over `r`: at `r` >= 2^-16 of the
/// extent the normal's length stays within a few 2^-8 of 1, and the
/// specular term (its 20th power, squared through the mirror ray) within
/// a few times its exact value. Far smaller spheres are rounding noise when
/// they are hit at all, and their normals can overflow the shading to
/// infinity. docs/scenes.md has the measurement.
pub const MIN_RADIUS_OF_EXTENT: f32 = 1.0 / 65536.0;
/// Largest image-plane distance, 2^60: a primary direction's `v·v` <=
/// 2^120 + 2 * 2^22.
pub const MAX_DISTANCE: f32 = (1u64 << 60) as f32;
/// Smallest image-plane distance, 2^-60: the primary direction of the
/// centre pixel is `distance` times a unit vector, so `v·v` >= 2^-120 stays
/// a normal f32 and its normalization cannot underflow.
pub const MIN_DISTANCE: f32 = 1.0 / (1u64 << 60) as f32;

/// Three f32 lanes x, y, z: a point, direction or RGB colour as the hardware
/// holds it, and a register of the pixel processor. (The f64 reference
/// renderer widens these, exactly, to [`glam::DVec3`].)
pub type Vec3f = [f32; 3];

/// `v` widened to f64, exactly.
pub(crate) fn dvec(v: Vec3f) -> DVec3 {
    DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))
}

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

/// Smallest index of refraction, 1/4: the index is the inside's relative
/// to the outside's, so below 1 the sphere is the thinner medium (a bubble);
/// no pair of common media is further apart.
pub const MIN_IOR: f32 = 0.25;
/// Largest index of refraction, 4 (diamond in air is 2.42).
pub const MAX_IOR: f32 = 4.0;

/// Surface properties (thesis 3.4): every value in [0, 1] but the index of
/// refraction.
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
    /// Weight of the refracted ray's colour (thesis 3.4.1, 3.6: the ray
    /// that passes through a sphere and leaves it as a new open-air ray);
    /// 0 for an opaque object. Spheres only: a plane bounds no inside.
    pub transmission: f32,
    /// Index of refraction of the inside relative to the outside, in
    /// [[`MIN_IOR`], [`MAX_IOR`]]; 1 bends nothing. Read only where
    /// `transmission > 0`.
    pub ior: f32,
}

impl Material {
    /// An opaque material (no transmission, index 1): every material
    /// before refraction.
    pub fn opaque(color: Vec3f, diffuse: f32, specular: f32, reflection: f32) -> Material {
        Material {
            color,
            diffuse,
            specular,
            reflection,
            transmission: 0.0,
            ior: 1.0,
        }
    }

    /// Whether light passes through it (a refracted child ray).
    pub fn transparent(&self) -> bool {
        self.transmission > 0.0
    }
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

impl Plane {
    /// `facing * unit(axis)`, with +0.0 in the other components.
    pub fn normal(&self) -> Vec3f {
        let mut n = [0.0; 3];
        n[self.axis.index()] = self.facing;
        n
    }
}

/// One of the scene's objects, by kind and index into the scene's `spheres`
/// or `planes`: what a ray hits, and what a secondary ray leaves from (and so
/// does not test). Every model names objects this way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Object {
    Sphere(usize),
    Plane(usize),
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

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Ray stack depth: generations of open-air rays, 1..=[`MAX_DEPTH`].
    pub max_depth: u32,
    pub speedups: Speedups,
    /// Method of the RTL's reciprocal unit.
    pub recip: Method,
    /// Method of the RTL's square-root unit.
    pub sqrt: Method,
    /// The weight cutoff (thesis 3.8, end): no reflected ray is spawned
    /// whose weight, the product of the reflection values along its path,
    /// is strictly below this. In [0, 1]; 0 (the default) switches it off.
    /// golden::reference compares in f64, golden::micro and the RTL in f32
    /// (the very product SH_CHILD_W writes): `weight < weight_cutoff`.
    pub weight_cutoff: f32,
    /// The exposure function of thesis 3.7, `colour = 1 - e^(exposure *
    /// colour)` per channel at the end of every pixel, which maps colours
    /// over 1 into [0, 1) instead of letting the 8-bit conversion clip
    /// them. `None` (the default) switches it off; else in
    /// `[-MAX_EXPOSURE, 0)`. Part of the picture (the render hash).
    pub exposure: Option<f32>,
}

impl RenderSettings {
    /// Whether the weight cutoff is on (a cutoff of 0 refuses no ray, and
    /// costs no cycle).
    pub fn cutoff_on(&self) -> bool {
        self.weight_cutoff > 0.0
    }
}
