`default_nettype none
// ============================================================================
// fp_itof -- combinational signed int32 -> IEEE-754 binary32 conversion
// ============================================================================
// a is a two's-complement signed 32-bit integer; y = (float)a rounded to
// nearest, ties to even (bit-identical to Rust `a as f32`). Integers never
// overflow or underflow binary32, and 0 converts to +0.
//
// Datapath:
//   1. take the magnitude (|-2^31| = 2^31 still fits in 32 unsigned bits)
//   2. normalize with a leading-zero count
//   3. round and pack in fp_round
// ============================================================================
module fp_itof (
    input  wire [31:0] a,
    output wire [31:0] y
);

    // Bit 31 of the magnitude has weight 2^31, i.e. biased exponent 127 + 31.
    localparam [11:0] EXP_MSB = 12'd158;

    // ------------------------------------------------------------------------
    // Sign / magnitude
    // ------------------------------------------------------------------------
    wire        neg = a[31];
    wire [31:0] mag = neg ? (~a + 32'd1) : a;

    // ------------------------------------------------------------------------
    // Normalize
    // ------------------------------------------------------------------------
    // For a = 0 the shift clears everything; the result is overridden below.
    wire [5:0] lz;
    fp_lzc #(.WIDTH(32), .COUNT_W(6)) u_lzc (.value(mag), .count(lz));
    wire [31:0]        norm_mag = mag << lz;
    wire signed [11:0] norm_exp = EXP_MSB - {6'd0, lz};

    // ------------------------------------------------------------------------
    // Round and pack
    // ------------------------------------------------------------------------
    // Only magnitudes >= 2^24 lose bits; bits 4:0 of the normalized value
    // lie below the round bit and only matter through their OR.
    wire [31:0] rounded;

    fp_round u_round (
        .sign   (neg),
        .exp    (norm_exp),
        .sig    (norm_mag[31:5]),
        .sticky (|norm_mag[4:0]),
        .y      (rounded)
    );

    // ------------------------------------------------------------------------
    // Zero override
    // ------------------------------------------------------------------------
    // fp_round requires a normalized significand, so zero bypasses it.
    assign y = (|a) ? rounded : 32'd0;

endmodule
`default_nettype wire
