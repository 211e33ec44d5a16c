`default_nettype none
`include "isa.vh"
// ============================================================================
// fast_regfile -- the fast processor's register file: block RAM, registered
//                 reads, one write port, one set of temporaries and one ray
//                 stack per pixel context
// ============================================================================
// Vector registers of three float32 lanes {z, y, x} (x = bits 31:0) at the
// physical addresses of isa.vh (rtl/pp/mem_ctrl.v decodes CUR/PAR first):
//
//   scene      0 .. ISA_REG_T0 - 1: the scene's registers and the constants,
//              one table every context reads; written only through the
//              scene port (swe)
//   context    the temporaries ISA_REG_T0 .. ISA_REG_CUR_O - 1 and the
//              stack ISA_REG_STK0_O + STK_STRIDE * level + field, level <
//              STACK_DEPTH, one copy per context: entry {ctx, address[5:0]}
//              (the temporaries are 76..87, entries 12..23; the stack
//              96..127, entries 32..63), written through the write port (we)
//              lane by lane (wmask bit 0 = lane x)
//
// Every other address has no storage: it reads as +0, and writes to it (and
// writes to the scene table through the write port) are dropped.
//
// Two read ports, each its own copy of every table (both copies take every
// write): addresses in a cycle, data two clock edges later (the block RAM's
// registered read, then the output register after the table's select). A
// read at the edge of a write to the same word returns the old contents;
// the barrel never reads a word of a context in the edge its write lands.
// No reset: the scene port and the program write every register before it
// is read.
// ============================================================================
module fast_regfile #(
    parameter integer STACK_DEPTH = `ISA_DIM_STK_COUNT,
    parameter integer CTX_BITS    = 5,
    parameter integer REFRACTION  = 1   // 0: no refraction bank (a scene table of 128 words)
) (
    input  wire                         clk,
    // Reads, two edges
    input  wire [CTX_BITS-1:0]          r_ctx,
    input  wire [`ISA_DIM_REG_BITS-1:0] ra_a,
    input  wire [`ISA_DIM_REG_BITS-1:0] ra_b,
    output wire [95:0]                  rd_a,
    output wire [95:0]                  rd_b,
    // The write port (a context's temporaries and stack)
    input  wire                         we,
    input  wire [CTX_BITS-1:0]          w_ctx,
    input  wire [`ISA_DIM_REG_BITS-1:0] wa,
    input  wire [2:0]                   wmask,
    input  wire [95:0]                  wd,
    // The scene port (the scene table)
    input  wire                         swe,
    input  wire [`ISA_DIM_REG_BITS-1:0] swa,
    input  wire [95:0]                  swd
);

    localparam integer RB         = `ISA_DIM_REG_BITS;
    localparam integer ENTRY_BITS = CTX_BITS + 6;
    localparam integer STK_END_I  = `ISA_REG_STK0_O + STACK_DEPTH * `ISA_DIM_STK_STRIDE;

    localparam [RB-1:0] T0       = `ISA_REG_T0;
    localparam [RB-1:0] TEMP_END = `ISA_REG_CUR_O;
    localparam [RB-1:0] STK0_O   = `ISA_REG_STK0_O;
    localparam [RB:0]   STK_END  = STK_END_I[RB:0];  // one bit wider than an address
    localparam integer  TRN_END_I = `ISA_REG_TRN0 + `ISA_DIM_TRN_COUNT * `ISA_DIM_TRN_STRIDE;
    localparam [RB-1:0] TRN0     = `ISA_REG_TRN0;
    localparam [RB:0]   TRN_END  = TRN_END_I[RB:0];
    // The scene table's address bits: the refraction bank lies above 127.
    localparam integer  SB       = REFRACTION != 0 ? RB : RB - 1;
    localparam integer  SCENE_WORDS = 1 << SB;
    localparam [RB:0]   SCENE_END = SCENE_WORDS[RB:0];

    // Which table an address is in: the scene's registers (the refraction
    // bank TRN0..7 among them, scene constants too) or a context's.
    localparam [1:0] T_NONE = 2'd0, T_SCENE = 2'd1, T_CTX = 2'd2;

    function [1:0] table_of(input [RB-1:0] addr);
        if (addr < T0 || (REFRACTION != 0 && addr >= TRN0 && {1'b0, addr} < TRN_END))
            table_of = T_SCENE;
        else if (addr < TEMP_END || (addr >= STK0_O && {1'b0, addr} < STK_END))
            table_of = T_CTX;
        else
            table_of = T_NONE;
    endfunction

    wire                  w_ctx_ok = we & (table_of(wa) == T_CTX);
    wire [ENTRY_BITS-1:0] w_entry  = {w_ctx, wa[5:0]};
    // A scene write outside the table is dropped (only above 127, without
    // refraction).
    wire                  sw_ok    = swe & ({1'b0, swa} < SCENE_END);

    // The two read ports, each with its copy of the tables.
    wire [RB-1:0]  ra [0:1];
    wire [95:0]    rd [0:1];
    assign ra[0] = ra_a;
    assign ra[1] = ra_b;
    assign rd_a  = rd[0];
    assign rd_b  = rd[1];

    genvar gp, gl;
    generate
        for (gp = 0; gp < 2; gp = gp + 1) begin : g_port
            reg [1:0] table_q;
            always @(posedge clk) table_q <= table_of(ra[gp]);
            reg [95:0] out_q;
            for (gl = 0; gl < 3; gl = gl + 1) begin : g_lane
                reg [31:0] ctx_mem   [0:(1 << ENTRY_BITS)-1];
                reg [31:0] scene_mem [0:(1 << SB)-1];
                reg [31:0] ctx_q, scene_q;
                always @(posedge clk) begin
                    if (w_ctx_ok && wmask[gl]) ctx_mem[w_entry] <= wd[32*gl +: 32];
                    if (sw_ok) scene_mem[swa[SB-1:0]] <= swd[32*gl +: 32];
                    ctx_q   <= ctx_mem[{r_ctx, ra[gp][5:0]}];
                    scene_q <= scene_mem[ra[gp][SB-1:0]];
                end
                always @(posedge clk) begin
                    case (table_q)
                        T_SCENE: out_q[32*gl +: 32] <= scene_q;
                        T_CTX:   out_q[32*gl +: 32] <= ctx_q;
                        default: out_q[32*gl +: 32] <= 32'd0;
                    endcase
                end
            end
            assign rd[gp] = out_q;
        end
    endgenerate

endmodule
`default_nettype wire
