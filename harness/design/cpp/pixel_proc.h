// The verilated pixel processor (rtl/pp/pixel_processor.v), one model per
// (recip, sqrt) method pair, driven a whole pixel per call from Rust
// (bridge.rs, pixel_proc.rs).
#pragma once

#include <cstdint>
#include <memory>

#include "rust/cxx.h"

namespace rtcosim {

struct PpEvent;
struct PpRun;

class PixelProc {
public:
    virtual ~PixelProc() = default;
    // rst_n low for two clock edges, then high for one; throws unless ready.
    virtual void reset() = 0;
    // One scene-port write at a rising edge (scene_we high while ready).
    virtual void write_scene(bool cfg, std::uint8_t addr, std::uint32_t x, std::uint32_t y, std::uint32_t z) = 0;
    // Drives the fault-injection inputs from now on (xor 0 disables).
    virtual void set_fault(std::uint16_t state, std::uint32_t xor_mask) = 0;
    // Selects mutant `id` of the mutant netlist from the next reset on (0:
    // the design as written); the other models throw.
    virtual void set_mutant(std::uint16_t id) = 0;
    // Runs one pixel: start at a rising edge while ready, then clock until
    // done (or a timeout, or the controller back in IDLE without done),
    // sampling the outputs before each rising edge. Appends the trace events
    // to `events` when `trace` is set.
    virtual PpRun run_pixel(std::uint16_t px, std::uint16_t py, bool trace, rust::Vec<PpEvent>& events,
                            std::uint64_t timeout_cycles) = 0;
    // The bare clock loop of bare.h over `coords` (x | y << 16): the sum of
    // the pixels' cycles.
    virtual std::uint64_t run_bare(rust::Slice<const std::uint32_t> coords, std::uint64_t timeout_cycles) = 0;
    // Waveforms (pp_wave.h), only on the models new_pixel_proc_wave builds;
    // the others throw. Dumps cycles [first, last] of the pixels run next
    // into the FST file `path` (once per model); close_wave finishes it.
    virtual void open_wave(rust::Str path, std::uint64_t first_cycle, std::uint64_t last_cycle) = 0;
    virtual void close_wave() = 0;
    // The cycle of each trace event of the last pixel, in order.
    virtual void event_cycles(rust::Vec<std::uint64_t>& out) const = 0;
    // Writes the model's coverage counts (Verilator's coverage.dat format)
    // to `path`: only on the models new_pixel_proc_cov builds; the others
    // throw.
    virtual void write_coverage(rust::Str path) = 0;
};

// Builds and resets the pixel processor model `class_name` (a class of
// the model table, harness/design/models.rs: plain, waveform, coverage,
// mutant or synthesized); throws if this build lacks it.
std::unique_ptr<PixelProc> new_pixel_proc(rust::Str class_name);

}  // namespace rtcosim
