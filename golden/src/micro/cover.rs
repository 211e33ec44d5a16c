//! What a run exercises in the controller and its datapath, as the model
//! predicts it: the feedback of the guided fuzzer (`rtcosim fuzz --corpus`),
//! measured on golden alone, so that a candidate scene is judged new or not
//! before any RTL runs.
//!
//! Two kinds of [`Point`]:
//!
//! - **A transition** `(from, to)` of the controller's ISA states: what the
//!   compact processor's `st_q -> st_d` takes (rtl/cover/pp_ctrl.transitions
//!   lists every one Yosys finds possible). A pixel's path is IDLE, the state
//!   of each instruction in issue order (a multi-cycle instruction's state
//!   once more for each cycle it waits for its unit: a self-loop), PIX_DONE,
//!   IDLE: the cycle rule of [`super`], so the path is the RTL's, cycle for
//!   cycle. Every pair but the self-loops and PIX_DONE's is also what each
//!   of the fast processor's contexts takes from one turn to its next.
//! - **A value class** `(state, lane, class)` of a register-file write: the
//!   sign and kind ([`ValueClass`]) of each lane written, in the state that
//!   wrote it. The controller branches on the signs and zero tests of
//!   written values, and the float units' edge cases are their operands'
//!   kinds, so a written -0 or subnormal where none was is worth keeping.
//!
//! - **A near miss** `(from, to, level)`: the transition `from -> to` taken
//!   by an instruction whose sum in lane x cancelled at least 8, 16 or 24
//!   bits of its larger addend ([`Step::near`]). The controller branches on
//!   the signs of such sums, and which side a sum falls on is decided by
//!   its last bits when it nearly cancels: a scene that brings a branch's
//!   sum nearer to 0 is a step towards its other side (the needles a
//!   random draw misses, such as a discriminant that rounds below 0),
//!   which the transitions alone do not reward until it is there.
//!
//! A [`Coverage`] is a dense bit set over every point a 7-bit state id can
//! name: cheap to fill for every pixel, to merge and to compare.

use super::core::{Step, NEAR_BITS, NEAR_LEVELS};
use super::isa::{self, State};
use crate::trace::TraceEvent;
use std::fmt;

/// State ids fit 7 bits (isa.vh; golden's isa tests hold every id below 128).
const STATES: usize = 128;
const LANES: usize = 3;
/// Value-class slots per (state, lane).
const CLASSES: usize = 16;
const TRANSITION_BITS: usize = STATES * STATES;
const VALUE_BITS: usize = STATES * LANES * CLASSES;
const NEAR_POINT_BITS: usize = TRANSITION_BITS * NEAR_LEVELS as usize;
const WORDS: usize = (TRANSITION_BITS + VALUE_BITS + NEAR_POINT_BITS).div_ceil(64);

/// The kind of a written f32: its sign and whether it is zero, subnormal,
/// normal, infinite or NaN (NaN without a sign).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ValueClass {
    PlusZero,
    MinusZero,
    PlusSubnormal,
    MinusSubnormal,
    PlusNormal,
    MinusNormal,
    PlusInfinity,
    MinusInfinity,
    NaN,
}

impl ValueClass {
    const ALL: [ValueClass; 9] = [
        ValueClass::PlusZero,
        ValueClass::MinusZero,
        ValueClass::PlusSubnormal,
        ValueClass::MinusSubnormal,
        ValueClass::PlusNormal,
        ValueClass::MinusNormal,
        ValueClass::PlusInfinity,
        ValueClass::MinusInfinity,
        ValueClass::NaN,
    ];

    /// The class of the f32 with bit pattern `bits`.
    pub fn of(bits: u32) -> ValueClass {
        let minus = bits >> 31 == 1;
        let exponent = bits >> 23 & 0xFF;
        let fraction = bits & 0x7F_FFFF;
        let (plus, negative) = match (exponent, fraction) {
            (0, 0) => (ValueClass::PlusZero, ValueClass::MinusZero),
            (0, _) => (ValueClass::PlusSubnormal, ValueClass::MinusSubnormal),
            (0xFF, 0) => (ValueClass::PlusInfinity, ValueClass::MinusInfinity),
            (0xFF, _) => return ValueClass::NaN,
            _ => (ValueClass::PlusNormal, ValueClass::MinusNormal),
        };
        if minus {
            negative
        } else {
            plus
        }
    }

    fn index(self) -> usize {
        self as usize
    }

    fn from_index(i: usize) -> Option<ValueClass> {
        ValueClass::ALL.get(i).copied()
    }

    /// How reports spell it: `+0`, `-subnormal`, `NaN`.
    pub fn label(self) -> &'static str {
        match self {
            ValueClass::PlusZero => "+0",
            ValueClass::MinusZero => "-0",
            ValueClass::PlusSubnormal => "+subnormal",
            ValueClass::MinusSubnormal => "-subnormal",
            ValueClass::PlusNormal => "+normal",
            ValueClass::MinusNormal => "-normal",
            ValueClass::PlusInfinity => "+inf",
            ValueClass::MinusInfinity => "-inf",
            ValueClass::NaN => "NaN",
        }
    }
}

/// One coverage point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Point {
    /// The controller went from state `.0` to state `.1` in one cycle.
    Transition(State, State),
    /// A write in state `.0` put a value of class `.2` in lane `.1` (0 = x).
    Value(State, u8, ValueClass),
    /// The controller went from state `.0` to state `.1` after a sum in
    /// lane x that cancelled at least `.2` x 8 bits (1 ..= 3).
    Near(State, State, u8),
}

impl Point {
    fn bit(self) -> usize {
        match self {
            Point::Transition(a, b) => usize::from(a.0) * STATES + usize::from(b.0),
            Point::Value(s, lane, class) => {
                TRANSITION_BITS
                    + (usize::from(s.0) * LANES + usize::from(lane)) * CLASSES
                    + class.index()
            }
            Point::Near(a, b, level) => {
                TRANSITION_BITS
                    + VALUE_BITS
                    + (usize::from(level) - 1) * TRANSITION_BITS
                    + usize::from(a.0) * STATES
                    + usize::from(b.0)
            }
        }
    }

    fn of_bit(bit: usize) -> Option<Point> {
        if bit < TRANSITION_BITS {
            let state = |i: usize| State(i as u16);
            return Some(Point::Transition(state(bit / STATES), state(bit % STATES)));
        }
        let v = bit - TRANSITION_BITS;
        if v >= VALUE_BITS {
            let n = v - VALUE_BITS;
            let level = n / TRANSITION_BITS + 1;
            if level > usize::from(NEAR_LEVELS) {
                return None;
            }
            let t = n % TRANSITION_BITS;
            let state = |i: usize| State(i as u16);
            return Some(Point::Near(
                state(t / STATES),
                state(t % STATES),
                level as u8,
            ));
        }
        let class = ValueClass::from_index(v % CLASSES)?;
        let slot = v / CLASSES;
        Some(Point::Value(
            State((slot / LANES) as u16),
            (slot % LANES) as u8,
            class,
        ))
    }
}

/// A state as rtl/cover/pp_ctrl.transitions names it: `NORM_SCALE`.
fn state_name(s: State) -> String {
    isa::state_name(s.0).map_or_else(|| isa::state_label(s.0), String::from)
}

impl fmt::Display for Point {
    /// `DOT_3 -> PIX_DONE`, `NORM_SCALE.y -subnormal`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Point::Transition(a, b) => write!(f, "{} -> {}", state_name(*a), state_name(*b)),
            Point::Value(s, lane, class) => write!(
                f,
                "{}.{} {}",
                state_name(*s),
                isa::LANE_NAMES[usize::from(*lane)],
                class.label()
            ),
            Point::Near(a, b, level) => write!(
                f,
                "{} -> {} near: x cancelled {}{} bits",
                state_name(*a),
                state_name(*b),
                i32::from(*level) * NEAR_BITS,
                if *level == NEAR_LEVELS { "+" } else { "" }
            ),
        }
    }
}

/// A set of points: what one pixel, a scene or a whole corpus reached.
#[derive(Clone, PartialEq, Eq)]
pub struct Coverage {
    bits: Box<[u64; WORDS]>,
}

impl Default for Coverage {
    fn default() -> Coverage {
        Coverage::new()
    }
}

impl fmt::Debug for Coverage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Coverage({} points)", self.len())
    }
}

impl Coverage {
    pub fn new() -> Coverage {
        Coverage {
            bits: Box::new([0; WORDS]),
        }
    }

    /// Marks `point` reached.
    pub fn insert(&mut self, point: Point) {
        let b = point.bit();
        self.bits[b / 64] |= 1 << (b % 64);
    }

    pub fn contains(&self, point: Point) -> bool {
        let b = point.bit();
        self.bits[b / 64] >> (b % 64) & 1 == 1
    }

    /// Points reached.
    pub fn len(&self) -> usize {
        self.bits.iter().map(|w| w.count_ones() as usize).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.bits.iter().all(|&w| w == 0)
    }

    /// Adds every point of `other`.
    pub fn merge(&mut self, other: &Coverage) {
        for (a, b) in self.bits.iter_mut().zip(other.bits.iter()) {
            *a |= b;
        }
    }

    /// The points of `other` that `self` lacks.
    pub fn new_in(&self, other: &Coverage) -> usize {
        self.bits
            .iter()
            .zip(other.bits.iter())
            .map(|(a, b)| (b & !a).count_ones() as usize)
            .sum()
    }

    /// Every point, in bit order: the transitions by from-state, then the
    /// value classes by state and lane, then the near misses by level.
    pub fn points(&self) -> impl Iterator<Item = Point> + '_ {
        self.bits.iter().enumerate().flat_map(|(w, &word)| {
            (0..64)
                .filter(move |i| word >> i & 1 == 1)
                .filter_map(move |i| Point::of_bit(w * 64 + i))
        })
    }

    /// Adds one pixel's path: its instructions' steps in issue order
    /// ([`super::Processor::render_pixel_covered`]).
    pub fn add_path(&mut self, steps: &[Step]) {
        let mut from = State::IDLE;
        let mut near = 0;
        for step in steps {
            self.insert(Point::Transition(from, step.state));
            for level in 1..=near {
                self.insert(Point::Near(from, step.state, level));
            }
            if step.cycles > 1 {
                self.insert(Point::Transition(step.state, step.state));
            }
            from = step.state;
            near = step.near;
        }
        self.insert(Point::Transition(from, State::PIX_DONE));
        for level in 1..=near {
            self.insert(Point::Near(from, State::PIX_DONE, level));
        }
        self.insert(Point::Transition(State::PIX_DONE, State::IDLE));
    }

    /// Adds one register-file write's value classes.
    pub fn add_write(&mut self, event: &TraceEvent) {
        for lane in 0..LANES {
            if event.lanes >> lane & 1 == 1 {
                self.insert(Point::Value(
                    State(event.state),
                    lane as u8,
                    ValueClass::of(event.values[lane]),
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_classes_follow_the_bit_pattern() {
        let cases = [
            (0x0000_0000, ValueClass::PlusZero),
            (0x8000_0000, ValueClass::MinusZero),
            (0x0000_0001, ValueClass::PlusSubnormal),
            (0x8010_0000, ValueClass::MinusSubnormal),
            (0x0080_0000, ValueClass::PlusNormal),
            (0xBF80_0000, ValueClass::MinusNormal),
            (0x7F80_0000, ValueClass::PlusInfinity),
            (0xFF80_0000, ValueClass::MinusInfinity),
            (0x7FC0_0000, ValueClass::NaN),
            (0xFF80_0001, ValueClass::NaN),
        ];
        for (bits, class) in cases {
            assert_eq!(ValueClass::of(bits), class, "{bits:#010x}");
        }
    }

    #[test]
    fn every_point_has_its_own_bit_and_reads_back() {
        let mut seen = std::collections::HashSet::new();
        let mut all = Coverage::new();
        for a in 0..STATES as u16 {
            for b in 0..STATES as u16 {
                let p = Point::Transition(State(a), State(b));
                assert!(seen.insert(p.bit()));
                assert_eq!(Point::of_bit(p.bit()), Some(p));
                all.insert(p);
            }
            for lane in 0..LANES as u8 {
                for class in ValueClass::ALL {
                    let p = Point::Value(State(a), lane, class);
                    assert!(seen.insert(p.bit()));
                    assert_eq!(Point::of_bit(p.bit()), Some(p));
                    all.insert(p);
                }
            }
            for b in 0..STATES as u16 {
                for level in 1..=NEAR_LEVELS {
                    let p = Point::Near(State(a), State(b), level);
                    assert!(seen.insert(p.bit()));
                    assert_eq!(Point::of_bit(p.bit()), Some(p));
                    all.insert(p);
                }
            }
        }
        assert!(seen.iter().all(|&b| b < WORDS * 64));
        assert_eq!(all.len(), seen.len());
        assert_eq!(all.points().count(), seen.len());
    }

    #[test]
    fn a_path_runs_from_idle_through_its_states_to_pix_done() {
        let step = |state, cycles| Step {
            state,
            cycles,
            near: 0,
        };
        let mut c = Coverage::new();
        c.add_path(&[
            step(State::PRI_ITOF, 1),
            step(State::NORM_ROOTS, 8),
            step(State::DOT_3, 1),
        ]);
        let mut got: Vec<String> = c.points().map(|p| p.to_string()).collect();
        got.sort();
        assert_eq!(
            got,
            [
                "DOT_3 -> PIX_DONE",
                "IDLE -> PRI_ITOF",
                "NORM_ROOTS -> DOT_3",
                "NORM_ROOTS -> NORM_ROOTS",
                "PIX_DONE -> IDLE",
                "PRI_ITOF -> NORM_ROOTS",
            ]
        );
    }

    #[test]
    fn merging_counts_only_what_is_new() {
        let p = Point::Transition(State::IDLE, State::PRI_ITOF);
        let q = Point::Value(State::DOT_3, 0, ValueClass::MinusZero);
        let (mut a, mut b) = (Coverage::new(), Coverage::new());
        a.insert(p);
        b.insert(p);
        b.insert(q);
        assert_eq!(a.new_in(&b), 1);
        assert_eq!(b.new_in(&a), 0);
        a.merge(&b);
        assert_eq!(a, b);
        assert_eq!(a.len(), 2);
        assert!(a.contains(q));
    }

    #[test]
    fn a_near_miss_marks_its_transition_at_every_level_up_to_its_own() {
        let mut c = Coverage::new();
        c.add_path(&[
            Step {
                state: State::ISECT_4,
                cycles: 1,
                near: 2,
            },
            Step {
                state: State::RF_CSQRT,
                cycles: 1,
                near: 3,
            },
        ]);
        let near: Vec<String> = c
            .points()
            .filter(|p| matches!(p, Point::Near(..)))
            .map(|p| p.to_string())
            .collect();
        assert_eq!(
            near,
            [
                "ISECT_4 -> RF_CSQRT near: x cancelled 8 bits",
                "RF_CSQRT -> PIX_DONE near: x cancelled 8 bits",
                "ISECT_4 -> RF_CSQRT near: x cancelled 16 bits",
                "RF_CSQRT -> PIX_DONE near: x cancelled 16 bits",
                "RF_CSQRT -> PIX_DONE near: x cancelled 24+ bits",
            ]
        );
    }

    #[test]
    fn a_sum_is_near_by_the_binades_it_cancels() {
        use super::super::core::near;
        let cases = [
            (1.0, -0.5, 0),                                   // 1 bit
            (1.0, -(1.0 - 2f32.powi(-8)), 1),                 // 2^-8: 8 bits
            (1.0, -(1.0 - 2f32.powi(-7)), 0),                 // 7 bits
            (16_777_216.0, -16_777_215.0, 3),                 // 24 bits
            (3.0e5, -(3.0e5 - 0.03125), 2),                   // 2^18 to 2^-5: 23 bits
            (1.0, -(1.0 - 2f32.powi(-16)), 2),                // 16 bits
            (2.5, -2.5, 3),                                   // exactly 0
            (0.0, 0.0, 0),                                    // nothing to cancel
            (1.0, f32::INFINITY, 0),                          // not finite
            (f32::MIN_POSITIVE, -f32::MIN_POSITIVE * 0.5, 0), // into the subnormals: 1 bit
            (
                f32::MIN_POSITIVE,
                -f32::MIN_POSITIVE * (1.0 - 2f32.powi(-20)),
                2,
            ), // 20 bits, subnormal
        ];
        for (p, q, level) in cases {
            assert_eq!(near(p, q, p + q), level, "{p:e} + {q:e} = {:e}", p + q);
        }
    }
}
