// ============================================================================
// alu_ctrl.vh -- the ALU control word: alu_ctrl drives it, alu obeys it
// ============================================================================
// alu_ctrl decodes an opcode (isa.vh) into this packed word; pp_core wires
// alu_ctrl.ctrl straight into alu.ctrl. Fields are bit ranges for
// ctrl[`ALU_CTRL_<FIELD>]; codes are sized constants.
//
// Lanes of the ALU (thesis 4.2): lane i has one fp_mul (A.i times a lane of
// B picked by B_LANE_<i>) and one fp_add whose operands depend on the lane:
//   x adder: (ADDX_A_F ? F.x : A.x) + {B.x with NEG_B, F.y, F.z, A.y}[ADDX_B]
//   y adder: ADDY_F ? F.x + F.z : A.y + B.y with NEG_B
//   z adder: A.z + B.z with NEG_B
// RES_SEL picks the result y, F_SEL the next value of the internal register
// F. RES_SEL = RECIP or SQRT makes the op multi-cycle: the unit starts in
// the op's first cycle and the op is done when the unit's out_valid rises;
// with ROOTS both units start and the op is done when both have finished.
// EXP likewise starts the three fp_exp units (one per lane).
// ============================================================================
`ifndef ALU_CTRL_VH
`define ALU_CTRL_VH

`define ALU_CTRL_W 23

// ---------------------------------------------------------------------------
// Fields
// ---------------------------------------------------------------------------
`define ALU_CTRL_B_LANE_X 1:0     // lane of B into result lane x's multiplier (ALU_LANE_*)
`define ALU_CTRL_B_LANE_Y 3:2     // ... result lane y's multiplier
`define ALU_CTRL_B_LANE_Z 5:4     // ... result lane z's multiplier
`define ALU_CTRL_NEG_B 6          // flip B's sign bits into the adders (SUB)
`define ALU_CTRL_NEG_MUL 7        // flip the products' sign bits (NMUL, NMULX, ISECT1)
`define ALU_CTRL_NEG_A 8          // flip A's sign bits on the pass path (NEG; MOV: 0)
`define ALU_CTRL_ADDX_A_F 9       // x adder operand 1: 0 = A.x, 1 = F.x
`define ALU_CTRL_ADDX_B 11:10     // x adder operand 2 (ALU_ADDX_B_*)
`define ALU_CTRL_ADDY_F 12        // y adder: 0 = A.y + B.y, 1 = F.x + F.z
`define ALU_CTRL_F_SEL 15:13      // next F (ALU_F_*)
`define ALU_CTRL_RES_SEL 18:16    // result y (ALU_RES_*)
`define ALU_CTRL_UNIT_A_Y 19      // fp_recip operand: 0 = A.x, 1 = A.y (RECIPY)
`define ALU_CTRL_ROOTS 20         // ROOTS: with RES_SEL = SQRT, fp_recip starts too and
                                  // y = <sqrt, recip, +0> when both are done
`define ALU_CTRL_DOUBLE 21        // double the products (MUL2X): exponent + 1, exact
`define ALU_CTRL_EXP 22           // EXP: y = the three fp_exp results (one per lane of A),
                                  // multi-cycle (RES_SEL is ignored)

// ---------------------------------------------------------------------------
// Codes
// ---------------------------------------------------------------------------
// B_LANE_*: a lane of B (code 3 is unused and reads as lane x).
`define ALU_LANE_X 2'd0
`define ALU_LANE_Y 2'd1
`define ALU_LANE_Z 2'd2

// ADDX_B: the x adder's second operand.
`define ALU_ADDX_B_B 2'd0         // B.x, sign flipped when NEG_B
`define ALU_ADDX_B_FY 2'd1        // F.y
`define ALU_ADDX_B_FZ 2'd2        // F.z
`define ALU_ADDX_B_AY 2'd3        // A.y

// F_SEL: the value F takes at the rising edge ending the cycle.
`define ALU_F_HOLD 3'd0           // F unchanged
`define ALU_F_MUL 3'd1            // F = products, NEG_MUL applied (DOT1, ISECT1)
`define ALU_F_SUM_X 3'd2          // F = <x sum, F.y, F.z>        (DOT2, ISECT2)
`define ALU_F_SUM_XY_AZ 3'd3      // F = <x sum, y sum, A.z>      (ISECT3)
`define ALU_F_SUM_XY_0 3'd4       // F = <x sum, y sum, +0>       (ISECT4)

// RES_SEL: the result y.
`define ALU_RES_ZERO 3'd0         // <+0, +0, +0> (ops that write nothing)
`define ALU_RES_SUM 3'd1          // the three adders
`define ALU_RES_MUL 3'd2          // the three products, NEG_MUL applied
`define ALU_RES_PASS 3'd3         // A, NEG_A applied
`define ALU_RES_ITOF 3'd4         // <itof(ix), itof(iy), +0>
`define ALU_RES_F 3'd5            // the next F (ISECT4: Y = F)
`define ALU_RES_RECIP 3'd6        // <fp_recip y, +0, +0>; multi-cycle
`define ALU_RES_SQRT 3'd7         // <fp_sqrt y, +0, +0>; multi-cycle

`endif
