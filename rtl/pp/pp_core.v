`default_nettype none
`include "isa.vh"
`include "fp_defs.vh"
`include "alu_ctrl.vh"
// ============================================================================
// pp_core -- the pixel processor's datapath (thesis 4.1, figure 11)
// ============================================================================
// The ALU with its controller, and the register file with its memory
// controller, driven by one instruction per cycle from pp_ctrl:
//
//   la_a, la_b --mem_ctrl(sp)--> memory read ports --> alu --> y, flags
//   la_w       --mem_ctrl(sp)--> memory write port <-- y (lanes of wmask)
//
// The write enable is the only thing the ALU's result gates: the register
// file is written when the opcode writes (alu_ctrl) and the instruction
// completes (alu done). While the controller is idle the scene port owns the
// write port (whole vectors).
//
// wd_flip is XORed into lane x of every ALU write: tied to 0 except by the
// fault-injection test of the co-simulation (pixel_processor, PP_TRACE).
// ============================================================================
module pp_core #(
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT,
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT,
    parameter integer STACK_DEPTH  = `ISA_DIM_STK_COUNT,
    parameter integer REFRACTION   = 1   // 0: no refraction registers (memory)
) (
    input  wire                          clk,
    input  wire                          rst_n,
    // The instruction (pp_ctrl).
    input  wire [`ISA_DIM_OP_BITS-1:0]   op,
    input  wire [`ISA_DIM_REG_BITS-1:0]  la_a,
    input  wire [`ISA_DIM_REG_BITS-1:0]  la_b,
    input  wire [`ISA_DIM_REG_BITS-1:0]  la_w,
    input  wire [2:0]                    wmask,
    input  wire [2:0]                    sp,
    input  wire [31:0]                   ix,
    input  wire [31:0]                   iy,
    output wire                          alu_done,
    output wire [2:0]                    y_neg,
    output wire [2:0]                    y_pos,
    output wire [2:0]                    y_sign,
    output wire [95:0]                   rd_a,
    // The scene port (only while the controller is idle).
    input  wire                          scene_we,
    input  wire [`ISA_DIM_REG_BITS-1:0]  scene_addr,
    input  wire [95:0]                   scene_data,
    input  wire [31:0]                   wd_flip,
    // The ALU's register-file write, as performed (the trace port).
    output wire                          alu_we,
    output wire [`ISA_DIM_REG_BITS-1:0]  alu_wa,
    output wire [95:0]                   alu_wd
);

    localparam integer RW = `ISA_DIM_REG_BITS;

    wire [`ALU_CTRL_W-1:0] ctrl;
    wire                   writes_rf;

    alu_ctrl u_alu_ctrl (
        .op        (op),
        .ctrl      (ctrl),
        .writes_rf (writes_rf)
    );

    wire [RW-1:0] pa_a, pa_b, pa_w;

    mem_ctrl #(.STACK_DEPTH(STACK_DEPTH)) u_mem_ctrl (
        .sp   (sp),
        .la_a (la_a),
        .la_b (la_b),
        .la_w (la_w),
        .pa_a (pa_a),
        .pa_b (pa_b),
        .pa_w (pa_w)
    );

    wire [95:0] rd_b;
    wire [95:0] y;

    alu #(
        .RECIP_METHOD (RECIP_METHOD),
        .SQRT_METHOD  (SQRT_METHOD)
    ) u_alu (
        .clk    (clk),
        .rst_n  (rst_n),
        .ctrl   (ctrl),
        .a      (rd_a),
        .b      (rd_b),
        .ix     (ix),
        .iy     (iy),
        .y      (y),
        .done   (alu_done),
        .y_neg  (y_neg),
        .y_pos  (y_pos),
        .y_sign (y_sign)
    );

    assign alu_we = writes_rf && alu_done;
    assign alu_wa = pa_w;
    assign alu_wd = {y[95:32], y[31:0] ^ wd_flip};

    memory #(.STACK_DEPTH(STACK_DEPTH), .REFRACTION(REFRACTION)) u_memory (
        .clk   (clk),
        .ra_a  (pa_a),
        .ra_b  (pa_b),
        .rd_a  (rd_a),
        .rd_b  (rd_b),
        .we    (alu_we || scene_we),
        .wa    (scene_we ? scene_addr : pa_w),
        .wmask (scene_we ? 3'b111 : wmask),
        .wd    (scene_we ? scene_data : alu_wd)
    );

endmodule
`default_nettype wire
