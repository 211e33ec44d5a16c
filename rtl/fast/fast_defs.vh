// ============================================================================
// fast_defs.vh -- latencies of the fast processor's pipelined units
// ============================================================================
// Clock edges from a unit's inputs to its output; a new operation may enter
// every cycle. Each unit's header says what its stages do; docs/fast.md has
// the figures. The harness (fp-check) reads the *_LATENCY lines.
`ifndef FAST_DEFS_VH
`define FAST_DEFS_VH

`define FAST_NORM_LATENCY 3    // fast_fp_norm: leading zeros by bytes, then shift
`define FAST_ROUND_LATENCY 3   // fast_fp_round: exponent class, denormalize, round
`define FAST_UNPACK_LATENCY 4  // fast_fp_unpack: classify, then norm
`define FAST_ADD_LATENCY 10    // fast_fp_add: 4 + norm + round
`define FAST_MUL_LATENCY 9     // fast_fp_mul: 3 + norm + round
`define FAST_ITOF_LATENCY 7    // fast_fp_itof: 1 + norm + round
`define FAST_RECIP_LATENCY 18  // fast_fp_recip, either method: 1 + norm + 11 + round
`define FAST_SQRT_LATENCY 22   // fast_fp_sqrt, either method: 1 + norm + 15 + round
`define FAST_EXP_LATENCY 20    // fast_fp_exp: 17 + round
`define FAST_ALU_LATENCY 27          // fast_alu with exposure (fast_alu checks it)
`define FAST_ALU_LATENCY_NOEXP 26    // fast_alu without (EXPOSURE = 0)

`endif
