// Waveform dumping for the pixel processor driver (pixel_proc.cpp): a policy
// the driver template takes, so the untraced models pay nothing (NoWave is
// empty and inline) and the models verilated with --trace-fst (FstWave) dump
// a window of cycles of one pixel into an FST file (harness/output/wave.rs).
//
// Time in the file: cycle c of a pixel (c = 0 is the idle cycle whose
// rising edge takes start; c = 1 the first counted cycle, as in
// harness/design/pixel_proc.rs) begins with its rising edge at c * 1000 ps = c ns
// and has its falling edge, where the harness samples the outputs, at
// c ns + 500 ps. The window [first, last] dumps from first ns up to and
// including the rising edge at (last + 1) ns that ends cycle last.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rust/cxx.h"
#include "verilated_fst_c.h"

namespace rtcosim {

// The untraced models: nothing to dump; the wave calls are refused.
struct NoWave {
    static constexpr bool kTraceEverOn = false;
    template <class M>
    void open(M&, const char* name, rust::Str, std::uint64_t, std::uint64_t) {
        throw std::logic_error(std::string(name) + " was not verilated with --trace-fst: no waveform");
    }
    void close() {}
    void begin_pixel() {}
    void sampled(bool) {}
    void event(std::uint64_t) {}
    void end_pixel() {}
    const std::vector<std::uint64_t>* event_cycles() const { return nullptr; }
};

// The --trace-fst models: an FST file open from open() to close().
class FstWave {
public:
    static constexpr bool kTraceEverOn = true;
    static constexpr std::uint64_t kPsPerCycle = 1000;

    ~FstWave() { close(); }

    // Opens `path` for the cycles [first, last] of the pixels run from now
    // on (one, in practice); once per model (Verilator attaches a model to
    // one trace file only before it opens).
    template <class M>
    void open(M& model, const char* name, rust::Str path, std::uint64_t first, std::uint64_t last) {
        if (opened_) throw std::logic_error(std::string(name) + ": the waveform was already opened once");
        opened_ = true;
        fst_.reset(new VerilatedFstC);
        model.trace(fst_.get(), 99);
        std::string file(path);
        fst_->open(file.c_str());
        if (!fst_->isOpen()) {
            fst_.reset();
            throw std::runtime_error("cannot open FST file " + file + " for writing");
        }
        first_ = first;
        last_ = last;
    }

    void close() {
        if (fst_) {
            fst_->close();
            fst_.reset();
        }
    }

    // Cycle 0 begins: the inputs of the start cycle are set and evaluated.
    void begin_pixel() {
        in_pixel_ = true;
        cycle_ = 0;
        cycles_.clear();
        dump(0);
    }

    // After each eval of the model: `rising` is the rising edge that begins
    // the next cycle, else the falling edge (the sample point) of this one.
    void sampled(bool rising) {
        if (!in_pixel_) return;
        if (rising) {
            ++cycle_;
            dump(cycle_ * kPsPerCycle);
        } else {
            dump(cycle_ * kPsPerCycle + kPsPerCycle / 2);
        }
    }

    // A trace event in cycle `cycle` (the driver's count, from 1).
    void event(std::uint64_t cycle) { cycles_.push_back(cycle); }

    void end_pixel() { in_pixel_ = false; }

    // The cycles of the last pixel's events, in order.
    const std::vector<std::uint64_t>* event_cycles() const { return &cycles_; }

private:
    void dump(std::uint64_t time) {
        if (fst_ && time >= first_ * kPsPerCycle && time <= (last_ + 1) * kPsPerCycle) fst_->dump(time);
    }

    std::unique_ptr<VerilatedFstC> fst_;
    bool opened_ = false;
    bool in_pixel_ = false;
    std::uint64_t cycle_ = 0;
    std::uint64_t first_ = 0;
    std::uint64_t last_ = 0;
    std::vector<std::uint64_t> cycles_;
};

}  // namespace rtcosim
