//! The pixel processor core as the controller sees it: the register file
//! with its memory controller (thesis 4.4, 4.5), the ALU controller's
//! opcode decoding (4.3), and the [`Alu`] (4.2) it feeds.
//!
//! Each public method is one instruction, issued from the FSM state passed
//! as its first argument: it reads its operands, has the ALU compute,
//! writes its destination lanes (or the ALU writes F), counts its cycles,
//! and reports the register-file write as a [`TraceEvent`] together with
//! the Rust source line that issued it (`#[track_caller]`).
//! Writes to F are internal to the ALU: they are not register-file writes
//! and emit no event (the RTL's trace port watches the memory's write port).
//!
//! The model refuses (panics on) anything the RTL could not do or should not
//! do: reading a register lane that was neither loaded with the scene nor
//! written earlier in this pixel, writing a scene register, a `PAR_*`
//! address at stack level 0, and lane masks an instruction does not have.

use super::alu::Alu;
use super::fault::Fault;
use super::isa::{self, op, Lanes, Reg, State, REGISTER_COUNT};
use super::stats::{OpClass, OpStats};
use crate::fp::Method;
use crate::scene::Vec3f;
use crate::trace::TraceEvent;
use std::panic::Location;

/// The value an instruction wrote, for the controller's branch flags
/// (thesis 4.2: "combinational float-to-boolean" on the written value).
/// Reading a lane the instruction did not write is a bug in the program and
/// panics.
#[derive(Debug, Clone, Copy)]
pub struct Written {
    value: Vec3f,
    mask: Lanes,
}

impl Written {
    #[inline(always)]
    fn lane(&self, i: usize) -> f32 {
        if !self.mask.has(i) {
            unwritten_flag(i, self.mask);
        }
        self.value[i]
    }

    /// Sign flag and not zero and not NaN: the lane is < 0.
    #[inline(always)]
    pub fn neg(&self, i: usize) -> bool {
        self.lane(i) < 0.0
    }

    /// Not sign, not zero, not NaN: the lane is > 0.
    #[inline(always)]
    pub fn pos(&self, i: usize) -> bool {
        self.lane(i) > 0.0
    }

    /// The sign bit of every lane, bit i = lane i (all three written).
    #[inline(always)]
    pub fn sign_bits(&self) -> u8 {
        if self.mask != Lanes::XYZ {
            partly_written_signs(self.mask);
        }
        let sign = |i: usize| u8::from(self.value[i].is_sign_negative()) << i;
        sign(0) | sign(1) | sign(2)
    }

    /// The written lanes, for tests and diagnostics.
    pub fn value(&self) -> Vec3f {
        self.value
    }
}

/// The register file contents a scene loads (see `micro::loader`), and which
/// lanes of each address it holds.
#[derive(Debug, Clone)]
pub struct RegisterImage {
    pub bits: [[u32; 3]; REGISTER_COUNT],
    pub valid: [Lanes; REGISTER_COUNT],
}

/// The register file as the core holds it: lane by lane (`lanes[i][a]` is
/// lane i of address a), and the mask of lanes each address holds. Kept apart,
/// the lanes of one register never share a memory word: every lane's read is
/// a 4-byte load of what one 4-byte store wrote, so an instruction's operand
/// is forwarded straight from the previous instruction's write instead of
/// stalling on a load that spans a partly written register.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct LoadedImage {
    lanes: [[u32; REGISTER_COUNT]; 3],
    valid: [Lanes; REGISTER_COUNT],
}

impl LoadedImage {
    pub(crate) fn new(image: &RegisterImage) -> LoadedImage {
        let mut lanes = [[0; REGISTER_COUNT]; 3];
        for (a, bits) in image.bits.iter().enumerate() {
            for (lane, &b) in lanes.iter_mut().zip(bits) {
                lane[a] = b;
            }
        }
        LoadedImage {
            lanes,
            valid: image.valid,
        }
    }
}

/// The core executing one pixel's program.
pub struct Core<T> {
    regs: LoadedImage,
    alu: Alu,
    /// The stack pointer: the level `CUR_*` addresses.
    pub sp: usize,
    px: u32,
    py: u32,
    seq: u32,
    /// Instructions and cycles so far.
    pub stats: OpStats,
    /// The injected fault: the state whose writes are hit (`u16::MAX`, no
    /// state, when none) and the XOR on lane x.
    fault_state: u16,
    fault_xor: u32,
    /// Each instruction's state and cycles, in issue order, when asked
    /// for ([`Core::record_steps`]): the controller's path through its
    /// states ([`super::cover`]).
    steps: Option<Vec<Step>>,
    trace: T,
}

/// One issued instruction: the state it issued from and the cycles it took
/// (more than 1: the controller stays in that state until out_valid), and
/// how near its lane x came to a sign test's threshold ([`Step::near`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    pub state: State,
    pub cycles: u32,
    /// For a sum (ADD, SUB, ISECT4's lane x): how many bits of its larger
    /// addend cancelled, in [`NEAR_BITS`] steps (0: fewer than
    /// `NEAR_BITS`, up to [`NEAR_LEVELS`]; an exact 0 is the last level).
    /// The controller branches on the sign of such sums (a discriminant, a
    /// distance, a cosine), so a sum that nearly cancels is a step towards
    /// the branch's other side; for any other instruction 0.
    pub near: u8,
}

/// The cancelled bits of one level of [`Step::near`].
pub const NEAR_BITS: i32 = 8;
/// The levels of [`Step::near`]: 8, 16 and 24 bits or more (or 0 exactly).
pub const NEAR_LEVELS: u8 = 3;

/// [`Step::near`] of the sum `y` of addends `p` and `q`: 0 unless all three
/// are finite and the sum is at least [`NEAR_BITS`] binades below the
/// larger addend.
pub fn near(p: f32, q: f32, y: f32) -> u8 {
    let big = p.abs().max(q.abs());
    if !(p.is_finite() && q.is_finite() && y.is_finite()) || big == 0.0 {
        return 0;
    }
    if y == 0.0 {
        return NEAR_LEVELS;
    }
    // Binades as the exponents count them (subnormals too): exact in f64.
    let binade = |v: f32| f64::from(v.abs()).log2().floor() as i32;
    let cancelled = binade(big) - binade(y);
    (cancelled / NEAR_BITS).clamp(0, i32::from(NEAR_LEVELS)) as u8
}

/// Whether register address `a` belongs to the scene (read-only).
#[inline(always)]
fn is_scene(a: Reg) -> bool {
    a < Reg::T0
}

impl<T: FnMut(&TraceEvent, &'static Location<'static>)> Core<T> {
    /// A core for pixel (px, py), with the scene's registers loaded, the
    /// temporaries and the stack empty, sp = 0.
    pub fn new(
        image: &RegisterImage,
        px: u32,
        py: u32,
        recip: Method,
        sqrt: Method,
        trace: T,
    ) -> Core<T> {
        Core::loaded(&LoadedImage::new(image), px, py, recip, sqrt, None, trace)
    }

    /// [`Core::new`] from an image already in the core's layout.
    #[inline(always)]
    pub(crate) fn loaded(
        image: &LoadedImage,
        px: u32,
        py: u32,
        recip: Method,
        sqrt: Method,
        fault: Option<Fault>,
        trace: T,
    ) -> Core<T> {
        let (fault_state, fault_xor) = fault.map_or((u16::MAX, 0), |f| (f.state, f.xor));
        Core {
            regs: image.clone(),
            alu: Alu::new(recip, sqrt),
            sp: 0,
            px,
            py,
            seq: 0,
            stats: OpStats::default(),
            fault_state,
            fault_xor,
            steps: None,
            trace,
        }
    }

    /// From now on, record each instruction's [`Step`] (see
    /// [`Core::take_steps`]).
    pub(crate) fn record_steps(&mut self) {
        self.steps = Some(Vec::with_capacity(256));
    }

    /// The steps recorded since [`Core::record_steps`] (empty if it was
    /// not called).
    pub(crate) fn take_steps(&mut self) -> Vec<Step> {
        self.steps.take().unwrap_or_default()
    }

    /// The physical register `code` decodes to at the current sp.
    #[inline(always)]
    fn decode(&self, code: Reg, at: &Location<'_>) -> Reg {
        match isa::decode(code, self.sp) {
            Some(a) => a,
            None => outside_the_stack(code, self.sp, at),
        }
    }

    #[inline(always)]
    fn read(&self, code: Reg, need: Lanes, at: &Location<'_>) -> Vec3f {
        let a = self.decode(code, at);
        let valid = self.regs.valid[a.0 as usize];
        if !valid.contains(need) {
            unwritten_read(code, a, need, valid, at);
        }
        let lane = |i: usize| f32::from_bits(self.regs.lanes[i][a.0 as usize]);
        [lane(0), lane(1), lane(2)]
    }

    /// The bits of physical register `a` as they are now (for the result).
    pub fn peek(&self, a: Reg) -> Option<[u32; 3]> {
        let a = a.0 as usize;
        let lane = |i: usize| self.regs.lanes[i][a];
        (self.regs.valid[a] == Lanes::XYZ).then(|| [lane(0), lane(1), lane(2)])
    }

    /// Overwrites all lanes of register `code` with `v`, outside the
    /// program: no cycle, no trace event (the perturbation study's hook,
    /// [`Processor::render_pixel_nudged`](super::Processor::render_pixel_nudged);
    /// the RTL has no such path). Returns the value as the controller's
    /// branches would see it.
    pub(crate) fn poke(&mut self, code: Reg, v: Vec3f) -> Written {
        let a = self.decode(code, Location::caller());
        for (i, x) in v.iter().enumerate() {
            self.regs.lanes[i][a.0 as usize] = x.to_bits();
        }
        self.regs.valid[a.0 as usize] = Lanes::XYZ;
        Written {
            value: v,
            mask: Lanes::XYZ,
        }
    }

    /// The end of every instruction that writes the register file: count
    /// its cycles, write lanes `mask` of `y` to `dst` (emitting the event),
    /// and hand the written value to the controller's branches.
    #[inline(always)]
    fn retire(
        &mut self,
        state: State,
        code: u8,
        dst: Reg,
        mask: Lanes,
        y: Vec3f,
        at: &'static Location<'static>,
    ) -> Written {
        self.count(state, code);
        self.write(state, dst, mask, y, at);
        Written { value: y, mask }
    }

    #[inline(always)]
    fn write(
        &mut self,
        state: State,
        code: Reg,
        mask: Lanes,
        y: Vec3f,
        at: &'static Location<'static>,
    ) {
        let a = self.decode(code, at);
        if is_scene(a) {
            scene_write(a, at);
        }
        if mask == Lanes::NONE || mask.0 > Lanes::XYZ.0 {
            bad_mask(mask, at);
        }
        let mut values = [0u32; 3];
        let xor = if state.0 == self.fault_state {
            self.fault_xor
        } else {
            0
        };
        for (i, value) in values.iter_mut().enumerate() {
            if mask.has(i) {
                *value = y[i].to_bits() ^ if i == 0 { xor } else { 0 };
                self.regs.lanes[i][a.0 as usize] = *value;
            }
        }
        self.regs.valid[a.0 as usize] |= mask;
        self.stats.register_writes += 1;
        let event = TraceEvent {
            x: self.px as u16,
            y: self.py as u16,
            seq: self.seq,
            state: state.0,
            dst: a.0,
            lanes: mask.0,
            values,
        };
        self.seq += 1;
        (self.trace)(&event, at);
    }

    #[inline(always)]
    fn count(&mut self, state: State, code: u8) {
        let class = OpClass::of(code).expect("every issued opcode has a class");
        let cycles = self.alu.cycles(code);
        self.stats.record(class, cycles);
        if let Some(steps) = &mut self.steps {
            steps.push(Step {
                state,
                cycles: cycles as u32,
                near: 0,
            });
        }
    }

    /// Lane-wise binary instructions: A, and B in the lanes the ALU routes
    /// to the written ones.
    #[inline(always)]
    fn lanewise(
        &mut self,
        state: State,
        code: u8,
        (dst, a, b, mask): (Reg, Reg, Reg, Lanes),
        at: &'static Location<'static>,
    ) -> Written {
        let route = Alu::route(code);
        let mut need_b = Lanes::NONE;
        for (i, &r) in route.iter().enumerate() {
            if mask.has(i) {
                need_b |= Lanes::lane(r);
            }
        }
        let av = self.read(a, mask, at);
        let bv = self.read(b, need_b, at);
        let y = Alu::lanewise(code, av, bv);
        let written = self.retire(state, code, dst, mask, y, at);
        if self.steps.is_some() && (code == op::ADD || code == op::SUB) && mask.has(0) {
            self.mark_near(near(av[0], bv[route[0]], y[0]));
        }
        written
    }

    /// Sets the last recorded step's [`Step::near`].
    #[inline(always)]
    fn mark_near(&mut self, level: u8) {
        if let Some(step) = self.steps.as_mut().and_then(|s| s.last_mut()) {
            step.near = level;
        }
    }

    // -----------------------------------------------------------------------
    // Single-cycle vector instructions
    // -----------------------------------------------------------------------

    /// ADD: Y = A + B.
    #[track_caller]
    #[inline(always)]
    pub fn add(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::ADD, (y, a, b, m), Location::caller())
    }

    /// SUB: Y = A - B.
    #[track_caller]
    #[inline(always)]
    pub fn sub(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::SUB, (y, a, b, m), Location::caller())
    }

    /// MUL: Y = A * B, componentwise.
    #[track_caller]
    #[inline(always)]
    pub fn mul(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::MUL, (y, a, b, m), Location::caller())
    }

    /// NMUL: Y = -(A * B).
    #[track_caller]
    #[inline(always)]
    pub fn nmul(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::NMUL, (y, a, b, m), Location::caller())
    }

    /// MULX: Y = A * <B.x, B.x, B.x>.
    #[track_caller]
    #[inline(always)]
    pub fn mulx(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::MULX, (y, a, b, m), Location::caller())
    }

    /// MULY: Y = A * <B.y, B.y, B.y>.
    #[track_caller]
    #[inline(always)]
    pub fn muly(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::MULY, (y, a, b, m), Location::caller())
    }

    /// MULZ: Y = A * <B.z, B.z, B.z>.
    #[track_caller]
    #[inline(always)]
    pub fn mulz(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::MULZ, (y, a, b, m), Location::caller())
    }

    /// NMULX: Y = -(A * <B.x, B.x, B.x>).
    #[track_caller]
    #[inline(always)]
    pub fn nmulx(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::NMULX, (y, a, b, m), Location::caller())
    }

    /// MULR1: Y = A * <B.y, B.z, B.x>.
    #[track_caller]
    #[inline(always)]
    pub fn mulr1(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::MULR1, (y, a, b, m), Location::caller())
    }

    /// MUL2X: Y = p + p with p = A * <B.x, B.x, B.x> (doubling is exact).
    #[track_caller]
    #[inline(always)]
    pub fn mul2x(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::MUL2X, (y, a, b, m), Location::caller())
    }

    /// MULR2: Y = A * <B.z, B.x, B.y>.
    #[track_caller]
    #[inline(always)]
    pub fn mulr2(&mut self, st: State, y: Reg, a: Reg, b: Reg, m: Lanes) -> Written {
        self.lanewise(st, op::MULR2, (y, a, b, m), Location::caller())
    }

    /// MOV: Y = A.
    #[track_caller]
    #[inline(always)]
    pub fn mov(&mut self, st: State, y: Reg, a: Reg, m: Lanes) -> Written {
        let at = Location::caller();
        let v = self.read(a, m, at);
        self.retire(st, op::MOV, y, m, v, at)
    }

    /// NEG: Y = -A (the sign bits flipped, exact).
    #[track_caller]
    #[inline(always)]
    pub fn neg(&mut self, st: State, y: Reg, a: Reg, m: Lanes) -> Written {
        let at = Location::caller();
        let v = Alu::neg(self.read(a, m, at));
        self.retire(st, op::NEG, y, m, v, at)
    }

    /// ITOF: Y = <itof(px), itof(-py), itof(0)>, from the controller's pixel
    /// coordinate registers (no register operand).
    #[track_caller]
    #[inline(always)]
    pub fn itof(&mut self, st: State, y: Reg) -> Written {
        let at = Location::caller();
        let v = Alu::itof(self.px, self.py);
        self.retire(st, op::ITOF, y, Lanes::XYZ, v, at)
    }

    // -----------------------------------------------------------------------
    // The dot product (thesis 4.7.1): three instructions through F
    // -----------------------------------------------------------------------

    /// DOT1: F = A * B.
    #[track_caller]
    #[inline(always)]
    pub fn dot1(&mut self, st: State, a: Reg, b: Reg) {
        let at = Location::caller();
        let (av, bv) = (self.read(a, Lanes::XYZ, at), self.read(b, Lanes::XYZ, at));
        self.alu.dot1(av, bv);
        self.count(st, op::DOT1);
    }

    /// DOT2: F.x = F.x + F.y.
    #[track_caller]
    #[inline(always)]
    pub fn dot2(&mut self, st: State) {
        self.alu.dot2(Location::caller());
        self.count(st, op::DOT2);
    }

    /// DOT3: Y.x = F.x + F.z, i.e. `(a.x*b.x + a.y*b.y) + a.z*b.z`.
    #[track_caller]
    #[inline(always)]
    pub fn dot3(&mut self, st: State, y: Reg) -> Written {
        let at = Location::caller();
        let v = self.alu.dot3(at);
        self.retire(st, op::DOT3, y, Lanes::X, v, at)
    }

    // -----------------------------------------------------------------------
    // The intersection sub-graph (thesis 4.7.1, eq. 29 and 30; see `alu`)
    // -----------------------------------------------------------------------

    /// ISECT1: F = -(A * B) [A = b, B = c].
    #[track_caller]
    #[inline(always)]
    pub fn isect1(&mut self, st: State, a: Reg, b: Reg) {
        let at = Location::caller();
        let (av, bv) = (self.read(a, Lanes::XYZ, at), self.read(b, Lanes::XYZ, at));
        self.alu.isect1(av, bv);
        self.count(st, op::ISECT1);
    }

    /// ISECT2: Y = A * B [A = d, B = c]; F = <F.x + F.y, F.y, F.z>.
    #[track_caller]
    #[inline(always)]
    pub fn isect2(&mut self, st: State, y: Reg, a: Reg, b: Reg) -> Written {
        let at = Location::caller();
        let (av, bv) = (self.read(a, Lanes::XYZ, at), self.read(b, Lanes::XYZ, at));
        let g = self.alu.isect2(av, bv, at);
        self.retire(st, op::ISECT2, y, Lanes::XYZ, g, at)
    }

    /// ISECT3: F = <A.x + A.y, F.x + F.z, A.z> [A = g].
    #[track_caller]
    #[inline(always)]
    pub fn isect3(&mut self, st: State, a: Reg) {
        let at = Location::caller();
        let g = self.read(a, Lanes::XYZ, at);
        self.alu.isect3(g, at);
        self.count(st, op::ISECT3);
    }

    /// ISECT4: Y = F = <A.x + F.y, F.x + F.z, 0> [A.x = a].
    #[track_caller]
    #[inline(always)]
    pub fn isect4(&mut self, st: State, y: Reg, a: Reg) -> Written {
        let at = Location::caller();
        let av = self.read(a, Lanes::X, at);
        let f_y = self.alu.f_lanes()[1];
        let v = self.alu.isect4(av[0], at);
        let written = self.retire(st, op::ISECT4, y, Lanes::XYZ, v, at);
        if self.steps.is_some() {
            self.mark_near(near(av[0], f_y, v[0]));
        }
        written
    }

    // -----------------------------------------------------------------------
    // Multi-cycle instructions: issued with in_valid, written when the unit
    // raises out_valid, latency + 1 cycles in all, lane x only
    // -----------------------------------------------------------------------

    /// RECIP: Y.x = 1 / A.x.
    #[track_caller]
    #[inline(always)]
    pub fn recip(&mut self, st: State, y: Reg, a: Reg) -> Written {
        self.unary(st, op::RECIP, y, a, 0, Location::caller())
    }

    /// RECIPY: Y.x = 1 / A.y.
    #[track_caller]
    #[inline(always)]
    pub fn recipy(&mut self, st: State, y: Reg, a: Reg) -> Written {
        self.unary(st, op::RECIPY, y, a, 1, Location::caller())
    }

    /// SQRT: Y.x = sqrt(A.x).
    #[track_caller]
    #[inline(always)]
    pub fn sqrt(&mut self, st: State, y: Reg, a: Reg) -> Written {
        self.unary(st, op::SQRT, y, a, 0, Location::caller())
    }

    /// ROOTS: Y.x = sqrt(A.x), Y.y = 1 / A.x, both units started in the
    /// same cycle; written together when the later one is done.
    #[track_caller]
    #[inline(always)]
    pub fn roots(&mut self, st: State, y: Reg, a: Reg) -> Written {
        let at = Location::caller();
        let v = self.alu.roots(self.read(a, Lanes::X, at)[0]);
        self.retire(st, op::ROOTS, y, Lanes::X | Lanes::Y, v, at)
    }

    /// EXP: Y = e^A in every lane of `m`, three fp_exp units started in the
    /// same cycle; written together when they are done (they finish
    /// together).
    #[track_caller]
    #[inline(always)]
    pub fn exp(&mut self, st: State, y: Reg, a: Reg, m: Lanes) -> Written {
        let at = Location::caller();
        let v = Alu::exp(self.read(a, m, at));
        self.retire(st, op::EXP, y, m, v, at)
    }

    #[inline(always)]
    fn unary(
        &mut self,
        st: State,
        code: u8,
        y: Reg,
        a: Reg,
        lane: usize,
        at: &'static Location<'static>,
    ) -> Written {
        let x = self.read(a, Lanes::lane(lane), at)[lane];
        let v = [self.alu.unary(code, x), 0.0, 0.0];
        self.retire(st, code, y, Lanes::X, v, at)
    }
}

// The refusals, out of line: the instructions are inlined into the
// controller, and their checks must cost a compare and a never-taken branch,
// not the formatting of a message.

#[cold]
#[inline(never)]
fn outside_the_stack(code: Reg, sp: usize, at: &Location<'_>) -> ! {
    panic!("{at}: {code} at stack level {sp} is outside the stack")
}

#[cold]
#[inline(never)]
fn unwritten_read(code: Reg, a: Reg, need: Lanes, valid: Lanes, at: &Location<'_>) -> ! {
    panic!(
        "{at}: reads lanes {need:03b} of {code} ({a}), but only {valid:03b} were loaded or written"
    )
}

#[cold]
#[inline(never)]
fn scene_write(a: Reg, at: &Location<'_>) -> ! {
    panic!("{at}: writes scene register {a} (read-only to the controller)")
}

#[cold]
#[inline(never)]
fn bad_mask(mask: Lanes, at: &Location<'_>) -> ! {
    panic!("{at}: lane mask {mask:03b}")
}

#[cold]
#[inline(never)]
fn unwritten_flag(i: usize, mask: Lanes) -> ! {
    panic!("branching on lane {i}, which was not written (mask {mask:03b})")
}

#[cold]
#[inline(never)]
fn partly_written_signs(mask: Lanes) -> ! {
    panic!("sign bits of a partly written vector (mask {mask:03b})")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fp;
    use crate::micro::isa::reg;

    fn image(regs: &[(Reg, Vec3f)]) -> RegisterImage {
        let mut img = RegisterImage {
            bits: [[0; 3]; REGISTER_COUNT],
            valid: [Lanes::NONE; REGISTER_COUNT],
        };
        for &(a, v) in regs {
            img.bits[a.0 as usize] = v.map(f32::to_bits);
            img.valid[a.0 as usize] = Lanes::XYZ;
        }
        img
    }

    fn core(img: &RegisterImage) -> Core<impl FnMut(&TraceEvent, &'static Location<'static>)> {
        Core::new(img, 3, 4, Method::Exact, Method::Exact, |_, _| {})
    }

    const A: Reg = Reg::EYE;
    const B: Reg = Reg::LIGHT_POS;
    const S: State = State::PRI_HALF;

    /// The core's layout holds exactly the image: every loaded register
    /// reads back bit for bit, and nothing else is readable.
    #[test]
    fn the_core_holds_the_register_image_bit_for_bit() {
        let mut img = image(&[]);
        for a in 0..reg::T0 {
            let v = [a, a + 1, a + 2].map(|i| f32::from(i) * -0.37);
            img.bits[a as usize] = v.map(f32::to_bits);
            img.valid[a as usize] = Lanes::XYZ;
        }
        img.bits[reg::T0 as usize] = [1, 2, 3];
        img.valid[reg::T0 as usize] = Lanes::Y;
        let c = core(&img);
        for a in 0..REGISTER_COUNT as u8 {
            let want = (img.valid[a as usize] == Lanes::XYZ).then_some(img.bits[a as usize]);
            assert_eq!(c.peek(Reg(a)), want, "{}", Reg(a));
        }
        assert_eq!(
            c.read(Reg::T0, Lanes::Y, Location::caller())[1].to_bits(),
            2
        );
    }

    #[test]
    fn lanewise_ops_route_b_as_documented() {
        let img = image(&[(A, [1.0, 2.0, 3.0]), (B, [10.0, 20.0, 30.0])]);
        let mut c = core(&img);
        let t = Reg::T0;
        assert_eq!(c.add(S, t, A, B, Lanes::XYZ).value(), [11.0, 22.0, 33.0]);
        assert_eq!(c.sub(S, t, A, B, Lanes::XYZ).value(), [-9.0, -18.0, -27.0]);
        assert_eq!(c.mul(S, t, A, B, Lanes::XYZ).value(), [10.0, 40.0, 90.0]);
        assert_eq!(
            c.nmul(S, t, A, B, Lanes::XYZ).value(),
            [-10.0, -40.0, -90.0]
        );
        assert_eq!(c.mulx(S, t, A, B, Lanes::XYZ).value(), [10.0, 20.0, 30.0]);
        assert_eq!(c.muly(S, t, A, B, Lanes::XYZ).value(), [20.0, 40.0, 60.0]);
        assert_eq!(c.mulz(S, t, A, B, Lanes::XYZ).value(), [30.0, 60.0, 90.0]);
        assert_eq!(
            c.nmulx(S, t, A, B, Lanes::XYZ).value(),
            [-10.0, -20.0, -30.0]
        );
        assert_eq!(c.mulr1(S, t, A, B, Lanes::XYZ).value(), [20.0, 60.0, 30.0]);
        assert_eq!(c.mulr2(S, t, A, B, Lanes::XYZ).value(), [30.0, 20.0, 60.0]);
        assert_eq!(c.mul2x(S, t, A, B, Lanes::XYZ).value(), [20.0, 40.0, 60.0]);
        assert_eq!(c.mov(S, t, A, Lanes::XYZ).value(), [1.0, 2.0, 3.0]);
        assert_eq!(c.neg(S, t, A, Lanes::XYZ).value(), [-1.0, -2.0, -3.0]);
        assert_eq!(c.itof(S, t).value(), [3.0, -4.0, 0.0]);
        assert_eq!(c.stats.instructions(), 14);
        assert_eq!(c.stats.register_writes, 14);
    }

    #[test]
    fn masked_writes_keep_the_other_lanes() {
        let img = image(&[(A, [1.0, 2.0, 3.0]), (B, [10.0, 20.0, 30.0])]);
        let mut events = Vec::new();
        {
            let mut c = Core::new(
                &img,
                0,
                0,
                Method::Exact,
                Method::Exact,
                |e: &TraceEvent, _: &_| events.push(*e),
            );
            c.mov(S, Reg::T1, A, Lanes::XYZ);
            c.add(S, Reg::T1, A, B, Lanes::Y | Lanes::Z);
            assert_eq!(
                c.read(Reg::T1, Lanes::XYZ, Location::caller()),
                [1.0, 22.0, 33.0]
            );
        }
        assert_eq!(events[1].lanes, 0b110);
        assert_eq!(events[1].values, [0, 22f32.to_bits(), 33f32.to_bits()]);
        assert_eq!(events[1].seq, 1);
    }

    #[test]
    fn dot_product_sums_x_plus_y_then_z() {
        let img = image(&[(A, [1.0, 2.0, 3.0]), (B, [4.0, 5.0, 6.0])]);
        let mut c = core(&img);
        c.dot1(S, A, B);
        c.dot2(S);
        assert_eq!(c.dot3(S, Reg::T0).value()[0], 32.0);
        assert_eq!(c.stats.count_of(OpClass::Dot), 3);
        assert_eq!(c.stats.register_writes, 1);
    }

    /// Eq. 29/30 on values whose every sum and product is exact.
    #[test]
    fn the_intersection_sub_graph_computes_a_minus_b_dot_c_and_c_dot_d() {
        let (b, cc, d, a) = (Reg::EYE, Reg::LIGHT_POS, Reg::LIGHT_COL, Reg::CAM_HALF);
        let img = image(&[
            (b, [1.0, 2.0, 3.0]),
            (cc, [4.0, 5.0, 6.0]),
            (d, [0.5, 0.25, 2.0]),
            (a, [100.0, -7.0, -9.0]),
        ]);
        let mut c = core(&img);
        c.isect1(S, b, cc);
        let g = c.isect2(S, Reg::T0, d, cc);
        assert_eq!(g.value(), [2.0, 1.25, 12.0]);
        c.isect3(S, Reg::T0);
        let y = c.isect4(S, Reg::T1, a);
        // a - b.c = 100 - 32; c.d = 2 + 1.25 + 12.
        assert_eq!(y.value(), [68.0, 15.25, 0.0]);
        assert_eq!(c.stats.register_writes, 2);
    }

    /// With rounding, lane x equals `a - DOT(b, c)` and lane y `DOT(c, d)`,
    /// bit for bit.
    #[test]
    fn the_sub_graph_rounds_like_dot_and_sub() {
        let (b, cc, d, a) = (Reg::EYE, Reg::LIGHT_POS, Reg::LIGHT_COL, Reg::CAM_HALF);
        let vals = [
            [0.1f32, -0.7, 1.3e3],
            [3.3, 1e-3, -0.45],
            [0.577, -0.577, 0.5773],
            [2.2e4, 0.0, 0.0],
        ];
        let img = image(&[(b, vals[0]), (cc, vals[1]), (d, vals[2]), (a, vals[3])]);
        let mut c = core(&img);
        c.isect1(S, b, cc);
        c.isect2(S, Reg::T0, d, cc);
        c.isect3(S, Reg::T0);
        let y = c.isect4(S, Reg::T1, a).value();
        c.dot1(S, b, cc);
        c.dot2(S);
        let bc = c.dot3(S, Reg::T2);
        let diff = c.sub(S, Reg::T3, a, Reg::T2, Lanes::X).value()[0];
        c.dot1(S, cc, d);
        c.dot2(S);
        let cd = c.dot3(S, Reg::T4).value()[0];
        assert!(bc.value()[0] != 0.0);
        assert_eq!(y[0].to_bits(), diff.to_bits());
        assert_eq!(y[1].to_bits(), cd.to_bits());
    }

    #[test]
    fn multi_cycle_instructions_take_latency_plus_one_cycles() {
        let img = image(&[(A, [4.0, 0.5, 0.0])]);
        for m in Method::ALL {
            let mut c = Core::new(&img, 0, 0, m, m, |_, _| {});
            assert_eq!(c.sqrt(S, Reg::T0, A).value()[0], 2.0);
            assert_eq!(c.recip(S, Reg::T0, A).value()[0], 0.25);
            assert_eq!(c.recipy(S, Reg::T0, A).value()[0], 2.0);
            assert_eq!(c.roots(S, Reg::T0, A).value(), [2.0, 0.25, 0.0]);
            assert_eq!(
                c.stats.instruction_cycles(),
                u64::from(
                    fp::sqrt_latency(m)
                        + 1
                        + 2 * (fp::recip_latency(m) + 1)
                        + fp::sqrt_latency(m).max(fp::recip_latency(m))
                        + 1
                )
            );
        }
    }

    #[test]
    #[should_panic(expected = "only 000 were loaded or written")]
    fn reading_an_unwritten_register_is_refused() {
        let img = image(&[]);
        core(&img).mov(S, Reg::T0, Reg::T1, Lanes::XYZ);
    }

    #[test]
    #[should_panic(expected = "only 001 were loaded or written")]
    fn reading_an_unwritten_lane_is_refused() {
        let img = image(&[(A, [4.0, 0.0, 0.0])]);
        let mut c = core(&img);
        c.sqrt(S, Reg::T0, A);
        c.add(S, Reg::T1, Reg::T0, Reg::T0, Lanes::Y);
    }

    #[test]
    #[should_panic(expected = "read-only")]
    fn writing_a_scene_register_is_refused() {
        let img = image(&[(A, [1.0; 3])]);
        core(&img).mov(S, Reg::EYE, A, Lanes::XYZ);
    }

    #[test]
    #[should_panic(expected = "outside the stack")]
    fn the_parent_of_the_root_does_not_exist() {
        let img = image(&[(A, [1.0; 3])]);
        core(&img).mov(S, Reg::PAR_O, A, Lanes::XYZ);
    }

    #[test]
    fn stack_relative_writes_land_in_the_decoded_level() {
        let img = image(&[(A, [1.0; 3])]);
        let mut dsts = Vec::new();
        {
            let mut c = Core::new(
                &img,
                0,
                0,
                Method::Exact,
                Method::Exact,
                |e: &TraceEvent, _: &_| dsts.push(Reg(e.dst)),
            );
            c.sp = 2;
            c.mov(S, Reg::CUR_W, A, Lanes::XYZ);
            c.mov(S, Reg::PAR_COL, A, Lanes::XYZ);
        }
        assert_eq!(
            dsts,
            [
                isa::stack(2, isa::RayField::W),
                isa::stack(1, isa::RayField::Col)
            ]
        );
    }
}
