//! Two trace files against each other: the thesis' verification tool
//! (section 4.10), through the same comparison engine as the live
//! co-simulation ([`crate::check::compare`]).
//!
//! Both files are streamed pixel by pixel ([`PixelReader`]: one pixel's
//! events at a time, checked for order and completeness) and aligned on
//! the pixel coordinates (both are written in row order); each pixel common
//! to both is compared with a [`PixelCompare`], event by event at equal
//! sequence numbers. Each divergent pixel is classified (numeric drift or
//! control flow, see [`DivergenceClass`]), its diverging events are named
//! in the Verilog (the state's line in the controller of the processor the
//! headers name: `pp_ctrl.v` or `fast_ctrl.v`) and in the Rust (the
//! line of the golden model that issues the event, found by re-running the
//! pixel on the scene the trace header carries), and the first one comes
//! with the events before it on both sides.
//!
//! Traces of different scenes (render hashes) are refused; traces of one
//! scene under different configurations (methods, depth, speed-ups, the
//! side that wrote them) are compared, and their header differences listed.

use crate::check::compare::{
    compare_pixel, CompareReport, Divergence, DivergenceClass, Labels, PixelVerdict, SourceLine,
    Tolerance,
};
use crate::check::trace_files;
use golden::micro::{Fault, Processor};
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::trace::{TraceError, TraceEvent, TraceHeader, TraceReader, TraceRecord};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

/// Errors of a trace diff: a file that cannot be read, is not a trace, or
/// breaks the format's order; or two traces that cannot be compared.
#[derive(Debug, thiserror::Error)]
pub enum TraceDiffError {
    #[error("{}: {source}", path.display())]
    Open {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: {source}", path.display())]
    Read { path: PathBuf, source: TraceError },
    #[error("{}: record {index} (byte offset {offset}): {what}", path.display())]
    Order {
        path: PathBuf,
        index: u64,
        offset: u64,
        what: String,
    },
    #[error("{}: the file ends inside pixel ({x}, {y}): {events} events and no end record (a truncated trace?)", path.display())]
    Unfinished {
        path: PathBuf,
        x: u16,
        y: u16,
        events: usize,
    },
    #[error(
        "the traces are of different scenes (scene hash {a:016x} in {}, {b:016x} in {}): \
         only traces of one scene can be compared",
        a_path.display(),
        b_path.display()
    )]
    DifferentScenes {
        a_path: PathBuf,
        a: u64,
        b_path: PathBuf,
        b: u64,
    },
    #[error("no pixel is in both traces ({a_pixels} pixels only in {}, {b_pixels} only in {})", a_path.display(), b_path.display())]
    NothingInCommon {
        a_path: PathBuf,
        a_pixels: u64,
        b_path: PathBuf,
        b_pixels: u64,
    },
}

/// One pixel of a trace: its events in sequence order and its outcome.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TracePixel {
    pub x: u16,
    pub y: u16,
    pub events: Vec<TraceEvent>,
    pub outcome: PixelOutcome,
}

/// A trace file read pixel by pixel, checking that pixels come in row
/// order, each with sequence numbers 0, 1, 2, ... and an end record.
pub struct PixelReader {
    path: PathBuf,
    reader: TraceReader<BufReader<File>>,
    last: Option<(u16, u16)>,
}

impl PixelReader {
    pub fn open(path: &Path) -> Result<PixelReader, TraceDiffError> {
        let file = File::open(path).map_err(|source| TraceDiffError::Open {
            path: path.to_path_buf(),
            source,
        })?;
        let reader =
            TraceReader::new(BufReader::with_capacity(1 << 16, file)).map_err(|source| {
                TraceDiffError::Read {
                    path: path.to_path_buf(),
                    source,
                }
            })?;
        Ok(PixelReader {
            path: path.to_path_buf(),
            reader,
            last: None,
        })
    }

    pub fn header(&self) -> &TraceHeader {
        self.reader.header()
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Reads the next pixel into `pixel` (reusing its buffer); false at the
    /// end of the file.
    pub fn next_into(&mut self, pixel: &mut TracePixel) -> Result<bool, TraceDiffError> {
        pixel.events.clear();
        loop {
            let (index, offset) = (self.reader.index(), self.reader.offset());
            let order = |what: String| TraceDiffError::Order {
                path: self.path.clone(),
                index,
                offset,
                what,
            };
            let record = match self.reader.next() {
                None => {
                    return match pixel.events.first() {
                        None => Ok(false),
                        Some(e) => Err(TraceDiffError::Unfinished {
                            path: self.path.clone(),
                            x: e.x,
                            y: e.y,
                            events: pixel.events.len(),
                        }),
                    }
                }
                Some(r) => r.map_err(|source| TraceDiffError::Read {
                    path: self.path.clone(),
                    source,
                })?,
            };
            let (x, y) = record.pixel();
            if let Some(first) = pixel.events.first() {
                if (first.x, first.y) != (x, y) {
                    return Err(order(format!(
                        "expected more of pixel ({}, {}) or its end record, found a record of pixel ({x}, {y})",
                        first.x, first.y
                    )));
                }
            } else if let Some((lx, ly)) = self.last {
                if (y, x) <= (ly, lx) {
                    return Err(order(format!(
                        "pixel ({x}, {y}) after pixel ({lx}, {ly}): pixels must come in row order, each once"
                    )));
                }
            }
            match record {
                TraceRecord::Event(e) => {
                    let expected = pixel.events.len() as u64;
                    if u64::from(e.seq) != expected {
                        return Err(order(format!(
                            "event of pixel ({x}, {y}) has sequence number {}, expected {expected}",
                            e.seq
                        )));
                    }
                    pixel.events.push(e);
                }
                TraceRecord::PixelEnd { rgb, cycles, .. } => {
                    self.last = Some((x, y));
                    pixel.x = x;
                    pixel.y = y;
                    pixel.outcome = PixelOutcome {
                        rgb,
                        cycles: u64::from(cycles),
                        events: pixel.events.len() as u64,
                    };
                    return Ok(true);
                }
            }
        }
    }
}

/// How to diff.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DiffOptions {
    pub tolerance: Tolerance,
    /// Only this pixel.
    pub pixel: Option<(u32, u32)>,
    /// Events before the first divergence to keep, from both sides.
    pub context: usize,
    /// Name the Rust lines of every divergent pixel's events (each costs a
    /// golden run of the pixel per side), not only the first one's.
    pub sources_for_all: bool,
}

/// A key whose value differs between the two headers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HeaderDifference {
    pub key: String,
    pub a: Option<String>,
    pub b: Option<String>,
}

/// The `key=value` pairs of the headers that differ (the writer's version
/// aside), side first.
pub fn header_differences(a: &TraceHeader, b: &TraceHeader) -> Vec<HeaderDifference> {
    let pairs = |h: &TraceHeader| -> Vec<(String, String)> {
        h.config
            .split_whitespace()
            .filter_map(|p| p.split_once('='))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    };
    let (pa, pb) = (pairs(a), pairs(b));
    let mut keys: Vec<&String> = pa.iter().chain(&pb).map(|(k, _)| k).collect();
    let mut seen = std::collections::HashSet::new();
    keys.retain(|k| seen.insert(*k));
    let value = |p: &[(String, String)], k: &str| {
        p.iter().find(|(key, _)| key == k).map(|(_, v)| v.clone())
    };
    keys.into_iter()
        .filter(|k| k.as_str() != "writer")
        .filter_map(|k| {
            let (va, vb) = (value(&pa, k), value(&pb, k));
            (va != vb).then(|| HeaderDifference {
                key: k.clone(),
                a: va,
                b: vb,
            })
        })
        .collect()
}

/// The events before the first divergence, from both sides.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Context {
    pub a: Vec<TraceEvent>,
    pub b: Vec<TraceEvent>,
}

/// What a trace diff found.
#[derive(Debug, Clone)]
pub struct TraceDiff {
    pub a_header: TraceHeader,
    pub b_header: TraceHeader,
    pub header_differences: Vec<HeaderDifference>,
    /// The comparison of the pixels in both traces.
    pub report: CompareReport,
    /// Pixels in one trace only (not compared).
    pub only_a: u64,
    pub only_b: u64,
    /// Every divergent pixel, in row order, and its class.
    pub divergent: Vec<(u32, u32, DivergenceClass)>,
    /// The events before the first divergence.
    pub context: Context,
}

impl TraceDiff {
    /// True when pixels were compared and none diverged.
    pub fn passed(&self) -> bool {
        self.report.passed()
    }
}

/// A golden model of one side's scene and fault, from its header, to find
/// the Rust line of an event by re-running its pixel.
struct Rerun {
    proc: Option<Processor>,
}

impl Rerun {
    fn of(header: &TraceHeader) -> Rerun {
        let scene = Scene::from_toml(&header.scene, "trace header")
            .ok()
            .filter(|s| s.render_hash() == header.scene_hash);
        let fault = header
            .config_value("fault")
            .and_then(|f| f.parse::<Fault>().ok());
        Rerun {
            proc: scene.map(|s| Processor::new(&s).with_fault(fault)),
        }
    }

    /// The golden line that issues event `e` of its pixel, when the model
    /// makes an event with its state at its sequence number.
    fn line_of(&self, e: &TraceEvent) -> Option<SourceLine> {
        let proc = self.proc.as_ref()?;
        let mut found = None;
        let (x, y) = (u32::from(e.x), u32::from(e.y));
        if !proc.contains(x, y) {
            return None;
        }
        proc.render_pixel(x, y, |g, at| {
            if g.seq == e.seq && g.state == e.state {
                found = Some(at);
            }
        });
        found
    }
}

/// The [`Labels`] of a diff: the file names, or the sides when the names
/// are equal; states are named at the lines of the processor that the
/// headers name (A's first; the compact one when neither does, or a file
/// cannot be read: the diff then reports why).
pub fn labels(a: &Path, b: &Path) -> Labels {
    let name = |p: &Path| {
        p.file_name()
            .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
    };
    let (na, nb) = (name(a), name(b));
    let labels = if na == nb {
        Labels::new("A", "B")
    } else {
        Labels::new(na, nb)
    };
    let processor = |p: &Path| {
        PixelReader::open(p)
            .ok()
            .and_then(|r| trace_files::processor_of(r.header()))
    };
    labels.on(processor(a).or_else(|| processor(b)).unwrap_or_default())
}

/// Diffs trace `a` against trace `b`. `each` sees every divergent pixel's
/// verdict as it is found (with its source lines filled in for the first,
/// and for all with [`DiffOptions::sources_for_all`]); `progress` is
/// called with the number of pixels compared, now and then.
pub fn diff(
    a: &Path,
    b: &Path,
    options: &DiffOptions,
    each: &mut dyn FnMut(&PixelVerdict),
    progress: &dyn Fn(u64),
) -> Result<TraceDiff, TraceDiffError> {
    let mut ra = PixelReader::open(a)?;
    let mut rb = PixelReader::open(b)?;
    let (ha, hb) = (ra.header().clone(), rb.header().clone());
    if ha.scene_hash != hb.scene_hash {
        return Err(TraceDiffError::DifferentScenes {
            a_path: a.to_path_buf(),
            a: ha.scene_hash,
            b_path: b.to_path_buf(),
            b: hb.scene_hash,
        });
    }
    let (rerun_a, rerun_b) = (Rerun::of(&ha), Rerun::of(&hb));
    let empty = || TracePixel {
        x: 0,
        y: 0,
        events: Vec::new(),
        outcome: PixelOutcome {
            rgb: [0; 3],
            cycles: 0,
            events: 0,
        },
    };
    let (mut pa, mut pb) = (empty(), empty());
    let mut more_a = ra.next_into(&mut pa)?;
    let mut more_b = rb.next_into(&mut pb)?;
    let mut report = CompareReport::new(labels(a, b));
    let (mut only_a, mut only_b) = (0u64, 0u64);
    let mut divergent = Vec::new();
    let mut context = Context::default();
    let mut since_progress = 0u64;
    while more_a || more_b {
        let key = |p: &TracePixel| (p.y, p.x);
        let order = match (more_a, more_b) {
            (true, true) => key(&pa).cmp(&key(&pb)),
            (true, false) => std::cmp::Ordering::Less,
            _ => std::cmp::Ordering::Greater,
        };
        let wanted = |p: &TracePixel| {
            options
                .pixel
                .map_or(true, |(x, y)| (u32::from(p.x), u32::from(p.y)) == (x, y))
        };
        match order {
            std::cmp::Ordering::Less => {
                only_a += u64::from(wanted(&pa));
                more_a = ra.next_into(&mut pa)?;
            }
            std::cmp::Ordering::Greater => {
                only_b += u64::from(wanted(&pb));
                more_b = rb.next_into(&mut pb)?;
            }
            std::cmp::Ordering::Equal => {
                if wanted(&pa) {
                    let mut v = compare(&pa, &pb, options.tolerance);
                    if let Some(d) = v.first.as_mut() {
                        let first = report.first_divergence.is_none();
                        if first || options.sources_for_all {
                            fill_sources(d, &rerun_a, &rerun_b);
                        }
                        if first {
                            context = context_before(&pa, &pb, d, options.context);
                        }
                        divergent.push((d.x, d.y, d.class));
                        each(&v);
                    }
                    report.add(&v);
                    since_progress += 1;
                    if since_progress == 1024 {
                        progress(since_progress);
                        since_progress = 0;
                    }
                }
                more_a = ra.next_into(&mut pa)?;
                more_b = rb.next_into(&mut pb)?;
            }
        }
    }
    progress(since_progress);
    if report.counts.pixels == 0 {
        return Err(TraceDiffError::NothingInCommon {
            a_path: a.to_path_buf(),
            a_pixels: only_a,
            b_path: b.to_path_buf(),
            b_pixels: only_b,
        });
    }
    Ok(TraceDiff {
        header_differences: header_differences(&ha, &hb),
        a_header: ha,
        b_header: hb,
        report,
        only_a,
        only_b,
        divergent,
        context,
    })
}

/// One pixel of both traces through the engine.
fn compare(a: &TracePixel, b: &TracePixel, tolerance: Tolerance) -> PixelVerdict {
    let (x, y) = (u32::from(a.x), u32::from(a.y));
    compare_pixel(x, y, tolerance, &a.events, a.outcome, |sink| {
        for e in &b.events {
            sink(e, None);
        }
        b.outcome
    })
}

fn fill_sources(d: &mut Divergence, a: &Rerun, b: &Rerun) {
    let (ea, eb) = d.events();
    d.a_at = ea.and_then(|e| a.line_of(&e));
    d.b_at = eb.and_then(|e| b.line_of(&e));
}

/// The `k` events before `d`'s sequence number (or before each side's end,
/// for a colour or cycle divergence), from both sides.
fn context_before(a: &TracePixel, b: &TracePixel, d: &Divergence, k: usize) -> Context {
    let before = |events: &[TraceEvent]| {
        let end = d
            .seq()
            .map_or(events.len(), |s| (s as usize).min(events.len()));
        events[end.saturating_sub(k)..end].to_vec()
    };
    Context {
        a: before(&a.events),
        b: before(&b.events),
    }
}
