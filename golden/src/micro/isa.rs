//! The pixel processor's ISA, generated at build time from `rtl/pp/isa.vh`
//! (the single source of truth, shared with the RTL): opcodes ([`op`]),
//! register addresses ([`reg`]), controller FSM states ([`state`]), widths,
//! counts and strides ([`dim`]), and the name tables.
//!
//! [`reg`] and [`state`] hold the header's codes as integers, as the RTL's
//! ports and the trace carry them. The model's instructions take them typed,
//! so that a state, a register and a lane mask cannot trade places in an
//! argument list: [`Reg`] (`Reg::EYE` is `Reg(reg::EYE)`), [`State`]
//! (`State::PRI_HALF`) and [`Lanes`].
//!
//! Register arrays are declared once in the header (element 0) with a count
//! and a stride; [`sphere`], [`plane`], [`rot`], [`corner`] and [`stack`]
//! compute the other elements' addresses, and [`register_name`] names every
//! one of them (`SPH3_C`, `STK2_COL`).
//!
//! Every label of a state, register or lane mask in messages and traces
//! comes from here: [`state_label`], [`register_label`], [`lanes_label`].

include!(concat!(env!("OUT_DIR"), "/isa.rs"));

use crate::scene::{MAX_DEPTH, MAX_PLANES, MAX_SPHERES};
use std::fmt;
use std::ops::{BitOr, BitOrAssign};

/// A register-file address: as an instruction names it (`CUR_*` and
/// `PAR_*` are decoded through the stack pointer, see [`decode`]) or as the
/// memory holds it. The header's codes, typed: `Reg::T0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct Reg(pub u8);

/// A controller FSM state id, the state an instruction is issued from. The
/// header's codes, typed: `State::PRI_HALF`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct State(pub u16);

/// A lane mask: bit i set means lane i (x, y, z; see [`LANE_NAMES`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[repr(transparent)]
pub struct Lanes(pub u8);

/// The names of lanes 0, 1 and 2.
pub const LANE_NAMES: [char; 3] = ['x', 'y', 'z'];

impl Lanes {
    pub const NONE: Lanes = Lanes(0);
    pub const X: Lanes = Lanes(0b001);
    pub const Y: Lanes = Lanes(0b010);
    pub const Z: Lanes = Lanes(0b100);
    pub const XYZ: Lanes = Lanes(0b111);

    /// Lane `i` alone (0 = x).
    #[inline(always)]
    pub const fn lane(i: usize) -> Lanes {
        Lanes(1 << i)
    }

    /// Whether lane `i` is in the mask.
    #[inline(always)]
    pub const fn has(self, i: usize) -> bool {
        self.0 >> i & 1 == 1
    }

    /// Whether every lane of `other` is in the mask.
    #[inline(always)]
    pub const fn contains(self, other: Lanes) -> bool {
        self.0 & other.0 == other.0
    }
}

impl BitOr for Lanes {
    type Output = Lanes;

    #[inline(always)]
    fn bitor(self, other: Lanes) -> Lanes {
        Lanes(self.0 | other.0)
    }
}

impl BitOrAssign for Lanes {
    #[inline(always)]
    fn bitor_assign(&mut self, other: Lanes) {
        self.0 |= other.0;
    }
}

/// `{:03b}`: the mask's bits, z first (`011` is x and y).
impl fmt::Binary for Lanes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Binary::fmt(&self.0, f)
    }
}

/// [`register_label`].
impl fmt::Display for Reg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&register_label(self.0))
    }
}

/// [`state_label`].
impl fmt::Display for State {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&state_label(self.0))
    }
}

/// [`lanes_label`].
impl fmt::Display for Lanes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&lanes_label(self.0))
    }
}

// The header's arrays are the scene limits the rest of golden enforces.
const _: () = assert!(dim::SPH_COUNT == MAX_SPHERES);
const _: () = assert!(dim::PLN_COUNT == MAX_PLANES);
const _: () = assert!(dim::STK_COUNT == MAX_DEPTH as usize);
const _: () = assert!(dim::REG_BITS == 8 && dim::ST_BITS <= 16 && dim::OP_BITS <= 8);
const _: () = assert!(dim::TRN_COUNT == MAX_SPHERES);
// CUR_<f> and PAR_<f> decode to STK<level>_<f>: the fields line up.
const _: () = assert!(reg::CUR_D - reg::CUR_O == reg::STK0_D - reg::STK0_O);
const _: () = assert!(reg::CUR_COL - reg::CUR_O == reg::STK0_COL - reg::STK0_O);
const _: () = assert!(reg::CUR_W - reg::CUR_O == reg::STK0_W - reg::STK0_O);
const _: () = assert!(reg::PAR_O - reg::CUR_O == dim::STK_STRIDE as u8);
const _: () = assert!(dim::STK_STRIDE == 4);

/// Number of register addresses.
pub const REGISTER_COUNT: usize = 1 << dim::REG_BITS;

/// A field of a sphere's registers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SphereField {
    /// Centre.
    C = 0,
    /// `<r*r, 1/r, 0>`.
    R = 1,
    Col = 2,
    /// `<kd, ks, kr>`.
    Mat = 3,
}

/// A field of a plane's registers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlaneField {
    /// Normal.
    N = 0,
    /// `<facing * offset, 0, 0>`.
    Q = 1,
    Col = 2,
    /// `<kd, ks, kr>`.
    Mat = 3,
}

/// A field of a ray on the stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RayField {
    O = 0,
    D = 1,
    Col = 2,
    W = 3,
}

const _: () = assert!(reg::SPH0_R - reg::SPH0_C == SphereField::R as u8);
const _: () = assert!(reg::SPH0_COL - reg::SPH0_C == SphereField::Col as u8);
const _: () = assert!(reg::SPH0_MAT - reg::SPH0_C == SphereField::Mat as u8);
const _: () = assert!(reg::PLN0_Q - reg::PLN0_N == PlaneField::Q as u8);
const _: () = assert!(reg::PLN0_COL - reg::PLN0_N == PlaneField::Col as u8);
const _: () = assert!(reg::PLN0_MAT - reg::PLN0_N == PlaneField::Mat as u8);
const _: () = assert!(reg::STK0_D - reg::STK0_O == RayField::D as u8);
const _: () = assert!(reg::STK0_COL - reg::STK0_O == RayField::Col as u8);
const _: () = assert!(reg::STK0_W - reg::STK0_O == RayField::W as u8);
const _: () = assert!(reg::ROT0_S - reg::ROT0_C == 1);

/// Address of sphere `k`'s `field`.
pub const fn sphere(k: usize, field: SphereField) -> Reg {
    assert!(k < dim::SPH_COUNT);
    Reg(reg::SPH0_C + (k * dim::SPH_STRIDE) as u8 + field as u8)
}

/// Address of plane `p`'s `field`.
pub const fn plane(p: usize, field: PlaneField) -> Reg {
    assert!(p < dim::PLN_COUNT);
    Reg(reg::PLN0_N + (p * dim::PLN_STRIDE) as u8 + field as u8)
}

/// Address of the rotation constants about `axis` (0 = x): `(ROTa_C, ROTa_S)`.
pub const fn rot(axis: usize) -> (Reg, Reg) {
    assert!(axis < dim::ROT_COUNT);
    let c = reg::ROT0_C + (axis * dim::ROT_STRIDE) as u8;
    (Reg(c), Reg(c + 1))
}

/// Address of transparent sphere `k`'s `<1/ior, ior, kt>`.
pub const fn trn(k: usize) -> Reg {
    assert!(k < dim::TRN_COUNT);
    Reg(reg::TRN0 + (k * dim::TRN_STRIDE) as u8)
}

/// Address of bounding-box corner `k` (lane i = maximum iff bit i of k).
pub const fn corner(k: usize) -> Reg {
    assert!(k < dim::BOX_COUNT);
    Reg(reg::BOX0 + (k * dim::BOX_STRIDE) as u8)
}

/// Physical address of stack level `level`'s `field`.
pub const fn stack(level: usize, field: RayField) -> Reg {
    assert!(level < dim::STK_COUNT);
    Reg(reg::STK0_O + (level * dim::STK_STRIDE) as u8 + field as u8)
}

/// Whether `code` is one of the stack-pointer-relative addresses
/// (`CUR_*`, `PAR_*`), which the memory controller decodes.
pub const fn is_stack_relative(code: Reg) -> bool {
    code.0 >= reg::CUR_O && code.0 <= reg::PAR_W
}

/// The memory controller's decoding: `CUR_<f>` is `STK<sp>_<f>`, `PAR_<f>`
/// is `STK<sp-1>_<f>`, every other address is itself. `None` for `PAR_*`
/// at sp = 0 or a level past the stack.
///
/// The root ray's origin and weight are always the eye and <1, 1, 1>:
/// `STK0_O` decodes to `EYE` and `STK0_W` to `ONE` (read-only scene
/// registers), so the primary ray needs no instructions to set them.
pub const fn decode(code: Reg, sp: usize) -> Option<Reg> {
    if !is_stack_relative(code) {
        return Some(code);
    }
    let rel = (code.0 - reg::CUR_O) as usize;
    let (level, field) = if rel < dim::STK_STRIDE {
        (sp, rel)
    } else {
        if sp == 0 {
            return None;
        }
        (sp - 1, rel - dim::STK_STRIDE)
    };
    if level >= dim::STK_COUNT {
        return None;
    }
    if level == 0 && field == RayField::O as usize {
        return Some(Reg::EYE);
    }
    if level == 0 && field == RayField::W as usize {
        return Some(Reg::ONE);
    }
    Some(Reg(reg::STK0_O + (level * dim::STK_STRIDE + field) as u8))
}

static REGISTER_NAMES: [Option<&str>; REGISTER_COUNT] = {
    let mut t = [None; REGISTER_COUNT];
    let mut i = 0;
    while i < REGISTERS.len() {
        t[REGISTERS[i].1 as usize] = Some(REGISTERS[i].0);
        i += 1;
    }
    t
};

/// The name of register address `code` (`"SPH1_R"`, `"T3"`, `"STK0_COL"`),
/// or `None` if the header names no register there.
pub fn register_name(code: u8) -> Option<&'static str> {
    REGISTER_NAMES.get(code as usize).copied().flatten()
}

/// The address of the register named `name` (array elements included).
pub fn register_code(name: &str) -> Option<u8> {
    REGISTERS.iter().find(|(n, _)| *n == name).map(|&(_, c)| c)
}

/// The name of FSM state `id` (`"SPH_SQRT"`), or `None`.
pub fn state_name(id: u16) -> Option<&'static str> {
    STATES.iter().find(|&&(_, c)| c == id).map(|&(n, _)| n)
}

/// The id of the FSM state named `name`.
pub fn state_code(name: &str) -> Option<u16> {
    STATES.iter().find(|(n, _)| *n == name).map(|&(_, c)| c)
}

/// `NAME (id)` from the state table (`PRI_HALF (11)`), or `state#id` for an
/// id it does not name.
pub fn state_label(id: u16) -> String {
    match state_name(id) {
        Some(name) => format!("{name} ({id})"),
        None => unnamed_state(id),
    }
}

/// How a state id the table does not name is written: `state#id`.
pub fn unnamed_state(id: u16) -> String {
    format!("state#{id}")
}

/// The register's name (`SPH1_R`), or `r{a}` for an address the header
/// does not name.
pub fn register_label(a: u8) -> String {
    register_name(a).map_or_else(|| unnamed_register(a), str::to_string)
}

/// How a register address the header does not name is written: `r{a}`.
pub fn unnamed_register(a: u8) -> String {
    format!("r{a}")
}

/// The lanes of `mask` by name, `_` for a lane not in it: `xyz`, `x_z`,
/// `_y_`. Bits above lane z are not shown.
pub fn lanes_label(mask: u8) -> String {
    LANE_NAMES
        .iter()
        .enumerate()
        .map(|(i, &name)| if mask >> i & 1 == 1 { name } else { '_' })
        .collect()
}

/// The name of opcode `code` (`"ISECT2"`), or `None`.
pub fn op_name(code: u8) -> Option<&'static str> {
    OPS.iter().find(|&&(_, c)| c == code).map(|&(n, _)| n)
}

/// The opcode named `name`.
pub fn op_code(name: &str) -> Option<u8> {
    OPS.iter().find(|(n, _)| *n == name).map(|&(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::micro::isa_parse;
    use std::collections::HashSet;

    /// The refraction states are the ids from RF_NSUB up, and only these
    /// (a controller built without refraction decodes no id from there up:
    /// ctrl_flow.vh's decoded_st), and every id is below 128 (bits 7 and up
    /// of a state stay 0: fast_ctrl.v carries a state id in 7 bits, its
    /// decodes within 4 LUT levels: docs/fast.md).
    #[test]
    fn refraction_states_are_the_ids_from_rf_nsub_up_and_every_id_fits_7_bits() {
        for (name, id) in STATES {
            assert_eq!(
                name.starts_with("RF_"),
                *id >= state::RF_NSUB,
                "{name} = {id}"
            );
            assert!(*id < 128, "{name} = {id}");
            // What a controller without refraction decodes an RF id as.
            assert_ne!(
                usize::from(*id),
                dim::ST_NONE,
                "{name} has ISA_DIM_ST_NONE's id"
            );
        }
        assert!(dim::ST_NONE < 128);
    }

    #[test]
    fn codes_are_unique_within_each_kind() {
        let ops: HashSet<u8> = OPS.iter().map(|o| o.1).collect();
        assert_eq!(ops.len(), OPS.len());
        let states: HashSet<u16> = STATES.iter().map(|s| s.1).collect();
        assert_eq!(states.len(), STATES.len());
        let regs: HashSet<u8> = REGISTERS.iter().map(|r| r.1).collect();
        assert_eq!(regs.len(), REGISTERS.len());
    }

    #[test]
    fn every_name_round_trips() {
        for &(name, code) in OPS {
            assert_eq!(op_name(code), Some(name));
            assert_eq!(op_code(name), Some(code));
        }
        for &(name, code) in STATES {
            assert_eq!(state_name(code), Some(name));
            assert_eq!(state_code(name), Some(code));
        }
        for &(name, code) in REGISTERS {
            assert_eq!(register_name(code), Some(name));
            assert_eq!(register_code(name), Some(code));
        }
    }

    #[test]
    fn array_elements_are_named_and_addressed_alike() {
        assert_eq!(register_name(sphere(3, SphereField::R).0), Some("SPH3_R"));
        assert_eq!(register_name(plane(5, PlaneField::Mat).0), Some("PLN5_MAT"));
        assert_eq!(register_name(rot(2).1 .0), Some("ROT2_S"));
        assert_eq!(register_name(corner(7).0), Some("BOX7"));
        assert_eq!(register_name(stack(7, RayField::W).0), Some("STK7_W"));
        assert_eq!(register_name(trn(7).0), Some("TRN7"));
        assert_eq!(trn(7).0 as usize, 135);
        assert_eq!(stack(7, RayField::W).0 as usize + 1, trn(0).0 as usize);
    }

    #[test]
    fn the_typed_codes_are_the_headers_codes() {
        assert_eq!(Reg::CUR_COL, Reg(reg::CUR_COL));
        assert_eq!(State::PRI_HALF, State(state::PRI_HALF));
        assert_eq!(Lanes::X | Lanes::Y | Lanes::Z, Lanes::XYZ);
        assert_eq!(
            (0..3).map(Lanes::lane).collect::<Vec<_>>(),
            [Lanes::X, Lanes::Y, Lanes::Z]
        );
    }

    #[test]
    fn labels_name_states_registers_and_lanes_or_give_their_numbers() {
        assert_eq!(
            state_label(state::PRI_HALF),
            format!("PRI_HALF ({})", state::PRI_HALF)
        );
        assert_eq!(state_label(0xffff), "state#65535");
        assert_eq!(register_label(reg::T0), "T0");
        assert_eq!(register_label(sphere(1, SphereField::R).0), "SPH1_R");
        assert_eq!(register_label(200), "r200");
        assert_eq!(lanes_label(0b111), "xyz");
        assert_eq!(lanes_label(0b101), "x_z");
        assert_eq!(lanes_label(0b010), "_y_");
        assert_eq!(lanes_label(0), "___");
        assert_eq!(State::PRI_HALF.to_string(), state_label(state::PRI_HALF));
        assert_eq!(Reg::CUR_COL.to_string(), "CUR_COL");
        assert_eq!((Lanes::X | Lanes::Z).to_string(), "x_z");
        assert_eq!(format!("{:03b}", Lanes::X), "001");
    }

    #[test]
    fn cur_and_par_decode_through_the_stack_pointer() {
        assert_eq!(decode(Reg::CUR_COL, 0), Some(stack(0, RayField::Col)));
        assert_eq!(decode(Reg::CUR_D, 3), Some(stack(3, RayField::D)));
        assert_eq!(decode(Reg::PAR_W, 3), Some(stack(2, RayField::W)));
        assert_eq!(decode(Reg::PAR_O, 0), None);
        assert_eq!(decode(Reg::CUR_O, dim::STK_COUNT), None);
        assert_eq!(decode(Reg::T5, 6), Some(Reg::T5));
        // The root's origin and weight are the eye and ONE.
        assert_eq!(decode(Reg::CUR_O, 0), Some(Reg::EYE));
        assert_eq!(decode(Reg::CUR_W, 0), Some(Reg::ONE));
        assert_eq!(decode(Reg::PAR_O, 1), Some(Reg::EYE));
        assert_eq!(decode(Reg::PAR_W, 1), Some(Reg::ONE));
        assert_eq!(decode(Reg::CUR_O, 1), Some(stack(1, RayField::O)));
        // Every decoded address is a named register; CUR/PAR never are
        // decoded to themselves.
        for sp in 0..dim::STK_COUNT {
            for code in reg::CUR_O..=reg::PAR_W {
                if let Some(a) = decode(Reg(code), sp) {
                    assert!(!is_stack_relative(a) && register_name(a.0).is_some());
                }
            }
        }
    }

    /// The drift guard: the header as it is now, parsed again at test time,
    /// is exactly what was compiled in.
    #[test]
    fn the_compiled_tables_match_the_header_on_disk() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../rtl/pp/isa.vh");
        let text = std::fs::read_to_string(path).expect("reading rtl/pp/isa.vh");
        let isa = isa_parse::parse(&text, path).expect("the header parses");
        let rows = |kind| -> Vec<(String, u32)> {
            isa.of(kind).map(|d| (d.name.clone(), d.value)).collect()
        };
        let owned = |t: &[(&str, u32)]| -> Vec<(String, u32)> {
            t.iter().map(|(n, c)| (n.to_string(), *c)).collect()
        };
        let ops: Vec<_> = OPS.iter().map(|&(n, c)| (n, u32::from(c))).collect();
        let states: Vec<_> = STATES.iter().map(|&(n, c)| (n, u32::from(c))).collect();
        let dims: Vec<_> = DIMS.iter().map(|&(n, c)| (n, c as u32)).collect();
        let regs: Vec<_> = REGISTERS.iter().map(|&(n, c)| (n, u32::from(c))).collect();
        assert_eq!(
            owned(&ops),
            rows(isa_parse::Kind::Op),
            "opcodes drifted: rebuild"
        );
        assert_eq!(
            owned(&states),
            rows(isa_parse::Kind::St),
            "states drifted: rebuild"
        );
        assert_eq!(
            owned(&dims),
            rows(isa_parse::Kind::Dim),
            "dims drifted: rebuild"
        );
        assert_eq!(
            owned(&regs),
            isa.register_names(),
            "registers drifted: rebuild"
        );
        assert_eq!(
            isa_parse::generate(&isa, "rtl/pp/isa.vh"),
            include_str!(concat!(env!("OUT_DIR"), "/isa.rs")),
            "the generated module differs from the header: rebuild"
        );
    }
}
