// The pixel processor's RTL driven with nothing around it: the reset
// sequence and the scene-write port (which the drivers in clocked.h use as
// well, for the pixel processor and for the top) and the bare clock loop,
// the baseline the harness's overhead is measured against (docs/perf.md,
// "What the harness costs"; benches/overhead.rs, benches/levers/). The cycle
// contract is the drivers': a cycle's inputs are set, the model is evaluated
// with clk low (its outputs sampled), then the rising edge. Only clk, rst_n,
// the scene port, start, px, py, ready and done are touched.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "verilated_owned.h"

namespace rtcosim {

// The scene port idle and rst_n low for two rising edges, then high for
// one; ends sampled (clk low, evaluated). The caller sets its other inputs
// first.
template <class M>
void reset_model(M& m) {
    m.scene_we = 0;
    m.scene_cfg = 0;
    m.scene_addr = 0;
    for (int i = 0; i < 3; ++i) m.scene_data[i] = 0;
    reset_edges(m);
}

// One scene-port write (register `addr`, or the configuration word when
// `cfg`), taken at the next rising edge; ends sampled. The caller has
// checked that the port is ready. Idle again, the port's address and data
// are don't-cares, and are driven so: the complement of what was written,
// so that RTL reading them outside a write (a configuration register that
// follows scene_data, say) loads other values and is seen.
template <class M>
void write_scene_port(M& m, bool cfg, std::uint8_t addr, std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    m.scene_we = 1;
    m.scene_cfg = cfg;
    m.scene_addr = addr;
    m.scene_data[0] = x;
    m.scene_data[1] = y;
    m.scene_data[2] = z;
    m.eval();
    m.clk = 1;
    m.eval();
    m.scene_we = 0;
    m.scene_cfg = 0;
    m.scene_addr = static_cast<std::uint8_t>(~addr);  // 8-bit addresses (pixel_proc.cpp checks)
    m.scene_data[0] = ~x;
    m.scene_data[1] = ~y;
    m.scene_data[2] = ~z;
    m.clk = 0;
    m.eval();
}

// Runs each pixel of `coords` (x | y << 16) to done on `m`, which is reset
// with a scene loaded and sampled (clk low, evaluated). Returns the sum of
// the pixels' cycles. Throws if the processor is not ready for a pixel, or a
// pixel takes more than `timeout` cycles.
template <class M>
std::uint64_t bare_pixels(M& m, const std::uint32_t* coords, std::size_t n, std::uint64_t timeout) {
    std::uint64_t cycles = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t x = coords[i] & 0xFFFF, y = coords[i] >> 16;
        m.clk = 0;
        m.eval();
        if (!m.ready) {
            throw std::runtime_error("bare loop: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                     ") offered while not ready");
        }
        m.px = x;
        m.py = y;
        m.start = 1;
        m.eval();  // this cycle's inputs, clk still low
        m.clk = 1;
        m.eval();  // the controller leaves IDLE at this edge
        m.start = 0;
        for (std::uint64_t edges = 1;; ++edges) {
            m.clk = 0;
            m.eval();
            if (!m.ready) ++cycles;
            const bool done = m.done;
            m.clk = 1;
            m.eval();
            if (done) break;
            if (edges >= timeout) {
                throw std::runtime_error("bare loop: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                         ") not done after " + std::to_string(timeout) + " cycles");
            }
        }
    }
    m.clk = 0;
    m.eval();
    return cycles;
}

}  // namespace rtcosim
