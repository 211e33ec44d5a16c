`default_nettype none
// ============================================================================
// fp_mul -- combinational IEEE-754 binary32 multiplier, y = a * b
// ============================================================================
// Round to nearest, ties to even; subnormal inputs and outputs are fully
// supported (no flush to zero). Any NaN result is the canonical quiet NaN
// 32'h7FC00000.
//
// Datapath:
//   1. unpack / classify both operands
//   2. full 24x24 -> 48-bit significand product (exact)
//   3. normalize with a leading-zero count; subnormal inputs make the
//      product arbitrarily unnormalized, so one wide normalizer covers them
//   4. round and pack in fp_round (which also denormalizes tiny results)
//   5. override the result for zero, infinity and NaN cases
// ============================================================================
module fp_mul (
    input  wire [31:0] a,
    input  wire [31:0] b,
    output wire [31:0] y
);

    localparam [7:0]  EXP_SPECIAL = 8'hFF;
    localparam [31:0] QNAN        = 32'h7FC00000;
    // Product bit 47 has weight 2^(ea + eb - 253) with a bias-127 result
    // exponent of ea + eb - 126 before normalization.
    localparam [11:0] EXP_OFFSET  = 12'd126;

    // ------------------------------------------------------------------------
    // Unpack and classify
    // ------------------------------------------------------------------------
    wire [7:0]  a_exp     = a[30:23];
    wire [7:0]  b_exp     = b[30:23];
    wire        a_hidden  = |a_exp;
    wire        b_hidden  = |b_exp;
    wire        a_special = (a_exp == EXP_SPECIAL);
    wire        b_special = (b_exp == EXP_SPECIAL);
    wire        a_is_nan  = a_special & (|a[22:0]);
    wire        b_is_nan  = b_special & (|b[22:0]);
    wire        a_is_inf  = a_special & ~(|a[22:0]);
    wire        b_is_inf  = b_special & ~(|b[22:0]);
    wire        a_is_zero = ~a_hidden & ~(|a[22:0]);
    wire        b_is_zero = ~b_hidden & ~(|b[22:0]);

    wire        prod_sign = a[31] ^ b[31];

    // Subnormals share the exponent of 2^-126 with the smallest normals.
    wire [7:0]  a_exp_eff = a_hidden ? a_exp : 8'd1;
    wire [7:0]  b_exp_eff = b_hidden ? b_exp : 8'd1;

    // ------------------------------------------------------------------------
    // Significand product
    // ------------------------------------------------------------------------
    // Operands are zero-extended so the multiply is evaluated at the full
    // 48-bit product width.
    wire [47:0] prod = {24'd0, a_hidden, a[22:0]} * {24'd0, b_hidden, b[22:0]};

    // ------------------------------------------------------------------------
    // Normalize
    // ------------------------------------------------------------------------
    // The product of two non-zero significands is non-zero, so lz <= 46 and
    // the leading one always reaches bit 47. Exponents of far-too-small
    // results go negative; fp_round turns those into subnormals or zero.
    wire [5:0] lz;
    fp_lzc #(.WIDTH(48), .COUNT_W(6)) u_lzc (.value(prod), .count(lz));
    wire [47:0]        norm_prod = prod << lz;
    wire signed [11:0] norm_exp  = {4'd0, a_exp_eff} + {4'd0, b_exp_eff}
                                   - EXP_OFFSET - {6'd0, lz};

    // ------------------------------------------------------------------------
    // Round and pack
    // ------------------------------------------------------------------------
    wire [31:0] rounded;

    fp_round u_round (
        .sign   (prod_sign),
        .exp    (norm_exp),
        .sig    (norm_prod[47:21]),
        .sticky (|norm_prod[20:0]),
        .y      (rounded)
    );

    // ------------------------------------------------------------------------
    // Special-case override
    // ------------------------------------------------------------------------
    reg [31:0] result;

    always @* begin
        result = rounded;
        if (a_is_nan | b_is_nan | (a_is_inf & b_is_zero) | (a_is_zero & b_is_inf))
            result = QNAN;
        else if (a_is_inf | b_is_inf)
            result = {prod_sign, EXP_SPECIAL, 23'd0};
        else if (a_is_zero | b_is_zero)
            result = {prod_sign, 31'd0};
    end

    assign y = result;

endmodule
`default_nettype wire
