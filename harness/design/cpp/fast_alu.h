// The verilated ALU of the fast processor (rtl/fast/fast_alu.v), driven in
// batches from Rust (bridge.rs, fast_alu.rs): one FFI call runs a whole
// schedule of opcodes, one cycle each, and returns what the output port
// showed.
#pragma once

#include <cstdint>
#include <memory>

#include "rust/cxx.h"

namespace rtcosim {

struct AluIn;
struct AluOut;

class FastAlu {
public:
    virtual ~FastAlu() = default;
    // rst_n low for two clock edges, then high for one; the cycle count
    // starts again at 0.
    virtual void reset() = 0;
    // Drives cycles[i] in cycle i (inputs set, outputs sampled with clk low,
    // then the rising edge), then `drain` idle cycles. Appends every sampled
    // cycle with out_valid high to `out`, and exp_ready as sampled in each
    // cycle of `cycles` to `exp_ready`.
    virtual void run(rust::Slice<const AluIn> cycles, std::uint32_t drain, rust::Vec<AluOut>& out,
                     rust::Vec<bool>& exp_ready) = 0;
};

// The fast ALU model `class_name` (harness/design/models.rs); throws if
// this build lacks it.
std::unique_ptr<FastAlu> new_fast_alu(rust::Str class_name);

}  // namespace rtcosim
