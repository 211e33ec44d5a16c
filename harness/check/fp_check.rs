//! Co-simulation of one float unit against its golden model.
//!
//! Operands stream through the verilated unit in chunks, one model per worker
//! thread. Every result is compared with the golden model's bits (a mismatch
//! is anything but the same bits, NaNs included: both sides give the
//! canonical NaN, see [`golden::fp`]), every
//! operation's cycle count with the latency the golden model promises, and
//! every result with the correctly rounded value, to measure the method's
//! error.

use crate::check::operands::{self, CHUNK};
use crate::design::fp_unit::{FpUnit, UnitError, UnitKind};
use golden::fp::{ulp_distance, UlpDistance};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// Where a check's operands come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Operands {
    /// [`operands::edge_cases`].
    Edge,
    /// `count` operands of the seeded random stream.
    Random { seed: u64, count: u64 },
    /// All 2^32 inputs (unary units only).
    Exhaustive,
    /// `count` consecutive input bit patterns from `start` (unary units
    /// only): a range of an exhaustive sweep, such as `fp_exp`'s x in
    /// [-104, -0].
    Span { start: u32, count: u64 },
}

impl Operands {
    /// How many operands the source yields for `kind`.
    pub fn count(self, kind: UnitKind) -> u64 {
        match self {
            Operands::Edge => operands::edge_cases(kind).0.len() as u64,
            Operands::Random { count, .. } => count,
            Operands::Exhaustive => 1 << 32,
            Operands::Span { count, .. } => count,
        }
    }
}

/// One operand on which the RTL and the golden model disagree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mismatch {
    pub a: u32,
    pub b: u32,
    pub rtl: u32,
    pub golden: u32,
    pub distance: UlpDistance,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "a={:#010x} ({:e}) b={:#010x} ({:e}): rtl {:#010x} ({:e}), golden {:#010x} ({:e}), {}",
            self.a,
            f32::from_bits(self.a),
            self.b,
            f32::from_bits(self.b),
            self.rtl,
            f32::from_bits(self.rtl),
            self.golden,
            f32::from_bits(self.golden),
            self.distance
        )
    }
}

/// What a check found.
#[derive(Debug, Clone)]
pub struct CheckReport {
    pub unit: UnitKind,
    pub operands: u64,
    pub mismatches: u64,
    /// The first mismatches, in stream order (at most [`CheckReport::KEEP`]).
    pub first_mismatches: Vec<Mismatch>,
    /// Operations whose cycle count differs from [`UnitKind::latency`].
    pub latency_violations: u64,
    /// Fewest and most clock edges any operation took.
    pub cycles: Option<(u32, u32)>,
    /// Largest distance of an RTL result from the correctly rounded one.
    pub worst_error: UlpDistance,
    /// Time spent inside the verilated model, summed over threads.
    pub rtl_time: Duration,
}

impl CheckReport {
    /// Mismatches kept for reporting.
    pub const KEEP: usize = 10;

    fn empty(unit: UnitKind) -> CheckReport {
        CheckReport {
            unit,
            operands: 0,
            mismatches: 0,
            first_mismatches: Vec::new(),
            latency_violations: 0,
            cycles: None,
            worst_error: UlpDistance::Ulps(0),
            rtl_time: Duration::ZERO,
        }
    }

    /// Folds `later` (operands after this report's) into this report.
    pub fn merge(mut self, later: CheckReport) -> CheckReport {
        self.operands += later.operands;
        self.mismatches += later.mismatches;
        let room = Self::KEEP.saturating_sub(self.first_mismatches.len());
        self.first_mismatches
            .extend(later.first_mismatches.into_iter().take(room));
        self.latency_violations += later.latency_violations;
        self.cycles = match (self.cycles, later.cycles) {
            (Some((a, b)), Some((c, d))) => Some((a.min(c), b.max(d))),
            (x, None) | (None, x) => x,
        };
        self.worst_error = self.worst_error.max(later.worst_error);
        self.rtl_time += later.rtl_time;
        self
    }

    /// True when every result and every cycle count agreed.
    pub fn passed(&self) -> bool {
        self.mismatches == 0 && self.latency_violations == 0 && self.operands > 0
    }

    /// Verilated evaluations per second of one model (operands over the time
    /// spent inside the models).
    pub fn evals_per_second(&self) -> f64 {
        self.operands as f64 / self.rtl_time.as_secs_f64().max(1e-9)
    }
}

/// Checks one batch on `unit`, comparing with `golden` (usually
/// [`UnitKind::golden`]; tests pass a wrong model to prove mismatches are caught).
pub fn check_batch(
    unit: &mut FpUnit,
    golden: &dyn Fn(u32, u32) -> u32,
    a: &[u32],
    b: &[u32],
) -> Result<CheckReport, UnitError> {
    let kind = unit.kind();
    let start = Instant::now();
    let (y, cycles) = unit.eval(a, b)?;
    let mut report = CheckReport::empty(kind);
    report.rtl_time = start.elapsed();
    report.operands = a.len() as u64;
    for i in 0..a.len() {
        let bi = if kind.is_binary() { b[i] } else { 0 };
        let want = golden(a[i], bi);
        let distance = ulp_distance(f32::from_bits(y[i]), f32::from_bits(want), false);
        if y[i] != want {
            report.mismatches += 1;
            if report.first_mismatches.len() < CheckReport::KEEP {
                report.first_mismatches.push(Mismatch {
                    a: a[i],
                    b: bi,
                    rtl: y[i],
                    golden: want,
                    distance,
                });
            }
        }
        let exact = kind.correctly_rounded(a[i], bi);
        report.worst_error = report.worst_error.max(ulp_distance(
            f32::from_bits(y[i]),
            f32::from_bits(exact),
            false,
        ));
        if cycles[i] != kind.latency() {
            report.latency_violations += 1;
        }
        report.cycles = Some(match report.cycles {
            Some((lo, hi)) => (lo.min(cycles[i]), hi.max(cycles[i])),
            None => (cycles[i], cycles[i]),
        });
    }
    Ok(report)
}

/// Streams `source` through `kind` on every rayon thread (one model each)
/// and compares with the golden model. `progress` is called with the number
/// of operands each finished chunk held.
pub fn run(
    kind: UnitKind,
    source: Operands,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<CheckReport, UnitError> {
    let golden = |a, b| kind.golden(a, b);
    let chunk_operands = |index: u64| -> (Vec<u32>, Vec<u32>) {
        match source {
            Operands::Edge => operands::edge_cases(kind),
            Operands::Random { seed, count } => {
                let len = (count - index * CHUNK as u64).min(CHUNK as u64) as usize;
                operands::random_chunk(kind, seed, index, len)
            }
            Operands::Exhaustive => {
                let start = (index * CHUNK as u64) as u32;
                (
                    (0..CHUNK as u32).map(|i| start.wrapping_add(i)).collect(),
                    Vec::new(),
                )
            }
            Operands::Span { start, count } => {
                let first = start.wrapping_add((index * CHUNK as u64) as u32);
                let len = (count - index * CHUNK as u64).min(CHUNK as u64) as u32;
                (
                    (0..len).map(|i| first.wrapping_add(i)).collect(),
                    Vec::new(),
                )
            }
        }
    };
    let chunks = match source {
        Operands::Edge => 1,
        Operands::Random { count, .. } => count.div_ceil(CHUNK as u64),
        Operands::Exhaustive | Operands::Span { .. } => {
            if kind.is_binary() {
                return Err(UnitError::Eval {
                    unit: kind,
                    message: "an exhaustive sweep needs a unary unit (2^64 pairs would not finish)"
                        .into(),
                });
            }
            source.count(kind).div_ceil(CHUNK as u64)
        }
    };
    let reports: Vec<Result<CheckReport, UnitError>> = (0..chunks)
        .into_par_iter()
        .map_init(
            || FpUnit::new(kind),
            |unit, index| {
                let unit = unit.as_mut().map_err(|e| UnitError::Build {
                    unit: kind,
                    message: e.to_string(),
                })?;
                let (a, b) = chunk_operands(index);
                let report = check_batch(unit, &golden, &a, &b)?;
                progress(report.operands);
                Ok(report)
            },
        )
        .collect();
    reports
        .into_iter()
        .try_fold(CheckReport::empty(kind), |acc, r| Ok(acc.merge(r?)))
}
