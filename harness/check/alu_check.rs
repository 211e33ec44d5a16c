//! The fast processor's ALU against golden's micro-op ALU
//! ([`golden::micro::alu::Alu::apply`]), opcode by opcode, with pixel
//! contexts interleaved as the barrel interleaves them.
//!
//! A [`Schedule`] is a seeded sequence of cycles that keeps the ALU's
//! contract (`crate::design::fast_alu`: a context's next opcode no earlier
//! than its last one's result, [`Schedule::min_gap`]; EXP only while
//! `exp_ready`), or, for the checker's own tests, breaks it on purpose,
//! built together with golden's expected results; [`check`] compares what
//! the port showed ([`Ran`]) with them and names every difference.

use crate::design::fast_alu::{AluIn, Ran};
use golden::fp::Method;
use golden::micro::alu::{fast_latency, Alu};
use golden::micro::isa::{op, op_name, Lanes};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// One opcode of a schedule and golden's result for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Expected {
    /// The cycle it entered.
    pub cycle: u64,
    pub ctx: u8,
    pub op: u8,
    /// Whether it writes the register file.
    pub writes: bool,
    /// The result (+0 in every lane for an opcode that writes nothing).
    pub y: [u32; 3],
    /// The lanes of `y` the opcode defines ([`Alu::result_lanes`]): the
    /// others, and their flags, are not compared.
    pub lanes: Lanes,
}

impl Expected {
    /// The flags of the result, bit i for lane i: (neg, pos, sign), on
    /// the defined lanes (0 elsewhere).
    pub fn flags(&self) -> (u8, u8, u8) {
        let (mut neg, mut pos, mut sign) = (0, 0, 0);
        for (i, &v) in self
            .y
            .iter()
            .enumerate()
            .filter(|&(i, _)| self.lanes.has(i))
        {
            let f = f32::from_bits(v);
            neg |= u8::from(f < 0.0) << i;
            pos |= u8::from(f > 0.0) << i;
            sign |= u8::from(f.is_sign_negative()) << i;
        }
        (neg, pos, sign)
    }
}

/// How a [`Schedule`] picks its cycles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Plan {
    /// Pixel contexts taking turns, at most 32 (the RTL's 2^CTX_BITS).
    pub contexts: u8,
    /// Opcodes in all.
    pub ops: usize,
    /// `true`: context `cycle mod contexts` issues when its turn comes (the
    /// barrel); `false`: a random context among those free.
    pub rotate: bool,
    /// Percent of cycles left empty (a bubble) where an opcode could go.
    pub bubbles: u32,
    /// Cycles between a context's opcodes, at least: the contract is the
    /// ALU's latency ([`Schedule::min_gap`]); less breaks it.
    pub gap: u32,
    /// Cycles between EXPs, at least: 3 keeps the contract, less breaks it.
    pub exp_gap: u32,
    /// Percent of a context's opcodes outside the F chains that are EXP
    /// where it may enter (else EXP is one code of 64).
    pub exp_share: u32,
    /// The build has fp_exp (EXP is issued).
    pub exposure: bool,
}

impl Plan {
    /// A plan keeping the contract of a build with `exposure`.
    pub fn new(contexts: u8, ops: usize, exposure: bool) -> Plan {
        Plan {
            contexts,
            ops,
            rotate: false,
            bubbles: 0,
            gap: Schedule::min_gap(exposure),
            exp_gap: 3,
            exp_share: 0,
            exposure,
        }
    }
}

/// A seeded sequence of cycles for the ALU and golden's results for it.
#[derive(Debug, Clone)]
pub struct Schedule {
    pub cycles: Vec<AluIn>,
    pub expected: Vec<Expected>,
    /// exp_ready as the contract says it must be in each cycle: no EXP in
    /// the two cycles before.
    pub exp_ready: Vec<bool>,
}

/// Opcodes that read F, and the chains through F the pixel program uses.
const READS_F: [u8; 5] = [op::DOT2, op::DOT3, op::ISECT2, op::ISECT3, op::ISECT4];
const DOT_CHAIN: [u8; 3] = [op::DOT1, op::DOT2, op::DOT3];
const ISECT_CHAIN: [u8; 4] = [op::ISECT1, op::ISECT2, op::ISECT3, op::ISECT4];

impl Schedule {
    /// The least gap between a context's opcodes the contract allows.
    pub const fn min_gap(exposure: bool) -> u32 {
        fast_latency(exposure)
    }

    /// Builds a schedule by `plan` from `seed`, running golden's ALU (one
    /// per context) alongside. Opcodes: the F chains of the pixel program
    /// (DOT1..3, ISECT1..4) and every other code of the 6-bit field (the
    /// unassigned ones are NOPs), F's readers only once F was written;
    /// operands: edge values (`harness::operands`), random bit patterns,
    /// and small numbers, lane by lane.
    pub fn random(plan: Plan, recip: Method, sqrt: Method, seed: u64) -> Schedule {
        assert!(
            (1..=32).contains(&plan.contexts),
            "contexts must be 1..=32 (the RTL's 2^CTX_BITS)"
        );
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let edges = crate::check::operands::edge_values();
        let k = usize::from(plan.contexts);
        let mut alus: Vec<Alu> = (0..k).map(|_| Alu::new(recip, sqrt)).collect();
        // Per context: the cycle it may issue from, and where it is in an F chain.
        let mut free_at = vec![0u64; k];
        let mut chain: Vec<Option<(&[u8], usize)>> = vec![None; k];
        let mut last_exp: Option<u64> = None;
        let mut s = Schedule {
            cycles: Vec::new(),
            expected: Vec::new(),
            exp_ready: Vec::new(),
        };
        let mut cycle = 0u64;
        while s.expected.len() < plan.ops {
            s.exp_ready
                .push(!plan.exposure || last_exp.map_or(true, |e| cycle >= e + 3));
            let free: Vec<usize> = (0..k).filter(|&c| free_at[c] <= cycle).collect();
            let pick = if plan.rotate {
                let c = (cycle % k as u64) as usize;
                free.contains(&c).then_some(c)
            } else if free.is_empty() {
                None
            } else {
                Some(free[rng.random_range(0..free.len())])
            };
            let Some(ctx) = pick.filter(|_| rng.random_range(0..100) >= plan.bubbles) else {
                s.cycles.push(AluIn::default());
                cycle += 1;
                continue;
            };
            let exp_ok =
                plan.exposure && last_exp.map_or(true, |e| cycle >= e + u64::from(plan.exp_gap));
            let exp_ok = exp_ok.then_some(plan.exp_share);
            let code = next_op(&mut rng, &mut chain[ctx], alus[ctx].f_written(), exp_ok);
            if code == op::EXP {
                last_exp = Some(cycle);
            }
            let mut lanes = || std::array::from_fn::<u32, 3, _>(|_| operand(&mut rng, &edges));
            let (a, b) = (lanes(), lanes());
            let (px, py) = (rng.random_range(0..4096u32), rng.random_range(0..4096u32));
            let fa = a.map(f32::from_bits);
            let fb = b.map(f32::from_bits);
            let y = alus[ctx].apply(code, fa, fb, px, py);
            s.cycles.push(AluIn {
                valid: true,
                ctx: ctx as u8,
                op: code,
                a,
                b,
                ix: px,
                iy: (py as i32).wrapping_neg() as u32,
            });
            s.expected.push(Expected {
                cycle,
                ctx: ctx as u8,
                op: code,
                writes: y.is_some(),
                y: y.unwrap_or([0.0; 3]).map(f32::to_bits),
                lanes: Alu::result_lanes(code),
            });
            free_at[ctx] = cycle + u64::from(plan.gap);
            cycle += 1;
        }
        s
    }
}

/// The next opcode of a context: the next of its F chain if it is in one
/// (sometimes abandoned, as a pixel's program never does, to mix them);
/// else, one time in four, the start of a chain; else any code, F's
/// readers only once F was written, EXP only where it may enter
/// (`exp_share`: `Some` of the percent of EXPs wanted).
fn next_op(
    rng: &mut ChaCha8Rng,
    chain: &mut Option<(&'static [u8], usize)>,
    f_written: bool,
    exp_share: Option<u32>,
) -> u8 {
    if let Some((ops, at)) = *chain {
        if at < ops.len() && rng.random_range(0..20) > 0 {
            *chain = Some((ops, at + 1));
            return ops[at];
        }
        *chain = None;
    }
    if rng.random_range(0..4) == 0 {
        let ops: &'static [u8] = if rng.random() {
            &DOT_CHAIN
        } else {
            &ISECT_CHAIN
        };
        *chain = Some((ops, 1));
        return ops[0];
    }
    if exp_share.is_some_and(|share| rng.random_range(0..100) < share) {
        return op::EXP;
    }
    loop {
        let code = rng.random_range(0..64u8);
        if (READS_F.contains(&code) && !f_written) || (code == op::EXP && exp_share.is_none()) {
            continue;
        }
        return code;
    }
}

/// One operand lane: an edge value, random bits, or a small number of
/// either sign (so that sums and products stay finite and interesting).
fn operand(rng: &mut ChaCha8Rng, edges: &[u32]) -> u32 {
    match rng.random_range(0..3) {
        0 => edges[rng.random_range(0..edges.len())],
        1 => rng.random(),
        _ => {
            let v: f32 = rng.random_range(-64.0..64.0);
            v.to_bits()
        }
    }
}

/// A difference between the port and golden.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// The opcode's index in the schedule's `expected`, if it is about one.
    pub index: Option<usize>,
    pub what: String,
}

/// Compares what the port showed in `ran` with `schedule`'s expected
/// results, `latency` cycles after each opcode entered: every result, in
/// order, its context, whether it writes, its three lanes bit for bit, its
/// flags, and exp_ready in every cycle (where `exposure`). Returns every
/// difference (empty: the RTL agreed).
pub fn check(schedule: &Schedule, ran: &Ran, latency: u32) -> Vec<Mismatch> {
    let mut bad = Vec::new();
    for (i, e) in schedule.expected.iter().enumerate() {
        let name = op_name(e.op).map_or_else(|| format!("op {}", e.op), str::to_string);
        let here = format!(
            "opcode #{i} ({name}, context {}, entered in cycle {})",
            e.ctx, e.cycle
        );
        let Some(o) = ran.out.get(i) else {
            bad.push(Mismatch {
                index: Some(i),
                what: format!("{here}: no result showed"),
            });
            continue;
        };
        let want_cycle = e.cycle + u64::from(latency);
        let mut say = |what: String| {
            bad.push(Mismatch {
                index: Some(i),
                what: format!("{here}: {what}"),
            })
        };
        if o.cycle != want_cycle {
            say(format!(
                "result showed in cycle {}, not {want_cycle}",
                o.cycle
            ));
        }
        if o.ctx != e.ctx {
            say(format!("result names context {}", o.ctx));
        }
        if o.writes != e.writes {
            say(format!("writes is {}, golden {}", o.writes, e.writes));
        }
        for lane in (0..3).filter(|&i| e.lanes.has(i)) {
            if o.y[lane] != e.y[lane] {
                say(format!(
                    "lane {}: RTL {:#010x} ({:e}), golden {:#010x} ({:e})",
                    ['x', 'y', 'z'][lane],
                    o.y[lane],
                    f32::from_bits(o.y[lane]),
                    e.y[lane],
                    f32::from_bits(e.y[lane])
                ));
            }
        }
        let (neg, pos, sign) = e.flags();
        let m = e.lanes.0;
        if (o.neg & m, o.pos & m, o.sign & m) != (neg, pos, sign) {
            say(format!(
                "flags neg/pos/sign {:03b}/{:03b}/{:03b}, from golden's result {neg:03b}/{pos:03b}/{sign:03b} (lanes {m:03b})",
                o.neg & m,
                o.pos & m,
                o.sign & m
            ));
        }
    }
    for extra in ran.out.iter().skip(schedule.expected.len()) {
        bad.push(Mismatch {
            index: None,
            what: format!(
                "a result no opcode asked for showed in cycle {} (context {})",
                extra.cycle, extra.ctx
            ),
        });
    }
    for (cycle, (&rtl, &want)) in ran.exp_ready.iter().zip(&schedule.exp_ready).enumerate() {
        if rtl != want {
            bad.push(Mismatch {
                index: None,
                what: format!("exp_ready {rtl} in cycle {cycle}, the contract says {want}"),
            });
        }
    }
    bad
}
