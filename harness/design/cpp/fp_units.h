// Float units verilated one by one, driven in batches from Rust (bridge.rs).
#pragma once

#include <cstdint>
#include <memory>

#include "rust/cxx.h"

namespace rtcosim {

enum class FpModel : std::uint8_t;

class FpUnit {
public:
    virtual ~FpUnit() = default;
    virtual void eval(rust::Slice<const std::uint32_t> a, rust::Slice<const std::uint32_t> b,
                      rust::Slice<std::uint32_t> y, rust::Slice<std::uint32_t> cycles,
                      std::uint32_t timeout_cycles) = 0;
};

std::unique_ptr<FpUnit> new_fp_unit(FpModel model);

// The unit cut from a mutant netlist (cargo feature `mutation`; exact
// methods) with mutant `mutant` selected (0: the design as written): a
// compact processor's unit, or a fast processor's pipelined one read
// `latency` clock edges after each operation enters.
std::unique_ptr<FpUnit> new_fp_unit_mut(FpModel model, std::uint16_t mutant, std::uint32_t latency);

// A pipelined unit of rtl/fast/ (the Fast* models), read `latency` clock
// edges after each operation enters.
std::unique_ptr<FpUnit> new_fp_unit_pipelined(FpModel model, std::uint32_t latency);

}  // namespace rtcosim
