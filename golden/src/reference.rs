//! The f64 reference renderer: ground truth for accuracy.
//!
//! Written plainly and recursively, as a textbook would, with none of the
//! speed-ups of thesis 3.10 (the scene's speed-up switches are ignored: they
//! must not change the image, and this renderer is what proves it). The
//! scene's f32 numbers are widened to f64 exactly; everything after that is
//! f64.
//!
//! The optics, which the micro-op model follows too:
//!
//! - Primary ray of pixel (px, py), py = 0 at the top: camera-space
//!   direction `(px - width/2, height/2 - py, distance)` (no half-pixel
//!   offset), rotated by `Rz * Ry * Rx`, normalized; origin the eye.
//! - Sphere (c, r): `v = o - c`, `b = v·d`, `w = v - b·d` (the centre's
//!   offset from the ray's line), `disc = r² - w·w`; a hit iff `disc >= 0`
//!   and `t = -b - sqrt(disc) > 0` (the ray starts outside). This is the
//!   thesis' `b² - (v·v - r²)` rearranged so that it does not cancel: far
//!   from the origin (coordinates near the 2^60 limit) the thesis' form
//!   loses every digit even in f64 and "hits" where there is nothing.
//! - Plane (normal n = facing·unit(axis), offset q): `denom = n·d`; a hit iff
//!   `denom < 0` and `t = (facing·q - n·o) / denom > 0`. Planes are one-sided.
//! - The nearest hit wins; on a tie in t, spheres before planes, lower index
//!   first. A ray never tests the object it leaves from (all objects are
//!   convex, so this is exact; no epsilon anywhere).
//! - Shading at p, normal n (a sphere's `normalize(p - c)`; exact hits make
//!   it `(p - c)/r`, and where p is imprecise a unit normal keeps every term
//!   bounded), incoming d, material (C, kd, ks, kr), light
//!   (L, Lc): `l = normalize(L - p)` (zero if p is the light); the light is visible unless another
//!   object is hit along (p, l) with `t < |L - p|`. If visible,
//!   `local = kd·(n·l)·(C∘Lc) + ks·max(r·l, 0)^20·Lc` where `n·l > 0`
//!   (both terms gated: light reaches only the lit side), with
//!   `r = d - 2(d·n)n` (the Phong highlight: thesis eq. 11 writes `d·l`);
//!   otherwise 0. No ambient light; a miss is black. Planes are one-sided,
//!   as in the fast-plane hack of thesis 3.10.2 (its 3.3.2 intersects both
//!   sides).
//! - `shade(ray, depth) = local + kr·shade(reflected ray, depth + 1)` when
//!   `kr > 0` and `depth + 1 < max_depth` (the primary ray has depth 0),
//!   and the reflected ray's weight `w·kr` (w: the product of the
//!   reflection values above it, 1 for the primary ray; f64) is not below
//!   the scene's weight cutoff: a ray with `w·kr < weight_cutoff` is not
//!   spawned (thesis 3.8, end; 0 = off).
//! - Then `+ kt·shade(refracted ray, depth + 1)` when the material's
//!   transmission `kt > 0` (spheres only), under the same depth and cutoff
//!   rules with the weight `w·kt` (thesis 3.6: the refracted child comes
//!   after the reflected one's whole subtree). The refracted ray is
//!   Snell's law into the sphere (relative index `ior`: `eta = 1/ior`),
//!   the chord to the far side, Snell's law out (`eta = ior`), and from
//!   there a new open-air ray that skips the sphere. Where the entry
//!   refracts nothing (total internal reflection: `ior < 1` and
//!   `sin θ > ior`), the child is the mirror ray `r`. Constant weights
//!   (Whitted's model, no Fresnel term), no reflection inside the sphere; a
//!   transparent object blocks shadow rays like an opaque one (light
//!   through it does not arrive in a straight line; the caustics it focuses
//!   are outside this model). docs/scenes.md, "Refraction", is the
//!   definition.
//! - The exposure (thesis 3.7), when the scene sets one: each channel c of
//!   the pixel becomes `1 - e^(exposure·c)` (f64 `exp`), which maps
//!   [0, inf) into [0, 1) instead of letting colours over 1 clip.

use crate::frame::Frame;
use crate::scene::{dvec, RenderSettings, Scene, SceneError, Vec3f, MAX_DEPTH};
use glam::{DMat3, DVec3};
use rayon::prelude::*;

/// Exponent of the specular term (thesis equation 11).
pub const SPECULAR_EXPONENT: i32 = 20;

pub use crate::scene::Object;

/// The colour of pixel (px, py): linear RGB, not clamped (with an exposure,
/// in [0, 1)).
pub fn render_pixel(scene: &Scene, px: u32, py: u32) -> [f64; 3] {
    let rotation = camera_rotation(scene.camera.rotation_deg);
    pixel_with(scene, &rotation, px, py)
}

/// [`render_pixel`] with the camera rotation computed once per frame.
fn pixel_with(scene: &Scene, rotation: &DMat3, px: u32, py: u32) -> [f64; 3] {
    let dir = rotated_direction(scene, rotation, px, py);
    expose(
        scene.render.exposure,
        shade(scene, dvec(scene.camera.eye), dir, None, 0, 1.0).to_array(),
    )
}

/// The exposure function of thesis 3.7 on one pixel: `1 - e^(exposure·c)`
/// per channel, or the colour unchanged without an exposure.
pub fn expose(exposure: Option<f32>, rgb: [f64; 3]) -> [f64; 3] {
    match exposure {
        Some(e) => rgb.map(|c| 1.0 - (f64::from(e) * c).exp()),
        None => rgb,
    }
}

/// What accuracy is measured against: the f64 render of `scene` at the
/// deepest stack ([`MAX_DEPTH`]) and with no weight cutoff (speed-ups and
/// methods do not change the reference). Used by `rtcosim sweep` and `tune`.
pub fn truth(scene: &Scene, progress: &(dyn Fn(u64) + Sync)) -> Result<Frame, SceneError> {
    let settings = RenderSettings {
        max_depth: MAX_DEPTH,
        weight_cutoff: 0.0,
        ..scene.render
    };
    let deepest = scene.with_render(settings, "the reference at the deepest stack")?;
    Ok(render(&deepest, progress))
}

/// Renders the whole frame, rows in parallel on the current rayon pool.
/// Every pixel is computed independently, so the frame is the same whatever
/// the number of threads. `progress` is called with the number of pixels
/// finished, once per row, from the worker threads.
pub fn render(scene: &Scene, progress: &(dyn Fn(u64) + Sync)) -> Frame {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let rotation = camera_rotation(scene.camera.rotation_deg);
    let mut pixels = vec![[0.0; 3]; w as usize * h as usize];
    pixels
        .par_chunks_mut(w as usize)
        .enumerate()
        .for_each(|(py, row)| {
            for (px, out) in row.iter_mut().enumerate() {
                *out = pixel_with(scene, &rotation, px as u32, py as u32);
            }
            progress(u64::from(w));
        });
    Frame {
        width: w,
        height: h,
        pixels,
    }
}

/// The unit direction of the primary ray through pixel (px, py).
pub fn primary_direction(scene: &Scene, px: u32, py: u32) -> DVec3 {
    rotated_direction(scene, &camera_rotation(scene.camera.rotation_deg), px, py)
}

/// [`primary_direction`] with the camera rotation given.
fn rotated_direction(scene: &Scene, rotation: &DMat3, px: u32, py: u32) -> DVec3 {
    let c = &scene.camera;
    let d_cam = DVec3::new(
        f64::from(px) - f64::from(c.width) / 2.0,
        f64::from(c.height) / 2.0 - f64::from(py),
        f64::from(c.distance),
    );
    (*rotation * d_cam).normalize()
}

/// `Rz * Ry * Rx` for rotations about x, then y, then z (degrees), each a
/// right-handed rotation as in thesis equation 13.
pub fn camera_rotation(deg: Vec3f) -> DMat3 {
    let [x, y, z] = deg.map(|a| f64::from(a).to_radians());
    DMat3::from_rotation_z(z) * DMat3::from_rotation_y(y) * DMat3::from_rotation_x(x)
}

/// Distance along the unit ray (o, d) to sphere `i`, if it is hit from
/// outside at t > 0.
fn hit_sphere(scene: &Scene, i: usize, o: DVec3, d: DVec3) -> Option<f64> {
    let s = &scene.spheres[i];
    let r = f64::from(s.radius);
    let v = o - dvec(s.center);
    let b = v.dot(d);
    let w = v - b * d;
    let disc = r * r - w.dot(w);
    if disc < 0.0 {
        return None;
    }
    let t = -b - disc.sqrt();
    (t > 0.0).then_some(t)
}

/// Distance along the ray (o, d) to plane `j`, if the ray comes from its
/// normal side and meets it at t > 0.
fn hit_plane(scene: &Scene, j: usize, o: DVec3, d: DVec3) -> Option<f64> {
    let p = &scene.planes[j];
    let n = dvec(p.normal());
    let denom = n.dot(d);
    if denom >= 0.0 {
        return None;
    }
    let t = (f64::from(p.facing) * f64::from(p.offset) - n.dot(o)) / denom;
    (t > 0.0).then_some(t)
}

/// Calls `hit` with every object the ray (o, d) hits, except `skip`, and
/// its distance, in the tie-break order: spheres by index, then planes by
/// index; stops early when `hit` returns true. Returns whether it stopped.
/// (Plain loops: an iterator chain here was left un-inlined by some builds,
/// costing a fifth of the frame time.)
fn for_each_hit(
    scene: &Scene,
    o: DVec3,
    d: DVec3,
    skip: Option<Object>,
    mut hit: impl FnMut(Object, f64) -> bool,
) -> bool {
    for i in 0..scene.spheres.len() {
        if skip != Some(Object::Sphere(i)) {
            if let Some(t) = hit_sphere(scene, i, o, d) {
                if hit(Object::Sphere(i), t) {
                    return true;
                }
            }
        }
    }
    for j in 0..scene.planes.len() {
        if skip != Some(Object::Plane(j)) {
            if let Some(t) = hit_plane(scene, j, o, d) {
                if hit(Object::Plane(j), t) {
                    return true;
                }
            }
        }
    }
    false
}

/// The nearest object along (o, d), ignoring `skip`; the first in tie-break
/// order among equally near ones.
pub fn nearest_hit(
    scene: &Scene,
    o: DVec3,
    d: DVec3,
    skip: Option<Object>,
) -> Option<(Object, f64)> {
    let mut best: Option<(Object, f64)> = None;
    for_each_hit(scene, o, d, skip, |obj, t| {
        if !matches!(best, Some((_, best_t)) if best_t <= t) {
            best = Some((obj, t));
        }
        false
    });
    best
}

/// Whether the light is visible from `p` on object `on`.
pub fn light_visible(scene: &Scene, p: DVec3, on: Object) -> bool {
    let to_light = dvec(scene.light.position) - p;
    let dist = to_light.length();
    let l = to_light.normalize_or_zero();
    !for_each_hit(scene, p, l, Some(on), |_, t| t < dist)
}

/// `weight`: the product of the reflection values of the ray's ancestors.
fn shade(
    scene: &Scene,
    o: DVec3,
    d: DVec3,
    from: Option<Object>,
    depth: u32,
    weight: f64,
) -> DVec3 {
    let Some((obj, t)) = nearest_hit(scene, o, d, from) else {
        return DVec3::ZERO;
    };
    let p = o + t * d;
    let (n, m) = surface(scene, obj, p);
    let r = d - 2.0 * d.dot(n) * n;
    let light_color = dvec(scene.light.color);
    let mut color = DVec3::ZERO;
    if light_visible(scene, p, obj) {
        let l = (dvec(scene.light.position) - p).normalize_or_zero();
        // Light reaches the surface only where n·l > 0: both terms are
        // gated on it (the highlight too: a ray never tests the object it
        // leaves for shadow, so the dark side of a sphere can see the light).
        let n_l = n.dot(l);
        let (diffuse, specular) = if n_l > 0.0 {
            (
                f64::from(m.diffuse) * n_l,
                f64::from(m.specular) * r.dot(l).max(0.0).powi(SPECULAR_EXPONENT),
            )
        } else {
            (0.0, 0.0)
        };
        color = diffuse * (dvec(m.color) * light_color) + specular * light_color;
    }
    let kr = f64::from(m.reflection);
    let child = weight * kr;
    if kr > 0.0
        && depth + 1 < scene.render.max_depth
        && child >= f64::from(scene.render.weight_cutoff)
    {
        color += kr * shade(scene, p, r, Some(obj), depth + 1, child);
    }
    // Then the refracted child (thesis 3.6: when control returns to the
    // ray): through the sphere and out of it, a new open-air ray one
    // generation down; under total internal reflection at the entry, the
    // mirror ray r.
    let kt = f64::from(m.transmission);
    let child = weight * kt;
    if kt > 0.0
        && depth + 1 < scene.render.max_depth
        && child >= f64::from(scene.render.weight_cutoff)
    {
        let (o2, d2) = match transmitted(scene, obj, p, d, n) {
            Transmitted::Out { exit, dir } => (exit, dir),
            Transmitted::Reflected => (p, r),
        };
        color += kt * shade(scene, o2, d2, Some(obj), depth + 1, child);
    }
    color
}

/// The refracted direction of the unit ray `d` at a surface of unit normal
/// `n` facing it (`n·d <= 0`), from index 1 into index `eta` times the
/// first's inverse (`eta` = n₁/n₂; Snell: n₁ sin θ₁ = n₂ sin θ₂):
/// `eta·d + (eta·cos θ₁ - cos θ₂)·n` with `cos θ₂ = sqrt(k)`, `k = 1 -
/// eta²(1 - cos² θ₁)`; `None` when `k < 0`, total internal reflection.
pub fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -n.dot(d);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| eta * d + (eta * cos_i - k.sqrt()) * n)
}

/// Where the refracted child of a ray hitting a transparent sphere goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transmitted {
    /// Into the sphere, across it, and out at `exit` along the unit `dir`.
    Out { exit: DVec3, dir: DVec3 },
    /// Total internal reflection at the entry (the sphere the thinner
    /// medium, `ior < 1`, beyond the critical angle): the mirror ray.
    Reflected,
}

/// The refracted child of the unit ray `d` hitting transparent sphere
/// `obj` at `p` (outward unit normal `n`): Snell's law into the sphere with
/// `eta = 1/ior`; the chord to the sphere's far side (the far root of the
/// sphere test from `p`, `t = -b + sqrt(r² - w·w)`); Snell's law out with
/// `eta = ior` against the inward normal. On the way out `k >= 0` in exact
/// arithmetic (a sphere's chord meets both ends at one angle, so the exit
/// sees the entry's angles swapped); where rounding makes it negative, at a
/// grazing exit, it is taken as 0: the ray leaves along the surface.
pub fn transmitted(scene: &Scene, obj: Object, p: DVec3, d: DVec3, n: DVec3) -> Transmitted {
    let Object::Sphere(i) = obj else {
        unreachable!("a plane is never transparent (golden::scene refuses it)")
    };
    let s = &scene.spheres[i];
    let ior = f64::from(s.material.ior);
    let Some(inside) = refract(d, n, 1.0 / ior) else {
        return Transmitted::Reflected;
    };
    let inside = inside.normalize_or_zero();
    let (c, r) = (dvec(s.center), f64::from(s.radius));
    let v = p - c;
    let b = v.dot(inside);
    let w = v - b * inside;
    let exit = p + (-b + (r * r - w.dot(w)).max(0.0).sqrt()) * inside;
    let n_out = (exit - c).normalize_or_zero();
    let dir = refract(inside, -n_out, ior).unwrap_or_else(|| {
        // k < 0 only by rounding: k = 0, cos θ₂ = 0.
        let cos_i = inside.dot(n_out);
        ior * inside - ior * cos_i * n_out
    });
    Transmitted::Out {
        exit,
        dir: dir.normalize_or_zero(),
    }
}

/// The unit normal and the material of `obj` at its surface point `p`.
fn surface(scene: &Scene, obj: Object, p: DVec3) -> (DVec3, &crate::scene::Material) {
    match obj {
        Object::Sphere(i) => {
            let s = &scene.spheres[i];
            ((p - dvec(s.center)).normalize_or_zero(), &s.material)
        }
        Object::Plane(j) => {
            let pl = &scene.planes[j];
            (dvec(pl.normal()), &pl.material)
        }
    }
}

/// Which child of its parent a ray of [`path_events`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ray {
    Primary,
    Reflected,
    /// Through a transparent sphere and out of it.
    Refracted,
    /// The refracted child under total internal reflection: the mirror ray.
    TotallyReflected,
}

/// The discrete events along the rays of pixel (px, py), in the order
/// [`render_pixel`] visits them (depth first, the reflected child before
/// the refracted one): which child each ray is, the object it hits and
/// whether light reaches that point (the light visible and `n·l > 0`, the
/// gate of both terms); a ray that misses, or a child the depth limit
/// stops, adds nothing. The colour is continuous in the primary direction
/// wherever this does not change, so neighbouring pixels with different
/// events mark an edge: a silhouette, a shadow edge or terminator, the
/// onset of total internal reflection, or a reflection or refraction of
/// one (`golden::stability::edge_mask`).
pub fn path_events(scene: &Scene, px: u32, py: u32) -> Vec<(Ray, Object, bool)> {
    let mut events = Vec::new();
    let d = primary_direction(scene, px, py);
    path_walk(
        scene,
        (dvec(scene.camera.eye), d, None),
        0,
        Ray::Primary,
        &mut events,
    );
    events
}

fn path_walk(
    scene: &Scene,
    (o, d, from): (DVec3, DVec3, Option<Object>),
    depth: u32,
    ray: Ray,
    events: &mut Vec<(Ray, Object, bool)>,
) {
    let Some((obj, t)) = nearest_hit(scene, o, d, from) else {
        return;
    };
    let p = o + t * d;
    let (n, m) = surface(scene, obj, p);
    let l = (dvec(scene.light.position) - p).normalize_or_zero();
    events.push((ray, obj, light_visible(scene, p, obj) && n.dot(l) > 0.0));
    if depth + 1 >= scene.render.max_depth {
        return;
    }
    let r = d - 2.0 * d.dot(n) * n;
    if m.reflection > 0.0 {
        path_walk(scene, (p, r, Some(obj)), depth + 1, Ray::Reflected, events);
    }
    if m.transparent() {
        let (next, ray) = match transmitted(scene, obj, p, d, n) {
            Transmitted::Out { exit, dir } => ((exit, dir, Some(obj)), Ray::Refracted),
            Transmitted::Reflected => ((p, r, Some(obj)), Ray::TotallyReflected),
        };
        path_walk(scene, next, depth + 1, ray, events);
    }
}
