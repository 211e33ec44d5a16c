`default_nettype none
`include "isa.vh"
`include "fp_defs.vh"
// ============================================================================
// top_tb -- the top module (rtl/top.v) under Icarus Verilog (tests/icarus.rs)
// ============================================================================
// The stream protocol of harness/cpp/top.cpp, in Verilog: the same reset, the
// scene written through the broadcast scene port while scene_ready, then the
// pixels fed through the in stream while the result stream is drained with
// out_ready low in a random STALL percent of the cycles ($random, SEED).
//
// Stimulus, written by the Rust test ($readmemh, plusargs), as pp_tb.v:
//   +scene=FILE +writes=N  N scene-port writes, 28 hex digits each:
//                          {8'cfg, 8'addr, 96'data} (data lane x = bits 31:0)
//   +pixels=FILE +count=M  M pixels, 8 hex digits each: {16'x, 16'y}
//   +seed=S +stall=P       backpressure: out_ready low in P% of the cycles
// Output on stdout, one line per result in the order they leave the top:
//   PIX x y rgb_x rgb_y rgb_z cycles proc
// then END, or `HUNG taken given` if no result comes for TIMEOUT cycles.
//
// Not under rtl/: a second top there would fail the whole-tree lint.
// ============================================================================
module top_tb;

    parameter integer N            = 2;
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT;
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT;
    parameter integer MAX_WRITES   = 1 << `ISA_DIM_REG_BITS;
    parameter integer MAX_PIXELS   = 1 << 16;
    parameter integer TIMEOUT      = 100000;  // pixel_proc::DEFAULT_TIMEOUT_CYCLES

    localparam integer CW = `ISA_DIM_COORD_BITS;
    localparam integer RW = `ISA_DIM_REG_BITS;
    localparam integer PW = (N > 1) ? $clog2(N) : 1;

    reg           clk, rst_n;
    reg           scene_we, scene_cfg;
    reg  [RW-1:0] scene_addr;
    reg  [95:0]   scene_data;
    wire          scene_ready;
    reg           in_valid, out_ready;
    reg  [CW-1:0] in_x, in_y;
    wire          in_ready, out_valid, raster_busy;
    wire [CW-1:0] out_x, out_y;
    wire [PW-1:0] out_proc;
    wire [95:0]   out_rgb;
    wire [31:0]   out_cycles;

    top #(
        .N            (N),
        .RECIP_METHOD (RECIP_METHOD),
        .SQRT_METHOD  (SQRT_METHOD)
    ) dut (
        .clk          (clk),
        .rst_n        (rst_n),
        .scene_we     (scene_we),
        .scene_cfg    (scene_cfg),
        .scene_addr   (scene_addr),
        .scene_data   (scene_data),
        .scene_ready  (scene_ready),
        .raster_mode  (1'b0),
        .raster_start (1'b0),
        .win_x0       ({CW{1'b0}}),
        .win_y0       ({CW{1'b0}}),
        .win_x1       ({CW{1'b0}}),
        .win_y1       ({CW{1'b0}}),
        .raster_busy  (raster_busy),
        .in_valid     (in_valid),
        .in_ready     (in_ready),
        .in_x         (in_x),
        .in_y         (in_y),
        .out_valid    (out_valid),
        .out_ready    (out_ready),
        .out_x        (out_x),
        .out_y        (out_y),
        .out_proc     (out_proc),
        .out_rgb      (out_rgb),
        .out_cycles   (out_cycles)
    );

    reg [111:0] writes [0:MAX_WRITES-1];
    reg [31:0]  pixels [0:MAX_PIXELS-1];

    `include "tb_clock.vh"

    `include "tb_stimulus.vh"

    integer      i, given, taken, quiet, seed, stall;

    initial begin
        load_stimulus(" [+seed=S +stall=P]");
        if (!$value$plusargs("seed=%d", seed)) seed = 1;
        if (!$value$plusargs("stall=%d", stall)) stall = 0;

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

        given = 0;
        taken = 0;
        quiet = 0;
        while (taken < n_pixels) begin
            fall;
            in_valid  = (given < n_pixels);
            in_x      = pixels[given % MAX_PIXELS][16 +: CW];
            in_y      = pixels[given % MAX_PIXELS][0 +: CW];
            out_ready = ($unsigned($random(seed)) % 100) >= stall;
            #1;
            if (in_valid && in_ready) given = given + 1;
            quiet = quiet + 1;
            if (out_valid && out_ready) begin
                $display("PIX %0d %0d %h %h %h %0d %0d", out_x, out_y, out_rgb[31:0], out_rgb[63:32],
                         out_rgb[95:64], out_cycles, out_proc);
                taken = taken + 1;
                quiet = 0;
            end
            if (quiet >= TIMEOUT) begin
                $display("HUNG %0d %0d", taken, given);
                $finish;
            end
            rise;
        end
        $display("END");
        $finish;
    end

endmodule
`default_nettype wire
