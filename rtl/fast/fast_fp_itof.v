`default_nettype none
`include "fast_defs.vh"
// ============================================================================
// fast_fp_itof -- fp_itof (rtl/fp/fp_itof.v) pipelined: y = float(a), LATENCY = 7
// ============================================================================
// a is a signed 32-bit integer; y its nearest binary32 (ties to even), bit
// for bit fp_itof's. y appears 7 clock edges after a; a new a may enter
// every cycle.
//
//   1. sign and magnitude (a 32-bit negation)
//   2, 3, 4. normalize (fast_fp_norm)
//   5, 6, 7. round and pack (fast_fp_round); a = 0 overrides to +0
// ============================================================================
module fast_fp_itof (
    input  wire        clk,
    input  wire [31:0] a,
    output wire [31:0] y
);

    // Bit 31 of the magnitude has weight 2^31, i.e. biased exponent 127 + 31.
    localparam signed [11:0] EXP_MSB = 12'sd158;

    // ------------------------------------------------------------------------
    // Stage 1: sign and magnitude
    // ------------------------------------------------------------------------
    reg        s1_neg, s1_zero;
    reg [31:0] s1_mag;

    always @(posedge clk) begin
        s1_neg  <= a[31];
        s1_zero <= ~(|a);
        s1_mag  <= a[31] ? (~a + 32'd1) : a;
    end

    // ------------------------------------------------------------------------
    // Stages 2, 3, 4: normalize
    // ------------------------------------------------------------------------
    wire [31:0]        norm_mag;
    wire signed [11:0] norm_exp;
    fast_fp_norm #(.WIDTH(32), .COUNT_W(6)) u_norm (
        .clk(clk), .value(s1_mag), .base(EXP_MSB), .y(norm_mag), .exp(norm_exp)
    );

    wire n_neg, n_zero;
    fast_delay #(.WIDTH(2), .STAGES(`FAST_NORM_LATENCY)) u_side (
        .clk(clk), .d({s1_neg, s1_zero}), .q({n_neg, n_zero})
    );

    // ------------------------------------------------------------------------
    // Stages 5, 6, 7: round and pack. Only magnitudes >= 2^24 lose bits;
    // bits 4:0 of the normalized value lie below the round bit.
    // ------------------------------------------------------------------------
    fast_fp_round u_round (
        .clk    (clk),
        .sign   (n_neg),
        .exp    (norm_exp),
        .sig    (norm_mag[31:5]),
        .sticky (|norm_mag[4:0]),
        .ovr    (n_zero),
        .ovr_y  (32'd0),
        .y      (y)
    );

endmodule
`default_nettype wire
