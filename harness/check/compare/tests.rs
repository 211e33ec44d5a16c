//! The engine on hand-made event streams: no model runs here.

use super::*;

fn ev(x: u16, y: u16, seq: u32, state: u16, values: [u32; 3]) -> TraceEvent {
    TraceEvent {
        x,
        y,
        seq,
        state,
        dst: 5,
        lanes: 0b111,
        values,
    }
}

fn stream(x: u16, y: u16, n: u32) -> Vec<TraceEvent> {
    (0..n)
        .map(|i| {
            ev(
                x,
                y,
                i,
                10 + i as u16,
                [1.5f32.to_bits() + i, 0, 0x4000_0000],
            )
        })
        .collect()
}

fn outcome(events: u64) -> PixelOutcome {
    PixelOutcome {
        rgb: [0x3f00_0000, 0, 0x3f80_0000],
        cycles: 100,
        events,
    }
}

/// Runs `a` against `b` as a live run would: A buffered, B streamed.
fn verdict(a: &[TraceEvent], b: &[TraceEvent], ao: PixelOutcome, bo: PixelOutcome) -> PixelVerdict {
    let (x, y) = (u32::from(a[0].x), u32::from(a[0].y));
    compare_pixel(x, y, Tolerance::default(), a, ao, |sink| {
        for e in b {
            sink(e, None);
        }
        bo
    })
}

#[test]
fn identical_streams_agree_and_count_every_pair_and_lane() {
    let s = stream(3, 4, 7);
    let v = verdict(&s, &s, outcome(7), outcome(7));
    assert!(!v.diverged());
    assert_eq!((v.compared, v.mismatches), (7, 0));
    assert_eq!(v.ulps.buckets[0], 21);
    let mut r = CompareReport::new(Labels::rtl_golden());
    r.add(&v);
    assert!(r.passed());
    assert_eq!(r.counts.a_events, 7);
    assert_eq!(r.counts.a_cycles, 100);
    // States 10..=16 were compared, and only they.
    assert_eq!(r.states.len(), 7);
    assert!((10..17).all(|s| r.states.contains(s)) && !r.states.contains(17));
}

#[test]
fn a_value_apart_is_an_event_divergence_at_its_seq_with_its_distance() {
    let b = stream(3, 4, 7);
    let mut a = b.clone();
    a[4].values[0] += 3; // 3 ULP up
    a[5].values[2] ^= 0x8000_0000; // sign flipped: far
    let v = verdict(&a, &b, outcome(7), outcome(7));
    let d = v.first.expect("diverges");
    assert_eq!(d.seq(), Some(4));
    assert_eq!(d.max_distance(), Some(UlpDistance::Ulps(3)));
    assert!(matches!(d.kind, DivergenceKind::Event { a, b } if a.seq == 4 && b.seq == 4));
    assert_eq!((v.compared, v.mismatches), (7, 2));
    assert_eq!(
        v.ulps.buckets[UlpHistogram::bucket(UlpDistance::Ulps(3))],
        1
    );
    assert_eq!(UlpHistogram::bucket(UlpDistance::Ulps(3)), 2);
    assert_eq!(UlpHistogram::bucket_label(2), "2-3");
    // Within a tolerance of 3 ULP only the sign flip is left.
    let tol = Tolerance { max_ulps: 3 };
    let mut cmp = PixelCompare::new(3, 4, tol);
    for (x, y) in a.iter().zip(&b) {
        cmp.pair(x, y, None);
    }
    let v = cmp.finish(outcome(7), outcome(7));
    assert_eq!(v.first.and_then(|d| d.seq()), Some(5));
}

#[test]
fn a_different_state_destination_or_lane_mask_differs_even_with_equal_values() {
    let b = ev(0, 0, 0, 11, [1, 2, 3]);
    for a in [
        TraceEvent { state: 12, ..b },
        TraceEvent { dst: 6, ..b },
        TraceEvent { lanes: 0b011, ..b },
    ] {
        assert!(events_differ(&a, &b, Tolerance::default()), "{a:?}");
    }
    assert!(!events_differ(&b, &b, Tolerance::default()));
    // Lanes that neither side wrote are not compared.
    let only_x = TraceEvent { lanes: 0b001, ..b };
    let other = TraceEvent {
        values: [1, 99, 99],
        ..only_x
    };
    assert!(!events_differ(&only_x, &other, Tolerance::default()));
}

#[test]
fn missing_and_extra_events_are_divergences_after_the_common_part() {
    let b = stream(1, 2, 6);
    let v = verdict(&b[..4], &b, outcome(4), outcome(6));
    let d = v.first.expect("diverges");
    assert!(matches!(d.kind, DivergenceKind::MissingEvent { b, .. } if b.seq == 4));
    assert_eq!(v.compared, 4);
    let v = verdict(&b, &b[..5], outcome(6), outcome(5));
    let d = v.first.expect("diverges");
    assert!(matches!(d.kind, DivergenceKind::ExtraEvent { a } if a.seq == 5));
    let mut r = CompareReport::new(Labels::rtl_golden());
    r.add(&v);
    assert_eq!(r.counts.event_count_mismatches, 1);
}

#[test]
fn colour_then_cycles_diverge_only_when_every_event_agrees() {
    let s = stream(0, 0, 3);
    let mut other = outcome(3);
    other.rgb[1] = 1;
    other.cycles = 101;
    let v = verdict(&s, &s, other, outcome(3));
    assert_eq!(v.first.map(|d| d.kind), Some(DivergenceKind::Rgb));
    assert!(v.rgb_differs && v.cycles_differ);
    other.rgb[1] = 0;
    let v = verdict(&s, &s, other, outcome(3));
    assert_eq!(v.first.map(|d| d.kind), Some(DivergenceKind::Cycles));
    let mut r = CompareReport::new(Labels::rtl_golden());
    r.add(&v);
    assert_eq!((r.counts.cycle_mismatches, r.counts.rgb_mismatches), (1, 0));
    assert!(!r.passed());
}

/// Reports of disjoint pixels merge to the same report in any order, and
/// the first divergence is the first in row order.
#[test]
fn reports_merge_exactly_in_any_order() {
    let pixels: Vec<(u16, u16)> = vec![(5, 0), (1, 2), (0, 2), (9, 1), (2, 2)];
    let verdicts: Vec<PixelVerdict> = pixels
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| {
            let b = stream(x, y, 5);
            let mut a = b.clone();
            if i % 2 == 1 {
                a[i].values[1] ^= 1;
            }
            verdict(&a, &b, outcome(5), outcome(5))
        })
        .collect();
    let report_of = |order: &[usize]| {
        let mut halves = [
            CompareReport::new(Labels::rtl_golden()),
            CompareReport::new(Labels::rtl_golden()),
        ];
        for (k, &i) in order.iter().enumerate() {
            halves[k % 2].add(&verdicts[i]);
        }
        let [mut a, b] = halves;
        a.merge(b);
        a
    };
    let one = report_of(&[0, 1, 2, 3, 4]);
    assert_eq!(report_of(&[4, 3, 2, 1, 0]), one);
    assert_eq!(report_of(&[2, 0, 4, 1, 3]), one);
    assert_eq!(one.counts.pixels, 5);
    assert_eq!(one.counts.divergent_pixels, 2);
    // Pixels (1, 2) and (9, 1) diverge: (9, 1) is first in row order.
    let first = one.first_divergence.expect("diverges");
    assert_eq!((first.x, first.y), (9, 1));
}

#[test]
fn a_divergence_reads_with_the_sides_names() {
    let b = stream(3, 4, 2);
    let mut a = b.clone();
    a[1].values[0] += 1024;
    let v = verdict(&a, &b, outcome(2), outcome(2));
    let text = v
        .first
        .expect("diverges")
        .text(&Labels::new("A.rtt", "B.rtt"))
        .to_string();
    assert!(
        text.starts_with("pixel (3, 4) event #1 (numeric drift):\n  A.rtt state PRI_HALF (11) [rtl/pp/pp_ctrl.v:"),
        "{text}"
    );
    assert!(text.contains("lane x: A.rtt 0x3fc00401"), "{text}");
    assert!(text.contains(": 1024 ulp"), "{text}");
    assert!(
        !text.contains("issued by"),
        "no golden line without a live model: {text}"
    );
}

/// One NaN rule: NaN lanes agree only bit for bit (the canonical NaN
/// against a sign-flipped or payload NaN is a divergence), whatever the
/// tolerance; signed zeros differ.
#[test]
fn nan_lanes_agree_only_bit_for_bit() {
    let canonical = 0x7FC0_0000;
    let b = ev(0, 0, 0, 11, [canonical, 0, 1]);
    for (other, tol) in [
        (0xFFC0_0000, 0),
        (0x7FC0_0001, 0),
        (0xFFC0_0000, 5),
        (0x3F80_0000, u32::MAX),
    ] {
        let a = TraceEvent {
            values: [other, 0, 1],
            ..b
        };
        assert!(
            events_differ(&a, &b, Tolerance { max_ulps: tol }),
            "{other:#x} vs canonical NaN at {tol} ulp"
        );
    }
    assert!(!events_differ(&b, &b, Tolerance::default()));
    let zero = ev(0, 0, 0, 11, [0, 0, 0]);
    let neg_zero = TraceEvent {
        values: [0x8000_0000, 0, 0],
        ..zero
    };
    assert!(events_differ(&zero, &neg_zero, Tolerance::default()));
    assert!(!events_differ(&zero, &neg_zero, Tolerance { max_ulps: 1 }));
}

#[test]
fn values_apart_on_the_same_path_are_numeric_drift() {
    let b = stream(3, 4, 7);
    let mut a = b.clone();
    a[2].values[1] ^= 1;
    let v = verdict(&a, &b, outcome(7), outcome(7));
    assert_eq!(
        v.first.map(|d| d.class),
        Some(DivergenceClass::NumericDrift)
    );
    // Only the colour apart: drift too.
    let mut other = outcome(7);
    other.rgb[0] ^= 1;
    let v = verdict(&b, &b, other, outcome(7));
    assert_eq!(
        v.first.map(|d| d.class),
        Some(DivergenceClass::NumericDrift)
    );
    // Only the cycles: timing.
    let mut slow = outcome(7);
    slow.cycles += 1;
    let v = verdict(&b, &b, slow, outcome(7));
    assert_eq!(v.first.map(|d| d.class), Some(DivergenceClass::Timing));
    let mut r = CompareReport::new(Labels::rtl_golden());
    r.add(&verdict(&a, &b, outcome(7), outcome(7)));
    assert_eq!(
        (r.counts.numeric_drift_pixels, r.counts.control_flow_pixels),
        (1, 0)
    );
}

#[test]
fn a_split_path_is_control_flow_with_its_branch_and_cause() {
    let b = stream(3, 4, 8);
    let mut a = b.clone();
    a[2].values[0] += 5; // the cause: 5 ULP apart
    a[6].state += 40; // the paths split at #6
    a[7].state += 40;
    let v = verdict(&a, &b, outcome(8), outcome(8));
    let d = v.first.expect("diverges");
    assert_eq!(d.seq(), Some(2), "the first divergence is the value");
    let DivergenceClass::ControlFlow(split) = d.class else {
        panic!("not control flow: {:?}", d.class);
    };
    assert_eq!(split.seq, 6);
    assert_eq!(split.after, Some(b[5]), "the branch after #5");
    assert_eq!(split.cause, Some((a[2], b[2])));
    assert_eq!((split.a, split.b), (Some(a[6]), Some(b[6])));
    let text = d.text(&Labels::rtl_golden()).to_string();
    assert!(text.contains("control-flow divergence"), "{text}");
    assert!(text.contains("split at event #6"), "{text}");
    assert!(text.contains("after event #5"), "{text}");
    // A split with no value apart before it says so.
    let mut a = b.clone();
    a[3].dst += 1;
    let v = verdict(&a, &b, outcome(8), outcome(8));
    let d = v.first.expect("diverges");
    let DivergenceClass::ControlFlow(split) = d.class else {
        panic!("not control flow: {:?}", d.class);
    };
    assert_eq!((split.seq, split.cause), (3, None));
    assert!(d
        .text(&Labels::rtl_golden())
        .to_string()
        .contains("without a traced cause"));
    // One side ending early splits there.
    let v = verdict(&b[..5], &b, outcome(5), outcome(8));
    let d = v.first.expect("diverges");
    let DivergenceClass::ControlFlow(split) = d.class else {
        panic!("not control flow: {:?}", d.class);
    };
    assert_eq!((split.seq, split.a, split.b), (5, None, Some(b[5])));
    assert_eq!(split.after, Some(b[4]));
    let mut r = CompareReport::new(Labels::rtl_golden());
    r.add(&v);
    assert_eq!(
        (r.counts.numeric_drift_pixels, r.counts.control_flow_pixels),
        (0, 1)
    );
}
