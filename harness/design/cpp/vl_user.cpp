// Verilator calls these instead of printing and calling abort(): build.rs
// defines VL_USER_FATAL, VL_USER_STOP and VL_USER_FINISH. The exception
// unwinds to the bridge, and cxx hands it to Rust as an Err.

#include <stdexcept>
#include <string>

#include "verilated.h"

void vl_fatal(const char* filename, int linenum, const char* hier, const char* msg) {
    throw std::runtime_error(std::string("verilated model fatal error at ") + (filename ? filename : "?") + ":" +
                             std::to_string(linenum) + " (" + (hier ? hier : "") + "): " + (msg ? msg : ""));
}

void vl_stop(const char* filename, int linenum, const char* hier) {
    vl_fatal(filename, linenum, hier, "$stop");
}

void vl_finish(const char* filename, int linenum, const char* hier) {
    vl_fatal(filename, linenum, hier, "$finish");
}
