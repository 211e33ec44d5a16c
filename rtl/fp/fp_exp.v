`default_nettype none
// ============================================================================
// fp_exp -- binary32 exponential y = e^a, multi-cycle
// ============================================================================
// Handshake as fp_recip / fp_sqrt: a is sampled on the rising edge where
// in_valid is high and the unit is idle (in_valid while busy is ignored).
// out_valid is high for one cycle LATENCY = 5 edges later, whatever the
// operand; y holds the result until the next one. golden::fp::exp_latency
// states the same. One multiplication per cycle:
//
//   S_IDLE   unpack; |a| as fixed point X, 32 fraction bits (truncated);
//            NaN, infinities and |a| >= 128 are decided here
//   S_RED    t = +-(X * log2(e)): k = floor(t), f = t - k in [0, 1)
//   S_POLY   u = ln2 + g * ln2^2/2            (g = low 24 bits of f, < 2^-8)
//   S_POW    p = 1 + g * u ~ 2^g               (the cubic term < 2^-28.2 dropped)
//   S_ROUND  s = T[f_hi] * p ~ 2^f in [1, 2]; normalize, round at exponent
//            k + 127 through fp_round (subnormals, underflow to +0, overflow
//            to +inf), raise out_valid
//
// T[i] = round(2^(i/256) * 2^30), 256 entries computed at elaboration with
// the real ** operator (the C library's pow), as golden::fp repeats.
// Not correctly rounded: within 1 ULP of e^a rounded to nearest for every
// input (measured over all 2^32 inputs, docs/fp.md). Every input has a
// defined result: NaN -> 0x7FC00000, -inf -> +0, +-0 -> 1.0, a <= -103.98 ->
// +0, a >= 88.73 -> +inf (positive inputs are computed, not saturated).
// golden::fp::exp (golden/src/fp/exp.rs) mirrors this datapath bit for bit.
// ============================================================================
module fp_exp (
    input  wire        clk,
    input  wire        rst_n,
    input  wire        in_valid,
    input  wire [31:0] a,
    output wire        out_valid,
    output wire [31:0] y
);

    localparam integer LATENCY    = 5;   // in_valid edge to out_valid (golden::fp::exp_latency)
    localparam integer X_FRAC     = 32;  // fraction bits of X = |a|
    localparam integer LOG2E_FRAC = 40;  // fraction bits of LOG2E
    localparam integer T_FRAC     = 32;  // fraction bits of t and f
    localparam integer TABLE_BITS = 8;   // f_hi: index of T
    localparam integer TABLE_FRAC = 30;  // fraction bits of a T entry
    localparam integer LO_BITS    = T_FRAC - TABLE_BITS;  // g = f_lo
    localparam integer X_E0_INT   = 150 - X_FRAC;        // field whose ulp is 2^-X_FRAC
    localparam [7:0]   X_E0       = X_E0_INT[7:0];

    localparam [40:0] LOG2E       = 41'h171_5476_52B8;  // round(log2(e) * 2^40)
    localparam [31:0] LN2         = 32'hB172_17F8;      // round(ln 2 * 2^32)
    localparam [31:0] LN2_SQ_HALF = 32'h3D7F_7BFF;      // round(ln(2)^2 / 2 * 2^32)

    localparam integer STATES = 5;  // S_IDLE .. S_ROUND, one edge each
    localparam [2:0] S_IDLE  = 3'd0,
                     S_RED   = 3'd1,
                     S_POLY  = 3'd2,
                     S_POW   = 3'd3,
                     S_ROUND = 3'd4;

    // ------------------------------------------------------------------------
    // Table: round(2^(index/256) * 2^TABLE_FRAC), in IEEE double at
    // elaboration; entries lie in [2^30, 2^31).
    // ------------------------------------------------------------------------
    function integer table_entry(input integer index);
        table_entry = $rtoi((2.0 ** (index / 256.0)) * 1073741824.0 + 0.5);
    endfunction

    wire [TABLE_FRAC:0] table_rom [0:(1 << TABLE_BITS)-1];
    genvar gi;
    generate
        for (gi = 0; gi < (1 << TABLE_BITS); gi = gi + 1) begin : g_table
            localparam integer ENTRY = table_entry(gi);
            assign table_rom[gi] = ENTRY[TABLE_FRAC:0];
        end
    endgenerate

    // ------------------------------------------------------------------------
    // Input stage
    // ------------------------------------------------------------------------
    wire        in_sign  = a[31];
    wire [7:0]  in_field = a[30:23];
    wire [22:0] in_frac  = a[22:0];
    wire [23:0] in_man   = {in_field != 8'd0, in_frac};
    // |a| = man * 2^(e - 150), e = max(field, 1); X = |a| * 2^32 = man * 2^(e - 118).
    wire [7:0]  in_e     = (in_field == 8'd0) ? 8'd1 : in_field;
    wire [38:0] x_left   = {15'd0, in_man} << (in_e - X_E0);   // e >= 118: at most 15
    wire [23:0] x_right  = in_man >> (X_E0 - in_e);            // e < 118
    wire [38:0] in_x     = (in_e >= X_E0) ? x_left : {15'd0, x_right};

    // Results that skip the datapath, decided at the input.
    reg        special_d;
    reg [31:0] special_y_d;
    always @* begin
        special_d   = 1'b1;
        special_y_d = 32'h7FC0_0000;
        if (in_field == 8'hFF && in_frac != 23'd0) begin
            special_y_d = 32'h7FC0_0000;             // NaN
        end else if (in_field >= 8'd134) begin       // |a| >= 128, infinities included
            special_y_d = in_sign ? 32'h0000_0000 : 32'h7F80_0000;
        end else begin
            special_d = 1'b0;
        end
    end

    // ------------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------------
    reg        [2:0]          state_q, state_d;
    reg                       special_q, out_valid_q;
    reg        [31:0]         special_y_q, y_q;
    reg                       sign_q;
    reg        [38:0]         x_q;      // |a|, 32 fraction bits
    reg signed [8:0]          k_q;      // floor(t), -185 ..= 184
    reg        [T_FRAC-1:0]   f_q;      // t - k, 32 fraction bits
    reg        [32:0]         u_q;      // ln2 + g ln2^2/2, 32 fraction bits
    reg        [32:0]         p_q;      // 1 + g u, 32 fraction bits

    // ------------------------------------------------------------------------
    // Datapath
    // ------------------------------------------------------------------------
    wire [79:0]         xl_full  = x_q * LOG2E;
    wire [39:0]         t_mag    = xl_full[79:LOG2E_FRAC];  // |t| < 185
    wire [40:0]         t_signed = sign_q ? (41'd0 - {1'b0, t_mag}) : {1'b0, t_mag};
    wire [LO_BITS-1:0]  g        = f_q[LO_BITS-1:0];
    wire [55:0]         gc2      = g * LN2_SQ_HALF;
    wire [32:0]         u_next   = {1'b0, LN2} + {9'd0, gc2[55:32]};
    wire [56:0]         gu       = g * u_q;
    wire [32:0]         p_next   = 33'h1_0000_0000 + {8'd0, gu[56:32]};
    wire [TABLE_FRAC:0] t_entry  = table_rom[f_q[T_FRAC-1:LO_BITS]];
    wire [63:0]         s        = t_entry * p_q;

    // s has 62 fraction bits; 2 only by rounding of the operands.
    wire               s_two  = s[63];
    wire [26:0]        sig    = s_two ? s[63:37] : s[62:36];
    wire               sticky = s_two ? (|s[36:0]) : (|s[35:0]);
    wire signed [11:0] exp_b  = {{3{k_q[8]}}, k_q} + (s_two ? 12'sd128 : 12'sd127);

    wire unused_datapath = ^{xl_full[LOG2E_FRAC-1:0], gc2[31:0], gu[31:0]};

    wire [31:0] rounded;

    fp_round u_round (
        .sign   (1'b0),
        .exp    (exp_b),
        .sig    (sig),
        .sticky (sticky),
        .y      (rounded)
    );

    // ------------------------------------------------------------------------
    // Controller
    // ------------------------------------------------------------------------
    always @* begin
        state_d = state_q;
        case (state_q)
            S_IDLE:  if (in_valid) state_d = S_RED;
            S_RED:   state_d = S_POLY;
            S_POLY:  state_d = S_POW;
            S_POW:   state_d = S_ROUND;
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
                sign_q      <= in_sign;
                x_q         <= in_x;
            end
            S_RED: begin
                k_q <= t_signed[40:T_FRAC];
                f_q <= t_signed[T_FRAC-1:0];
            end
            S_POLY: u_q <= u_next;
            S_POW:  p_q <= p_next;
            default: ;
        endcase
    end

    assign out_valid = out_valid_q;
    assign y         = y_q;

    // The schedule above (S_IDLE .. S_ROUND, one edge each) must take
    // LATENCY edges: otherwise elaboration stops on a module that does not
    // exist, naming the mismatch.
    generate
        if (STATES != LATENCY) begin : g_bad_latency
            fp_error_fp_exp_schedule_does_not_take_LATENCY_cycles u_bad_latency ();
        end
    endgenerate

endmodule
`default_nettype wire
