//! The comparison as JSON (serde_json values), for `report.json` and
//! `trace-diff --json`: the same facts as the text, keyed for machines.

use super::{
    CompareReport, Divergence, DivergenceClass, DivergenceKind, Labels, SourceLine, UlpHistogram,
};
use crate::design::processor::ProcessorKind;
use crate::design::rtl_source::state_line;
use golden::micro::isa::{register_label, state_name};
use golden::pixel::PixelOutcome;
use golden::trace::TraceEvent;
use serde_json::{json, Value};

fn rust_line(at: Option<SourceLine>) -> Value {
    at.map_or(Value::Null, |at| {
        json!(format!("{}:{}", at.file(), at.line()))
    })
}

/// An event: state (name, id, Verilog line), destination, lanes, values in
/// hex and as floats (lanes not written are null).
pub fn event_json(processor: ProcessorKind, e: &TraceEvent, at: Option<SourceLine>) -> Value {
    let lanes: Vec<Value> = (0..3)
        .map(|i| {
            if e.lanes >> i & 1 == 1 {
                let bits = e.values[i];
                json!({ "hex": format!("{bits:#010x}"), "value": float(bits) })
            } else {
                Value::Null
            }
        })
        .collect();
    json!({
        "seq": e.seq,
        "state": state_name(e.state),
        "state_id": e.state,
        "verilog": state_line(processor, e.state).map(|l| l.to_string()),
        "rust": rust_line(at),
        "dst": register_label(e.dst),
        "lanes": lanes,
    })
}

/// A float as JSON: a number, or its name when JSON has none (NaN, inf).
fn float(bits: u32) -> Value {
    let f = f32::from_bits(bits);
    if f.is_finite() {
        json!(f64::from(f))
    } else {
        json!(f.to_string())
    }
}

fn outcome(o: &PixelOutcome) -> Value {
    json!({
        "rgb": o.rgb.iter().map(|&c| json!({"hex": format!("{c:#010x}"), "value": float(c)})).collect::<Vec<_>>(),
        "cycles": o.cycles,
        "events": o.events,
    })
}

impl UlpHistogram {
    /// The non-empty buckets: `{"ulps": "2-3", "lanes": 17}`.
    pub fn to_json(&self) -> Value {
        Value::Array(
            self.buckets
                .iter()
                .enumerate()
                .filter(|(_, &n)| n > 0)
                .map(|(k, &n)| json!({ "ulps": UlpHistogram::bucket_label(k), "lanes": n }))
                .collect(),
        )
    }
}

impl Divergence {
    /// The divergence, its class and both sides' events and outcomes, the
    /// sides named by `labels`.
    pub fn to_json(&self, labels: &Labels) -> Value {
        let p = labels.processor;
        let (a, b) = self.events();
        let kind = match self.kind {
            DivergenceKind::Event { .. } => "event",
            DivergenceKind::MissingEvent { .. } => "missing_event",
            DivergenceKind::ExtraEvent { .. } => "extra_event",
            DivergenceKind::Rgb => "colour",
            DivergenceKind::Cycles => "cycles",
        };
        let distances: Vec<Value> = match (a, b) {
            (Some(a), Some(b)) => (0..3)
                .map(|i| {
                    super::lane_distance(&a, &b, i).map_or(Value::Null, |d| json!(d.to_string()))
                })
                .collect(),
            _ => Vec::new(),
        };
        let class = match &self.class {
            DivergenceClass::NumericDrift => json!({ "class": "numeric_drift" }),
            DivergenceClass::Timing => json!({ "class": "timing" }),
            DivergenceClass::ControlFlow(s) => json!({
                "class": "control_flow",
                "split_seq": s.seq,
                "a": s.a.map(|e| event_json(p, &e, None)),
                "b": s.b.map(|e| event_json(p, &e, None)),
                "branch_after": s.after.map(|e| event_json(p, &e, None)),
                "cause": s.cause.map(|(a, b)| json!({ "a": event_json(p, &a, None), "b": event_json(p, &b, None) })),
            }),
        };
        json!({
            "pixel": [self.x, self.y],
            "seq": self.seq(),
            "kind": kind,
            "classification": class,
            "sides": [labels.a, labels.b],
            "a": a.map(|e| event_json(p, &e, self.a_at)),
            "b": b.map(|e| event_json(p, &e, self.b_at)),
            "lane_ulps": distances,
            "a_outcome": outcome(&self.a),
            "b_outcome": outcome(&self.b),
        })
    }
}

impl CompareReport {
    /// The counts, the ULP histogram, the state coverage and the first
    /// divergence.
    pub fn to_json(&self) -> Value {
        let counts: serde_json::Map<String, Value> = self
            .counts
            .named()
            .into_iter()
            .map(|(k, v)| (k.to_string(), json!(v)))
            .collect();
        let c = &self.a_cycles;
        json!({
            "sides": [self.labels.a, self.labels.b],
            "passed": self.passed(),
            "counts": counts,
            "a_cycles_per_pixel": {
                "mean": c.mean(),
                "min": c.min(),
                "max": c.max(),
                "histogram": c.histogram.iter().map(|(c, n)| json!({"cycles": c, "pixels": n})).collect::<Vec<_>>(),
            },
            "ulp_histogram": self.ulps.to_json(),
            "states_compared": self.states.len(),
            "first_divergence": self.first_divergence.map(|d| d.to_json(&self.labels)),
        })
    }
}
