`default_nettype none
`include "fp_defs.vh"
// ============================================================================
// fp_sqrt -- binary32 square root y = sqrt(a), multi-cycle
// ============================================================================
// Handshake: a is sampled on the rising edge where in_valid is high and the
// unit is idle (in_valid while busy is ignored). out_valid is high for one
// cycle, 7 edges later (FP_METHOD_EXACT) or 6 (FP_METHOD_FAST); y holds the
// result until the next one. golden::fp::sqrt_latency states the same.
//
// The operand is scaled to m' in [1, 4) so that the exponent is even
// (m' = m, or 2m when the unbiased exponent is odd). The unit finds
// Q = floor(sqrt(m') * 2^26) = isqrt(M' * 2^29) and whether it is exact:
//   seed    y0 ~ 1/sqrt(m'), table indexed by parity and 12 fraction bits
//   sq      y0^2
//   half    h = 3 - m' * y0^2                 (one Newton-Raphson step for
//   step    y1 = y0 * h / 2                    the reciprocal square root)
//   est     q = m' * y1, clamped to >= 2^26   (lands in Q-1 ..= Q+1)
//   rem     M' * 2^29 - q^2, exact            (FP_METHOD_EXACT only)
//   round   FAST: round q directly (<= 1 ULP); EXACT: move q by one where the
//           remainder says so and round with sticky = (remainder != 0).
// golden::fp::sqrt_datapath mirrors this datapath register by register.
// ============================================================================
module fp_sqrt #(
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

    localparam integer SEED_BITS  = 12;  // fraction bits indexing the seed table
    localparam integer SEED_WIDTH = 16;  // seed fraction bits, entries in (0.5, 1)
    localparam integer STEP_FRAC  = 32;  // fraction bits kept of m'*y0^2 and y1
    localparam integer HALF_SIZE  = 1 << SEED_BITS;  // entries per exponent parity

    localparam [2:0] S_IDLE  = 3'd0,  // wait for in_valid; unpack, look up the seed
                     S_SQ    = 3'd1,  // y0^2
                     S_HALF  = 3'd2,  // h = 3 - m' * y0^2
                     S_STEP  = 3'd3,  // y1 = y0 * h / 2
                     S_EST   = 3'd4,  // q = m' * y1
                     S_REM   = 3'd5,  // rem = M' * 2^29 - q^2 (exact method only)
                     S_ROUND = 3'd6;  // correct, round, pack, raise out_valid

    // ------------------------------------------------------------------------
    // Seed table: round(2^SEED_WIDTH / sqrt(m_mid)) for each interval's
    // midpoint, evaluated at elaboration in IEEE double (golden::fp repeats the
    // same double operations). An integer square-root loop would be exact too,
    // but Verilator takes ~30 s to elaborate 8192 of them; $sqrt takes none.
    // ------------------------------------------------------------------------
    function [SEED_WIDTH-1:0] seed_entry(input integer odd, input integer index);
        reg [31:0] v_unused_hi;  // only the low SEED_WIDTH bits are ever set
        begin
            v_unused_hi = $rtoi((1 << SEED_WIDTH)
                                / $sqrt((1.0 + (index + 0.5) / HALF_SIZE) * (odd + 1)) + 0.5);
            seed_entry = v_unused_hi[SEED_WIDTH-1:0];
        end
    endfunction

    // Index {odd, fraction}. A ROM, filled once at time 0 (the standard FPGA
    // ROM-init idiom: Yosys turns the loop into the memory's initial contents,
    // simulators run it) and read only at the clock edge, into seed_q: block
    // RAM, not logic.
    reg [SEED_WIDTH-1:0] seed_rom [0:2*HALF_SIZE-1];
    integer seed_i;
    initial begin
        for (seed_i = 0; seed_i < 2 * HALF_SIZE; seed_i = seed_i + 1) begin
            seed_rom[seed_i] = seed_entry(seed_i / HALF_SIZE, seed_i % HALF_SIZE);
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

    // |a| = m * 2^(e - 127): the unbiased exponent is odd exactly when e is even.
    wire               in_odd = ~in_exp[0];
    wire signed [10:0] in_exp_sum = {in_exp[9], in_exp} + 11'sd127;
    wire               unused_exp_sum_lsb = in_exp_sum[0];  // (e + 127) / 2 drops it

    // Results that skip the datapath, decided at the input.
    reg        special_d;
    reg [31:0] special_y_d;
    always @* begin
        special_d   = 1'b1;
        special_y_d = 32'h7FC0_0000;
        if (in_nan) begin
            special_y_d = 32'h7FC0_0000;
        end else if (in_zero) begin
            special_y_d = {in_sign, 31'd0};
        end else if (in_sign) begin
            special_y_d = 32'h7FC0_0000;
        end else if (in_inf) begin
            special_y_d = 32'h7F80_0000;
        end else begin
            special_d = 1'b0;
        end
    end

    // ------------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------------
    reg        [2:0]            state_q, state_d;
    reg                         special_q, out_valid_q;
    reg        [31:0]           special_y_q, y_q;
    reg signed [11:0]           exp_q;      // biased result exponent (e + 127) / 2
    reg        [24:0]           mp_q;       // M', m' in [1, 4) with 23 fraction bits
    reg        [SEED_WIDTH-1:0] seed_q;
    reg        [31:0]           y0_sq_q;    // y0^2, fraction 32
    reg        [STEP_FRAC+1:0]  h_q;        // 3 - m'*y0^2, near 2
    reg        [STEP_FRAC:0]    y1_q;       // near 1/sqrt(m'), fraction STEP_FRAC
    reg        [26:0]           q_q;        // estimate of isqrt(M' * 2^29)
    reg signed [29:0]           rem_q;      // M' * 2^29 - q^2, |rem| < 2^29

    // ------------------------------------------------------------------------
    // Datapath: one multiplication per cycle
    // ------------------------------------------------------------------------
    wire [2*SEED_WIDTH-1:0]            y0_sq    = seed_q * seed_q;
    wire [2*SEED_WIDTH+24:0]           t_full   = mp_q * y0_sq_q;
    wire [STEP_FRAC+1:0]               h_full   = (34'd3 << STEP_FRAC) - t_full[2*SEED_WIDTH+24:23];
    wire [SEED_WIDTH+STEP_FRAC+1:0]    y0_h     = seed_q * h_q;
    wire [STEP_FRAC+25:0]              s_full   = mp_q * y1_q;
    wire [26:0]                        q_est    = s_full[STEP_FRAC+23:29];
    wire [53:0]                        q_sq     = q_q * q_q;
    wire [54:0]                        rem_full = {1'b0, mp_q, 29'd0} - {1'b0, q_sq};

    wire unused_datapath = ^{t_full[22:0], y0_h[16:0], s_full[STEP_FRAC+25:STEP_FRAC+24],
                             s_full[28:0], rem_full[54:30]};

    // Exact method: the estimate is within one of Q.
    wire [27:0]        two_q = {q_q, 1'b0};
    reg  [26:0]        q_fixed;
    reg  signed [29:0] rem_fixed;
    always @* begin
        if (rem_q < 30'sd0) begin
            q_fixed   = q_q - 27'd1;
            rem_fixed = rem_q + $signed({2'b00, two_q}) - 30'sd1;
        end else if (rem_q > $signed({2'b00, two_q})) begin
            q_fixed   = q_q + 27'd1;
            rem_fixed = rem_q - $signed({2'b00, two_q}) - 30'sd1;
        end else begin
            q_fixed   = q_q;
            rem_fixed = rem_q;
        end
    end

    // ------------------------------------------------------------------------
    // Round and pack
    // ------------------------------------------------------------------------
    wire        exact_method = (METHOD == `FP_METHOD_EXACT);
    wire [31:0] rounded;

    fp_round u_round (
        .sign   (1'b0),
        .exp    (exp_q),
        .sig    (exact_method ? q_fixed : q_q),
        .sticky (exact_method && (rem_fixed != 30'sd0)),
        .y      (rounded)
    );

    // ------------------------------------------------------------------------
    // Controller
    // ------------------------------------------------------------------------
    always @* begin
        state_d = state_q;
        case (state_q)
            S_IDLE:  if (in_valid) state_d = S_SQ;
            S_SQ:    state_d = S_HALF;
            S_HALF:  state_d = S_STEP;
            S_STEP:  state_d = S_EST;
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
                special_q   <= special_d;
                special_y_q <= special_y_d;
                exp_q       <= {{2{in_exp_sum[10]}}, in_exp_sum[10:1]};
                mp_q        <= in_odd ? {in_man, 1'b0} : {1'b0, in_man};
                seed_q      <= seed_rom[{in_odd, in_man[22:23-SEED_BITS]}];
            end
            S_SQ:   y0_sq_q <= y0_sq;
            S_HALF: h_q     <= h_full;
            S_STEP: y1_q    <= y0_h[SEED_WIDTH+STEP_FRAC+1:SEED_WIDTH+1];
            // sqrt(m') >= 1, so Q >= 2^26; only m' = 1 undershoots, to 2^26 - 1.
            S_EST:  q_q     <= q_est[26] ? q_est : 27'h400_0000;
            S_REM:  rem_q   <= rem_full[29:0];
            default: ;
        endcase
    end

    assign out_valid = out_valid_q;
    assign y         = y_q;

endmodule
`default_nettype wire
