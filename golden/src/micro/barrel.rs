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
    assert!(contexts > 0, "a barrel of no contexts");
    let mut closed_run = 0u64;
    let k = contexts as usize;
    let mut ctx = vec![Context::Idle; k];
    let mut out: Vec<Option<BarrelPixel>> = vec![None; pixels.len()];
    let mut waiting = 0usize; // the next input pixel
    let mut finished = 0usize;
    let mut last_exp: Option<u64> = None;
    let mut exp_waits = 0u64;
    let mut t = 0u64;
    while finished < pixels.len() {
        let c = (t % k as u64) as usize;
        let may_take = open(t);
        closed_run = if may_take { 0 } else { closed_run + 1 };
        assert!(closed_run < 1 << 32, "takes refused for 2^32 cycles");
        let take = |t: u64, c: usize, waiting: &mut usize, out: &mut [Option<BarrelPixel>]| {
            if may_take {
                take(t, c, waiting, out)
            } else {
                Context::Idle
            }
        };
        ctx[c] = match ctx[c] {
            Context::Idle => take(t, c, &mut waiting, &mut out),
            Context::Running { pixel, next } if next < pixels[pixel].instructions => {
                if pixels[pixel].exp_at == Some(next) {
                    if last_exp.is_some_and(|e| t <= e + 2) {
                        exp_waits += 1;
                        ctx[c]
                    } else {
                        last_exp = Some(t);
                        Context::Running {
                            pixel,
                            next: next + 1,
                        }
                    }
                } else {
                    Context::Running {
                        pixel,
                        next: next + 1,
                    }
                }
            }
            Context::Running { pixel, .. } => {
                if let Some(p) = out[pixel].as_mut() {
                    p.done = t;
                }
                finished += 1;
                take(t, c, &mut waiting, &mut out)
            }
        };
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
        exp_waits,
    }
}

/// Context `c`'s turn t takes the next waiting pixel, if any.
fn take(t: u64, c: usize, waiting: &mut usize, out: &mut [Option<BarrelPixel>]) -> Context {
    if *waiting == out.len() {
        return Context::Idle;
    }
    let pixel = *waiting;
    *waiting += 1;
    out[pixel] = Some(BarrelPixel {
        context: c as u32,
        taken: t,
        done: 0,
    });
    Context::Running { pixel, next: 0 }
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

    #[test]
    #[should_panic(expected = "no contexts")]
    fn no_contexts_is_refused() {
        run(0, &[work(1)]);
    }
}
