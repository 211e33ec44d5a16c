//! The one path from an unchecked [`RawScene`] (read from a file, or a scene
//! built in code and widened) to a [`Scene`], checking every rule once:
//!
//! 1. What the hardware can hold at all, in the order of the file: the
//!    object counts first (so that a file with a thousand spheres gets the
//!    message about the count), then every number finite and within the f32
//!    range, rounded to f32 here, exactly once; the image sides and the
//!    stack depth within the RTL's limits.
//! 2. The rules on the f32 values: ranges (the magnitude limits that keep
//!    every product of the program finite: [`MAX_COORD`], the radius and
//!    distance limits), at least one object, and what the RTL precomputes
//!    (r², 1/r) finite.
//! 3. The precondition of each speed-up that is switched on.
//!
//! The first broken rule is the error; it names the field.

use super::derived::Derived;
use super::error::SceneError;
use super::file::{RawCamera, RawLight, RawPlane, RawRender, RawScene, RawSphere};
use super::types::{
    dvec, Camera, Light, Material, Plane, RenderSettings, Speedups, Sphere, Vec3f, MAX_COORD,
    MAX_DEPTH, MAX_DISTANCE, MAX_EXPOSURE, MAX_IMAGE_SIDE, MAX_IOR, MAX_PLANES, MAX_RADIUS,
    MAX_SPHERES, MIN_DISTANCE, MIN_IOR, MIN_RADIUS, MIN_RADIUS_OF_EXTENT,
};
use super::Scene;
use glam::DVec3;

/// Checks `raw` and builds the scene and its [`Derived`] constants;
/// `origin` names the file (or the request) in errors.
pub(super) fn scene(raw: &RawScene, origin: &str) -> Result<Scene, SceneError> {
    let check = Check { origin };
    check.counts(raw.sphere.len(), raw.plane.len())?;
    let camera = check.narrow_camera(&raw.camera)?;
    let light = check.narrow_light(&raw.light)?;
    let spheres = raw
        .sphere
        .iter()
        .enumerate()
        .map(|(i, s)| check.narrow_sphere(i, s))
        .collect::<Result<Vec<_>, _>>()?;
    let planes = raw
        .plane
        .iter()
        .enumerate()
        .map(|(j, p)| check.narrow_plane(j, p))
        .collect::<Result<Vec<_>, _>>()?;
    let render = check.narrow_render(&raw.render)?;

    check.camera(&camera)?;
    check.light(&light)?;
    check.objects(&spheres, &planes)?;
    check.resolved(&camera, &spheres, &planes)?;
    check.refraction(&camera, &light, &spheres, &planes)?;

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

/// The scene's extent: the largest coordinate magnitude of the eye, the
/// sphere centres and the plane offsets, and the field that holds it. (The
/// light is left out: no ray starts there. Radii are left out: a point on a
/// sphere far from the others is not an origin of a ray that reaches them,
/// unless its centre is far too.)
#[derive(Debug, Clone, PartialEq)]
pub struct Extent {
    pub value: f32,
    /// The first field holding `value` (`camera.eye[2]`).
    pub field: String,
}

impl Extent {
    pub fn of(eye: Vec3f, centres: &[Vec3f], offsets: &[f32]) -> Extent {
        let points = std::iter::once(("camera.eye".to_string(), eye))
            .chain((centres.iter().enumerate()).map(|(i, &c)| (format!("sphere[{i}].center"), c)));
        let coords = points
            .flat_map(|(at, v)| (0..3).map(move |k| (format!("{at}[{k}]"), v[k])))
            .chain((offsets.iter().enumerate()).map(|(j, &o)| (format!("plane[{j}].offset"), o)));
        let mut extent = Extent {
            value: 0.0,
            field: "camera.eye[0]".to_string(),
        };
        for (field, x) in coords {
            if x.abs() > extent.value {
                extent = Extent {
                    value: x.abs(),
                    field,
                };
            }
        }
        extent
    }

    /// The smallest radius a sphere may have in a scene of this extent
    /// ([`MIN_RADIUS_OF_EXTENT`] of it; exact: a power of two times an
    /// f32, in f64).
    pub fn least_radius(&self) -> f64 {
        f64::from(self.value) * f64::from(MIN_RADIUS_OF_EXTENT)
    }
}

struct Check<'a> {
    origin: &'a str,
}

// ---------------------------------------------------------------------------
// 1. What the hardware can hold
// ---------------------------------------------------------------------------

impl Check<'_> {
    fn fail(&self, field: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            origin: self.origin.to_string(),
            field: field.into(),
            message: message.into(),
        }
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

    /// `x` rounded to f32: it must be finite, and so must the f32.
    fn num(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        if !x.is_finite() {
            return Err(self.fail(field, format!("not a finite number, got {x}")));
        }
        let y = x as f32;
        if !y.is_finite() {
            return Err(self.fail(field, format!("{x:e} is outside the range of f32")));
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

    /// An integer in `1..=max`.
    fn count_in(&self, field: &str, x: i64, max: u32) -> Result<u32, SceneError> {
        match u32::try_from(x) {
            Ok(v) if (1..=max).contains(&v) => Ok(v),
            _ => Err(self.fail(field, format!("must be 1..={max}, got {x}"))),
        }
    }

    fn narrow_material(
        &self,
        at: &str,
        color: [f64; 3],
        diffuse: f64,
        specular: f64,
        reflection: f64,
        [transmission, ior]: [f64; 2],
    ) -> Result<Material, SceneError> {
        Ok(Material {
            color: self.vec(&format!("{at}.color"), color)?,
            diffuse: self.num(&format!("{at}.diffuse"), diffuse)?,
            specular: self.num(&format!("{at}.specular"), specular)?,
            reflection: self.num(&format!("{at}.reflection"), reflection)?,
            transmission: self.num(&format!("{at}.transmission"), transmission)?,
            ior: self.num(&format!("{at}.ior"), ior)?,
        })
    }

    fn narrow_camera(&self, c: &RawCamera) -> Result<Camera, SceneError> {
        Ok(Camera {
            eye: self.vec("camera.eye", c.eye)?,
            rotation_deg: self.vec("camera.rotation", c.rotation)?,
            distance: self.num("camera.distance", c.distance)?,
            width: self.count_in("camera.width", c.width, MAX_IMAGE_SIDE)?,
            height: self.count_in("camera.height", c.height, MAX_IMAGE_SIDE)?,
        })
    }

    fn narrow_light(&self, l: &RawLight) -> Result<Light, SceneError> {
        Ok(Light {
            position: self.vec("light.position", l.position)?,
            color: self.vec("light.color", l.color)?,
        })
    }

    fn narrow_sphere(&self, i: usize, s: &RawSphere) -> Result<Sphere, SceneError> {
        let at = format!("sphere[{i}]");
        Ok(Sphere {
            center: self.vec(&format!("{at}.center"), s.center)?,
            radius: self.num(&format!("{at}.radius"), s.radius)?,
            material: self.narrow_material(
                &at,
                s.color,
                s.diffuse,
                s.specular,
                s.reflection,
                [s.transmission, s.ior],
            )?,
        })
    }

    fn narrow_plane(&self, j: usize, p: &RawPlane) -> Result<Plane, SceneError> {
        let at = format!("plane[{j}]");
        Ok(Plane {
            axis: p.axis.0,
            facing: p.facing.0,
            offset: self.num(&format!("{at}.offset"), p.offset)?,
            material: self.narrow_material(
                &at,
                p.color,
                p.diffuse,
                p.specular,
                p.reflection,
                [p.transmission, p.ior],
            )?,
        })
    }

    fn narrow_render(&self, r: &RawRender) -> Result<RenderSettings, SceneError> {
        Ok(RenderSettings {
            max_depth: self.count_in("render.max_depth", r.max_depth, MAX_DEPTH)?,
            speedups: Speedups {
                bounding_box: r.bounding_box,
                fast_plane: r.fast_plane,
                shadow_shortcut: r.shadow_shortcut,
            },
            recip: r.recip.into(),
            sqrt: r.sqrt.into(),
            weight_cutoff: self.weight_cutoff(r.weight_cutoff)?,
            exposure: r.exposure.map(|x| self.exposure(x)).transpose()?,
        })
    }

    /// Thesis 3.7 puts the exposure in [-inf, 0]: refused are 0 and -0
    /// (every pixel black: leave the key out for no exposure), positive
    /// values (1 - e^(positive) is negative), NaN, infinities (-inf * 0 is
    /// NaN on a black channel) and magnitudes above [`MAX_EXPOSURE`].
    fn exposure(&self, x: f64) -> Result<f32, SceneError> {
        let field = "render.exposure";
        let e = self.num(field, x)?;
        if !(-MAX_EXPOSURE..0.0).contains(&e) {
            return Err(self.fail(
                field,
                format!(
                    "must be in [-{MAX_EXPOSURE}, 0) (colour = 1 - e^(exposure * colour); leave it out for none), got {x}"
                ),
            ));
        }
        Ok(e)
    }

    /// A weight is a product of reflection values in [0, 1], so a cutoff
    /// outside [0, 1] means nothing (above 1 it would refuse every ray):
    /// refused, as are NaN and infinities. -0 is 0 (off).
    fn weight_cutoff(&self, x: f64) -> Result<f32, SceneError> {
        let field = "render.weight_cutoff";
        let c = self.num(field, x)?;
        if !(0.0..=1.0).contains(&c) {
            return Err(self.fail(
                field,
                format!("must be in [0, 1] (a weight is a product of reflection values; 0 = off), got {x}"),
            ));
        }
        Ok(c + 0.0)
    }
}

// ---------------------------------------------------------------------------
// 2. The rules on the f32 values (all finite by now)
// ---------------------------------------------------------------------------

impl Check<'_> {
    fn unit(&self, field: &str, x: f32) -> Result<(), SceneError> {
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

    /// `x` in `[lo, hi]`, named with the limits' names.
    fn within(
        &self,
        field: &str,
        x: f32,
        lo: f32,
        hi: f32,
        limits: &str,
    ) -> Result<(), SceneError> {
        if (lo..=hi).contains(&x) {
            Ok(())
        } else {
            Err(self.fail(
                field,
                format!("must be in [{lo:e}, {hi:e}] ({limits}: docs/scenes.md), got {x:e}"),
            ))
        }
    }

    /// A coordinate within [`MAX_COORD`].
    fn coord(&self, field: &str, x: f32) -> Result<(), SceneError> {
        self.within(field, x, -MAX_COORD, MAX_COORD, "±MAX_COORD = ±2^60")
    }

    fn point(&self, field: &str, v: Vec3f) -> Result<(), SceneError> {
        for (i, &x) in v.iter().enumerate() {
            self.coord(&format!("{field}[{i}]"), x)?;
        }
        Ok(())
    }

    fn camera(&self, c: &Camera) -> Result<(), SceneError> {
        self.point("camera.eye", c.eye)?;
        if c.distance <= 0.0 {
            return Err(self.fail(
                "camera.distance",
                format!("must be > 0, got {}", c.distance),
            ));
        }
        self.within(
            "camera.distance",
            c.distance,
            MIN_DISTANCE,
            MAX_DISTANCE,
            "MIN_DISTANCE = 2^-60 to MAX_DISTANCE = 2^60",
        )
    }

    fn light(&self, l: &Light) -> Result<(), SceneError> {
        self.point("light.position", l.position)?;
        self.unit_vec("light.color", l.color)
    }

    fn material(&self, at: &str, m: &Material) -> Result<(), SceneError> {
        self.unit_vec(&format!("{at}.color"), m.color)?;
        self.unit(&format!("{at}.diffuse"), m.diffuse)?;
        self.unit(&format!("{at}.specular"), m.specular)?;
        self.unit(&format!("{at}.reflection"), m.reflection)?;
        self.unit(&format!("{at}.transmission"), m.transmission)?;
        self.within(
            &format!("{at}.ior"),
            m.ior,
            MIN_IOR,
            MAX_IOR,
            "MIN_IOR = 1/4 to MAX_IOR = 4, the inside's index relative to the outside's",
        )
    }

    fn objects(&self, spheres: &[Sphere], planes: &[Plane]) -> Result<(), SceneError> {
        if spheres.is_empty() && planes.is_empty() {
            return Err(self.fail(
                "sphere, plane",
                "the scene has no objects (add a [[sphere]] or a [[plane]])",
            ));
        }
        for (i, s) in spheres.iter().enumerate() {
            let at = format!("sphere[{i}]");
            self.point(&format!("{at}.center"), s.center)?;
            let field = format!("{at}.radius");
            if s.radius <= 0.0 {
                return Err(self.fail(field, format!("must be > 0, got {}", s.radius)));
            }
            // The limits keep what the RTL precomputes, r² and 1/r, finite.
            self.within(
                &field,
                s.radius,
                MIN_RADIUS,
                MAX_RADIUS,
                "MIN_RADIUS = 2^-60 to MAX_RADIUS = 2^60",
            )?;
            self.material(&at, &s.material)?;
        }
        for (i, p) in planes.iter().enumerate() {
            let at = format!("plane[{i}]");
            self.coord(&format!("{at}.offset"), p.offset)?;
            if p.facing != 1.0 && p.facing != -1.0 {
                return Err(self.fail(
                    format!("{at}.facing"),
                    format!("must be +1 or -1, got {}", p.facing),
                ));
            }
            self.material(&at, &p.material)?;
            if p.material.transparent() {
                return Err(self.fail(
                    format!("{at}.transmission"),
                    format!(
                        "must be 0, got {}: a plane bounds no inside, so light it let through \
                         would never leave it (refraction is for spheres: docs/scenes.md)",
                        p.material.transmission
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Every sphere is at least [`MIN_RADIUS_OF_EXTENT`] of the scene's
    /// extent: smaller ones are below what f32 resolves there.
    fn resolved(
        &self,
        camera: &Camera,
        spheres: &[Sphere],
        planes: &[Plane],
    ) -> Result<(), SceneError> {
        let centres: Vec<Vec3f> = spheres.iter().map(|s| s.center).collect();
        let offsets: Vec<f32> = planes.iter().map(|p| p.offset).collect();
        let extent = Extent::of(camera.eye, &centres, &offsets);
        let least = extent.least_radius();
        for (i, s) in spheres.iter().enumerate() {
            if f64::from(s.radius) < least {
                return Err(self.fail(
                    format!("sphere[{i}].radius"),
                    format!(
                        "must be at least {least:e}, 2^-16 of the scene's extent {:e} (at {}), \
                         got {:e}: f32 places a point to 2^-24 of its magnitude, so a smaller \
                         sphere's hit points and normals are rounding noise \
                         (MIN_RADIUS_OF_EXTENT: docs/scenes.md)",
                        extent.value, extent.field, s.radius
                    ),
                ));
            }
        }
        Ok(())
    }

    /// A transparent sphere's inside holds nothing but its own medium: the
    /// refracted ray crosses it to its far side without testing any other
    /// object (docs/scenes.md, "Refraction"), which is exact only if no
    /// other object reaches inside. So a transparent sphere may touch
    /// another sphere or a plane but not cut into it, and the eye and the
    /// light lie outside it. (Compared in f64 on the f32 values: a touch is
    /// decided within f64's rounding of the squared distances, far below
    /// f32's resolution of the scene.)
    fn refraction(
        &self,
        camera: &Camera,
        light: &Light,
        spheres: &[Sphere],
        planes: &[Plane],
    ) -> Result<(), SceneError> {
        for (i, s) in spheres.iter().enumerate() {
            if !s.material.transparent() {
                continue;
            }
            let at = format!("sphere[{i}]");
            let (c, r) = (dvec(s.center), f64::from(s.radius));
            for (what, p) in [
                ("camera.eye", camera.eye),
                ("light.position", light.position),
            ] {
                if (dvec(p) - c).length_squared() <= r * r {
                    return Err(self.fail(
                        format!("{at}.transmission"),
                        format!("the sphere is transparent, so {what} must lie outside it"),
                    ));
                }
            }
            for (j, o) in spheres.iter().enumerate().filter(|&(j, _)| j != i) {
                let reach = r + f64::from(o.radius);
                if (dvec(o.center) - c).length_squared() < reach * reach {
                    return Err(self.fail(
                        format!("{at}.transmission"),
                        format!(
                            "the sphere is transparent, so it may touch sphere[{j}] but not cut into it"
                        ),
                    ));
                }
            }
            for (j, p) in planes.iter().enumerate() {
                if (c[p.axis.index()] - f64::from(p.offset)).abs() < r {
                    return Err(self.fail(
                        format!("{at}.transmission"),
                        format!(
                            "the sphere is transparent, so it may touch plane[{j}] but not cut through it"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// 3. The speed-ups' preconditions
// ---------------------------------------------------------------------------

impl Check<'_> {
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

impl Plane {
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

/// Angle between two non-zero vectors, accurate also near 0 and pi.
fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_angle_between_vectors_is_accurate_near_zero() {
        let a = DVec3::new(1.0, 0.0, 0.0);
        let b = DVec3::new(1.0, 1e-12, 0.0);
        assert!((angle_between(a, b) - 1e-12).abs() < 1e-24);
        assert!((angle_between(a, -a) - std::f64::consts::PI).abs() < 1e-15);
    }
}
