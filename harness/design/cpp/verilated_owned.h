// What every C++ driver of a verilated model shares: the model with its own
// VerilatedContext, and hex formatting for error messages.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "verilated.h"

namespace rtcosim {

// The model and its own context; destroyed model-first. One per driver
// object, so models on different threads share nothing.
template <class M>
struct Owned {
    std::unique_ptr<VerilatedContext> context{new VerilatedContext};
    std::unique_ptr<M> model;
    // `trace_ever_on`: the model may be traced (verilated with --trace-fst).
    explicit Owned(bool trace_ever_on = false) {
        context->fatalOnError(true);
        if (trace_ever_on) context->traceEverOn(true);
        model.reset(new M(context.get(), "TOP"));
    }
    ~Owned() {
        if (model) model->final();
        model.reset();
    }
    Owned(const Owned&) = delete;
    Owned& operator=(const Owned&) = delete;
};

// rst_n low for two rising edges, then high for one; ends sampled (clk
// low, evaluated). The caller sets the model's other inputs first.
template <class M>
void reset_edges(M& m) {
    m.rst_n = 0;
    for (int edge = 0; edge < 3; ++edge) {
        if (edge == 2) m.rst_n = 1;
        m.clk = 0;
        m.eval();
        m.clk = 1;
        m.eval();
    }
    m.clk = 0;
    m.eval();
}

inline std::string hex(std::uint32_t v) {
    static const char* digits = "0123456789abcdef";
    std::string s = "0x";
    for (int shift = 28; shift >= 0; shift -= 4) s += digits[(v >> shift) & 0xF];
    return s;
}

}  // namespace rtcosim
