//! Instruction and cycle statistics (thesis 3.9: "keep track of number of
//! times operators are used").

use super::isa::op;
use std::fmt;

/// A class of ALU instructions, for the instruction mix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum OpClass {
    /// ADD, SUB: the vector adder alone.
    Add,
    /// MUL, NMUL, MULX, MULY, MULZ, NMULX, MULR1, MULR2, MUL2X: the vector multiplier alone.
    Mul,
    /// MOV, NEG: bypass.
    Mov,
    /// ITOF: the int-to-float converters.
    Itof,
    /// DOT1, DOT2, DOT3 (three per dot product).
    Dot,
    /// ISECT1..ISECT4 (four per intersection sub-graph).
    Isect,
    /// RECIP, RECIPY.
    Recip,
    /// SQRT.
    Sqrt,
    /// ROOTS: fp_sqrt and fp_recip started together.
    Roots,
    /// EXP: the three fp_exp units (the exposure).
    Exp,
}

impl OpClass {
    pub const COUNT: usize = 10;
    pub const ALL: [OpClass; OpClass::COUNT] = [
        OpClass::Add,
        OpClass::Mul,
        OpClass::Mov,
        OpClass::Itof,
        OpClass::Dot,
        OpClass::Isect,
        OpClass::Recip,
        OpClass::Sqrt,
        OpClass::Roots,
        OpClass::Exp,
    ];

    /// The class of opcode `code`; `None` for NOP and unknown codes.
    pub const fn of(code: u8) -> Option<OpClass> {
        Some(match code {
            op::ADD | op::SUB => OpClass::Add,
            op::MUL
            | op::NMUL
            | op::MULX
            | op::MULY
            | op::MULZ
            | op::NMULX
            | op::MULR1
            | op::MULR2
            | op::MUL2X => OpClass::Mul,
            op::MOV | op::NEG => OpClass::Mov,
            op::ITOF => OpClass::Itof,
            op::DOT1 | op::DOT2 | op::DOT3 => OpClass::Dot,
            op::ISECT1 | op::ISECT2 | op::ISECT3 | op::ISECT4 => OpClass::Isect,
            op::RECIP | op::RECIPY => OpClass::Recip,
            op::SQRT => OpClass::Sqrt,
            op::ROOTS => OpClass::Roots,
            op::EXP => OpClass::Exp,
            _ => return None,
        })
    }

    pub const fn name(self) -> &'static str {
        match self {
            OpClass::Add => "add",
            OpClass::Mul => "mul",
            OpClass::Mov => "mov",
            OpClass::Itof => "itof",
            OpClass::Dot => "dot",
            OpClass::Isect => "isect",
            OpClass::Recip => "recip",
            OpClass::Sqrt => "sqrt",
            OpClass::Roots => "roots",
            OpClass::Exp => "exp",
        }
    }
}

impl fmt::Display for OpClass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Executed instructions and the cycles they took, per class, over one
/// pixel or many. Adding is exact and order-independent, so a frame's
/// statistics do not depend on the thread count.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OpStats {
    /// Instructions executed, indexed by `OpClass as usize`.
    pub count: [u64; OpClass::COUNT],
    /// Cycles those instructions took (1 each, `latency + 1` for RECIP and
    /// SQRT), indexed by `OpClass as usize`.
    pub cycles: [u64; OpClass::COUNT],
    /// Register-file writes (= trace events); F writes are not counted.
    pub register_writes: u64,
}

impl OpStats {
    /// Instructions of `class`.
    pub fn count_of(&self, class: OpClass) -> u64 {
        self.count[class as usize]
    }

    /// Cycles of `class`.
    pub fn cycles_of(&self, class: OpClass) -> u64 {
        self.cycles[class as usize]
    }

    /// All instructions.
    pub fn instructions(&self) -> u64 {
        self.count.iter().sum()
    }

    /// Cycles spent in instructions (without the start and done cycles).
    pub fn instruction_cycles(&self) -> u64 {
        self.cycles.iter().sum()
    }

    pub(crate) fn record(&mut self, class: OpClass, cycles: u64) {
        self.count[class as usize] += 1;
        self.cycles[class as usize] += cycles;
    }

    /// Adds `other` into `self`.
    pub fn merge(&mut self, other: &OpStats) {
        for i in 0..OpClass::COUNT {
            self.count[i] += other.count[i];
            self.cycles[i] += other.cycles[i];
        }
        self.register_writes += other.register_writes;
    }
}
