//! Trace events and trace files: the thesis' per-state float trace (4.10).
//!
//! One [`TraceEvent`] per register-file write: the pixel, the write's sequence
//! number within that pixel, the FSM state that made it, the destination
//! register and lane mask, and the written values as raw bits. The RTL emits
//! them on its trace port, the golden model in the same order.
//!
//! Trace files are versioned binary: a header (magic, version, scene hash,
//! configuration text) followed by fixed-size records, read and written as
//! streams. A truncated or foreign file is an error that says what and where,
//! never a panic and never a silently shorter trace.

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
pub const VERSION: u16 = 1;
/// Bytes per record.
pub const RECORD_BYTES: usize = 24;
/// Longest configuration text a header may carry.
pub const MAX_CONFIG_BYTES: u32 = 64 * 1024;

/// What a trace file says about the run that made it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceHeader {
    /// [`crate::scene::Scene::content_hash`] of the scene traced.
    pub scene_hash: u64,
    /// Free-form configuration (methods, speed-ups, depth, who wrote it),
    /// `key=value` pairs separated by spaces by convention.
    pub config: String,
}

/// Errors reading or writing a trace file.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    #[error(
        "not an rtcosim trace file (starts with {found:02x?}, expected {MAGIC:02x?} \"RTCOSIMT\")"
    )]
    NotATrace { found: Vec<u8> },
    #[error("trace format version {found} is not supported (this build reads version {VERSION})")]
    UnsupportedVersion { found: u16 },
    #[error("trace header declares {len} bytes of configuration; at most {MAX_CONFIG_BYTES} are allowed")]
    ConfigTooLong { len: u32 },
    #[error("trace header configuration is not UTF-8")]
    ConfigNotUtf8,
    #[error("trace file is truncated in the header: it ends {got} bytes into the {what}")]
    TruncatedHeader { what: &'static str, got: usize },
    #[error("trace file is truncated: record {index} (byte offset {offset}) has {got} of {RECORD_BYTES} bytes")]
    TruncatedRecord { index: u64, offset: u64, got: usize },
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

/// Streams events into a trace file.
pub struct TraceWriter<W: Write> {
    out: W,
}

impl<W: Write> TraceWriter<W> {
    /// Writes the header.
    pub fn new(mut out: W, header: &TraceHeader) -> Result<TraceWriter<W>, TraceError> {
        let config = header.config.as_bytes();
        let len = u32::try_from(config.len())
            .ok()
            .filter(|&l| l <= MAX_CONFIG_BYTES)
            .ok_or(TraceError::ConfigTooLong {
                len: config.len().min(u32::MAX as usize) as u32,
            })?;
        out.write_all(&MAGIC)?;
        out.write_all(&VERSION.to_le_bytes())?;
        out.write_all(&0u16.to_le_bytes())?; // flags, reserved
        out.write_all(&header.scene_hash.to_le_bytes())?;
        out.write_all(&len.to_le_bytes())?;
        out.write_all(config)?;
        Ok(TraceWriter { out })
    }

    /// Appends one event.
    pub fn write(&mut self, event: &TraceEvent) -> Result<(), TraceError> {
        Ok(self.out.write_all(&event.to_bytes())?)
    }

    /// Flushes and returns the underlying writer.
    pub fn finish(mut self) -> Result<W, TraceError> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Streams events out of a trace file; an iterator of `Result<TraceEvent>`
/// that ends after the last complete record, or with one error.
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

impl<R: Read> TraceReader<R> {
    /// Reads and checks the header.
    pub fn new(mut input: R) -> Result<TraceReader<R>, TraceError> {
        let mut fixed = [0u8; 8 + 2 + 2 + 8 + 4];
        let got = read_full(&mut input, &mut fixed)?;
        if got < MAGIC.len() || fixed[..8] != MAGIC {
            return Err(TraceError::NotATrace {
                found: fixed[..got.min(8)].to_vec(),
            });
        }
        if got < fixed.len() {
            return Err(TraceError::TruncatedHeader {
                what: "fixed header",
                got,
            });
        }
        let version = u16::from_le_bytes([fixed[8], fixed[9]]);
        if version != VERSION {
            return Err(TraceError::UnsupportedVersion { found: version });
        }
        let scene_hash = u64::from_le_bytes(fixed[12..20].try_into().expect("8 bytes"));
        let len = u32::from_le_bytes(fixed[20..24].try_into().expect("4 bytes"));
        if len > MAX_CONFIG_BYTES {
            return Err(TraceError::ConfigTooLong { len });
        }
        let mut config = vec![0u8; len as usize];
        let got = read_full(&mut input, &mut config)?;
        if got < config.len() {
            return Err(TraceError::TruncatedHeader {
                what: "configuration text",
                got,
            });
        }
        let config = String::from_utf8(config).map_err(|_| TraceError::ConfigNotUtf8)?;
        let offset = (fixed.len() + len as usize) as u64;
        Ok(TraceReader {
            input,
            header: TraceHeader { scene_hash, config },
            index: 0,
            offset,
            failed: false,
        })
    }

    /// The file's header.
    pub fn header(&self) -> &TraceHeader {
        &self.header
    }
}

impl<R: Read> Iterator for TraceReader<R> {
    type Item = Result<TraceEvent, TraceError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let mut record = [0u8; RECORD_BYTES];
        let result = match read_full(&mut self.input, &mut record) {
            Ok(0) => return None,
            Ok(RECORD_BYTES) => Ok(TraceEvent::from_bytes(&record)),
            Ok(got) => Err(TraceError::TruncatedRecord {
                index: self.index,
                offset: self.offset,
                got,
            }),
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

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(n: u32) -> Vec<TraceEvent> {
        (0..n)
            .map(|i| TraceEvent {
                x: 799,
                y: 599,
                seq: i,
                state: 300 + i as u16,
                dst: 17,
                lanes: 0b101,
                values: [1.0f32.to_bits(), 0, f32::NAN.to_bits() ^ i],
            })
            .collect()
    }

    fn file(events: &[TraceEvent]) -> Vec<u8> {
        let header = TraceHeader {
            scene_hash: 0xDEAD_BEEF_0123_4567,
            config: "recip=fast depth=4".into(),
        };
        let mut w = TraceWriter::new(Vec::new(), &header).expect("header");
        for e in events {
            w.write(e).expect("record");
        }
        w.finish().expect("flush")
    }

    #[test]
    fn events_survive_a_round_trip_bit_for_bit() -> Result<(), TraceError> {
        let events = sample(1000);
        let bytes = file(&events);
        assert_eq!(
            bytes.len(),
            24 + "recip=fast depth=4".len() + 1000 * RECORD_BYTES
        );
        let reader = TraceReader::new(&bytes[..])?;
        assert_eq!(reader.header().scene_hash, 0xDEAD_BEEF_0123_4567);
        assert_eq!(reader.header().config, "recip=fast depth=4");
        let back: Vec<TraceEvent> = reader.collect::<Result<_, _>>()?;
        assert_eq!(back, events);
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
        assert_eq!(
            err,
            "trace file is truncated: record 2 (byte offset 90) has 19 of 24 bytes"
        );
        assert!(reader.next().is_none(), "nothing after the error");
    }

    #[test]
    fn a_header_cut_short_is_an_error() {
        let bytes = file(&[]);
        let err = TraceReader::new(&bytes[..15])
            .err()
            .expect("must fail")
            .to_string();
        assert_eq!(
            err,
            "trace file is truncated in the header: it ends 15 bytes into the fixed header"
        );
        let err = TraceReader::new(&bytes[..30])
            .err()
            .expect("must fail")
            .to_string();
        assert_eq!(
            err,
            "trace file is truncated in the header: it ends 6 bytes into the configuration text"
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
    fn a_future_version_is_refused() {
        let mut bytes = file(&sample(1));
        bytes[8] = 2;
        let err = TraceReader::new(&bytes[..])
            .err()
            .expect("must fail")
            .to_string();
        assert_eq!(
            err,
            "trace format version 2 is not supported (this build reads version 1)"
        );
    }

    #[test]
    fn a_hostile_configuration_length_is_refused_before_allocating() {
        let mut bytes = file(&[]);
        bytes[20..24].copy_from_slice(&u32::MAX.to_le_bytes());
        let err = TraceReader::new(&bytes[..]).err().expect("must fail");
        assert!(
            matches!(err, TraceError::ConfigTooLong { len: u32::MAX }),
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
    }
}
