`default_nettype none
`include "fp_defs.vh"
// ============================================================================
// fp_recip -- binary32 reciprocal y = 1 / a, multi-cycle
// ============================================================================
// Handshake: a is sampled on the rising edge where in_valid is high and the
// unit is idle (in_valid while busy is ignored). out_valid is high for one
// cycle, 5 edges later (FP_METHOD_EXACT) or 4 (FP_METHOD_FAST); y holds the
// result until the next one. golden::fp::recip_latency states the same.
//
// For a mantissa m in (1, 2) the unit finds Q = floor(2^27 / m) (24 kept bits,
// a guard bit and two more) and whether 2^27 / m is exact:
//   seed    y0 ~ 1/m from a 2^SEED_BITS-entry table (relative error ~2^-13)
//   corr    2 - m*y0                       (one Newton-Raphson step ...)
//   est     q = y0 * (2 - m*y0)            (... lands in Q-3 ..= Q)
//   rem     2^50 - M*q, exact              (FP_METHOD_EXACT only)
//   round   FAST: round q directly (<= 1 ULP); EXACT: step q up by
//           floor(rem / M) and round with sticky = (remainder != 0), which is
//           correctly rounded, subnormal results included.
// golden::fp::recip_datapath mirrors this datapath register by register.
// ============================================================================
module fp_recip #(
    parameter integer METHOD = `FP_METHOD_EXACT
) (
    input  wire        clk,
    input  wire        rst_n,
    input  wire        in_valid,
    input  wire [31:0] a,
    output wire        out_valid,
    output wire [31:0] y
);

    // ------------------------------------------------------------------------
    // METHOD must name a method: any other value would run as the fast one.
    // An unknown value instantiates a module that does not exist, so every
    // simulator and synthesis tool stops at elaboration, naming it.
    // ------------------------------------------------------------------------
    generate
        if (METHOD != `FP_METHOD_EXACT && METHOD != `FP_METHOD_FAST) begin : g_bad_method
            fp_error_METHOD_must_be_FP_METHOD_EXACT_or_FP_METHOD_FAST u_bad_method ();
        end
    endgenerate

    localparam integer SEED_BITS  = 12;  // seed table index bits
    localparam integer SEED_WIDTH = 16;  // seed fraction bits, entries in (0.5, 1)
    localparam integer CORR_FRAC  = 30;  // fraction bits kept of 2 - m*y0
    localparam integer SEED_SIZE  = 1 << SEED_BITS;

    localparam [2:0] S_IDLE  = 3'd0,  // wait for in_valid; unpack, look up the seed
                     S_CORR  = 3'd1,  // corr = 2 - m*y0
                     S_EST   = 3'd2,  // q = y0 * corr
                     S_REM   = 3'd3,  // rem = 2^50 - M*q (exact method only)
                     S_ROUND = 3'd4;  // correct, round, pack, raise out_valid

    // ------------------------------------------------------------------------
    // Seed table: round(2^SEED_WIDTH / m_mid) for each interval's midpoint,
    // computed in integers at elaboration (golden::fp mirrors the formula).
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

    // A ROM, filled once at time 0 (the standard FPGA ROM-init idiom: Yosys
    // turns the loop into the memory's initial contents, simulators run it)
    // and read only at the clock edge, into seed_q: block RAM, not logic.
    reg [SEED_WIDTH-1:0] seed_rom [0:SEED_SIZE-1];
    integer seed_i;
    initial begin
        for (seed_i = 0; seed_i < SEED_SIZE; seed_i = seed_i + 1) begin
            seed_rom[seed_i] = seed_entry(seed_i);
        end
    end

    // ------------------------------------------------------------------------
    // Input stage
    // ------------------------------------------------------------------------
    wire              in_sign, in_nan, in_inf, in_zero;
    wire signed [9:0] in_exp;
    wire       [23:0] in_man;

    fp_unpack u_unpack (
        .a       (a),
        .sign    (in_sign),
        .is_nan  (in_nan),
        .is_inf  (in_inf),
        .is_zero (in_zero),
        .exp     (in_exp),
        .man     (in_man)
    );

    // Results that skip the datapath, decided at the input.
    reg        special_d;
    reg [31:0] special_y_d;
    always @* begin
        special_d   = 1'b1;
        special_y_d = {in_sign, 31'd0};
        if (in_nan) begin
            special_y_d = 32'h7FC0_0000;
        end else if (in_inf) begin
            special_y_d = {in_sign, 31'd0};
        end else if (in_zero) begin
            special_y_d = {in_sign, 8'hFF, 23'd0};
        end else begin
            special_d = 1'b0;
        end
    end

    // ------------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------------
    reg        [2:0]            state_q, state_d;
    reg                         sign_q, special_q, pow2_q, out_valid_q;
    reg        [31:0]           special_y_q, y_q;
    reg signed [11:0]           exp_q;      // biased result exponent 253 - e
    reg        [23:0]           man_q;
    reg        [SEED_WIDTH-1:0] seed_q;
    reg        [CORR_FRAC+1:0]  corr_q;     // 2 - m*y0, in (1 - 2^-12, 1 + 2^-12)
    reg        [26:0]           q_q;        // estimate of floor(2^27 / m)
    reg        [25:0]           rem_q;      // 2^50 - M*q, below 4*M < 2^26

    // ------------------------------------------------------------------------
    // Datapath: one multiplication per cycle
    // ------------------------------------------------------------------------
    wire [SEED_WIDTH+23:0]            m_y0     = man_q * seed_q;
    wire [SEED_WIDTH+24:0]            two_m_y0 = (41'd1 << (SEED_WIDTH + 24)) - {1'b0, m_y0};
    wire [SEED_WIDTH+CORR_FRAC+1:0]   y0_corr  = seed_q * corr_q;
    wire [50:0]                       m_q      = man_q * q_q;
    wire [50:0]                       rem_full = (51'd1 << 50) - m_q;

    wire unused_datapath = ^{two_m_y0[SEED_WIDTH+22-CORR_FRAC:0],
                             y0_corr[SEED_WIDTH+CORR_FRAC+1:SEED_WIDTH+CORR_FRAC],
                             y0_corr[SEED_WIDTH+CORR_FRAC-28:0],
                             rem_full[50:26]};

    // Exact method: q + floor(rem / M), at most 3 steps (golden::fp measures
    // the estimate over all 2^23 mantissas).
    wire [25:0] man_x1 = {2'b00, man_q};
    wire [25:0] man_x2 = {1'b0, man_q, 1'b0};
    wire [25:0] man_x3 = man_x1 + man_x2;
    reg  [26:0] q_fixed;
    reg  [25:0] rem_fixed;
    always @* begin
        if (rem_q >= man_x3) begin
            q_fixed   = q_q + 27'd3;
            rem_fixed = rem_q - man_x3;
        end else if (rem_q >= man_x2) begin
            q_fixed   = q_q + 27'd2;
            rem_fixed = rem_q - man_x2;
        end else if (rem_q >= man_x1) begin
            q_fixed   = q_q + 27'd1;
            rem_fixed = rem_q - man_x1;
        end else begin
            q_fixed   = q_q;
            rem_fixed = rem_q;
        end
    end

    // ------------------------------------------------------------------------
    // Round and pack
    // ------------------------------------------------------------------------
    // A power of two (m = 1) is exact, and 2^27 / m would not fit in 27 bits.
    wire               exact_method = (METHOD == `FP_METHOD_EXACT);
    wire        [26:0] round_sig    = pow2_q ? 27'h400_0000 : (exact_method ? q_fixed : q_q);
    wire signed [11:0] round_exp    = pow2_q ? exp_q + 12'sd1 : exp_q;
    wire               round_sticky = exact_method && !pow2_q && (rem_fixed != 26'd0);
    wire        [31:0] rounded;

    fp_round u_round (
        .sign   (sign_q),
        .exp    (round_exp),
        .sig    (round_sig),
        .sticky (round_sticky),
        .y      (rounded)
    );

    // ------------------------------------------------------------------------
    // Controller
    // ------------------------------------------------------------------------
    always @* begin
        state_d = state_q;
        case (state_q)
            S_IDLE:  if (in_valid) state_d = S_CORR;
            S_CORR:  state_d = S_EST;
            S_EST:   state_d = exact_method ? S_REM : S_ROUND;
            S_REM:   state_d = S_ROUND;
            S_ROUND: state_d = S_IDLE;
            default: state_d = S_IDLE;
        endcase
    end

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            state_q     <= S_IDLE;
            out_valid_q <= 1'b0;
            y_q         <= 32'd0;
        end else begin
            state_q     <= state_d;
            out_valid_q <= (state_q == S_ROUND);
            if (state_q == S_ROUND) y_q <= special_q ? special_y_q : rounded;
        end
    end

    // Datapath registers need no reset: nothing reads them before S_IDLE loads them.
    always @(posedge clk) begin
        case (state_q)
            S_IDLE: if (in_valid) begin
                sign_q      <= in_sign;
                special_q   <= special_d;
                special_y_q <= special_y_d;
                pow2_q      <= (in_man[22:0] == 23'd0);
                exp_q       <= 12'sd253 - {{2{in_exp[9]}}, in_exp};
                man_q       <= in_man;
                seed_q      <= seed_rom[in_man[22:23-SEED_BITS]];
            end
            S_CORR: corr_q <= two_m_y0[SEED_WIDTH+23-CORR_FRAC+CORR_FRAC+1:SEED_WIDTH+23-CORR_FRAC];
            S_EST:  q_q    <= y0_corr[SEED_WIDTH+CORR_FRAC-1:SEED_WIDTH+CORR_FRAC-27];
            S_REM:  rem_q  <= rem_full[25:0];
            default: ;
        endcase
    end

    assign out_valid = out_valid_q;
    assign y         = y_q;

endmodule
`default_nettype wire
