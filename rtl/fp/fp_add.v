`default_nettype none
// ============================================================================
// fp_add -- combinational IEEE-754 binary32 adder, y = a + b
// ============================================================================
// Round to nearest, ties to even; subnormal inputs and outputs are fully
// supported (no flush to zero). Any NaN result is the canonical quiet NaN
// 32'h7FC00000.
//
// Datapath:
//   1. unpack / classify both operands
//   2. order by magnitude so the subtraction never goes negative and the
//      larger operand alone fixes the result sign and exponent
//   3. align the smaller significand (3 extra low bits: guard, round and a
//      sticky bit that ORs everything shifted further out)
//   4. add or subtract in a 28-bit datapath (one bit of carry headroom)
//   5. normalize with a leading-zero count
//   6. round and pack in fp_round
//   7. override the result for zero, infinity and NaN cases
//
// Folding the sticky into the LSB of the aligned operand is exact enough for
// correct rounding: a sticky can only be set when the exponent difference is
// >= 2, in which case the difference needs at most one left shift, so the
// rounding position always stays at least one bit above the sticky bit.
// ============================================================================
module fp_add (
    input  wire [31:0] a,
    input  wire [31:0] b,
    output wire [31:0] y
);

    localparam [7:0]  EXP_SPECIAL = 8'hFF;
    localparam [31:0] QNAN        = 32'h7FC00000;
    // Past 27 positions every bit of the 27-bit aligned operand is sticky.
    localparam [7:0]  ALIGN_LIMIT = 8'd27;
    localparam [4:0]  ALIGN_MAX   = 5'd27;

    // ------------------------------------------------------------------------
    // Unpack and classify
    // ------------------------------------------------------------------------
    wire       a_sign    = a[31];
    wire       b_sign    = b[31];
    wire       a_special = (a[30:23] == EXP_SPECIAL);
    wire       b_special = (b[30:23] == EXP_SPECIAL);
    wire       a_is_nan  = a_special & (|a[22:0]);
    wire       b_is_nan  = b_special & (|b[22:0]);
    wire       a_is_inf  = a_special & ~(|a[22:0]);
    wire       b_is_inf  = b_special & ~(|b[22:0]);

    // Opposite signs mean the magnitudes are subtracted.
    wire       eff_sub   = a_sign ^ b_sign;

    // ------------------------------------------------------------------------
    // Order operands by magnitude
    // ------------------------------------------------------------------------
    // For binary32 the unsigned order of {exponent, fraction} is the order of
    // the magnitudes, subnormals included.
    wire        a_ge_b    = (a[30:0] >= b[30:0]);
    wire        big_sign  = a_ge_b ? a_sign  : b_sign;
    wire [30:0] big_mag   = a_ge_b ? a[30:0] : b[30:0];
    wire [30:0] small_mag = a_ge_b ? b[30:0] : a[30:0];

    // Subnormals have no implicit one but share the exponent of 2^-126 with
    // the smallest normals, hence effective exponent 1.
    wire        big_hidden    = |big_mag[30:23];
    wire        small_hidden  = |small_mag[30:23];
    wire [7:0]  big_exp_eff   = big_hidden   ? big_mag[30:23]   : 8'd1;
    wire [7:0]  small_exp_eff = small_hidden ? small_mag[30:23] : 8'd1;

    // ------------------------------------------------------------------------
    // Align the smaller significand
    // ------------------------------------------------------------------------
    wire [7:0]  exp_diff    = big_exp_eff - small_exp_eff;
    wire [4:0]  align_shift = (exp_diff > ALIGN_LIMIT) ? ALIGN_MAX : exp_diff[4:0];
    // Upper 27 bits are the aligned operand, lower 27 bits catch what falls
    // off the end so it can be folded into the sticky bit.
    wire [53:0] align_wide  = {small_hidden, small_mag[22:0], 3'd0, 27'd0} >> align_shift;
    wire [26:0] small_sig   = {align_wide[53:28], align_wide[27] | (|align_wide[26:0])};
    wire [26:0] big_sig     = {big_hidden, big_mag[22:0], 3'd0};

    // ------------------------------------------------------------------------
    // Significand add / subtract
    // ------------------------------------------------------------------------
    // Magnitude ordering guarantees big_sig >= small_sig, so no negation step.
    wire [27:0] raw_sum = eff_sub ? ({1'b0, big_sig} - {1'b0, small_sig})
                                  : ({1'b0, big_sig} + {1'b0, small_sig});
    wire        sum_zero = ~(|raw_sum);

    // ------------------------------------------------------------------------
    // Normalize
    // ------------------------------------------------------------------------
    // Leading one is moved to bit 27. Bit 27 of raw_sum carries weight
    // 2^(big_exp_eff + 1), so each leading zero costs one exponent step.
    wire [4:0] lz;
    fp_lzc #(.WIDTH(28), .COUNT_W(5)) u_lzc (.value(raw_sum), .count(lz));
    wire [27:0]        norm_sum = raw_sum << lz;
    wire signed [11:0] norm_exp = {4'd0, big_exp_eff} + 12'd1 - {7'd0, lz};

    // ------------------------------------------------------------------------
    // Round and pack
    // ------------------------------------------------------------------------
    wire [31:0] rounded;

    fp_round u_round (
        .sign   (big_sign),
        .exp    (norm_exp),
        .sig    (norm_sum[27:1]),
        .sticky (norm_sum[0]),
        .y      (rounded)
    );

    // ------------------------------------------------------------------------
    // Special-case override
    // ------------------------------------------------------------------------
    // An exact zero sum is +0 under RNE unless both operands were zeros of
    // the same sign (-0 + -0 = -0), which is exactly the effective-add case.
    reg [31:0] result;

    always @* begin
        result = rounded;
        if (a_is_nan | b_is_nan | (a_is_inf & b_is_inf & eff_sub))
            result = QNAN;
        else if (a_is_inf)
            result = {a_sign, EXP_SPECIAL, 23'd0};
        else if (b_is_inf)
            result = {b_sign, EXP_SPECIAL, 23'd0};
        else if (sum_zero)
            result = {big_sign & ~eff_sub, 31'd0};
    end

    assign y = result;

endmodule
`default_nettype wire
