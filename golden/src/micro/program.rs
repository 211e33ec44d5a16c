//! The pixel processor controller (thesis 4.7): the per-pixel program, one
//! ALU instruction per line, each issued from its FSM state.
//!
//! Rust control flow is the FSM's next-state logic: loops over objects,
//! stack-pointer moves, exclusions and branches on the flags of the value an
//! instruction just wrote cost no cycle of their own (thesis 4.2: booleans
//! and integers live "at a higher hierarchical level ... executed at the
//! same time as floating point operators"). The helpers (dot, normalize,
//! the intersection sub-graph, the sphere and plane tests, the box test)
//! are the sub-state machines of thesis 4.7.1; they take
//! their operand addresses as arguments as the RTL's sub-machines take them
//! from pointer registers, and `#[track_caller]` makes their instructions
//! report the line that called them.
//!
//! The algorithm is thesis 3.6, iterative with the explicit ray stack: the
//! primary ray is pushed at level 0; each ray's nearest hit is shaded into
//! its colour (weighted by the product of its ancestors' reflection values);
//! a reflective hit below the depth limit pushes the reflected ray; when a
//! ray does not push, the stack unwinds, adding each ray's colour into its
//! parent's. Only reflection rays exist, so the ray tree is a list.

use super::core::{lanes, Core, Written, LANE};
use super::isa::{self, reg, state as st, PlaneField, SphereField};
use super::loader::{Config, MaterialBits};
use crate::scene::{Object, Vec3f, MAX_DEPTH};
use crate::trace::TraceEvent;
use std::panic::Location;

use lanes::{X, XYZ, Y};

/// The temporaries' roles. Registers are shared between roles whose
/// lifetimes never overlap (thesis 3.12: "limit the duration a value must be
/// accessible").
mod t {
    use super::reg;
    /// Primary ray: camera-space direction. Shading: the hit point when no
    /// child ray is pushed (else it goes straight to CUR_O).
    pub const P: u8 = reg::T0;
    /// Rotation: cos products. Shading: the sphere normal.
    pub const N: u8 = reg::T1;
    /// Rotation: sin products. Shading: light - p, then the reflected
    /// direction when no child is pushed (else it goes to CUR_D).
    pub const R: u8 = reg::T2;
    /// The unit vector towards the light (the shadow ray's direction).
    pub const L: u8 = reg::T3;
    /// Normalize: v.v, then |v| (for the light vector: its distance).
    pub const LEN: u8 = reg::T4;
    /// Normalize: 1/|v|.
    pub const INV: u8 = reg::T5;
    /// -t of the nearest hit so far.
    pub const BEST: u8 = reg::T6;
    /// Scratch of the tests and of shading.
    pub const V: u8 = reg::T7;
    pub const G: u8 = reg::T8;
    pub const S: u8 = reg::T9;
    pub const Q: u8 = reg::T10;
    pub const U: u8 = reg::T11;
}

/// The flags of the last ray direction written (NORM_SCALE, SH_REFL),
/// latched by the controller: the fast plane test and the box test's corner
/// choice read them.
#[derive(Debug, Clone, Copy, Default)]
struct DirFlags {
    /// Bit i: the sign bit of lane i.
    sign: u8,
    /// Bit i: lane i < 0.
    neg: u8,
    /// Bit i: lane i > 0.
    pos: u8,
}

impl DirFlags {
    fn of(w: &Written) -> DirFlags {
        let bits = |f: &dyn Fn(usize) -> bool| (0..3).fold(0, |m, i| m | u8::from(f(i)) << i);
        DirFlags {
            sign: w.sign_bits(),
            neg: bits(&|i| w.neg(i)),
            pos: bits(&|i| w.pos(i)),
        }
    }

    /// Thesis 3.10.2: the direction opposes a plane's normal (facing * unit
    /// axis) iff its component along the axis is strictly of the other sign.
    fn opposes(&self, axis: usize, facing_neg: bool) -> bool {
        let flags = if facing_neg { self.pos } else { self.neg };
        flags >> axis & 1 == 1
    }

    fn sign_of(&self, lane: usize) -> bool {
        self.sign >> lane & 1 == 1
    }
}

/// The registers of the ray being shaded and of its products.
struct Shading {
    o: u8,
    d: u8,
    col: u8,
    w: u8,
    /// The level whose colour `col` is.
    level: usize,
    /// The hit point and reflected direction: the child's CUR_O and CUR_D
    /// when it is pushed, else temporaries.
    p: u8,
    r: u8,
}

/// One pixel's run of the controller.
pub struct Program<'c, T> {
    pub core: Core<T>,
    cfg: &'c Config,
    dir: DirFlags,
    /// Whether each level's colour register has been written this pixel
    /// (an unwritten colour is black, and adding it is skipped).
    coloured: [bool; MAX_DEPTH as usize],
}

impl<'c, T: FnMut(&TraceEvent, &'static Location<'static>)> Program<'c, T> {
    pub fn new(core: Core<T>, cfg: &'c Config) -> Program<'c, T> {
        Program {
            core,
            cfg,
            dir: DirFlags::default(),
            coloured: [false; MAX_DEPTH as usize],
        }
    }

    /// Runs the pixel (the cycles before PIX_DONE) and
    /// returns the colour in STK0_COL.
    pub fn run(&mut self) -> [u32; 3] {
        self.primary_ray();
        let mut from = None;
        while let Some(obj) = self.nearest_hit(reg::CUR_O, reg::CUR_D, from) {
            let push = self.bits(obj).reflective && self.core.sp + 1 < self.cfg.max_depth;
            if push {
                self.core.sp += 1;
            }
            self.shade(obj, push);
            if !push {
                break;
            }
            from = Some(obj);
        }
        self.unwind();
        self.core
            .peek(isa::stack(0, isa::RayField::Col))
            .expect("the root colour is written before PIX_DONE")
    }

    fn bits(&self, obj: Object) -> MaterialBits {
        match obj {
            Object::Sphere(k) => self.cfg.sphere_bits[k],
            Object::Plane(j) => self.cfg.plane_bits[j],
        }
    }

    // -----------------------------------------------------------------------
    // Sub-machines
    // -----------------------------------------------------------------------

    /// y.x = a.b (3 cycles).
    #[track_caller]
    fn dot(&mut self, y: u8, a: u8, b: u8) -> Written {
        self.core.dot1(st::DOT_1, a, b);
        self.core.dot2(st::DOT_2);
        self.core.dot3(st::DOT_3, y)
    }

    /// y = v / |v|, leaving |v| in LEN.x, and latches y's direction flags
    /// (dot + ROOTS + 2 cycles).
    #[track_caller]
    fn normalize(&mut self, y: u8, v: u8) -> Written {
        self.dot(t::LEN, v, v);
        // |v| and 1/(v.v) at once, then 1/|v| = |v| * 1/(v.v): the square
        // root and the reciprocal overlap instead of following each other.
        self.core.roots(st::NORM_ROOTS, t::LEN, t::LEN);
        self.core.mulr1(st::NORM_INV, t::INV, t::LEN, t::LEN, X);
        let w = self.core.mulx(st::NORM_SCALE, y, v, t::INV, XYZ);
        self.dir = DirFlags::of(&w);
        w
    }

    /// S = <a.x - b.c, c.d, 0> with g in G (4 cycles; see `alu`).
    #[track_caller]
    fn isect(&mut self, b: u8, c: u8, d: u8, a: u8) -> Written {
        self.core.isect1(st::ISECT_1, b, c);
        self.core.isect2(st::ISECT_2, t::G, d, c);
        self.core.isect3(st::ISECT_3, t::G);
        self.core.isect4(st::ISECT_4, t::S, a)
    }

    // -----------------------------------------------------------------------
    // The primary ray (thesis 3.5)
    // -----------------------------------------------------------------------

    fn primary_ray(&mut self) {
        let c = &mut self.core;
        c.itof(st::PRI_ITOF, t::P);
        // <px - w/2, h/2 - py, distance>: exact (integers and halves).
        c.add(st::PRI_HALF, t::P, t::P, reg::CAM_HALF, XYZ);
        // About x, then y, then z: with (u, v) the two lanes that turn,
        // u' = u c - v s and v' = u s + v c.
        for a in 0..3 {
            if !self.cfg.rotate[a] {
                continue;
            }
            let (u, v) = (LANE[(a + 1) % 3], LANE[(a + 2) % 3]);
            let (rc, rs) = isa::rot(a);
            let c = &mut self.core;
            c.mul(st::ROT_COS, t::N, t::P, rc, XYZ);
            c.mulr1(st::ROT_SIN_U, t::R, rs, t::P, u); // -s * v
            c.mulr2(st::ROT_SIN_V, t::R, rs, t::P, v); // s * u
            c.add(st::ROT_ADD, t::P, t::N, t::R, u | v);
        }
        // CUR_O and CUR_W at level 0 are EYE and ONE (isa::decode).
        self.normalize(reg::CUR_D, t::P);
    }

    // -----------------------------------------------------------------------
    // Intersection tests
    // -----------------------------------------------------------------------

    /// Sphere k against the ray (o, d): `Some(u)` with u = -t written to
    /// `dst.x` if the line meets the sphere (disc >= 0), `None` if not.
    ///
    /// The reference's optics (v = o - c, b = v.d, disc = r*r - (v.v - b*b),
    /// t = -b - sqrt(disc)) with v.v - b*b computed as |w|^2, w = v - b d the
    /// centre's offset from the line: the same number for a unit d, but
    /// without the catastrophic cancellation of v.v - b*b, whose f32 error is
    /// a few ulps of |v|^2. From a wall point 2e7 away (a reflection grazing
    /// the wall), that error is ~1e8 and "hits" spheres the ray passes far
    /// from; |w| is good to a few ulps of |v|.
    fn sphere_u(&mut self, k: usize, o: u8, d: u8, dst: u8) -> Option<Written> {
        self.core
            .sub(st::SPH_V, t::V, o, isa::sphere(k, SphereField::C), XYZ);
        // Q.x = b. With b >= 0 (or NaN) u = sqrt(disc) + b below is never
        // < 0 (a rounded sum of non-negative numbers), so the near root is
        // not ahead of the ray whatever disc is: the test ends here, and
        // exactly the same hits are found.
        if !self.dot(t::Q, t::V, d).neg(0) {
            return None;
        }
        let c = &mut self.core;
        c.nmulx(st::SPH_BD, t::U, d, t::Q, XYZ); // -b d
        c.add(st::SPH_W, t::V, t::V, t::U, XYZ); // w = v - b d
                                                 // The shared sub-graph with b = c = w, a = r*r: S.x = disc = r*r - w.w
                                                 // (S.y = w.d, about 0, unused).
        if self
            .isect(t::V, t::V, d, isa::sphere(k, SphereField::R))
            .neg(0)
        {
            return None;
        }
        let c = &mut self.core;
        c.sqrt(st::SPH_SQRT, t::S, t::S);
        Some(c.add(st::SPH_T, dst, t::S, t::Q, X)) // sqrt(disc) + b = -t
    }

    /// After `isect` left <q - n.o, n.d, 0> in S: u = -t = -(q - n.o)/(n.d)
    /// into `dst.x`.
    fn plane_u(&mut self, dst: u8) -> Written {
        self.core.recipy(st::PLN_RECIP, t::Q, t::S);
        self.core.nmulx(st::PLN_T, dst, t::S, t::Q, X)
    }

    /// Plane j against the ray (o, d) up to its t: `Some(u)` with u = -t in
    /// `dst.x` and whether t > 0 holds, or `None` if the plane faces away.
    /// With fast_plane (thesis 3.10.2) the facing decision is the latched
    /// sign of one direction lane (no instruction), and t > 0 is assumed
    /// (the scene's precondition); without it, the sub-graph's n.d < 0 and
    /// the sign of u decide. n.d of an axis normal is exactly +-d[axis], so
    /// both decide facing alike, and t comes from the same instructions.
    fn plane_u_checked(&mut self, j: usize, o: u8, d: u8, dst: u8) -> Option<(Written, bool)> {
        let fast = self.cfg.speedups.fast_plane;
        if fast
            && !self
                .dir
                .opposes(self.cfg.plane_axis[j], self.cfg.plane_facing_neg[j])
        {
            return None;
        }
        let s = self.isect(
            o,
            isa::plane(j, PlaneField::N),
            d,
            isa::plane(j, PlaneField::Q),
        );
        if !fast && !s.neg(1) {
            return None;
        }
        let u = self.plane_u(dst);
        let ahead = fast || u.neg(0);
        Some((u, ahead))
    }

    /// Thesis 3.10.1: whether the ray (o, d) can meet the box around all the
    /// spheres at t >= 0. A slab test without division: per axis i, the
    /// near and far corner offsets N_i, F_i (chosen by the sign of d_i, so
    /// t_near_i = N_i/d_i <= t_far_i = F_i/d_i) give a miss iff some
    /// t_far_i < 0 (sign of F_i*d_i) or some t_near_i > t_far_j, which,
    /// multiplied by d_i*d_j, compares N_i*d_j with F_j*d_i (the inequality
    /// flips when d_i and d_j differ in sign). Only strict inequalities
    /// reject, and a zero lane of d makes its comparisons give way, so the
    /// test errs towards "hit".
    fn box_hit(&mut self, o: u8, d: u8) -> bool {
        let s = self.dir.sign as usize;
        let c = &mut self.core;
        // The far corner first: a box behind the ray is refused after two
        // instructions instead of three.
        c.sub(st::BOX_FAR, t::G, isa::corner(s ^ 7), o, XYZ);
        let behind = c.mul(st::BOX_BEHIND, t::S, t::G, d, XYZ);
        if (0..3).any(|i| behind.neg(i)) {
            return false;
        }
        c.sub(st::BOX_NEAR, t::V, isa::corner(s), o, XYZ);
        c.mulr1(st::BOX_P1, t::Q, t::V, d, XYZ); // N_i d_(i+1)
        c.mulr1(st::BOX_Q1, t::U, d, t::G, XYZ); // d_i F_(i+1)
        let d1 = c.sub(st::BOX_D1, t::Q, t::Q, t::U, XYZ);
        if self.separated(&d1, 1) {
            return false;
        }
        let c = &mut self.core;
        c.mulr2(st::BOX_P2, t::Q, t::V, d, XYZ); // N_i d_(i+2)
        c.mulr2(st::BOX_Q2, t::U, d, t::G, XYZ); // d_i F_(i+2)
        let d2 = c.sub(st::BOX_D2, t::Q, t::Q, t::U, XYZ);
        !self.separated(&d2, 2)
    }

    /// Whether lane i of `diff` = N_i d_j - F_j d_i (j = i + shift) proves
    /// t_near_i > t_far_j.
    fn separated(&self, diff: &Written, shift: usize) -> bool {
        (0..3).any(|i| {
            let j = (i + shift) % 3;
            if self.dir.sign_of(i) == self.dir.sign_of(j) {
                diff.pos(i)
            } else {
                diff.neg(i)
            }
        })
    }

    fn spheres_other_than(&self, skip: Option<Object>) -> usize {
        (0..self.cfg.spheres)
            .filter(|&k| skip != Some(Object::Sphere(k)))
            .count()
    }

    // -----------------------------------------------------------------------
    // The nearest hit of an open-air ray
    // -----------------------------------------------------------------------

    /// The nearest object along (o, d) other than `from`, its -t left in
    /// BEST.x; ties go to the first in sphere-then-plane order.
    fn nearest_hit(&mut self, o: u8, d: u8, from: Option<Object>) -> Option<Object> {
        let mut best = None;
        let any_sphere = self.spheres_other_than(from) > 0;
        if any_sphere && (!self.cfg.speedups.bounding_box || self.box_hit(o, d)) {
            for k in 0..self.cfg.spheres {
                if from == Some(Object::Sphere(k)) {
                    continue;
                }
                let dst = if best.is_none() { t::BEST } else { t::U };
                if let Some(u) = self.sphere_u(k, o, d, dst) {
                    if u.neg(0) {
                        self.offer(&mut best, Object::Sphere(k));
                    }
                }
            }
        }
        for j in 0..self.cfg.planes {
            if from == Some(Object::Plane(j)) {
                continue;
            }
            let dst = if best.is_none() { t::BEST } else { t::U };
            if let Some((_, true)) = self.plane_u_checked(j, o, d, dst) {
                self.offer(&mut best, Object::Plane(j));
            }
        }
        best
    }

    /// A hit ahead of the ray: the first becomes the best where it was
    /// written (BEST); a later one (in U) replaces it only if strictly
    /// nearer: u - u_best > 0, i.e. t < t_best.
    fn offer(&mut self, best: &mut Option<Object>, obj: Object) {
        if best.is_none() {
            *best = Some(obj);
            return;
        }
        if self.core.sub(st::HIT_CMP, t::G, t::U, t::BEST, X).pos(0) {
            self.core.mov(st::HIT_KEEP, t::BEST, t::U, X);
            *best = Some(obj);
        }
    }

    // -----------------------------------------------------------------------
    // The shadow ray (p, L), |light - p| in LEN.x
    // -----------------------------------------------------------------------

    /// Whether an object other than `on` blocks the light from p: a hit at
    /// 0 < t < |light - p|. With shadow_shortcut (thesis 3.10.3) only
    /// spheres are tested and any t > 0 blocks.
    fn shadowed(&mut self, p: u8, on: Object) -> bool {
        let shortcut = self.cfg.speedups.shadow_shortcut;
        let any_sphere = self.spheres_other_than(Some(on)) > 0;
        if any_sphere && (!self.cfg.speedups.bounding_box || self.box_hit(p, t::L)) {
            for k in 0..self.cfg.spheres {
                if on == Object::Sphere(k) {
                    continue;
                }
                if let Some(u) = self.sphere_u(k, p, t::L, t::U) {
                    if u.neg(0) && (shortcut || self.before_light()) {
                        return true;
                    }
                }
            }
        }
        if shortcut {
            return false;
        }
        for j in 0..self.cfg.planes {
            if on == Object::Plane(j) {
                continue;
            }
            if let Some((_, true)) = self.plane_u_checked(j, p, t::L, t::U) {
                if self.before_light() {
                    return true;
                }
            }
        }
        false
    }

    /// t < |light - p|, as |light - p| + u > 0 with u = -t in U.x.
    fn before_light(&mut self) -> bool {
        self.core.add(st::SHD_DIST, t::G, t::U, t::LEN, X).pos(0)
    }

    // -----------------------------------------------------------------------
    // Shading (thesis 3.4)
    // -----------------------------------------------------------------------

    /// Shades the hit of the ray at level sp (or sp - 1 when `push`: the
    /// child's level is already current, and p and r are written straight
    /// into its origin and direction). Writes the ray's colour = w * local
    /// unless no light arrives, and, when pushing, the child's weight.
    fn shade(&mut self, obj: Object, push: bool) {
        let sp = self.core.sp;
        let ray = if push {
            Shading {
                o: reg::PAR_O,
                d: reg::PAR_D,
                col: reg::PAR_COL,
                w: reg::PAR_W,
                level: sp - 1,
                p: reg::CUR_O,
                r: reg::CUR_D,
            }
        } else {
            Shading {
                o: reg::CUR_O,
                d: reg::CUR_D,
                col: reg::CUR_COL,
                w: reg::CUR_W,
                level: sp,
                p: t::P,
                r: t::R,
            }
        };
        let (n, mat, colour) = match obj {
            Object::Sphere(k) => (
                t::N,
                isa::sphere(k, SphereField::Mat),
                isa::sphere(k, SphereField::Col),
            ),
            Object::Plane(j) => (
                isa::plane(j, PlaneField::N),
                isa::plane(j, PlaneField::Mat),
                isa::plane(j, PlaneField::Col),
            ),
        };
        let bits = self.bits(obj);

        // p = o + t d, with t d = -(d * u_best).
        let c = &mut self.core;
        c.nmulx(st::SH_OFFSET, t::V, ray.d, t::BEST, XYZ);
        c.add(st::SH_POINT, ray.p, ray.o, t::V, XYZ);
        if let Object::Sphere(k) = obj {
            // n = (p - c) * 1/r (thesis eq. 28).
            c.sub(
                st::SH_NORMAL_SUB,
                t::N,
                ray.p,
                isa::sphere(k, SphereField::C),
                XYZ,
            );
            c.muly(
                st::SH_NORMAL_SCALE,
                t::N,
                t::N,
                isa::sphere(k, SphereField::R),
                XYZ,
            );
        }
        self.core
            .sub(st::SH_LIGHT_VEC, t::R, reg::LIGHT_POS, ray.p, XYZ);
        self.normalize(t::L, t::R);
        let lit = !self.shadowed(ray.p, obj);

        // Diffuse: kd * max(n.l, 0) * (C * Lc); a zero term is skipped.
        let mut diffuse = None;
        if lit && bits.diffuse && self.dot(t::V, n, t::L).pos(0) {
            let c = &mut self.core;
            c.mulx(st::SH_KD, t::G, mat, t::V, X);
            c.mul(st::SH_CL, t::S, colour, reg::LIGHT_COL, XYZ);
            c.mulx(st::SH_DIFFUSE, t::S, t::S, t::G, XYZ);
            diffuse = Some(t::S);
        }

        // r = d - 2 (d.n) n, after the shadow test so that its direction
        // flags are the last latched before the child's search.
        if push || (lit && bits.specular) {
            self.dot(t::Q, ray.d, n);
            let c = &mut self.core;
            c.mul2x(st::SH_REFL_K, t::U, n, t::Q, XYZ); // k = 2 (d.n) n
            let r = c.sub(st::SH_REFL, ray.r, ray.d, t::U, XYZ);
            self.dir = DirFlags::of(&r);
        }

        // Specular: ks * max(r.l, 0)^20 * Lc.
        let mut specular = None;
        if lit && bits.specular && self.dot(t::Q, ray.r, t::L).pos(0) {
            let c = &mut self.core;
            c.mul(st::SH_POW2, t::U, t::Q, t::Q, X);
            c.mul(st::SH_POW4, t::U, t::U, t::U, X);
            c.mul(st::SH_POW5, t::U, t::U, t::Q, X);
            c.mul(st::SH_POW10, t::U, t::U, t::U, X);
            c.mul(st::SH_POW20, t::U, t::U, t::U, X);
            c.mulx(st::SH_KS, t::V, mat, t::U, Y); // V.y = ks * x^20
            c.muly(st::SH_SPEC, t::G, reg::LIGHT_COL, t::V, XYZ);
            specular = Some(t::G);
        }

        let local = match (diffuse, specular) {
            (Some(a), Some(b)) => {
                self.core.add(st::SH_LOCAL, t::S, a, b, XYZ);
                Some(t::S)
            }
            (a, b) => a.or(b),
        };
        if let Some(local) = local {
            self.core.mul(st::SH_COLOUR, ray.col, local, ray.w, XYZ);
            self.coloured[ray.level] = true;
        }
        if push {
            self.core
                .mulz(st::SH_CHILD_W, reg::CUR_W, reg::PAR_W, mat, XYZ);
        }
    }

    // -----------------------------------------------------------------------
    // Unwinding (thesis 3.6: "this ray's color is added to its parent's")
    // -----------------------------------------------------------------------

    fn unwind(&mut self) {
        while self.core.sp > 0 {
            let sp = self.core.sp;
            if self.coloured[sp] {
                if self.coloured[sp - 1] {
                    self.core
                        .add(st::POP_ADD, reg::PAR_COL, reg::PAR_COL, reg::CUR_COL, XYZ);
                } else {
                    self.core.mov(st::POP_MOV, reg::PAR_COL, reg::CUR_COL, XYZ);
                    self.coloured[sp - 1] = true;
                }
            }
            self.core.sp -= 1;
        }
        if !self.coloured[0] {
            self.core.mov(st::ROOT_BLACK, reg::CUR_COL, reg::ZERO, XYZ);
        }
    }
}

/// The colour as f32 lanes.
pub fn rgb_of(bits: [u32; 3]) -> Vec3f {
    bits.map(f32::from_bits)
}
