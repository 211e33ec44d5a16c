// The verilated top module (rtl/top.v): N pixel processors behind a
// coordinate stream and a result stream, driven in batches from Rust
// (bridge.rs, top.rs): one FFI call runs many cycles and fills Rust-owned
// vectors with results and trace events.
#pragma once

#include <cstdint>
#include <memory>

#include "rust/cxx.h"

namespace rtcosim {

struct TopEvent;
struct TopResult;
struct TopRun;

class TopSim {
public:
    virtual ~TopSim() = default;
    // rst_n low for two clock edges, then high for one; forgets queued
    // coordinates; throws unless scene_ready is then high.
    virtual void reset() = 0;
    // One broadcast scene-port write at a rising edge; throws while a frame
    // is in flight or scene_ready is low.
    virtual void write_scene(bool cfg, std::uint8_t addr, std::uint32_t x, std::uint32_t y, std::uint32_t z) = 0;
    // The mutant netlist (new_fast_mut_top): drives mutsel = id from now on
    // and at every reset (0: the design as written); throws on the others.
    virtual void set_mutant(std::uint16_t id) = 0;
    // Drives fault_state, fault_xor and fault_procs from now on.
    virtual void set_fault(std::uint16_t state, std::uint32_t xor_mask, std::uint32_t procs_mask) = 0;
    // out_ready low in `stall_percent` % of the cycles, from a xorshift
    // generator seeded with `seed` (0 percent: always ready). Burst 1: each
    // cycle drawn on its own; otherwise stalls of 1 to `burst` cycles
    // (uniform) alternate with ready runs as much shorter as the share
    // says, the first run a stall.
    virtual void set_backpressure(std::uint64_t seed, std::uint32_t stall_percent, std::uint32_t burst) = 0;
    // Cycles a processor may spend on one pixel (Watchdog), and, twice
    // over, the top without any handshake (Stalled), before run() stops.
    virtual void set_timeout(std::uint64_t cycles) = 0;
    // Starts a frame from the coordinate stream: `coords` (x | y << 16) are
    // offered in order. Throws while a frame is in flight.
    virtual void feed(rust::Slice<const std::uint32_t> coords) = 0;
    // Starts a frame from the raster generator over the inclusive window.
    // Throws while a frame is in flight.
    virtual void start_raster(std::uint16_t x0, std::uint16_t y0, std::uint16_t x1, std::uint16_t y1) = 0;
    // Clocks the model until the frame is drained, `max_results` results or
    // `max_events` events are buffered, `max_cycles` cycles have run, or a
    // watchdog trips; appends to `results` and `events`.
    virtual TopRun run(rust::Vec<TopResult>& results, rust::Vec<TopEvent>& events, std::uint64_t max_results,
                       std::uint64_t max_events, std::uint64_t max_cycles) = 0;
    // The fast processor: the cycles of the last frame, counted from its
    // first take, in which 2K pixels were held (taken, and their results
    // not yet out), so that a take had to be refused; counted here from
    // the handshakes seen, not read from the model. Empty for the top.
    virtual void refused_takes(rust::Vec<std::uint64_t>& out) const = 0;
    // The cycles of the last frame, counted from the one that took its
    // first coordinate, in which out_ready was low.
    virtual void stalled_cycles(rust::Vec<std::uint64_t>& out) const = 0;
    // Fast processors: the context whose turn the next cycle is (every
    // processor's ring turns together); 0 for compact ones. Evaluates the
    // model with clk low and no coordinate offered: no edge.
    virtual std::uint32_t turn_phase() = 0;
    // A top of fast processors: processors per result group (ARB_GROUP);
    // 1 for the others.
    virtual std::uint32_t arb_group() const = 0;
    // Waveforms (pp_wave.h), only on the models new_fast_wave_top builds
    // (the others throw): open_wave dumps the cycles [first, last] of the
    // next frame, counted from 0, the frame's first cycle (the one whose
    // rising edge takes its first coordinate), into the FST file `path`
    // (once per model); close_wave finishes it.
    virtual void open_wave(rust::Str path, std::uint64_t first, std::uint64_t last) = 0;
    virtual void close_wave() = 0;
    // On those models: pixel (x, y) of the last frame, its take's cycle, its
    // done turn's cycle, then the cycle of each of its trace events, in
    // frame cycles as above; nothing for a pixel the frame did not run, or
    // on the other models.
    virtual void wave_cycles(std::uint16_t x, std::uint16_t y, rust::Vec<std::uint64_t>& out) const = 0;
    // Writes the model's coverage counts (Verilator's coverage.dat format)
    // to `path`; throws on a model verilated without coverage.
    virtual void write_coverage(rust::Str path) = 0;
};

// Builds and resets the model `class_name` (a class of the model table,
// harness/design/models.rs): a top of compact processors, a top of fast
// ones (slots: processor * 32 + context), or the fast processor alone (its
// 32 contexts the slots), in any flavour; throws if this build lacks it.
std::unique_ptr<TopSim> new_top(rust::Str class_name);

}  // namespace rtcosim
