`default_nettype none
`include "isa.vh"
`include "fp_defs.vh"
`include "fast_defs.vh"
// ============================================================================
// fast_pp_tb -- the fast pixel processor (rtl/fast/fast_pp.v) under Icarus
//               Verilog, with its trace port (tests/icarus.rs)
// ============================================================================
// The stream protocol of harness/cpp/top.cpp with Fast = true, in Verilog:
// the same reset, the scene written through the scene port while
// scene_ready, then the coordinates offered on the in stream every cycle
// and the results taken with out_ready high. Every cycle is sampled with
// clk low after its inputs have settled, as the C++ driver samples it:
// takes, register-file writes and results are printed in the order of the
// cycles that show them.
//
// Stimulus, written by the Rust test ($readmemh, plusargs), as top_tb.v:
//   +scene=FILE +writes=N  N scene-port writes, 28 hex digits each:
//                          {8'cfg, 8'addr, 96'data} (data lane x = bits 31:0)
//   +pixels=FILE +count=M  M pixels, 8 hex digits each: {16'x, 16'y}
//   +fault_state=S         (decimal) the fault port: lane x of every write
//   +fault_xor=H           of state S XORed with H (hex); both 0 if absent
// Output on stdout, one line per sampled event, in cycle order:
//   TAKE ctx x y                   context ctx takes the queue's head (x, y)
//   EV ctx x y state dst lanes vx vy vz
//                                  a register-file write of ctx's pixel
//                                  (x, y); state, dst, lanes decimal,
//                                  values hex (lanes not written are 0)
//   PIX x y rgb_x rgb_y rgb_z cycles ctx
//                                  a result leaving on the out stream
// then `FRAME c` (the cycles from the one that took the first coordinate
// to the one that gave the last result, both counted: top.cpp's
// frame_cycles) and END, or `HUNG taken given` if no coordinate goes in and
// no result comes out for more than 2 TIMEOUT + 16 cycles (top.cpp's stall).
//
// Not under rtl/: a second top there would fail the whole-tree lint.
// ============================================================================
module fast_pp_tb;

    parameter integer RECIP_METHOD = `FP_METHOD_EXACT;
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT;
    parameter integer EXPOSURE     = 1;
    parameter integer REFRACTION   = 1;
    parameter integer CTX_BITS     = 5;
    parameter integer MAX_WRITES   = 1 << `ISA_DIM_REG_BITS;
    parameter integer MAX_PIXELS   = 1 << 16;
    parameter integer TIMEOUT      = 100000;  // pixel_proc::DEFAULT_TIMEOUT_CYCLES

    localparam integer CW = `ISA_DIM_COORD_BITS;
    localparam integer RW = `ISA_DIM_REG_BITS;
    localparam integer SW = `ISA_DIM_ST_BITS;

    reg                 clk, rst_n;
    reg                 scene_we, scene_cfg;
    reg  [RW-1:0]       scene_addr;
    reg  [95:0]         scene_data;
    wire                scene_ready;
    reg                 in_valid, out_ready;
    reg  [CW-1:0]       in_x, in_y;
    wire                in_ready, out_valid;
    wire [CW-1:0]       out_x, out_y;
    wire [CTX_BITS-1:0] out_ctx;
    wire [95:0]         out_rgb;
    wire [31:0]         out_cycles;

    wire                trace_valid, trace_take, trace_done;
    wire [CW-1:0]       trace_take_px, trace_take_py;
    wire [CTX_BITS-1:0] trace_ctx, trace_turn_ctx;
    wire [CW-1:0]       trace_px, trace_py;
    wire [SW-1:0]       trace_state;
    wire [RW-1:0]       trace_dst;
    wire [2:0]          trace_lanes;
    wire [95:0]         trace_value;
    reg  [SW-1:0]       fault_state;
    reg  [31:0]         fault_xor;

    fast_pp #(
        .RECIP_METHOD (RECIP_METHOD),
        .SQRT_METHOD  (SQRT_METHOD),
        .EXPOSURE     (EXPOSURE),
        .REFRACTION   (REFRACTION),
        .CTX_BITS     (CTX_BITS)
    ) dut (
        .clk            (clk),
        .rst_n          (rst_n),
        .scene_we       (scene_we),
        .scene_cfg      (scene_cfg),
        .scene_addr     (scene_addr),
        .scene_data     (scene_data),
        .scene_ready    (scene_ready),
        .in_valid       (in_valid),
        .in_ready       (in_ready),
        .in_x           (in_x),
        .in_y           (in_y),
        .out_valid      (out_valid),
        .out_ready      (out_ready),
        .out_x          (out_x),
        .out_y          (out_y),
        .out_ctx        (out_ctx),
        .out_rgb        (out_rgb),
        .out_cycles     (out_cycles),
        .trace_valid    (trace_valid),
        .trace_ctx      (trace_ctx),
        .trace_px       (trace_px),
        .trace_py       (trace_py),
        .trace_state    (trace_state),
        .trace_dst      (trace_dst),
        .trace_lanes    (trace_lanes),
        .trace_value    (trace_value),
        .trace_take     (trace_take),
        .trace_take_px  (trace_take_px),
        .trace_take_py  (trace_take_py),
        .trace_done     (trace_done),
        .trace_turn_ctx (trace_turn_ctx),
        .fault_state    (fault_state),
        .fault_xor      (fault_xor)
    );

    reg [111:0] writes [0:MAX_WRITES-1];
    reg [31:0]  pixels [0:MAX_PIXELS-1];

    `include "tb_clock.vh"

    `include "tb_stimulus.vh"

    integer      i, given, taken, quiet, cycle, first_in, last_out;
    integer      fault_state_arg;

    initial begin
        load_stimulus(" [+fault_state=S +fault_xor=H]");
        if (!$value$plusargs("fault_state=%d", fault_state_arg)) fault_state_arg = 0;
        if (!$value$plusargs("fault_xor=%h", fault_xor)) fault_xor = 32'd0;
        fault_state = fault_state_arg[SW-1:0];

        // Reset: rst_n low for two rising edges (verilated_owned.h).
        clk        = 1'b0;
        rst_n      = 1'b0;
        scene_we   = 1'b0;
        scene_cfg  = 1'b0;
        scene_addr = {RW{1'b0}};
        scene_data = 96'd0;
        in_valid   = 1'b0;
        in_x       = {CW{1'b0}};
        in_y       = {CW{1'b0}};
        out_ready  = 1'b0;
        fall; rise;
        fall; rise;
        rst_n = 1'b1;
        fall; rise;

        // The scene port: one write per rising edge while scene_ready.
        for (i = 0; i < n_writes; i = i + 1) begin
            fall;
            if (!scene_ready) begin
                $display("ERROR: scene write %0d while scene_ready is low", i);
                $finish;
            end
            scene_we   = 1'b1;
            scene_cfg  = writes[i][104];
            scene_addr = writes[i][96 +: RW];
            scene_data = writes[i][95:0];
            rise;
            scene_we   = 1'b0;
            scene_cfg  = 1'b0;
        end

        // The frame: a coordinate offered every cycle, out_ready high.
        given    = 0;
        taken    = 0;
        quiet    = 0;
        cycle    = 0;
        first_in = 0;
        last_out = 0;
        while (taken < n_pixels) begin
            fall;
            in_valid  = (given < n_pixels);
            in_x      = pixels[given % MAX_PIXELS][16 +: CW];
            in_y      = pixels[given % MAX_PIXELS][0 +: CW];
            out_ready = 1'b1;
            #1;
            cycle = cycle + 1;
            quiet = quiet + 1;
            if (in_valid && in_ready) begin
                if (given == 0) first_in = cycle;
                given = given + 1;
                quiet = 0;
            end
            if (trace_take) $display("TAKE %0d %0d %0d", trace_turn_ctx, trace_take_px, trace_take_py);
            if (trace_valid)
                $display("EV %0d %0d %0d %0d %0d %0d %h %h %h", trace_ctx, trace_px, trace_py, trace_state,
                         trace_dst, trace_lanes, trace_value[31:0], trace_value[63:32], trace_value[95:64]);
            if (out_valid && out_ready) begin
                $display("PIX %0d %0d %h %h %h %0d %0d", out_x, out_y, out_rgb[31:0], out_rgb[63:32],
                         out_rgb[95:64], out_cycles, out_ctx);
                taken    = taken + 1;
                last_out = cycle;
                quiet    = 0;
            end
            if (quiet > 2 * TIMEOUT + 16) begin
                $display("HUNG %0d %0d", taken, given);
                $finish;
            end
            rise;
        end
        $display("FRAME %0d", last_out - first_in + 1);
        $display("END");
        $finish;
    end

endmodule
`default_nettype wire
