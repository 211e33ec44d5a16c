`default_nettype none
// ============================================================================
// fast_fp_round -- fp_round (rtl/fp/fp_round.v) in three registered stages
// ============================================================================
// The same contract as fp_round: the value presented is
// (-1)^sign * (sig / 2^26) * 2^(exp - 127), plus less than one unit of
// sig[0] when sticky, with sig[26] = 1; y is that value rounded to nearest,
// ties to even, and packed, subnormals and overflow to infinity included.
// One more input: when ovr is set, y is ovr_y instead (the caller's special
// case: zero, infinity, NaN), carried along so that the caller needs no
// delay line of its own for it.
//
// y appears LATENCY = 3 clock edges after the inputs; a new value may enter
// every cycle. No reset: the datapath carries no state of its own (the
// pipeline's valid bits live with the processor).
//
// Stages (each a few LUT levels or one short carry chain, for the fast
// processor's clock; docs/fast.md):
//   1. the exponent's class: tiny (exp <= 0), overflow (exp > 254) and the
//      denormalizing shift min(-exp, 26), from exp's low bits;
//      and the mask of the bits of sig that shift moves out (i <= shift);
//   2. the denormalizing shift of sig, and the sticky bit of what it shifts
//      out (the OR of sig under the mask, in parallel with the shift);
//   3. round to nearest even and the carry into the exponent field, then
//      overflow and the override.
// fp_round computes the same in one combinational step; the fast-unit test
// (fp-check) holds both to golden::fp bit for bit.
// ============================================================================
module fast_fp_round (
    input  wire               clk,
    input  wire               sign,
    input  wire signed [11:0] exp,
    input  wire        [26:0] sig,
    input  wire               sticky,
    input  wire               ovr,
    input  wire        [31:0] ovr_y,
    output reg         [31:0] y
);

    localparam signed [11:0] EXP_MAX_FINITE = 12'sd254;
    localparam signed [11:0] DENORM_MIN     = -12'sd26;  // exp below: shift saturates at 26
    localparam        [4:0]  SHIFT_MAX      = 5'd26;
    localparam        [7:0]  EXP_FIELD_INF  = 8'hFF;

    // ------------------------------------------------------------------------
    // Stage 1: classify the exponent
    // ------------------------------------------------------------------------
    // The true right shift is 1 - exp; {sig, 26'd0} sits one bit low, so the
    // shifter amount is -exp, i.e. the two's complement of exp's low five
    // bits while exp >= -26, else 26 (every bit of sig goes to the sticky).
    wire [4:0] neg_low = ~exp[4:0] + 5'd1;

    // The bits the shift moves out are sig[shift:0]: bit i is one of them
    // iff i <= shift, i.e. iff exp <= -i (the shift saturates at 26, and
    // bit 26 is the last). The mask is taken here from exp, in parallel with
    // the rest, so that stage 2 only ANDs and ORs.
    wire [26:0] out_mask;
    genvar i;
    generate
        for (i = 0; i < 27; i = i + 1) begin : g_out_mask
            assign out_mask[i] = (exp <= -i);
        end
    endgenerate

    reg               s1_sign, s1_sticky, s1_tiny, s1_overflow, s1_ovr;
    reg        [4:0]  s1_shift;
    reg        [7:0]  s1_exp_field;
    reg        [26:0] s1_sig, s1_out_mask;
    reg        [31:0] s1_ovr_y;

    always @(posedge clk) begin
        s1_sign      <= sign;
        s1_sticky    <= sticky;
        s1_tiny      <= (exp <= 12'sd0);
        s1_overflow  <= (exp > EXP_MAX_FINITE);
        s1_shift     <= (exp < DENORM_MIN) ? SHIFT_MAX : neg_low;
        s1_exp_field <= exp[7:0];
        s1_sig       <= sig;
        s1_out_mask  <= out_mask;
        s1_ovr       <= ovr;
        s1_ovr_y     <= ovr_y;
    end

    // ------------------------------------------------------------------------
    // Stage 2: denormalize
    // ------------------------------------------------------------------------
    // fp_round's {sig, 26'd0} >> shift keeps sig[26:shift+1] as the 26 bits
    // of frac_ext, i.e. sig[26:1] >> shift, and shifts sig[shift:0] out, into
    // the sticky: bit i of sig is shifted out iff i <= shift.
    wire [25:0] denorm_frac = s1_sig[26:1] >> s1_shift;
    wire        shifted_out = |(s1_sig & s1_out_mask);

    reg               s2_sign, s2_overflow, s2_sticky, s2_ovr;
    reg        [25:0] s2_frac_ext;   // {23 fraction bits, guard, two lower bits}
    reg        [7:0]  s2_exp_field;
    reg        [31:0] s2_ovr_y;

    always @(posedge clk) begin
        s2_sign      <= s1_sign;
        s2_overflow  <= s1_overflow;
        s2_frac_ext  <= s1_tiny ? denorm_frac : s1_sig[25:0];
        s2_sticky    <= s1_sticky | (s1_tiny & shifted_out);
        s2_exp_field <= s1_tiny ? 8'd0 : s1_exp_field;
        s2_ovr       <= s1_ovr;
        s2_ovr_y     <= s1_ovr_y;
    end

    // ------------------------------------------------------------------------
    // Stage 3: round to nearest, ties to even; pack
    // ------------------------------------------------------------------------
    // Adding into the packed field lets the fraction carry ripple into the
    // exponent (subnormal -> normal, max normal -> infinity).
    wire        round_up   = s2_frac_ext[2] & (s2_frac_ext[1] | s2_frac_ext[0] | s2_sticky
                                               | s2_frac_ext[3]);
    wire [30:0] packed_mag = {s2_exp_field, s2_frac_ext[25:3]} + {30'd0, round_up};

    always @(posedge clk) begin
        if (s2_ovr)
            y <= s2_ovr_y;
        else if (s2_overflow)
            y <= {s2_sign, EXP_FIELD_INF, 23'd0};
        else
            y <= {s2_sign, packed_mag};
    end

endmodule
`default_nettype wire
