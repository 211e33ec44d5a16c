// ============================================================================
// fp_defs.vh -- constants shared by the float units and their users
// ============================================================================
// The METHOD parameter of fp_recip and fp_sqrt. golden::fp::Method::code()
// mirrors these codes; the root crate's build.rs reads this file and refuses
// to build when the two disagree.
`ifndef FP_DEFS_VH
`define FP_DEFS_VH

// Correctly rounded (round to nearest even), bit-identical to IEEE-754.
`define FP_METHOD_EXACT 0
// Seed table + one Newton-Raphson step, rounded directly: at most 1 ULP off.
`define FP_METHOD_FAST 1

`endif
