// What the two drivers of the pixel processor's RTL share (pixel_proc.cpp
// drives pixel_processor, top.cpp the top with N of them): the model with
// its context, the clock with the waveform policy's hooks, and (from bare.h)
// the reset sequence and the scene-write port.
//
// The cycle contract of both: a cycle's inputs are set, then the model is
// evaluated with clk low (fall: the outputs are this cycle's, sampled
// here), then the rising edge (rise).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "bare.h"
#include "pp_wave.h"
#include "verilated_owned.h"
#if RTCOSIM_COVERAGE
#include "verilated_cov.h"
#endif

namespace rtcosim {

// M: the verilated class; W: the waveform policy of pp_wave.h (NoWave, or
// FstWave for the models verilated with --trace-fst), told of every eval.
template <class M, class W = NoWave>
class Clocked {
protected:
    M& model() { return *owned_.model; }
    const M& model() const { return *owned_.model; }

    // Selects mutant `id` (0: the design as written) of a model verilated
    // from a mutant netlist (Mut: it has the `mutsel` port), keeping it in
    // `slot` for the resets to drive again; a model without mutants (`name`)
    // refuses.
    template <bool Mut>
    void select_mutant(const char* name, std::uint16_t id, [[maybe_unused]] std::uint16_t& slot) {
        if constexpr (Mut) {
            slot = id;
            model().mutsel = id;
        } else {
            throw std::runtime_error(std::string(name) + " carries no mutants (selecting mutant " + std::to_string(id) +
                                     ")");
        }
    }

    // clk low, evaluated: settles the inputs; the outputs are this cycle's.
    void fall() {
        M& m = model();
        m.clk = 0;
        m.eval();
        wave_.sampled(false);
    }
    // The rising edge.
    void rise() {
        M& m = model();
        m.clk = 1;
        m.eval();
        wave_.sampled(true);
    }
    void tick() {
        fall();
        rise();
    }

    // rst_n and the scene port (bare.h), unseen by the waveform policy:
    // FstWave dumps only inside a pixel.
    void reset_sequence() { reset_model(model()); }
    void scene_write(bool cfg, std::uint8_t addr, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
        write_scene_port(model(), cfg, addr, x, y, z);
    }

    // Writes the model's coverage counts (Verilator's coverage.dat format)
    // to `file`; Cov: the model was verilated with coverage. Throws naming
    // the model `name` if it was not.
    template <bool Cov>
    void write_counts(const char* name, const std::string& file) {
#if RTCOSIM_COVERAGE
        if constexpr (Cov) {
            owned_.context->coveragep()->write(file.c_str());
            return;
        }
#endif
        throw std::runtime_error(std::string(name) + " was not verilated with coverage (writing " + file + ")");
    }

    Owned<M> owned_{W::kTraceEverOn};
    W wave_;  // after owned_: closed before the model is destroyed
};

}  // namespace rtcosim
