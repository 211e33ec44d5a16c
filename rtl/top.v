`default_nettype none
`include "isa.vh"
`include "fp_defs.vh"
// ============================================================================
// top -- N pixel processors behind one scene port, a coordinate stream and a
// result stream (thesis 4.9, "Topmodule", which the thesis left unbuilt)
// ============================================================================
//
//   scene port ------------------------------------------> every processor
//   in stream  --\
//                 +--> stg (1 entry) --dispatcher--> start_q[i], tag[i]
//   raster gen --/                                     |
//                                  pixel_processor[i] -+-> done: slot[i]
//   out stream <-- out register <-- round-robin arbiter <-- slot[0..N-1]
//
// Coordinates. raster_mode = 0: the in stream (in_valid/in_ready, in_x,
// in_y) feeds the staging register. raster_mode = 1: the raster generator
// does, row by row over the window win_x0..win_x1, win_y0..win_y1
// (inclusive, sampled at an accepted raster_start), and in_ready stays low;
// raster_busy is high until the window's last coordinate is staged.
// raster_mode may change only while nothing is staged or generated.
// in_ready is a register bit (no combinational path from any input but
// raster_mode), so the stage takes a coordinate every other cycle at most:
// far more than N processors of about 160 cycles a pixel consume.
//
// Dispatcher. A processor is free when the dispatcher has not given it a
// pixel (busy_q) and its result slot is empty (res_valid_q). In a cycle with
// a staged coordinate, a free processor and scene_we low, the lowest-
// numbered free processor gets it at the rising edge: busy_q and the tag
// (x, y) are set, and start_q raises start for the next cycle, in which the
// processor is idle (ready) by construction. busy_q falls at the edge that
// ends the processor's done cycle, when the slot takes the result. Between a
// pixel's done cycle and the next pixel's first cycle on the same processor
// lie three cycles (slot to the out register, dispatch, start).
//
// Results. Each processor has a result slot: x, y, rgb (valid only in the
// done cycle, so captured there), and the pixel's cycles (every cycle with
// ready low from the one after the start edge up to and including the done
// cycle: the count harness/pixel_proc.rs defines and golden::micro
// predicts). A round-robin arbiter moves one slot per cycle into the out
// register (out_valid, out_x, out_y, out_proc, out_rgb, out_cycles) whenever
// that register is empty or being taken (out_valid && out_ready). A pixel is
// dispatched only to a processor whose slot is empty, so a processor never
// finishes into a full slot: backpressure stalls processors, it loses and
// duplicates nothing. Results leave in completion order, not coordinate
// order; out_x, out_y and out_proc tag them.
//
// Timing. Every path through the dispatcher and the arbiter starts at a
// register (busy_q, res_valid_q, rr_q, stg_valid_q) and ends at one: an
// N-bit priority search each. No output depends combinationally on an input
// except in_ready (on raster_mode) and the out register's load enable (on
// out_ready, one gate).
//
// Scene. The scene port is broadcast to every processor. A write is taken at
// a rising edge with scene_we && scene_ready; scene_ready is high while no
// processor has a pixel (every busy_q low: every processor idle). While
// scene_we is high nothing is dispatched, so a host that waits for
// scene_ready, then writes, changes the scene between two pixels of no
// processor: between frames, drain (every result out), write the new scene
// (registers, then the configuration word), and stream the next frame.
// Writes while scene_ready is low are dropped.
//
// With PP_TRACE (the co-simulation; never for synthesis) each processor's
// trace port is brought out, lane i of each bus being processor i, with
// trace_busy (busy_q) and trace_px, trace_py (the pixel it was given), and
// the fault port is broadcast to the processors selected by fault_procs.
//
// FAST = 1: the processors are fast ones (rtl/fast/fast_pp.v, 2^CTX_BITS
// pixel contexts each, with a coordinate queue and a result queue of their
// own), behind the same stage, dispatcher and arbiter. A processor is free
// when its coordinate queue has room (its in_ready): the dispatcher hands
// the staged coordinate to the lowest-numbered free one, straight into its
// queue. Its result slot is the head of its result queue (out_valid); the
// arbiter takes it from there. out_cycles is the processor's count (the
// barrel rule's, golden::micro::barrel) and out_ctx the context that ran
// the pixel; a processor is busy (scene_ready, trace_busy) while it holds a
// pixel. Trace: lane i of trace_ctx, trace_take, trace_take_px/py,
// trace_done and trace_turn_ctx is processor i's port of the same name, and
// trace_px, trace_py the pixel of its write.
// ============================================================================
module top #(
    parameter integer N            = 4,
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT,
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT,
    parameter integer STACK_DEPTH  = `ISA_DIM_STK_COUNT,
    parameter integer FAST         = 0,   // 1: fast processors (rtl/fast/fast_pp.v)
    parameter integer EXPOSURE     = 1,   // FAST: 0 builds no exponential
    parameter integer REFRACTION   = 1,   // 0: no refraction (scenes without transparent spheres only)
    parameter integer CTX_BITS     = 5,   // FAST: 2^CTX_BITS contexts a processor
    parameter integer ARB_GROUP    = 6    // FAST: processors per result group
) (
    input  wire                             clk,
    input  wire                             rst_n,
    // Scene port (broadcast).
    input  wire                             scene_we,
    input  wire                             scene_cfg,
    input  wire [`ISA_DIM_REG_BITS-1:0]     scene_addr,
    input  wire [95:0]                      scene_data,
    output wire                             scene_ready,
    // Coordinate source: the in stream, or the raster generator.
    input  wire                             raster_mode,
    input  wire                             raster_start,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   win_x0,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   win_y0,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   win_x1,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   win_y1,
    output wire                             raster_busy,
    input  wire                             in_valid,
    output wire                             in_ready,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   in_x,
    input  wire [`ISA_DIM_COORD_BITS-1:0]   in_y,
    // Result stream.
    output wire                             out_valid,
    input  wire                             out_ready,
    output wire [`ISA_DIM_COORD_BITS-1:0]   out_x,
    output wire [`ISA_DIM_COORD_BITS-1:0]   out_y,
    output wire [((N > 1) ? $clog2(N) : 1)-1:0] out_proc,
    output wire [CTX_BITS-1:0]              out_ctx,    // FAST; 0 otherwise
    output wire [95:0]                      out_rgb,
    output wire [31:0]                      out_cycles
`ifdef PP_TRACE
    ,
    output wire [N-1:0]                     trace_valid,
    output wire [N-1:0]                     trace_busy,
    output wire [N*`ISA_DIM_ST_BITS-1:0]    trace_state,
    output wire [N*`ISA_DIM_REG_BITS-1:0]   trace_dst,
    output wire [N*3-1:0]                   trace_lanes,
    output wire [N*96-1:0]                  trace_value,
    output wire [N*`ISA_DIM_COORD_BITS-1:0] trace_px,
    output wire [N*`ISA_DIM_COORD_BITS-1:0] trace_py,
    output wire [N*CTX_BITS-1:0]            trace_ctx,       // FAST; 0 otherwise
    output wire [N-1:0]                     trace_take,      // FAST; 0 otherwise
    output wire [N*`ISA_DIM_COORD_BITS-1:0] trace_take_px,   // FAST; 0 otherwise
    output wire [N*`ISA_DIM_COORD_BITS-1:0] trace_take_py,   // FAST; 0 otherwise
    output wire [N-1:0]                     trace_done,      // FAST; 0 otherwise
    output wire [N*CTX_BITS-1:0]            trace_turn_ctx,  // FAST; 0 otherwise
    input  wire [`ISA_DIM_ST_BITS-1:0]      fault_state,
    input  wire [31:0]                      fault_xor,
    input  wire [N-1:0]                     fault_procs
`endif
);

    localparam integer CW = `ISA_DIM_COORD_BITS;
    localparam integer PW = (N > 1) ? $clog2(N) : 1;

    // ------------------------------------------------------------------------
    // Staging register, fed by the in stream or the raster generator
    // ------------------------------------------------------------------------
    reg          stg_valid_q;
    reg [CW-1:0] stg_x_q, stg_y_q;
    reg          rs_busy_q;
    reg [CW-1:0] rs_x_q, rs_y_q, rs_x0_q, rs_x1_q, rs_y1_q;
    wire         dispatch;

    assign in_ready    = !stg_valid_q && !raster_mode;
    assign raster_busy = rs_busy_q;

    wire in_take = in_valid && in_ready;
    wire rs_take = raster_mode && rs_busy_q && !stg_valid_q;

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            stg_valid_q <= 1'b0;
            stg_x_q     <= {CW{1'b0}};
            stg_y_q     <= {CW{1'b0}};
        end else if (in_take || rs_take) begin
            stg_valid_q <= 1'b1;
            stg_x_q     <= in_take ? in_x : rs_x_q;
            stg_y_q     <= in_take ? in_y : rs_y_q;
        end else if (dispatch) begin
            stg_valid_q <= 1'b0;
        end
    end

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            rs_busy_q <= 1'b0;
            rs_x_q    <= {CW{1'b0}};
            rs_y_q    <= {CW{1'b0}};
            rs_x0_q   <= {CW{1'b0}};
            rs_x1_q   <= {CW{1'b0}};
            rs_y1_q   <= {CW{1'b0}};
        end else if (!rs_busy_q) begin
            if (raster_mode && raster_start) begin
                rs_busy_q <= 1'b1;
                rs_x_q    <= win_x0;
                rs_y_q    <= win_y0;
                rs_x0_q   <= win_x0;
                rs_x1_q   <= win_x1;
                rs_y1_q   <= win_y1;
            end
        end else if (rs_take) begin
            if (rs_x_q != rs_x1_q) begin
                rs_x_q <= rs_x_q + 1'b1;
            end else if (rs_y_q != rs_y1_q) begin
                rs_x_q <= rs_x0_q;
                rs_y_q <= rs_y_q + 1'b1;
            end else begin
                rs_busy_q <= 1'b0;
            end
        end
    end

    // ------------------------------------------------------------------------
    // Dispatcher: the lowest-numbered free processor takes the staged pixel
    // ------------------------------------------------------------------------
    wire [N-1:0]    busy;        // the processor holds a pixel
    wire [N-1:0]    free;        // it may be given one

    // The result slots the arbiter serves: each compact processor's own;
    // for fast processors, the result register of each group of ARB_GROUP
    // (below).
    localparam integer G  = (FAST == 0) ? 1 : (ARB_GROUP < N) ? ARB_GROUP : N;
    localparam integer S  = (N + G - 1) / G;
    localparam integer GW = (G > 1) ? $clog2(G) : 1;
    wire [S-1:0]    res_valid;   // slot full
    reg  [N-1:0]    pick;        // one-hot: the lowest-numbered free processor
    reg             pick_seen;
    integer         k;

    always @* begin
        pick      = {N{1'b0}};
        pick_seen = 1'b0;
        for (k = 0; k < N; k = k + 1)
            if (free[k] && !pick_seen) begin
                pick[k]   = 1'b1;
                pick_seen = 1'b1;
            end
    end

    assign dispatch    = stg_valid_q && (|free) && !scene_we;
    assign scene_ready = ~|busy;

    // ------------------------------------------------------------------------
    // Round-robin arbiter over the result slots, into the out register
    // ------------------------------------------------------------------------
    reg  [PW-1:0]   rr_q;        // the last grant
    wire [S-1:0]    grant;       // one-hot
    wire [PW-1:0]   grant_at;    // its index
    wire            grant_found;

    reg             out_valid_q;
    reg  [CW-1:0]   out_x_q, out_y_q;
    reg  [PW-1:0]   out_proc_q;
    reg  [CTX_BITS-1:0] out_ctx_q;
    reg  [95:0]     out_rgb_q;
    reg  [31:0]     out_cycles_q;
    wire            out_load = (!out_valid_q || out_ready) && grant_found;

    wire [S*CW-1:0] res_x_flat, res_y_flat;
    wire [S*96-1:0] res_rgb_flat;
    wire [S*32-1:0] res_cyc_flat;
    wire [S*CTX_BITS-1:0] res_ctx_flat;
    wire [S*PW-1:0] res_proc_flat;

    // Each slot's result as one word, and the granted slot's.
    localparam integer OW = 2 * CW + PW + CTX_BITS + 96 + 32;
    wire [S*OW-1:0] slot_words;
    wire [OW-1:0]   granted;
    genvar          gs;
    generate
        for (gs = 0; gs < S; gs = gs + 1) begin : g_slot
            assign slot_words[gs*OW +: OW] =
                {res_x_flat[gs*CW +: CW], res_y_flat[gs*CW +: CW], res_proc_flat[gs*PW +: PW],
                 res_ctx_flat[gs*CTX_BITS +: CTX_BITS], res_rgb_flat[gs*96 +: 96],
                 res_cyc_flat[gs*32 +: 32]};
        end
    endgenerate

    rr_arbiter #(.N(S), .IW(PW), .DW(OW)) u_arb (
        .req     (res_valid),
        .last    (rr_q),
        .data    (slot_words),
        .grant   (grant),
        .at      (grant_at),
        .found   (grant_found),
        .granted (granted)
    );

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            out_valid_q  <= 1'b0;
            out_x_q      <= {CW{1'b0}};
            out_y_q      <= {CW{1'b0}};
            out_proc_q   <= {PW{1'b0}};
            out_ctx_q    <= {CTX_BITS{1'b0}};
            out_rgb_q    <= 96'd0;
            out_cycles_q <= 32'd0;
            rr_q         <= {PW{1'b0}};
        end else if (!out_valid_q || out_ready) begin
            out_valid_q <= grant_found;
            if (grant_found) begin
                {out_x_q, out_y_q, out_proc_q, out_ctx_q, out_rgb_q, out_cycles_q} <= granted;
                rr_q <= grant_at;
            end
        end
    end

    assign out_valid  = out_valid_q;
    assign out_x      = out_x_q;
    assign out_y      = out_y_q;
    assign out_proc   = out_proc_q;
    assign out_ctx    = out_ctx_q;
    assign out_rgb    = out_rgb_q;
    assign out_cycles = out_cycles_q;

    // ------------------------------------------------------------------------
    // The processors, each with its tag, cycle counter and result slot
    // ------------------------------------------------------------------------
    wire scene_take = scene_we && scene_ready;

    genvar gi;
    generate
        for (gi = 0; gi < N; gi = gi + 1) begin : g_pp
            localparam [PW-1:0] ID = gi;
            wire          mine = dispatch && pick[gi];

            if (FAST == 0) begin : g_compact
                wire          take = out_load && grant[gi];   // the slot empties
                reg           busy_q, start_q, res_valid_q;
                reg  [CW-1:0] tag_x_q, tag_y_q;
                reg  [31:0]   cnt_q;
                reg  [CW-1:0] res_x_q, res_y_q;
                reg  [95:0]   res_rgb_q;
                reg  [31:0]   res_cyc_q;
                wire          ready, done;
                wire [95:0]   rgb;

                always @(posedge clk or negedge rst_n) begin
                    if (!rst_n) begin
                        busy_q  <= 1'b0;
                        start_q <= 1'b0;
                        tag_x_q <= {CW{1'b0}};
                        tag_y_q <= {CW{1'b0}};
                    end else begin
                        start_q <= mine;
                        if (mine) begin
                            busy_q  <= 1'b1;
                            tag_x_q <= stg_x_q;
                            tag_y_q <= stg_y_q;
                        end else if (done) begin
                            busy_q <= 1'b0;
                        end
                    end
                end

                // The pixel's cycles: from the cycle after its start edge to
                // its done cycle inclusive.
                always @(posedge clk or negedge rst_n) begin
                    if (!rst_n) cnt_q <= 32'd0;
                    else if (start_q) cnt_q <= 32'd0;
                    else if (!ready) cnt_q <= cnt_q + 32'd1;
                end

                always @(posedge clk or negedge rst_n) begin
                    if (!rst_n) begin
                        res_valid_q <= 1'b0;
                        res_x_q     <= {CW{1'b0}};
                        res_y_q     <= {CW{1'b0}};
                        res_rgb_q   <= 96'd0;
                        res_cyc_q   <= 32'd0;
                    end else if (done) begin
                        res_valid_q <= 1'b1;
                        res_x_q     <= tag_x_q;
                        res_y_q     <= tag_y_q;
                        res_rgb_q   <= rgb;
                        res_cyc_q   <= cnt_q + 32'd1;
                    end else if (take) begin
                        res_valid_q <= 1'b0;
                    end
                end

                assign busy[gi]                           = busy_q;
                assign free[gi]                           = !busy_q && !res_valid_q;
                assign res_valid[gi]                      = res_valid_q;
                assign res_x_flat[gi*CW +: CW]            = res_x_q;
                assign res_y_flat[gi*CW +: CW]            = res_y_q;
                assign res_rgb_flat[gi*96 +: 96]          = res_rgb_q;
                assign res_cyc_flat[gi*32 +: 32]          = res_cyc_q;
                assign res_ctx_flat[gi*CTX_BITS +: CTX_BITS] = {CTX_BITS{1'b0}};
                assign res_proc_flat[gi*PW +: PW]         = ID;
                assign pp_valid[gi]                       = 1'b0;
                assign pp_x_flat[gi*CW +: CW]             = {CW{1'b0}};
                assign pp_y_flat[gi*CW +: CW]             = {CW{1'b0}};
                assign pp_rgb_flat[gi*96 +: 96]           = 96'd0;
                assign pp_cyc_flat[gi*32 +: 32]           = 32'd0;
                assign pp_ctx_flat[gi*CTX_BITS +: CTX_BITS] = {CTX_BITS{1'b0}};
                assign pp_pop[gi]                         = 1'b0;

                pixel_processor #(
                    .RECIP_METHOD (RECIP_METHOD),
                    .SQRT_METHOD  (SQRT_METHOD),
                    .STACK_DEPTH  (STACK_DEPTH),
                    .REFRACTION   (REFRACTION)
                ) u_pp (
                    .clk        (clk),
                    .rst_n      (rst_n),
                    .scene_we   (scene_take),
                    .scene_cfg  (scene_cfg),
                    .scene_addr (scene_addr),
                    .scene_data (scene_data),
                    .start      (start_q),
                    .px         (tag_x_q),
                    .py         (tag_y_q),
                    .ready      (ready),
                    .done       (done),
                    .rgb        (rgb)
`ifdef PP_TRACE
                    ,
                    .trace_valid (trace_valid[gi]),
                    .trace_state (trace_state[gi*`ISA_DIM_ST_BITS +: `ISA_DIM_ST_BITS]),
                    .trace_dst   (trace_dst[gi*`ISA_DIM_REG_BITS +: `ISA_DIM_REG_BITS]),
                    .trace_lanes (trace_lanes[gi*3 +: 3]),
                    .trace_value (trace_value[gi*96 +: 96]),
                    .fault_state (fault_state),
                    .fault_xor   (fault_procs[gi] ? fault_xor : 32'd0)
`endif
                );

`ifdef PP_TRACE
                assign trace_busy[gi]                          = busy_q;
                assign trace_px[gi*CW +: CW]                   = tag_x_q;
                assign trace_py[gi*CW +: CW]                   = tag_y_q;
                assign trace_ctx[gi*CTX_BITS +: CTX_BITS]      = {CTX_BITS{1'b0}};
                assign trace_take[gi]                          = 1'b0;
                assign trace_take_px[gi*CW +: CW]              = {CW{1'b0}};
                assign trace_take_py[gi*CW +: CW]              = {CW{1'b0}};
                assign trace_done[gi]                          = 1'b0;
                assign trace_turn_ctx[gi*CTX_BITS +: CTX_BITS] = {CTX_BITS{1'b0}};
`endif
            end else begin : g_fast
                wire          in_ready_i, idle;

                fast_pp #(
                    .RECIP_METHOD (RECIP_METHOD),
                    .SQRT_METHOD  (SQRT_METHOD),
                    .STACK_DEPTH  (STACK_DEPTH),
                    .EXPOSURE     (EXPOSURE),
                    .REFRACTION   (REFRACTION),
                    .CTX_BITS     (CTX_BITS)
                ) u_pp (
                    .clk         (clk),
                    .rst_n       (rst_n),
                    .scene_we    (scene_take),
                    .scene_cfg   (scene_cfg),
                    .scene_addr  (scene_addr),
                    .scene_data  (scene_data),
                    .scene_ready (idle),
                    .in_valid    (mine),
                    .in_ready    (in_ready_i),
                    .in_x        (stg_x_q),
                    .in_y        (stg_y_q),
                    .out_valid   (pp_valid[gi]),
                    .out_ready   (pp_pop[gi]),
                    .out_x       (pp_x_flat[gi*CW +: CW]),
                    .out_y       (pp_y_flat[gi*CW +: CW]),
                    .out_ctx     (pp_ctx_flat[gi*CTX_BITS +: CTX_BITS]),
                    .out_rgb     (pp_rgb_flat[gi*96 +: 96]),
                    .out_cycles  (pp_cyc_flat[gi*32 +: 32])
`ifdef PP_TRACE
                    ,
                    .trace_valid    (trace_valid[gi]),
                    .trace_ctx      (trace_ctx[gi*CTX_BITS +: CTX_BITS]),
                    .trace_px       (trace_px[gi*CW +: CW]),
                    .trace_py       (trace_py[gi*CW +: CW]),
                    .trace_state    (trace_state[gi*`ISA_DIM_ST_BITS +: `ISA_DIM_ST_BITS]),
                    .trace_dst      (trace_dst[gi*`ISA_DIM_REG_BITS +: `ISA_DIM_REG_BITS]),
                    .trace_lanes    (trace_lanes[gi*3 +: 3]),
                    .trace_value    (trace_value[gi*96 +: 96]),
                    .trace_take     (trace_take[gi]),
                    .trace_take_px  (trace_take_px[gi*CW +: CW]),
                    .trace_take_py  (trace_take_py[gi*CW +: CW]),
                    .trace_done     (trace_done[gi]),
                    .trace_turn_ctx (trace_turn_ctx[gi*CTX_BITS +: CTX_BITS]),
                    .fault_state    (fault_state),
                    .fault_xor      (fault_procs[gi] ? fault_xor : 32'd0)
`endif
                );

                assign busy[gi] = !idle;
                assign free[gi] = in_ready_i;
`ifdef PP_TRACE
                assign trace_busy[gi]          = !idle;
`endif
            end
        end
    endgenerate


    // ------------------------------------------------------------------------
    // Fast processors: their result queues' heads into group registers
    // ------------------------------------------------------------------------
    // A 34-way round-robin search and multiplexer into the out register is
    // 17 LUT levels (docs/rtl.md), so results meet in two steps, each a
    // small search: processor i belongs to group i / ARB_GROUP; a group's
    // result register, when empty, takes the head of one of its
    // processors' result queues (round robin from the one after its last
    // pick); the arbiter above serves the groups' registers. The processor
    // no longer holds the pixel once its head has left for the group.
    wire [N-1:0]          pp_valid;   // its result queue is not empty
    wire [N-1:0]          pp_pop;     // its head leaves for its group
    wire [N*CW-1:0]       pp_x_flat, pp_y_flat;
    wire [N*96-1:0]       pp_rgb_flat;
    wire [N*32-1:0]       pp_cyc_flat;
    wire [N*CTX_BITS-1:0] pp_ctx_flat;
    wire unused_pp = ^{pp_valid, pp_pop, pp_x_flat, pp_y_flat, pp_rgb_flat, pp_cyc_flat, pp_ctx_flat};

    genvar gk;
    generate
        if (FAST != 0) begin : g_arb
            for (gk = 0; gk < S; gk = gk + 1) begin : g_grp
                localparam integer FIRST = gk * G;
                localparam integer COUNT = (N - FIRST < G) ? N - FIRST : G;
                reg                 v_q;
                reg  [PW-1:0]       proc_q;
                reg  [CW-1:0]       x_q, y_q;
                reg  [CTX_BITS-1:0] ctx_q;
                reg  [95:0]         rgb_q;
                reg  [31:0]         cyc_q;
                reg  [GW-1:0]       last_q;
                // The members' queue heads, and the one picked round robin
                // from the member after the last pick.
                localparam integer HW = 2 * CW + CTX_BITS + 96 + 32;
                wire [COUNT*HW-1:0] heads;
                wire [COUNT-1:0]    grant1;
                wire [GW-1:0]       member;
                wire                found;
                wire [HW-1:0]       head;
                genvar              gm;
                for (gm = 0; gm < COUNT; gm = gm + 1) begin : g_member
                    assign heads[gm*HW +: HW] =
                        {pp_x_flat[(FIRST + gm)*CW +: CW], pp_y_flat[(FIRST + gm)*CW +: CW],
                         pp_ctx_flat[(FIRST + gm)*CTX_BITS +: CTX_BITS],
                         pp_rgb_flat[(FIRST + gm)*96 +: 96], pp_cyc_flat[(FIRST + gm)*32 +: 32]};
                end
                rr_arbiter #(.N(COUNT), .IW(GW), .DW(HW)) u_arb (
                    .req     (pp_valid[FIRST +: COUNT]),
                    .last    (last_q),
                    .data    (heads),
                    .grant   (grant1),
                    .at      (member),
                    .found   (found),
                    .granted (head)
                );

                wire        load = !v_q && found;
                localparam [31:0] FIRST_W = FIRST;
                wire [PW-1:0] who = FIRST_W[PW-1:0] + {{(PW - GW){1'b0}}, member};
                always @(posedge clk or negedge rst_n) begin
                    if (!rst_n) begin
                        v_q    <= 1'b0;
                        proc_q <= {PW{1'b0}};
                        x_q    <= {CW{1'b0}};
                        y_q    <= {CW{1'b0}};
                        ctx_q  <= {CTX_BITS{1'b0}};
                        rgb_q  <= 96'd0;
                        cyc_q  <= 32'd0;
                        last_q <= {GW{1'b0}};
                    end else if (load) begin
                        v_q    <= 1'b1;
                        proc_q <= who;
                        {x_q, y_q, ctx_q, rgb_q, cyc_q} <= head;
                        last_q <= member;
                    end else if (out_load && grant[gk]) begin
                        v_q <= 1'b0;
                    end
                end

                assign pp_pop[FIRST +: COUNT] = load ? grant1 : {COUNT{1'b0}};

                assign res_valid[gk]                          = v_q;
                assign res_proc_flat[gk*PW +: PW]             = proc_q;
                assign res_x_flat[gk*CW +: CW]                = x_q;
                assign res_y_flat[gk*CW +: CW]                = y_q;
                assign res_ctx_flat[gk*CTX_BITS +: CTX_BITS]  = ctx_q;
                assign res_rgb_flat[gk*96 +: 96]              = rgb_q;
                assign res_cyc_flat[gk*32 +: 32]              = cyc_q;
            end
        end
    endgenerate

    // The compact processor always has its exponential: EXPOSURE = 0 is a
    // fast-processor build.
    generate
        if (FAST == 0 && EXPOSURE != 1) begin : g_exposure_is_fast_only
            top_exposure_0_needs_fast_processors u_error ();
        end
    endgenerate

endmodule
`default_nettype wire
