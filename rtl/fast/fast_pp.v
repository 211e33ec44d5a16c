`default_nettype none
`include "isa.vh"
`include "fp_defs.vh"
`include "fast_defs.vh"
// ============================================================================
// fast_pp -- the fast pixel processor: 2^CTX_BITS pixels in flight, one
//            micro-op a cycle (docs/fast.md)
// ============================================================================
// The same ISA and the same program as the compact processor
// (rtl/pp/pixel_processor.v); each pixel's register-file writes are golden's
// micro-op model's, in order, bit for bit. The cycles follow the barrel rule
// (golden::micro::barrel): cycle t is context t mod K's turn; a turn issues
// the context's next micro-op, or is its done turn (the result leaves, the
// next waiting pixel is taken in the same turn), or an idle context's take.
//
//   in stream --> 2-entry queue --take--> fast_ctrl (the ring of contexts)
//                                           | micro-op, context
//   scene port --> cfg_q, scene table --> fast_regfile (2 edges) --> fast_alu
//                                           ^ write back (LAT + 2)     |
//                                           +--------------------------+
//                                              flags --> fast_ctrl
//   out stream <-- result queue (2K) <-- done turn: STK0_COL (2 edges)
//
// Streams. in_valid/in_ready/in_x/in_y: coordinates, into a 2-entry queue
// (in_ready is registered: the queue is not full, and the K cycles after
// reset are over); a context takes the head at its turn. out_valid/out_ready/out_*: results in the order the done
// turns came, each tagged with its coordinates, its context and its cycles
// (from the cycle after the turn that took it to its done turn inclusive,
// the barrel rule's count). A pixel is taken only while fewer than 2K
// pixels are held (taken, and not yet out), and the result queue has 2K
// entries, so a done turn never finds it full: backpressure on out_ready
// delays takes, never a pixel already running (its cycles are its own and
// the other contexts'). With coordinates offered every cycle and out_ready
// high, a frame takes the barrel rule's cycles for its pixels + 4, from the
// cycle whose edge takes the first coordinate to the one whose edge takes
// the last result: one into the queue, two of the register file's read,
// one into the result queue.
//
// Scene. scene_ready is high while no pixel is held (every context idle,
// every result out); writes are taken only then (the configuration word
// with scene_cfg, else a scene register), and while scene_we is high no
// pixel is taken.
//
// With PP_TRACE (the co-simulation; never for synthesis) the trace port
// shows every register-file write in the cycle whose edge performs it, with
// the context and its pixel; trace_take (the pixel taken on
// trace_take_px, trace_take_py) and trace_done mark the take of a
// pixel and the done turn of context trace_turn_ctx; and the fault port
// XORs lane x of every write of state fault_state with fault_xor, in the
// register file too.
// ============================================================================
module fast_pp #(
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT,
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT,
    parameter integer STACK_DEPTH  = `ISA_DIM_STK_COUNT,
    parameter integer EXPOSURE     = 1,   // 0: no exponential (scenes without exposure only)
    parameter integer REFRACTION   = 1,   // 0: no refraction (scenes without transparent spheres only)
    parameter integer CTX_BITS     = 5
) (
    input  wire                             clk,
    input  wire                             rst_n,
    // Scene port.
    input  wire                             scene_we,
    input  wire                             scene_cfg,
    input  wire [`ISA_DIM_REG_BITS-1:0]     scene_addr,
    input  wire [95:0]                      scene_data,
    output wire                             scene_ready,
    // Coordinates in.
    input  wire                             in_valid,
    output wire                             in_ready,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   in_x,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   in_y,
    // Results out.
    output wire                             out_valid,
    input  wire                             out_ready,
    output wire [`ISA_DIM_COORD_BITS-1:0]   out_x,
    output wire [`ISA_DIM_COORD_BITS-1:0]   out_y,
    output wire [CTX_BITS-1:0]              out_ctx,
    output wire [95:0]                      out_rgb,
    output wire [31:0]                      out_cycles
`ifdef PP_TRACE
    ,
    output wire                             trace_valid,
    output wire [CTX_BITS-1:0]              trace_ctx,
    output wire [`ISA_DIM_COORD_BITS-1:0]   trace_px,
    output wire [`ISA_DIM_COORD_BITS-1:0]   trace_py,
    output wire [`ISA_DIM_ST_BITS-1:0]      trace_state,
    output wire [`ISA_DIM_REG_BITS-1:0]     trace_dst,
    output wire [2:0]                       trace_lanes,
    output wire [95:0]                      trace_value,
    output wire                             trace_take,
    output wire [`ISA_DIM_COORD_BITS-1:0]   trace_take_px,
    output wire [`ISA_DIM_COORD_BITS-1:0]   trace_take_py,
    output wire                             trace_done,
    output wire [CTX_BITS-1:0]              trace_turn_ctx,
    input  wire [`ISA_DIM_ST_BITS-1:0]      fault_state,
    input  wire [31:0]                      fault_xor
`endif
);

    localparam integer RW      = `ISA_DIM_REG_BITS;
    localparam integer CW      = `ISA_DIM_COORD_BITS;
    localparam integer SW      = `ISA_DIM_ST_BITS;
    localparam integer OPW     = `ISA_DIM_OP_BITS;
    localparam integer LATENCY = (EXPOSURE != 0) ? `FAST_ALU_LATENCY : `FAST_ALU_LATENCY_NOEXP;
    localparam integer HW      = CTX_BITS + 2;      // held pixels: 0 .. 2K
    localparam [HW-1:0] HOLD_MAX = {1'b1, {(HW - 1){1'b0}}};

    // ------------------------------------------------------------------------
    // Configuration, cycle count, pixels held
    // ------------------------------------------------------------------------
    reg  [95:0]   cfg_q;
    reg  [31:0]   now_q;
    reg  [HW-1:0] held_q;
    wire          take;
    wire          out_take = out_valid && out_ready;

    assign scene_ready = (held_q == {HW{1'b0}});
    wire   cfg_we      = scene_we && scene_cfg && scene_ready;
    wire   scene_rf    = scene_we && !scene_cfg && scene_ready;

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            cfg_q  <= 96'd0;
            now_q  <= 32'd0;
            held_q <= {HW{1'b0}};
        end else begin
            if (cfg_we) cfg_q <= scene_data;
            now_q  <= now_q + 1'b1;
            held_q <= held_q + {{(HW - 1){1'b0}}, take} - {{(HW - 1){1'b0}}, out_take};
        end
    end

    // ------------------------------------------------------------------------
    // The coordinate queue (2 entries)
    // ------------------------------------------------------------------------
    reg [2*CW-1:0] inq [0:1];
    reg [1:0]      inq_n;          // entries
    reg            inq_rd, inq_wr; // their positions
    wire           in_push = in_valid && in_ready;

    wire sweeping;   // the controller's ring after reset: no coordinate yet
    assign in_ready = !inq_n[1] && !sweeping;
    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            inq_n  <= 2'd0;
            inq_rd <= 1'b0;
            inq_wr <= 1'b0;
        end else begin
            inq_n  <= inq_n + {1'b0, in_push} - {1'b0, take};
            inq_rd <= inq_rd ^ take;
            inq_wr <= inq_wr ^ in_push;
        end
    end
    always @(posedge clk) if (in_push) inq[inq_wr] <= {in_x, in_y};
    wire [CW-1:0] head_x, head_y;
    assign {head_x, head_y} = inq[inq_rd];

    wire take_ok = (inq_n != 2'd0) && (held_q != HOLD_MAX) && !scene_we;

    // ------------------------------------------------------------------------
    // The controller
    // ------------------------------------------------------------------------
    wire [CTX_BITS-1:0] turn_ctx;
    wire                done, issue;
    wire [OPW-1:0]      op;
    wire [RW-1:0]       pa_a, pa_b, pa_w;
    wire [2:0]          wmask;
    wire [SW-1:0]       state;
    wire [2:0]          y_neg, y_pos, y_sign;

    fast_ctrl #(
        .LATENCY     (LATENCY),
        .CTX_BITS    (CTX_BITS),
        .STACK_DEPTH (STACK_DEPTH),
        .REFRACTION  (REFRACTION)
    ) u_ctrl (
        .clk      (clk),
        .rst_n    (rst_n),
        .cfg      (cfg_q),
        .sweeping (sweeping),
        .turn_ctx (turn_ctx),
        .take_ok  (take_ok),
        .take     (take),
        .done     (done),
        .issue    (issue),
        .op       (op),
        .pa_a     (pa_a),
        .pa_b     (pa_b),
        .pa_w     (pa_w),
        .wmask    (wmask),
        .state    (state),
        .y_neg    (y_neg),
        .y_pos    (y_pos),
        .y_sign   (y_sign)
    );

    // ------------------------------------------------------------------------
    // Each context's pixel: coordinates and the cycle that took it
    // ------------------------------------------------------------------------
    reg  [2*CW+31:0] pix_mem [0:(1 << CTX_BITS)-1];
    always @(posedge clk) if (take) pix_mem[turn_ctx] <= {head_x, head_y, now_q};
    wire [CW-1:0] turn_px, turn_py;
    wire [31:0]   turn_taken;
    assign {turn_px, turn_py, turn_taken} = pix_mem[turn_ctx];

    // ------------------------------------------------------------------------
    // Register file and ALU: the operands two edges after the turn
    // ------------------------------------------------------------------------
    wire [95:0] rd_a, rd_b;
    wire        we;
    wire [CTX_BITS-1:0] w_ctx;
    wire [RW-1:0]       wa;
    wire [2:0]          wm;
    wire [95:0]         wd;

    fast_regfile #(
        .STACK_DEPTH (STACK_DEPTH),
        .CTX_BITS    (CTX_BITS),
        .REFRACTION  (REFRACTION)
    ) u_rf (
        .clk   (clk),
        .r_ctx (turn_ctx),
        .ra_a  (pa_a),
        .ra_b  (pa_b),
        .rd_a  (rd_a),
        .rd_b  (rd_b),
        .we    (we),
        .w_ctx (w_ctx),
        .wa    (wa),
        .wmask (wm),
        .wd    (wd),
        .swe   (scene_rf),
        .swa   (scene_addr),
        .swd   (scene_data)
    );

    // ITOF's operands <px, -py> (pp_ctrl ix, iy).
    wire [31:0] ix = {{(32 - CW){1'b0}}, turn_px};
    wire [31:0] iy = -{{(32 - CW){1'b0}}, turn_py};

    wire                in_v;
    wire [CTX_BITS-1:0] in_ctx;
    wire [OPW-1:0]      in_op;
    wire [31:0]         in_ix, in_iy;
    fast_delay #(.WIDTH(1 + CTX_BITS + OPW + 64), .STAGES(2)) u_to_alu (
        .clk (clk),
        .d   ({issue, turn_ctx, op, ix, iy}),
        .q   ({in_v, in_ctx, in_op, in_ix, in_iy})
    );

    wire                exp_ready, out_v, out_writes;
    wire [CTX_BITS-1:0] y_ctx;
    wire [95:0]         y;

    fast_alu #(
        .RECIP_METHOD (RECIP_METHOD),
        .SQRT_METHOD  (SQRT_METHOD),
        .EXPOSURE     (EXPOSURE),
        .CTX_BITS     (CTX_BITS)
    ) u_alu (
        .clk        (clk),
        .rst_n      (rst_n),
        .in_valid   (in_v),
        .in_ctx     (in_ctx),
        .in_op      (in_op),
        .a          (rd_a),
        .b          (rd_b),
        .ix         (in_ix),
        .iy         (in_iy),
        .exp_ready  (exp_ready),
        .out_valid  (out_v),
        .out_ctx    (y_ctx),
        .out_writes (out_writes),
        .y          (y),
        .y_neg      (y_neg),
        .y_pos      (y_pos),
        .y_sign     (y_sign)
    );
    // The controller keeps EXPs three cycles apart itself (fast_ctrl).
    wire unused_exp_ready = exp_ready;

    // ------------------------------------------------------------------------
    // Write back: the micro-op's destination beside its result
    // ------------------------------------------------------------------------
    wire [RW-1:0] back_w;
    wire [2:0]    back_mask;
    wire [SW-1:0] back_state;
    fast_delay #(.WIDTH(RW + 3 + SW), .STAGES(LATENCY + 2)) u_to_back (
        .clk (clk),
        .d   ({pa_w, wmask, state}),
        .q   ({back_w, back_mask, back_state})
    );

`ifdef PP_TRACE
    wire [31:0] wd_flip = (back_state == fault_state) ? fault_xor : 32'd0;
`else
    wire [31:0] wd_flip = 32'd0;
    wire unused_back_state = ^back_state;
`endif

    assign we    = out_v && out_writes;
    assign w_ctx = y_ctx;
    assign wa    = back_w;
    assign wm    = back_mask;
    assign wd    = {y[95:32], y[31:0] ^ wd_flip};

    // ------------------------------------------------------------------------
    // Results: the colour two edges after the done turn, into the queue
    // ------------------------------------------------------------------------
    localparam integer RES_W = 2 * CW + CTX_BITS + 32;
    wire               res_v;
    wire [RES_W-1:0]   res_tag;
    fast_delay #(.WIDTH(1 + RES_W), .STAGES(2)) u_to_res (
        .clk (clk),
        .d   ({done, turn_px, turn_py, turn_ctx, now_q - turn_taken}),
        .q   ({res_v, res_tag})
    );

    // out_valid is a register (the queue holds a result), so that a top's
    // logic around many processors starts its paths at a flip-flop: its
    // next value from the entry count's registered flags, the result
    // arriving, and the take (out_ready the only input before it).
    reg [RES_W+95:0]   outq [0:(1 << (CTX_BITS + 1))-1];
    reg [CTX_BITS:0]   outq_rd, outq_wr;   // 2K entries
    reg [CTX_BITS+1:0] outq_n;             // entries: 0 .. 2K
    reg                outq_valid;         // outq_n != 0
    wire outq_many = |outq_n[CTX_BITS+1:1];          // 2 or more
    wire outq_one  = (outq_n == {{(CTX_BITS + 1){1'b0}}, 1'b1});
    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            outq_rd    <= {(CTX_BITS + 1){1'b0}};
            outq_wr    <= {(CTX_BITS + 1){1'b0}};
            outq_n     <= {(CTX_BITS + 2){1'b0}};
            outq_valid <= 1'b0;
        end else begin
            if (res_v)    outq_wr <= outq_wr + 1'b1;
            if (out_take) outq_rd <= outq_rd + 1'b1;
            outq_n     <= outq_n + {{(CTX_BITS + 1){1'b0}}, res_v} - {{(CTX_BITS + 1){1'b0}}, out_take};
            outq_valid <= res_v || outq_many || (outq_one && !out_take);
        end
    end
    always @(posedge clk) if (res_v) outq[outq_wr] <= {res_tag, rd_a};

    assign out_valid = outq_valid;
    assign {out_x, out_y, out_ctx, out_cycles, out_rgb} = outq[outq_rd];

`ifdef PP_TRACE
    // The pixel of each write: its context's entry (a context's writes all
    // land before its done turn, so before its next take).
    wire [31:0] w_taken;
    assign {trace_px, trace_py, w_taken} = pix_mem[y_ctx];
    wire unused_w_taken = ^w_taken;
    assign trace_valid    = we;
    assign trace_ctx      = y_ctx;
    assign trace_state    = back_state;
    assign trace_dst      = back_w;
    assign trace_lanes    = back_mask;
    assign trace_value    = wd & {{32{back_mask[2]}}, {32{back_mask[1]}}, {32{back_mask[0]}}};
    assign trace_take     = take;
    assign trace_take_px  = head_x;
    assign trace_take_py  = head_y;
    assign trace_done     = done;
    assign trace_turn_ctx = turn_ctx;
`endif

endmodule
`default_nettype wire
