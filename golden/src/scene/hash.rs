//! The scene's hashes: stable identities for trace files. One of what is
//! rendered (the picture's content), one of how it is computed (the
//! configuration), so that two traces of one picture computed two ways are
//! recognised as such.

use super::types::{Material, Vec3f};
use super::Scene;
use std::hash::Hasher;

/// A stable 64-bit FNV-1a hash of what is rendered: the camera (with the
/// image size), the light, every object and its material (the bits of the
/// f32s, the integers) in a fixed order.
pub(super) fn render_hash(scene: &Scene) -> u64 {
    let mut h = Fnv1a::new();
    h.bytes(b"rtcosim-scene-v2");
    let c = &scene.camera;
    h.vec(c.eye);
    h.vec(c.rotation_deg);
    h.f32(c.distance);
    h.u32(c.width);
    h.u32(c.height);
    h.vec(scene.light.position);
    h.vec(scene.light.color);
    // The exposure changes the picture, not how it is computed. Only when
    // on: scenes without it keep their hashes.
    if let Some(e) = scene.render.exposure {
        h.bytes(b"exposure");
        h.f32(e);
    }
    h.u32(scene.spheres.len() as u32);
    for s in &scene.spheres {
        h.vec(s.center);
        h.f32(s.radius);
        h.material(&s.material);
    }
    h.u32(scene.planes.len() as u32);
    for p in &scene.planes {
        h.u32(p.axis.index() as u32);
        h.f32(p.facing);
        h.f32(p.offset);
        h.material(&p.material);
    }
    h.finish()
}

/// A stable 64-bit FNV-1a hash of how the scene is computed: the stack
/// depth, the speed-ups, the methods.
pub(super) fn config_hash(scene: &Scene) -> u64 {
    let mut h = Fnv1a::new();
    h.bytes(b"rtcosim-config-v1");
    let r = &scene.render;
    h.u32(r.max_depth);
    h.bytes(&[
        u8::from(r.speedups.bounding_box),
        u8::from(r.speedups.fast_plane),
        u8::from(r.speedups.shadow_shortcut),
    ]);
    h.u32(r.recip.code());
    h.u32(r.sqrt.code());
    // Only when on: scenes without a cutoff keep their hashes.
    if r.cutoff_on() {
        h.bytes(b"weight_cutoff");
        h.f32(r.weight_cutoff);
    }
    h.finish()
}

/// 64-bit FNV-1a (the `fnv` crate) over the fields in a fixed order, each
/// number as its little-endian bytes: stable across platforms and Rust
/// versions, unlike `std`'s `DefaultHasher`.
struct Fnv1a(fnv::FnvHasher);

impl Fnv1a {
    fn new() -> Fnv1a {
        Fnv1a(fnv::FnvHasher::default())
    }

    fn bytes(&mut self, bytes: &[u8]) {
        self.0.write(bytes);
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
        // Only when not opaque: scenes without refraction keep their hashes.
        if m.transmission != 0.0 || m.ior != 1.0 {
            self.bytes(b"refraction");
            self.f32(m.transmission);
            self.f32(m.ior);
        }
    }

    fn finish(&self) -> u64 {
        self.0.finish()
    }
}
