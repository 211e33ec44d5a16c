// The bare clock loop (harness/design/cpp/bare.h) as a program of its own, for
// trying Verilator's and the C++ compiler's speed levers on the pixel
// processor without the harness (benches/levers/levers.sh builds it once
// per lever with `verilator --exe --build`).
//
//   bare_main WRITES WIDTH HEIGHT ROUNDS
//
// WRITES: the scene-port writes, `cfg addr x y z` a line (examples/
// scene_writes.rs). Runs every pixel of the WIDTH x HEIGHT image ROUNDS
// times and prints, per round, `cycles seconds`.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <vector>

#include "Vpp.h"
#include "bare.h"
#include "verilated_owned.h"

int main(int argc, char** argv) {
    if (argc != 5) {
        std::cerr << "usage: " << argv[0] << " WRITES WIDTH HEIGHT ROUNDS\n";
        return 2;
    }
    const unsigned width = std::atoi(argv[2]), height = std::atoi(argv[3]), rounds = std::atoi(argv[4]);
    if (width == 0 || height == 0 || width > 4096 || height > 4096 || rounds == 0) {
        std::cerr << argv[0] << ": WIDTH and HEIGHT must be 1 to 4096, ROUNDS at least 1\n";
        return 2;
    }
    try {
        rtcosim::Owned<Vpp> owned;
        Vpp& m = *owned.model;
        m.start = 0;
        m.fault_state = 0;
        m.fault_xor = 0;
        rtcosim::reset_model(m);
        std::ifstream in(argv[1]);
        if (!in) throw std::runtime_error(std::string("cannot read ") + argv[1]);
        unsigned cfg, addr, writes = 0;
        std::uint32_t x, y, z;
        while (in >> cfg >> addr >> std::hex >> x >> y >> z >> std::dec) {
            if (!m.ready) throw std::runtime_error("scene write while not ready");
            rtcosim::write_scene_port(m, cfg != 0, static_cast<std::uint8_t>(addr), x, y, z);
            ++writes;
        }
        if (!in.eof() || writes == 0) throw std::runtime_error(std::string(argv[1]) + ": not a list of scene writes");
        std::vector<std::uint32_t> coords;
        for (unsigned py = 0; py < height; ++py)
            for (unsigned px = 0; px < width; ++px) coords.push_back(px | py << 16);
        for (unsigned r = 0; r < rounds; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            const std::uint64_t cycles = rtcosim::bare_pixels(m, coords.data(), coords.size(), 100000);
            const std::chrono::duration<double> s = std::chrono::steady_clock::now() - t0;
            std::printf("%llu %.6f\n", static_cast<unsigned long long>(cycles), s.count());
        }
    } catch (const std::exception& e) {
        std::cerr << argv[0] << ": " << e.what() << "\n";
        return 1;
    }
    return 0;
}
