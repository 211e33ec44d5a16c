`default_nettype none
`include "isa.vh"
`include "alu_ctrl.vh"
// ============================================================================
// alu_ctrl -- the ALU controller: opcode to datapath controls (thesis 4.3)
// ============================================================================
// Purely combinational decoding of an isa.vh opcode into the packed control
// word of alu_ctrl.vh, which pp_core wires straight into alu.ctrl, plus
// whether the opcode writes the register file when it completes.
//
//   opcode   B lanes (x,y,z)  adders                     F                  y
//   ADD      -                A + B                      hold               sums
//   SUB      -                A + B, B sign flipped      hold               sums
//   MUL      x, y, z          -                          hold               products
//   NMUL     x, y, z          -                          hold               -products
//   MULX     x, x, x          -                          hold               products
//   MULY     y, y, y          -                          hold               products
//   MULZ     z, z, z          -                          hold               products
//   NMULX    x, x, x          -                          hold               -products
//   MUL2X    x, x, x          -                          hold               2 * products (exact)
//   MULR1    y, z, x          -                          hold               products
//   MULR2    z, x, y          -                          hold               products
//   MOV      -                -                          hold               A
//   NEG      -                -                          hold               -A
//   ITOF     -                -                          hold               itof
//   DOT1     x, y, z          -                          products           (none)
//   DOT2     -                x: F.x + F.y               <sx, F.y, F.z>     (none)
//   DOT3     -                x: F.x + F.z               hold               sums (x)
//   ISECT1   x, y, z          -                          -products          (none)
//   ISECT2   x, y, z          x: F.x + F.y               <sx, F.y, F.z>     products
//   ISECT3   -                x: A.x + A.y, y: F.x + F.z <sx, sy, A.z>      (none)
//   ISECT4   -                x: A.x + F.y, y: F.x + F.z <sx, sy, +0>       Y = F
//   RECIP    -                -                          hold               1 / A.x
//   RECIPY   -                -                          hold               1 / A.y
//   SQRT     -                -                          hold               sqrt(A.x)
//   ROOTS    -                -                          hold               <sqrt(A.x), 1 / A.x, +0>
//   EXP      -                -                          hold               <e^A.x, e^A.y, e^A.z>
//
// NOP and the unassigned opcodes decode to all-default controls: y = +0,
// F held, single-cycle, no register-file write.
// ============================================================================
module alu_ctrl (
    input  wire [`ISA_DIM_OP_BITS-1:0] op,
    output wire [`ALU_CTRL_W-1:0]      ctrl,
    output wire                        writes_rf
);

    reg [1:0] b_lane_x, b_lane_y, b_lane_z;
    reg       neg_b, neg_mul, neg_a;
    reg       addx_a_f, addy_f;
    reg [1:0] addx_b;
    reg [2:0] f_sel, res_sel;
    reg       unit_a_y;
    reg       roots;
    reg       double;
    reg       exp;
    reg       writes;

    always @* begin
        b_lane_x = `ALU_LANE_X;
        b_lane_y = `ALU_LANE_Y;
        b_lane_z = `ALU_LANE_Z;
        neg_b    = 1'b0;
        neg_mul  = 1'b0;
        neg_a    = 1'b0;
        addx_a_f = 1'b0;
        addx_b   = `ALU_ADDX_B_B;
        addy_f   = 1'b0;
        f_sel    = `ALU_F_HOLD;
        res_sel  = `ALU_RES_ZERO;
        unit_a_y = 1'b0;
        roots    = 1'b0;
        double   = 1'b0;
        exp      = 1'b0;
        writes   = 1'b0;
        case (op)
            `ISA_OP_ADD: begin
                res_sel = `ALU_RES_SUM;
                writes  = 1'b1;
            end
            `ISA_OP_SUB: begin
                neg_b   = 1'b1;
                res_sel = `ALU_RES_SUM;
                writes  = 1'b1;
            end
            `ISA_OP_MUL: begin
                res_sel = `ALU_RES_MUL;
                writes  = 1'b1;
            end
            `ISA_OP_NMUL: begin
                neg_mul = 1'b1;
                res_sel = `ALU_RES_MUL;
                writes  = 1'b1;
            end
            `ISA_OP_MULX: begin
                b_lane_y = `ALU_LANE_X;
                b_lane_z = `ALU_LANE_X;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_MULY: begin
                b_lane_x = `ALU_LANE_Y;
                b_lane_z = `ALU_LANE_Y;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_MULZ: begin
                b_lane_x = `ALU_LANE_Z;
                b_lane_y = `ALU_LANE_Z;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_NMULX: begin
                b_lane_y = `ALU_LANE_X;
                b_lane_z = `ALU_LANE_X;
                neg_mul  = 1'b1;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_MULR1: begin
                b_lane_x = `ALU_LANE_Y;
                b_lane_y = `ALU_LANE_Z;
                b_lane_z = `ALU_LANE_X;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_MUL2X: begin
                b_lane_y = `ALU_LANE_X;
                b_lane_z = `ALU_LANE_X;
                double   = 1'b1;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_MULR2: begin
                b_lane_x = `ALU_LANE_Z;
                b_lane_y = `ALU_LANE_X;
                b_lane_z = `ALU_LANE_Y;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_MOV: begin
                res_sel = `ALU_RES_PASS;
                writes  = 1'b1;
            end
            `ISA_OP_NEG: begin
                neg_a   = 1'b1;
                res_sel = `ALU_RES_PASS;
                writes  = 1'b1;
            end
            `ISA_OP_ITOF: begin
                res_sel = `ALU_RES_ITOF;
                writes  = 1'b1;
            end
            `ISA_OP_DOT1: begin
                f_sel = `ALU_F_MUL;
            end
            `ISA_OP_DOT2: begin
                addx_a_f = 1'b1;
                addx_b   = `ALU_ADDX_B_FY;
                f_sel    = `ALU_F_SUM_X;
            end
            `ISA_OP_DOT3: begin
                addx_a_f = 1'b1;
                addx_b   = `ALU_ADDX_B_FZ;
                res_sel  = `ALU_RES_SUM;
                writes   = 1'b1;
            end
            `ISA_OP_ISECT1: begin
                neg_mul = 1'b1;
                f_sel   = `ALU_F_MUL;
            end
            `ISA_OP_ISECT2: begin
                addx_a_f = 1'b1;
                addx_b   = `ALU_ADDX_B_FY;
                f_sel    = `ALU_F_SUM_X;
                res_sel  = `ALU_RES_MUL;
                writes   = 1'b1;
            end
            `ISA_OP_ISECT3: begin
                addx_b = `ALU_ADDX_B_AY;
                addy_f = 1'b1;
                f_sel  = `ALU_F_SUM_XY_AZ;
            end
            `ISA_OP_ISECT4: begin
                addx_b  = `ALU_ADDX_B_FY;
                addy_f  = 1'b1;
                f_sel   = `ALU_F_SUM_XY_0;
                res_sel = `ALU_RES_F;
                writes  = 1'b1;
            end
            `ISA_OP_RECIP: begin
                res_sel = `ALU_RES_RECIP;
                writes  = 1'b1;
            end
            `ISA_OP_RECIPY: begin
                res_sel  = `ALU_RES_RECIP;
                unit_a_y = 1'b1;
                writes   = 1'b1;
            end
            `ISA_OP_SQRT: begin
                res_sel = `ALU_RES_SQRT;
                writes  = 1'b1;
            end
            `ISA_OP_ROOTS: begin
                res_sel = `ALU_RES_SQRT;
                roots   = 1'b1;
                writes  = 1'b1;
            end
            `ISA_OP_EXP: begin
                exp    = 1'b1;
                writes = 1'b1;
            end
            default: ;
        endcase
    end

    // Pack by the header's field ranges, so the layout lives in one place.
    reg [`ALU_CTRL_W-1:0] packed_ctrl;

    always @* begin
        packed_ctrl                     = {`ALU_CTRL_W{1'b0}};
        packed_ctrl[`ALU_CTRL_B_LANE_X] = b_lane_x;
        packed_ctrl[`ALU_CTRL_B_LANE_Y] = b_lane_y;
        packed_ctrl[`ALU_CTRL_B_LANE_Z] = b_lane_z;
        packed_ctrl[`ALU_CTRL_NEG_B]    = neg_b;
        packed_ctrl[`ALU_CTRL_NEG_MUL]  = neg_mul;
        packed_ctrl[`ALU_CTRL_NEG_A]    = neg_a;
        packed_ctrl[`ALU_CTRL_ADDX_A_F] = addx_a_f;
        packed_ctrl[`ALU_CTRL_ADDX_B]   = addx_b;
        packed_ctrl[`ALU_CTRL_ADDY_F]   = addy_f;
        packed_ctrl[`ALU_CTRL_F_SEL]    = f_sel;
        packed_ctrl[`ALU_CTRL_RES_SEL]  = res_sel;
        packed_ctrl[`ALU_CTRL_UNIT_A_Y] = unit_a_y;
        packed_ctrl[`ALU_CTRL_ROOTS]    = roots;
        packed_ctrl[`ALU_CTRL_DOUBLE]   = double;
        packed_ctrl[`ALU_CTRL_EXP]      = exp;
    end

    assign ctrl      = packed_ctrl;
    assign writes_rf = writes;

endmodule
`default_nettype wire
