`default_nettype none
`include "fast_defs.vh"
// ============================================================================
// fast_fp_add -- fp_add (rtl/fp/fp_add.v) pipelined: y = a + b, LATENCY = 10
// ============================================================================
// fp_add's datapath, step for step, with a register between steps so that
// no register-to-register path holds more than a few LUT levels or one
// short carry chain (docs/fast.md). Bit for bit fp_add's result: round to
// nearest even, subnormals in and out, the canonical quiet NaN 32'h7FC00000.
// y appears 10 clock edges after a and b; a new pair may enter every cycle.
//
//   1. classify a and b (exponent all ones, fraction zero); order them by
//      magnitude (a 31-bit compare); both exponent differences, a - b and
//      b - a (the effective exponents: 1 for a subnormal)
//   2. swap into big and small; the shift (the difference the order picks,
//      clamped); the special result (NaN, infinity), which depends on the
//      inputs only
//   3. align the small significand, with the sticky of what falls out
//   4. add or subtract (28 bits)
//   5, 6, 7. normalize (fast_fp_norm); an exact zero sum becomes +-0
//   8, 9, 10. round and pack (fast_fp_round), the special result overriding
// ============================================================================
module fast_fp_add (
    input  wire        clk,
    input  wire [31:0] a,
    input  wire [31:0] b,
    output wire [31:0] y
);

    localparam [7:0]   EXP_SPECIAL = 8'hFF;
    localparam [31:0]  QNAN        = 32'h7FC00000;
    // Past 27 positions every bit of the 27-bit aligned operand is sticky.
    localparam [7:0]   ALIGN_LIMIT = 8'd27;
    localparam [4:0]   ALIGN_MAX   = 5'd27;

    // ------------------------------------------------------------------------
    // Stage 1: classify, order by magnitude
    // ------------------------------------------------------------------------
    reg        s1_a_ge_b, s1_a_sign, s1_b_sign;
    reg        s1_a_ff, s1_b_ff, s1_a_nz, s1_b_nz;  // exponent all ones, fraction not zero
    reg [30:0] s1_a_mag, s1_b_mag;
    reg [7:0]  s1_d_ab, s1_d_ba;                    // the effective exponents' differences

    // Subnormals have no implicit one but share the exponent of 2^-126 with
    // the smallest normals, hence effective exponent 1.
    function [7:0] exp_eff(input [7:0] e);
        exp_eff = {e[7:1], e[0] | (e == 8'd0)};
    endfunction

    always @(posedge clk) begin
        // For binary32 the unsigned order of {exponent, fraction} is the
        // order of the magnitudes, subnormals included.
        s1_a_ge_b <= (a[30:0] >= b[30:0]);
        s1_a_sign <= a[31];
        s1_b_sign <= b[31];
        s1_a_mag  <= a[30:0];
        s1_b_mag  <= b[30:0];
        // The operands' classes here, the special result in stage 2 (the
        // two in one stage were one path of wide functions).
        s1_a_ff   <= (a[30:23] == EXP_SPECIAL);
        s1_b_ff   <= (b[30:23] == EXP_SPECIAL);
        s1_a_nz   <= |a[22:0];
        s1_b_nz   <= |b[22:0];
        // Both, beside the order: stage 2 picks the one that is >= 0.
        s1_d_ab   <= exp_eff(a[30:23]) - exp_eff(b[30:23]);
        s1_d_ba   <= exp_eff(b[30:23]) - exp_eff(a[30:23]);
    end

    wire s1_a_nan = s1_a_ff & s1_a_nz;
    wire s1_b_nan = s1_b_ff & s1_b_nz;
    wire s1_a_inf = s1_a_ff & ~s1_a_nz;
    wire s1_b_inf = s1_b_ff & ~s1_b_nz;

    // ------------------------------------------------------------------------
    // Stage 2: swap; the exponent difference
    // ------------------------------------------------------------------------
    wire [30:0] big_mag       = s1_a_ge_b ? s1_a_mag : s1_b_mag;
    wire [30:0] small_mag     = s1_a_ge_b ? s1_b_mag : s1_a_mag;
    wire        big_hidden    = |big_mag[30:23];
    wire        small_hidden  = |small_mag[30:23];
    wire [7:0]  exp_diff      = s1_a_ge_b ? s1_d_ab : s1_d_ba;

    reg        s2_big_sign, s2_eff_sub, s2_small_hidden, s2_special;
    reg [4:0]  s2_shift;
    reg [7:0]  s2_big_exp;
    reg [23:0] s2_big_sig;
    reg [22:0] s2_small_frac;
    reg [31:0] s2_special_y;

    always @(posedge clk) begin
        s2_big_sign     <= s1_a_ge_b ? s1_a_sign : s1_b_sign;
        s2_eff_sub      <= s1_a_sign ^ s1_b_sign;
        s2_shift        <= (exp_diff > ALIGN_LIMIT) ? ALIGN_MAX : exp_diff[4:0];
        s2_big_exp      <= exp_eff(big_mag[30:23]);
        s2_big_sig      <= {big_hidden, big_mag[22:0]};
        s2_small_hidden <= small_hidden;
        s2_small_frac   <= small_mag[22:0];
        s2_special      <= s1_a_ff | s1_b_ff;
        s2_special_y    <= (s1_a_nan | s1_b_nan | (s1_a_inf & s1_b_inf & (s1_a_sign ^ s1_b_sign))) ? QNAN
                         : s1_a_inf ? {s1_a_sign, EXP_SPECIAL, 23'd0}
                         : {s1_b_sign, EXP_SPECIAL, 23'd0};
    end

    // ------------------------------------------------------------------------
    // Stage 3: align the small significand
    // ------------------------------------------------------------------------
    // {small, 3 zero bits} >> shift keeps the top 26 bits of the 27-bit
    // result and ORs the rest into bit 0 (fp_add's align_wide and sticky).
    // Bit i of small_sig0 lands at or below bit 0 of the shift's result iff
    // i <= shift, and strictly below iff i < shift: the sticky is the OR of
    // those bits, from a mask in parallel with the shift.
    wire [26:0] small_sig0  = {s2_small_hidden, s2_small_frac, 3'd0};
    wire [26:0] small_shift = small_sig0 >> s2_shift;
    reg  [26:0] below_mask;
    integer i;
    always @* begin
        for (i = 0; i < 27; i = i + 1) below_mask[i] = (i[4:0] < s2_shift);
    end
    wire below = |(small_sig0 & below_mask);

    reg        s3_big_sign, s3_eff_sub, s3_special;
    reg [7:0]  s3_big_exp;
    reg [26:0] s3_big_sig, s3_small_sig;
    reg [31:0] s3_special_y;

    always @(posedge clk) begin
        s3_big_sign  <= s2_big_sign;
        s3_eff_sub   <= s2_eff_sub;
        s3_big_exp   <= s2_big_exp;
        s3_big_sig   <= {s2_big_sig, 3'd0};
        s3_small_sig <= {small_shift[26:1], small_shift[0] | below};
        s3_special   <= s2_special;
        s3_special_y <= s2_special_y;
    end

    // ------------------------------------------------------------------------
    // Stage 4: add or subtract (big >= small: never negative)
    // ------------------------------------------------------------------------
    reg               s4_big_sign, s4_eff_sub, s4_special;
    reg        [27:0] s4_sum;
    reg signed [11:0] s4_base;  // the exponent of sum bit 27
    reg        [31:0] s4_special_y;

    always @(posedge clk) begin
        s4_big_sign  <= s3_big_sign;
        s4_eff_sub   <= s3_eff_sub;
        s4_sum       <= s3_eff_sub ? ({1'b0, s3_big_sig} - {1'b0, s3_small_sig})
                                   : ({1'b0, s3_big_sig} + {1'b0, s3_small_sig});
        s4_base      <= {4'd0, s3_big_exp} + 12'sd1;
        s4_special   <= s3_special;
        s4_special_y <= s3_special_y;
    end

    // ------------------------------------------------------------------------
    // Stages 5, 6, 7: normalize. An exact zero sum is +0 under RNE unless both
    // operands were zeros of the same sign (-0 + -0 = -0): the effective-add
    // case.
    // ------------------------------------------------------------------------
    wire [27:0]        norm_sum;
    wire signed [11:0] norm_exp;
    fast_fp_norm #(.WIDTH(28), .COUNT_W(5)) u_norm (
        .clk(clk), .value(s4_sum), .base(s4_base), .y(norm_sum), .exp(norm_exp)
    );

    wire        n_big_sign, n_eff_sub, n_special, n_sum_zero;
    wire [31:0] n_special_y;
    fast_delay #(.WIDTH(36), .STAGES(`FAST_NORM_LATENCY)) u_side (
        .clk(clk),
        .d({s4_big_sign, s4_eff_sub, s4_special, ~(|s4_sum), s4_special_y}),
        .q({n_big_sign, n_eff_sub, n_special, n_sum_zero, n_special_y})
    );

    // ------------------------------------------------------------------------
    // Stages 8, 9, 10: round and pack; the special result overrides
    // ------------------------------------------------------------------------
    fast_fp_round u_round (
        .clk    (clk),
        .sign   (n_big_sign),
        .exp    (norm_exp),
        .sig    (norm_sum[27:1]),
        .sticky (norm_sum[0]),
        .ovr    (n_special | n_sum_zero),
        .ovr_y  (n_special ? n_special_y : {n_big_sign & ~n_eff_sub, 31'd0}),
        .y      (y)
    );

endmodule
`default_nettype wire
