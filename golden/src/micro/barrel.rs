//! The fast processor's cycle rule (docs/fast.md, `rtl/fast/`): a barrel of
//! K pixel contexts taking turns, one micro-op a turn. The compact
//! processor's rule is in [`super`] ("The cycle rule"); this is the other
//! one, beside it, and the RTL of the fast processor is built to it.
//!
//! # The rule
//!
//! Cycle t is the turn of context `t mod K`. Pixels wait in order at the
//! processor's input. At its turn a context does exactly one thing:
//!
//! - **running, instructions left**: issues its pixel's next instruction,
//!   except an EXP while another EXP issued in one of the two cycles before
//!   (the ALU's one exponential takes an EXP's lanes in three cycles,
//!   `exp_ready`): then the turn passes, and the EXP waits for the next;
//! - **running, every instruction issued**: the done turn: the pixel's
//!   result leaves, and the context takes the next waiting pixel in the same
//!   turn if there is one (else it is idle);
//! - **idle**: takes the next waiting pixel, if any.
//!
//! Every instruction takes one turn whatever it is (the units are
//! pipelined), so a pixel of N instructions that waits for no EXP takes N +
//! 1 turns from the turn that took it to its done turn, K (N + 1) cycles;
//! with K contexts busy, the processor finishes a pixel every N + 1 cycles
//! on average. A pixel's cycles are counted from the cycle after the turn
//! that took it to its done turn inclusive (as the compact rule counts from
//! the cycle after its start edge to PIX_DONE inclusive).
//!
//! A processor whose results wait in a queue of bounded room may refuse a
//! take (`rtl/fast/fast_pp.v` takes a pixel only while fewer than 2K are
//! held); [`run_gated`] is the rule with the cycles in which takes are
//! refused given: the context then stays idle (a done turn still ends its
//! pixel). [`run`] refuses none.
//!
//! K must cover the round trip of a turn (register read, ALU, next-state
//! decision) for the rule to need no stall; that is the RTL's business, and
//! the rule does not depend on it.

use super::{OpClass, PixelResult};

/// What the rule needs of a pixel: its instructions, and where its EXP is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelWork {
    /// Instructions executed (`OpStats::instructions`).
    pub instructions: u64,
    /// The index of its EXP among them, if it has one.
    pub exp_at: Option<u64>,
}

impl PixelWork {
    /// A pixel as golden's micro-op model ran it. EXP is the exposure's
    /// middle instruction (EXPO_MUL, EXPO_EXP, EXPO_SUB, then PIX_DONE:
    /// `program::Program::expose`), so it is the second to last.
    ///
    /// Panics on a pixel with more than one EXP (the program has none).
    pub fn of(result: &PixelResult) -> PixelWork {
        let n = result.ops.instructions();
        let exps = result.ops.count_of(OpClass::Exp);
        assert!(exps <= 1, "a pixel with {exps} EXPs");
        PixelWork {
            instructions: n,
            exp_at: (exps == 1).then(|| n - 2),
        }
    }
}

/// When a pixel ran, in cycles from the first cycle (0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BarrelPixel {
    /// The context that ran it.
    pub context: u32,
    /// The turn that took it.
    pub taken: u64,
    /// Its done turn (its result leaves in this cycle).
    pub done: u64,
}

impl BarrelPixel {
    /// Its cycles: from the cycle after `taken` to `done` inclusive.
    pub fn cycles(&self) -> u64 {
        self.done - self.taken
    }
}

/// A whole sequence of pixels through the barrel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BarrelRun {
    /// Each pixel, in input order.
    pub pixels: Vec<BarrelPixel>,
    /// Cycles from the first to the last done turn inclusive.
    pub cycles: u64,
    /// Turns an EXP let pass (another EXP one or two cycles before).
    pub exp_waits: u64,
}

#[derive(Debug, Clone, Copy)]
enum Context {
    Idle,
    /// Running input pixel `pixel`, `next` instructions issued.
    Running {
        pixel: usize,
        next: u64,
    },
}

/// One processor's contexts and its EXP history: the rule, a turn at a
/// time.
#[derive(Debug, Clone)]
struct Barrel {
    ctx: Vec<Context>,
    last_exp: Option<u64>,
    exp_waits: u64,
}

/// What a turn did: the pixel it ended (its done turn), and whether it took
/// the pixel offered.
#[derive(Debug, Clone, Copy, Default)]
struct Turn {
    done: Option<usize>,
    took: bool,
}

impl Barrel {
    fn new(contexts: u32) -> Barrel {
        assert!(contexts > 0, "a barrel of no contexts");
        Barrel {
            ctx: vec![Context::Idle; contexts as usize],
            last_exp: None,
            exp_waits: 0,
        }
    }

    /// Cycle `t`, the turn of context `c`: `offer` is the pixel it may take
    /// (None: no pixel waits, or takes are refused).
    fn turn(&mut self, t: u64, c: usize, pixels: &[PixelWork], offer: Option<usize>) -> Turn {
        let take = |offer: Option<usize>| match offer {
            Some(pixel) => (Context::Running { pixel, next: 0 }, true),
            None => (Context::Idle, false),
        };
        let mut turn = Turn::default();
        let (next, took) = match self.ctx[c] {
            Context::Idle => take(offer),
            Context::Running { pixel, next } if next < pixels[pixel].instructions => {
                if pixels[pixel].exp_at == Some(next) && self.last_exp.is_some_and(|e| t <= e + 2) {
                    self.exp_waits += 1;
                    (self.ctx[c], false)
                } else {
                    if pixels[pixel].exp_at == Some(next) {
                        self.last_exp = Some(t);
                    }
                    (
                        Context::Running {
                            pixel,
                            next: next + 1,
                        },
                        false,
                    )
                }
            }
            Context::Running { pixel, .. } => {
                turn.done = Some(pixel);
                take(offer)
            }
        };
        self.ctx[c] = next;
        turn.took = took;
        turn
    }
}

/// Runs `pixels`, all waiting at cycle 0, through a barrel of `contexts`
/// contexts by the rule above.
///
/// Panics if `contexts` is 0.
pub fn run(contexts: u32, pixels: &[PixelWork]) -> BarrelRun {
    run_gated(contexts, pixels, &|_| true)
}

/// [`run`], with a take allowed only in the cycles `t` where `open(t)`.
///
/// Panics if `contexts` is 0, or if `open` stays false for 2^32 cycles in a
/// row while a pixel waits.
pub fn run_gated(contexts: u32, pixels: &[PixelWork], open: &dyn Fn(u64) -> bool) -> BarrelRun {
    let mut barrel = Barrel::new(contexts);
    let k = contexts as u64;
    let mut closed_run = 0u64;
    let mut out: Vec<Option<BarrelPixel>> = vec![None; pixels.len()];
    let mut waiting = 0usize; // the next input pixel
    let mut finished = 0usize;
    let mut t = 0u64;
    while finished < pixels.len() {
        let c = (t % k) as usize;
        let may_take = open(t);
        closed_run = if may_take { 0 } else { closed_run + 1 };
        assert!(closed_run < 1 << 32, "takes refused for 2^32 cycles");
        let offer = (may_take && waiting < pixels.len()).then_some(waiting);
        let turn = barrel.turn(t, c, pixels, offer);
        if let Some(p) = turn.done {
            if let Some(p) = out[p].as_mut() {
                p.done = t;
            }
            finished += 1;
        }
        if turn.took {
            out[waiting] = Some(BarrelPixel {
                context: c as u32,
                taken: t,
                done: 0,
            });
            waiting += 1;
        }
        t += 1;
    }
    let pixels: Vec<BarrelPixel> = out
        .into_iter()
        .map(|p| p.expect("every pixel ran"))
        .collect();
    let cycles = pixels.iter().map(|p| p.done + 1).max().unwrap_or(0);
    BarrelRun {
        pixels,
        cycles,
        exp_waits: barrel.exp_waits,
    }
}

// ---------------------------------------------------------------------------
// A top of fast processors (rtl/top.v with FAST = 1)
// ---------------------------------------------------------------------------

/// A top of `procs` fast processors (`rtl/top.v`, FAST = 1), as it starts a
/// frame: every processor idle, its queues empty; the top's stage and out
/// register empty.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopStart {
    /// Processors.
    pub procs: u32,
    /// Contexts of each.
    pub contexts: u32,
    /// The context whose turn cycle 0 is (every processor's ring turns
    /// together: they leave reset together).
    pub phase: u32,
    /// Processors per result group (`ARB_GROUP`): processor i's results
    /// meet in group i / group's register.
    pub group: u32,
    /// The arbiter's last grant (`rr_q`: the group of the last result that
    /// left; 0 after reset). Each group's own last pick starts at 0.
    pub last_grant: u32,
}

/// When a pixel ran on a top, in cycles from the frame's first (0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopPixel {
    /// The processor the dispatcher gave it to.
    pub proc: u32,
    /// The context that ran it, its turn and its done turn.
    pub run: BarrelPixel,
    /// The cycle its result left the top (out_valid && out_ready).
    pub out: u64,
}

/// A frame through a top of fast processors.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopRun {
    /// Each pixel, in input order.
    pub pixels: Vec<TopPixel>,
    /// From the cycle the first coordinate entered (0) to the one the last
    /// result left, inclusive.
    pub frame_cycles: u64,
}

/// Cycles from a processor's done turn to its result's slot in the top
/// (`rtl/fast/fast_pp.v`: the colour two edges on, then the result queue).
const DONE_TO_SLOT: u64 = 3;

/// The pixels of one frame through a top of fast processors, with the
/// top's coordinate stream offered every cycle from cycle 0 and its result
/// stream taken in the cycles `t` where `out_ready(t)`. The top's rule
/// (`rtl/top.v`'s stage, dispatcher, result groups and arbiter; each
/// processor's queues, `rtl/fast/fast_pp.v`), a cycle t at a time, every
/// decision on the state at the start of the cycle:
///
/// - the stage takes the next coordinate if it is empty;
/// - a staged coordinate goes to the lowest-numbered processor with fewer
///   than 2 coordinates queued (it may take it from t + 1);
/// - each processor's turn (context (t + phase) mod K) follows the barrel
///   rule, a take offered the head of its queue while it holds fewer than
///   2K pixels (taken, and not yet out of it);
/// - a done turn at t puts the result in the processor's result queue, its
///   head from t + 3;
/// - a group's register, if empty, takes one of its processors' heads,
///   round robin from the member after its last pick (the processor no
///   longer holds the pixel);
/// - the arbiter, round robin from the group after the last grant, moves
///   one group's register into the out register when that is empty or
///   taken this cycle;
/// - the out register's result leaves in a cycle with out_ready.
///
/// Panics if `procs`, `contexts` or `group` is 0, `phase` or `last_grant`
/// is out of range, or no result leaves for 2^32 cycles while a pixel
/// waits (an `out_ready` that never opens).
pub fn run_top(start: TopStart, pixels: &[PixelWork], out_ready: &dyn Fn(u64) -> bool) -> TopRun {
    assert!(start.procs > 0, "a top of no processors");
    assert!(start.group > 0, "result groups of no processors");
    assert!(
        start.phase < start.contexts,
        "phase {} of {} contexts",
        start.phase,
        start.contexts
    );
    let n = start.procs as usize;
    let g = start.group as usize;
    let groups = n.div_ceil(g);
    assert!(
        (start.last_grant as usize) < groups,
        "last grant {} of {groups} groups",
        start.last_grant
    );
    let k = start.contexts as u64;
    let hold_max = 2 * k;

    struct Proc {
        barrel: Barrel,
        queue: std::collections::VecDeque<usize>,
        results: std::collections::VecDeque<(usize, u64)>, // (pixel, its queue's head from)
        held: u64,
    }
    struct Group {
        first: usize,
        count: usize,
        reg: Option<usize>,
        last: usize,
    }
    let mut procs: Vec<Proc> = (0..n)
        .map(|_| Proc {
            barrel: Barrel::new(start.contexts),
            queue: Default::default(),
            results: Default::default(),
            held: 0,
        })
        .collect();
    let mut group: Vec<Group> = (0..groups)
        .map(|i| Group {
            first: i * g,
            count: g.min(n - i * g),
            reg: None,
            last: 0,
        })
        .collect();
    let mut runs: Vec<Option<(u32, BarrelPixel)>> = vec![None; pixels.len()];
    let mut outs: Vec<Option<u64>> = vec![None; pixels.len()];
    let mut fed = 0usize;
    let mut stage: Option<usize> = None;
    let mut out_reg: Option<usize> = None;
    let mut last_grant = start.last_grant as usize;
    let mut left = 0usize;
    let mut last_out = 0u64;
    let mut quiet = 0u64;
    let mut t = 0u64;
    while left < pixels.len() {
        quiet += 1;
        assert!(quiet < 1 << 32, "no result left the top for 2^32 cycles");
        let ready = out_ready(t);
        // The out register, the arbiter and the groups (on the state at
        // t's start).
        if let (Some(p), true) = (out_reg, ready) {
            outs[p] = Some(t);
            left += 1;
            last_out = t;
            quiet = 0;
        }
        let grant = (1..=groups)
            .map(|j| (last_grant + j) % groups)
            .find(|&i| group[i].reg.is_some());
        let moves = out_reg.is_none() || ready;
        let picks: Vec<Option<usize>> = group
            .iter()
            .map(|gr| {
                if gr.reg.is_some() {
                    return None;
                }
                (1..=gr.count).map(|j| (gr.last + j) % gr.count).find(|&m| {
                    procs[gr.first + m]
                        .results
                        .front()
                        .is_some_and(|&(_, from)| from <= t)
                })
            })
            .collect();
        // The dispatcher, and the stage.
        let pick = stage.and((0..n).find(|&i| procs[i].queue.len() < 2));
        // Each processor's turn.
        let c = ((t + start.phase as u64) % k) as usize;
        for (i, proc) in procs.iter_mut().enumerate() {
            let offer = proc.queue.front().copied().filter(|_| proc.held < hold_max);
            let turn = proc.barrel.turn(t, c, pixels, offer);
            if let Some(p) = turn.done {
                if let Some((_, run)) = runs[p].as_mut() {
                    run.done = t;
                }
                proc.results.push_back((p, t + DONE_TO_SLOT));
            }
            if turn.took {
                let p = proc.queue.pop_front().expect("the offered pixel");
                runs[p] = Some((
                    i as u32,
                    BarrelPixel {
                        context: c as u32,
                        taken: t,
                        done: 0,
                    },
                ));
                proc.held += 1;
            }
        }
        // The edge.
        if moves {
            out_reg = grant.and_then(|i| {
                last_grant = i;
                group[i].reg.take()
            });
        }
        for (gr, m) in group.iter_mut().zip(picks) {
            if let Some(m) = m {
                let proc = &mut procs[gr.first + m];
                let (p, _) = proc.results.pop_front().expect("the picked result");
                proc.held -= 1;
                gr.reg = Some(p);
                gr.last = m;
            }
        }
        if let (Some(p), Some(i)) = (stage, pick) {
            procs[i].queue.push_back(p);
            stage = None;
        } else if stage.is_none() && fed < pixels.len() {
            stage = Some(fed);
            fed += 1;
        }
        t += 1;
    }
    let pixels = runs
        .into_iter()
        .zip(outs)
        .map(|(run, out)| {
            let (proc, run) = run.expect("every pixel ran");
            TopPixel {
                proc,
                run,
                out: out.expect("every result left"),
            }
        })
        .collect();
    TopRun {
        pixels,
        frame_cycles: if left == 0 { 0 } else { last_out + 1 },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn work(instructions: u64) -> PixelWork {
        PixelWork {
            instructions,
            exp_at: None,
        }
    }

    /// One context: a pixel of N instructions takes N + 1 turns, the next
    /// pixel is taken in the done turn.
    #[test]
    fn one_context_runs_pixels_back_to_back() {
        let r = run(1, &[work(3), work(5)]);
        assert_eq!(
            r.pixels,
            [
                BarrelPixel {
                    context: 0,
                    taken: 0,
                    done: 4
                },
                BarrelPixel {
                    context: 0,
                    taken: 4,
                    done: 10
                },
            ]
        );
        assert_eq!(r.pixels[0].cycles(), 4);
        assert_eq!(r.cycles, 11);
    }

    /// K contexts take the first K pixels in their first turns; each pixel
    /// takes K (N + 1) cycles; the K + 1-th pixel goes to the first context
    /// to finish.
    #[test]
    fn contexts_take_pixels_in_turn() {
        let r = run(4, &[work(2), work(9), work(2), work(2), work(1)]);
        let taken: Vec<(u32, u64)> = r.pixels.iter().map(|p| (p.context, p.taken)).collect();
        // Pixel 0 (context 0) is done at 0 + 4 * 3 = 12, pixel 2 (context
        // 2) at 14: context 0 takes pixel 4 in its done turn.
        assert_eq!(taken, [(0, 0), (1, 1), (2, 2), (3, 3), (0, 12)]);
        assert_eq!(r.pixels[1].cycles(), 4 * 10);
        assert_eq!(r.pixels[4].done, 12 + 4 * 2);
        assert_eq!(r.pixels[1].done, 1 + 4 * 10);
        assert_eq!(r.cycles, r.pixels[1].done + 1);
    }

    /// Two EXPs whose turns are one cycle apart: the second waits a whole
    /// round; three cycles apart: neither waits.
    #[test]
    fn an_exp_waits_for_the_shared_exponential() {
        let exp = |instructions, at| PixelWork {
            instructions,
            exp_at: Some(at),
        };
        let close = run(4, &[exp(3, 1), exp(3, 1)]);
        assert_eq!(close.exp_waits, 1);
        assert_eq!(close.pixels[0].cycles(), 4 * 4);
        assert_eq!(close.pixels[1].cycles(), 4 * 5);
        let apart = run(4, &[exp(3, 1), work(1), work(1), exp(3, 1)]);
        assert_eq!(apart.exp_waits, 0);
    }

    /// A refused take leaves the context idle until its next turn; a done
    /// turn still ends its pixel.
    #[test]
    fn a_refused_take_waits_for_the_next_turn() {
        // Two contexts, three pixels of 1 instruction. Without refusals:
        // pixel 0 taken at 0 (context 0), pixel 1 at 1; context 0's done
        // turn at 4 takes pixel 2. Refusing cycle 4: pixel 0 still ends at
        // 4, pixel 2 waits for context 1's done turn at 5.
        let open = run(2, &[work(1), work(1), work(1)]);
        assert_eq!(
            open.pixels[2],
            BarrelPixel {
                context: 0,
                taken: 4,
                done: 8
            }
        );
        let gated = run_gated(2, &[work(1), work(1), work(1)], &|t| t != 4);
        assert_eq!(gated.pixels[0].done, 4);
        assert_eq!(
            gated.pixels[2],
            BarrelPixel {
                context: 1,
                taken: 5,
                done: 9
            }
        );
        assert_eq!(gated.cycles, 10);
    }

    fn top(procs: u32, contexts: u32) -> TopStart {
        TopStart {
            procs,
            contexts,
            phase: 0,
            group: 6,
            last_grant: 0,
        }
    }

    fn top_pixel(proc: u32, taken: u64, done: u64, out: u64) -> TopPixel {
        TopPixel {
            proc,
            run: BarrelPixel {
                context: 0,
                taken,
                done,
            },
            out,
        }
    }

    /// Worked by hand from the rule: a coordinate a cycle into the stage
    /// when it is empty (0, 2, 4), to processor 0 the cycle after (its
    /// queue has room), taken from its queue at the next turn; with one
    /// context the processor holds at most 2 pixels, so pixel 2 waits in
    /// its queue (cycles 6, 7) until pixel 0's result leaves for the group's
    /// register (edge of 7), and processor 1 never gets a pixel. A result:
    /// in the processor's queue 3 cycles after its done turn, the group's
    /// register the next edge, the out register the one after, out the
    /// cycle after that.
    #[test]
    fn a_top_dispatches_to_the_first_queue_with_room_and_holds_2k() {
        let r = run_top(top(2, 1), &[work(1), work(1), work(1)], &|_| true);
        assert_eq!(
            r.pixels,
            [
                top_pixel(0, 2, 4, 9),
                top_pixel(0, 4, 6, 11),
                top_pixel(0, 8, 10, 15)
            ]
        );
        assert_eq!(r.frame_cycles, 16);
    }

    /// Processor 0's queue full (pixels 1, 2 behind the running pixel 0),
    /// the stage's next coordinate goes to processor 1 (cycle 7), which
    /// takes it at its next turn.
    #[test]
    fn a_top_spreads_when_the_first_queue_is_full() {
        let r = run_top(top(2, 1), &[work(10); 4], &|_| true);
        let procs: Vec<u32> = r.pixels.iter().map(|p| p.proc).collect();
        assert_eq!(procs, [0, 0, 0, 1]);
        assert_eq!(r.pixels[3].run.taken, 8);
        assert_eq!(r.pixels[0].run.done, 2 + 11);
        assert_eq!(r.pixels[1].run.taken, 13);
    }

    /// A result waits in the out register while out_ready is low, and the
    /// stalled cycles add to the frame.
    #[test]
    fn a_top_result_waits_for_out_ready() {
        let open = run_top(top(1, 1), &[work(1)], &|_| true);
        assert_eq!(open.pixels, [top_pixel(0, 2, 4, 9)]);
        let held = run_top(top(1, 1), &[work(1)], &|t| t >= 12);
        assert_eq!(held.pixels, [top_pixel(0, 2, 4, 12)]);
        assert_eq!(held.frame_cycles, 13);
    }

    #[test]
    #[should_panic(expected = "no contexts")]
    fn no_contexts_is_refused() {
        run(0, &[work(1)]);
    }
}
