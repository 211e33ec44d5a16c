`default_nettype none
`include "isa.vh"
// ============================================================================
// memory -- the pixel processor's register file (thesis 4.4)
// ============================================================================
// Vector registers of three float32 lanes {z, y, x}, two asynchronous read
// ports and one write port whose lanes are written separately (wmask bit 0 =
// lane x), at the rising edge of clk. Addresses are physical (mem_ctrl has
// decoded CUR/PAR already). Two banks, one array per lane each:
//   registers  0 .. ISA_REG_CUR_O - 1: scene registers, constants and
//              temporaries
//   stack      ISA_REG_STK0_O + STK_STRIDE * level + field, level < STACK_DEPTH
//   refraction ISA_REG_TRN0 + k, k < ISA_DIM_TRN_COUNT (REFRACTION = 1 only)
// Every other address (the logical CUR/PAR codes, levels past STACK_DEPTH)
// has no storage: it reads as 0 and writes to it are dropped.
//
// Addresses go to the arrays unconditionally and only the write enables are
// gated (thesis figures 18/19). The contents have no reset: the scene port
// and the program write every register before it is read.
// ============================================================================
module memory #(
    parameter integer STACK_DEPTH = `ISA_DIM_STK_COUNT,
    parameter integer REFRACTION  = 1   // 0: no TRN registers (a scene without refraction)
) (
    input  wire                         clk,
    input  wire [`ISA_DIM_REG_BITS-1:0] ra_a,
    input  wire [`ISA_DIM_REG_BITS-1:0] ra_b,
    output wire [95:0]                  rd_a,
    output wire [95:0]                  rd_b,
    input  wire                         we,
    input  wire [`ISA_DIM_REG_BITS-1:0] wa,
    input  wire [2:0]                   wmask,
    input  wire [95:0]                  wd
);

    localparam integer RB        = `ISA_DIM_REG_BITS;
    localparam integer REG_WORDS = `ISA_REG_CUR_O;
    localparam integer STK_WORDS = STACK_DEPTH * `ISA_DIM_STK_STRIDE;
    localparam integer STK_BITS  = $clog2(STK_WORDS);
    localparam integer REG_BITS  = $clog2(REG_WORDS);
    localparam integer TRN_WORDS = `ISA_DIM_TRN_COUNT;
    localparam integer TRN_BITS  = $clog2(TRN_WORDS);
    localparam [RB-1:0] TRN0     = `ISA_REG_TRN0;

    localparam [RB-1:0] REG_END = `ISA_REG_CUR_O;
    localparam [RB-1:0] STK0_O  = `ISA_REG_STK0_O;
    localparam [RB:0]   STK_END = STK_WORDS[RB:0];  // one bit more: 32 words end at 128

    // ------------------------------------------------------------------------
    // Address decoding: bank and index within the stack bank
    // ------------------------------------------------------------------------
    wire          a_in_reg = (ra_a < REG_END);
    wire          b_in_reg = (ra_b < REG_END);
    wire          w_in_reg = (wa < REG_END);
    wire [RB-1:0] a_off    = ra_a - STK0_O;
    wire [RB-1:0] b_off    = ra_b - STK0_O;
    wire [RB-1:0] w_off    = wa - STK0_O;
    wire          a_in_stk = (ra_a >= STK0_O) && ({1'b0, a_off} < STK_END);
    wire          b_in_stk = (ra_b >= STK0_O) && ({1'b0, b_off} < STK_END);
    wire          w_in_stk = (wa >= STK0_O) && ({1'b0, w_off} < STK_END);

    wire          a_in_trn = REFRACTION != 0 && (ra_a[RB-1:TRN_BITS] == TRN0[RB-1:TRN_BITS]);
    wire          b_in_trn = REFRACTION != 0 && (ra_b[RB-1:TRN_BITS] == TRN0[RB-1:TRN_BITS]);
    wire          w_in_trn = REFRACTION != 0 && (wa[RB-1:TRN_BITS] == TRN0[RB-1:TRN_BITS]);

    // The range checks use the whole address or offset, the arrays its low
    // bits.
    wire [REG_BITS-1:0] a_reg = ra_a[REG_BITS-1:0];
    wire [REG_BITS-1:0] b_reg = ra_b[REG_BITS-1:0];
    wire [REG_BITS-1:0] w_reg = wa[REG_BITS-1:0];
    wire [STK_BITS-1:0] a_idx = a_off[STK_BITS-1:0];
    wire [STK_BITS-1:0] b_idx = b_off[STK_BITS-1:0];
    wire [STK_BITS-1:0] w_idx = w_off[STK_BITS-1:0];

    // ------------------------------------------------------------------------
    // Storage, one array per lane and bank
    // ------------------------------------------------------------------------
    genvar gl;
    generate
        for (gl = 0; gl < 3; gl = gl + 1) begin : g_lane
            reg [31:0] regs_q  [0:REG_WORDS-1];
            reg [31:0] stack_q [0:STK_WORDS-1];
            reg [31:0] trn_q   [0:TRN_WORDS-1];

            always @(posedge clk) begin
                if (we && wmask[gl] && w_in_reg) regs_q[w_reg] <= wd[32*gl +: 32];
                if (we && wmask[gl] && w_in_stk) stack_q[w_idx] <= wd[32*gl +: 32];
                if (we && wmask[gl] && w_in_trn) trn_q[wa[TRN_BITS-1:0]] <= wd[32*gl +: 32];
            end

            assign rd_a[32*gl +: 32] = a_in_reg ? regs_q[a_reg]
                                     : a_in_stk ? stack_q[a_idx]
                                     : a_in_trn ? trn_q[ra_a[TRN_BITS-1:0]] : 32'd0;
            assign rd_b[32*gl +: 32] = b_in_reg ? regs_q[b_reg]
                                     : b_in_stk ? stack_q[b_idx]
                                     : b_in_trn ? trn_q[ra_b[TRN_BITS-1:0]] : 32'd0;
        end
    endgenerate

endmodule
`default_nettype wire
