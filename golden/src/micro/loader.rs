//! What the scene loader puts into a pixel processor before the first
//! pixel: the scene registers of the register file (written through the
//! scene port, read-only afterwards) and the controller's configuration
//! (counts, switches and per-object bits the FSM branches on).
//!
//! The loader places numbers: every value comes from the validated
//! [`Scene`] and its [`Derived`](crate::scene::Derived) constants, moved or
//! sign-flipped (exact), except the bounding box, which is widened here
//! (see [`bounding_box`]). The RTL harness loads these very bits.

use super::core::RegisterImage;
use super::isa::{self, dim, Lanes, PlaneField, Reg, SphereField, REGISTER_COUNT};
use crate::fp::Method;
use crate::scene::{
    round_down, round_up, Material, Scene, Speedups, Vec3f, MAX_IMAGE_SIDE, MAX_PLANES, MAX_SPHERES,
};

// The configuration word's fields (rtl/pp/isa.vh) fit in its 96 bits and
// do not overlap; the coordinate ports hold every pixel of the largest image.
const _: () = assert!(dim::CFG_SPHERES_LSB + 4 <= dim::CFG_PLANES_LSB);
const _: () = assert!(dim::CFG_PLANES_LSB + 3 <= dim::CFG_DEPTH_LSB);
const _: () = assert!(dim::CFG_DEPTH_LSB + 4 <= dim::CFG_BBOX_LSB);
const _: () = assert!(dim::CFG_BBOX_LSB < dim::CFG_FAST_PLANE_LSB);
const _: () = assert!(dim::CFG_FAST_PLANE_LSB < dim::CFG_SHORTCUT_LSB);
const _: () = assert!(dim::CFG_SHORTCUT_LSB < dim::CFG_CUTOFF_LSB);
const _: () = assert!(dim::CFG_CUTOFF_LSB < dim::CFG_ROTATE_LSB);
const _: () = assert!(dim::CFG_ROTATE_LSB + 3 <= dim::CFG_EXPOSURE_LSB);
const _: () = assert!(dim::CFG_EXPOSURE_LSB < dim::CFG_TRN_LSB);
const _: () = assert!(dim::CFG_TRN_LSB + MAX_SPHERES <= dim::CFG_SPH_BITS_LSB);
const _: () = assert!(dim::CFG_SPH_BITS_LSB + 3 * MAX_SPHERES <= dim::CFG_PLN_BITS_LSB);
const _: () = assert!(dim::CFG_PLN_BITS_LSB + 3 * MAX_PLANES <= dim::CFG_PLN_AXIS_LSB);
const _: () = assert!(dim::CFG_PLN_AXIS_LSB + 2 * MAX_PLANES <= dim::CFG_PLN_NEG_LSB);
const _: () = assert!(dim::CFG_PLN_NEG_LSB + MAX_PLANES <= 96);
const _: () = assert!(1 << dim::COORD_BITS == MAX_IMAGE_SIDE as usize);

/// Per-object bits the controller branches on. Each lets it skip work whose
/// result would be an exact +0 or would never be used.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MaterialBits {
    /// kd > 0: compute the diffuse term.
    pub diffuse: bool,
    /// ks > 0: compute the specular term.
    pub specular: bool,
    /// kr > 0: spawn a reflected ray.
    pub reflective: bool,
}

impl MaterialBits {
    /// The configuration word's 3 bits: diffuse, specular, reflective.
    pub fn code(self) -> u128 {
        u128::from(self.diffuse) | u128::from(self.specular) << 1 | u128::from(self.reflective) << 2
    }

    fn of(m: &Material) -> MaterialBits {
        MaterialBits {
            diffuse: m.diffuse > 0.0,
            specular: m.specular > 0.0,
            reflective: m.reflection > 0.0,
        }
    }
}

/// The controller's configuration registers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    /// Spheres in the scene (0..=8); the sphere loops run over these.
    pub spheres: usize,
    /// Planes in the scene (0..=6).
    pub planes: usize,
    /// Ray stack levels used (1..=8).
    pub max_depth: usize,
    pub speedups: Speedups,
    /// The fp_recip and fp_sqrt methods (RTL parameters).
    pub recip: Method,
    pub sqrt: Method,
    /// The weight cutoff is on (render.weight_cutoff > 0): a push is
    /// preceded by CUT_W and CUT_CMP. The value is in lane z of each
    /// object's SPHk_R / PLNj_Q register ([`scene_writes`]).
    pub cutoff: bool,
    /// The exposure is on (render.exposure is set): EXPO_MUL, EXPO_EXP and
    /// EXPO_SUB before PIX_DONE. The value is in lane x of ROT0_S
    /// ([`scene_writes`]).
    pub exposure: bool,
    /// Rotate the primary ray about axis a (x, y, z): false when the angle's
    /// cos is exactly 1 and its sin exactly 0, so the rotation is skipped.
    pub rotate: [bool; 3],
    pub sphere_bits: [MaterialBits; MAX_SPHERES],
    /// Each sphere is transparent (transmission > 0): a hit on it spawns a
    /// refracted child, which reads its TRNk register ([`scene_writes`]).
    pub transparent: [bool; MAX_SPHERES],
    pub plane_bits: [MaterialBits; MAX_PLANES],
    /// Each plane's axis (0 = x): the lane the fast plane test looks at.
    pub plane_axis: [usize; MAX_PLANES],
    /// Each plane's facing is -1 (the normal points down its axis).
    pub plane_facing_neg: [bool; MAX_PLANES],
}

impl Config {
    pub fn new(scene: &Scene) -> Config {
        let mut c = Config {
            spheres: scene.spheres.len(),
            planes: scene.planes.len(),
            max_depth: scene.render.max_depth as usize,
            speedups: scene.render.speedups,
            recip: scene.render.recip,
            sqrt: scene.render.sqrt,
            cutoff: scene.render.cutoff_on(),
            exposure: scene.render.exposure.is_some(),
            rotate: [0, 1, 2]
                .map(|a| !(scene.derived.cos[a] == 1.0 && scene.derived.sin[a] == 0.0)),
            sphere_bits: [MaterialBits::default(); MAX_SPHERES],
            transparent: [false; MAX_SPHERES],
            plane_bits: [MaterialBits::default(); MAX_PLANES],
            plane_axis: [0; MAX_PLANES],
            plane_facing_neg: [false; MAX_PLANES],
        };
        for (k, s) in scene.spheres.iter().enumerate() {
            c.sphere_bits[k] = MaterialBits::of(&s.material);
            c.transparent[k] = s.material.transparent();
        }
        for (j, p) in scene.planes.iter().enumerate() {
            c.plane_bits[j] = MaterialBits::of(&p.material);
            c.plane_axis[j] = p.axis.index();
            c.plane_facing_neg[j] = p.facing < 0.0;
        }
        c
    }

    /// The configuration word the scene port writes with scene_cfg = 1
    /// (layout: `ISA_DIM_CFG_*` in rtl/pp/isa.vh), as lanes x, y, z.
    pub fn word(&self) -> [u32; 3] {
        let mut w: u128 = 0;
        let mut put = |lsb: usize, v: u128| w |= v << lsb;
        put(dim::CFG_SPHERES_LSB, self.spheres as u128);
        put(dim::CFG_PLANES_LSB, self.planes as u128);
        put(dim::CFG_DEPTH_LSB, self.max_depth as u128);
        put(dim::CFG_BBOX_LSB, u128::from(self.speedups.bounding_box));
        put(
            dim::CFG_FAST_PLANE_LSB,
            u128::from(self.speedups.fast_plane),
        );
        put(
            dim::CFG_SHORTCUT_LSB,
            u128::from(self.speedups.shadow_shortcut),
        );
        put(dim::CFG_CUTOFF_LSB, u128::from(self.cutoff));
        put(dim::CFG_EXPOSURE_LSB, u128::from(self.exposure));
        for a in 0..3 {
            put(dim::CFG_ROTATE_LSB + a, u128::from(self.rotate[a]));
        }
        for (k, b) in self.sphere_bits.iter().enumerate() {
            put(dim::CFG_SPH_BITS_LSB + 3 * k, b.code());
            put(dim::CFG_TRN_LSB + k, u128::from(self.transparent[k]));
        }
        for j in 0..MAX_PLANES {
            put(dim::CFG_PLN_BITS_LSB + 3 * j, self.plane_bits[j].code());
            put(dim::CFG_PLN_AXIS_LSB + 2 * j, self.plane_axis[j] as u128);
            put(
                dim::CFG_PLN_NEG_LSB + j,
                u128::from(self.plane_facing_neg[j]),
            );
        }
        [w as u32, (w >> 32) as u32, (w >> 64) as u32]
    }
}

/// The scene port's writes, in address order: (address, lanes x, y, z as
/// f32 bits). Unused sphere and plane slots are not written.
pub fn scene_writes(scene: &Scene) -> Vec<(u8, [u32; 3])> {
    let d = &scene.derived;
    // Lane z of SPHk_R and PLNj_Q: the weight cutoff (isa.vh).
    let cut = scene.render.weight_cutoff;
    let mut w: Vec<(Reg, Vec3f)> = Vec::new();
    for (k, s) in scene.spheres.iter().enumerate() {
        let m = &s.material;
        w.push((isa::sphere(k, SphereField::C), s.center));
        w.push((
            isa::sphere(k, SphereField::R),
            [d.radius_sq[k], d.inv_radius[k], cut],
        ));
        w.push((isa::sphere(k, SphereField::Col), m.color));
        w.push((
            isa::sphere(k, SphereField::Mat),
            [m.diffuse, m.specular, m.reflection],
        ));
        if m.transparent() {
            w.push((isa::trn(k), [d.inv_ior[k], m.ior, m.transmission]));
        }
    }
    for (j, p) in scene.planes.iter().enumerate() {
        let m = &p.material;
        // facing is +-1: the product is the offset or its negation, exact.
        let q = if p.facing < 0.0 { -p.offset } else { p.offset };
        w.push((isa::plane(j, PlaneField::N), d.plane_normal[j]));
        w.push((isa::plane(j, PlaneField::Q), [q, 0.0, cut]));
        w.push((isa::plane(j, PlaneField::Col), m.color));
        w.push((
            isa::plane(j, PlaneField::Mat),
            [m.diffuse, m.specular, m.reflection],
        ));
    }
    w.push((Reg::LIGHT_POS, scene.light.position));
    w.push((Reg::LIGHT_COL, scene.light.color));
    w.push((Reg::EYE, scene.camera.eye));
    w.push((
        Reg::CAM_HALF,
        [-d.half_width, d.half_height, scene.camera.distance],
    ));
    for a in 0..3 {
        let (c, s) = (d.cos[a], d.sin[a]);
        let (u, v) = ((a + 1) % 3, (a + 2) % 3);
        let mut cv = [1.0; 3];
        let mut sv = [0.0; 3];
        cv[u] = c;
        cv[v] = c;
        sv[u] = -s;
        sv[v] = s;
        if a == 0 {
            // Lane a of ROTa_S is read by no write: ROT0_S.x is the
            // exposure (isa.vh), +0 when off.
            sv[0] = scene.render.exposure.unwrap_or(0.0);
        }
        let (rc, rs) = isa::rot(a);
        w.push((rc, cv));
        w.push((rs, sv));
    }
    let (lo, hi) = bounding_box(scene);
    for k in 0..8 {
        let corner = [0, 1, 2].map(|i| if k >> i & 1 == 1 { hi[i] } else { lo[i] });
        w.push((isa::corner(k), corner));
    }
    w.push((Reg::ZERO, [0.0; 3]));
    w.push((Reg::ONE, [1.0; 3]));
    w.sort_by_key(|&(a, _)| a);
    w.into_iter()
        .map(|(a, v)| (a.0, v.map(f32::to_bits)))
        .collect()
}

/// The box's longest side divided by this is the margin [`bounding_box`]
/// adds on every side.
pub const BOX_MARGIN_DIVISOR: f64 = 256.0;

/// The bounding box the RTL tests (corners BOX0 = min, BOX7 = max): the
/// scene's derived box around the spheres, widened on every side by its
/// longest side / [`BOX_MARGIN_DIVISOR`] and rounded outwards.
///
/// Why wider: the box must never refuse a ray that the f32 sphere test
/// accepts, or switching it on would change the image. The sphere test
/// decides from the centre's distance to the line, |w| = |v - (v.d) d|,
/// which f32 gets right to a few ulps of the origin's coordinates: it may
/// accept a ray passing up to ~4 * 2^-23 * |o| outside the sphere, which the
/// exact box would refuse. The margin (1.95 units in the reference scene)
/// covers origins up to ~4e6 units away; it costs a few more box hits.
pub fn bounding_box(scene: &Scene) -> (Vec3f, Vec3f) {
    let d = &scene.derived;
    if scene.spheres.is_empty() {
        return (d.bbox_min, d.bbox_max);
    }
    let side = (0..3)
        .map(|i| f64::from(d.bbox_max[i]) - f64::from(d.bbox_min[i]))
        .fold(0.0, f64::max);
    let margin = side / BOX_MARGIN_DIVISOR;
    (
        [0, 1, 2].map(|i| round_down(f64::from(d.bbox_min[i]) - margin)),
        [0, 1, 2].map(|i| round_up(f64::from(d.bbox_max[i]) + margin)),
    )
}

/// The register file after the scene port's writes.
pub fn register_image(scene: &Scene) -> RegisterImage {
    let mut img = RegisterImage {
        bits: [[0; 3]; REGISTER_COUNT],
        valid: [Lanes::NONE; REGISTER_COUNT],
    };
    for (a, v) in scene_writes(scene) {
        img.bits[a as usize] = v;
        img.valid[a as usize] = Lanes::XYZ;
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::micro::isa::reg;

    #[test]
    fn the_reference_scene_loads_every_scene_register_it_uses_once() {
        let s = Scene::reference();
        let w = scene_writes(&s);
        let addrs: Vec<u8> = w.iter().map(|e| e.0).collect();
        let mut dedup = addrs.clone();
        dedup.dedup();
        assert_eq!(addrs, dedup, "each address once, ascending");
        // 2 spheres, 2 planes, 4 light/camera, 6 rotation, 8 corners, 2 constants.
        assert_eq!(w.len(), 2 * 4 + 2 * 4 + 4 + 6 + 8 + 2);
        assert!(w.iter().all(|&(a, _)| a < reg::T0));
        let at = |a: Reg| {
            w.iter()
                .find(|e| e.0 == a.0)
                .expect("written")
                .1
                .map(f32::from_bits)
        };
        assert_eq!(
            at(isa::sphere(1, SphereField::R)),
            [4900.0, 1.0 / 70.0, 0.0]
        );
        // The back wall: z = 700 facing -: n = <0, 0, -1>, q = -700.
        assert_eq!(at(isa::plane(1, PlaneField::N)), [0.0, 0.0, -1.0]);
        assert_eq!(at(isa::plane(1, PlaneField::Q)), [-700.0, 0.0, 0.0]);
        assert_eq!(at(Reg::CAM_HALF), [-400.0, 300.0, 600.0]);
        // The spheres span x -260..240, y 2..302, z 10..400: margin 500/256.
        let m = 500.0 / 256.0;
        assert_eq!(at(isa::corner(0)), [-260.0 - m, 2.0 - m, 10.0 - m]);
        assert_eq!(at(isa::corner(7)), [240.0 + m, 302.0 + m, 400.0 + m]);
        assert_eq!(at(isa::corner(5)), [240.0 + m, 2.0 - m, 400.0 + m]);
        let (c, sn) = (s.derived.cos[0], s.derived.sin[0]);
        assert_eq!(at(isa::rot(0).0), [1.0, c, c]);
        assert_eq!(at(isa::rot(0).1), [0.0, -sn, sn]);
    }

    #[test]
    fn the_configuration_skips_identity_rotations() {
        let c = Config::new(&Scene::reference());
        assert_eq!(c.rotate, [true, false, false]);
        assert_eq!((c.spheres, c.planes, c.max_depth), (2, 2, 4));
        assert!(c.sphere_bits[0].specular && !c.plane_bits[0].specular);
        assert_eq!(c.plane_axis[..2], [1, 2]);
        assert_eq!(c.plane_facing_neg[..2], [false, true]);
    }

    #[test]
    fn the_configuration_word_packs_every_field_where_the_header_says() {
        let c = Config::new(&Scene::reference());
        let [x, y, z] = c.word();
        let w = u128::from(x) | u128::from(y) << 32 | u128::from(z) << 64;
        let field = |lsb: usize, bits: usize| (w >> lsb) & ((1 << bits) - 1);
        assert_eq!(field(dim::CFG_SPHERES_LSB, 4), 2);
        assert_eq!(field(dim::CFG_PLANES_LSB, 3), 2);
        assert_eq!(field(dim::CFG_DEPTH_LSB, 4), 4);
        let s = c.speedups;
        assert_eq!(field(dim::CFG_BBOX_LSB, 1), u128::from(s.bounding_box));
        assert_eq!(field(dim::CFG_FAST_PLANE_LSB, 1), u128::from(s.fast_plane));
        assert_eq!(
            field(dim::CFG_SHORTCUT_LSB, 1),
            u128::from(s.shadow_shortcut)
        );
        assert_eq!(field(dim::CFG_CUTOFF_LSB, 1), 0);
        assert_eq!(field(dim::CFG_EXPOSURE_LSB, 1), 0);
        assert_eq!(field(dim::CFG_ROTATE_LSB, 3), 0b001);
        for k in 0..2 {
            assert_eq!(
                field(dim::CFG_SPH_BITS_LSB + 3 * k, 3),
                c.sphere_bits[k].code()
            );
        }
        // The floor (y, facing +) and the back wall (z, facing -).
        assert_eq!(field(dim::CFG_PLN_AXIS_LSB, 4), 1 | 2 << 2);
        assert_eq!(field(dim::CFG_PLN_NEG_LSB, 2), 0b10);
        assert_eq!(
            field(dim::CFG_PLN_BITS_LSB, 6),
            c.plane_bits[0].code() | c.plane_bits[1].code() << 3
        );
        // Nothing beyond the last field.
        assert_eq!(w >> (dim::CFG_PLN_NEG_LSB + MAX_PLANES), 0);
    }
}
