`default_nettype none
`include "fp_defs.vh"
`include "fast_defs.vh"
// ============================================================================
// fast_fp_sqrt -- fp_sqrt (rtl/fp/fp_sqrt.v) pipelined: y = sqrt(a),
// LATENCY = 22 for either METHOD
// ============================================================================
// fp_sqrt's datapath, step for step, one register between steps; bit for
// bit fp_sqrt's result for the same METHOD (FP_METHOD_EXACT: correctly
// rounded; FP_METHOD_FAST: the Newton estimate rounded directly, within
// 1 ULP). y appears 22 clock edges after a; a new a may enter every cycle.
// The fast method takes the same number of stages (its unused ones delay).
//
// The operand is scaled to m' in [1, 4) so that its exponent is even; the
// unit finds Q = floor(sqrt(m') * 2^26) = isqrt(M' * 2^29) and whether it is
// exact (fp_sqrt's header; golden::fp mirrors it):
//   1, 2, 3, 4. classify and normalize the mantissa (fast_fp_unpack)
//   5. the exponent's parity, m', the result's exponent; the seed
//      y0 ~ 1/sqrt(m') from the ROM (block RAM, registered read)
//   6. the ROM's output register
//   7. y0^2 (a DSP)
//   8. m' * y0^2 as two partial products (DSPs)
//   9. their sum
//   10. h = 3 - m' * y0^2
//   11. y0 * h as two partial products
//   12. their sum: y1 = y0 * h / 2 ~ 1/sqrt(m')
//   13. m' * y1 as two partial products
//   14. their sum: q, clamped to >= 2^26 (Q - 1 ..= Q + 1)
//   15. (exact) q^2 modulo 2^30 as two partial products; 2q + 1, 1 - 2q
//   16. their sum
//   17. the remainder M' * 2^29 - q^2, exact in 30 bits (|rem| < 2^29)
//   18. the remainder's side of q (below, above q + 1/2's square) and
//       whether the remainder left after the move is 0
//   19. q moved by one where the remainder says so; the sticky bit
//   20, 21, 22. round and pack (fast_fp_round), special results overriding
// ============================================================================
module fast_fp_sqrt #(
    parameter integer METHOD = `FP_METHOD_EXACT
) (
    input  wire        clk,
    input  wire [31:0] a,
    output wire [31:0] y
);

    // An unknown METHOD stops elaboration, naming it (fp_sqrt's rule).
    generate
        if (METHOD != `FP_METHOD_EXACT && METHOD != `FP_METHOD_FAST) begin : g_bad_method
            fp_error_METHOD_must_be_FP_METHOD_EXACT_or_FP_METHOD_FAST u_bad_method ();
        end
    endgenerate

    localparam integer SEED_BITS  = 12;  // fraction bits indexing the seed table
    localparam integer SEED_WIDTH = 16;  // seed fraction bits, entries in (0.5, 1)
    localparam integer HALF_SIZE  = 1 << SEED_BITS;  // entries per exponent parity
    localparam         EXACT      = (METHOD == `FP_METHOD_EXACT);

    // ------------------------------------------------------------------------
    // The seed ROM: fp_sqrt's table, by the same double-precision formula
    // (golden::fp repeats it), indexed {odd, fraction}, filled at time 0,
    // read at the clock edge.
    // ------------------------------------------------------------------------
    function [SEED_WIDTH-1:0] seed_entry(input integer odd, input integer index);
        reg [31:0] v_unused_hi;  // only the low SEED_WIDTH bits are ever set
        begin
            v_unused_hi = $rtoi((1 << SEED_WIDTH)
                                / $sqrt((1.0 + (index + 0.5) / HALF_SIZE) * (odd + 1)) + 0.5);
            seed_entry = v_unused_hi[SEED_WIDTH-1:0];
        end
    endfunction

    reg [SEED_WIDTH-1:0] seed_rom [0:2*HALF_SIZE-1];
    integer seed_i;
    initial begin
        for (seed_i = 0; seed_i < 2 * HALF_SIZE; seed_i = seed_i + 1) begin
            seed_rom[seed_i] = seed_entry(seed_i / HALF_SIZE, seed_i % HALF_SIZE);
        end
    end

    // ------------------------------------------------------------------------
    // Stages 1 to 4: classify and normalize (fast_fp_unpack); the results
    // that skip the datapath
    // ------------------------------------------------------------------------
    wire               n_sign, n_nan, n_inf, n_zero;
    wire signed [11:0] n_exp;
    wire        [23:0] n_man;
    fast_fp_unpack u_unpack (
        .clk(clk), .a(a), .sign(n_sign), .is_nan(n_nan), .is_inf(n_inf), .is_zero(n_zero),
        .exp(n_exp), .man(n_man)
    );
    wire        n_special   = n_nan | n_zero | n_sign | n_inf;
    wire [31:0] n_special_y = n_nan ? 32'h7FC0_0000
                            : n_zero ? {n_sign, 31'd0}
                            : n_sign ? 32'h7FC0_0000
                            : 32'h7F80_0000;

    // ------------------------------------------------------------------------
    // Stage 5: parity, m', the exponent (e + 127) / 2; the seed
    // ------------------------------------------------------------------------
    // |a| = m * 2^(e - 127): the unbiased exponent is odd exactly when e is
    // even.
    wire               odd     = ~n_exp[0];
    wire signed [11:0] exp_sum = n_exp + 12'sd127;
    reg         [SEED_WIDTH-1:0] s5_seed_rom;
    reg         [23:0]           s5_man;   // M' = M << odd: m' in [1, 4)
    reg                          s5_odd;
    reg  signed [11:0]           s5_exp;
    reg                          s5_special;
    reg         [31:0]           s5_special_y;
    always @(posedge clk) begin
        s5_seed_rom  <= seed_rom[{odd, n_man[22:23-SEED_BITS]}];
        s5_man       <= n_man;
        s5_odd       <= odd;
        s5_exp       <= {exp_sum[11], exp_sum[11:1]};
        s5_special   <= n_special;
        s5_special_y <= n_special_y;
    end
    wire unused_exp_sum_lsb = exp_sum[0];  // (e + 127) / 2 drops it

    // The exponent and the special result wait until stage 19.
    wire signed [11:0] w_exp;
    wire               w_special;
    wire        [31:0] w_special_y;
    fast_delay #(.WIDTH(45), .STAGES(13)) u_side19 (
        .clk(clk), .d({s5_exp, s5_special, s5_special_y}), .q({w_exp, w_special, w_special_y})
    );
    // M, the parity and y0 beside the steps that use them again. A product
    // with m' is M's shifted by the parity: M (24 bits) fits a DSP48E1's
    // 25-bit signed port, M' (25) would take two DSPs a product.
    wire [23:0]           man_8, man_13;
    wire                  odd_9, odd_14;
    wire                  mp0_17;  // M' * 2^29 modulo 2^30: bit 0 of M' only
    wire [SEED_WIDTH-1:0] seed_11;
    fast_delay #(.WIDTH(24), .STAGES(2)) u_man8 (.clk(clk), .d(s5_man), .q(man_8));
    fast_delay #(.WIDTH(24), .STAGES(7)) u_man13 (.clk(clk), .d(s5_man), .q(man_13));
    fast_delay #(.WIDTH(1), .STAGES(3)) u_odd9 (.clk(clk), .d(s5_odd), .q(odd_9));
    fast_delay #(.WIDTH(1), .STAGES(8)) u_odd14 (.clk(clk), .d(s5_odd), .q(odd_14));
    fast_delay #(.WIDTH(1), .STAGES(11)) u_mp17 (
        .clk(clk), .d(!s5_odd && s5_man[0]), .q(mp0_17)
    );
    fast_delay #(.WIDTH(SEED_WIDTH), .STAGES(4)) u_seed11 (.clk(clk), .d(s6_seed), .q(seed_11));

    // ------------------------------------------------------------------------
    // Stage 6: the seed out of the ROM's output register (a multiplier fed
    // by a block RAM's unregistered output is ECP5's longest path)
    // ------------------------------------------------------------------------
    reg [SEED_WIDTH-1:0] s6_seed;
    always @(posedge clk) s6_seed <= s5_seed_rom;

    // ------------------------------------------------------------------------
    // Stage 7: y0^2, fraction 32
    // ------------------------------------------------------------------------
    reg [2*SEED_WIDTH-1:0] s7_y0_sq;
    always @(posedge clk) s7_y0_sq <= s6_seed * s6_seed;

    // ------------------------------------------------------------------------
    // Stages 8, 9: t = m' * y0^2
    // ------------------------------------------------------------------------
    reg [40:0] s8_lo;  // M * y0^2[16:0]
    reg [38:0] s8_hi;  // M * y0^2[31:17]
    always @(posedge clk) begin
        s8_lo <= man_8 * s7_y0_sq[16:0];
        s8_hi <= man_8 * s7_y0_sq[31:17];
    end
    // t = m' * y0^2 = (M * y0^2) << odd; its bits 56..23 (fraction 32).
    wire [55:0] m_y0_sq = {15'd0, s8_lo} + {s8_hi, 17'd0};
    reg  [33:0] s9_t;
    always @(posedge clk) s9_t <= odd_9 ? m_y0_sq[55:22] : {1'b0, m_y0_sq[55:23]};
    wire unused_t = ^m_y0_sq[21:0];

    // ------------------------------------------------------------------------
    // Stage 10: h = 3 - m' * y0^2, fraction 32, near 2
    // ------------------------------------------------------------------------
    reg [33:0] s10_h;
    always @(posedge clk) s10_h <= (34'd3 << 32) - s9_t;

    // ------------------------------------------------------------------------
    // Stages 11, 12: y1 = y0 * h / 2
    // ------------------------------------------------------------------------
    reg [SEED_WIDTH+16:0] s11_lo;  // y0 * h[16:0]
    reg [SEED_WIDTH+16:0] s11_hi;  // y0 * h[33:17]
    always @(posedge clk) begin
        s11_lo <= seed_11 * s10_h[16:0];
        s11_hi <= seed_11 * s10_h[33:17];
    end
    wire [SEED_WIDTH+33:0] y0_h = {17'd0, s11_lo} + {s11_hi, 17'd0};
    reg  [32:0]            s12_y1;  // fraction 32
    always @(posedge clk) s12_y1 <= y0_h[SEED_WIDTH+33:SEED_WIDTH+1];
    wire unused_y0_h = ^y0_h[SEED_WIDTH:0];

    // ------------------------------------------------------------------------
    // Stages 13, 14: q = m' * y1, clamped
    // ------------------------------------------------------------------------
    reg [40:0] s13_lo;  // M * y1[16:0]
    reg [39:0] s13_hi;  // M * y1[32:17]
    always @(posedge clk) begin
        s13_lo <= man_13 * s12_y1[16:0];
        s13_hi <= man_13 * s12_y1[32:17];
    end
    // m' * y1 = (M * y1) << odd; q is its bits 55..29.
    wire [56:0] m_y1  = {16'd0, s13_lo} + {s13_hi, 17'd0};
    wire [26:0] q_est = odd_14 ? m_y1[54:28] : m_y1[55:29];
    reg  [26:0] s14_q;
    // sqrt(m') >= 1, so Q >= 2^26; only m' = 1 undershoots, to 2^26 - 1.
    always @(posedge clk) s14_q <= q_est[26] ? q_est : 27'h400_0000;
    wire unused_s = ^{m_y1[56], m_y1[27:0]};

    // ------------------------------------------------------------------------
    // Stages 15 to 19
    // ------------------------------------------------------------------------
    wire [26:0] q_18;  // q beside stage 19
    fast_delay #(.WIDTH(27), .STAGES(4)) u_q (.clk(clk), .d(s14_q), .q(q_18));
    reg [26:0] s19_sig;
    reg        s19_sticky;

    generate
        if (EXACT) begin : g_exact
            // Stage 15: q^2 modulo 2^30 from q = qh * 2^17 + ql: ql^2, and
            // qh * ql modulo 2^12 (2 qh ql 2^17 keeps 12 bits of it); the
            // bounds the remainder is checked against.
            reg [33:0]        s15_ll;
            reg [11:0]        s15_hl;
            reg signed [29:0] s15_two_q_p1, s15_one_m_two_q;
            always @(posedge clk) begin
                s15_ll          <= s14_q[16:0] * s14_q[16:0];
                s15_hl          <= s14_q[26:17] * s14_q[11:0];
                s15_two_q_p1    <= $signed({2'b00, s14_q, 1'b1});
                s15_one_m_two_q <= 30'sd1 - $signed({2'b00, s14_q, 1'b0});
            end
            wire unused_ll = ^s15_ll[33:30];
            // Stage 16: their sum.
            reg [29:0] s16_q_sq;
            always @(posedge clk) s16_q_sq <= s15_ll[29:0] + {s15_hl, 1'b0, 17'd0};
            // Stage 17: rem = M' * 2^29 - q^2, whose low 30 bits are all of
            // it (|rem| < 2^29), two's complement.
            reg signed [29:0] s17_rem;
            always @(posedge clk) s17_rem <= $signed({mp0_17, 29'd0} - s16_q_sq);
            // Stage 18: below (q too big), above (q too small; rem > 2q),
            // and whether the remainder after the move is 0.
            wire signed [29:0] two_q_p1, one_m_two_q;
            fast_delay #(.WIDTH(60), .STAGES(2)) u_bounds (
                .clk(clk), .d({s15_two_q_p1, s15_one_m_two_q}), .q({two_q_p1, one_m_two_q})
            );
            reg s18_below, s18_above, s18_zero_below, s18_zero_above, s18_zero;
            always @(posedge clk) begin
                s18_below      <= s17_rem < 30'sd0;
                s18_above      <= s17_rem >= two_q_p1;           // rem > 2q
                s18_zero_below <= s17_rem == one_m_two_q;        // rem + 2q - 1 = 0
                s18_zero_above <= s17_rem == two_q_p1;           // rem - 2q - 1 = 0
                s18_zero       <= s17_rem == 30'sd0;
            end
            // Stage 19: q moved by one; sticky = the remainder left != 0.
            always @(posedge clk) begin
                s19_sig    <= s18_below ? q_18 - 27'd1 : s18_above ? q_18 + 27'd1 : q_18;
                s19_sticky <= s18_below ? !s18_zero_below
                            : s18_above ? !s18_zero_above
                            : !s18_zero;
            end
        end else begin : g_fast
            wire unused_exact = mp0_17;
            always @(posedge clk) begin
                s19_sig    <= q_18;
                s19_sticky <= 1'b0;
            end
        end
    endgenerate

    reg signed [11:0] s19_exp;
    reg               s19_special;
    reg        [31:0] s19_special_y;
    always @(posedge clk) begin
        s19_exp       <= w_exp;
        s19_special   <= w_special;
        s19_special_y <= w_special_y;
    end

    // ------------------------------------------------------------------------
    // Stages 20, 21, 22: round and pack
    // ------------------------------------------------------------------------
    fast_fp_round u_round (
        .clk    (clk),
        .sign   (1'b0),
        .exp    (s19_exp),
        .sig    (s19_sig),
        .sticky (s19_sticky),
        .ovr    (s19_special),
        .ovr_y  (s19_special_y),
        .y      (y)
    );

endmodule
`default_nettype wire
