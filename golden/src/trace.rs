//! Trace events and trace files: the thesis' per-state float trace (4.10).
//!
//! One [`TraceEvent`] per register-file write: the pixel, the write's sequence
//! number within that pixel, the FSM state that made it, the destination
//! register and lane mask, and the written values as raw bits. The RTL emits
//! them on its trace port, the golden model in the same order.
//!
//! Trace files are versioned binary, read and written as streams (a frame's
//! trace is tens of millions of events; nothing holds more than a record):
//!
//! - the header: magic `RTCOSIMT`, version (u16), the side that wrote it
//!   (u8: 1 RTL, 2 golden), a reserved byte, the scene's render hash and
//!   configuration hash (u64 each), then two length-prefixed (u32) UTF-8
//!   texts: the configuration (`key=value` pairs) and the scene file;
//! - then 24-byte records, all little-endian, pixel after pixel: each
//!   pixel's events in sequence order, then its end record (colour and
//!   cycles; see [`TraceRecord::PixelEnd`]).
//!
//! A truncated, corrupt or foreign file is an error that says what and
//! where (the byte offset), never a panic and never a silently shorter
//! trace.

use crate::micro::isa;
use std::io::{self, Read, Write};

/// One register-file write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TraceEvent {
    /// Pixel column.
    pub x: u16,
    /// Pixel row (0 at the top).
    pub y: u16,
    /// Index of this write among the pixel's writes, from 0.
    pub seq: u32,
    /// FSM state id (the ISA's state table names it).
    pub state: u16,
    /// Destination register address.
    pub dst: u8,
    /// Lanes written: bit `i` set means lane `i` (x, y, z) was written.
    pub lanes: u8,
    /// Written values as raw f32 bits; lanes not written are 0.
    pub values: [u32; 3],
}

/// The first bytes of every trace file.
pub const MAGIC: [u8; 8] = *b"RTCOSIMT";
/// The format version this code writes and reads.
pub const VERSION: u16 = 2;
/// Bytes per record.
pub const RECORD_BYTES: usize = 24;
/// Longest configuration text a header may carry.
pub const MAX_CONFIG_BYTES: u32 = 64 * 1024;
/// Longest scene text a header may carry.
pub const MAX_SCENE_BYTES: u32 = 1024 * 1024;
/// The `state` field of a pixel's end record (no ISA state has it: state
/// ids are [`isa::dim::ST_BITS`] wide).
pub const END_STATE: u16 = u16::MAX;
/// Bytes of the header before the configuration text.
const FIXED_HEADER_BYTES: usize = 8 + 2 + 1 + 1 + 8 + 8 + 4;

/// Which side of a co-simulation wrote a trace.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TraceSide {
    /// The verilated RTL (its trace port).
    Rtl,
    /// The golden micro-op model ([`crate::micro`]).
    Golden,
}

impl TraceSide {
    fn code(self) -> u8 {
        match self {
            TraceSide::Rtl => 1,
            TraceSide::Golden => 2,
        }
    }

    /// The side as one word, for `key=value` text: `rtl` or `golden`.
    pub fn key(self) -> &'static str {
        match self {
            TraceSide::Rtl => "rtl",
            TraceSide::Golden => "golden",
        }
    }

    fn from_code(code: u8) -> Option<TraceSide> {
        match code {
            1 => Some(TraceSide::Rtl),
            2 => Some(TraceSide::Golden),
            _ => None,
        }
    }
}

impl std::fmt::Display for TraceSide {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TraceSide::Rtl => "RTL",
            TraceSide::Golden => "golden model",
        })
    }
}

/// What a trace file says about the run that made it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceHeader {
    /// Who wrote the events.
    pub side: TraceSide,
    /// [`crate::scene::Scene::render_hash`] of the scene traced: what is
    /// rendered.
    pub scene_hash: u64,
    /// [`crate::scene::Scene::config_hash`]: how it is computed (depth,
    /// speed-ups, methods).
    pub config_hash: u64,
    /// Free-form configuration (methods, speed-ups, depth, the writer, the
    /// simulator's version), `key=value` pairs separated by spaces by
    /// convention.
    pub config: String,
    /// The scene traced, as a scene file's text
    /// ([`crate::scene::Scene::to_toml`]); empty when not recorded.
    pub scene: String,
}

impl TraceHeader {
    /// The value of `key` in the configuration's `key=value` pairs.
    pub fn config_value(&self, key: &str) -> Option<&str> {
        self.config
            .split_whitespace()
            .find_map(|pair| pair.strip_prefix(key)?.strip_prefix('='))
    }
}

/// One record of a trace file: a register-file write, or the end of a pixel
/// with its colour and cycle count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TraceRecord {
    Event(TraceEvent),
    /// The pixel's last record: its colour (STK0_COL's bits) and cycles.
    /// On disk: an event record with state [`END_STATE`], the cycles in
    /// `seq`, `dst` 0, lanes 0b111, the colour in the values.
    PixelEnd {
        x: u16,
        y: u16,
        rgb: [u32; 3],
        cycles: u32,
    },
}

impl TraceRecord {
    /// The pixel the record belongs to.
    pub fn pixel(&self) -> (u16, u16) {
        match *self {
            TraceRecord::Event(e) => (e.x, e.y),
            TraceRecord::PixelEnd { x, y, .. } => (x, y),
        }
    }
}

/// Errors reading or writing a trace file.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    #[error(
        "not an rtcosim trace file (starts with {found:02x?}, expected {MAGIC:02x?} \"RTCOSIMT\")"
    )]
    NotATrace { found: Vec<u8> },
    #[error("trace format version {found} is not supported (this build reads version {VERSION}; re-write the trace with this build)")]
    UnsupportedVersion { found: u16 },
    #[error("trace header (byte offset 10): side code {found} is neither 1 (RTL) nor 2 (golden)")]
    BadSide { found: u8 },
    #[error("trace header declares {len} bytes of {what}; at most {max} are allowed")]
    HeaderTooLong {
        what: &'static str,
        len: u32,
        max: u32,
    },
    #[error("trace header {what} is not UTF-8")]
    NotUtf8 { what: &'static str },
    #[error("trace file is truncated in the header: it ends {got} bytes into the {what}")]
    TruncatedHeader { what: &'static str, got: usize },
    #[error("trace file is truncated: record {index} (byte offset {offset}) has {got} of {RECORD_BYTES} bytes")]
    TruncatedRecord { index: u64, offset: u64, got: usize },
    #[error("trace file is corrupt at record {index} (byte offset {offset}): {what}")]
    Corrupt {
        index: u64,
        offset: u64,
        what: String,
    },
    #[error("reading or writing the trace: {0}")]
    Io(#[from] io::Error),
}

impl TraceEvent {
    fn to_bytes(self) -> [u8; RECORD_BYTES] {
        let mut b = [0u8; RECORD_BYTES];
        b[0..2].copy_from_slice(&self.x.to_le_bytes());
        b[2..4].copy_from_slice(&self.y.to_le_bytes());
        b[4..8].copy_from_slice(&self.seq.to_le_bytes());
        b[8..10].copy_from_slice(&self.state.to_le_bytes());
        b[10] = self.dst;
        b[11] = self.lanes;
        for (i, v) in self.values.iter().enumerate() {
            b[12 + 4 * i..16 + 4 * i].copy_from_slice(&v.to_le_bytes());
        }
        b
    }

    fn from_bytes(b: &[u8; RECORD_BYTES]) -> TraceEvent {
        let u16_at = |i: usize| u16::from_le_bytes([b[i], b[i + 1]]);
        let u32_at = |i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        TraceEvent {
            x: u16_at(0),
            y: u16_at(2),
            seq: u32_at(4),
            state: u16_at(8),
            dst: b[10],
            lanes: b[11],
            values: [u32_at(12), u32_at(16), u32_at(20)],
        }
    }
}

impl TraceRecord {
    fn to_bytes(self) -> [u8; RECORD_BYTES] {
        match self {
            TraceRecord::Event(e) => e.to_bytes(),
            TraceRecord::PixelEnd { x, y, rgb, cycles } => TraceEvent {
                x,
                y,
                seq: cycles,
                state: END_STATE,
                dst: 0,
                lanes: 0b111,
                values: rgb,
            }
            .to_bytes(),
        }
    }

    /// The record, or what is wrong with it.
    fn from_bytes(b: &[u8; RECORD_BYTES]) -> Result<TraceRecord, String> {
        let e = TraceEvent::from_bytes(b);
        if e.state == END_STATE {
            if e.dst != 0 || e.lanes != 0b111 {
                return Err(format!(
                    "a pixel end record must have dst 0 and lanes 0b111, found dst {} and lanes {:#04b}",
                    e.dst, e.lanes
                ));
            }
            return Ok(TraceRecord::PixelEnd {
                x: e.x,
                y: e.y,
                rgb: e.values,
                cycles: e.seq,
            });
        }
        if e.state >= 1 << isa::dim::ST_BITS {
            return Err(format!(
                "state {} is not a controller state (expected below {})",
                e.state,
                1 << isa::dim::ST_BITS
            ));
        }
        if e.lanes == 0 || e.lanes > 0b111 {
            return Err(format!(
                "lane mask {:#04x} is not 1..=0b111 (x, y, z)",
                e.lanes
            ));
        }
        Ok(TraceRecord::Event(e))
    }
}

/// Streams records into a trace file.
pub struct TraceWriter<W: Write> {
    out: W,
}

/// `text` as a length-prefixed header field, at most `max` bytes.
fn header_text<'a>(
    what: &'static str,
    text: &'a str,
    max: u32,
) -> Result<(u32, &'a [u8]), TraceError> {
    let bytes = text.as_bytes();
    u32::try_from(bytes.len())
        .ok()
        .filter(|&l| l <= max)
        .map(|len| (len, bytes))
        .ok_or(TraceError::HeaderTooLong {
            what,
            len: bytes.len().min(u32::MAX as usize) as u32,
            max,
        })
}

impl<W: Write> TraceWriter<W> {
    /// Writes the header.
    pub fn new(mut out: W, header: &TraceHeader) -> Result<TraceWriter<W>, TraceError> {
        let (config_len, config) = header_text("configuration", &header.config, MAX_CONFIG_BYTES)?;
        let (scene_len, scene) = header_text("scene text", &header.scene, MAX_SCENE_BYTES)?;
        out.write_all(&MAGIC)?;
        out.write_all(&VERSION.to_le_bytes())?;
        out.write_all(&[header.side.code(), 0])?; // side, reserved
        out.write_all(&header.scene_hash.to_le_bytes())?;
        out.write_all(&header.config_hash.to_le_bytes())?;
        out.write_all(&config_len.to_le_bytes())?;
        out.write_all(config)?;
        out.write_all(&scene_len.to_le_bytes())?;
        out.write_all(scene)?;
        Ok(TraceWriter { out })
    }

    /// Appends one event.
    pub fn write(&mut self, event: &TraceEvent) -> Result<(), TraceError> {
        self.record(TraceRecord::Event(*event))
    }

    /// Appends one record.
    pub fn record(&mut self, record: TraceRecord) -> Result<(), TraceError> {
        Ok(self.out.write_all(&record.to_bytes())?)
    }

    /// Flushes and returns the underlying writer.
    pub fn finish(mut self) -> Result<W, TraceError> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Streams records out of a trace file; an iterator of
/// `Result<TraceRecord>` that ends after the last complete record, or with
/// one error.
pub struct TraceReader<R: Read> {
    input: R,
    header: TraceHeader,
    index: u64,
    offset: u64,
    failed: bool,
}

/// Reads until `buf` is full or the input ends; returns the bytes read.
fn read_full(input: &mut impl Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match input.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}

/// Reads a length-prefixed text field of the header.
fn read_text(input: &mut impl Read, what: &'static str, max: u32) -> Result<String, TraceError> {
    let mut len = [0u8; 4];
    let got = read_full(input, &mut len)?;
    if got < len.len() {
        return Err(TraceError::TruncatedHeader {
            what: "length of the scene text",
            got,
        });
    }
    read_text_of_len(input, what, u32::from_le_bytes(len), max)
}

fn read_text_of_len(
    input: &mut impl Read,
    what: &'static str,
    len: u32,
    max: u32,
) -> Result<String, TraceError> {
    if len > max {
        return Err(TraceError::HeaderTooLong { what, len, max });
    }
    let mut text = vec![0u8; len as usize];
    let got = read_full(input, &mut text)?;
    if got < text.len() {
        return Err(TraceError::TruncatedHeader { what, got });
    }
    String::from_utf8(text).map_err(|_| TraceError::NotUtf8 { what })
}

impl<R: Read> TraceReader<R> {
    /// Reads and checks the header.
    pub fn new(mut input: R) -> Result<TraceReader<R>, TraceError> {
        let mut fixed = [0u8; FIXED_HEADER_BYTES];
        let got = read_full(&mut input, &mut fixed)?;
        if got < MAGIC.len() || fixed[..8] != MAGIC {
            return Err(TraceError::NotATrace {
                found: fixed[..got.min(8)].to_vec(),
            });
        }
        if got < 10 {
            return Err(TraceError::TruncatedHeader {
                what: "fixed header",
                got,
            });
        }
        let version = u16::from_le_bytes([fixed[8], fixed[9]]);
        if version != VERSION {
            return Err(TraceError::UnsupportedVersion { found: version });
        }
        if got < fixed.len() {
            return Err(TraceError::TruncatedHeader {
                what: "fixed header",
                got,
            });
        }
        let side =
            TraceSide::from_code(fixed[10]).ok_or(TraceError::BadSide { found: fixed[10] })?;
        let u64_at = |i: usize| u64::from_le_bytes(fixed[i..i + 8].try_into().expect("8 bytes"));
        let scene_hash = u64_at(12);
        let config_hash = u64_at(20);
        let config_len = u32::from_le_bytes(fixed[28..32].try_into().expect("4 bytes"));
        let config = read_text_of_len(
            &mut input,
            "configuration text",
            config_len,
            MAX_CONFIG_BYTES,
        )?;
        let scene = read_text(&mut input, "scene text", MAX_SCENE_BYTES)?;
        let offset = (fixed.len() + config.len() + 4 + scene.len()) as u64;
        Ok(TraceReader {
            input,
            header: TraceHeader {
                side,
                scene_hash,
                config_hash,
                config,
                scene,
            },
            index: 0,
            offset,
            failed: false,
        })
    }

    /// The file's header.
    pub fn header(&self) -> &TraceHeader {
        &self.header
    }

    /// The byte offset of the next record.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// The index of the next record.
    pub fn index(&self) -> u64 {
        self.index
    }
}

impl<R: Read> Iterator for TraceReader<R> {
    type Item = Result<TraceRecord, TraceError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let mut record = [0u8; RECORD_BYTES];
        let (index, offset) = (self.index, self.offset);
        let result = match read_full(&mut self.input, &mut record) {
            Ok(0) => return None,
            Ok(RECORD_BYTES) => {
                TraceRecord::from_bytes(&record).map_err(|what| TraceError::Corrupt {
                    index,
                    offset,
                    what,
                })
            }
            Ok(got) => Err(TraceError::TruncatedRecord { index, offset, got }),
            Err(e) => Err(e.into()),
        };
        if result.is_err() {
            self.failed = true;
        }
        self.index += 1;
        self.offset += RECORD_BYTES as u64;
        Some(result)
    }
}

/// The human-readable form of an event: one line, lanes shown as raw bits and
/// as the float they hold. `state_name` and `register_name` turn ids into
/// names (usually the ISA's tables, `&isa::state_name` and
/// `&isa::register_name`); pass `|_| None` to print numbers, written as
/// [`isa`] writes unnamed ones.
pub fn format_event(
    e: &TraceEvent,
    state_name: &dyn Fn(u16) -> Option<&'static str>,
    register_name: &dyn Fn(u8) -> Option<&'static str>,
) -> String {
    let state = state_name(e.state).map_or_else(|| isa::unnamed_state(e.state), str::to_string);
    let dst = register_name(e.dst).map_or_else(|| isa::unnamed_register(e.dst), str::to_string);
    let lanes = isa::lanes_label(e.lanes);
    let mut line = format!(
        "({:>4},{:>4}) #{:<5} {state:<16} {dst}.{lanes}",
        e.x, e.y, e.seq
    );
    for i in 0..3 {
        if e.lanes >> i & 1 == 1 {
            line += &format!(" {:#010x}({:e})", e.values[i], f32::from_bits(e.values[i]));
        }
    }
    line
}

/// The human-readable form of a record: [`format_event`] for an event, the
/// colour and cycles for a pixel's end.
pub fn format_record(
    r: &TraceRecord,
    state_name: &dyn Fn(u16) -> Option<&'static str>,
    register_name: &dyn Fn(u8) -> Option<&'static str>,
) -> String {
    match r {
        TraceRecord::Event(e) => format_event(e, state_name, register_name),
        TraceRecord::PixelEnd { x, y, rgb, cycles } => {
            let mut line = format!("({x:>4},{y:>4}) end    {cycles} cycles, rgb");
            for c in rgb {
                line += &format!(" {c:#010x}({:e})", f32::from_bits(*c));
            }
            line
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(n: u32) -> Vec<TraceEvent> {
        (0..n)
            .map(|i| TraceEvent {
                x: 799,
                y: 599,
                seq: i,
                state: 300 + (i % 200) as u16,
                dst: 17,
                lanes: 0b101,
                values: [1.0f32.to_bits(), 0, f32::NAN.to_bits() ^ i],
            })
            .collect()
    }

    fn header() -> TraceHeader {
        TraceHeader {
            side: TraceSide::Rtl,
            scene_hash: 0xDEAD_BEEF_0123_4567,
            config_hash: 0x0123_4567_89AB_CDEF,
            config: "recip=fast depth=4".into(),
            scene: "[camera]".into(),
        }
    }

    /// Header bytes of [`header`]: fixed part, config, scene length, scene.
    const HEADER_BYTES: usize = FIXED_HEADER_BYTES + 18 + 4 + 8;

    fn file(events: &[TraceEvent]) -> Vec<u8> {
        let mut w = TraceWriter::new(Vec::new(), &header()).expect("header");
        for e in events {
            w.write(e).expect("record");
        }
        w.finish().expect("flush")
    }

    #[test]
    fn records_survive_a_round_trip_bit_for_bit() -> Result<(), TraceError> {
        let mut records: Vec<TraceRecord> =
            sample(1000).into_iter().map(TraceRecord::Event).collect();
        records.push(TraceRecord::PixelEnd {
            x: 799,
            y: 599,
            rgb: [0x3f00_0000, 0, 0x7fc0_0000],
            cycles: 159,
        });
        let mut w = TraceWriter::new(Vec::new(), &header())?;
        for r in &records {
            w.record(*r)?;
        }
        let bytes = w.finish()?;
        assert_eq!(bytes.len(), HEADER_BYTES + 1001 * RECORD_BYTES);
        let reader = TraceReader::new(&bytes[..])?;
        assert_eq!(reader.header(), &header());
        assert_eq!(reader.header().config_value("depth"), Some("4"));
        assert_eq!(reader.header().config_value("dept"), None);
        let back: Vec<TraceRecord> = reader.collect::<Result<_, _>>()?;
        assert_eq!(back, records);
        Ok(())
    }

    #[test]
    fn a_record_cut_short_is_an_error_naming_the_record_and_offset() {
        let bytes = file(&sample(3));
        let cut = &bytes[..bytes.len() - 5];
        let mut reader = TraceReader::new(cut).expect("header is intact");
        assert!(reader.next().expect("first").is_ok());
        assert!(reader.next().expect("second").is_ok());
        let err = reader.next().expect("third").unwrap_err().to_string();
        let offset = HEADER_BYTES + 2 * RECORD_BYTES;
        assert_eq!(
            err,
            format!("trace file is truncated: record 2 (byte offset {offset}) has 19 of 24 bytes")
        );
        assert!(reader.next().is_none(), "nothing after the error");
    }

    #[test]
    fn a_corrupt_record_is_an_error_naming_the_record_offset_and_field() {
        let mut bytes = file(&sample(3));
        // Record 1's lane mask.
        let at = HEADER_BYTES + RECORD_BYTES + 11;
        bytes[at] = 0x40;
        let mut reader = TraceReader::new(&bytes[..]).expect("header is intact");
        assert!(reader.next().expect("first").is_ok());
        let err = reader.next().expect("second").unwrap_err().to_string();
        assert_eq!(
            err,
            format!(
                "trace file is corrupt at record 1 (byte offset {}): lane mask 0x40 is not 1..=0b111 (x, y, z)",
                HEADER_BYTES + RECORD_BYTES
            )
        );
        assert!(reader.next().is_none(), "nothing after the error");
        // A state past the ISA's.
        let mut bytes = file(&sample(1));
        bytes[HEADER_BYTES + 8..HEADER_BYTES + 10].copy_from_slice(&4000u16.to_le_bytes());
        let err = TraceReader::new(&bytes[..]).expect("header").next();
        assert!(
            matches!(err, Some(Err(TraceError::Corrupt { index: 0, .. }))),
            "{err:?}"
        );
    }

    #[test]
    fn a_header_cut_short_is_an_error() {
        let bytes = file(&[]);
        let cut = |n: usize| {
            TraceReader::new(&bytes[..n])
                .err()
                .expect("must fail")
                .to_string()
        };
        assert_eq!(
            cut(15),
            "trace file is truncated in the header: it ends 15 bytes into the fixed header"
        );
        assert_eq!(
            cut(FIXED_HEADER_BYTES + 6),
            "trace file is truncated in the header: it ends 6 bytes into the configuration text"
        );
        assert_eq!(
            cut(HEADER_BYTES - 3),
            "trace file is truncated in the header: it ends 5 bytes into the scene text"
        );
    }

    #[test]
    fn a_foreign_file_is_not_a_trace() {
        let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR";
        let err = TraceReader::new(&png[..]).err().expect("must fail");
        assert!(matches!(err, TraceError::NotATrace { .. }), "{err}");
        assert!(matches!(
            TraceReader::new(&b""[..]).err(),
            Some(TraceError::NotATrace { .. })
        ));
    }

    #[test]
    fn another_version_or_side_is_refused() {
        let mut bytes = file(&sample(1));
        bytes[8] = 1;
        let err = TraceReader::new(&bytes[..])
            .err()
            .expect("must fail")
            .to_string();
        assert_eq!(
            err,
            "trace format version 1 is not supported (this build reads version 2; re-write the trace with this build)"
        );
        let mut bytes = file(&sample(1));
        bytes[10] = 7;
        let err = TraceReader::new(&bytes[..]).err().expect("must fail");
        assert!(matches!(err, TraceError::BadSide { found: 7 }), "{err}");
    }

    #[test]
    fn a_hostile_text_length_is_refused_before_allocating() {
        let mut bytes = file(&[]);
        bytes[28..32].copy_from_slice(&u32::MAX.to_le_bytes());
        let err = TraceReader::new(&bytes[..]).err().expect("must fail");
        assert!(
            matches!(err, TraceError::HeaderTooLong { len: u32::MAX, .. }),
            "{err}"
        );
        let mut bytes = file(&[]);
        let at = FIXED_HEADER_BYTES + 18;
        bytes[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        let err = TraceReader::new(&bytes[..]).err().expect("must fail");
        assert!(
            matches!(
                err,
                TraceError::HeaderTooLong {
                    what: "scene text",
                    ..
                }
            ),
            "{err}"
        );
    }

    #[test]
    fn the_text_form_names_lanes_and_values() {
        let e = sample(1)[0];
        let line = format_event(&e, &|s| (s == 300).then_some("S_DOT1"), &|_| None);
        assert_eq!(
            line,
            "( 799, 599) #0     S_DOT1           r17.x_z 0x3f800000(1e0) 0x7fc00000(NaN)"
        );
        let end = TraceRecord::PixelEnd {
            x: 3,
            y: 4,
            rgb: [0x3f80_0000, 0, 0],
            cycles: 159,
        };
        assert_eq!(
            format_record(&end, &|_| None, &|_| None),
            "(   3,   4) end    159 cycles, rgb 0x3f800000(1e0) 0x00000000(0e0) 0x00000000(0e0)"
        );
    }
}
