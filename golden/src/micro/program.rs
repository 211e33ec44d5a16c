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
//! its colour (weighted by the product of its ancestors' reflection and
//! transmission values); a reflective hit below the depth limit pushes the
//! reflected ray (unless the weight cutoff refuses it: `Program::cut`);
//! when a ray does not push, the stack unwinds, adding each ray's colour
//! into its parent's. A hit on a transparent sphere also has a refracted
//! child (docs/scenes.md, "Refraction"): the level's pending bit keeps it
//! until the reflected subtree has been added into the hit ray's colour,
//! then it takes the same level (`Program::refract`); without a reflected
//! child it is pushed at once. The tree is walked depth first, post order.

use super::core::{Core, Written};
use super::isa::{self, Lanes, PlaneField, Reg, SphereField, State};
use super::loader::{Config, MaterialBits};
use crate::scene::{Object, Vec3f, MAX_DEPTH};
use crate::trace::TraceEvent;
use std::panic::Location;

/// The temporaries' roles. Registers are shared between roles whose
/// lifetimes never overlap (thesis 3.12: "limit the duration a value must be
/// accessible").
mod t {
    use super::Reg;
    /// Primary ray: camera-space direction. Shading: the hit point when no
    /// child ray is pushed (else it goes straight to CUR_O).
    pub const P: Reg = Reg::T0;
    /// Rotation: cos products. Shading: the sphere normal.
    pub const N: Reg = Reg::T1;
    /// Rotation: sin products. Shading: light - p, then the reflected
    /// direction when no child is pushed (else it goes to CUR_D).
    pub const R: Reg = Reg::T2;
    /// The unit vector towards the light (the shadow ray's direction).
    pub const L: Reg = Reg::T3;
    /// Normalize: v.v, then |v| (for the light vector: its distance).
    pub const LEN: Reg = Reg::T4;
    /// Normalize: 1/|v|.
    pub const INV: Reg = Reg::T5;
    /// -t of the nearest hit so far.
    pub const BEST: Reg = Reg::T6;
    /// Scratch of the tests and of shading.
    pub const V: Reg = Reg::T7;
    pub const G: Reg = Reg::T8;
    pub const S: Reg = Reg::T9;
    pub const Q: Reg = Reg::T10;
    pub const U: Reg = Reg::T11;
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
    o: Reg,
    d: Reg,
    col: Reg,
    w: Reg,
    /// The level whose colour `col` is.
    level: usize,
    /// The hit point and reflected direction: the child's CUR_O and CUR_D
    /// when it is pushed, else temporaries.
    p: Reg,
    r: Reg,
}

/// One pixel's run of the controller.
pub struct Program<'c, T> {
    pub core: Core<T>,
    cfg: &'c Config,
    dir: DirFlags,
    /// Whether each level's colour register has been written this pixel
    /// (an unwritten colour is black, and adding it is skipped).
    coloured: [bool; MAX_DEPTH as usize],
    /// Per level: the transparent sphere whose refracted child the ray at
    /// that level still owes, once its reflected child's subtree is done.
    pending: [Option<usize>; MAX_DEPTH as usize],
}

impl<'c, T: FnMut(&TraceEvent, &'static Location<'static>)> Program<'c, T> {
    pub fn new(core: Core<T>, cfg: &'c Config) -> Program<'c, T> {
        Program {
            core,
            cfg,
            dir: DirFlags::default(),
            coloured: [false; MAX_DEPTH as usize],
            pending: [None; MAX_DEPTH as usize],
        }
    }

    /// Runs the pixel (the cycles before PIX_DONE) and
    /// returns the colour in STK0_COL.
    pub fn run(&mut self) -> [u32; 3] {
        self.primary_ray();
        self.trace_primary()
    }

    /// [`Program::run`] with the primary direction replaced by
    /// `nudge(direction)` once it is computed (the perturbation study: a
    /// model-only path, not an RTL one; the replacement costs no cycle).
    pub fn run_nudged(&mut self, nudge: impl FnOnce(Vec3f) -> Vec3f) -> [u32; 3] {
        self.primary_ray();
        let d = self
            .core
            .peek(isa::stack(0, isa::RayField::D))
            .expect("the primary direction is written");
        let w = self.core.poke(Reg::CUR_D, nudge(rgb_of(d)));
        self.dir = DirFlags::of(&w);
        self.trace_primary()
    }

    /// The rest of the pixel after the primary ray: the nearest hits, the
    /// shading, the unwinding; returns STK0_COL.
    fn trace_primary(&mut self) -> [u32; 3] {
        let mut from = None;
        loop {
            while let Some(obj) = self.nearest_hit(Reg::CUR_O, Reg::CUR_D, from) {
                let room = self.core.sp + 1 < self.cfg.max_depth;
                let reflect = self.bits(obj).reflective && room && !self.cut(obj);
                let refract = match obj {
                    Object::Sphere(k) if self.cfg.transparent[k] && room => {
                        (!self.cut_refracted(k)).then_some(k)
                    }
                    _ => None,
                };
                let push = reflect || refract.is_some();
                if push {
                    self.core.sp += 1;
                    // The level may have held a ray of an earlier subtree
                    // (a reflected child's, before its sibling refracted
                    // one): its colour is not this child's.
                    self.coloured[self.core.sp] = false;
                }
                self.shade(obj, push, reflect);
                if !push {
                    break;
                }
                if reflect {
                    self.pending[self.core.sp - 1] = refract;
                } else if let Some(k) = refract {
                    self.refract(k);
                }
                from = Some(obj);
            }
            match self.unwind() {
                // The refracted child owed at this level, now current.
                Some(k) => from = Some(Object::Sphere(k)),
                None => break,
            }
        }
        self.expose();
        self.core
            .peek(isa::stack(0, isa::RayField::Col))
            .expect("the root colour is written before PIX_DONE")
    }

    /// The weight cutoff (thesis 3.8, end), with the configuration's bit
    /// set: whether the child of a reflective hit on `obj` is refused, its
    /// weight w * kr (the f32 product SH_CHILD_W would write; every lane of
    /// a weight is the same) strictly below the cutoff c. u - c < 0 iff
    /// u < c exactly: an IEEE difference of finite numbers is 0 only for
    /// equal ones and has the sign of the exact difference.
    fn cut(&mut self, obj: Object) -> bool {
        if !self.cfg.cutoff {
            return false;
        }
        let (mat, c) = match obj {
            Object::Sphere(k) => (
                isa::sphere(k, SphereField::Mat),
                isa::sphere(k, SphereField::R),
            ),
            Object::Plane(j) => (isa::plane(j, PlaneField::Mat), isa::plane(j, PlaneField::Q)),
        };
        let core = &mut self.core;
        core.mulz(State::CUT_W, t::U, Reg::CUR_W, mat, Lanes::Z);
        core.sub(State::CUT_CMP, t::G, t::U, c, Lanes::Z).neg(2)
    }

    /// [`Program::cut`] for the refracted child of a hit on transparent
    /// sphere `k`: its weight w * kt (RF_CHILD_W's product) against the
    /// cutoff.
    fn cut_refracted(&mut self, k: usize) -> bool {
        if !self.cfg.cutoff {
            return false;
        }
        let core = &mut self.core;
        core.mulz(State::RF_CUT_W, t::U, Reg::CUR_W, isa::trn(k), Lanes::Z);
        core.sub(
            State::RF_CUT_CMP,
            t::G,
            t::U,
            isa::sphere(k, SphereField::R),
            Lanes::Z,
        )
        .neg(2)
    }

    /// The exposure function (thesis 3.7), with the configuration's bit
    /// set: STK0_COL = 1 - e^(exposure * STK0_COL) in every lane, after the
    /// unwinding (sp = 0, so CUR_COL is STK0_COL). The exposure is lane x
    /// of ROT0_S (isa.vh).
    fn expose(&mut self) {
        if !self.cfg.exposure {
            return;
        }
        let (_, exposure) = isa::rot(0);
        let c = &mut self.core;
        c.mulx(State::EXPO_MUL, t::U, Reg::CUR_COL, exposure, Lanes::XYZ);
        c.exp(State::EXPO_EXP, t::U, t::U, Lanes::XYZ);
        c.sub(State::EXPO_SUB, Reg::CUR_COL, Reg::ONE, t::U, Lanes::XYZ);
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
    fn dot(&mut self, y: Reg, a: Reg, b: Reg) -> Written {
        self.core.dot1(State::DOT_1, a, b);
        self.core.dot2(State::DOT_2);
        self.core.dot3(State::DOT_3, y)
    }

    /// y = v / |v|, leaving |v| in LEN.x, and latches y's direction flags
    /// (dot + ROOTS + 2 cycles).
    #[track_caller]
    fn normalize(&mut self, y: Reg, v: Reg) -> Written {
        self.dot(t::LEN, v, v);
        // |v| and 1/(v.v) at once, then 1/|v| = |v| * 1/(v.v): the square
        // root and the reciprocal overlap instead of following each other.
        self.core.roots(State::NORM_ROOTS, t::LEN, t::LEN);
        self.core
            .mulr1(State::NORM_INV, t::INV, t::LEN, t::LEN, Lanes::X);
        let w = self.core.mulx(State::NORM_SCALE, y, v, t::INV, Lanes::XYZ);
        self.dir = DirFlags::of(&w);
        w
    }

    /// S = <a.x - b.c, c.d, 0> with g in G (4 cycles; see `alu`).
    #[track_caller]
    fn isect(&mut self, b: Reg, c: Reg, d: Reg, a: Reg) -> Written {
        self.core.isect1(State::ISECT_1, b, c);
        self.core.isect2(State::ISECT_2, t::G, d, c);
        self.core.isect3(State::ISECT_3, t::G);
        self.core.isect4(State::ISECT_4, t::S, a)
    }

    // -----------------------------------------------------------------------
    // The primary ray (thesis 3.5)
    // -----------------------------------------------------------------------

    fn primary_ray(&mut self) {
        let c = &mut self.core;
        c.itof(State::PRI_ITOF, t::P);
        // <px - w/2, h/2 - py, distance>: exact (integers and halves).
        c.add(State::PRI_HALF, t::P, t::P, Reg::CAM_HALF, Lanes::XYZ);
        // About x, then y, then z: with (u, v) the two lanes that turn,
        // u' = u c - v s and v' = u s + v c.
        for a in 0..3 {
            if !self.cfg.rotate[a] {
                continue;
            }
            let (u, v) = (Lanes::lane((a + 1) % 3), Lanes::lane((a + 2) % 3));
            let (rc, rs) = isa::rot(a);
            let c = &mut self.core;
            c.mul(State::ROT_COS, t::N, t::P, rc, Lanes::XYZ);
            c.mulr1(State::ROT_SIN_U, t::R, rs, t::P, u); // -s * v
            c.mulr2(State::ROT_SIN_V, t::R, rs, t::P, v); // s * u
            c.add(State::ROT_ADD, t::P, t::N, t::R, u | v);
        }
        // CUR_O and CUR_W at level 0 are EYE and ONE (isa::decode).
        self.normalize(Reg::CUR_D, t::P);
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
    fn sphere_u(&mut self, k: usize, o: Reg, d: Reg, dst: Reg) -> Option<Written> {
        self.core.sub(
            State::SPH_V,
            t::V,
            o,
            isa::sphere(k, SphereField::C),
            Lanes::XYZ,
        );
        // Q.x = b. With b >= 0 (or NaN) u = sqrt(disc) + b below is never
        // < 0 (a rounded sum of non-negative numbers), so the near root is
        // not ahead of the ray whatever disc is: the test ends here, and
        // exactly the same hits are found.
        if !self.dot(t::Q, t::V, d).neg(0) {
            return None;
        }
        let c = &mut self.core;
        c.nmulx(State::SPH_BD, t::U, d, t::Q, Lanes::XYZ); // -b d
        c.add(State::SPH_W, t::V, t::V, t::U, Lanes::XYZ); // w = v - b d

        // The shared sub-graph with b = c = w, a = r*r: S.x = disc = r*r - w.w
        // (S.y = w.d, about 0, unused).
        if self
            .isect(t::V, t::V, d, isa::sphere(k, SphereField::R))
            .neg(0)
        {
            return None;
        }
        let c = &mut self.core;
        c.sqrt(State::SPH_SQRT, t::S, t::S);
        Some(c.add(State::SPH_T, dst, t::S, t::Q, Lanes::X)) // sqrt(disc) + b = -t
    }

    /// After `isect` left <q - n.o, n.d, 0> in S: u = -t = -(q - n.o)/(n.d)
    /// into `dst.x`.
    fn plane_u(&mut self, dst: Reg) -> Written {
        self.core.recipy(State::PLN_RECIP, t::Q, t::S);
        self.core.nmulx(State::PLN_T, dst, t::S, t::Q, Lanes::X)
    }

    /// Plane j against the ray (o, d) up to its t: `Some(u)` with u = -t in
    /// `dst.x` and whether t > 0 holds, or `None` if the plane faces away.
    /// With fast_plane (thesis 3.10.2) the facing decision is the latched
    /// sign of one direction lane (no instruction), and t > 0 is assumed
    /// (the scene's precondition); without it, the sub-graph's n.d < 0 and
    /// the sign of u decide. n.d of an axis normal is exactly +-d[axis], so
    /// both decide facing alike, and t comes from the same instructions.
    fn plane_u_checked(&mut self, j: usize, o: Reg, d: Reg, dst: Reg) -> Option<(Written, bool)> {
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
    fn box_hit(&mut self, o: Reg, d: Reg) -> bool {
        let s = self.dir.sign as usize;
        let c = &mut self.core;
        // The far corner first: a box behind the ray is refused after two
        // instructions instead of three.
        c.sub(State::BOX_FAR, t::G, isa::corner(s ^ 7), o, Lanes::XYZ);
        let behind = c.mul(State::BOX_BEHIND, t::S, t::G, d, Lanes::XYZ);
        if (0..3).any(|i| behind.neg(i)) {
            return false;
        }
        c.sub(State::BOX_NEAR, t::V, isa::corner(s), o, Lanes::XYZ);
        c.mulr1(State::BOX_P1, t::Q, t::V, d, Lanes::XYZ); // N_i d_(i+1)
        c.mulr1(State::BOX_Q1, t::U, d, t::G, Lanes::XYZ); // d_i F_(i+1)
        let d1 = c.sub(State::BOX_D1, t::Q, t::Q, t::U, Lanes::XYZ);
        if self.separated(&d1, 1) {
            return false;
        }
        let c = &mut self.core;
        c.mulr2(State::BOX_P2, t::Q, t::V, d, Lanes::XYZ); // N_i d_(i+2)
        c.mulr2(State::BOX_Q2, t::U, d, t::G, Lanes::XYZ); // d_i F_(i+2)
        let d2 = c.sub(State::BOX_D2, t::Q, t::Q, t::U, Lanes::XYZ);
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
    fn nearest_hit(&mut self, o: Reg, d: Reg, from: Option<Object>) -> Option<Object> {
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
        if self
            .core
            .sub(State::HIT_CMP, t::G, t::U, t::BEST, Lanes::X)
            .pos(0)
        {
            self.core.mov(State::HIT_KEEP, t::BEST, t::U, Lanes::X);
            *best = Some(obj);
        }
    }

    // -----------------------------------------------------------------------
    // The shadow ray (p, L), |light - p| in LEN.x
    // -----------------------------------------------------------------------

    /// Whether an object other than `on` blocks the light from p: a hit at
    /// 0 < t < |light - p|. With shadow_shortcut (thesis 3.10.3) only
    /// spheres are tested and any t > 0 blocks.
    fn shadowed(&mut self, p: Reg, on: Object) -> bool {
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
        self.core
            .add(State::SHD_DIST, t::G, t::U, t::LEN, Lanes::X)
            .pos(0)
    }

    // -----------------------------------------------------------------------
    // Shading (thesis 3.4)
    // -----------------------------------------------------------------------

    /// Shades the hit of the ray at level sp (or sp - 1 when `push`: the
    /// child's level is already current, and p and r are written straight
    /// into its origin and direction). Writes the ray's colour = w * local
    /// unless no light arrives, and, when the child is the reflected ray
    /// (`reflect`), its weight.
    fn shade(&mut self, obj: Object, push: bool, reflect: bool) {
        let sp = self.core.sp;
        let ray = if push {
            Shading {
                o: Reg::PAR_O,
                d: Reg::PAR_D,
                col: Reg::PAR_COL,
                w: Reg::PAR_W,
                level: sp - 1,
                p: Reg::CUR_O,
                r: Reg::CUR_D,
            }
        } else {
            Shading {
                o: Reg::CUR_O,
                d: Reg::CUR_D,
                col: Reg::CUR_COL,
                w: Reg::CUR_W,
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
        c.nmulx(State::SH_OFFSET, t::V, ray.d, t::BEST, Lanes::XYZ);
        c.add(State::SH_POINT, ray.p, ray.o, t::V, Lanes::XYZ);
        if let Object::Sphere(k) = obj {
            // n = (p - c) * 1/r (thesis eq. 28).
            c.sub(
                State::SH_NORMAL_SUB,
                t::N,
                ray.p,
                isa::sphere(k, SphereField::C),
                Lanes::XYZ,
            );
            c.muly(
                State::SH_NORMAL_SCALE,
                t::N,
                t::N,
                isa::sphere(k, SphereField::R),
                Lanes::XYZ,
            );
        }
        self.core
            .sub(State::SH_LIGHT_VEC, t::R, Reg::LIGHT_POS, ray.p, Lanes::XYZ);
        self.normalize(t::L, t::R);
        let lit = !self.shadowed(ray.p, obj);

        // n.l, once for both terms: light reaches the surface only where
        // n.l > 0, so both the diffuse term and the highlight are gated on
        // it. (Thesis eq. 11 gates neither explicitly; an object is never
        // tested against itself for shadow, so without the gate the dark
        // side of a sphere that sees the light past its own edge got a
        // highlight.)
        let faces_light = lit && (bits.diffuse || bits.specular) && self.dot(t::V, n, t::L).pos(0);

        // Diffuse: kd * max(n.l, 0) * (C * Lc); a zero term is skipped.
        let mut diffuse = None;
        if faces_light && bits.diffuse {
            let c = &mut self.core;
            c.mulx(State::SH_KD, t::G, mat, t::V, Lanes::X);
            c.mul(State::SH_CL, t::S, colour, Reg::LIGHT_COL, Lanes::XYZ);
            c.mulx(State::SH_DIFFUSE, t::S, t::S, t::G, Lanes::XYZ);
            diffuse = Some(t::S);
        }

        // r = d - 2 (d.n) n, after the shadow test so that its direction
        // flags are the last latched before the child's search.
        if reflect || (faces_light && bits.specular) {
            self.dot(t::Q, ray.d, n);
            let c = &mut self.core;
            c.mul2x(State::SH_REFL_K, t::U, n, t::Q, Lanes::XYZ); // k = 2 (d.n) n
            let r = c.sub(State::SH_REFL, ray.r, ray.d, t::U, Lanes::XYZ);
            self.dir = DirFlags::of(&r);
        }

        // Specular (the Phong form: thesis eq. 11 writes d.l, we use the
        // reflected ray r.l): ks * max(r.l, 0)^20 * Lc, where n.l > 0.
        let mut specular = None;
        if faces_light && bits.specular && self.dot(t::Q, ray.r, t::L).pos(0) {
            let c = &mut self.core;
            c.mul(State::SH_POW2, t::U, t::Q, t::Q, Lanes::X);
            c.mul(State::SH_POW4, t::U, t::U, t::U, Lanes::X);
            c.mul(State::SH_POW5, t::U, t::U, t::Q, Lanes::X);
            c.mul(State::SH_POW10, t::U, t::U, t::U, Lanes::X);
            c.mul(State::SH_POW20, t::U, t::U, t::U, Lanes::X);
            c.mulx(State::SH_KS, t::V, mat, t::U, Lanes::Y); // V.y = ks * x^20
            c.muly(State::SH_SPEC, t::G, Reg::LIGHT_COL, t::V, Lanes::XYZ);
            specular = Some(t::G);
        }

        let local = match (diffuse, specular) {
            (Some(a), Some(b)) => {
                self.core.add(State::SH_LOCAL, t::S, a, b, Lanes::XYZ);
                Some(t::S)
            }
            (a, b) => a.or(b),
        };
        if let Some(local) = local {
            self.core
                .mul(State::SH_COLOUR, ray.col, local, ray.w, Lanes::XYZ);
            self.coloured[ray.level] = true;
        }
        if reflect {
            self.core
                .mulz(State::SH_CHILD_W, Reg::CUR_W, Reg::PAR_W, mat, Lanes::XYZ);
        }
    }

    // -----------------------------------------------------------------------
    // Refraction (docs/scenes.md, "Refraction")
    // -----------------------------------------------------------------------

    /// The refracted child of a hit on transparent sphere `k`, into the
    /// current level (the hit ray's is sp - 1): p is in CUR_O (SH_POINT
    /// wrote it there), d in PAR_D; TRNk = <eta = 1/ior, ior, kt>. Writes
    /// the child's origin (the exit point), direction and weight, and
    /// clears its colour. Snell's law into the sphere, the far root of the
    /// sphere test from p, Snell's law out; total internal reflection at
    /// the entry gives the mirror ray from p; k' < 0 at the exit (rounding
    /// only) is taken as 0, and so is a negative discriminant of the chord.
    fn refract(&mut self, k: usize) {
        let (c, r, trn) = (
            isa::sphere(k, SphereField::C),
            isa::sphere(k, SphereField::R),
            isa::trn(k),
        );
        self.coloured[self.core.sp] = false;
        let co = &mut self.core;
        co.sub(State::RF_NSUB, t::N, Reg::CUR_O, c, Lanes::XYZ);
        co.muly(State::RF_NSCALE, t::N, t::N, r, Lanes::XYZ);
        self.dot(t::Q, Reg::PAR_D, t::N); // Q.x = d.n = -cos
        let co = &mut self.core;
        co.mul(State::RF_COS2, t::U, t::Q, t::Q, Lanes::X);
        co.sub(State::RF_SIN2, t::U, Reg::ONE, t::U, Lanes::X);
        co.mulx(State::RF_ETA1, t::U, t::U, trn, Lanes::X);
        co.mulx(State::RF_ETA2, t::U, t::U, trn, Lanes::X);
        if co.sub(State::RF_K, t::U, Reg::ONE, t::U, Lanes::X).neg(0) {
            // The mirror ray, as SH_REFL_K and SH_REFL compute it.
            co.mul2x(State::RF_TIR_K, t::U, t::N, t::Q, Lanes::XYZ);
            let w = co.sub(State::RF_TIR, Reg::CUR_D, Reg::PAR_D, t::U, Lanes::XYZ);
            self.dir = DirFlags::of(&w);
        } else {
            co.sqrt(State::RF_SQRT, t::U, t::U);
            co.mulx(State::RF_EDN, t::G, t::Q, trn, Lanes::X);
            co.add(State::RF_COEF, t::G, t::G, t::U, Lanes::X);
            co.mulx(State::RF_ED, t::V, Reg::PAR_D, trn, Lanes::XYZ);
            co.mulx(State::RF_CN, t::S, t::N, t::G, Lanes::XYZ);
            co.sub(State::RF_DIR, t::R, t::V, t::S, Lanes::XYZ); // t, inside
            co.sub(State::RF_CV, t::V, Reg::CUR_O, c, Lanes::XYZ);
            self.dot(t::Q, t::V, t::R); // Q.x = b
            let co = &mut self.core;
            co.nmulx(State::RF_CBD, t::U, t::R, t::Q, Lanes::XYZ);
            co.add(State::RF_CW, t::V, t::V, t::U, Lanes::XYZ);
            let disc_neg = self.isect(t::V, t::V, t::R, r).neg(0);
            let co = &mut self.core;
            let root = if disc_neg {
                Reg::ZERO
            } else {
                co.sqrt(State::RF_CSQRT, t::S, t::S);
                t::S
            };
            co.sub(State::RF_CS, t::S, root, t::Q, Lanes::X); // s = sqrt(disc) - b
            co.mulx(State::RF_CST, t::U, t::R, t::S, Lanes::XYZ);
            co.add(State::RF_EXIT, Reg::CUR_O, Reg::CUR_O, t::U, Lanes::XYZ);
            co.sub(State::RF_OSUB, t::N, Reg::CUR_O, c, Lanes::XYZ);
            co.muly(State::RF_OSCALE, t::N, t::N, r, Lanes::XYZ);
            self.dot(t::Q, t::R, t::N); // Q.x = t.n' = cos
            let co = &mut self.core;
            co.mul(State::RF_OCOS2, t::U, t::Q, t::Q, Lanes::X);
            co.sub(State::RF_OSIN2, t::U, Reg::ONE, t::U, Lanes::X);
            co.muly(State::RF_OIOR1, t::U, t::U, trn, Lanes::X);
            co.muly(State::RF_OIOR2, t::U, t::U, trn, Lanes::X);
            let k_neg = co.sub(State::RF_OK, t::U, Reg::ONE, t::U, Lanes::X).neg(0);
            co.muly(State::RF_OEDN, t::G, t::Q, trn, Lanes::X); // ior cos
            if !k_neg {
                co.sqrt(State::RF_OSQRT, t::U, t::U);
                co.sub(State::RF_OCOEF, t::G, t::G, t::U, Lanes::X);
            }
            co.muly(State::RF_OED, t::V, t::R, trn, Lanes::XYZ);
            co.mulx(State::RF_OCN, t::S, t::N, t::G, Lanes::XYZ);
            let w = co.sub(State::RF_ODIR, Reg::CUR_D, t::V, t::S, Lanes::XYZ);
            self.dir = DirFlags::of(&w);
        }
        self.core
            .mulz(State::RF_CHILD_W, Reg::CUR_W, Reg::PAR_W, trn, Lanes::XYZ);
    }

    // -----------------------------------------------------------------------
    // Unwinding (thesis 3.6: "this ray's color is added to its parent's")
    // -----------------------------------------------------------------------

    /// Adds the colours of the finished rays into their parents', level by
    /// level, until a level owes a refracted child: that child is made
    /// current at the level just added ([`Program::refract`]) and its
    /// sphere returned. `None` when the root is reached.
    fn unwind(&mut self) -> Option<usize> {
        while self.core.sp > 0 {
            let sp = self.core.sp;
            if self.coloured[sp] {
                if self.coloured[sp - 1] {
                    self.core.add(
                        State::POP_ADD,
                        Reg::PAR_COL,
                        Reg::PAR_COL,
                        Reg::CUR_COL,
                        Lanes::XYZ,
                    );
                } else {
                    self.core
                        .mov(State::POP_MOV, Reg::PAR_COL, Reg::CUR_COL, Lanes::XYZ);
                    self.coloured[sp - 1] = true;
                }
            }
            if let Some(k) = self.pending[sp - 1].take() {
                self.refract(k);
                return Some(k);
            }
            self.core.sp -= 1;
        }
        if !self.coloured[0] {
            self.core
                .mov(State::ROOT_BLACK, Reg::CUR_COL, Reg::ZERO, Lanes::XYZ);
        }
        None
    }
}

/// The colour as f32 lanes.
pub fn rgb_of(bits: [u32; 3]) -> Vec3f {
    bits.map(f32::from_bits)
}
