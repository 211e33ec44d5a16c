`default_nettype none
`include "fp_defs.vh"
`include "alu_ctrl.vh"
// ============================================================================
// alu -- the pixel processor's vector ALU with its internal register F
// ============================================================================
// Three float32 lanes {z, y, x} (x = bits 31:0) and the controls of
// alu_ctrl.vh (thesis 4.2; golden::micro::alu is the spec, bit for bit):
//
//   lane i     one fp_mul: A.i * B.(B_LANE_i), sign flipped when NEG_MUL
//              one fp_add: x: (A.x | F.x) + (B.x | F.y | F.z | A.y)
//                          y: A.y + B.y, or F.x + F.z
//                          z: A.z + B.z
//              (B's sign bits flipped into the adders when NEG_B)
//   itof       lanes x and y convert ix and iy; lane z is +0
//   fp_recip   1 / A.x (1 / A.y when UNIT_A_Y), multi-cycle
//   fp_sqrt    sqrt(A.x), multi-cycle
//   fp_exp     e^A.i in each lane i (three units), multi-cycle
//   F          96-bit internal register (eq. 30), written at the edge ending
//              a cycle whose F_SEL is not HOLD
//
// Every single-cycle op is done in its cycle. RECIP, RECIPY and SQRT are held
// on ctrl by the controller until done: the unit's in_valid is raised only in
// the first cycle (busy_q clear), and done is the unit's out_valid, so the op
// takes the unit's latency + 1 cycles (golden::fp::recip_latency,
// sqrt_latency). Their result is <unit y, +0, +0>. ROOTS starts both units
// in its first cycle and is done when both results are in (max latency + 1
// cycles); its result is <sqrt y, recip y, +0>. EXP starts the three fp_exp
// units in its first cycle, which finish together (fp_exp latency + 1
// cycles: golden::fp::exp_latency); its result is <e^A.x, e^A.y, e^A.z>.
//
// The flags describe y, lane by lane, for the controller's branches:
// y_neg (< 0: sign, not zero, not NaN), y_pos (> 0) and the raw sign bit.
// ============================================================================
module alu #(
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT,
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT
) (
    input  wire                   clk,
    input  wire                   rst_n,
    input  wire [`ALU_CTRL_W-1:0] ctrl,
    input  wire [95:0]            a,
    input  wire [95:0]            b,
    input  wire [31:0]            ix,
    input  wire [31:0]            iy,
    output wire [95:0]            y,
    output wire                   done,
    output wire [2:0]             y_neg,
    output wire [2:0]             y_pos,
    output wire [2:0]             y_sign
);

    localparam [31:0] POS_ZERO = 32'd0;

    // ------------------------------------------------------------------------
    // Controls
    // ------------------------------------------------------------------------
    wire [1:0] b_lane_x = ctrl[`ALU_CTRL_B_LANE_X];
    wire [1:0] b_lane_y = ctrl[`ALU_CTRL_B_LANE_Y];
    wire [1:0] b_lane_z = ctrl[`ALU_CTRL_B_LANE_Z];
    wire       neg_b    = ctrl[`ALU_CTRL_NEG_B];
    wire       neg_mul  = ctrl[`ALU_CTRL_NEG_MUL];
    wire       neg_a    = ctrl[`ALU_CTRL_NEG_A];
    wire       addx_a_f = ctrl[`ALU_CTRL_ADDX_A_F];
    wire [1:0] addx_b   = ctrl[`ALU_CTRL_ADDX_B];
    wire       addy_f   = ctrl[`ALU_CTRL_ADDY_F];
    wire [2:0] f_sel    = ctrl[`ALU_CTRL_F_SEL];
    wire [2:0] res_sel  = ctrl[`ALU_CTRL_RES_SEL];
    wire       unit_a_y = ctrl[`ALU_CTRL_UNIT_A_Y];
    wire       roots    = ctrl[`ALU_CTRL_ROOTS];
    wire       double   = ctrl[`ALU_CTRL_DOUBLE];
    wire       is_exp   = ctrl[`ALU_CTRL_EXP];

    // ------------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------------
    reg [95:0] f_q, f_d;
    reg        busy_q, busy_d;
    reg        recip_got_q, recip_got_d;  // ROOTS: each unit's result has arrived
    reg        sqrt_got_q, sqrt_got_d;

    // ------------------------------------------------------------------------
    // Operand lanes
    // ------------------------------------------------------------------------
    wire [31:0] a_x = a[31:0];
    wire [31:0] a_y = a[63:32];
    wire [31:0] a_z = a[95:64];
    wire [31:0] b_x = b[31:0];
    wire [31:0] b_y = b[63:32];
    wire [31:0] b_z = b[95:64];
    wire [31:0] f_x = f_q[31:0];
    wire [31:0] f_y = f_q[63:32];
    wire [31:0] f_z = f_q[95:64];

    // ------------------------------------------------------------------------
    // Multipliers: A.i * B.(B_LANE_i)
    // ------------------------------------------------------------------------
    function [31:0] b_lane(input [1:0] lane, input [95:0] v);
        case (lane)
            `ALU_LANE_Y: b_lane = v[63:32];
            `ALU_LANE_Z: b_lane = v[95:64];
            default:     b_lane = v[31:0];
        endcase
    endfunction

    wire [31:0] mul_b_x = b_lane(b_lane_x, b);
    wire [31:0] mul_b_y = b_lane(b_lane_y, b);
    wire [31:0] mul_b_z = b_lane(b_lane_z, b);
    wire [31:0] prod_x, prod_y, prod_z;

    fp_mul u_mul_x (.a(a_x), .b(mul_b_x), .y(prod_x));
    fp_mul u_mul_y (.a(a_y), .b(mul_b_y), .y(prod_y));
    fp_mul u_mul_z (.a(a_z), .b(mul_b_z), .y(prod_z));

    // -(p * q) is the rounded product with its sign bit flipped (NaN too).
    // 2p, exactly p + p rounded: the exponent goes up by one; a subnormal's
    // bits shift left (into the exponent field if they carry); the largest
    // binade overflows to infinity; infinities and NaNs pass.
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

    wire [31:0] scaled_x = double ? twice(prod_x) : prod_x;
    wire [31:0] scaled_y = double ? twice(prod_y) : prod_y;
    wire [31:0] scaled_z = double ? twice(prod_z) : prod_z;

    wire [95:0] prods = {scaled_z[31] ^ neg_mul, scaled_z[30:0],
                         scaled_y[31] ^ neg_mul, scaled_y[30:0],
                         scaled_x[31] ^ neg_mul, scaled_x[30:0]};

    // ------------------------------------------------------------------------
    // Adders
    // ------------------------------------------------------------------------
    // A - B is fp_add with B's sign bit flipped (thesis 4.2).
    wire [31:0] bs_x = {b_x[31] ^ neg_b, b_x[30:0]};
    wire [31:0] bs_y = {b_y[31] ^ neg_b, b_y[30:0]};
    wire [31:0] bs_z = {b_z[31] ^ neg_b, b_z[30:0]};

    reg [31:0] add_x_b;
    always @* begin
        add_x_b = bs_x;
        case (addx_b)
            `ALU_ADDX_B_FY: add_x_b = f_y;
            `ALU_ADDX_B_FZ: add_x_b = f_z;
            `ALU_ADDX_B_AY: add_x_b = a_y;
            default:        add_x_b = bs_x;
        endcase
    end

    wire [31:0] add_x_a = addx_a_f ? f_x : a_x;
    wire [31:0] add_y_a = addy_f   ? f_x : a_y;
    wire [31:0] add_y_b = addy_f   ? f_z : bs_y;
    wire [31:0] sum_x, sum_y, sum_z;

    fp_add u_add_x (.a(add_x_a), .b(add_x_b), .y(sum_x));
    fp_add u_add_y (.a(add_y_a), .b(add_y_b), .y(sum_y));
    fp_add u_add_z (.a(a_z),     .b(bs_z),    .y(sum_z));

    // ------------------------------------------------------------------------
    // Int to float
    // ------------------------------------------------------------------------
    wire [31:0] itof_x, itof_y;

    fp_itof u_itof_x (.a(ix), .y(itof_x));
    fp_itof u_itof_y (.a(iy), .y(itof_y));

    // ------------------------------------------------------------------------
    // Multi-cycle units
    // ------------------------------------------------------------------------
    wire        is_recip    = (res_sel == `ALU_RES_RECIP);
    wire        is_sqrt     = (res_sel == `ALU_RES_SQRT);
    wire        recip_valid, sqrt_valid;
    wire [31:0] recip_y, sqrt_y;

    fp_recip #(.METHOD(RECIP_METHOD)) u_recip (
        .clk       (clk),
        .rst_n     (rst_n),
        .in_valid  ((is_recip | roots) & ~busy_q),
        .a         (unit_a_y ? a_y : a_x),
        .out_valid (recip_valid),
        .y         (recip_y)
    );

    fp_sqrt #(.METHOD(SQRT_METHOD)) u_sqrt (
        .clk       (clk),
        .rst_n     (rst_n),
        .in_valid  (is_sqrt & ~busy_q),
        .a         (a_x),
        .out_valid (sqrt_valid),
        .y         (sqrt_y)
    );

    // One fp_exp per lane, started together: they finish in the same cycle.
    wire [2:0]  exp_valid;
    wire [95:0] exp_y;
    genvar ge;
    generate
        for (ge = 0; ge < 3; ge = ge + 1) begin : g_exp
            fp_exp u_exp (
                .clk       (clk),
                .rst_n     (rst_n),
                .in_valid  (is_exp & ~busy_q),
                .a         (a[32*ge +: 32]),
                .out_valid (exp_valid[ge]),
                .y         (exp_y[32*ge +: 32])
            );
        end
    endgenerate

    // Only the op's own unit can finish it; ROOTS needs both units, whose
    // out_valid pulses may come in different cycles (y holds each result).
    wire recip_in = recip_valid | recip_got_q;
    wire sqrt_in  = sqrt_valid | sqrt_got_q;
    wire unit_done = roots  ? (recip_in & sqrt_in)
                   : is_exp ? (&exp_valid)
                   : (is_recip & recip_valid) | (is_sqrt & sqrt_valid);

    // Set by the first cycle of RECIP/RECIPY/SQRT/ROOTS/EXP, cleared when it is
    // done; ROOTS remembers which results have arrived until then.
    always @* begin
        busy_d      = busy_q;
        recip_got_d = recip_got_q;
        sqrt_got_d  = sqrt_got_q;
        if ((is_recip | is_sqrt | is_exp) & ~busy_q) busy_d = 1'b1;
        if (roots & recip_valid) recip_got_d = 1'b1;
        if (roots & sqrt_valid)  sqrt_got_d  = 1'b1;
        if (unit_done) begin
            busy_d      = 1'b0;
            recip_got_d = 1'b0;
            sqrt_got_d  = 1'b0;
        end
    end

    // ------------------------------------------------------------------------
    // F
    // ------------------------------------------------------------------------
    always @* begin
        f_d = f_q;
        case (f_sel)
            `ALU_F_MUL:       f_d = prods;
            `ALU_F_SUM_X:     f_d = {f_z, f_y, sum_x};
            `ALU_F_SUM_XY_AZ: f_d = {a_z, sum_y, sum_x};
            `ALU_F_SUM_XY_0:  f_d = {POS_ZERO, sum_y, sum_x};
            default:          f_d = f_q;
        endcase
    end

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            f_q         <= 96'd0;
            busy_q      <= 1'b0;
            recip_got_q <= 1'b0;
            sqrt_got_q  <= 1'b0;
        end else begin
            f_q         <= f_d;
            busy_q      <= busy_d;
            recip_got_q <= recip_got_d;
            sqrt_got_q  <= sqrt_got_d;
        end
    end

    // ------------------------------------------------------------------------
    // Result
    // ------------------------------------------------------------------------
    reg [95:0] result;

    always @* begin
        result = {POS_ZERO, POS_ZERO, POS_ZERO};
        case (res_sel)
            `ALU_RES_SUM:   result = {sum_z, sum_y, sum_x};
            `ALU_RES_MUL:   result = prods;
            `ALU_RES_PASS:  result = {a_z[31] ^ neg_a, a_z[30:0],
                                      a_y[31] ^ neg_a, a_y[30:0],
                                      a_x[31] ^ neg_a, a_x[30:0]};
            `ALU_RES_ITOF:  result = {POS_ZERO, itof_y, itof_x};
            `ALU_RES_F:     result = f_d;
            `ALU_RES_RECIP: result = {POS_ZERO, POS_ZERO, recip_y};
            `ALU_RES_SQRT:  result = {POS_ZERO, roots ? recip_y : POS_ZERO, sqrt_y};
            default:        result = {POS_ZERO, POS_ZERO, POS_ZERO};
        endcase
        if (is_exp) result = exp_y;
    end

    assign y    = result;
    assign done = (is_recip | is_sqrt | is_exp) ? unit_done : 1'b1;

    // ------------------------------------------------------------------------
    // Flags
    // ------------------------------------------------------------------------
    genvar gi;
    generate
        for (gi = 0; gi < 3; gi = gi + 1) begin : g_flag
            wire [31:0] lane    = result[32*gi +: 32];
            wire        is_zero = ~(|lane[30:0]);
            wire        is_nan  = (&lane[30:23]) & (|lane[22:0]);
            assign y_sign[gi] = lane[31];
            assign y_neg[gi]  = lane[31] & ~is_zero & ~is_nan;
            assign y_pos[gi]  = ~lane[31] & ~is_zero & ~is_nan;
        end
    endgenerate

endmodule
`default_nettype wire
