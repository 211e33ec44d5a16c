`default_nettype none
// ============================================================================
// fp_reg -- one float unit between registers, for a measured Fmax of the
// unit alone (rtl/synth/synth.sh add|mul|fast-*, docs/rtl.md
// "Synthesis", docs/fast.md): a, b registered in, y registered out (a
// pipelined unit's own stages lie between). Synthesis only.
// ============================================================================
module fp_reg #(
    // 0: fp_add, 1: fp_mul, 2: fast_fp_add, 3: fast_fp_mul, 4: fast_fp_itof,
    // 5: fast_fp_recip, 6: fast_fp_sqrt (METHOD), 7: fast_fp_exp; the unary
    // ones ignore b.
    parameter integer UNIT   = 0,
    parameter integer METHOD = 0
) (
    input  wire        clk,
    input  wire [31:0] a,
    input  wire [31:0] b,
    output reg  [31:0] y_q
);
    reg  [31:0] a_q, b_q;
    wire [31:0] y;

    generate
        if (UNIT == 7) begin : g_fast_exp
            fast_fp_exp u_unit (.clk(clk), .a(a_q), .y(y));
        end else if (UNIT == 6) begin : g_fast_sqrt
            fast_fp_sqrt #(.METHOD(METHOD)) u_unit (.clk(clk), .a(a_q), .y(y));
        end else if (UNIT == 5) begin : g_fast_recip
            fast_fp_recip #(.METHOD(METHOD)) u_unit (.clk(clk), .a(a_q), .y(y));
        end else if (UNIT == 4) begin : g_fast_itof
            fast_fp_itof u_unit (.clk(clk), .a(a_q), .y(y));
        end else if (UNIT == 3) begin : g_fast_mul
            fast_fp_mul u_unit (.clk(clk), .a(a_q), .b(b_q), .y(y));
        end else if (UNIT == 2) begin : g_fast_add
            fast_fp_add u_unit (.clk(clk), .a(a_q), .b(b_q), .y(y));
        end else if (UNIT == 1) begin : g_mul
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
