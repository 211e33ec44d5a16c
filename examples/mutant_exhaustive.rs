//! Decides float-unit mutants of `fp_recip`, `fp_sqrt` and `fp_exp` by
//! exhaustive simulation (docs/mutation.md, "Exhaustive simulation"): the mutant's
//! unit, cut from the mutant netlist (`FpUnit::new_mutant`), runs every
//! significand in each exponent class its mantissa datapath can tell apart,
//! then every exponent field with both signs and a set of fractions, bit for
//! bit and cycle for cycle against golden::fp. Operations run back to back
//! (each starts on the edge after the last result's out_valid, while y holds
//! that result: the only sequence the unit driver makes).
//!
//!     cargo run --release --features mutation --example mutant_exhaustive -- 89 90 163
//!     ... -- --threads 2 --all 89      # two mutants at a time; count every difference
//!     ... -- 42 58                     # fp_exp: one operand per x_q it can hold
//!     ... -- --fields 0,64 890         # every operand of those exponent fields
//!     ... -- --below 128 42            # fp_exp: every |a| < 128 (2^31 operands: slow)
//!     ... -- --processor fast 1049     # the fast processor's list: its pipelined units
//!     ... -- --processor fast --unit fast_fp_recip 77  # a shared module's mutant, in that unit
//!
//! The fast processor's units (`fast_fp_recip`, `fast_fp_sqrt`,
//! `fast_fp_exp`, cut from its netlist and driven one operation a cycle)
//! are their compact units' datapaths step for step with registers between
//! (each header says so), and take the same classes: fast_fp_exp's first
//! stage registers (sign, M', j) with X = M' * 2^(15 - j) = fp_exp's x_q,
//! and the special flags, which the sweep covers. A mutant of a module the
//! units share (fast_fp_unpack, fast_fp_round, fp_lzc, a fast_delay) is
//! run through the unit `--unit` names.
//!
//! The classes (the argument is in docs/mutation.md):
//! - fp_recip: the 2^23 fractions at biased exponent 127 (every normal
//!   result: the rounding of the significand is the same at every normal
//!   result exponent), 253 and 254 (results of 0.5 and 0.25 times the
//!   smallest normal: the subnormal results, shifted right 1 and 2);
//! - fp_sqrt: the 2^23 fractions at biased exponents 127 and 128 (both
//!   parities; every result is normal);
//! - fp_exp: one operand for each value its register x_q (|a| as fixed
//!   point, 32 fraction bits, truncated) can hold below |a| = 128, with
//!   both signs: every fraction of fields 118..=133 (x = man << (e - 118):
//!   distinct), and of fields 95..=117 the fractions whose bits x drops are
//!   zero (x = man >> (118 - e) takes each value once), and 0 (every field
//!   below 95 truncates to x = 0). Every later register is a function of
//!   (sign, x_q), so this decides a mutant acting after the input stage;
//!   one in the input stage gets `--fields` with the fields it can change;
//! - `--fields LO-HI,...` (any unit): every fraction of those fields, both
//!   signs;
//! - every unit: every exponent field 0..=255, both signs, the fractions of
//!   [`sweep_fractions`] (a subnormal one with its leading one at each
//!   position: every exponent the unpacker makes).
//!
//! A difference is printed with its operand, the smallest first (the
//! classes run in increasing bit pattern; without `--all` a mutant stops at
//! its first difference). Exits 1 if any mutant differs. Mutant 0 runs the
//! design as written through both units (it must agree everywhere).

use anyhow::{bail, Context, Result};
use golden::fp::Method;
use rtcosim::campaign::mutation::List;
use rtcosim::check::operands::CHUNK;
use rtcosim::design::fp_unit::{FpUnit, UnitKind};
use rtcosim::design::processor::ProcessorKind;
use std::time::Instant;

/// Fractions the exponent sweep runs at every exponent field and sign:
/// zero, the ends, alternating patterns, every single bit and every run of
/// low ones (for a subnormal, a leading one at each of the 23 positions),
/// and a few hashed ones.
fn sweep_fractions() -> Vec<u32> {
    let mut f = vec![0, 1, 2, 3, 0x7F_FFFF, 0x7F_FFFE, 0x40_0000, 0x40_0001];
    f.extend([0x2A_AAAA, 0x55_5555, 0x35_04F3, 0x0C_CCCD]);
    f.extend((0..23).map(|k| 1u32 << k));
    f.extend((1..=23).map(|k| (1u32 << k) - 1));
    let mut x: u32 = 0x9E37_79B9;
    for _ in 0..16 {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        f.push(x & 0x7F_FFFF);
    }
    f.sort_unstable();
    f.dedup();
    f
}

/// The operand classes of `kind`, each a list of contiguous bit-pattern
/// ranges (an exponent field's 2^23 fractions), smallest first.
fn exhaustive_exponents(kind: UnitKind) -> &'static [u32] {
    match kind.arithmetic() {
        UnitKind::Recip(_) => &[127, 253, 254],
        UnitKind::Sqrt(_) => &[127, 128],
        _ => &[],
    }
}

/// fp_exp's operands, one for each `(sign, x_q)` its input stage makes
/// below |a| = 128 (the special results decide the rest at the input), as
/// contiguous bit-pattern ranges with a stride: `(first, end, step)`.
fn exp_x_classes() -> Vec<(u64, u64, u64)> {
    let mut ranges = Vec::new();
    for sign in [0u64, 0x8000_0000] {
        // x = 0: every field below 95 (and +-0 itself).
        ranges.push((sign, sign + 1, 1));
        // x = man >> (118 - e): one fraction per value, the dropped bits 0.
        for e in 95..118u64 {
            ranges.push((sign | e << 23, sign | (e + 1) << 23, 1 << (118 - e)));
        }
        // x = man << (e - 118): every fraction.
        ranges.push((sign | 118 << 23, sign | 134 << 23, 1));
    }
    ranges
}
/// What one mutant's run found.
struct Found {
    operands: u64,
    differing: u64,
    /// The smallest differing operand: `(a, mutant y, golden y, mutant
    /// cycles)`.
    first: Option<(u32, u32, u32, u32)>,
    seconds: f64,
}

/// Runs `a` through `unit` and compares with golden; records differences.
fn run_batch(unit: &mut FpUnit, a: &[u32], found: &mut Found) -> Result<()> {
    let kind = unit.kind();
    let (y, cycles) = unit.eval(a, &[])?;
    found.operands += a.len() as u64;
    for i in 0..a.len() {
        let want = kind.golden(a[i], 0);
        if y[i] != want || cycles[i] != kind.latency() {
            found.differing += 1;
            let better = found.first.map_or(true, |(f, ..)| a[i] < f);
            if better {
                found.first = Some((a[i], y[i], want, cycles[i]));
            }
        }
    }
    Ok(())
}

/// Which operands beyond the exponent sweep a run takes.
#[derive(Clone)]
enum Classes {
    /// The unit's own classes (module doc).
    Unit,
    /// fp_exp: every |a| below this.
    Below(f32),
    /// Every fraction of each range of exponent fields `lo..=hi`, both
    /// signs.
    Fields(Vec<(u32, u32)>),
}

/// Judges mutant `id` of `kind` on the exponent sweep and `classes`; stops
/// at the first differing batch unless `all`.
fn judge(kind: UnitKind, id: u16, all: bool, classes: &Classes) -> Result<Found> {
    let start = Instant::now();
    let mut unit = FpUnit::new_mutant(kind, id)?;
    let mut found = Found {
        operands: 0,
        differing: 0,
        first: None,
        seconds: 0.0,
    };
    let done = |f: &Found| !all && f.differing > 0;
    // The exponent sweep.
    let fracs = sweep_fractions();
    let mut sweep = Vec::new();
    for s in 0..2u32 {
        for e in 0..=255u32 {
            sweep.extend(fracs.iter().map(|&f| s << 31 | e << 23 | f));
        }
    }
    run_batch(&mut unit, &sweep, &mut found)?;
    let sweep_first = found.first.take();
    // Every operand of each class: (first, end, step).
    // (Bit patterns as u64: the negative field 255's end is 2^32.)
    let ranges: Vec<(u64, u64, u64)> = match classes {
        &Classes::Below(limit) => {
            let top = u64::from(limit.to_bits());
            vec![(0, top, 1), (0x8000_0000, 0x8000_0000 | top, 1)]
        }
        Classes::Fields(fields) => [0u64, 0x8000_0000]
            .iter()
            .flat_map(|&sign| {
                fields.iter().map(move |&(lo, hi)| {
                    let (lo, hi) = (u64::from(lo), u64::from(hi));
                    (sign + (lo << 23), sign + ((hi + 1) << 23), 1)
                })
            })
            .collect(),
        Classes::Unit if kind.arithmetic() == UnitKind::Exp => exp_x_classes(),
        Classes::Unit => exhaustive_exponents(kind)
            .iter()
            .map(|&e| (u64::from(e) << 23, u64::from(e + 1) << 23, 1))
            .collect(),
    };
    let mut batch = Vec::with_capacity(CHUNK);
    'classes: for (lo, hi, step) in ranges {
        let mut a = lo;
        while a < hi {
            batch.clear();
            while batch.len() < CHUNK && a < hi {
                batch.push(a as u32);
                a += step;
            }
            run_batch(&mut unit, &batch, &mut found)?;
            if done(&found) {
                break 'classes;
            }
        }
    }
    // The smallest of the sweep's and the classes' first differences.
    found.first = match (sweep_first, found.first) {
        (Some(s), Some(c)) => Some(if s.0 < c.0 { s } else { c }),
        (s, c) => s.or(c),
    };
    found.seconds = start.elapsed().as_secs_f64();
    Ok(found)
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let (mut threads, mut all, mut classes, mut ids) = (1usize, false, Classes::Unit, Vec::new());
    let (mut processor, mut unit) = (ProcessorKind::default(), None);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--processor" => {
                let name = args.next().unwrap_or_default();
                processor = ProcessorKind::ALL
                    .into_iter()
                    .find(|k| k.name() == name)
                    .with_context(|| format!("--processor compact|fast, got {name:?}"))?;
            }
            "--unit" => unit = Some(args.next().context("--unit NAME")?),
            "--threads" => {
                threads = args
                    .next()
                    .context("--threads N")?
                    .parse()
                    .context("--threads N")?;
            }
            "--all" => all = true,
            "--below" => {
                classes = Classes::Below(
                    args.next()
                        .context("--below X")?
                        .parse::<f32>()
                        .context("--below X")?,
                );
            }
            "--fields" => {
                let list = args.next().context("--fields LO-HI,...")?;
                let bad = || {
                    format!("--fields {list:?}: want exponent fields 0..=255 as F or LO-HI, comma-separated")
                };
                let mut fields = Vec::new();
                for item in list.split(',') {
                    let (lo, hi) = item.split_once('-').unwrap_or((item, item));
                    let (lo, hi): (u32, u32) =
                        (lo.parse().with_context(bad)?, hi.parse().with_context(bad)?);
                    if lo > hi || hi > 255 {
                        bail!(bad());
                    }
                    fields.push((lo, hi));
                }
                classes = Classes::Fields(fields);
            }
            _ => {
                for part in arg.split(',') {
                    ids.push(
                        part.parse::<u16>()
                            .with_context(|| format!("mutant id {part:?}"))?,
                    );
                }
            }
        }
    }
    if ids.is_empty() {
        bail!(
            "usage: mutant_exhaustive [--processor compact|fast] [--unit NAME] [--threads N] [--all] \
             [--below X | --fields LO-HI,...] ID..."
        );
    }
    let list = List::committed(processor)?;
    // The units this tool takes: the unary ones with classes.
    let units: Vec<UnitKind> = processor
        .row()
        .units
        .into_iter()
        .filter(|k| k.method() == Some(Method::Exact) || k.module().ends_with("exp"))
        .collect();
    let named = |module: &str| units.iter().copied().find(|k| k.module() == module);
    let forced = match &unit {
        None => None,
        Some(name) => Some(named(name).with_context(|| {
            let names: Vec<&str> = units.iter().map(|k| k.module()).collect();
            format!("--unit {name}: this tool takes {}", names.join(", "))
        })?),
    };
    let mut jobs = Vec::new();
    for &id in &ids {
        if id == 0 {
            // The design as written: golden's own check, on all three units.
            for &kind in &units {
                jobs.push((0, kind, "the design".to_string()));
            }
            continue;
        }
        let m = list
            .get(id)
            .with_context(|| format!("mutant {id} is not in the list"))?;
        let Some(kind) = forced.or_else(|| named(&m.module)) else {
            let names: Vec<&str> = units.iter().map(|k| k.module()).collect();
            bail!(
                "mutant {id} is in {}: this tool takes {} (or --unit NAME for a module they share)",
                m.module,
                names.join(", ")
            )
        };
        jobs.push((id, kind, m.location.clone()));
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let any_differs = std::sync::atomic::AtomicBool::new(false);
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some((id, kind, location)) = jobs.get(i) else {
                    break;
                };
                match judge(*kind, *id, all, &classes) {
                    Err(e) => {
                        any_differs.store(true, std::sync::atomic::Ordering::Relaxed);
                        println!("mutant {id} ({kind}, {location}): error: {e:#}");
                    }
                    Ok(f) => {
                        let rate = f.operands as f64 / f.seconds.max(1e-9);
                        let head = format!(
                            "mutant {id} ({kind}, {location}): {} operands in {:.1} s ({:.0}/s)",
                            f.operands, f.seconds, rate
                        );
                        match f.first {
                            None => println!("{head}: none differs from golden"),
                            Some((a, y, want, cycles)) => {
                                any_differs.store(true, std::sync::atomic::Ordering::Relaxed);
                                println!(
                                    "{head}: {} differ{}; smallest a = {a:#010x} ({:e}): y = {y:#010x}, golden {want:#010x}, {cycles} cycles",
                                    f.differing,
                                    if all { "" } else { " (stopped at the first batch)" },
                                    f32::from_bits(a)
                                );
                            }
                        }
                    }
                }
            });
        }
    });
    if any_differs.into_inner() {
        std::process::exit(1);
    }
    Ok(())
}
