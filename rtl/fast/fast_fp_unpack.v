`default_nettype none
`include "fast_defs.vh"
// ============================================================================
// fast_fp_unpack -- fp_unpack (rtl/fp/fp_unpack.v) pipelined, LATENCY = 4
// ============================================================================
// The input stage of fast_fp_recip and fast_fp_sqrt: classify a binary32
// operand and normalize its significand, as fp_unpack does in one step:
//   finite nonzero a:  |a| = (man / 2^23) * 2^(exp - 127), man[23] = 1;
//   a subnormal's exp reaches -22. For zero, infinity and NaN, exp and man
//   are unspecified.
// Every output appears 4 clock edges after a; a new a may enter every cycle.
//   1. classify; a subnormal's fraction lined up one bit up, from exponent 0
//   2, 3, 4. normalize (fast_fp_norm)
// ============================================================================
module fast_fp_unpack (
    input  wire               clk,
    input  wire        [31:0] a,
    output wire               sign,
    output wire               is_nan,
    output wire               is_inf,
    output wire               is_zero,
    output wire signed [11:0] exp,
    output wire        [23:0] man
);

    wire [7:0]  field = a[30:23];
    wire [22:0] frac  = a[22:0];

    // ------------------------------------------------------------------------
    // Stage 1: classify
    // ------------------------------------------------------------------------
    reg               s1_sign, s1_nan, s1_inf, s1_zero;
    reg        [23:0] s1_v;     // the significand before normalizing
    reg signed [11:0] s1_base;  // its exponent

    always @(posedge clk) begin
        s1_sign <= a[31];
        s1_nan  <= (field == 8'hFF) && (frac != 23'd0);
        s1_inf  <= (field == 8'hFF) && (frac == 23'd0);
        s1_zero <= (field == 8'h00) && (frac == 23'd0);
        // A subnormal is frac * 2^-149: its leading one goes up to bit 23
        // and its exponent down by as much, from 0 (fp_unpack).
        s1_v    <= (field != 8'h00) ? {1'b1, frac} : {frac, 1'b0};
        s1_base <= (field != 8'h00) ? {4'd0, field} : 12'sd0;
    end

    // ------------------------------------------------------------------------
    // Stages 2, 3, 4: normalize; the class waits beside
    // ------------------------------------------------------------------------
    fast_fp_norm #(.WIDTH(24), .COUNT_W(5)) u_norm (
        .clk(clk), .value(s1_v), .base(s1_base), .y(man), .exp(exp)
    );
    fast_delay #(.WIDTH(4), .STAGES(`FAST_NORM_LATENCY)) u_class (
        .clk(clk), .d({s1_sign, s1_nan, s1_inf, s1_zero}), .q({sign, is_nan, is_inf, is_zero})
    );

endmodule
`default_nettype wire
