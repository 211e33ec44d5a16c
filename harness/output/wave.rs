//! The waveform window: one pixel re-run on the pixel processor verilated
//! with `--trace-fst`, dumped to an FST file for K cycles either side of a
//! divergence, with the files GTKWave needs to show the controller's state
//! names (`rtcosim cosim --wave K`).
//!
//! [`write_window`] builds the traced twin of the variant the scene names
//! (the same RTL and Verilator flags plus `--trace-fst`, one per method pair:
//! `Vpixel_processor_wave_<recip>_<sqrt>`, see `build.rs`), resets it, loads
//! the scene, sets the fault, and runs the pixel twice, each time on a fresh
//! model: once to find the cycle of the divergent event, once with the FST
//! open for the window. It writes three files side by side:
//!
//! - `wave.fst`: the window (every signal of the design);
//! - `wave-states.txt`: a GTKWave translate filter file, `<hex value> <name>`
//!   for every controller state of `rtl/pp/isa.vh`;
//! - `wave.gtkw`: a GTKWave save file that shows the clock, the pixel
//!   handshake, the controller state (`u_ctrl.st_q`, through the filter),
//!   the opcode and stack pointer, the trace and fault ports and the colour,
//!   with the primary marker on the divergence.
//!
//! Open them with `gtkwave wave.fst wave.gtkw`.
//!
//! # A streamed design
//!
//! A fast processor's pixel shares its cycles with 31 other contexts, so the
//! re-run is its tile ([`Replay`]): the fast processor verilated with
//! `--trace-fst` (`Vfast_pp_wave_<recip>_<sqrt>`) is fed the tile's
//! coordinates as `cosim --processor fast` fed them (with the same
//! backpressure), twice, from reset; the window is of the tile's frame,
//! its cycles counted from the one that takes the first coordinate, around
//! the divergent event's cycle, clamped to the pixel's life (its take to its
//! done turn). The save file shows the streams, the controller's turn
//! (context, take, issue, done, the issuing state and opcode), the trace
//! and fault ports and the colour (`TOP.fast_pp`). A run through a top of
//! fast processors (`--procs`) is re-run the same way on one processor: the
//! pixel's events are the same, its cycles those of one processor.
//!
//! # The time axis
//!
//! Cycle `c` of the pixel begins with its rising edge at `c` ns (1000 ps,
//! the file's time unit is 1 ps) and is sampled (clk low, where the harness
//! reads the outputs) at `c` ns + 500 ps. Cycle 0 is the idle cycle whose
//! rising edge takes `start`; cycle 1 is the pixel's first counted cycle,
//! as in [`crate::design::pixel_proc`] (a trace event of cycle `c` is written by the
//! rising edge at `c + 1` ns). The window `first..=last` spans
//! `first` ns to `last + 1` ns.

use crate::check::compare::Divergence;
use crate::check::cosim;
use crate::design::pixel_proc::PixelProcessor;
use crate::design::processor::{Driver, ProcessorKind, Radix, WaveBits};
use crate::design::top::{Source, Stall, Top};
use crate::design::{Design, Flavour};
use crate::design::{Fault, PpError};
use golden::micro::isa::{self, dim};
use golden::pixel::PixelOutcome;
use golden::scene::Scene;
use golden::window::Window;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The FST file's name when only a directory is given ([`write_window_in`]).
pub const FST_NAME: &str = "wave.fst";

/// Picoseconds per cycle in the FST file (`harness/design/cpp/pp_wave.h`).
pub const PS_PER_CYCLE: u64 = 1000;

/// How the run that diverged drove the RTL, so that the re-run drives it
/// the same way: the design's waveform twin (the processor alone: a top's
/// divergence is re-run on one processor), driven one pixel from reset, or
/// fed `tile`'s coordinates row by row from reset with `out_ready` held
/// back by `stall` as the run drew it for the tile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Replay {
    /// The waveform twin re-run.
    pub design: Design,
    /// The tile that holds the pixel (its stream's frame; unused one
    /// pixel at a time).
    pub tile: Window,
    pub stall: Stall,
}

impl Replay {
    /// The re-run of pixel row `y` of a run of `window` on `design` with
    /// `stall`: the tile of [`cosim::tiles`] that holds the row, on the
    /// processor alone.
    pub fn of(design: &Design, stall: Stall, window: Window, y: u32) -> Replay {
        let tile = cosim::tiles(window)
            .into_iter()
            .find(|t| (t.y..t.y + t.height).contains(&y))
            .unwrap_or(window);
        Replay {
            design: design.procs(None).flavour(Flavour::Wave),
            tile,
            stall,
        }
    }

    /// The re-run of one pixel on `design`'s twin, never stalled (a
    /// design driven one pixel at a time).
    pub fn pixel(design: &Design, x: u32, y: u32) -> Replay {
        Replay::of(design, Stall::NONE, Window::new(x, y, 1, 1), y)
    }

    /// The processor it runs on.
    pub fn processor(&self) -> ProcessorKind {
        self.design.processor
    }

    /// Whether the pixel's tile is streamed (not one pixel alone).
    pub fn streamed(&self) -> bool {
        self.design.driver() == Driver::Streams
    }
}

/// What [`write_window`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WaveWindow {
    /// The pixel re-run.
    pub x: u32,
    pub y: u32,
    /// How (the fast processor: in which tile).
    pub replay: Replay,
    /// The cycle of the divergence: the one in which the RTL's divergent
    /// event was sampled (the rising edge at `divergence_cycle + 1` ns
    /// writes it), or the pixel's last cycle.
    pub divergence_cycle: u64,
    /// Why that cycle ([`DivergenceAt`]).
    pub at: DivergenceAt,
    /// The first and last cycle dumped: `divergence_cycle` ± K, clamped to
    /// the pixel (cycle 0, the start cycle, to its done cycle; the fast
    /// processor: the tile's frame cycles of its take to its done turn).
    pub first_cycle: u64,
    pub last_cycle: u64,
    /// The pixel's outcome on the traced model (the compact processor: its
    /// `cycles` is the done cycle).
    pub outcome: PixelOutcome,
    /// The files written.
    pub fst: PathBuf,
    pub filter: PathBuf,
    pub gtkw: PathBuf,
}

/// How the divergence cycle was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DivergenceAt {
    /// The cycle of the RTL's event with this sequence number, in this
    /// controller state.
    Event { seq: u32, state: u16 },
    /// The RTL wrote fewer events than the sequence number (golden's event
    /// has no counterpart): the pixel's last cycle.
    MissingEvent { seq: u32, rtl_events: u64 },
    /// No event named (a divergence of colour or cycle count): the pixel's
    /// last cycle.
    LastCycle,
}

impl WaveWindow {
    /// The FST time (ps) at which cycle `c` begins (its rising edge).
    pub fn cycle_start_ps(c: u64) -> u64 {
        c * PS_PER_CYCLE
    }

    /// The FST time (ps) of cycle `c`'s sample point (falling edge).
    pub fn cycle_sample_ps(c: u64) -> u64 {
        c * PS_PER_CYCLE + PS_PER_CYCLE / 2
    }

    /// How to open the files, as a shell command.
    pub fn open_command(&self) -> String {
        format!(
            "gtkwave {} {}",
            shell_word(&self.fst),
            shell_word(&self.gtkw)
        )
    }
}

fn shell_word(p: &Path) -> String {
    let s = p.display().to_string();
    if s.chars()
        .all(|c| c.is_ascii_alphanumeric() || "/._-+,:@".contains(c))
    {
        s
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

/// Errors of the waveform window.
#[derive(Debug, thiserror::Error)]
pub enum WaveError {
    /// The traced model could not be built or failed (a Verilator fatal
    /// error inside it is one of these, never an abort).
    #[error("waveform re-run: {0}")]
    Rtl(#[from] PpError),
    /// The FST writer failed.
    #[error("waveform of pixel ({x}, {y}): {message}")]
    Fst { x: u32, y: u32, message: String },
    /// A file could not be written.
    #[error("cannot write the waveform file {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The path names no file (a directory, or nothing).
    #[error("the waveform path {} is not a file name (expected e.g. wave.fst)", path.display())]
    NotAFile { path: PathBuf },
}

/// The files [`write_window`] writes for the FST file `fst`: the filter
/// file (`<stem>-states.txt`) and the save file (`<stem>.gtkw`).
pub fn companion_paths(fst: &Path) -> (PathBuf, PathBuf) {
    let stem = fst
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "wave".into());
    (
        fst.with_file_name(format!("{stem}-states.txt")),
        fst.with_file_name(format!("{stem}.gtkw")),
    )
}

/// [`write_window`] for a run's first divergence (`divergence_seq` from
/// [`Divergence::seq`]).
pub fn write_divergence(
    scene: &Scene,
    fault: Option<Fault>,
    d: &Divergence,
    k: u64,
    path: &Path,
    replay: Replay,
) -> Result<WaveWindow, WaveError> {
    write_window(scene, fault, d.x, d.y, d.seq(), k, path, replay)
}

/// [`write_divergence`] into the directory `dir` (a run's output
/// directory), as `dir/`[`FST_NAME`] and its companions.
pub fn write_window_in(
    dir: &Path,
    scene: &Scene,
    fault: Option<Fault>,
    d: &Divergence,
    k: u64,
    replay: Replay,
) -> Result<WaveWindow, WaveError> {
    write_divergence(scene, fault, d, k, &dir.join(FST_NAME), replay)
}

/// Re-runs pixel (x, y) of `scene` (with `fault` injected, as the run that
/// diverged had it) on the traced processor of the scene's method pair, as
/// `replay` says, and writes the cycles `d - k ..= d + k` around the
/// divergence cycle `d` (clamped to the pixel) to the FST file `path`, with
/// the translate filter and the GTKWave save file beside it
/// ([`companion_paths`]).
///
/// `divergence_seq` is the sequence number of the divergent event
/// ([`Divergence::seq`]): `d` is the cycle in which the RTL's event with that
/// number was sampled, or the pixel's last cycle when the RTL wrote fewer
/// events or no event is named (a divergence of colour or cycle count).
#[allow(clippy::too_many_arguments)]
pub fn write_window(
    scene: &Scene,
    fault: Option<Fault>,
    x: u32,
    y: u32,
    divergence_seq: Option<u32>,
    k: u64,
    path: &Path,
    replay: Replay,
) -> Result<WaveWindow, WaveError> {
    if path.file_name().is_none() || path.is_dir() {
        return Err(WaveError::NotAFile {
            path: path.to_path_buf(),
        });
    }
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| WaveError::Io { path, source }
    };
    // Fail on a bad path now, with the OS's reason, rather than after the
    // simulation (Verilator's FST writer only says that it did not open).
    std::fs::File::create(path).map_err(io(path))?;
    let fst = std::path::absolute(path).map_err(io(path))?;
    let (filter, gtkw) = companion_paths(&fst);
    let (divergence_cycle, at, first_cycle, last_cycle, outcome, states) =
        match replay.design.driver() {
            Driver::OnePixel => {
                one_pixel_window(&replay.design, scene, fault, x, y, divergence_seq, k, &fst)?
            }
            Driver::Streams => tile_window(
                &replay.design,
                scene,
                fault,
                x,
                y,
                divergence_seq,
                k,
                &fst,
                (replay.tile, replay.stall),
            )?,
        };
    let at = match at {
        DivergenceAt::Event { seq, .. } => DivergenceAt::Event {
            seq,
            state: states[seq as usize],
        },
        other => other,
    };
    let window = WaveWindow {
        x,
        y,
        replay,
        divergence_cycle,
        at,
        first_cycle,
        last_cycle,
        outcome,
        fst,
        filter,
        gtkw,
    };
    std::fs::write(&window.filter, state_filter()).map_err(io(&window.filter))?;
    std::fs::write(&window.gtkw, save_file(&window)).map_err(io(&window.gtkw))?;
    Ok(window)
}

/// What a re-run found: the divergence cycle and why, the window's first
/// and last cycle, the pixel's outcome, and the state of each of its events.
type Rerun = (u64, DivergenceAt, u64, u64, PixelOutcome, Vec<u16>);

/// The divergence cycle of a pixel whose events came in `cycles` and whose
/// last cycle is `last`.
fn divergence_at(
    divergence_seq: Option<u32>,
    cycles: &[u64],
    events: u64,
    last: u64,
) -> (u64, DivergenceAt) {
    match divergence_seq {
        Some(seq) => match cycles.get(seq as usize) {
            Some(&c) => (c, DivergenceAt::Event { seq, state: 0 }),
            None => (
                last,
                DivergenceAt::MissingEvent {
                    seq,
                    rtl_events: events,
                },
            ),
        },
        None => (last, DivergenceAt::LastCycle),
    }
}

/// [`write_window`] on a design driven one pixel at a time: the pixel
/// twice from reset.
#[allow(clippy::too_many_arguments)]
fn one_pixel_window(
    design: &Design,
    scene: &Scene,
    fault: Option<Fault>,
    x: u32,
    y: u32,
    divergence_seq: Option<u32>,
    k: u64,
    fst: &Path,
) -> Result<Rerun, WaveError> {
    // Pass 1: the cycle of every RTL event of the pixel.
    let mut rtl = traced(design, scene, fault)?;
    let outcome = rtl.run_pixel(x, y, None)?;
    let mut cycles = Vec::new();
    rtl.model().event_cycles(&mut cycles);
    drop(rtl);
    let last_cycle_of_pixel = outcome.cycles;
    let (divergence_cycle, at) =
        divergence_at(divergence_seq, &cycles, outcome.events, last_cycle_of_pixel);
    let first_cycle = divergence_cycle.saturating_sub(k);
    let last_cycle = divergence_cycle.saturating_add(k).min(last_cycle_of_pixel);

    // Pass 2: the same pixel from reset, with the FST open for the window.
    let mut rtl = traced(design, scene, fault)?;
    let fst_error = |e: cxx::Exception| WaveError::Fst {
        x,
        y,
        message: e.what().to_string(),
    };
    rtl.model()
        .open_wave(&fst.to_string_lossy(), first_cycle, last_cycle)
        .map_err(fst_error)?;
    let mut events = Vec::new();
    let again = rtl.run_pixel(x, y, Some(&mut events));
    rtl.model().close_wave().map_err(fst_error)?;
    let again = again?;
    if again != outcome {
        return Err(not_repeated(x, y, format!("{again:?} vs {outcome:?}")));
    }
    let states = events.iter().map(|e| e.state).collect();
    Ok((
        divergence_cycle,
        at,
        first_cycle,
        last_cycle,
        outcome,
        states,
    ))
}

/// The error of a re-run that did not repeat the first.
fn not_repeated(x: u32, y: u32, what: String) -> WaveError {
    WaveError::Fst {
        x,
        y,
        message: format!(
            "the re-run differs from the first run ({what}): the RTL does not repeat itself from reset"
        ),
    }
}

/// [`write_window`] on a streamed design: `tile` fed twice from reset.
#[allow(clippy::too_many_arguments)]
fn tile_window(
    design: &Design,
    scene: &Scene,
    fault: Option<Fault>,
    x: u32,
    y: u32,
    divergence_seq: Option<u32>,
    k: u64,
    fst: &Path,
    (tile, stall): (Window, Stall),
) -> Result<Rerun, WaveError> {
    let coords: Vec<(u32, u32)> = tile.iter().collect();
    let fst_error = |message: String| WaveError::Fst { x, y, message };
    // One run of the tile on a fresh traced model: the pixel's outcome,
    // its events' states, and its cycles (take, done turn, events).
    let run = |window: Option<(u64, u64)>| -> Result<_, WaveError> {
        let mut rtl = Top::open(design)?;
        rtl.set_fault(fault, u32::MAX);
        rtl.load_scene(scene)?;
        rtl.set_backpressure(cosim::backpressure_seed(&coords), stall);
        if let Some((first, last)) = window {
            rtl.open_wave(&fst.to_string_lossy(), first, last)
                .map_err(fst_error)?;
        }
        let mut pixel = None;
        let ran = rtl.run_frame(Source::Stream(&coords), &mut |p| {
            if (p.x, p.y) == (x, y) {
                pixel = Some((
                    p.outcome,
                    p.events.iter().map(|e| e.state).collect::<Vec<_>>(),
                ));
            }
        });
        rtl.close_wave().map_err(fst_error)?;
        ran?;
        let (outcome, states) = pixel
            .ok_or_else(|| fst_error(format!("the pixel is not in the re-run tile {tile}")))?;
        let cycles = rtl
            .wave_cycles(x, y)
            .ok_or_else(|| fst_error("the traced model kept no cycles of the pixel".into()))?;
        Ok((outcome, states, cycles))
    };
    // Pass 1: the cycle of every event of the pixel.
    let (outcome, states, (taken, done, cycles)) = run(None)?;
    let (divergence_cycle, at) = divergence_at(divergence_seq, &cycles, outcome.events, done);
    let first_cycle = divergence_cycle.saturating_sub(k).max(taken);
    let last_cycle = divergence_cycle.saturating_add(k).min(done);
    // Pass 2: the same tile from reset, with the FST open for the window.
    let again = run(Some((first_cycle, last_cycle)))?;
    if again != (outcome, states.clone(), (taken, done, cycles)) {
        return Err(not_repeated(x, y, format!("{:?} vs {outcome:?}", again.0)));
    }
    Ok((
        divergence_cycle,
        at,
        first_cycle,
        last_cycle,
        outcome,
        states,
    ))
}

/// A fresh traced model of `design` with the scene loaded.
fn traced(design: &Design, scene: &Scene, fault: Option<Fault>) -> Result<PixelProcessor, PpError> {
    let mut rtl = PixelProcessor::open(design)?;
    rtl.set_fault(fault);
    rtl.load_scene(scene)?;
    Ok(rtl)
}

/// Hex digits GTKWave shows for a vector of `bits` bits.
fn hex_digits(bits: usize) -> usize {
    bits.div_ceil(4)
}

/// A GTKWave translate filter file naming every controller state: each
/// value twice, as GTKWave shows it in hex with and without its base symbol
/// (`$`, View > Show Base Symbols, on by default).
pub fn state_filter() -> String {
    let mut text = String::from(
        "# GTKWave translate filter: controller states of rtl/pp/isa.vh (ISA_ST_*),\n\
         # for u_ctrl.st_q and trace_state shown in hex (harness/output/wave.rs)\n",
    );
    let digits = hex_digits(dim::ST_BITS);
    for &(name, code) in isa::STATES {
        let _ = writeln!(text, "{code:0digits$X} {name}");
        let _ = writeln!(text, "${code:0digits$X} {name}");
    }
    text
}

/// One signal of the save file: its flags and its name in GTKWave.
struct Trace {
    flags: u32,
    name: String,
    filter: bool,
}

// GTKWave's trace flags (analyzer.h): hex, decimal, binary, right-justified,
// translated by a filter file.
const TR_HEX: u32 = 0x2;
const TR_DEC: u32 = 0x4;
const TR_BIN: u32 = 0x8;
const TR_RJUSTIFY: u32 = 0x20;
const TR_FTRANSLATED: u32 = 0x2000;

/// The signals the save file shows for `processor` (its row's
/// `wave_signals` under its `wave_scope`), grouped under comments (`None`).
fn traces(processor: ProcessorKind) -> Vec<Option<(&'static str, Trace)>> {
    let row = processor.row();
    let sp_bits = (isa::dim::STK_COUNT as u32)
        .next_power_of_two()
        .trailing_zeros() as usize;
    let mut out = Vec::new();
    for &(title, signals) in row.wave_signals {
        out.push(None);
        for &(name, kind, radix) in signals {
            // A state goes through the state-name filter.
            let filter = kind == WaveBits::State;
            let bits = match kind {
                WaveBits::Bits(b) => b,
                WaveBits::State => dim::ST_BITS,
                WaveBits::Reg => dim::REG_BITS,
                WaveBits::Lanes => dim::LANES,
                WaveBits::Value => 32 * dim::LANES,
                WaveBits::Coord => dim::COORD_BITS,
                WaveBits::Op => dim::OP_BITS,
                WaveBits::StackPointer => sp_bits,
                WaveBits::Context => row.contexts.trailing_zeros() as usize,
            };
            let flags = match radix {
                Radix::Bin => TR_BIN,
                Radix::Dec => TR_DEC,
                Radix::Hex => TR_HEX,
            } | TR_RJUSTIFY
                | if filter { TR_FTRANSLATED } else { 0 };
            let name = if bits == 1 {
                format!("{}.{name}", row.wave_scope)
            } else {
                format!("{}.{name}[{}:0]", row.wave_scope, bits - 1)
            };
            out.push(Some((
                title,
                Trace {
                    flags,
                    name,
                    filter,
                },
            )));
        }
    }
    out
}

/// The names of the signals the save file shows for `processor`, as
/// GTKWave names them (`TOP.pixel_processor.u_ctrl.st_q[8:0]`), and whether
/// each goes through the state filter.
pub fn shown_signals(processor: ProcessorKind) -> Vec<(String, bool)> {
    traces(processor)
        .into_iter()
        .flatten()
        .map(|(_, t)| (t.name, t.filter))
        .collect()
}

/// The GTKWave save file (`.gtkw`) of a window: the dump and save file
/// (absolute paths; GTKWave adjusts them if the three files move
/// together), the marker on the divergence's sample point, the zoom to the
/// window, and the signals with their formats.
fn save_file(w: &WaveWindow) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "[*] rtcosim cosim --wave (harness/output/wave.rs): pixel ({}, {}){}, cycles {}..={}, \
         divergence in cycle {}; cycle c begins at c ns",
        w.x,
        w.y,
        if w.replay.streamed() {
            format!(
                " on the {} processor fed tile {}",
                w.replay.processor(),
                w.replay.tile
            )
        } else {
            String::new()
        },
        w.first_cycle,
        w.last_cycle,
        w.divergence_cycle
    );
    let _ = writeln!(s, "[dumpfile] \"{}\"", w.fst.display());
    let _ = writeln!(s, "[savefile] \"{}\"", w.gtkw.display());
    let start = WaveWindow::cycle_start_ps(w.first_cycle);
    let span = WaveWindow::cycle_start_ps(w.last_cycle + 1) - start;
    let _ = writeln!(s, "[timestart] {start}");
    let _ = writeln!(s, "[size] 1400 700");
    let _ = writeln!(s, "[signals_width] 300");
    // Zoom: GTKWave shows 2^-zoom time units per pixel; about 1000 pixels.
    let zoom = -((span as f64 / 1000.0).max(1.0)).log2();
    let _ = writeln!(
        s,
        "*{zoom:.6} {}",
        WaveWindow::cycle_sample_ps(w.divergence_cycle)
    );
    let mut flags = None;
    let mut filter_declared = false;
    let mut title = "";
    for entry in traces(w.replay.processor()) {
        let Some((group, t)) = entry else { continue };
        if group != title {
            title = group;
            // A blank trace with a comment: the group's title.
            let _ = writeln!(s, "@{:x}", 0x200u32);
            let _ = writeln!(s, "-{title}");
            flags = Some(0x200);
        }
        if flags != Some(t.flags) {
            let _ = writeln!(s, "@{:x}", t.flags);
            flags = Some(t.flags);
        }
        if t.filter {
            // Filter file 1 for this and every later filtered trace.
            let _ = writeln!(s, "^1 {}", w.filter.display());
            filter_declared = true;
        }
        let _ = writeln!(s, "{}", t.name);
    }
    debug_assert!(filter_declared);
    s
}
