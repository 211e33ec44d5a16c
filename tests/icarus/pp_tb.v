`default_nettype none
`include "isa.vh"
`include "fp_defs.vh"
// ============================================================================
// pp_tb -- the pixel processor under Icarus Verilog (tests/icarus.rs)
// ============================================================================
// The clock loop of harness/cpp/pixel_proc.cpp, in Verilog: the same reset,
// the same scene-port writes, the same pixel protocol and the same cycle
// count (every cycle with ready low, sampled with clk low, from the one after
// the start edge up to and including the one with done high).
//
// Stimulus, written by the Rust test ($readmemh, plusargs):
//   +scene=FILE +writes=N  N scene-port writes, one per line, 28 hex digits:
//                          {8'cfg, 8'addr, 96'data} (data lane x = bits 31:0)
//   +pixels=FILE +count=M  M pixels, one per line, 8 hex digits: {16'x, 16'y}
//   +mutsel=N              (with MUTANTS defined) the mutant of the netlist
// Output, one line per pixel on stdout:
//   PIX x y rgb_x rgb_y rgb_z cycles   (rgb lanes r, g, b as f32 bits, hex)
// or `HUNG x y cycles` and the simulation stops.
//
// Not under rtl/: the whole-tree lint names no top, so a second top there
// would fail it.
// ============================================================================
module pp_tb;

    parameter integer RECIP_METHOD = `FP_METHOD_EXACT;
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT;
    parameter integer STACK_DEPTH  = `ISA_DIM_STK_COUNT;
    parameter integer REFRACTION   = 1;
    parameter integer MAX_WRITES   = 1 << `ISA_DIM_REG_BITS;
    parameter integer MAX_PIXELS   = 1 << 16;
    parameter integer TIMEOUT      = 100000;  // pixel_proc::DEFAULT_TIMEOUT_CYCLES

    localparam integer CW = `ISA_DIM_COORD_BITS;
    localparam integer RW = `ISA_DIM_REG_BITS;

    reg           clk, rst_n;
    reg           scene_we, scene_cfg;
    reg  [RW-1:0] scene_addr;
    reg  [95:0]   scene_data;
    reg           start;
    reg  [CW-1:0] px, py;
    wire          ready, done;
    wire [95:0]   rgb;

    `define PP_TB_PORTS \
        .clk        (clk), \
        .rst_n      (rst_n), \
        .scene_we   (scene_we), \
        .scene_cfg  (scene_cfg), \
        .scene_addr (scene_addr), \
        .scene_data (scene_data), \
        .start      (start), \
        .px         (px), \
        .py         (py), \
        .ready      (ready), \
        .done       (done), \
        .rgb        (rgb)
`ifdef MUTANTS
    // The netlist of rtl/mutate/mutants.sh (tests/mutation.rs): elaborated
    // by Yosys with the exact methods and the default depth (no parameters
    // left), with PP_TRACE's ports (the fault port held at 0) and `mutsel`,
    // the mutant (0: none), from +mutsel=N.
    reg [15:0] mutsel;
    initial if (!$value$plusargs("mutsel=%d", mutsel)) mutsel = 16'd0;
    pixel_processor dut (
        `PP_TB_PORTS,
        .trace_valid (),
        .trace_state (),
        .trace_dst   (),
        .trace_lanes (),
        .trace_value (),
        .fault_state ({`ISA_DIM_ST_BITS{1'b0}}),
        .fault_xor   (32'd0),
        .mutsel      (mutsel)
    );
`else
    pixel_processor #(
        .RECIP_METHOD (RECIP_METHOD),
        .SQRT_METHOD  (SQRT_METHOD),
        .STACK_DEPTH  (STACK_DEPTH),
        .REFRACTION   (REFRACTION)
    ) dut (
        `PP_TB_PORTS
    );
`endif
    `undef PP_TB_PORTS

    reg [111:0] writes [0:MAX_WRITES-1];
    reg [31:0]  pixels [0:MAX_PIXELS-1];

    `include "tb_clock.vh"

    // fall, and stop the simulation unless ready: the port protocol takes
    // scene writes and pixels only while the controller is idle.
    task fall_ready(input [8*16-1:0] what, input integer n);
        begin
            fall;
            if (!ready) begin
                $display("ERROR: %0s %0d while not ready", what, n);
                $finish;
            end
        end
    endtask

    `include "tb_stimulus.vh"

    integer      i, cycles, edges;
    reg          finished, trace;

`ifndef MUTANTS
    // +trace: every cycle of every pixel, for a human chasing a difference
    // (the RTL's hierarchy; a mutant netlist is flat).
    always @(negedge clk)
        if (trace && !ready)
            $display("  st %0d op %0d la %0d %0d %0d pa %0d %0d %0d sp %0d we %b y %h flags -%b +%b",
                     dut.u_ctrl.st_q, dut.u_ctrl.op, dut.u_ctrl.la_a, dut.u_ctrl.la_b, dut.u_ctrl.la_w,
                     dut.u_core.pa_a, dut.u_core.pa_b, dut.u_core.pa_w, dut.u_ctrl.sp, dut.u_core.alu_we,
                     dut.u_core.alu_wd, dut.u_core.y_neg, dut.u_core.y_pos);
`endif

    initial begin
        load_stimulus("");
        trace = $test$plusargs("trace");

        // Reset: rst_n low for two rising edges.
        clk        = 1'b0;
        rst_n      = 1'b0;
        scene_we   = 1'b0;
        scene_cfg  = 1'b0;
        scene_addr = {RW{1'b0}};
        scene_data = 96'd0;
        start      = 1'b0;
        px         = {CW{1'b0}};
        py         = {CW{1'b0}};
        fall; rise;
        fall; rise;
        rst_n = 1'b1;
        fall; rise;

        // The scene port: one write per rising edge while ready.
        for (i = 0; i < n_writes; i = i + 1) begin
            fall_ready("scene write", i);
            scene_we   = 1'b1;
            scene_cfg  = writes[i][104];
            scene_addr = writes[i][96 +: RW];
            scene_data = writes[i][95:0];
            rise;
            scene_we   = 1'b0;
            scene_cfg  = 1'b0;
        end

        for (i = 0; i < n_pixels; i = i + 1) begin
            fall_ready("pixel", i);
            px    = pixels[i][16 +: CW];
            py    = pixels[i][0 +: CW];
            start = 1'b1;
            rise;  // the controller leaves IDLE at this edge
            start = 1'b0;
            cycles   = 0;
            edges    = 0;
            finished = 1'b0;
            while (!finished) begin
                fall;
                edges = edges + 1;
                if (!ready) cycles = cycles + 1;
                if (done) begin
                    $display("PIX %0d %0d %h %h %h %0d", px, py, rgb[31:0], rgb[63:32], rgb[95:64], cycles);
                    rise;  // back to IDLE
                    finished = 1'b1;
                end else if (ready || edges >= TIMEOUT) begin
                    $display("HUNG %0d %0d %0d", px, py, cycles);
                    $finish;
                end else
                    rise;
            end
        end
        $display("END");
        $finish;
    end

endmodule
`default_nettype wire
