//! Exhaustive error of every reciprocal and square-root method: all 2^32
//! inputs through the golden bit model, each compared with the correctly
//! rounded native result. Prints a Markdown table (used in docs/fp.md).
//!
//!     cargo run --release -p golden --example fp_error

use golden::fp::{self, ulp_distance, Method, UlpDistance};
use std::time::Instant;

#[derive(Default, Clone)]
struct Tally {
    /// Inputs at 0, 1 and more than 1 ULP from the correctly rounded result.
    by_ulps: [u64; 3],
    nan_mismatches: u64,
    worst: u32,
    worst_input: u32,
}

impl Tally {
    fn merge(mut self, other: &Tally) -> Tally {
        for (a, b) in self.by_ulps.iter_mut().zip(other.by_ulps) {
            *a += b;
        }
        self.nan_mismatches += other.nan_mismatches;
        if other.worst > self.worst {
            self.worst = other.worst;
            self.worst_input = other.worst_input;
        }
        self
    }
}

fn sweep(model: fn(u32, Method) -> u32, native: fn(f32) -> f32, method: Method) -> Tally {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
    let chunk = (1u64 << 32).div_ceil(threads);
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                s.spawn(move || {
                    let mut tally = Tally::default();
                    for bits in t * chunk..((t + 1) * chunk).min(1 << 32) {
                        let bits = bits as u32;
                        let got = f32::from_bits(model(bits, method));
                        let want = native(f32::from_bits(bits));
                        match ulp_distance(got, want, false) {
                            UlpDistance::NanMismatch => tally.nan_mismatches += 1,
                            UlpDistance::Ulps(d) => {
                                tally.by_ulps[d.min(2) as usize] += 1;
                                if d > tally.worst {
                                    tally.worst = d;
                                    tally.worst_input = bits;
                                }
                            }
                        }
                    }
                    tally
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("sweep thread panicked"))
            .fold(Tally::default(), |acc, t| acc.merge(&t))
    })
}

fn main() {
    println!("| unit | method | latency (cycles) | worst error (ULP) | inputs at 0 ULP | at 1 ULP | at >1 ULP | NaN mismatches | worst input |");
    println!("|---|---|---|---|---|---|---|---|---|");
    type Unit = (
        &'static str,
        fn(u32, Method) -> u32,
        fn(f32) -> f32,
        fn(Method) -> u32,
    );
    let units: [Unit; 2] = [
        (
            "fp_recip",
            fp::recip_datapath,
            |x| 1.0 / x,
            fp::recip_latency,
        ),
        ("fp_sqrt", fp::sqrt_datapath, f32::sqrt, fp::sqrt_latency),
    ];
    for (name, model, native, latency) in units {
        for method in Method::ALL {
            let start = Instant::now();
            let t = sweep(model, native, method);
            println!(
                "| {name} | {method} | {} | {} | {} | {} | {} | {} | {:#010x} |",
                latency(method),
                t.worst,
                t.by_ulps[0],
                t.by_ulps[1],
                t.by_ulps[2],
                t.nan_mismatches,
                t.worst_input,
            );
            eprintln!(
                "{name} {method}: 2^32 inputs in {:.1} s",
                start.elapsed().as_secs_f64()
            );
        }
    }
}
