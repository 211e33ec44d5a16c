`default_nettype none
`include "fp_defs.vh"
`include "isa.vh"
`include "alu_ctrl.vh"
`include "fast_defs.vh"
// ============================================================================
// fast_alu -- the fast processor's vector ALU: every opcode one pipeline,
//             one latency, a micro-op entering every cycle
// ============================================================================
// The compact ALU (rtl/pp/alu.v) computes a single-cycle opcode in one
// combinational cycle and holds the multi-cycle ones (RECIP, SQRT, ROOTS,
// EXP) for their unit's latency. This ALU computes the same function of the
// same isa.vh opcodes (golden::micro::alu is the spec of both, bit for bit)
// through the pipelined units of rtl/fast/, and every opcode takes the same
// LATENCY clock edges from in_* to out_*: results leave in the order their
// opcodes entered, so the register file needs one write port.
//
// Micro-ops of up to 2^CTX_BITS pixel contexts are interleaved. F, the
// internal register (thesis 4.2, eq. 30), is one per context, in a small
// memory addressed by the context: an opcode reads its context's F as it
// enters and writes it LATENCY - 1 edges later. The contract, which the
// barrel's issue rule keeps (docs/fast.md):
//
//   * a context's next opcode enters no earlier than the edge at which its
//     last one's result leaves (the edge after out_valid rose for it), so
//     it reads the F that opcode wrote;
//   * EXP (one fp_exp shared by the three lanes, fed x, y, z in three
//     consecutive cycles) may enter only while exp_ready is high: never
//     within two cycles of another EXP. With EXPOSURE = 0 there is no
//     fp_exp (a scene with exposure needs the other build) and EXP gives +0.
//
// Stages (edges after the opcode enters):
//   1        decode (alu_ctrl), operands and the context's F registered
//   2        operand selection: the multipliers' B lanes, the adders'
//            operands from A, B and F (NEG_B), the unary units' operands;
//            EXP's lanes queued for the shared fp_exp
//   3 ..     fast_fp_mul (then twice and NEG_MUL in one stage more),
//            fast_fp_add, fast_fp_itof, fast_fp_recip, fast_fp_sqrt and
//            fast_fp_exp (lanes x, y, z one edge apart, collected), each
//            result delayed to the slowest: edge ALIGN
//   ALIGN+1  F's next value (F_SEL) and the result (RES_SEL), registered;
//            F written to the context's entry
//   ALIGN+2  the result out, with its flags registered: y_neg (< 0: sign,
//            not zero, not NaN), y_pos (> 0), y_sign, lane by lane
// ============================================================================
module fast_alu #(
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT,
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT,
    parameter integer EXPOSURE     = 1,   // 1: fp_exp built (EXP computes e^A)
    parameter integer CTX_BITS     = 5    // 2^CTX_BITS contexts
) (
    input  wire                        clk,
    input  wire                        rst_n,
    input  wire                        in_valid,
    input  wire [CTX_BITS-1:0]         in_ctx,
    input  wire [`ISA_DIM_OP_BITS-1:0] in_op,
    input  wire [95:0]                 a,
    input  wire [95:0]                 b,
    input  wire [31:0]                 ix,
    input  wire [31:0]                 iy,
    output wire                        exp_ready,
    output wire                        out_valid,
    output wire [CTX_BITS-1:0]         out_ctx,
    output wire                        out_writes,  // the opcode writes the register file
    output wire [95:0]                 y,
    output wire [2:0]                  y_neg,
    output wire [2:0]                  y_pos,
    output wire [2:0]                  y_sign
);

    localparam [31:0] POS_ZERO = 32'd0;

    // Edges from the operands' selection (stage 2) to each result.
    localparam integer MUL_AT   = `FAST_MUL_LATENCY + 1;    // + twice, NEG_MUL
    localparam integer ADD_AT   = `FAST_ADD_LATENCY;
    localparam integer ITOF_AT  = `FAST_ITOF_LATENCY;
    localparam integer RECIP_AT = `FAST_RECIP_LATENCY;
    localparam integer SQRT_AT  = `FAST_SQRT_LATENCY;
    localparam integer EXP_AT   = (EXPOSURE != 0) ? `FAST_EXP_LATENCY + 3 : 0;  // z lane + collect
    function integer max2(input integer p, input integer q);
        max2 = (p > q) ? p : q;
    endfunction
    localparam integer UNITS_AT = max2(max2(max2(MUL_AT, ADD_AT), max2(ITOF_AT, RECIP_AT)),
                                       max2(SQRT_AT, EXP_AT));
    localparam integer ALIGN    = 2 + UNITS_AT;
    localparam integer LATENCY  = ALIGN + 2;   // golden::micro::alu::fast_latency
    // fast_defs.vh states it for the processor around the ALU.
    localparam integer STATED   = (EXPOSURE != 0) ? `FAST_ALU_LATENCY : `FAST_ALU_LATENCY_NOEXP;
    generate
        if (LATENCY != STATED) begin : g_latency_not_as_stated
            fast_alu_latency_differs_from_fast_defs u_error ();
        end
    endgenerate

    // ------------------------------------------------------------------------
    // Stage 1: decode, operands, the context's F
    // ------------------------------------------------------------------------
    wire [`ALU_CTRL_W-1:0] dec_ctrl;
    wire                   dec_writes;
    alu_ctrl u_decode (.op(in_op), .ctrl(dec_ctrl), .writes_rf(dec_writes));

    reg [95:0] f_mem [0:(1 << CTX_BITS)-1];  // F per context (distributed RAM)

    reg                   s1_writes;
    reg [CTX_BITS-1:0]    s1_ctx;
    reg [`ALU_CTRL_W-1:0] s1_ctrl;
    reg [95:0]            s1_a, s1_b, s1_f;
    reg [31:0]            s1_ix, s1_iy;

    always @(posedge clk) begin
        s1_writes <= dec_writes;
        s1_ctx    <= in_ctx;
        s1_ctrl   <= dec_ctrl;
        s1_a      <= a;
        s1_b      <= b;
        s1_f      <= f_mem[in_ctx];
        s1_ix     <= ix;
        s1_iy     <= iy;
    end

    // ------------------------------------------------------------------------
    // Stage 2: operand selection
    // ------------------------------------------------------------------------
    wire [1:0] b_lane_x = s1_ctrl[`ALU_CTRL_B_LANE_X];
    wire [1:0] b_lane_y = s1_ctrl[`ALU_CTRL_B_LANE_Y];
    wire [1:0] b_lane_z = s1_ctrl[`ALU_CTRL_B_LANE_Z];
    wire       neg_b    = s1_ctrl[`ALU_CTRL_NEG_B];
    wire       addx_a_f = s1_ctrl[`ALU_CTRL_ADDX_A_F];
    wire [1:0] addx_b   = s1_ctrl[`ALU_CTRL_ADDX_B];
    wire       addy_f   = s1_ctrl[`ALU_CTRL_ADDY_F];
    wire       unit_a_y = s1_ctrl[`ALU_CTRL_UNIT_A_Y];
    wire       s1_exp   = s1_ctrl[`ALU_CTRL_EXP];

    wire [31:0] a_x = s1_a[31:0];
    wire [31:0] a_y = s1_a[63:32];
    wire [31:0] a_z = s1_a[95:64];
    wire [31:0] f_x = s1_f[31:0];
    wire [31:0] f_y = s1_f[63:32];
    wire [31:0] f_z = s1_f[95:64];

    function [31:0] b_lane(input [1:0] lane, input [95:0] v);
        case (lane)
            `ALU_LANE_Y: b_lane = v[63:32];
            `ALU_LANE_Z: b_lane = v[95:64];
            default:     b_lane = v[31:0];
        endcase
    endfunction

    // A - B is fp_add with B's sign bit flipped (thesis 4.2).
    wire [31:0] bs_x = {s1_b[31] ^ neg_b, s1_b[30:0]};
    wire [31:0] bs_y = {s1_b[63] ^ neg_b, s1_b[62:32]};
    wire [31:0] bs_z = {s1_b[95] ^ neg_b, s1_b[94:64]};

    reg [31:0] add_x_b;
    always @* begin
        case (addx_b)
            `ALU_ADDX_B_FY: add_x_b = f_y;
            `ALU_ADDX_B_FZ: add_x_b = f_z;
            `ALU_ADDX_B_AY: add_x_b = a_y;
            default:        add_x_b = bs_x;
        endcase
    end

    reg [95:0] s2_mul_a, s2_mul_b, s2_add_a, s2_add_b;
    reg [31:0] s2_recip_a, s2_sqrt_a, s2_ix, s2_iy;
    always @(posedge clk) begin
        s2_mul_a   <= s1_a;
        s2_mul_b   <= {b_lane(b_lane_z, s1_b), b_lane(b_lane_y, s1_b), b_lane(b_lane_x, s1_b)};
        s2_add_a   <= {a_z, addy_f ? f_x : a_y, addx_a_f ? f_x : a_x};
        s2_add_b   <= {bs_z, addy_f ? f_z : bs_y, add_x_b};
        s2_recip_a <= unit_a_y ? a_y : a_x;
        s2_sqrt_a  <= a_x;
        s2_ix      <= s1_ix;
        s2_iy      <= s1_iy;
    end

    // What the last stages need besides the units' results, delayed to
    // them: the last stages' controls, the context, A (PASS, F = <.., A.z>)
    // and F.
    localparam integer SIDE_W = 1 + CTX_BITS + 9 + 96 + 96;
    wire                al_writes;
    wire [CTX_BITS-1:0] al_ctx;
    wire [2:0]          f_sel, res_sel;
    wire                neg_a, roots, al_exp;
    wire [95:0]         al_a, al_f;
    fast_delay #(.WIDTH(SIDE_W), .STAGES(ALIGN - 1)) u_side (
        .clk(clk),
        .d({s1_writes, s1_ctx, s1_ctrl[`ALU_CTRL_F_SEL], s1_ctrl[`ALU_CTRL_RES_SEL],
            s1_ctrl[`ALU_CTRL_NEG_A], s1_ctrl[`ALU_CTRL_ROOTS], s1_exp, s1_a, s1_f}),
        .q({al_writes, al_ctx, f_sel, res_sel, neg_a, roots, al_exp, al_a, al_f})
    );

    // The valid bits are reset (the datapath is not): LATENCY edges.
    reg [LATENCY-1:0] valid_q;
    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) valid_q <= {LATENCY{1'b0}};
        else        valid_q <= {valid_q[LATENCY-2:0], in_valid};
    end
    wire s1_valid_w = valid_q[0];
    wire al_valid   = valid_q[ALIGN-1];

    // ------------------------------------------------------------------------
    // Units, lane by lane; each result delayed to edge ALIGN
    // ------------------------------------------------------------------------
    // -(p * q) is the rounded product with its sign bit flipped (NaN too).
    // 2p, exactly p + p rounded: the exponent goes up by one; a subnormal's
    // bits shift left (into the exponent field if they carry); the largest
    // binade overflows to infinity; infinities and NaNs pass. (The compact
    // ALU's twice, rtl/pp/alu.v.)
    function [31:0] twice(input [31:0] p);
        begin
            if (p[30:23] == 8'hff)
                twice = p;
            else if (p[30:23] == 8'hfe)
                twice = {p[31], 8'hff, 23'd0};
            else if (p[30:23] == 8'h00)
                twice = {p[31], p[29:0], 1'b0};
            else
                twice = {p[31], p[30:23] + 8'd1, p[22:0]};
        end
    endfunction

    // The product's controls, delayed to the multipliers' results.
    wire mul_double, mul_neg;
    fast_delay #(.WIDTH(2), .STAGES(`FAST_MUL_LATENCY + 1)) u_mul_ctl (
        .clk(clk),
        .d({s1_ctrl[`ALU_CTRL_DOUBLE], s1_ctrl[`ALU_CTRL_NEG_MUL]}),
        .q({mul_double, mul_neg})
    );

    wire [95:0] prod, sum, prod_al, sum_al;
    reg  [95:0] prod_q;
    genvar gl;
    generate
        for (gl = 0; gl < 3; gl = gl + 1) begin : g_lane
            fast_fp_mul u_mul (
                .clk(clk), .a(s2_mul_a[32*gl +: 32]), .b(s2_mul_b[32*gl +: 32]),
                .y(prod[32*gl +: 32])
            );
            fast_fp_add u_add (
                .clk(clk), .a(s2_add_a[32*gl +: 32]), .b(s2_add_b[32*gl +: 32]),
                .y(sum[32*gl +: 32])
            );
            wire [31:0] scaled = mul_double ? twice(prod[32*gl +: 32]) : prod[32*gl +: 32];
            always @(posedge clk) prod_q[32*gl +: 32] <= {scaled[31] ^ mul_neg, scaled[30:0]};
        end
    endgenerate

    fast_delay #(.WIDTH(96), .STAGES(UNITS_AT - MUL_AT)) u_prod_al (
        .clk(clk), .d(prod_q), .q(prod_al)
    );
    fast_delay #(.WIDTH(96), .STAGES(UNITS_AT - ADD_AT)) u_sum_al (
        .clk(clk), .d(sum), .q(sum_al)
    );

    wire [31:0] itof_x, itof_y, itof_x_al, itof_y_al;
    fast_fp_itof u_itof_x (.clk(clk), .a(s2_ix), .y(itof_x));
    fast_fp_itof u_itof_y (.clk(clk), .a(s2_iy), .y(itof_y));
    fast_delay #(.WIDTH(64), .STAGES(UNITS_AT - ITOF_AT)) u_itof_al (
        .clk(clk), .d({itof_y, itof_x}), .q({itof_y_al, itof_x_al})
    );

    wire [31:0] recip_y, sqrt_y, recip_al, sqrt_al;
    fast_fp_recip #(.METHOD(RECIP_METHOD)) u_recip (.clk(clk), .a(s2_recip_a), .y(recip_y));
    fast_fp_sqrt #(.METHOD(SQRT_METHOD)) u_sqrt (.clk(clk), .a(s2_sqrt_a), .y(sqrt_y));
    fast_delay #(.WIDTH(32), .STAGES(UNITS_AT - RECIP_AT)) u_recip_al (
        .clk(clk), .d(recip_y), .q(recip_al)
    );
    fast_delay #(.WIDTH(32), .STAGES(UNITS_AT - SQRT_AT)) u_sqrt_al (
        .clk(clk), .d(sqrt_y), .q(sqrt_al)
    );

    // EXP: the lanes of A queue for the one fp_exp, x first; its results
    // are collected into a vector as they come out, one edge apart.
    wire [95:0] exp_al;
    generate
        if (EXPOSURE != 0) begin : g_exp
            reg  [95:0] queue_q;   // lane x: the unit's operand this cycle
            reg  [95:0] collect_q; // lane z: the newest result
            wire [31:0] exp_y;
            always @(posedge clk) begin
                queue_q   <= (s1_valid_w & s1_exp) ? s1_a : {POS_ZERO, queue_q[95:32]};
                collect_q <= {exp_y, collect_q[95:32]};
            end
            fast_fp_exp u_exp (.clk(clk), .a(queue_q[31:0]), .y(exp_y));
            fast_delay #(.WIDTH(96), .STAGES(UNITS_AT - EXP_AT)) u_exp_al (
                .clk(clk), .d(collect_q), .q(exp_al)
            );
            // EXP in stage 1 or entering stage 2's queue: the next may not enter.
            reg exp_busy_q;
            always @(posedge clk or negedge rst_n) begin
                if (!rst_n) exp_busy_q <= 1'b0;
                else        exp_busy_q <= s1_valid_w & s1_exp;
            end
            assign exp_ready = ~(s1_valid_w & s1_exp) & ~exp_busy_q;
        end else begin : g_no_exp
            assign exp_al    = {POS_ZERO, POS_ZERO, POS_ZERO};
            assign exp_ready = 1'b1;
            wire unused_exp = s1_valid_w & s1_exp;
        end
    endgenerate

    // ------------------------------------------------------------------------
    // Stage ALIGN + 1: F's next value and the result
    // ------------------------------------------------------------------------
    reg [95:0] f_d;
    always @* begin
        case (f_sel)
            `ALU_F_MUL:       f_d = prod_al;
            `ALU_F_SUM_X:     f_d = {al_f[95:32], sum_al[31:0]};
            `ALU_F_SUM_XY_AZ: f_d = {al_a[95:64], sum_al[63:0]};
            `ALU_F_SUM_XY_0:  f_d = {POS_ZERO, sum_al[63:0]};
            default:          f_d = al_f;
        endcase
    end

    always @(posedge clk) begin
        if (al_valid && f_sel != `ALU_F_HOLD) f_mem[al_ctx] <= f_d;
    end

    reg [95:0] result;
    always @* begin
        case (res_sel)
            `ALU_RES_SUM:   result = sum_al;
            `ALU_RES_MUL:   result = prod_al;
            `ALU_RES_PASS:  result = {al_a[95] ^ neg_a, al_a[94:64],
                                      al_a[63] ^ neg_a, al_a[62:32],
                                      al_a[31] ^ neg_a, al_a[30:0]};
            `ALU_RES_ITOF:  result = {POS_ZERO, itof_y_al, itof_x_al};
            `ALU_RES_F:     result = f_d;
            `ALU_RES_RECIP: result = {POS_ZERO, POS_ZERO, recip_al};
            `ALU_RES_SQRT:  result = {POS_ZERO, roots ? recip_al : POS_ZERO, sqrt_al};
            default:        result = {POS_ZERO, POS_ZERO, POS_ZERO};
        endcase
        if (al_exp) result = exp_al;
    end

    reg [95:0]         r_y;
    reg                r_writes;
    reg [CTX_BITS-1:0] r_ctx;
    always @(posedge clk) begin
        r_y      <= result;
        r_writes <= al_writes;
        r_ctx    <= al_ctx;
    end

    // ------------------------------------------------------------------------
    // Stage ALIGN + 2: the result and its flags
    // ------------------------------------------------------------------------
    reg [95:0]         o_y;
    reg                o_writes;
    reg [CTX_BITS-1:0] o_ctx;
    reg [2:0]          o_neg, o_pos, o_sign;
    integer li;
    always @(posedge clk) begin
        o_y      <= r_y;
        o_writes <= r_writes;
        o_ctx    <= r_ctx;
        for (li = 0; li < 3; li = li + 1) begin
            o_sign[li] <= r_y[32*li + 31];
            o_neg[li]  <= r_y[32*li + 31] & (|r_y[32*li +: 31])
                          & ~((&r_y[32*li + 23 +: 8]) & (|r_y[32*li +: 23]));
            o_pos[li]  <= ~r_y[32*li + 31] & (|r_y[32*li +: 31])
                          & ~((&r_y[32*li + 23 +: 8]) & (|r_y[32*li +: 23]));
        end
    end

    assign out_valid  = valid_q[LATENCY-1];
    assign out_ctx    = o_ctx;
    assign out_writes = o_writes;
    assign y          = o_y;
    assign y_neg      = o_neg;
    assign y_pos      = o_pos;
    assign y_sign     = o_sign;

endmodule
`default_nettype wire
