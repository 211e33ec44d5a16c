`default_nettype none
`include "fp_defs.vh"
`include "fast_defs.vh"
// ============================================================================
// fast_fp_recip -- fp_recip (rtl/fp/fp_recip.v) pipelined: y = 1 / a,
// LATENCY = 18 for either METHOD
// ============================================================================
// fp_recip's datapath, step for step, one register between steps; bit for
// bit fp_recip's result for the same METHOD (FP_METHOD_EXACT: correctly
// rounded; FP_METHOD_FAST: the Newton estimate rounded directly, within
// 1 ULP). y appears 18 clock edges after a; a new a may enter every cycle.
// The fast method takes the same number of stages (its unused ones are
// delay), so that a processor's micro-ops all take one latency.
//
// For a mantissa m in (1, 2): Q = floor(2^27 / m) with 27 significant bits,
// and whether 2^27 / m is exact (fp_recip's header; golden::fp mirrors it):
//   1, 2, 3, 4. classify and normalize the mantissa (fast_fp_unpack)
//   5. the seed y0 ~ 1/m from the ROM (block RAM, registered read)
//   6. the ROM's output register
//   7. m * y0 (a DSP)
//   8. corr = 2 - m * y0
//   9. y0 * corr as two partial products (DSPs)
//   10. their sum: q, the estimate of Q (Q - 3 ..= Q)
//   11. (exact) M * q modulo 2^26, two partial products
//   12. their sum
//   13. the remainder 2^50 - M * q, exact in 26 bits (it is below 4M)
//   14. the remainder against M, 2M, 3M: ordered and equal
//   15. q stepped up by floor(rem / M), and the sticky bit rem != kM
//   16, 17, 18. round and pack (fast_fp_round), special results overriding
// ============================================================================
module fast_fp_recip #(
    parameter integer METHOD = `FP_METHOD_EXACT
) (
    input  wire        clk,
    input  wire [31:0] a,
    output wire [31:0] y
);

    // An unknown METHOD stops elaboration, naming it (fp_recip's rule).
    generate
        if (METHOD != `FP_METHOD_EXACT && METHOD != `FP_METHOD_FAST) begin : g_bad_method
            fp_error_METHOD_must_be_FP_METHOD_EXACT_or_FP_METHOD_FAST u_bad_method ();
        end
    endgenerate

    localparam integer SEED_BITS  = 12;  // seed table index bits
    localparam integer SEED_WIDTH = 16;  // seed fraction bits, entries in (0.5, 1)
    localparam integer SEED_SIZE  = 1 << SEED_BITS;
    localparam         EXACT      = (METHOD == `FP_METHOD_EXACT);

    // ------------------------------------------------------------------------
    // The seed ROM: fp_recip's table, by the same formula (golden::fp's
    // seed_entry mirrors it), filled at time 0, read at the clock edge.
    // ------------------------------------------------------------------------
    function [SEED_WIDTH-1:0] seed_entry(input integer index);
        reg [63:0] d;
        reg [63:0] v_unused_hi;  // only the low SEED_WIDTH bits are ever set
        begin
            d = (64'd1 << (SEED_BITS + 1)) + 64'd2 * index + 64'd1;
            v_unused_hi = (((64'd1 << (SEED_WIDTH + SEED_BITS + 2)) / d) + 64'd1) >> 1;
            seed_entry = v_unused_hi[SEED_WIDTH-1:0];
        end
    endfunction

    reg [SEED_WIDTH-1:0] seed_rom [0:SEED_SIZE-1];
    integer seed_i;
    initial begin
        for (seed_i = 0; seed_i < SEED_SIZE; seed_i = seed_i + 1) begin
            seed_rom[seed_i] = seed_entry(seed_i);
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
    wire        n_special   = n_nan | n_inf | n_zero;
    wire [31:0] n_special_y = n_nan ? 32'h7FC0_0000
                            : n_inf ? {n_sign, 31'd0}
                            : {n_sign, 8'hFF, 23'd0};

    // ------------------------------------------------------------------------
    // Stage 5: the seed; the result's exponent 253 - e
    // ------------------------------------------------------------------------
    reg        [SEED_WIDTH-1:0] s5_seed_rom;
    reg        [23:0]           s5_man;
    reg                         s5_pow2;
    reg signed [11:0]           s5_exp;
    always @(posedge clk) begin
        s5_seed_rom <= seed_rom[n_man[22:23-SEED_BITS]];
        s5_man  <= n_man;
        s5_pow2 <= (n_man[22:0] == 23'd0);
        s5_exp  <= 12'sd253 - n_exp;
    end
    // What waits beside the datapath until stage 15.
    wire        w_sign, w_special, w_pow2;
    wire [31:0] w_special_y;
    wire signed [11:0] w_exp;
    reg  [33:0] s5_side;
    always @(posedge clk) s5_side <= {n_sign, n_special, n_special_y};
    fast_delay #(.WIDTH(47), .STAGES(9)) u_side14 (
        .clk(clk), .d({s5_side, s5_pow2, s5_exp}), .q({w_sign, w_special, w_special_y, w_pow2, w_exp})
    );

    // ------------------------------------------------------------------------
    // Stage 6: the seed out of the ROM's output register (a multiplier fed
    // by a block RAM's unregistered output was ECP5's longest path)
    // ------------------------------------------------------------------------
    reg [SEED_WIDTH-1:0] s6_seed;
    reg [23:0]           s6_man;
    always @(posedge clk) begin
        s6_seed <= s5_seed_rom;
        s6_man  <= s5_man;
    end

    // ------------------------------------------------------------------------
    // Stage 7: m * y0; 3M for stage 14
    // ------------------------------------------------------------------------
    reg [SEED_WIDTH+23:0] s7_m_y0;
    reg [SEED_WIDTH-1:0]  s7_seed;
    reg [25:0]            s7_man_x3;
    always @(posedge clk) begin
        s7_m_y0   <= s6_man * s6_seed;
        s7_seed   <= s6_seed;
        s7_man_x3 <= {2'b00, s6_man} + {1'b0, s6_man, 1'b0};
    end

    // ------------------------------------------------------------------------
    // Stage 8: corr = 2 - m*y0, 32 bits (fraction 30)
    // ------------------------------------------------------------------------
    wire [SEED_WIDTH+24:0] two_m_y0 = (41'd1 << (SEED_WIDTH + 24)) - {1'b0, s7_m_y0};
    reg  [31:0]            s8_corr;
    reg  [SEED_WIDTH-1:0]  s8_seed;
    always @(posedge clk) begin
        s8_corr <= two_m_y0[SEED_WIDTH+24:SEED_WIDTH-7];
        s8_seed <= s7_seed;
    end
    wire unused_corr = ^two_m_y0[SEED_WIDTH-8:0];

    // ------------------------------------------------------------------------
    // Stage 9: y0 * corr, partial products of corr's low 17 and high 15 bits
    // ------------------------------------------------------------------------
    reg [SEED_WIDTH+16:0] s9_lo;
    reg [SEED_WIDTH+14:0] s9_hi;
    always @(posedge clk) begin
        s9_lo <= s8_seed * s8_corr[16:0];
        s9_hi <= s8_seed * s8_corr[31:17];
    end

    // ------------------------------------------------------------------------
    // Stage 10: q, bits 45..19 of y0 * corr
    // ------------------------------------------------------------------------
    wire [SEED_WIDTH+31:0] y0_corr = {15'd0, s9_lo} + {s9_hi, 17'd0};
    reg  [26:0]            s10_q;
    always @(posedge clk) s10_q <= y0_corr[SEED_WIDTH+29:SEED_WIDTH+3];
    wire unused_y0_corr = ^{y0_corr[SEED_WIDTH+31:SEED_WIDTH+30], y0_corr[SEED_WIDTH+2:0]};

    // M and 3M wait for stage 14 (M from stage 5, 3M from stage 7), M also
    // for stage 11.
    wire [23:0] w_man;
    wire [25:0] w_man_x3;
    fast_delay #(.WIDTH(24), .STAGES(8)) u_man (.clk(clk), .d(s5_man), .q(w_man));
    fast_delay #(.WIDTH(26), .STAGES(6)) u_man_x3 (.clk(clk), .d(s7_man_x3), .q(w_man_x3));
    wire [23:0] m_man;  // M beside stage 11, for M * q
    fast_delay #(.WIDTH(24), .STAGES(5)) u_man10 (.clk(clk), .d(s5_man), .q(m_man));

    // ------------------------------------------------------------------------
    // Stages 11 to 15
    // ------------------------------------------------------------------------
    reg        [26:0] s15_sig;
    reg signed [11:0] s15_exp;
    reg               s15_sticky;
    wire       [26:0] w_q;  // q beside stage 15
    fast_delay #(.WIDTH(27), .STAGES(4)) u_q (.clk(clk), .d(s10_q), .q(w_q));

    generate
        if (EXACT) begin : g_exact
            // Stage 11: M * q modulo 2^26 (the remainder's bits), as
            // M * q[16:0] and M * q[25:17] modulo 2^9.
            reg [40:0] s11_lo;
            reg [8:0]  s11_hi;
            always @(posedge clk) begin
                s11_lo <= m_man * s10_q[16:0];
                s11_hi <= m_man[8:0] * s10_q[25:17];
            end
            wire unused_lo = ^s11_lo[40:26];
            // Stage 12: their sum.
            reg [25:0] s12_mq;
            always @(posedge clk) s12_mq <= s11_lo[25:0] + {s11_hi, 17'd0};
            // Stage 13: rem = 2^50 - M*q: below 4M < 2^26, so its low 26
            // bits are all of it, and those are -(M*q) modulo 2^26.
            reg [25:0] s13_rem;
            always @(posedge clk) s13_rem <= 26'd0 - s12_mq;
            // Stage 14: rem against M, 2M, 3M.
            wire [25:0] man_x1 = {2'b00, w_man};
            wire [25:0] man_x2 = {1'b0, w_man, 1'b0};
            reg         s14_ge1, s14_ge2, s14_ge3, s14_eq0, s14_eq1, s14_eq2, s14_eq3;
            always @(posedge clk) begin
                s14_ge1 <= (s13_rem >= man_x1);
                s14_ge2 <= (s13_rem >= man_x2);
                s14_ge3 <= (s13_rem >= w_man_x3);
                s14_eq0 <= (s13_rem == 26'd0);
                s14_eq1 <= (s13_rem == man_x1);
                s14_eq2 <= (s13_rem == man_x2);
                s14_eq3 <= (s13_rem == w_man_x3);
            end
            // Stage 15: q + floor(rem / M), sticky = the remainder left != 0.
            reg  [1:0] steps;
            reg        rest_zero;
            always @* begin
                if (s14_ge3) begin
                    steps = 2'd3;
                    rest_zero = s14_eq3;
                end else if (s14_ge2) begin
                    steps = 2'd2;
                    rest_zero = s14_eq2;
                end else if (s14_ge1) begin
                    steps = 2'd1;
                    rest_zero = s14_eq1;
                end else begin
                    steps = 2'd0;
                    rest_zero = s14_eq0;
                end
            end
            always @(posedge clk) begin
                s15_sig    <= w_pow2 ? 27'h400_0000 : w_q + {25'd0, steps};
                s15_sticky <= !w_pow2 && !rest_zero;
            end
        end else begin : g_fast
            wire unused_exact = ^{m_man, w_man, w_man_x3};
            always @(posedge clk) begin
                s15_sig    <= w_pow2 ? 27'h400_0000 : w_q;
                s15_sticky <= 1'b0;
            end
        end
    endgenerate

    // A power of two (m = 1) is exact, and 2^27 / m would not fit in 27
    // bits: 2^26 one exponent up.
    always @(posedge clk) s15_exp <= w_pow2 ? w_exp + 12'sd1 : w_exp;
    reg        s15_sign, s15_special;
    reg [31:0] s15_special_y;
    always @(posedge clk) begin
        s15_sign      <= w_sign;
        s15_special   <= w_special;
        s15_special_y <= w_special_y;
    end

    // ------------------------------------------------------------------------
    // Stages 16, 17, 18: round and pack
    // ------------------------------------------------------------------------
    fast_fp_round u_round (
        .clk    (clk),
        .sign   (s15_sign),
        .exp    (s15_exp),
        .sig    (s15_sig),
        .sticky (s15_sticky),
        .ovr    (s15_special),
        .ovr_y  (s15_special_y),
        .y      (y)
    );

endmodule
`default_nettype wire
