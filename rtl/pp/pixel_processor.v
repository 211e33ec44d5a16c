`default_nettype none
`include "isa.vh"
`include "fp_defs.vh"
// ============================================================================
// pixel_processor -- pixel coordinates in, RGB out (thesis chapter 4)
// ============================================================================
// The controller (pp_ctrl) and the datapath (pp_core), the configuration
// register, and the scene port that loads both:
//
//   scene port --> cfg_q (scene_cfg = 1) or a scene register (scene_cfg = 0)
//   start, px, py --> pp_ctrl --instruction--> pp_core --flags--> pp_ctrl
//   done, rgb <-- PIX_DONE reads STK0_COL through read port A
//
// A pixel: start is taken at a rising edge while ready; the controller then
// spends exactly the cycles golden::micro predicts (one per instruction,
// latency + 1 per reciprocal or square root, PIX_DONE) and
// raises done for one cycle, in which rgb = STK0_COL (rgb is only valid
// with done). Scene writes are accepted only while ready.
//
// With PP_TRACE defined (the co-simulation; never for synthesis) the trace
// port shows every register-file write the ALU performs, in the cycle whose
// rising edge performs it: the issuing state, the physical destination, the
// lane mask and the written lanes (unwritten lanes read 0). fault_state and
// fault_xor inject one fault for the harness's self-test: lane x of every
// write in fault_state is XORed with fault_xor, in the register file too.
// ============================================================================
module pixel_processor #(
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT,
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT,
    parameter integer STACK_DEPTH  = `ISA_DIM_STK_COUNT,
    parameter integer REFRACTION   = 1   // 0: no refraction (scenes without transparent spheres only)
) (
    input  wire                           clk,
    input  wire                           rst_n,
    // Scene port.
    input  wire                           scene_we,
    input  wire                           scene_cfg,
    input  wire [`ISA_DIM_REG_BITS-1:0]   scene_addr,
    input  wire [95:0]                    scene_data,
    // Pixels.
    input  wire                           start,
    input  wire [`ISA_DIM_COORD_BITS-1:0] px,
    input  wire [`ISA_DIM_COORD_BITS-1:0] py,
    output wire                           ready,
    output wire                           done,
    output wire [95:0]                    rgb
`ifdef PP_TRACE
    ,
    output wire                           trace_valid,
    output wire [`ISA_DIM_ST_BITS-1:0]    trace_state,
    output wire [`ISA_DIM_REG_BITS-1:0]   trace_dst,
    output wire [2:0]                     trace_lanes,
    output wire [95:0]                    trace_value,
    input  wire [`ISA_DIM_ST_BITS-1:0]    fault_state,
    input  wire [31:0]                    fault_xor
`endif
);

    localparam integer RW = `ISA_DIM_REG_BITS;

    // ------------------------------------------------------------------------
    // Configuration register
    // ------------------------------------------------------------------------
    reg  [95:0] cfg_q;
    wire        cfg_we   = scene_we && scene_cfg && ready;
    wire        scene_rf = scene_we && !scene_cfg && ready;

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) cfg_q <= 96'd0;
        else if (cfg_we) cfg_q <= scene_data;
    end

    // ------------------------------------------------------------------------
    // Controller and datapath
    // ------------------------------------------------------------------------
    wire [`ISA_DIM_OP_BITS-1:0] op;
    wire [RW-1:0]               la_a, la_b, la_w;
    wire [2:0]                  wmask, sp;
    wire [`ISA_DIM_ST_BITS-1:0] state;
    wire [31:0]                 ix, iy;
    wire                        alu_done;
    wire [2:0]                  y_neg, y_pos, y_sign;

    pp_ctrl #(.REFRACTION(REFRACTION)) u_ctrl (
        .clk      (clk),
        .rst_n    (rst_n),
        .cfg      (cfg_q),
        .start    (start),
        .px       (px),
        .py       (py),
        .ready    (ready),
        .done     (done),
        .op       (op),
        .la_a     (la_a),
        .la_b     (la_b),
        .la_w     (la_w),
        .wmask    (wmask),
        .state    (state),
        .sp       (sp),
        .ix       (ix),
        .iy       (iy),
        .alu_done (alu_done),
        .y_neg    (y_neg),
        .y_pos    (y_pos),
        .y_sign   (y_sign)
    );

`ifdef PP_TRACE
    wire [31:0] wd_flip = (state == fault_state) ? fault_xor : 32'd0;
`else
    wire [31:0] wd_flip = 32'd0;
`endif

    wire          alu_we;
    wire [RW-1:0] alu_wa;
    wire [95:0]   alu_wd;

    pp_core #(
        .RECIP_METHOD (RECIP_METHOD),
        .SQRT_METHOD  (SQRT_METHOD),
        .STACK_DEPTH  (STACK_DEPTH),
        .REFRACTION   (REFRACTION)
    ) u_core (
        .clk        (clk),
        .rst_n      (rst_n),
        .op         (op),
        .la_a       (la_a),
        .la_b       (la_b),
        .la_w       (la_w),
        .wmask      (wmask),
        .sp         (sp),
        .ix         (ix),
        .iy         (iy),
        .alu_done   (alu_done),
        .y_neg      (y_neg),
        .y_pos      (y_pos),
        .y_sign     (y_sign),
        .rd_a       (rgb),
        .scene_we   (scene_rf),
        .scene_addr (scene_addr),
        .scene_data (scene_data),
        .wd_flip    (wd_flip),
        .alu_we     (alu_we),
        .alu_wa     (alu_wa),
        .alu_wd     (alu_wd)
    );

`ifdef PP_TRACE
    assign trace_valid = alu_we;
    assign trace_state = state;
    assign trace_dst   = alu_wa;
    assign trace_lanes = wmask;
    assign trace_value = alu_wd & {{32{wmask[2]}}, {32{wmask[1]}}, {32{wmask[0]}}};
`else
    // Without the trace port the write-port signals only feed the memory.
    wire unused_trace = ^{alu_we, alu_wa, alu_wd, state};
`endif

endmodule
`default_nettype wire
