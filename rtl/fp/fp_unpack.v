`default_nettype none
// ============================================================================
// fp_unpack -- classify a binary32 operand and normalize its significand
// ============================================================================
// Purely combinational; the input stage of fp_recip and fp_sqrt.
//
//   finite nonzero a:  |a| = (man / 2^23) * 2^(exp - 127), man[23] = 1.
//   Subnormals are normalized by a leading-zero count, so exp reaches -22.
//   For zero, infinity and NaN, exp and man are don't-care (zero).
// ============================================================================
module fp_unpack (
    input  wire        [31:0] a,
    output wire               sign,
    output wire               is_nan,
    output wire               is_inf,
    output wire               is_zero,
    output reg  signed [9:0]  exp,
    output reg         [23:0] man
);

    wire [7:0]  field = a[30:23];
    wire [22:0] frac  = a[22:0];

    assign sign    = a[31];
    assign is_nan  = (field == 8'hFF) && (frac != 23'd0);
    assign is_inf  = (field == 8'hFF) && (frac == 23'd0);
    assign is_zero = (field == 8'h00) && (frac == 23'd0);

    // ------------------------------------------------------------------------
    // Leading-zero count of a subnormal fraction (1..22 shifts; 23 only for
    // zero, whose outputs are don't-care)
    // ------------------------------------------------------------------------
    wire [4:0] lz;
    fp_lzc #(.WIDTH(23), .COUNT_W(5)) u_lzc (.value(frac), .count(lz));

    // ------------------------------------------------------------------------
    // Normalization
    // ------------------------------------------------------------------------
    always @* begin
        if (field != 8'h00) begin
            exp = {2'b00, field};
            man = {1'b1, frac};
        end else begin
            // A subnormal is frac * 2^-149: shift the leading one up to bit 23
            // and lower the exponent by the same amount, from 1.
            exp = 10'sd0 - {5'd0, lz};
            man = {frac, 1'b0} << lz;
        end
    end

endmodule
`default_nettype wire
