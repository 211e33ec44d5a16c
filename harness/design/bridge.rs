//! The cxx bridge to the verilated models (C++ side in `harness/design/cpp/`).
//!
//! The C++ side runs the clock loop over whole batches of operands (float
//! units), a whole pixel (the pixel processor), or a batch of results and
//! trace events (the top), so one FFI call covers thousands of evaluations. Every model has its own
//! `VerilatedContext`; the handles are `!Send` (cxx opaque types), which keeps
//! each model on the thread that built it, as Verilator requires.

#[cxx::bridge(namespace = "rtcosim")]
pub(crate) mod ffi {
    /// The separately verilated float units (one model per unit and method).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    enum FpModel {
        Add,
        Mul,
        Itof,
        RecipExact,
        RecipFast,
        SqrtExact,
        SqrtFast,
        Exp,
        FastAdd,
        FastMul,
        FastItof,
        FastRecipExact,
        FastRecipFast,
        FastSqrtExact,
        FastSqrtFast,
        FastExp,
    }

    /// One trace event as the RTL's trace port shows it (the pixel and the
    /// sequence number are the caller's to add).
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    struct PpEvent {
        state: u16,
        dst: u8,
        lanes: u8,
        values: [u32; 3],
    }

    /// How a pixel's clock loop ended.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    enum PpStatus {
        /// done was high (the result is valid).
        Done,
        /// No done within the timeout.
        Timeout,
        /// ready went high (the controller is in IDLE) without done.
        Idle,
    }

    /// One pixel's run on the verilated pixel processor.
    #[derive(Debug, Clone, Copy)]
    struct PpRun {
        status: PpStatus,
        /// rgb in the done cycle, lanes r, g, b.
        rgb: [u32; 3],
        /// Sampled cycles with ready low, up to and including the done cycle.
        cycles: u64,
        /// Sampled cycles after the start edge, whatever ready said.
        edges: u64,
        /// trace_valid cycles (counted also when the events are not kept).
        events: u64,
        /// The state of the last trace event, if there was one, and its cycle.
        has_last_state: bool,
        last_state: u16,
        last_state_cycle: u64,
        /// trace_state in the last cycle sampled.
        state_port: u16,
    }

    /// A trace event of the top: the processor that made it, the pixel
    /// that processor was given, that pixel's number among the processor's
    /// pixels since reset (from 0), and the event as its trace port shows it.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    struct TopEvent {
        proc: u16,
        x: u16,
        y: u16,
        pixel: u32,
        event: PpEvent,
    }

    /// A result off the top's result stream.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    struct TopResult {
        proc: u16,
        x: u16,
        y: u16,
        rgb: [u32; 3],
        /// The pixel's own cycle count (out_cycles).
        cycles: u32,
        /// The events buffered (in the same run's vector) before this
        /// result left: every event of this pixel is among them.
        events_before: u64,
    }

    /// Why a batch of the top's clock loop ended.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    enum TopStatus {
        /// Every result of the frame is out.
        Drained,
        /// The result or event limit was reached.
        Batch,
        /// The cycle limit was reached.
        CycleLimit,
        /// A processor spent more than the timeout on one pixel.
        Watchdog,
        /// No coordinate went in and no result came out for the timeout.
        Stalled,
    }

    /// One batch of the top's clock loop.
    #[derive(Debug, Clone, Copy)]
    struct TopRun {
        status: TopStatus,
        /// Cycles run in this batch (Watchdog: the processor's cycles on
        /// the pixel; Stalled: the cycles without a handshake).
        cycles: u64,
        /// Drained: cycles from the one taking the first coordinate (or
        /// starting the raster) to the one taking the last result, both in.
        frame_cycles: u64,
        /// Watchdog: the processor (0xFF otherwise), its pixel, the state
        /// of its last trace event and that event's cycle, its trace_state.
        proc: u16,
        x: u16,
        y: u16,
        has_last_state: bool,
        last_state: u16,
        last_state_cycle: u64,
        state_port: u16,
    }

    /// One cycle's inputs of the fast processor's ALU (harness::fast_alu).
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    struct AluIn {
        valid: bool,
        ctx: u8,
        op: u8,
        a: [u32; 3],
        b: [u32; 3],
        ix: u32,
        iy: u32,
    }

    /// A result as the fast ALU's output port showed it, in the cycle it
    /// showed it (cycles counted from reset).
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    struct AluOut {
        cycle: u64,
        ctx: u8,
        writes: bool,
        y: [u32; 3],
        /// The flags, bit i for lane i.
        neg: u8,
        pos: u8,
        sign: u8,
    }

    unsafe extern "C++" {
        include!("fp_units.h");

        /// One verilated float unit.
        type FpUnit;

        /// Builds and resets a model. Fails if the model cannot be constructed.
        fn new_fp_unit(model: FpModel) -> Result<UniquePtr<FpUnit>>;

        /// The unit cut from a mutant netlist (cargo feature `mutation`,
        /// exact methods), mutant `mutant` selected (0: the design as
        /// written); a pipelined one (the `Fast*` models, cut from the fast
        /// processor's) read `latency` edges after each operation enters.
        /// Fails if it was not built.
        fn new_fp_unit_mut(model: FpModel, mutant: u16, latency: u32) -> Result<UniquePtr<FpUnit>>;

        /// A pipelined unit of `rtl/fast/` (the `Fast*` models): `eval` puts
        /// one operation in every cycle and reads each result `latency`
        /// edges after its operands (`cycles[i]` = `latency`); fails for
        /// any other model.
        fn new_fp_unit_pipelined(model: FpModel, latency: u32) -> Result<UniquePtr<FpUnit>>;

        /// Evaluates `y[i] = unit(a[i], b[i])` for every `i`; `b` is ignored by
        /// unary units. For multi-cycle units, `cycles[i]` receives the clock
        /// edges from the one sampling `in_valid` to the one after which
        /// `out_valid` is high (0 for combinational units). Fails on slices of
        /// different lengths, on a unit that does not answer within
        /// `timeout_cycles`, or on a fatal error inside the model.
        fn eval(
            self: Pin<&mut FpUnit>,
            a: &[u32],
            b: &[u32],
            y: &mut [u32],
            cycles: &mut [u32],
            timeout_cycles: u32,
        ) -> Result<()>;
    }

    unsafe extern "C++" {
        include!("pixel_proc.h");

        /// One verilated pixel processor (trace and fault ports included).
        type PixelProc;

        /// Builds and resets the pixel processor model `class_name` (a
        /// class of `design::models`: plain, waveform, coverage, mutant with
        /// mutant 0 selected, or synthesized). Fails if this build lacks it.
        fn new_pixel_proc(class_name: &str) -> Result<UniquePtr<PixelProc>>;

        /// Holds rst_n low for two clock edges, releases it for one; fails
        /// unless ready is then high.
        fn reset(self: Pin<&mut PixelProc>) -> Result<()>;

        /// One scene-port write (register `addr`, or the configuration word
        /// when `cfg`) at a rising edge; fails unless ready.
        fn write_scene(
            self: Pin<&mut PixelProc>,
            cfg: bool,
            addr: u8,
            x: u32,
            y: u32,
            z: u32,
        ) -> Result<()>;

        /// Selects mutant `id` (0: the design as written) from the next
        /// reset on; fails on a model that carries no mutants.
        fn set_mutant(self: Pin<&mut PixelProc>, id: u16) -> Result<()>;

        /// Drives fault_state and fault_xor from now on (0 disables).
        fn set_fault(self: Pin<&mut PixelProc>, state: u16, xor_mask: u32);

        /// Runs pixel (px, py) to done, a timeout after `timeout_cycles`
        /// cycles, or the controller back in IDLE without done; appends the
        /// trace events to `events` when `trace`. Fails when not ready at
        /// the start, or on a fatal error inside the model.
        fn run_pixel(
            self: Pin<&mut PixelProc>,
            px: u16,
            py: u16,
            trace: bool,
            events: &mut Vec<PpEvent>,
            timeout_cycles: u64,
        ) -> Result<PpRun>;

        /// The bare clock loop (`harness/design/cpp/bare.h`): runs each pixel of
        /// `coords` (x | y << 16) to done reading nothing but ready and
        /// done; returns the sum of their cycles. The baseline of the
        /// harness's overhead. Fails when not ready for a pixel or a pixel
        /// takes more than `timeout_cycles`.
        fn run_bare(self: Pin<&mut PixelProc>, coords: &[u32], timeout_cycles: u64) -> Result<u64>;

        /// On a `new_pixel_proc_wave` model (others fail), once: dumps the
        /// cycles `first_cycle..=last_cycle` of the pixels run next into the
        /// FST file `path` (see `harness/design/cpp/pp_wave.h` for the time axis).
        fn open_wave(
            self: Pin<&mut PixelProc>,
            path: &str,
            first_cycle: u64,
            last_cycle: u64,
        ) -> Result<()>;

        /// Finishes and closes the FST file, if one is open.
        fn close_wave(self: Pin<&mut PixelProc>) -> Result<()>;

        /// Appends the cycle of each trace event of the last pixel (on a
        /// `new_pixel_proc_wave` model; nothing on the others).
        fn event_cycles(self: &PixelProc, out: &mut Vec<u64>);

        /// Writes the model's coverage counts to `path` in Verilator's
        /// coverage.dat format; fails on a model built without coverage.
        fn write_coverage(self: Pin<&mut PixelProc>, path: &str) -> Result<()>;
    }

    unsafe extern "C++" {
        include!("top.h");

        /// The verilated top module (rtl/top.v, trace and fault ports in).
        type TopSim;

        /// Builds and resets the model `class_name` (a class of
        /// `design::models`): a top of compact processors, a top of fast
        /// ones (slots: processor * 32 + context), or the fast processor
        /// alone (its 32 contexts the slots), in any flavour. Fails if this
        /// build lacks it.
        fn new_top(class_name: &str) -> Result<UniquePtr<TopSim>>;

        /// Holds rst_n low for two clock edges, releases it for one; fails
        /// unless scene_ready is then high. Forgets any frame.
        fn reset(self: Pin<&mut TopSim>) -> Result<()>;

        /// One broadcast scene-port write; fails while a frame is in flight
        /// or scene_ready is low.
        fn write_scene(
            self: Pin<&mut TopSim>,
            cfg: bool,
            addr: u8,
            x: u32,
            y: u32,
            z: u32,
        ) -> Result<()>;

        /// Drives fault_state, fault_xor and fault_procs from now on.
        fn set_fault(self: Pin<&mut TopSim>, state: u16, xor_mask: u32, procs_mask: u32);

        /// out_ready low in `stall_percent` % of the cycles (seeded): each
        /// cycle on its own (burst 1), or in stalls of 1 to `burst` cycles.
        fn set_backpressure(self: Pin<&mut TopSim>, seed: u64, stall_percent: u32, burst: u32);

        /// Cycles a processor may spend on a pixel before a Watchdog status
        /// (and twice that, plus 16, the top without a handshake before a
        /// Stalled one).
        fn set_timeout(self: Pin<&mut TopSim>, cycles: u64);

        /// A frame from the coordinate stream: `x | y << 16` each, in order.
        fn feed(self: Pin<&mut TopSim>, coords: &[u32]) -> Result<()>;

        /// A frame from the raster generator over an inclusive window.
        fn start_raster(self: Pin<&mut TopSim>, x0: u16, y0: u16, x1: u16, y1: u16) -> Result<()>;

        /// The fast processor: the last frame's cycles, from its first
        /// take, in which a take had to be refused (2K pixels held, by the
        /// handshakes seen); nothing for the top.
        fn refused_takes(self: &TopSim, out: &mut Vec<u64>);

        /// The last frame's cycles, from the one that took its first
        /// coordinate, in which out_ready was low.
        fn stalled_cycles(self: &TopSim, out: &mut Vec<u64>);

        /// Fast processors: the context whose turn the next cycle is (0 for
        /// compact ones); evaluates the model without an edge.
        fn turn_phase(self: Pin<&mut TopSim>) -> u32;

        /// A top of fast processors: processors per result group
        /// (`ARB_GROUP`); 1 for the others.
        fn arb_group(self: &TopSim) -> u32;

        /// On a `new_fast_wave_top` model (others fail), once: dumps the
        /// cycles `first..=last` of the next frame (counted from 0, the
        /// cycle whose rising edge takes its first coordinate) into the FST
        /// file `path`.
        fn open_wave(self: Pin<&mut TopSim>, path: &str, first: u64, last: u64) -> Result<()>;

        /// Finishes and closes the FST file, if one is open.
        fn close_wave(self: Pin<&mut TopSim>) -> Result<()>;

        /// On a `new_fast_wave_top` model: pixel (x, y) of the last frame,
        /// its take's cycle, its done turn's cycle, then each of its trace
        /// events' cycles (frame cycles as `open_wave`'s); nothing for a
        /// pixel the frame did not run, or on other models.
        fn wave_cycles(self: &TopSim, x: u16, y: u16, out: &mut Vec<u64>);

        /// Writes the model's coverage counts to `path` in Verilator's
        /// coverage.dat format; fails on a model built without coverage.
        fn write_coverage(self: Pin<&mut TopSim>, path: &str) -> Result<()>;

        /// On a `new_fast_mut_top` model (others fail): drives mutsel = id
        /// from now on and at every reset (0: the design as written).
        fn set_mutant(self: Pin<&mut TopSim>, id: u16) -> Result<()>;

        /// Clocks until the frame drains, `max_results` results or
        /// `max_events` events are buffered, `max_cycles` cycles ran, or a
        /// watchdog trips; appends to `results` and `events`. Fails on a
        /// fatal error inside the model.
        fn run(
            self: Pin<&mut TopSim>,
            results: &mut Vec<TopResult>,
            events: &mut Vec<TopEvent>,
            max_results: u64,
            max_events: u64,
            max_cycles: u64,
        ) -> Result<TopRun>;
    }

    unsafe extern "C++" {
        include!("fast_alu.h");

        /// The verilated ALU of the fast processor (rtl/fast/fast_alu.v).
        type FastAlu;

        /// Builds and resets the fast ALU model `class_name` (a class of
        /// `design::models`); fails if this build lacks it.
        fn new_fast_alu(class_name: &str) -> Result<UniquePtr<FastAlu>>;

        /// Holds rst_n low for two clock edges, releases it for one; the
        /// cycle count starts again.
        fn reset(self: Pin<&mut FastAlu>);

        /// Drives `cycles[i]` in cycle i, then `drain` idle cycles; appends
        /// every result the output port shows to `out`, and exp_ready in
        /// each cycle of `cycles` to `exp_ready`.
        fn run(
            self: Pin<&mut FastAlu>,
            cycles: &[AluIn],
            drain: u32,
            out: &mut Vec<AluOut>,
            exp_ready: &mut Vec<bool>,
        ) -> Result<()>;
    }
}
