// Batch drivers for the separately verilated float units.
//
// Combinational units: set inputs, eval, read y. Multi-cycle units: one
// operation at a time through the in_valid/out_valid handshake, counting
// clock edges, with a timeout so a hung unit is an error, not a hang.

#include "fp_units.h"

#include <stdexcept>
#include <string>

#include "rtcosim/harness/bridge.rs.h"
#include "verilated.h"
#include "verilated_owned.h"

#include "Vfp_add.h"
#include "Vfp_exp.h"
#include "Vfp_itof.h"
#include "Vfp_mul.h"
#include "Vfp_recip_exact.h"
#include "Vfp_recip_fast.h"
#include "Vfp_sqrt_exact.h"
#include "Vfp_sqrt_fast.h"

namespace rtcosim {
namespace {

void check_lengths(const char* name, std::size_t a, std::size_t b, std::size_t y, std::size_t c, bool binary) {
    if ((binary && b != a) || y != a || c != a) {
        throw std::invalid_argument(std::string(name) + ": operand and result slices differ in length (a " +
                                    std::to_string(a) + ", b " + std::to_string(b) + ", y " + std::to_string(y) +
                                    ", cycles " + std::to_string(c) + ")");
    }
}

template <class M, bool Binary>
class CombUnit final : public FpUnit {
public:
    explicit CombUnit(const char* name) : name_(name) {}
    void eval(rust::Slice<const std::uint32_t> a, rust::Slice<const std::uint32_t> b, rust::Slice<std::uint32_t> y,
              rust::Slice<std::uint32_t> cycles, std::uint32_t) override {
        check_lengths(name_, a.size(), b.size(), y.size(), cycles.size(), Binary);
        M& m = *owned_.model;
        for (std::size_t i = 0; i < a.size(); ++i) {
            m.a = a[i];
            if constexpr (Binary) m.b = b[i];
            m.eval();
            y[i] = m.y;
            cycles[i] = 0;
        }
    }

private:
    const char* name_;
    Owned<M> owned_;
};

template <class M>
class SeqUnit final : public FpUnit {
public:
    explicit SeqUnit(const char* name) : name_(name) {
        M& m = *owned_.model;
        m.clk = 0;
        m.in_valid = 0;
        m.a = 0;
        m.rst_n = 0;
        m.eval();
        tick();
        m.rst_n = 1;
        tick();
    }
    void eval(rust::Slice<const std::uint32_t> a, rust::Slice<const std::uint32_t>, rust::Slice<std::uint32_t> y,
              rust::Slice<std::uint32_t> cycles, std::uint32_t timeout_cycles) override {
        check_lengths(name_, a.size(), 0, y.size(), cycles.size(), false);
        M& m = *owned_.model;
        for (std::size_t i = 0; i < a.size(); ++i) {
            m.a = a[i];
            m.in_valid = 1;
            tick();
            m.in_valid = 0;
            std::uint32_t edges = 1;
            while (!m.out_valid) {
                if (edges >= timeout_cycles) {
                    throw std::runtime_error(std::string(name_) + ": no out_valid within " +
                                             std::to_string(timeout_cycles) + " cycles for operand " +
                                             std::to_string(i) + " (a = " + hex(a[i]) + "); the unit hangs");
                }
                tick();
                ++edges;
            }
            y[i] = m.y;
            cycles[i] = edges;
        }
    }

private:
    void tick() {
        M& m = *owned_.model;
        m.clk = 0;
        m.eval();
        m.clk = 1;
        m.eval();
    }

    const char* name_;
    Owned<M> owned_;
};

}  // namespace

std::unique_ptr<FpUnit> new_fp_unit(FpModel model) {
    switch (model) {
        case FpModel::Add: return std::make_unique<CombUnit<Vfp_add, true>>("fp_add");
        case FpModel::Mul: return std::make_unique<CombUnit<Vfp_mul, true>>("fp_mul");
        case FpModel::Itof: return std::make_unique<CombUnit<Vfp_itof, false>>("fp_itof");
        case FpModel::RecipExact: return std::make_unique<SeqUnit<Vfp_recip_exact>>("fp_recip(exact)");
        case FpModel::RecipFast: return std::make_unique<SeqUnit<Vfp_recip_fast>>("fp_recip(fast)");
        case FpModel::SqrtExact: return std::make_unique<SeqUnit<Vfp_sqrt_exact>>("fp_sqrt(exact)");
        case FpModel::SqrtFast: return std::make_unique<SeqUnit<Vfp_sqrt_fast>>("fp_sqrt(fast)");
        case FpModel::Exp: return std::make_unique<SeqUnit<Vfp_exp>>("fp_exp");
    }
    throw std::invalid_argument("unknown float unit model " + std::to_string(static_cast<int>(model)));
}

}  // namespace rtcosim
