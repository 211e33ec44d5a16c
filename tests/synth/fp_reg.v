`default_nettype none
// ============================================================================
// fp_reg -- one combinational float unit (fp_add or fp_mul) between
// registers, for a measured Fmax of the unit alone (rtl/synth/, docs/rtl.md
// "Synthesis"): a, b registered in, y registered out. Synthesis only.
// ============================================================================
module fp_reg #(
    parameter integer MUL = 0  // 0: fp_add, 1: fp_mul
) (
    input  wire        clk,
    input  wire [31:0] a,
    input  wire [31:0] b,
    output reg  [31:0] y_q
);
    reg  [31:0] a_q, b_q;
    wire [31:0] y;

    generate
        if (MUL != 0) begin : g_mul
            fp_mul u_unit (.a(a_q), .b(b_q), .y(y));
        end else begin : g_add
            fp_add u_unit (.a(a_q), .b(b_q), .y(y));
        end
    endgenerate

    always @(posedge clk) begin
        a_q <= a;
        b_q <= b;
        y_q <= y;
    end
endmodule
`default_nettype wire
