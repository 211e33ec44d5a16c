//! The comparison engine: two streams of [`TraceEvent`]s and two
//! [`PixelOutcome`]s per pixel, whatever produced them.
//!
//! A live co-simulation feeds it the RTL's events against the golden
//! model's as they are produced; a trace diff feeds it two files; an
//! N-processor top feeds it each pixel's events once they are split out by
//! processor. Each pixel is compared on its own ([`PixelCompare`], events in
//! sequence order), and ends in a [`PixelVerdict`]; verdicts add up into a
//! [`CompareReport`], whose counts add exactly and whose first divergence is
//! the first in row order, so reports of disjoint pixel sets merge to the
//! same report in any order.
//!
//! The two sides are called A and B; [`Labels`] names them for people ("RTL"
//! and "golden" in a co-simulation). Two events agree when they have the
//! same state, destination and lane mask and every written lane is within
//! the [`Tolerance`]: by default the same bits (so +0 and -0 differ, and a
//! NaN matches only the same NaN: every unit makes the canonical one, see
//! [`golden::fp`]); with `max_ulps` > 0, numbers that many ULPs apart agree,
//! NaNs still only bit for bit.

mod json;
mod text;

use crate::design::processor::ProcessorKind;
use golden::fp::{ulp_distance, UlpDistance};
use golden::pixel::PixelOutcome;
use golden::trace::TraceEvent;
use std::panic::Location;

pub use json::event_json;
pub use text::state_with_line;

/// The source line of the golden model that issued an event.
pub type SourceLine = &'static Location<'static>;

/// What the two sides are called in reports, and the processor whose
/// controller's Verilog lines the reports name for a state.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Labels {
    pub a: String,
    pub b: String,
    pub processor: ProcessorKind,
}

impl Labels {
    /// Sides `a` and `b`, states named at the compact processor's lines.
    pub fn new(a: impl Into<String>, b: impl Into<String>) -> Labels {
        Labels {
            a: a.into(),
            b: b.into(),
            processor: ProcessorKind::default(),
        }
    }

    /// The same sides, states named at `processor`'s lines.
    pub fn on(self, processor: ProcessorKind) -> Labels {
        Labels { processor, ..self }
    }

    /// A co-simulation: the RTL (A) against the golden model (B).
    pub fn rtl_golden() -> Labels {
        Labels::new("RTL", "golden")
    }
}

/// How far apart two written lanes may be and still agree.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Tolerance {
    /// Largest ULP distance between two numbers that counts as agreement
    /// (0: bit for bit). A NaN agrees only with the same bits.
    pub max_ulps: u32,
}

impl Tolerance {
    /// Whether two values (raw f32 bits) agree.
    pub fn agrees(self, a: u32, b: u32) -> bool {
        let (fa, fb) = (f32::from_bits(a), f32::from_bits(b));
        a == b
            || (!fa.is_nan() && !fb.is_nan() && ulp_distance(fa, fb, false).within(self.max_ulps))
    }
}

/// ULP distance of lane `i` between two events, when both wrote it.
pub fn lane_distance(a: &TraceEvent, b: &TraceEvent, i: usize) -> Option<UlpDistance> {
    (a.lanes >> i & 1 == 1 && b.lanes >> i & 1 == 1).then(|| {
        ulp_distance(
            f32::from_bits(a.values[i]),
            f32::from_bits(b.values[i]),
            false,
        )
    })
}

/// Whether two events differ in state, destination, lanes or a written
/// value beyond `tolerance` (the pixel and seq are not compared: the caller
/// pairs them).
pub fn events_differ(a: &TraceEvent, b: &TraceEvent, tolerance: Tolerance) -> bool {
    a.state != b.state
        || a.dst != b.dst
        || a.lanes != b.lanes
        || (0..3).any(|i| a.lanes >> i & 1 == 1 && !tolerance.agrees(a.values[i], b.values[i]))
}

/// Whether two colours differ beyond `tolerance`.
fn rgb_differs(a: [u32; 3], b: [u32; 3], tolerance: Tolerance) -> bool {
    (0..3).any(|i| !tolerance.agrees(a[i], b[i]))
}

/// Counts of how many lanes were how far apart: bucket 0 holds exact
/// agreement, bucket `k` in 1..=32 distances in `2^(k-1) .. 2^k`, and the
/// last bucket NaN against a number.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct UlpHistogram {
    pub buckets: [u64; UlpHistogram::BUCKETS],
}

impl Default for UlpHistogram {
    fn default() -> UlpHistogram {
        UlpHistogram {
            buckets: [0; UlpHistogram::BUCKETS],
        }
    }
}

impl UlpHistogram {
    pub const BUCKETS: usize = 34;
    /// The bucket of NaN-against-a-number.
    pub const NAN: usize = UlpHistogram::BUCKETS - 1;

    /// The bucket `d` falls in.
    pub fn bucket(d: UlpDistance) -> usize {
        match d {
            UlpDistance::Ulps(n) => (u32::BITS - n.leading_zeros()) as usize,
            UlpDistance::NanMismatch => UlpHistogram::NAN,
        }
    }

    pub fn add(&mut self, d: UlpDistance) {
        self.buckets[UlpHistogram::bucket(d)] += 1;
    }

    pub fn merge(&mut self, other: &UlpHistogram) {
        for (a, b) in self.buckets.iter_mut().zip(other.buckets) {
            *a += b;
        }
    }

    /// Lanes counted.
    pub fn total(&self) -> u64 {
        self.buckets.iter().sum()
    }

    /// The label of bucket `k`: `0`, `1`, `2-3`, ..., `NaN vs number`.
    pub fn bucket_label(k: usize) -> String {
        match k {
            0 => "0".to_string(),
            1 => "1".to_string(),
            UlpHistogram::NAN => "NaN vs number".to_string(),
            k => format!("{}-{}", 1u64 << (k - 1), (1u64 << k) - 1),
        }
    }
}

/// A set of controller state ids: which states a comparison saw (state
/// coverage). Merges by union.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StateSet {
    bits: [u64; StateSet::WORDS],
}

impl Default for StateSet {
    fn default() -> StateSet {
        StateSet {
            bits: [0; StateSet::WORDS],
        }
    }
}

impl StateSet {
    const WORDS: usize = (1 << golden::micro::isa::dim::ST_BITS) / 64;

    pub fn insert(&mut self, state: u16) {
        if let Some(w) = self.bits.get_mut(usize::from(state) / 64) {
            *w |= 1 << (state % 64);
        }
    }

    pub fn contains(&self, state: u16) -> bool {
        self.bits
            .get(usize::from(state) / 64)
            .is_some_and(|w| w >> (state % 64) & 1 == 1)
    }

    pub fn union(&mut self, other: &StateSet) {
        for (a, b) in self.bits.iter_mut().zip(other.bits) {
            *a |= b;
        }
    }

    pub fn len(&self) -> usize {
        self.bits.iter().map(|w| w.count_ones() as usize).sum()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// What diverged first in a pixel: the first event that differs (in
/// sequence order), else a missing or extra event, else the colour, else
/// the cycle count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DivergenceKind {
    /// Event `seq` differs in state, destination, lanes or a written value.
    Event { a: TraceEvent, b: TraceEvent },
    /// A wrote fewer events: B's event at this seq has no counterpart.
    MissingEvent { b: TraceEvent },
    /// A wrote more events: this one has no counterpart in B.
    ExtraEvent { a: TraceEvent },
    /// Every event agreed, but not the colour.
    Rgb,
    /// Events and colour agreed, but not the cycle count.
    Cycles,
}

/// What kind of divergence a pixel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DivergenceClass {
    /// Numeric drift: both sides went through the same states, writing the
    /// same registers and lanes, and some values (or the colour) are apart.
    NumericDrift,
    /// Control-flow divergence: the state sequences split (a hit against a
    /// miss, another stack depth, one side ending early).
    ControlFlow(Split),
    /// Events and colour agree; only the cycle count differs.
    Timing,
}

/// Where and why two state sequences split.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Split {
    /// The first sequence number where the sides' events differ in state,
    /// destination or lanes, or where one side has no event.
    pub seq: u32,
    /// The two sides' events there (`None`: that side had ended).
    pub a: Option<TraceEvent>,
    pub b: Option<TraceEvent>,
    /// The last event before the split, the same state on both sides (B's
    /// event): the branch was taken differently after it. `None` when the
    /// sequences split at the first event.
    pub after: Option<TraceEvent>,
    /// The first pair before the split with the same state, destination
    /// and lanes but values apart: the numeric difference that sent the
    /// branch another way. `None` when every value agreed up to the split.
    pub cause: Option<(TraceEvent, TraceEvent)>,
}

/// The first divergence of a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Divergence {
    pub x: u32,
    pub y: u32,
    pub kind: DivergenceKind,
    pub class: DivergenceClass,
    pub a: PixelOutcome,
    pub b: PixelOutcome,
    /// The golden model's source line that issued A's diverging event,
    /// when known (a golden side, or a golden re-run that reached it).
    pub a_at: Option<SourceLine>,
    /// The same for B's.
    pub b_at: Option<SourceLine>,
}

impl Divergence {
    /// The sequence number of the diverging event, if an event diverged.
    pub fn seq(&self) -> Option<u32> {
        match self.kind {
            DivergenceKind::Event { b, .. } | DivergenceKind::MissingEvent { b } => Some(b.seq),
            DivergenceKind::ExtraEvent { a } => Some(a.seq),
            DivergenceKind::Rgb | DivergenceKind::Cycles => None,
        }
    }

    /// The two sides' diverging events (`None` where a side had none).
    pub fn events(&self) -> (Option<TraceEvent>, Option<TraceEvent>) {
        match self.kind {
            DivergenceKind::Event { a, b } => (Some(a), Some(b)),
            DivergenceKind::MissingEvent { b } => (None, Some(b)),
            DivergenceKind::ExtraEvent { a } => (Some(a), None),
            DivergenceKind::Rgb | DivergenceKind::Cycles => (None, None),
        }
    }

    /// The largest ULP distance over the lanes both events wrote (for an
    /// event divergence).
    pub fn max_distance(&self) -> Option<UlpDistance> {
        match &self.kind {
            DivergenceKind::Event { a, b } => (0..3).filter_map(|i| lane_distance(a, b, i)).max(),
            _ => None,
        }
    }

    /// Whether `self` comes before `other` in row order.
    fn precedes(&self, other: &Divergence) -> bool {
        (self.y, self.x) < (other.y, other.x)
    }
}

/// Whether two events were made by the same instruction: the same state,
/// destination and lanes (values aside).
fn same_step(a: &TraceEvent, b: &TraceEvent) -> bool {
    a.state == b.state && a.dst == b.dst && a.lanes == b.lanes
}

/// One pixel's comparison, fed event by event in sequence order: a pair
/// for every sequence number both sides reached, then the events only one
/// side made.
#[derive(Debug, Clone)]
pub struct PixelCompare {
    x: u32,
    y: u32,
    tolerance: Tolerance,
    compared: u64,
    mismatches: u64,
    ulps: UlpHistogram,
    states: StateSet,
    first: Option<(DivergenceKind, Option<SourceLine>)>,
    /// The last pair that was the same step, while no split is seen.
    last_common: Option<TraceEvent>,
    /// The first same-step pair with values apart.
    first_value: Option<(TraceEvent, TraceEvent)>,
    split: Option<Split>,
}

impl PixelCompare {
    pub fn new(x: u32, y: u32, tolerance: Tolerance) -> PixelCompare {
        PixelCompare {
            x,
            y,
            tolerance,
            compared: 0,
            mismatches: 0,
            ulps: UlpHistogram::default(),
            states: StateSet::default(),
            first: None,
            last_common: None,
            first_value: None,
            split: None,
        }
    }

    /// Both sides made an event at this sequence number; `at` is the
    /// golden source line of B's, when B is a live golden model.
    pub fn pair(&mut self, a: &TraceEvent, b: &TraceEvent, at: Option<SourceLine>) {
        self.compared += 1;
        self.states.insert(b.state);
        for i in 0..3 {
            if let Some(d) = lane_distance(a, b, i) {
                self.ulps.add(d);
            }
        }
        let differ = events_differ(a, b, self.tolerance);
        if differ {
            self.mismatches += 1;
            self.first
                .get_or_insert((DivergenceKind::Event { a: *a, b: *b }, at));
        }
        if self.split.is_none() {
            if same_step(a, b) {
                self.last_common = Some(*b);
                if differ && self.first_value.is_none() {
                    self.first_value = Some((*a, *b));
                }
            } else {
                self.split_at(b.seq, Some(*a), Some(*b));
            }
        }
    }

    fn split_at(&mut self, seq: u32, a: Option<TraceEvent>, b: Option<TraceEvent>) {
        self.split.get_or_insert(Split {
            seq,
            a,
            b,
            after: self.last_common,
            cause: self.first_value,
        });
    }

    /// B made an event where A had ended.
    pub fn only_b(&mut self, b: &TraceEvent, at: Option<SourceLine>) {
        self.first
            .get_or_insert((DivergenceKind::MissingEvent { b: *b }, at));
        self.split_at(b.seq, None, Some(*b));
    }

    /// A made an event where B had ended.
    pub fn only_a(&mut self, a: &TraceEvent) {
        self.first
            .get_or_insert((DivergenceKind::ExtraEvent { a: *a }, None));
        self.split_at(a.seq, Some(*a), None);
    }

    /// Compares `a` (the pairs and single events fed so far) with the
    /// pixels' outcomes, `a` on side A and `b` on side B.
    pub fn finish(self, a: PixelOutcome, b: PixelOutcome) -> PixelVerdict {
        let rgb_differs = rgb_differs(a.rgb, b.rgb, self.tolerance);
        let cycles_differ = a.cycles != b.cycles;
        let first = self
            .first
            .or(rgb_differs.then_some((DivergenceKind::Rgb, None)))
            .or(cycles_differ.then_some((DivergenceKind::Cycles, None)));
        let class = match (self.split, first) {
            (Some(split), _) => DivergenceClass::ControlFlow(split),
            (None, Some((DivergenceKind::Cycles, _))) => DivergenceClass::Timing,
            _ => DivergenceClass::NumericDrift,
        };
        PixelVerdict {
            x: self.x,
            y: self.y,
            a,
            b,
            compared: self.compared,
            mismatches: self.mismatches,
            ulps: self.ulps,
            states: self.states,
            rgb_differs,
            cycles_differ,
            first: first.map(|(kind, at)| Divergence {
                x: self.x,
                y: self.y,
                kind,
                class,
                a,
                b,
                a_at: None,
                b_at: at,
            }),
        }
    }
}

/// Compares a pixel whose A events are all at hand with B events that come
/// one by one: `run_b` gets a sink to call with each B event (and the
/// source line that issued it) and returns B's outcome.
pub fn compare_pixel(
    x: u32,
    y: u32,
    tolerance: Tolerance,
    a_events: &[TraceEvent],
    a: PixelOutcome,
    run_b: impl FnOnce(&mut dyn FnMut(&TraceEvent, Option<SourceLine>)) -> PixelOutcome,
) -> PixelVerdict {
    let mut cmp = PixelCompare::new(x, y, tolerance);
    let mut a_iter = a_events.iter();
    let b = run_b(&mut |b, at| match a_iter.next() {
        Some(a) => cmp.pair(a, b, at),
        None => cmp.only_b(b, at),
    });
    for a in a_iter {
        cmp.only_a(a);
    }
    cmp.finish(a, b)
}

/// How one pixel compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelVerdict {
    pub x: u32,
    pub y: u32,
    pub a: PixelOutcome,
    pub b: PixelOutcome,
    /// Event pairs compared.
    pub compared: u64,
    /// Compared pairs that differ.
    pub mismatches: u64,
    /// The distances of the lanes both sides wrote.
    pub ulps: UlpHistogram,
    /// The states of B's events that had a counterpart in A.
    pub states: StateSet,
    pub rgb_differs: bool,
    pub cycles_differ: bool,
    /// What diverged first, if anything did.
    pub first: Option<Divergence>,
}

impl PixelVerdict {
    pub fn diverged(&self) -> bool {
        self.first.is_some()
    }
}

/// Declares the report's counters once: the struct and its exact merge.
macro_rules! counters {
    ($(#[$meta:meta])* pub struct $name:ident { $($(#[doc = $doc:literal])* $field:ident,)* }) => {
        $(#[$meta])*
        pub struct $name { $($(#[doc = $doc])* pub $field: u64,)* }

        impl std::ops::AddAssign for $name {
            fn add_assign(&mut self, other: $name) {
                $(self.$field += other.$field;)*
            }
        }

        impl $name {
            /// Every counter with its name, in declaration order.
            pub fn named(&self) -> Vec<(&'static str, u64)> {
                vec![$((stringify!($field), self.$field),)*]
            }
        }
    };
}

counters! {
    /// What a comparison counted; adds exactly. (Serialized in fuzz shard
    /// files, crate::campaign::fuzz::summary.)
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize)]
    pub struct Counts {
        /// Pixels compared.
        pixels,
        /// Event pairs compared (per pixel, the events both sides wrote).
        events_compared,
        /// Compared pairs that differ.
        event_mismatches,
        /// Events side A wrote.
        a_events,
        /// Events side B wrote.
        b_events,
        /// Pixels whose sides wrote different numbers of events.
        event_count_mismatches,
        /// Cycles side A took.
        a_cycles,
        /// Cycles side B took.
        b_cycles,
        /// Pixels whose cycle counts differ.
        cycle_mismatches,
        /// Pixels whose final colours differ.
        rgb_mismatches,
        /// Pixels with any divergence (events, counts, colour, cycles).
        divergent_pixels,
        /// Divergent pixels whose state sequences split.
        control_flow_pixels,
        /// Divergent pixels with the same state sequence, values apart.
        numeric_drift_pixels,
    }
}

impl Counts {
    /// The counts of one pixel.
    pub fn of(v: &PixelVerdict) -> Counts {
        Counts {
            pixels: 1,
            events_compared: v.compared,
            event_mismatches: v.mismatches,
            a_events: v.a.events,
            b_events: v.b.events,
            event_count_mismatches: u64::from(v.a.events != v.b.events),
            a_cycles: v.a.cycles,
            b_cycles: v.b.cycles,
            cycle_mismatches: u64::from(v.cycles_differ),
            rgb_mismatches: u64::from(v.rgb_differs),
            divergent_pixels: u64::from(v.diverged()),
            control_flow_pixels: u64::from(matches!(
                v.first.map(|d| d.class),
                Some(DivergenceClass::ControlFlow(_))
            )),
            numeric_drift_pixels: u64::from(matches!(
                v.first.map(|d| d.class),
                Some(DivergenceClass::NumericDrift)
            )),
        }
    }
}

/// How many cycles pixels took: the fewest, the most, and how many pixels
/// took each number of cycles. Merges exactly.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CycleStats {
    /// Cycles -> pixels that took them.
    pub histogram: std::collections::BTreeMap<u64, u64>,
}

impl CycleStats {
    pub fn add(&mut self, cycles: u64) {
        *self.histogram.entry(cycles).or_default() += 1;
    }

    pub fn merge(&mut self, other: &CycleStats) {
        for (&c, &n) in &other.histogram {
            *self.histogram.entry(c).or_default() += n;
        }
    }

    pub fn min(&self) -> Option<u64> {
        self.histogram.keys().next().copied()
    }

    pub fn max(&self) -> Option<u64> {
        self.histogram.keys().next_back().copied()
    }

    /// Pixels counted.
    pub fn pixels(&self) -> u64 {
        self.histogram.values().sum()
    }

    /// Mean cycles per pixel (0 with no pixels).
    pub fn mean(&self) -> f64 {
        let total: u64 = self.histogram.iter().map(|(c, n)| c * n).sum();
        total as f64 / self.pixels().max(1) as f64
    }
}

/// What a comparison of many pixels found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompareReport {
    pub labels: Labels,
    pub counts: Counts,
    /// Side A's cycles per pixel.
    pub a_cycles: CycleStats,
    /// Distances of every lane both sides wrote.
    pub ulps: UlpHistogram,
    /// The controller states compared (state coverage).
    pub states: StateSet,
    /// The first divergent pixel in row order, and what diverged first.
    pub first_divergence: Option<Divergence>,
}

impl CompareReport {
    pub fn new(labels: Labels) -> CompareReport {
        CompareReport {
            labels,
            counts: Counts::default(),
            a_cycles: CycleStats::default(),
            ulps: UlpHistogram::default(),
            states: StateSet::default(),
            first_divergence: None,
        }
    }

    /// Adds one pixel's verdict.
    pub fn add(&mut self, v: &PixelVerdict) {
        self.counts += Counts::of(v);
        self.a_cycles.add(v.a.cycles);
        self.ulps.merge(&v.ulps);
        self.states.union(&v.states);
        self.keep_first(v.first);
    }

    /// Adds `other` in (the same labels); the result does not depend on
    /// the order of merges.
    pub fn merge(&mut self, other: CompareReport) {
        self.counts += other.counts;
        self.a_cycles.merge(&other.a_cycles);
        self.ulps.merge(&other.ulps);
        self.states.union(&other.states);
        self.keep_first(other.first_divergence);
    }

    fn keep_first(&mut self, d: Option<Divergence>) {
        if let Some(d) = d {
            if self.first_divergence.map_or(true, |f| d.precedes(&f)) {
                self.first_divergence = Some(d);
            }
        }
    }

    /// True when pixels ran, events were compared, and nothing diverged.
    pub fn passed(&self) -> bool {
        self.counts.pixels > 0
            && self.counts.events_compared > 0
            && self.counts.divergent_pixels == 0
    }
}

#[cfg(test)]
mod tests;
