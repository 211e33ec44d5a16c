//! Co-simulation of the fast processor's ALU (rtl/fast/fast_alu.v) against
//! golden's micro-op ALU, opcode by opcode, contexts interleaved.
//!
//! A pass means every opcode's result came out of the verilated ALU exactly
//! the promised latency after it entered, in order, with its context, its
//! write bit, the lanes it defines bit for bit golden's and their flags those of
//! golden's result; and exp_ready was what the contract says in every cycle.
//! The schedules aim at the pipeline's hazards: every context issuing again
//! the very cycle its last result shows (back-to-back dependent opcodes
//! through F), random interleavings of one to many contexts with bubbles,
//! and EXPs as close together as the shared fp_exp allows. The `checker_*`
//! tests prove the comparison fails on a wrong result, a wrong latency, and
//! a schedule that breaks either rule of the contract.

use golden::fp::Method;
use golden::micro::alu::fast_latency;
use golden::micro::isa::op;
use rtcosim::check::alu_check::{check, Plan, Schedule};
use rtcosim::design::fast_alu::FastAlu;

const SEED: u64 = 0x2011_0607;

fn agrees(alu: &mut FastAlu, plan: Plan, seed: u64) -> Schedule {
    let (recip, sqrt, _) = alu.build();
    let schedule = Schedule::random(plan, recip, sqrt, seed);
    let ran = alu.run(&schedule.cycles).expect("running the fast ALU");
    let bad = check(&schedule, &ran, alu.latency());
    assert!(
        bad.is_empty(),
        "{plan:?} seed {seed:#x}: {} mismatches, first: {:#?}",
        bad.len(),
        &bad[..bad.len().min(5)]
    );
    assert_eq!(ran.out.len(), plan.ops);
    schedule
}

fn alu(recip: Method, sqrt: Method, exposure: bool) -> FastAlu {
    FastAlu::new(recip, sqrt, exposure).expect("the fast ALU variant is built")
}

/// The barrel at its tightest: as many contexts as the latency, each
/// issuing in its turn, so every opcode depends on the result that shows in
/// the very cycle it enters; and with more contexts than that (32).
#[test]
fn barrel_rotation_back_to_back() {
    for (recip, sqrt) in [(Method::Exact, Method::Exact), (Method::Fast, Method::Fast)] {
        let mut alu = alu(recip, sqrt, true);
        let latency = alu.latency();
        for contexts in [latency as u8, 32] {
            let plan = Plan {
                rotate: true,
                ..Plan::new(contexts, 100_000, true)
            };
            agrees(&mut alu, plan, SEED ^ u64::from(contexts));
        }
    }
}

/// Random interleavings of 1, 2, 3, 7 and 32 contexts, with and without
/// bubbles: a context finishing while others wait, and a lone context
/// paying the whole latency for each opcode; with many contexts, EXPs as
/// close as the shared fp_exp allows (one in three opcodes).
#[test]
fn random_interleavings() {
    let mut alu = alu(Method::Exact, Method::Exact, true);
    for (i, contexts) in [1u8, 2, 3, 7, 32].into_iter().enumerate() {
        for bubbles in [0, 40] {
            let plan = Plan {
                bubbles,
                exp_share: if contexts > 3 { 33 } else { 0 },
                ..Plan::new(contexts, 20_000, true)
            };
            let schedule = agrees(&mut alu, plan, SEED + (i as u64) * 100 + u64::from(bubbles));
            if plan.exp_share > 0 {
                let exps: Vec<u64> = schedule
                    .expected
                    .iter()
                    .filter(|e| e.op == op::EXP)
                    .map(|e| e.cycle)
                    .collect();
                assert!(
                    exps.windows(2).any(|w| w[1] - w[0] == 3),
                    "no EXPs three cycles apart"
                );
            }
        }
    }
}

/// The build without exposure: no fp_exp, a shorter latency when fp_exp
/// was the slowest unit, exp_ready always high; and EXP there gives +0.
#[test]
fn without_exposure() {
    let mut alu = alu(Method::Exact, Method::Exact, false);
    assert_eq!(alu.latency(), fast_latency(false));
    let plan = Plan {
        rotate: true,
        ..Plan::new(fast_latency(false) as u8, 50_000, false)
    };
    agrees(&mut alu, plan, SEED);
    // An EXP on this build: documented as +0 (a scene with exposure needs
    // the other build).
    let mut schedule = Schedule::random(Plan::new(1, 1, false), Method::Exact, Method::Exact, SEED);
    schedule.cycles[0].op = op::EXP;
    schedule.cycles[0].a = [1.0f32.to_bits(); 3];
    let ran = alu.run(&schedule.cycles).unwrap();
    assert_eq!(ran.out.len(), 1);
    assert_eq!(ran.out[0].y, [0; 3]);
    assert!(ran.out[0].writes, "EXP writes the register file");
}

/// A result changed in one lane is reported as exactly that opcode.
#[test]
fn checker_catches_a_wrong_result() {
    let mut alu = alu(Method::Exact, Method::Exact, true);
    let plan = Plan::new(4, 2_000, true);
    let schedule = Schedule::random(plan, Method::Exact, Method::Exact, SEED);
    let mut ran = alu.run(&schedule.cycles).unwrap();
    assert!(check(&schedule, &ran, alu.latency()).is_empty());
    ran.out[1234].y[1] ^= 1;
    let bad = check(&schedule, &ran, alu.latency());
    assert_eq!(bad.len(), 1, "{bad:#?}");
    assert_eq!(bad[0].index, Some(1234));
    assert!(bad[0].what.contains("lane y"), "{}", bad[0].what);
}

/// Read one cycle early or late, every result is reported.
#[test]
fn checker_catches_a_wrong_latency() {
    let mut alu = alu(Method::Exact, Method::Exact, true);
    let plan = Plan::new(8, 1_000, true);
    let schedule = Schedule::random(plan, Method::Exact, Method::Exact, SEED);
    let ran = alu.run(&schedule.cycles).unwrap();
    for latency in [alu.latency() - 1, alu.latency() + 1] {
        let bad = check(&schedule, &ran, latency);
        let named: std::collections::BTreeSet<_> = bad.iter().filter_map(|m| m.index).collect();
        assert_eq!(named.len(), 1_000, "latency {latency}");
    }
}

/// A context issuing two cycles before its last result shows reads F
/// before that result's write: the dependent opcodes of the F chains come
/// out wrong, and the checker names them. (One cycle early still works:
/// F is written the cycle before the result shows; the contract keeps that
/// cycle as margin.)
#[test]
fn checker_catches_an_f_hazard() {
    let mut alu = alu(Method::Exact, Method::Exact, true);
    let plan = Plan {
        rotate: true,
        gap: alu.latency() - 2,
        ..Plan::new((alu.latency() - 2) as u8, 5_000, true)
    };
    let schedule = Schedule::random(plan, Method::Exact, Method::Exact, SEED);
    let ran = alu.run(&schedule.cycles).unwrap();
    let bad = check(&schedule, &ran, alu.latency());
    let readers = [op::DOT2, op::DOT3, op::ISECT2, op::ISECT3, op::ISECT4];
    assert!(bad.len() > 100, "only {} mismatches", bad.len());
    for m in &bad {
        let e = schedule.expected[m.index.expect("about an opcode")];
        assert!(readers.contains(&e.op), "{}", m.what);
    }
}

/// EXPs one cycle apart break the shared fp_exp's queue: their results
/// are wrong, and exp_ready was low when the second entered.
#[test]
fn checker_catches_an_exp_collision() {
    let mut alu = alu(Method::Exact, Method::Exact, true);
    let plan = Plan {
        exp_gap: 1,
        exp_share: 50,
        ..Plan::new(32, 5_000, true)
    };
    let schedule = Schedule::random(plan, Method::Exact, Method::Exact, SEED);
    let ran = alu.run(&schedule.cycles).unwrap();
    let bad = check(&schedule, &ran, alu.latency());
    let exp_results = bad
        .iter()
        .filter(|m| m.index.is_some_and(|i| schedule.expected[i].op == op::EXP))
        .count();
    assert!(exp_results > 10, "{bad:#?}");
    assert!(
        ran.exp_ready
            .iter()
            .zip(&schedule.cycles)
            .any(|(&ready, c)| c.valid && c.op == op::EXP && !ready),
        "an EXP entered while exp_ready was low"
    );
}

/// A variant that was not built is a clear error naming it.
#[test]
fn missing_variant_is_a_clear_error() {
    let err = FastAlu::new(Method::Fast, Method::Exact, false)
        .err()
        .expect("not built");
    let text = err.to_string();
    assert!(
        text.contains("Vfast_alu_fast_exact_noexp is not a model of the table"),
        "{text}"
    );
}
