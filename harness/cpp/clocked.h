// What the two drivers of the pixel processor's RTL share (pixel_proc.cpp
// drives pixel_processor, top.cpp the top with N of them): the model with
// its context, the clock, the reset sequence and the scene-write port.
//
// The cycle contract of both: a cycle's inputs are set, then the model is
// evaluated with clk low (fall: the outputs are this cycle's, sampled
// here), then the rising edge (rise).
#pragma once

#include <cstdint>

#include "pp_wave.h"
#include "verilated_owned.h"

namespace rtcosim {

// M: the verilated class; W: the waveform policy of pp_wave.h (NoWave, or
// FstWave for the models verilated with --trace-fst), told of every eval.
template <class M, class W = NoWave>
class Clocked {
protected:
    M& model() { return *owned_.model; }
    const M& model() const { return *owned_.model; }

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

    // The scene port idle and rst_n low for two rising edges, then high for
    // one; ends sampled (clk low). The driver sets its other inputs first.
    void reset_sequence() {
        M& m = model();
        m.clk = 0;
        m.rst_n = 0;
        m.scene_we = 0;
        m.scene_cfg = 0;
        m.scene_addr = 0;
        for (int i = 0; i < 3; ++i) m.scene_data[i] = 0;
        m.eval();
        tick();
        tick();
        m.rst_n = 1;
        tick();
        fall();
    }

    // One scene-port write, taken at the next rising edge; the driver has
    // checked that the port is ready.
    void scene_write(bool cfg, std::uint8_t addr, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
        M& m = model();
        m.scene_we = 1;
        m.scene_cfg = cfg;
        m.scene_addr = addr;
        m.scene_data[0] = x;
        m.scene_data[1] = y;
        m.scene_data[2] = z;
        tick();
        m.scene_we = 0;
        m.scene_cfg = 0;
    }

    Owned<M> owned_{W::kTraceEverOn};
    W wave_;  // after owned_: closed before the model is destroyed
};

}  // namespace rtcosim
