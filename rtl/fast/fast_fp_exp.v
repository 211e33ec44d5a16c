`default_nettype none
`include "fast_defs.vh"
// ============================================================================
// fast_fp_exp -- fp_exp (rtl/fp/fp_exp.v) pipelined: y = e^a, LATENCY = 20
// ============================================================================
// fp_exp's datapath, step for step, with registers between steps (docs/
// fast.md); bit for bit fp_exp's result (golden::fp::exp): NaN ->
// 32'h7FC00000, -inf and a <= -103.98 -> +0, +inf and a >= 88.73 -> +inf,
// +-0 -> 1.0, subnormal results. y appears 20 clock edges after a; a new a
// may enter every cycle. fp_exp's five steps, each cut into stages of a few
// LUT levels or one carry chain:
//
//   1. classify (NaN, |a| >= 128: the special result); fp_exp's X =
//      |a| * 2^32 (truncated) as M' * 2^s, M' the mantissa and s = e - 118
//      in 0..15 (e >= 118), or M' the mantissa shifted right (truncated,
//      e < 118) and s = 0
//   2, 3, 4. M' * LOG2E without a multiplier: a signed-digit recoding of
//      LOG2E (16 digits), the positive and the negative digits' shifted
//      copies of M' summed in two registered adder trees (3 levels); for a
//      negative a the negative tree also takes 2^m, m = 40 - s (below)
//   5. the two trees' difference, its carry out of bit 25
//   6. ... and bits 65..25: for a >= 0, R = Pos - Neg = M' * LOG2E; for
//      a < 0, R = Neg + 2^m - Pos - 1 = 2^m - 1 - M' * LOG2E
//   7. t = R >>> m (bits 65..25 shifted by 15 - s): for a >= 0 fp_exp's
//      floor(X * LOG2E / 2^40), for a < 0 its negation (the ceiling of the
//      negated value, hence the 2^m - 1); k = t[40:32], f = t[31:0], and
//      g = f[23:0]
//   8. u = ln2 + g * ln2^2/2, its constant product as
//      2^32 ln2 + g 2^30 - g (2^25 + 2^23 + 2^15 + 2^10 + 1): level 1;
//      the table T[f[31:24]] read (block RAM, registered read)
//   9. level 2; the ROM's output register
//   10. U1 - U2 (level 2's two sums): the borrow of the low 32 bits
//   11. ... and bits 63..32: u
//   12. g * u, as g * u[16:0] and g * u[31:17] (a DSP48E1 each)
//   13. their sum: p - 1 = g * u / 2^32, 24 bits
//   14. T * (p - 1), as T[16:0] * (p - 1) and T[30:17] * (p - 1) (DSPs)
//   15. their sum
//   16. s = T * 2^32 + T * (p - 1): bits 63..32 (one 32-bit add; the low
//       32 bits are the sum's own) and the OR of the low 32 bits
//   17. normalize: s in [1, 2] with 62 fraction bits, 27 bits and a
//       sticky; the exponent k + 127 (+1 when s >= 2)
//   18, 19, 20. round and pack (fast_fp_round), the special result
//       overriding
//
// T[i] = round(2^(i/256) * 2^30), 256 entries computed at elaboration with
// the real ** operator, as fp_exp does (golden::fp repeats it). The only
// multipliers are the two variable products, each two DSP48E1-sized
// (at most 25 x 18) partial products between registers: 4 DSP48E1.
// ============================================================================
module fast_fp_exp (
    input  wire        clk,
    input  wire [31:0] a,
    output wire [31:0] y
);

    localparam integer TABLE_BITS = 8;    // f[31:24]: index of T
    localparam integer TABLE_FRAC = 30;   // fraction bits of a T entry
    localparam [31:0]  LN2        = 32'hB172_17F8;  // round(ln 2 * 2^32)
    // ln(2)^2/2 * 2^32 rounded = 32'h3D7F_7BFF = 2^30 - 2^25 - 2^23 - 2^15 - 2^10 - 1.
    // LOG2E = 41'h171_5476_52B8 = round(log2(e) * 2^40)
    //       = 2^41 + 2^32 + 2^30 + 2^28 + 2^26 + 2^23 + 2^14 + 2^12 + 2^10
    //       - 2^39 - 2^36 - 2^19 - 2^17 - 2^8 - 2^6 - 2^3.

    // ------------------------------------------------------------------------
    // The table: fp_exp's, round(2^(index/256) * 2^30) in IEEE double at
    // elaboration; entries in [2^30, 2^31). Filled at time 0, read at the
    // clock edge (block RAM).
    // ------------------------------------------------------------------------
    function integer table_entry(input integer index);
        table_entry = $rtoi((2.0 ** (index / 256.0)) * 1073741824.0 + 0.5);
    endfunction

    // 256 x 31 bits: without the attribute Yosys maps so small a ROM to
    // LUTs on Virtex-6 (about 110 more, MUXF7/8 trees); in block RAM it
    // takes one RAMB18 (one DP16KD on ECP5, attribute or not).
    (* rom_style = "block" *)
    reg [TABLE_FRAC:0] table_rom [0:(1 << TABLE_BITS)-1];
    integer table_i;
    reg [31:0] table_v_unused_hi;  // entries are below 2^31
    initial begin
        for (table_i = 0; table_i < (1 << TABLE_BITS); table_i = table_i + 1) begin
            table_v_unused_hi = table_entry(table_i);
            table_rom[table_i] = table_v_unused_hi[TABLE_FRAC:0];
        end
    end

    // ------------------------------------------------------------------------
    // Stage 1: classify; M', the shifts
    // ------------------------------------------------------------------------
    wire        in_sign  = a[31];
    wire [7:0]  in_field = a[30:23];
    wire [22:0] in_frac  = a[22:0];
    wire [23:0] in_man   = {in_field != 8'd0, in_frac};
    // e >= 118 (field 118 ..= 133 here; larger fields are special): M' is the
    // mantissa and s = field - 118, whose low 4 bits are field[3:0] - 6.
    // e < 118: X = man >> (118 - e), nonzero for field 95 ..= 117 only; for
    // field 96 ..= 117, 118 - field = 22 - field[4:0].
    wire        in_big   = (in_field >= 8'd118);
    wire [54:0] in_wide  = {31'd0, in_man} << in_field[4:0];
    wire        unused_wide = ^{in_wide[54:46], in_wide[21:0]};
    reg  [23:0] in_m;
    always @* begin
        if (in_big)
            in_m = in_man;
        else if (in_field[7:5] == 3'b011)
            in_m = in_wide[45:22];
        else if (in_field == 8'd95)
            in_m = 24'd1;  // man >> 23, man[23] = 1
        else
            in_m = 24'd0;
    end
    // j = 15 - s, the final shift; m = 25 + j.
    wire [3:0]  in_j     = in_big ? (4'd5 - in_field[3:0]) : 4'd15;

    reg        [23:0] s1_m;
    reg        [3:0]  s1_j;
    reg               s1_sign, s1_special;
    reg        [15:0] s1_em;       // 2^m >> 25 for a negative a, else 0
    reg        [31:0] s1_special_y;
    always @(posedge clk) begin
        s1_m         <= in_m;
        s1_j         <= in_j;
        s1_sign      <= in_sign;
        s1_em        <= in_sign ? (16'd1 << in_j) : 16'd0;
        s1_special   <= (in_field == 8'hFF && in_frac != 23'd0) || (in_field >= 8'd134);
        s1_special_y <= (in_field == 8'hFF && in_frac != 23'd0) ? 32'h7FC0_0000
                      : in_sign ? 32'h0000_0000 : 32'h7F80_0000;
    end

    // ------------------------------------------------------------------------
    // Stages 2, 3, 4: the two trees of M' * LOG2E's digits
    // ------------------------------------------------------------------------
    // Level 1: pairs; two copies 24 bits or more apart are one term (no
    // overlap, no adder).
    wire [23:0] m1 = s1_m;
    reg  [64:0] s2_p1;
    reg  [47:0] s2_p2;
    reg  [52:0] s2_p3;
    reg  [56:0] s2_p4;
    reg  [59:0] s2_n1;
    reg  [63:0] s2_n2;
    reg  [43:0] s2_n3;
    always @(posedge clk) begin
        s2_p1 <= {m1, 7'd0, m1, 10'd0} + {29'd0, m1, 12'd0};
        s2_p2 <= {10'd0, m1, 14'd0} + {1'd0, m1, 23'd0};
        s2_p3 <= {3'd0, m1, 26'd0} + {1'd0, m1, 28'd0};
        s2_p4 <= {3'd0, m1, 30'd0} + {1'd0, m1, 32'd0};
        s2_n1 <= {m1, 9'd0, m1, 3'd0} + {28'd0, m1, 8'd0};
        s2_n2 <= {1'd0, m1, 9'd0, m1, 6'd0} + {23'd0, m1, 17'd0};
        s2_n3 <= {1'd0, m1, 19'd0} + {3'd0, s1_em, 25'd0};
    end

    // Level 2.
    reg [65:0] s3_p12;
    reg [56:0] s3_p34;
    reg [63:0] s3_n12;
    reg [43:0] s3_n3;
    always @(posedge clk) begin
        s3_p12 <= {1'd0, s2_p1} + {18'd0, s2_p2};
        s3_p34 <= {4'd0, s2_p3} + s2_p4;
        s3_n12 <= {4'd0, s2_n1} + s2_n2;
        s3_n3  <= s2_n3;
    end

    // Level 3: Pos and Neg (+ 2^m for a negative a).
    reg [65:0] s4_pos;
    reg [63:0] s4_neg;
    always @(posedge clk) begin
        s4_pos <= s3_p12 + {9'd0, s3_p34};
        s4_neg <= s3_n12 + {20'd0, s3_n3};
    end

    wire [3:0] w4_j;
    wire       w4_sign;
    fast_delay #(.WIDTH(5), .STAGES(3)) u_sign4 (
        .clk(clk), .d({s1_sign, s1_j}), .q({w4_sign, w4_j})
    );

    // ------------------------------------------------------------------------
    // Stage 5: R = A + ~B + c (mod 2^66): A - B for a >= 0 (c = 1), A - B - 1
    // for a < 0 (c = 0), with A, B = Pos, Neg or Neg, Pos; the carry out of
    // bit 25
    // ------------------------------------------------------------------------
    wire [65:0] d_a  = w4_sign ? {2'd0, s4_neg} : s4_pos;
    wire [65:0] d_nb = ~(w4_sign ? s4_pos : {2'd0, s4_neg});
    wire [26:0] d_lo = {1'b0, d_a[24:0], 1'b1} + {1'b0, d_nb[24:0], ~w4_sign};
    reg  [40:0] s5_a_hi, s5_nb_hi;
    reg         s5_c;
    reg  [3:0]  s5_j;
    always @(posedge clk) begin
        s5_a_hi  <= d_a[65:25];
        s5_nb_hi <= d_nb[65:25];
        s5_c     <= d_lo[26];
        s5_j     <= w4_j;
    end
    wire unused_d_lo = ^d_lo[25:0];

    // ------------------------------------------------------------------------
    // Stage 6: R's bits 65..25
    // ------------------------------------------------------------------------
    wire [41:0] r_sum = {s5_a_hi, 1'b1} + {s5_nb_hi, s5_c};
    reg  [40:0] s6_r;
    reg  [3:0]  s6_j;
    always @(posedge clk) begin
        s6_r <= r_sum[41:1];
        s6_j <= s5_j;
    end
    wire unused_r_sum = r_sum[0];

    // ------------------------------------------------------------------------
    // Stage 7: t = R >>> m: k, f
    // ------------------------------------------------------------------------
    wire signed [40:0] r_signed = s6_r;
    wire        [40:0] t        = r_signed >>> s6_j;
    reg signed  [8:0]  s7_k;
    reg         [7:0]  s7_hi;
    reg         [23:0] s7_g;
    always @(posedge clk) begin
        s7_k  <= t[40:32];
        s7_hi <= t[31:24];
        s7_g  <= t[23:0];
    end

    // ------------------------------------------------------------------------
    // Stages 8 to 11: u = ln2 + g * ln2^2/2 (32 fraction bits); the table
    // ------------------------------------------------------------------------
    // Level 1: T1 = 2^32 ln2 + g 2^30, T2 = g (2^25 + 2^23),
    // T3 = g (2^15 + 2^10); the table's read.
    reg  [63:0]         s8_t1;
    reg  [49:0]         s8_t2;
    reg  [39:0]         s8_t3;
    reg  [23:0]         s8_g;
    reg  [TABLE_FRAC:0] s8_table;
    always @(posedge clk) begin
        s8_t1    <= {LN2, 32'd0} + {10'd0, s7_g, 30'd0};
        s8_t2    <= {1'd0, s7_g, 25'd0} + {3'd0, s7_g, 23'd0};
        s8_t3    <= {1'd0, s7_g, 15'd0} + {6'd0, s7_g, 10'd0};
        s8_g     <= s7_g;
        s8_table <= table_rom[s7_hi];
    end

    // Level 2: U1 = T1 - T2, U2 = T3 + g; the ROM's output register.
    reg  [63:0]         s9_u1;
    reg  [40:0]         s9_u2;
    reg  [TABLE_FRAC:0] s9_table;
    always @(posedge clk) begin
        s9_u1    <= s8_t1 - {14'd0, s8_t2};
        s9_u2    <= {1'd0, s8_t3} + {17'd0, s8_g};
        s9_table <= s8_table;
    end

    // Stage 10: the borrow of U1 - U2 out of bit 32.
    wire [32:0] u_lo = {1'b0, s9_u1[31:0]} - {1'b0, s9_u2[31:0]};
    reg  [31:0] s10_u1_hi;
    reg  [8:0]  s10_u2_hi;
    reg         s10_borrow;
    always @(posedge clk) begin
        s10_u1_hi  <= s9_u1[63:32];
        s10_u2_hi  <= s9_u2[40:32];
        s10_borrow <= u_lo[32];
    end
    wire unused_u_lo = ^u_lo[31:0];

    // Stage 11: u = (U1 - U2) >> 32 = U1_hi + ~U2_hi + (1 - borrow).
    wire [32:0] u_sum = {s10_u1_hi, 1'b1} + {~{23'd0, s10_u2_hi}, ~s10_borrow};
    reg  [31:0] s11_u;
    always @(posedge clk) s11_u <= u_sum[32:1];
    wire unused_u_sum = u_sum[0];

    wire [23:0] w11_g;
    fast_delay #(.WIDTH(24), .STAGES(3)) u_g11 (.clk(clk), .d(s8_g), .q(w11_g));

    // ------------------------------------------------------------------------
    // Stage 12: g * u, two partial products (a DSP48E1 each)
    // ------------------------------------------------------------------------
    reg [40:0] s12_lo;  // g * u[16:0]
    reg [38:0] s12_hi;  // g * u[31:17]
    always @(posedge clk) begin
        s12_lo <= {17'd0, w11_g} * {24'd0, s11_u[16:0]};
        s12_hi <= {15'd0, w11_g} * {24'd0, s11_u[31:17]};
    end

    // ------------------------------------------------------------------------
    // Stage 13: p - 1 = (g * u) >> 32 = ((lo >> 17) + hi) >> 15
    // ------------------------------------------------------------------------
    wire [38:0] gu_hi = {15'd0, s12_lo[40:17]} + s12_hi;
    reg  [23:0] s13_pl;
    always @(posedge clk) s13_pl <= gu_hi[38:15];
    wire unused_gu = ^{s12_lo[16:0], gu_hi[14:0]};

    wire [TABLE_FRAC:0] w13_table;
    fast_delay #(.WIDTH(TABLE_FRAC + 1), .STAGES(4)) u_table13 (
        .clk(clk), .d(s9_table), .q(w13_table)
    );

    // ------------------------------------------------------------------------
    // Stage 14: T * (p - 1), two partial products (DSPs)
    // ------------------------------------------------------------------------
    reg [40:0] s14_lo;  // T[16:0] * (p - 1)
    reg [37:0] s14_hi;  // T[30:17] * (p - 1)
    always @(posedge clk) begin
        s14_lo <= {24'd0, w13_table[16:0]} * {17'd0, s13_pl};
        s14_hi <= {24'd0, w13_table[30:17]} * {14'd0, s13_pl};
    end

    // ------------------------------------------------------------------------
    // Stage 15: q = T * (p - 1), below 2^55
    // ------------------------------------------------------------------------
    wire [37:0] q_hi = {14'd0, s14_lo[40:17]} + s14_hi;
    reg  [54:0] s15_q;
    always @(posedge clk) s15_q <= {q_hi[37:0], s14_lo[16:0]};

    wire [TABLE_FRAC:0] w15_table;
    fast_delay #(.WIDTH(TABLE_FRAC + 1), .STAGES(2)) u_table15 (
        .clk(clk), .d(w13_table), .q(w15_table)
    );

    // ------------------------------------------------------------------------
    // Stage 16: s = T * 2^32 + q, 62 fraction bits: bits 63..32, and the
    // OR of bits 31..0
    // ------------------------------------------------------------------------
    reg [31:0] s16_s_hi;
    reg        s16_sticky_lo;
    always @(posedge clk) begin
        s16_s_hi      <= {1'b0, w15_table} + {9'd0, s15_q[54:32]};
        s16_sticky_lo <= |s15_q[31:0];
    end

    wire signed [8:0] w16_k;
    fast_delay #(.WIDTH(9), .STAGES(9)) u_k16 (.clk(clk), .d(s7_k), .q(w16_k));

    // ------------------------------------------------------------------------
    // Stage 17: normalize; the exponent
    // ------------------------------------------------------------------------
    wire s_two = s16_s_hi[31];  // s >= 2 only by rounding of the operands
    reg               s17_sticky;
    reg        [26:0] s17_sig;
    reg signed [11:0] s17_exp;
    always @(posedge clk) begin
        s17_sig    <= s_two ? s16_s_hi[31:5] : s16_s_hi[30:4];
        s17_sticky <= s16_sticky_lo | (s_two ? (|s16_s_hi[4:0]) : (|s16_s_hi[3:0]));
        s17_exp    <= {{3{w16_k[8]}}, w16_k} + (s_two ? 12'sd128 : 12'sd127);
    end

    wire        w17_special;
    wire [31:0] w17_special_y;
    fast_delay #(.WIDTH(33), .STAGES(16)) u_special17 (
        .clk(clk), .d({s1_special, s1_special_y}), .q({w17_special, w17_special_y})
    );

    // ------------------------------------------------------------------------
    // Stages 18, 19, 20: round and pack; the special result overrides
    // ------------------------------------------------------------------------
    fast_fp_round u_round (
        .clk    (clk),
        .sign   (1'b0),
        .exp    (s17_exp),
        .sig    (s17_sig),
        .sticky (s17_sticky),
        .ovr    (w17_special),
        .ovr_y  (w17_special_y),
        .y      (y)
    );

endmodule
`default_nettype wire
