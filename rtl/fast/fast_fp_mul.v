`default_nettype none
`include "fast_defs.vh"
// ============================================================================
// fast_fp_mul -- fp_mul (rtl/fp/fp_mul.v) pipelined: y = a * b, LATENCY = 9
// ============================================================================
// fp_mul's datapath, step for step, with a register between steps (docs/
// fast.md). Bit for bit fp_mul's result: round to nearest even, subnormals in
// and out, the canonical quiet NaN 32'h7FC00000. y appears 9 clock edges
// after a and b; a new pair may enter every cycle.
//
//   1. classify; the special result (NaN, infinity, zero)
//   2. the exponent sum; two partial products, a 24 x 17 and a 24 x 7 bit multiply, each one
//      DSP48E1 (25 x 18) between registers
//   3. their sum: the exact 48-bit product
//   4, 5, 6. normalize (fast_fp_norm)
//   7, 8, 9. round and pack (fast_fp_round), the special result overriding
// ============================================================================
module fast_fp_mul (
    input  wire        clk,
    input  wire [31:0] a,
    input  wire [31:0] b,
    output wire [31:0] y
);

    localparam [7:0]   EXP_SPECIAL = 8'hFF;
    localparam [31:0]  QNAN        = 32'h7FC00000;
    // Product bit 47 has weight 2^(ea + eb - 253) with a bias-127 result
    // exponent of ea + eb - 126 before normalization.
    localparam signed [11:0] EXP_OFFSET = 12'sd126;

    // ------------------------------------------------------------------------
    // Stage 1: classify, the special result
    // ------------------------------------------------------------------------
    wire [7:0] a_exp     = a[30:23];
    wire [7:0] b_exp     = b[30:23];
    wire       a_hidden  = |a_exp;
    wire       b_hidden  = |b_exp;
    wire       a_special = (a_exp == EXP_SPECIAL);
    wire       b_special = (b_exp == EXP_SPECIAL);
    wire       a_is_nan  = a_special & (|a[22:0]);
    wire       b_is_nan  = b_special & (|b[22:0]);
    wire       a_is_inf  = a_special & ~(|a[22:0]);
    wire       b_is_inf  = b_special & ~(|b[22:0]);
    wire       a_is_zero = ~a_hidden & ~(|a[22:0]);
    wire       b_is_zero = ~b_hidden & ~(|b[22:0]);
    wire       sign      = a[31] ^ b[31];
    // Subnormals share the exponent of 2^-126 with the smallest normals.
    wire [7:0] a_exp_eff = a_hidden ? a_exp : 8'd1;
    wire [7:0] b_exp_eff = b_hidden ? b_exp : 8'd1;

    reg               s1_sign, s1_special;
    reg        [7:0]  s1_a_exp, s1_b_exp;
    reg        [23:0] s1_a_sig, s1_b_sig;
    reg        [31:0] s1_special_y;

    always @(posedge clk) begin
        s1_sign      <= sign;
        s1_a_exp     <= a_exp_eff;
        s1_b_exp     <= b_exp_eff;
        s1_a_sig     <= {a_hidden, a[22:0]};
        s1_b_sig     <= {b_hidden, b[22:0]};
        s1_special   <= a_special | b_special | a_is_zero | b_is_zero;
        s1_special_y <= (a_is_nan | b_is_nan | (a_is_inf & b_is_zero) | (a_is_zero & b_is_inf)) ? QNAN
                      : (a_is_inf | b_is_inf) ? {sign, EXP_SPECIAL, 23'd0}
                      : {sign, 31'd0};
    end

    // ------------------------------------------------------------------------
    // Stage 2: partial products (one DSP48E1 each); the exponent sum
    // ------------------------------------------------------------------------
    reg        [40:0] s2_lo;  // a * b[16:0]
    reg        [30:0] s2_hi;  // a * b[23:17]
    reg               s2_sign, s2_special;
    reg signed [11:0] s2_base;
    reg        [31:0] s2_special_y;

    always @(posedge clk) begin
        s2_lo        <= {17'd0, s1_a_sig} * {24'd0, s1_b_sig[16:0]};
        s2_hi        <= {7'd0, s1_a_sig} * {24'd0, s1_b_sig[23:17]};
        s2_sign      <= s1_sign;
        s2_special   <= s1_special;
        s2_base      <= {4'd0, s1_a_exp} + {4'd0, s1_b_exp} - EXP_OFFSET;
        s2_special_y <= s1_special_y;
    end

    // ------------------------------------------------------------------------
    // Stage 3: the exact product
    // ------------------------------------------------------------------------
    reg [47:0] s3_prod;
    always @(posedge clk) s3_prod <= {7'd0, s2_lo} + {s2_hi, 17'd0};

    // The sign, exponent and special result wait for the product's sum,
    // then for the normalization.
    wire               s3_sign, s3_special;
    wire signed [11:0] s3_base;
    wire        [31:0] s3_special_y;
    fast_delay #(.WIDTH(46), .STAGES(1)) u_side3 (
        .clk(clk),
        .d({s2_sign, s2_special, s2_base, s2_special_y}),
        .q({s3_sign, s3_special, s3_base, s3_special_y})
    );

    // ------------------------------------------------------------------------
    // Stages 4, 5, 6: normalize. The product of two non-zero significands is
    // non-zero, so the leading one always reaches bit 47; a zero operand is
    // the special result.
    // ------------------------------------------------------------------------
    wire [47:0]        norm_prod;
    wire signed [11:0] norm_exp;
    fast_fp_norm #(.WIDTH(48), .COUNT_W(6)) u_norm (
        .clk(clk), .value(s3_prod), .base(s3_base), .y(norm_prod), .exp(norm_exp)
    );

    wire        n_sign, n_special;
    wire [31:0] n_special_y;
    fast_delay #(.WIDTH(34), .STAGES(`FAST_NORM_LATENCY)) u_side5 (
        .clk(clk),
        .d({s3_sign, s3_special, s3_special_y}),
        .q({n_sign, n_special, n_special_y})
    );

    // ------------------------------------------------------------------------
    // Stages 7, 8, 9: round and pack; the special result overrides
    // ------------------------------------------------------------------------
    fast_fp_round u_round (
        .clk    (clk),
        .sign   (n_sign),
        .exp    (norm_exp),
        .sig    (norm_prod[47:21]),
        .sticky (|norm_prod[20:0]),
        .ovr    (n_special),
        .ovr_y  (n_special_y),
        .y      (y)
    );

endmodule
`default_nettype wire
