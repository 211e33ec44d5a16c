`default_nettype none
`include "fp_defs.vh"
// ============================================================================
// alu_pins -- fast_alu (rtl/fast/fast_alu.v) behind 32-bit ports, for place
// and route (rtl/synth/synth.sh ecp5 fast-alu, docs/fast.md): the ALU's 272
// input bits shift in 32 a cycle and its 113 output bits leave 32 a cycle
// through a registered 4:1 choice, so the design fits a package's pins and
// every path to and from the ALU starts and ends at a register. Synthesis
// only.
// ============================================================================
module alu_pins #(
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT,
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT,
    parameter integer EXPOSURE     = 1
) (
    input  wire        clk,
    input  wire        rst_n,
    input  wire [31:0] din,
    output reg  [31:0] dout
);
    localparam integer IN_W = 1 + 5 + 6 + 96 + 96 + 32 + 32;  // 268

    reg [287:0] in_q;
    always @(posedge clk) in_q <= {in_q[255:0], din};

    wire        out_valid, out_writes, exp_ready;
    wire [4:0]  out_ctx;
    wire [95:0] y;
    wire [2:0]  y_neg, y_pos, y_sign;

    fast_alu #(
        .RECIP_METHOD(RECIP_METHOD), .SQRT_METHOD(SQRT_METHOD), .EXPOSURE(EXPOSURE), .CTX_BITS(5)
    ) u_alu (
        .clk(clk), .rst_n(rst_n),
        .in_valid(in_q[0]), .in_ctx(in_q[5:1]), .in_op(in_q[11:6]),
        .a(in_q[107:12]), .b(in_q[203:108]), .ix(in_q[235:204]), .iy(in_q[267:236]),
        .exp_ready(exp_ready), .out_valid(out_valid), .out_ctx(out_ctx), .out_writes(out_writes),
        .y(y), .y_neg(y_neg), .y_pos(y_pos), .y_sign(y_sign)
    );

    reg [1:0] pick;
    always @(posedge clk) begin
        pick <= pick + 2'd1;
        case (pick)
            2'd0: dout <= y[31:0];
            2'd1: dout <= y[63:32];
            2'd2: dout <= y[95:64];
            default: dout <= {15'd0, exp_ready, out_valid, out_writes, out_ctx, y_neg, y_pos, y_sign};
        endcase
    end

    wire unused_in = ^in_q[287:IN_W];
endmodule
`default_nettype wire
