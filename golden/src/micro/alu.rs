//! The ALU (thesis 4.2): what each opcode computes from its operand values,
//! through `golden::fp` only (one rounding per operation, lanes
//! independent), its internal vector register F, and the cycles each opcode
//! takes. It knows no registers: the core ([`super::core`]) reads the
//! operands, hands their values here, and writes the result.

use super::isa::{op, Lanes};
use super::OpClass;
use crate::fp::{self, Method};
use crate::scene::Vec3f;
use std::panic::Location;

/// The ALU of one pixel's run: F, and the methods of its reciprocal and
/// square-root units (RTL parameters).
#[derive(Debug, Clone)]
pub struct Alu {
    f: Vec3f,
    f_valid: bool,
    recip: Method,
    sqrt: Method,
}

/// `[f(0), f(1), f(2)]`, spelled out (`array::map` is not always inlined,
/// and this is the inner loop).
#[inline(always)]
fn lanes3(mut f: impl FnMut(usize) -> f32) -> Vec3f {
    [f(0), f(1), f(2)]
}

impl Alu {
    /// An ALU with F not yet written.
    #[inline(always)]
    pub fn new(recip: Method, sqrt: Method) -> Alu {
        Alu {
            f: [0.0; 3],
            f_valid: false,
            recip,
            sqrt,
        }
    }

    /// Cycles opcode `code` takes: 1, or the unit's latency + 1 for the
    /// multi-cycle ones (issued with in_valid, written when out_valid).
    #[inline(always)]
    pub fn cycles(&self, code: u8) -> u64 {
        match code {
            op::RECIP | op::RECIPY => u64::from(fp::recip_latency(self.recip)) + 1,
            op::SQRT => u64::from(fp::sqrt_latency(self.sqrt)) + 1,
            op::ROOTS => u64::from(roots_latency(self.recip, self.sqrt)) + 1,
            op::EXP => u64::from(fp::exp_latency()) + 1,
            _ => 1,
        }
    }

    /// The B-operand routing of a lane-wise binary opcode: lane i of the
    /// result combines A.i with B.(`route[i]`).
    #[inline(always)]
    pub fn route(code: u8) -> [usize; 3] {
        match code {
            op::ADD | op::SUB | op::MUL | op::NMUL => [0, 1, 2],
            op::MULX | op::NMULX | op::MUL2X => [0, 0, 0],
            op::MULY => [1, 1, 1],
            op::MULZ => [2, 2, 2],
            op::MULR1 => [1, 2, 0],
            op::MULR2 => [2, 0, 1],
            _ => unreachable!("not a lane-wise binary opcode: {code}"),
        }
    }

    /// ADD, SUB, MUL, NMUL, MULX, MULY, MULZ, NMULX, MULR1, MULR2, MUL2X:
    /// every lane of `a` with the lane of `b` that [`Alu::route`] gives.
    #[inline(always)]
    pub fn lanewise(code: u8, a: Vec3f, b: Vec3f) -> Vec3f {
        let route = Alu::route(code);
        let mut y = [0.0f32; 3];
        for i in 0..3 {
            let (p, q) = (a[i], b[route[i]]);
            y[i] = match code {
                op::ADD => fp::add(p, q),
                // fp_add with B's sign bit flipped (thesis 4.2).
                op::SUB => fp::add(p, -q),
                op::NMUL | op::NMULX => -fp::mul(p, q),
                // The doubled product, exactly p + p rounded.
                op::MUL2X => {
                    let m = fp::mul(p, q);
                    fp::add(m, m)
                }
                _ => fp::mul(p, q),
            };
        }
        y
    }

    /// NEG: the sign bits flipped (exact).
    #[inline(always)]
    pub fn neg([x, y, z]: Vec3f) -> Vec3f {
        [-x, -y, -z]
    }

    /// ITOF: `<itof(px), itof(-py), itof(0)>`.
    #[inline(always)]
    pub fn itof(px: u32, py: u32) -> Vec3f {
        [fp::itof(px as i32), fp::itof(-(py as i32)), fp::itof(0)]
    }

    /// F as it stands, written or not (for coverage: [`super::core::near`]).
    #[inline(always)]
    pub(crate) fn f_lanes(&self) -> Vec3f {
        self.f
    }

    #[inline(always)]
    fn f(&self, at: &Location<'_>) -> Vec3f {
        if !self.f_valid {
            unwritten_f(at);
        }
        self.f
    }

    #[inline(always)]
    fn set_f(&mut self, f: Vec3f) {
        self.f = f;
        self.f_valid = true;
    }

    // -----------------------------------------------------------------------
    // The dot product (thesis 4.7.1): three instructions through F
    // -----------------------------------------------------------------------

    /// DOT1: F = A * B.
    #[inline(always)]
    pub fn dot1(&mut self, a: Vec3f, b: Vec3f) {
        self.set_f(lanes3(|i| fp::mul(a[i], b[i])));
    }

    /// DOT2: F.x = F.x + F.y.
    #[inline(always)]
    pub fn dot2(&mut self, at: &Location<'_>) {
        let f = self.f(at);
        self.f[0] = fp::add(f[0], f[1]);
    }

    /// DOT3: `<F.x + F.z, 0, 0>`, i.e. `(a.x*b.x + a.y*b.y) + a.z*b.z`.
    #[inline(always)]
    pub fn dot3(&self, at: &Location<'_>) -> Vec3f {
        let f = self.f(at);
        [fp::add(f[0], f[2]), 0.0, 0.0]
    }

    // -----------------------------------------------------------------------
    // The intersection sub-graph (thesis 4.7.1, eq. 29 and 30)
    //
    // With b, c, d vectors and a = A.x in ISECT4, the four instructions
    // compute, with the additions in the order written:
    //
    //   ISECT1  F = <-b.x c.x, -b.y c.y, -b.z c.z>
    //   ISECT2  g = <d.x c.x, d.y c.y, d.z c.z>                  (register)
    //           F = <-b.x c.x - b.y c.y, -b.y c.y, -b.z c.z>     (same cycle:
    //               the multiplier makes g while the adder updates F)
    //   ISECT3  F = <d.x c.x + d.y c.y, (-b.x c.x - b.y c.y) - b.z c.z, d.z c.z>
    //   ISECT4  Y = F = <a + (-(b.c)), (d.x c.x + d.y c.y) + d.z c.z, 0>
    //                 = <a - b.c, c.d, 0>
    //
    // The eq. 30 table writes ISECT3's F.x from v1 = g and ISECT4's Y.x as
    // v1x + fy with v1 = <a, DK, DK>; "DK" lanes are written as computed (z:
    // +0). Both dot products sum (x + y) + z, like DOT1..DOT3, and -(p*q)
    // is exactly -(p*q) rounded, so lane y is bit-identical to `c.d` by
    // DOT and lane x to `a - b.c` by DOT and SUB.
    //
    //   plane  (b = o, c = n, d = dir, a = q):          <q - n.o, n.d, 0>
    //   sphere (b = c = v = o - centre, a = r*r):       <r*r - v.v, v.d, 0>
    //
    // (the pixel program feeds spheres b = c = w = v - (v.d) d instead of v,
    // for the disc r*r - w.w without cancellation; see `program`).
    // -----------------------------------------------------------------------

    /// ISECT1: F = -(A * B) [A = b, B = c].
    #[inline(always)]
    pub fn isect1(&mut self, a: Vec3f, b: Vec3f) {
        self.set_f(lanes3(|i| -fp::mul(a[i], b[i])));
    }

    /// ISECT2: returns g = A * B [A = d, B = c]; F = <F.x + F.y, F.y, F.z>.
    #[inline(always)]
    pub fn isect2(&mut self, a: Vec3f, b: Vec3f, at: &Location<'_>) -> Vec3f {
        let f = self.f(at);
        let g = lanes3(|i| fp::mul(a[i], b[i]));
        self.f = [fp::add(f[0], f[1]), f[1], f[2]];
        g
    }

    /// ISECT3: F = <A.x + A.y, F.x + F.z, A.z> [A = g].
    #[inline(always)]
    pub fn isect3(&mut self, g: Vec3f, at: &Location<'_>) {
        let f = self.f(at);
        self.f = [fp::add(g[0], g[1]), fp::add(f[0], f[2]), g[2]];
    }

    /// ISECT4: returns F = <a + F.y, F.x + F.z, 0> [a = A.x].
    #[inline(always)]
    pub fn isect4(&mut self, a: f32, at: &Location<'_>) -> Vec3f {
        let f = self.f(at);
        let v = [fp::add(a, f[1]), fp::add(f[0], f[2]), 0.0];
        self.f = v;
        v
    }

    // -----------------------------------------------------------------------
    // The multi-cycle units
    // -----------------------------------------------------------------------

    /// RECIP, RECIPY: `1 / x`; SQRT: `sqrt(x)`.
    #[inline(always)]
    pub fn unary(&self, code: u8, x: f32) -> f32 {
        if code == op::SQRT {
            fp::sqrt(x, self.sqrt)
        } else {
            fp::recip(x, self.recip)
        }
    }

    /// EXP: `e^v` in every lane (three fp_exp units started together).
    #[inline(always)]
    pub fn exp(v: Vec3f) -> Vec3f {
        lanes3(|i| fp::exp(v[i]))
    }

    /// ROOTS: `<sqrt(x), 1 / x, 0>`, both units started in the same cycle.
    #[inline(always)]
    pub fn roots(&self, x: f32) -> Vec3f {
        [fp::sqrt(x, self.sqrt), fp::recip(x, self.recip), 0.0]
    }
}

impl Alu {
    /// The ALU as one function of an opcode and its operands' values, as
    /// the fast processor's ALU (`rtl/fast/fast_alu.v`) takes them: `a`
    /// and `b` whole (the core reads only the lanes an instruction names),
    /// the controller's pixel for ITOF. Returns the result it writes to the
    /// register file, or `None` for the opcodes that write nothing (DOT1,
    /// DOT2, ISECT1, ISECT3, NOP and unassigned codes; the RTL's result
    /// port shows +0 then); F is updated as the opcode says.
    #[track_caller]
    pub fn apply(&mut self, code: u8, a: Vec3f, b: Vec3f, px: u32, py: u32) -> Option<Vec3f> {
        let at = Location::caller();
        if let Some(OpClass::Add | OpClass::Mul) = OpClass::of(code) {
            return Some(Alu::lanewise(code, a, b));
        }
        Some(match code {
            op::MOV => a,
            op::NEG => Alu::neg(a),
            op::ITOF => Alu::itof(px, py),
            op::DOT1 => {
                self.dot1(a, b);
                return None;
            }
            op::DOT2 => {
                self.dot2(at);
                return None;
            }
            op::DOT3 => self.dot3(at),
            op::ISECT1 => {
                self.isect1(a, b);
                return None;
            }
            op::ISECT2 => self.isect2(a, b, at),
            op::ISECT3 => {
                self.isect3(a, at);
                return None;
            }
            op::ISECT4 => self.isect4(a[0], at),
            op::RECIP | op::SQRT => [self.unary(code, a[0]), 0.0, 0.0],
            op::RECIPY => [self.unary(code, a[1]), 0.0, 0.0],
            op::ROOTS => self.roots(a[0]),
            op::EXP => Alu::exp(a),
            _ => return None,
        })
    }

    /// The lanes of [`Alu::apply`]'s result that opcode `code` defines: x
    /// alone for DOT3, RECIP, RECIPY and SQRT, x and y for ROOTS (isa.vh:
    /// "Y.x = ..."), every lane otherwise. The program writes and branches
    /// on no other lane of theirs, and the RTL leaves the others as its
    /// datapath has them (the compact ALU's DOT3 shows all three sums).
    pub fn result_lanes(code: u8) -> Lanes {
        match code {
            op::DOT3 | op::RECIP | op::RECIPY | op::SQRT => Lanes::X,
            op::ROOTS => Lanes::X | Lanes::Y,
            _ => Lanes::XYZ,
        }
    }

    /// Whether F has been written (reading it before is refused).
    pub fn f_written(&self) -> bool {
        self.f_valid
    }
}

/// Clock edges from an opcode entering the fast processor's ALU
/// (`rtl/fast/fast_alu.v`) to its result leaving, for every opcode: the
/// slowest unit after the operands' selection (the square root, or the
/// shared `fp_exp` fed lanes x, y, z one edge apart and collected, when
/// the build has exposure), plus decode and selection before it and the
/// result's and its flags' registers after.
pub const fn fast_latency(exposure: bool) -> u32 {
    use crate::fp::pipelined as p;
    let mut slowest = p::SQRT_LATENCY;
    let units = [
        p::MUL_LATENCY + 1,
        p::ADD_LATENCY,
        p::ITOF_LATENCY,
        p::RECIP_LATENCY,
    ];
    let mut i = 0;
    while i < units.len() {
        if units[i] > slowest {
            slowest = units[i];
        }
        i += 1;
    }
    if exposure && p::EXP_LATENCY + 3 > slowest {
        slowest = p::EXP_LATENCY + 3;
    }
    2 + slowest + 2
}

/// The latency of ROOTS: the later of its two units.
const fn roots_latency(recip: Method, sqrt: Method) -> u32 {
    let (r, s) = (fp::recip_latency(recip), fp::sqrt_latency(sqrt));
    if r > s {
        r
    } else {
        s
    }
}

// Out of line, as the core's refusals are (see there).
#[cold]
#[inline(never)]
fn unwritten_f(at: &Location<'_>) -> ! {
    panic!("{at}: reads F before anything wrote it")
}
