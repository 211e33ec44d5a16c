`default_nettype none
// ============================================================================
// fp_round -- shared IEEE-754 binary32 round-to-nearest-even and pack stage
// ============================================================================
// Purely combinational. Used by fp_add, fp_mul and fp_itof so that every unit
// rounds through exactly the same logic.
//
// Contract:
//   The value presented is  (-1)^sign * (sig / 2^26) * 2^(exp - 127)
//   plus a positive amount smaller than one unit of sig[0] when sticky = 1.
//
//   sign    result sign (also the sign of a result that rounds to zero)
//   exp     signed biased exponent of sig[26]; any value in [-2048, 2047]
//           is accepted (1..254 = normal range, <= 0 = below normal range,
//           >= 255 = overflow)
//   sig     significand, normalized so that sig[26] = 1:
//             sig[26]    implicit leading one
//             sig[25:3]  23 fraction bits
//             sig[2]     guard bit
//             sig[1:0]   bits below guard (only their OR matters)
//   sticky  OR of all bits of the exact result below sig[0]
//   y       packed binary32 result
//
//   - exp <= 0: the significand is shifted right by (1 - exp) with sticky
//     collection, producing a subnormal (or zero) encoding before rounding,
//     so gradual underflow is rounded exactly once.
//   - Rounding increments the packed {exponent, fraction} field as a single
//     31-bit number, so a carry out of the fraction naturally turns the
//     largest subnormal into the smallest normal and the largest normal
//     into infinity.
//   - exp >= 255 saturates to infinity (RNE never rounds toward zero past
//     max-normal).
//   - Zero, infinity and NaN operands are NOT handled here: sig must be
//     normalized, callers override the output for special cases.
// ============================================================================
module fp_round (
    input  wire               sign,
    input  wire signed [11:0] exp,
    input  wire        [26:0] sig,
    input  wire               sticky,
    output wire        [31:0] y
);

    localparam signed [11:0] EXP_MAX_FINITE   = 12'sd254;
    localparam signed [11:0] DENORM_LIMIT     = 12'sd26;
    // A true right shift of 27 (shifter amount 26, see below) already moves
    // every significand bit into the sticky region, so larger shifts need not
    // be distinguished.
    localparam        [4:0]  DENORM_SHIFT_MAX = 5'd26;
    localparam        [7:0]  EXP_FIELD_INF    = 8'hFF;

    // ------------------------------------------------------------------------
    // Denormalization (results below the normal range)
    // ------------------------------------------------------------------------
    // The true right shift is (1 - exp). The wide vector is pre-shifted by one
    // position (sig sits one bit lower than its "unshifted" slot), so the
    // shifter amount is just -exp and the always-zero top bit never exists.
    wire               tiny         = (exp <= 12'sd0);
    wire signed [11:0] neg_exp      = -exp;
    wire        [4:0]  denorm_shift = (neg_exp > DENORM_LIMIT) ? DENORM_SHIFT_MAX
                                                                : neg_exp[4:0];
    wire        [52:0] denorm_wide  = {sig, 26'd0} >> denorm_shift;

    // ------------------------------------------------------------------------
    // Select normal / subnormal significand and exponent field
    // ------------------------------------------------------------------------
    // frac_ext = {23 fraction bits, guard, two lower bits}; the implicit bit
    // is dropped because it is encoded by a non-zero exponent field.
    wire [25:0] frac_ext   = tiny ? denorm_wide[52:27] : sig[25:0];
    wire        sticky_all = sticky | (tiny & (|denorm_wide[26:0]));
    wire [7:0]  exp_field  = tiny ? 8'd0 : exp[7:0];

    // ------------------------------------------------------------------------
    // Round to nearest, ties to even
    // ------------------------------------------------------------------------
    wire lsb       = frac_ext[3];
    wire guard     = frac_ext[2];
    wire below     = frac_ext[1] | frac_ext[0] | sticky_all;
    wire round_up  = guard & (below | lsb);

    // Adding into the packed field lets the fraction carry ripple into the
    // exponent (subnormal -> normal, max normal -> infinity).
    wire [30:0] packed_mag = {exp_field, frac_ext[25:3]} + {30'd0, round_up};

    // ------------------------------------------------------------------------
    // Overflow saturation
    // ------------------------------------------------------------------------
    wire overflow = (exp > EXP_MAX_FINITE);

    assign y = overflow ? {sign, EXP_FIELD_INF, 23'd0} : {sign, packed_mag};

endmodule
`default_nettype wire
