`default_nettype none
`include "isa.vh"
// ============================================================================
// ctrl_reg -- the compact processor's controller (pp_ctrl) alone, its inputs
// and its instruction outputs registered: the depth of its next-state logic
// without a float unit in front (rtl/synth/synth.sh xc6v ctrl exact,
// docs/fast.md "Why the compact processor is slow"). Synthesis only.
// ============================================================================
module ctrl_reg (
    input  wire                         clk,
    input  wire                         rst_n,
    input  wire [`ISA_DIM_LANES*32-1:0] cfg_in,
    input  wire                         start_in,
    input  wire [`ISA_DIM_COORD_BITS-1:0] px_in,
    input  wire [`ISA_DIM_COORD_BITS-1:0] py_in,
    input  wire                         done_in,
    input  wire [3*`ISA_DIM_LANES-1:0]  flags_in,
    output reg  [`ISA_DIM_OP_BITS+3*`ISA_DIM_REG_BITS+`ISA_DIM_LANES+4-1:0] out_q
);
    reg [`ISA_DIM_LANES*32-1:0]   cfg;
    reg                           start, alu_done;
    reg [`ISA_DIM_COORD_BITS-1:0] px, py;
    reg [`ISA_DIM_LANES-1:0]      y_neg, y_pos, y_sign;
    always @(posedge clk) begin
        cfg      <= cfg_in;
        start    <= start_in;
        px       <= px_in;
        py       <= py_in;
        alu_done <= done_in;
        {y_neg, y_pos, y_sign} <= flags_in;
    end

    wire                            ready, done;
    wire [`ISA_DIM_OP_BITS-1:0]     op;
    wire [`ISA_DIM_REG_BITS-1:0]    la_a, la_b, la_w;
    wire [`ISA_DIM_LANES-1:0]       wmask;
    wire [`ISA_DIM_ST_BITS-1:0]     state;
    wire [$clog2(`ISA_DIM_STK_COUNT)-1:0] sp;
    wire [31:0]                     ix, iy;
    pp_ctrl u_ctrl (
        .clk(clk), .rst_n(rst_n), .cfg(cfg), .start(start), .px(px), .py(py),
        .ready(ready), .done(done), .op(op), .la_a(la_a), .la_b(la_b), .la_w(la_w),
        .wmask(wmask), .state(state), .sp(sp), .ix(ix), .iy(iy),
        .alu_done(alu_done), .y_neg(y_neg), .y_pos(y_pos), .y_sign(y_sign)
    );

    // The instruction of the cycle and a bit of the rest, so that synthesis
    // keeps the controller whole.
    always @(posedge clk) out_q <= {ready, done, op, la_a, la_b, la_w, wmask, ix[0], iy[0]};
endmodule
`default_nettype wire
