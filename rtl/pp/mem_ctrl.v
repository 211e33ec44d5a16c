`default_nettype none
`include "isa.vh"
// ============================================================================
// mem_ctrl -- the memory controller: logical to physical register addresses
// ============================================================================
// Thesis 4.5; golden::micro::isa::decode is the spec. The controller names
// the ray stack only relative to the stack pointer sp:
//   CUR_<f> (ISA_REG_CUR_O + f) -> ISA_REG_STK0_O + sp       * STK_STRIDE + f
//   PAR_<f> (ISA_REG_PAR_O + f) -> ISA_REG_STK0_O + (sp - 1) * STK_STRIDE + f
// and every other address is itself, except that the root ray's origin and
// weight are the constants EYE and ONE: STK0_O decodes to ISA_REG_EYE and
// STK0_W to ISA_REG_ONE (no instruction sets them). Purely combinational,
// one decoder per port (read A, read B, write), all three alike.
//
// Where golden's decode has no answer (PAR_* at sp = 0, or a level at or
// past STACK_DEPTH) the logical code passes through unchanged: CUR/PAR codes
// are never physical, so such a read returns 0 and such a write is dropped by
// the memory, and the code on the write port shows what went wrong.
//
// sp is $clog2(ISA_DIM_STK_COUNT) = 3 bits wide whatever STACK_DEPTH is.
// ============================================================================
module mem_ctrl #(
    parameter integer STACK_DEPTH = `ISA_DIM_STK_COUNT
) (
    input  wire [$clog2(`ISA_DIM_STK_COUNT)-1:0] sp,
    input  wire [`ISA_DIM_REG_BITS-1:0]          la_a,
    input  wire [`ISA_DIM_REG_BITS-1:0]          la_b,
    input  wire [`ISA_DIM_REG_BITS-1:0]          la_w,
    output wire [`ISA_DIM_REG_BITS-1:0]          pa_a,
    output wire [`ISA_DIM_REG_BITS-1:0]          pa_b,
    output wire [`ISA_DIM_REG_BITS-1:0]          pa_w
);

    localparam integer RB         = `ISA_DIM_REG_BITS;
    localparam integer SP_BITS    = $clog2(`ISA_DIM_STK_COUNT);
    localparam integer FIELD_BITS = $clog2(`ISA_DIM_STK_STRIDE);

    localparam [RB-1:0]      CUR_O  = `ISA_REG_CUR_O;
    localparam [RB-1:0]      PAR_O  = `ISA_REG_PAR_O;
    localparam [RB-1:0]      STK0_O = `ISA_REG_STK0_O;
    localparam [RB-1:0]      STK0_W = `ISA_REG_STK0_W;
    localparam [RB-1:0]      EYE    = `ISA_REG_EYE;
    localparam [RB-1:0]      ONE    = `ISA_REG_ONE;
    localparam [RB-1:0]      STRIDE = `ISA_DIM_STK_STRIDE;
    localparam [SP_BITS-1:0] SP_0   = {SP_BITS{1'b0}};
    localparam [SP_BITS:0]   DEPTH  = STACK_DEPTH[SP_BITS:0];

    // ------------------------------------------------------------------------
    // One decoder per port
    // ------------------------------------------------------------------------
    // A pure function of the address and the stack pointer: a continuous
    // assignment re-evaluates a function only when its arguments change, so
    // everything it reads is an argument (the same meaning in every
    // simulator, and sp changes with la unchanged on back-to-back POPs).
    // Inside either range the field (la - CUR_O or la - PAR_O) is below
    // STK_STRIDE, so the difference of the low FIELD_BITS bits is all of it.
    function [RB-1:0] decode(input [RB-1:0] la, input [SP_BITS-1:0] level);
        reg [RB-1:0]         cur_base, par_base;
        reg                  cur_ok, par_ok, is_cur, is_par;
        reg [FIELD_BITS-1:0] field;
        begin
            // The current and parent levels' first addresses, and whether
            // those levels exist.
            cur_base = STK0_O + {{(RB-SP_BITS){1'b0}}, level} * STRIDE;
            par_base = cur_base - STRIDE;
            cur_ok   = ({1'b0, level} < DEPTH);
            par_ok   = (level != SP_0) && ({1'b0, level} <= DEPTH);
            is_cur   = (la >= CUR_O) && (la < CUR_O + STRIDE);
            is_par   = (la >= PAR_O) && (la < PAR_O + STRIDE);
            field    = la[FIELD_BITS-1:0]
                       - (is_par ? PAR_O[FIELD_BITS-1:0] : CUR_O[FIELD_BITS-1:0]);
            decode = la;
            if (is_cur && cur_ok)
                decode = cur_base + {{(RB-FIELD_BITS){1'b0}}, field};
            else if (is_par && par_ok)
                decode = par_base + {{(RB-FIELD_BITS){1'b0}}, field};
            if (decode == STK0_O)
                decode = EYE;
            else if (decode == STK0_W)
                decode = ONE;
        end
    endfunction

    assign pa_a = decode(la_a, sp);
    assign pa_b = decode(la_b, sp);
    assign pa_w = decode(la_w, sp);

endmodule
`default_nettype wire
