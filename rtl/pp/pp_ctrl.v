`default_nettype none
`include "isa.vh"
// ============================================================================
// pp_ctrl -- the pixel processor's controller FSM (thesis 4.7)
// ============================================================================
// One ISA state per ALU instruction: the state register st_q holds an
// ISA_ST_* id, and the instruction that state issues (opcode, the logical
// addresses of read ports A and B and of the write port, the lane mask) is
// decoded from st_q and the controller's registers only, never from this
// cycle's ALU result (thesis figures 18/19: addresses are set
// unconditionally, only the write enable is gated, by alu_ctrl/alu).
//
// This FSM is golden::micro::program (golden/src/micro/program.rs) line by
// line; the comments name the Rust function each group of states mirrors.
// What Rust does between two instructions (loops over objects, exclusions,
// the stack pointer, material and speed-up switches, branches on the flags
// of the value written in the same cycle) is next-state logic here and costs
// no cycle: that is the cycle rule of golden/src/micro/mod.rs, which the
// co-simulation checks per pixel.
//
// Sub-machines (thesis 4.7.1) with pointer registers and a return register:
//   DOT_1..3    y.x = a.b         pointers dot_a/dot_b/dot_y, return dot_ret
//   NORM_*      y = v / |v|       after a DOT with return R_NORM; norm_pri
//                                 says which vector (primary ray or light)
//   ISECT_1..4  the shared sub-graph; operands from the object under test
// Searches (nearest hit, shadow) share the object loop: ctx says which, and
// ray_o/ray_d point at the ray's origin and direction registers.
//
// A multi-cycle instruction (RECIP, RECIPY, SQRT, ROOTS) holds its state, and every
// other register, until alu_done.
// ============================================================================
module pp_ctrl (
    input  wire                          clk,
    input  wire                          rst_n,
    // The configuration word (layout: ISA_DIM_CFG_* in isa.vh).
    input  wire [95:0]                   cfg,
    // Pixels.
    input  wire                          start,
    input  wire [`ISA_DIM_COORD_BITS-1:0] px,
    input  wire [`ISA_DIM_COORD_BITS-1:0] py,
    output wire                          ready,
    output wire                          done,
    // The instruction of this cycle.
    output reg  [`ISA_DIM_OP_BITS-1:0]   op,
    output reg  [`ISA_DIM_REG_BITS-1:0]  la_a,
    output reg  [`ISA_DIM_REG_BITS-1:0]  la_b,
    output reg  [`ISA_DIM_REG_BITS-1:0]  la_w,
    output reg  [2:0]                    wmask,
    output wire [`ISA_DIM_ST_BITS-1:0]   state,
    output wire [2:0]                    sp,
    output wire [31:0]                   ix,     // ITOF operands: px and -py
    output wire [31:0]                   iy,
    // From the ALU: the instruction completes this cycle, and the flags of
    // the value it writes.
    input  wire                          alu_done,
    input  wire [2:0]                    y_neg,
    input  wire [2:0]                    y_pos,
    input  wire [2:0]                    y_sign
);

    localparam integer CW = `ISA_DIM_COORD_BITS;
    localparam integer RW = `ISA_DIM_REG_BITS;
    localparam integer SW = `ISA_DIM_ST_BITS;

    // Object kinds, search contexts, DOT return points.
    localparam       K_SPH = 1'b0, K_PLN = 1'b1;
    localparam       C_HIT = 1'b0, C_SHD = 1'b1;
    localparam [2:0] R_NORM = 3'd0,  // -> NORM_ROOTS
                     R_SPH  = 3'd1,  // b < 0 ? SPH_BD : the next object
                     R_DIFF = 3'd2,  // n.l > 0 ? SH_KD : the reflection step
                     R_REFL = 3'd3,  // -> SH_REFL_K
                     R_SPEC = 3'd4;  // r.l > 0 ? SH_POW2 : the local colour step

    // Temporaries by role (program.rs, mod t).
    localparam [RW-1:0] T_P   = `ISA_REG_T0,
                        T_N   = `ISA_REG_T1,
                        T_R   = `ISA_REG_T2,
                        T_L   = `ISA_REG_T3,
                        T_LEN = `ISA_REG_T4,
                        T_INV = `ISA_REG_T5,
                        T_BEST = `ISA_REG_T6,
                        T_V   = `ISA_REG_T7,
                        T_G   = `ISA_REG_T8,
                        T_S   = `ISA_REG_T9,
                        T_Q   = `ISA_REG_T10,
                        T_U   = `ISA_REG_T11;

    localparam [2:0] M_X = 3'b001, M_Y = 3'b010, M_Z = 3'b100, M_XYZ = 3'b111;

    // ------------------------------------------------------------------------
    // The configuration
    // ------------------------------------------------------------------------
    wire [3:0]  n_sph     = cfg[`ISA_DIM_CFG_SPHERES_LSB +: 4];
    wire [2:0]  n_pln     = cfg[`ISA_DIM_CFG_PLANES_LSB +: 3];
    wire [3:0]  max_depth = cfg[`ISA_DIM_CFG_DEPTH_LSB +: 4];
    wire        bbox      = cfg[`ISA_DIM_CFG_BBOX_LSB];
    wire        fast      = cfg[`ISA_DIM_CFG_FAST_PLANE_LSB];
    wire        shortcut  = cfg[`ISA_DIM_CFG_SHORTCUT_LSB];
    wire [2:0]  rotate    = cfg[`ISA_DIM_CFG_ROTATE_LSB +: 3];
    wire [23:0] sph_bits  = cfg[`ISA_DIM_CFG_SPH_BITS_LSB +: 24];
    wire [23:0] pln_bits  = {6'd0, cfg[`ISA_DIM_CFG_PLN_BITS_LSB +: 18]};
    wire [15:0] pln_axis  = {4'd0, cfg[`ISA_DIM_CFG_PLN_AXIS_LSB +: 12]};
    wire [7:0]  pln_neg   = {2'd0, cfg[`ISA_DIM_CFG_PLN_NEG_LSB +: 6]};
    // The word's spare bits.
    wire unused_cfg = ^{cfg[95:`ISA_DIM_CFG_PLN_NEG_LSB + 6], cfg[31:`ISA_DIM_CFG_ROTATE_LSB + 3],
                        cfg[`ISA_DIM_CFG_ROTATE_LSB - 1:`ISA_DIM_CFG_SHORTCUT_LSB + 1],
                        cfg[`ISA_DIM_CFG_DEPTH_LSB - 1:`ISA_DIM_CFG_PLANES_LSB + 3]};

    // ------------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------------
    reg [SW-1:0] st_q, st_d;
    reg [CW-1:0] px_q, px_d, py_q, py_d;
    reg [2:0]    sp_q, sp_d;
    reg [1:0]    rot_q, rot_d;            // rotation axis being applied
    reg          norm_pri_q, norm_pri_d;  // NORM_*: primary ray (1) or light vector (0)
    reg [RW-1:0] dot_a_q, dot_a_d, dot_b_q, dot_b_d, dot_y_q, dot_y_d;
    reg [2:0]    dot_ret_q, dot_ret_d;
    reg          ctx_q, ctx_d;            // the search under way
    reg [RW-1:0] ray_o_q, ray_o_d, ray_d_q, ray_d_d;
    reg          kind_q, kind_d;          // the object under test
    reg [2:0]    idx_q, idx_d;
    reg          excl_q, excl_d;          // obj is excluded from searches
    reg          obj_kind_q, obj_kind_d;  // the object being shaded (the last hit)
    reg [2:0]    obj_idx_q, obj_idx_d;
    reg          best_q, best_d;          // the nearest hit so far
    reg          best_kind_q, best_kind_d;
    reg [2:0]    best_idx_q, best_idx_d;
    reg          push_q, push_d;          // shading pushes a reflected ray
    reg          lit_q, lit_d, diff_q, diff_d, spec_q, spec_d;
    reg [7:0]    col_q, col_d;            // the levels whose colour is written
    reg [2:0]    dsign_q, dsign_d, dneg_q, dneg_d, dpos_q, dpos_d;  // direction flags

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            st_q        <= `ISA_ST_IDLE;
            px_q        <= {CW{1'b0}};
            py_q        <= {CW{1'b0}};
            sp_q        <= 3'd0;
            rot_q       <= 2'd0;
            norm_pri_q  <= 1'b0;
            dot_a_q     <= {RW{1'b0}};
            dot_b_q     <= {RW{1'b0}};
            dot_y_q     <= {RW{1'b0}};
            dot_ret_q   <= R_NORM;
            ctx_q       <= C_HIT;
            ray_o_q     <= {RW{1'b0}};
            ray_d_q     <= {RW{1'b0}};
            kind_q      <= K_SPH;
            idx_q       <= 3'd0;
            excl_q      <= 1'b0;
            obj_kind_q  <= K_SPH;
            obj_idx_q   <= 3'd0;
            best_q      <= 1'b0;
            best_kind_q <= K_SPH;
            best_idx_q  <= 3'd0;
            push_q      <= 1'b0;
            lit_q       <= 1'b0;
            diff_q      <= 1'b0;
            spec_q      <= 1'b0;
            col_q       <= 8'd0;
            dsign_q     <= 3'd0;
            dneg_q      <= 3'd0;
            dpos_q      <= 3'd0;
        end else begin
            st_q        <= st_d;
            px_q        <= px_d;
            py_q        <= py_d;
            sp_q        <= sp_d;
            rot_q       <= rot_d;
            norm_pri_q  <= norm_pri_d;
            dot_a_q     <= dot_a_d;
            dot_b_q     <= dot_b_d;
            dot_y_q     <= dot_y_d;
            dot_ret_q   <= dot_ret_d;
            ctx_q       <= ctx_d;
            ray_o_q     <= ray_o_d;
            ray_d_q     <= ray_d_d;
            kind_q      <= kind_d;
            idx_q       <= idx_d;
            excl_q      <= excl_d;
            obj_kind_q  <= obj_kind_d;
            obj_idx_q   <= obj_idx_d;
            best_q      <= best_d;
            best_kind_q <= best_kind_d;
            best_idx_q  <= best_idx_d;
            push_q      <= push_d;
            lit_q       <= lit_d;
            diff_q      <= diff_d;
            spec_q      <= spec_d;
            col_q       <= col_d;
            dsign_q     <= dsign_d;
            dneg_q      <= dneg_d;
            dpos_q      <= dpos_d;
        end
    end

    assign ready = (st_q == `ISA_ST_IDLE);
    assign done  = (st_q == `ISA_ST_PIX_DONE);
    assign state = st_q;
    assign sp    = sp_q;
    assign ix    = {{(32 - CW){1'b0}}, px_q};
    assign iy    = -{{(32 - CW){1'b0}}, py_q};

    // ------------------------------------------------------------------------
    // Addresses
    // ------------------------------------------------------------------------
    function [RW-1:0] sph_reg(input [2:0] k, input [1:0] field);
        sph_reg = `ISA_REG_SPH0_C + k * `ISA_DIM_SPH_STRIDE + {5'd0, field};
    endfunction
    function [RW-1:0] pln_reg(input [2:0] j, input [1:0] field);
        pln_reg = `ISA_REG_PLN0_N + j * `ISA_DIM_PLN_STRIDE + {5'd0, field};
    endfunction

    localparam [1:0] F_SPH_C = 2'd0, F_SPH_R = 2'd1, F_COL = 2'd2, F_MAT = 2'd3,
                     F_PLN_N = 2'd0, F_PLN_Q = 2'd1;

    // The shaded object's registers and switches.
    // Material bits (loader::MaterialBits::code): diffuse, specular, reflective.
    // A function reads only its arguments: a continuous assignment
    // re-evaluates it only when they change.
    function [2:0] bits_of(input kind, input [2:0] idx, input [23:0] sph, input [23:0] pln);
        bits_of = kind == K_SPH ? sph[3*idx +: 3] : pln[3*idx +: 3];
    endfunction
    wire [2:0]    obj_bits     = bits_of(obj_kind_q, obj_idx_q, sph_bits, pln_bits);
    wire          obj_diffuse  = obj_bits[0];
    wire          obj_specular = obj_bits[1];
    wire          unused_obj_reflective = obj_bits[2];  // read from best at shade_start
    wire [RW-1:0] obj_mat = obj_kind_q == K_SPH ? sph_reg(obj_idx_q, F_MAT) : pln_reg(obj_idx_q, F_MAT);
    wire [RW-1:0] obj_col = obj_kind_q == K_SPH ? sph_reg(obj_idx_q, F_COL) : pln_reg(obj_idx_q, F_COL);
    wire [RW-1:0] obj_n   = obj_kind_q == K_SPH ? T_N : pln_reg(obj_idx_q, F_PLN_N);

    // The ray being shaded (program.rs, struct Shading): when pushing, the
    // child's level is current and the parent's is shaded.
    wire [RW-1:0] ray_o   = push_q ? `ISA_REG_PAR_O : `ISA_REG_CUR_O;
    wire [RW-1:0] ray_d   = push_q ? `ISA_REG_PAR_D : `ISA_REG_CUR_D;
    wire [RW-1:0] ray_col = push_q ? `ISA_REG_PAR_COL : `ISA_REG_CUR_COL;
    wire [RW-1:0] ray_w   = push_q ? `ISA_REG_PAR_W : `ISA_REG_CUR_W;
    wire [RW-1:0] ray_p   = push_q ? `ISA_REG_CUR_O : T_P;
    wire [RW-1:0] ray_r   = push_q ? `ISA_REG_CUR_D : T_R;
    wire [2:0]    ray_lvl = push_q ? sp_q - 3'd1 : sp_q;

    // The lanes a rotation about rot_q turns: u = rot + 1, v = rot + 2.
    wire [2:0] rot_u = rot_q == 2'd0 ? M_Y : rot_q == 2'd1 ? M_Z : M_X;
    wire [2:0] rot_v = rot_q == 2'd0 ? M_Z : rot_q == 2'd1 ? M_X : M_Y;
    wire [RW-1:0] rot_c = `ISA_REG_ROT0_C + rot_q * `ISA_DIM_ROT_STRIDE;
    wire [RW-1:0] rot_s = `ISA_REG_ROT0_S + rot_q * `ISA_DIM_ROT_STRIDE;

    // The destination of a test's u = -t: BEST for the first hit of a
    // nearest-hit search, else U (offer compares it with BEST).
    wire [RW-1:0] u_dst = (ctx_q == C_HIT && !best_q) ? T_BEST : T_U;

    // ------------------------------------------------------------------------
    // Instruction decoding: the state's instruction (program.rs, each line)
    // ------------------------------------------------------------------------
    always @* begin
        op    = `ISA_OP_NOP;
        la_a  = dot_a_q;
        la_b  = dot_b_q;
        la_w  = dot_y_q;
        wmask = M_XYZ;
        case (st_q)
            // primary_ray
            `ISA_ST_PRI_ITOF:   begin op = `ISA_OP_ITOF; la_w = T_P; end
            `ISA_ST_PRI_HALF:   begin op = `ISA_OP_ADD; la_w = T_P; la_a = T_P; la_b = `ISA_REG_CAM_HALF; end
            `ISA_ST_ROT_COS:    begin op = `ISA_OP_MUL; la_w = T_N; la_a = T_P; la_b = rot_c; end
            `ISA_ST_ROT_SIN_U:  begin op = `ISA_OP_MULR1; la_w = T_R; la_a = rot_s; la_b = T_P; wmask = rot_u; end
            `ISA_ST_ROT_SIN_V:  begin op = `ISA_OP_MULR2; la_w = T_R; la_a = rot_s; la_b = T_P; wmask = rot_v; end
            `ISA_ST_ROT_ADD:    begin op = `ISA_OP_ADD; la_w = T_P; la_a = T_N; la_b = T_R; wmask = rot_u | rot_v; end
            // dot
            `ISA_ST_DOT_1:      op = `ISA_OP_DOT1;
            `ISA_ST_DOT_2:      op = `ISA_OP_DOT2;
            `ISA_ST_DOT_3:      begin op = `ISA_OP_DOT3; wmask = M_X; end
            // normalize
            `ISA_ST_NORM_ROOTS: begin op = `ISA_OP_ROOTS; la_w = T_LEN; la_a = T_LEN; wmask = M_X | M_Y; end
            `ISA_ST_NORM_INV:   begin op = `ISA_OP_MULR1; la_w = T_INV; la_a = T_LEN; la_b = T_LEN; wmask = M_X; end
            `ISA_ST_NORM_SCALE: begin
                op   = `ISA_OP_MULX;
                la_w = norm_pri_q ? `ISA_REG_CUR_D : T_L;
                la_a = norm_pri_q ? T_P : T_R;
                la_b = T_INV;
            end
            // isect: spheres b = c = w (in V), a = r*r; planes b = o, c = n, a = q
            `ISA_ST_ISECT_1: begin
                op   = `ISA_OP_ISECT1;
                la_a = kind_q == K_SPH ? T_V : ray_o_q;
                la_b = kind_q == K_SPH ? T_V : pln_reg(idx_q, F_PLN_N);
            end
            `ISA_ST_ISECT_2: begin
                op   = `ISA_OP_ISECT2;
                la_w = T_G;
                la_a = ray_d_q;
                la_b = kind_q == K_SPH ? T_V : pln_reg(idx_q, F_PLN_N);
            end
            `ISA_ST_ISECT_3:    begin op = `ISA_OP_ISECT3; la_a = T_G; end
            `ISA_ST_ISECT_4: begin
                op   = `ISA_OP_ISECT4;
                la_w = T_S;
                la_a = kind_q == K_SPH ? sph_reg(idx_q, F_SPH_R) : pln_reg(idx_q, F_PLN_Q);
            end
            // box_hit
            `ISA_ST_BOX_NEAR:   begin op = `ISA_OP_SUB; la_w = T_V; la_a = `ISA_REG_BOX0 + {4'd0, dsign_q}; la_b = ray_o_q; end
            `ISA_ST_BOX_FAR:    begin op = `ISA_OP_SUB; la_w = T_G; la_a = `ISA_REG_BOX0 + {4'd0, ~dsign_q}; la_b = ray_o_q; end
            `ISA_ST_BOX_BEHIND: begin op = `ISA_OP_MUL; la_w = T_S; la_a = T_G; la_b = ray_d_q; end
            `ISA_ST_BOX_P1:     begin op = `ISA_OP_MULR1; la_w = T_Q; la_a = T_V; la_b = ray_d_q; end
            `ISA_ST_BOX_Q1:     begin op = `ISA_OP_MULR1; la_w = T_U; la_a = ray_d_q; la_b = T_G; end
            `ISA_ST_BOX_D1:     begin op = `ISA_OP_SUB; la_w = T_Q; la_a = T_Q; la_b = T_U; end
            `ISA_ST_BOX_P2:     begin op = `ISA_OP_MULR2; la_w = T_Q; la_a = T_V; la_b = ray_d_q; end
            `ISA_ST_BOX_Q2:     begin op = `ISA_OP_MULR2; la_w = T_U; la_a = ray_d_q; la_b = T_G; end
            `ISA_ST_BOX_D2:     begin op = `ISA_OP_SUB; la_w = T_Q; la_a = T_Q; la_b = T_U; end
            // sphere_u, plane_u, offer, before_light
            `ISA_ST_SPH_V:      begin op = `ISA_OP_SUB; la_w = T_V; la_a = ray_o_q; la_b = sph_reg(idx_q, F_SPH_C); end
            `ISA_ST_SPH_BD:     begin op = `ISA_OP_NMULX; la_w = T_U; la_a = ray_d_q; la_b = T_Q; end
            `ISA_ST_SPH_W:      begin op = `ISA_OP_ADD; la_w = T_V; la_a = T_V; la_b = T_U; end
            `ISA_ST_SPH_SQRT:   begin op = `ISA_OP_SQRT; la_w = T_S; la_a = T_S; wmask = M_X; end
            `ISA_ST_SPH_T:      begin op = `ISA_OP_ADD; la_w = u_dst; la_a = T_S; la_b = T_Q; wmask = M_X; end
            `ISA_ST_PLN_RECIP:  begin op = `ISA_OP_RECIPY; la_w = T_Q; la_a = T_S; wmask = M_X; end
            `ISA_ST_PLN_T:      begin op = `ISA_OP_NMULX; la_w = u_dst; la_a = T_S; la_b = T_Q; wmask = M_X; end
            `ISA_ST_HIT_CMP:    begin op = `ISA_OP_SUB; la_w = T_G; la_a = T_U; la_b = T_BEST; wmask = M_X; end
            `ISA_ST_HIT_KEEP:   begin op = `ISA_OP_MOV; la_w = T_BEST; la_a = T_U; wmask = M_X; end
            `ISA_ST_SHD_DIST:   begin op = `ISA_OP_ADD; la_w = T_G; la_a = T_U; la_b = T_LEN; wmask = M_X; end
            // shade
            `ISA_ST_SH_OFFSET:  begin op = `ISA_OP_NMULX; la_w = T_V; la_a = ray_d; la_b = T_BEST; end
            `ISA_ST_SH_POINT:   begin op = `ISA_OP_ADD; la_w = ray_p; la_a = ray_o; la_b = T_V; end
            `ISA_ST_SH_NORMAL_SUB:   begin op = `ISA_OP_SUB; la_w = T_N; la_a = ray_p; la_b = sph_reg(obj_idx_q, F_SPH_C); end
            `ISA_ST_SH_NORMAL_SCALE: begin op = `ISA_OP_MULY; la_w = T_N; la_a = T_N; la_b = sph_reg(obj_idx_q, F_SPH_R); end
            `ISA_ST_SH_LIGHT_VEC: begin op = `ISA_OP_SUB; la_w = T_R; la_a = `ISA_REG_LIGHT_POS; la_b = ray_p; end
            `ISA_ST_SH_KD:      begin op = `ISA_OP_MULX; la_w = T_G; la_a = obj_mat; la_b = T_V; wmask = M_X; end
            `ISA_ST_SH_CL:      begin op = `ISA_OP_MUL; la_w = T_S; la_a = obj_col; la_b = `ISA_REG_LIGHT_COL; end
            `ISA_ST_SH_DIFFUSE: begin op = `ISA_OP_MULX; la_w = T_S; la_a = T_S; la_b = T_G; end
            `ISA_ST_SH_REFL_K:  begin op = `ISA_OP_MUL2X; la_w = T_U; la_a = obj_n; la_b = T_Q; end
            `ISA_ST_SH_REFL:    begin op = `ISA_OP_SUB; la_w = ray_r; la_a = ray_d; la_b = T_U; end
            `ISA_ST_SH_POW2:    begin op = `ISA_OP_MUL; la_w = T_U; la_a = T_Q; la_b = T_Q; wmask = M_X; end
            `ISA_ST_SH_POW4:    begin op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_U; wmask = M_X; end
            `ISA_ST_SH_POW5:    begin op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_Q; wmask = M_X; end
            `ISA_ST_SH_POW10:   begin op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_U; wmask = M_X; end
            `ISA_ST_SH_POW20:   begin op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_U; wmask = M_X; end
            `ISA_ST_SH_KS:      begin op = `ISA_OP_MULX; la_w = T_V; la_a = obj_mat; la_b = T_U; wmask = M_Y; end
            `ISA_ST_SH_SPEC:    begin op = `ISA_OP_MULY; la_w = T_G; la_a = `ISA_REG_LIGHT_COL; la_b = T_V; end
            `ISA_ST_SH_LOCAL:   begin op = `ISA_OP_ADD; la_w = T_S; la_a = T_S; la_b = T_G; end
            `ISA_ST_SH_COLOUR:  begin op = `ISA_OP_MUL; la_w = ray_col; la_a = (spec_q && !diff_q) ? T_G : T_S; la_b = ray_w; end
            `ISA_ST_SH_CHILD_W: begin op = `ISA_OP_MULZ; la_w = `ISA_REG_CUR_W; la_a = `ISA_REG_PAR_W; la_b = obj_mat; end
            // unwind
            `ISA_ST_POP_ADD:    begin op = `ISA_OP_ADD; la_w = `ISA_REG_PAR_COL; la_a = `ISA_REG_PAR_COL; la_b = `ISA_REG_CUR_COL; end
            `ISA_ST_POP_MOV:    begin op = `ISA_OP_MOV; la_w = `ISA_REG_PAR_COL; la_a = `ISA_REG_CUR_COL; end
            `ISA_ST_ROOT_BLACK: begin op = `ISA_OP_MOV; la_w = `ISA_REG_CUR_COL; la_a = `ISA_REG_ZERO; end
            // The pixel's colour leaves through read port A.
            `ISA_ST_PIX_DONE:   la_a = `ISA_REG_STK0_COL;
            default: ;
        endcase
    end

    // ------------------------------------------------------------------------
    // Object loops: the next sphere or plane a search tests
    // ------------------------------------------------------------------------
    // The direction flags the search decides with: those being latched this
    // cycle (NORM_SCALE, SH_REFL write the new direction), else the latched.
    wire       dir_latch = (st_q == `ISA_ST_NORM_SCALE) || (st_q == `ISA_ST_SH_REFL);
    wire [2:0] dneg_now  = dir_latch ? y_neg : dneg_q;
    wire [2:0] dpos_now  = dir_latch ? y_pos : dpos_q;

    // {found, k}: the first sphere k >= from in the scene that is not the
    // excluded object (spheres_other_than, the sphere loop's `continue`).
    function [3:0] sphere_from(input [3:0] from, input [3:0] n, input ex, input [2:0] ex_k);
        integer k;
        begin
            sphere_from = 4'd0;
            for (k = 7; k >= 0; k = k - 1)
                if (k >= from && k < n && !(ex && ex_k == k[2:0]))
                    sphere_from = {1'b1, k[2:0]};
        end
    endfunction

    // {found, j}: the first plane j >= from in the scene, not excluded, and,
    // with the fast plane test, facing the ray (plane_u_checked's early
    // `return None`, which issues no instruction).
    function [3:0] plane_from(input [3:0] from, input [2:0] n, input ex, input [2:0] ex_j,
                              input fast_on, input [15:0] axis, input [7:0] neg,
                              input [2:0] dneg, input [2:0] dpos);
        integer j;
        reg [2:0] against;
        begin
            plane_from = 4'd0;
            for (j = 5; j >= 0; j = j - 1) begin
                // DirFlags::opposes: a normal facing -axis needs d.axis > 0.
                against = neg[j] ? dpos : dneg;
                if (j >= from && j < {1'b0, n} && !(ex && ex_j == j[2:0]) &&
                    (!fast_on || against[axis[2*j +: 2]]))
                    plane_from = {1'b1, j[2:0]};
            end
        end
    endfunction

    // Box test (box_hit, separated): lane i of the difference is
    // N_i d_j - F_j d_i with j = i + shift; it proves t_near_i > t_far_j if
    // it is > 0 where d_i and d_j have the same sign, < 0 where they differ.
    // sign_j is the direction's sign vector rotated by shift lanes.
    function separated(input [2:0] pos, input [2:0] neg, input [2:0] sign, input [2:0] sign_j);
        separated = |((pos & ~(sign ^ sign_j)) | (neg & (sign ^ sign_j)));
    endfunction
    wire [2:0] dsign_r1 = {dsign_q[0], dsign_q[2], dsign_q[1]};  // lane i: sign of d_(i+1)
    wire [2:0] dsign_r2 = {dsign_q[1], dsign_q[0], dsign_q[2]};  // lane i: sign of d_(i+2)

    wire [3:0] sph_first = sphere_from(4'd0, n_sph, excl_q && obj_kind_q == K_SPH, obj_idx_q);
    wire [3:0] sph_next  = sphere_from({1'b0, idx_q} + 4'd1, n_sph, excl_q && obj_kind_q == K_SPH, obj_idx_q);
    wire [3:0] pln_first = plane_from(4'd0, n_pln, excl_q && obj_kind_q == K_PLN, obj_idx_q,
                                      fast, pln_axis, pln_neg, dneg_now, dpos_now);
    wire [3:0] pln_next  = plane_from({1'b0, idx_q} + 4'd1, n_pln, excl_q && obj_kind_q == K_PLN, obj_idx_q,
                                      fast, pln_axis, pln_neg, dneg_now, dpos_now);

    // ------------------------------------------------------------------------
    // Next-state logic: the program's control flow
    // ------------------------------------------------------------------------
    // Each task is a place in program.rs that decides where to go next
    // without issuing an instruction; they read the *_d values set before
    // them in the same cycle.

    task call_dot(input [RW-1:0] src_a, input [RW-1:0] src_b, input [RW-1:0] dst, input [2:0] ret);
        begin
            dot_a_d   = src_a;
            dot_b_d   = src_b;
            dot_y_d   = dst;
            dot_ret_d = ret;
            st_d      = `ISA_ST_DOT_1;
        end
    endtask

    // Rotations still to apply from axis a0 on, then normalize the primary ray.
    task rot_from(input [1:0] a0);
        begin
            if (a0 == 2'd0 && rotate[0]) begin
                rot_d = 2'd0;
                st_d  = `ISA_ST_ROT_COS;
            end else if (a0 <= 2'd1 && rotate[1]) begin
                rot_d = 2'd1;
                st_d  = `ISA_ST_ROT_COS;
            end else if (a0 <= 2'd2 && rotate[2]) begin
                rot_d = 2'd2;
                st_d  = `ISA_ST_ROT_COS;
            end else begin
                norm_pri_d = 1'b1;
                call_dot(T_P, T_P, T_LEN, R_NORM);
            end
        end
    endtask

    // unwind: skip the uncoloured levels above the highest coloured one
    // (their `if` issues nothing), then one POP per level down to 1.
    task unwind;
        integer l;
        reg       found;
        reg [2:0] lvl;
        begin
            found = 1'b0;
            lvl   = 3'd0;
            for (l = 1; l < 8; l = l + 1)
                if (l[2:0] <= sp_q && col_d[l]) begin
                    found = 1'b1;
                    lvl   = l[2:0];
                end
            if (found) begin
                sp_d = lvl;
                st_d = col_d[lvl - 3'd1] ? `ISA_ST_POP_ADD : `ISA_ST_POP_MOV;
            end else begin
                sp_d = 3'd0;
                st_d = col_d[0] ? `ISA_ST_PIX_DONE : `ISA_ST_ROOT_BLACK;
            end
        end
    endtask

    // After a POP at level sp: the level below is coloured now.
    task pop_next;
        begin
            sp_d = sp_q - 3'd1;
            if (sp_q == 3'd1)
                st_d = `ISA_ST_PIX_DONE;
            else
                st_d = col_d[sp_q - 3'd2] ? `ISA_ST_POP_ADD : `ISA_ST_POP_MOV;
        end
    endtask

    // run: a hit found -> push if reflective and below the depth, then shade.
    function reflective(input kind, input [2:0] idx, input [23:0] sph, input [23:0] pln);
        reflective = kind == K_SPH ? sph[3*idx + 2] : pln[3*idx + 2];
    endfunction

    task shade_start;
        begin
            push_d     = reflective(best_kind_d, best_idx_d, sph_bits, pln_bits) && ({1'b0, sp_q} + 4'd1 < max_depth);
            sp_d       = push_d ? sp_q + 3'd1 : sp_q;
            obj_kind_d = best_kind_d;
            obj_idx_d  = best_idx_d;
            excl_d     = 1'b1;
            lit_d      = 1'b0;
            diff_d     = 1'b0;
            spec_d     = 1'b0;
            st_d       = `ISA_ST_SH_OFFSET;
        end
    endtask

    // shade, after the diffuse term: the reflected direction if a child is
    // pushed or the specular term needs it.
    task local_step;
        begin
            if (diff_d && spec_d)
                st_d = `ISA_ST_SH_LOCAL;
            else if (diff_d || spec_d)
                st_d = `ISA_ST_SH_COLOUR;
            else if (push_q)
                st_d = `ISA_ST_SH_CHILD_W;
            else
                unwind;
        end
    endtask

    task spec_step;
        begin
            if (lit_d && obj_specular)
                call_dot(ray_r, T_L, T_Q, R_SPEC);
            else
                local_step;
        end
    endtask

    task refl_step;
        begin
            if (push_q || (lit_d && obj_specular))
                call_dot(ray_d, obj_n, T_Q, R_REFL);
            else
                spec_step;
        end
    endtask

    // shadowed() has decided.
    task shadow_result(input shadowed);
        begin
            lit_d = !shadowed;
            if (lit_d && obj_diffuse)
                call_dot(obj_n, T_L, T_V, R_DIFF);
            else
                refl_step;
        end
    endtask

    // The end of a search: nearest_hit returns, or shadowed returns false.
    task search_end;
        begin
            if (ctx_d == C_SHD)
                shadow_result(1'b0);
            else if (best_d)
                shade_start;
            else
                unwind;
        end
    endtask

    // Planes from plane_from's answer (the plane loops).
    task planes(input [3:0] cand);
        begin
            if (cand[3]) begin
                kind_d = K_PLN;
                idx_d  = cand[2:0];
                st_d   = `ISA_ST_ISECT_1;
            end else
                search_end;
        end
    endtask

    // The sphere loop is over (or skipped): planes, unless the shadow
    // shortcut ignores them.
    task spheres_done;
        begin
            if (ctx_d == C_SHD && shortcut)
                shadow_result(1'b0);
            else
                planes(pln_first);
        end
    endtask

    task sphere_at(input [2:0] k);
        begin
            kind_d = K_SPH;
            idx_d  = k;
            st_d   = `ISA_ST_SPH_V;
        end
    endtask

    // nearest_hit / shadowed from the top.
    task search_start(input ctx, input [RW-1:0] o, input [RW-1:0] d);
        begin
            ctx_d   = ctx;
            ray_o_d = o;
            ray_d_d = d;
            best_d  = 1'b0;
            if (sph_first[3]) begin
                if (bbox)
                    st_d = `ISA_ST_BOX_FAR;
                else
                    sphere_at(sph_first[2:0]);
            end else
                spheres_done;
        end
    endtask

    // The loop's next object after the one under test.
    task next_object;
        begin
            if (kind_q == K_SPH) begin
                if (sph_next[3])
                    sphere_at(sph_next[2:0]);
                else
                    spheres_done;
            end else
                planes(pln_next);
        end
    endtask

    // offer: the first hit is the best where it was written; a later one is
    // compared.
    task offer;
        begin
            if (!best_q) begin
                best_d      = 1'b1;
                best_kind_d = kind_q;
                best_idx_d  = idx_q;
                next_object;
            end else
                st_d = `ISA_ST_HIT_CMP;
        end
    endtask

    always @* begin
        st_d        = st_q;
        px_d        = px_q;
        py_d        = py_q;
        sp_d        = sp_q;
        rot_d       = rot_q;
        norm_pri_d  = norm_pri_q;
        dot_a_d     = dot_a_q;
        dot_b_d     = dot_b_q;
        dot_y_d     = dot_y_q;
        dot_ret_d   = dot_ret_q;
        ctx_d       = ctx_q;
        ray_o_d     = ray_o_q;
        ray_d_d     = ray_d_q;
        kind_d      = kind_q;
        idx_d       = idx_q;
        excl_d      = excl_q;
        obj_kind_d  = obj_kind_q;
        obj_idx_d   = obj_idx_q;
        best_d      = best_q;
        best_kind_d = best_kind_q;
        best_idx_d  = best_idx_q;
        push_d      = push_q;
        lit_d       = lit_q;
        diff_d      = diff_q;
        spec_d      = spec_q;
        col_d       = col_q;
        dsign_d     = dsign_q;
        dneg_d      = dneg_q;
        dpos_d      = dpos_q;

        if (alu_done) begin
            case (st_q)
                `ISA_ST_IDLE: if (start) begin
                    px_d = px;
                    py_d = py;
                    // What a start cycle would do, in the edge that takes
                    // start: the first instruction follows at once.
                    sp_d    = 3'd0;
                    col_d   = 8'd0;
                    excl_d  = 1'b0;
                    push_d  = 1'b0;
                    dsign_d = 3'd0;
                    dneg_d  = 3'd0;
                    dpos_d  = 3'd0;
                    st_d    = `ISA_ST_PRI_ITOF;
                end
                // primary_ray
                `ISA_ST_PRI_ITOF:   st_d = `ISA_ST_PRI_HALF;
                `ISA_ST_PRI_HALF:   rot_from(2'd0);
                `ISA_ST_ROT_COS:    st_d = `ISA_ST_ROT_SIN_U;
                `ISA_ST_ROT_SIN_U:  st_d = `ISA_ST_ROT_SIN_V;
                `ISA_ST_ROT_SIN_V:  st_d = `ISA_ST_ROT_ADD;
                `ISA_ST_ROT_ADD:    rot_from(rot_q + 2'd1);
                // dot
                `ISA_ST_DOT_1:      st_d = `ISA_ST_DOT_2;
                `ISA_ST_DOT_2:      st_d = `ISA_ST_DOT_3;
                `ISA_ST_DOT_3: case (dot_ret_q)
                    R_NORM:  st_d = `ISA_ST_NORM_ROOTS;
                    // b >= 0: the near root is not ahead (sphere_u).
                    R_SPH:   if (y_neg[0]) st_d = `ISA_ST_SPH_BD; else next_object;
                    R_DIFF:  if (y_pos[0]) st_d = `ISA_ST_SH_KD; else refl_step;
                    R_REFL:  st_d = `ISA_ST_SH_REFL_K;
                    default: if (y_pos[0]) st_d = `ISA_ST_SH_POW2; else local_step;
                endcase
                // normalize
                `ISA_ST_NORM_ROOTS: st_d = `ISA_ST_NORM_INV;
                `ISA_ST_NORM_INV:   st_d = `ISA_ST_NORM_SCALE;
                `ISA_ST_NORM_SCALE: begin
                    dsign_d = y_sign;
                    dneg_d  = y_neg;
                    dpos_d  = y_pos;
                    // Level 0's origin and weight are EYE and ONE (mem_ctrl).
                    if (norm_pri_q)
                        search_start(C_HIT, `ISA_REG_CUR_O, `ISA_REG_CUR_D);
                    else
                        search_start(C_SHD, ray_p, T_L);
                end
                // box_hit
                // The far corner first: behind the ray after two instructions.
                `ISA_ST_BOX_FAR:    st_d = `ISA_ST_BOX_BEHIND;
                `ISA_ST_BOX_BEHIND: if (|y_neg) spheres_done; else st_d = `ISA_ST_BOX_NEAR;
                `ISA_ST_BOX_NEAR:   st_d = `ISA_ST_BOX_P1;
                `ISA_ST_BOX_P1:     st_d = `ISA_ST_BOX_Q1;
                `ISA_ST_BOX_Q1:     st_d = `ISA_ST_BOX_D1;
                `ISA_ST_BOX_D1: if (separated(y_pos, y_neg, dsign_q, dsign_r1)) spheres_done;
                                else st_d = `ISA_ST_BOX_P2;
                `ISA_ST_BOX_P2:     st_d = `ISA_ST_BOX_Q2;
                `ISA_ST_BOX_Q2:     st_d = `ISA_ST_BOX_D2;
                `ISA_ST_BOX_D2: if (separated(y_pos, y_neg, dsign_q, dsign_r2)) spheres_done;
                                else sphere_at(sph_first[2:0]);
                // sphere_u
                `ISA_ST_SPH_V:      call_dot(T_V, ray_d_q, T_Q, R_SPH);
                `ISA_ST_SPH_BD:     st_d = `ISA_ST_SPH_W;
                `ISA_ST_SPH_W:      st_d = `ISA_ST_ISECT_1;
                `ISA_ST_ISECT_1:    st_d = `ISA_ST_ISECT_2;
                `ISA_ST_ISECT_2:    st_d = `ISA_ST_ISECT_3;
                `ISA_ST_ISECT_3:    st_d = `ISA_ST_ISECT_4;
                `ISA_ST_ISECT_4: begin
                    if (kind_q == K_SPH) begin
                        // disc < 0: the line misses the sphere.
                        if (y_neg[0]) next_object; else st_d = `ISA_ST_SPH_SQRT;
                    end else begin
                        // plane_u_checked: n.d >= 0 faces away (unless fast).
                        if (!fast && !y_neg[1]) next_object; else st_d = `ISA_ST_PLN_RECIP;
                    end
                end
                `ISA_ST_SPH_SQRT:   st_d = `ISA_ST_SPH_T;
                `ISA_ST_SPH_T: begin
                    if (!y_neg[0])
                        next_object;  // t <= 0: behind the ray
                    else if (ctx_q == C_HIT)
                        offer;
                    else if (shortcut)
                        shadow_result(1'b1);
                    else
                        st_d = `ISA_ST_SHD_DIST;
                end
                // plane_u
                `ISA_ST_PLN_RECIP:  st_d = `ISA_ST_PLN_T;
                `ISA_ST_PLN_T: begin
                    if (!(fast || y_neg[0]))
                        next_object;
                    else if (ctx_q == C_HIT)
                        offer;
                    else
                        st_d = `ISA_ST_SHD_DIST;
                end
                `ISA_ST_HIT_CMP:    if (y_pos[0]) st_d = `ISA_ST_HIT_KEEP; else next_object;
                `ISA_ST_HIT_KEEP: begin
                    best_kind_d = kind_q;
                    best_idx_d  = idx_q;
                    next_object;
                end
                `ISA_ST_SHD_DIST:   if (y_pos[0]) shadow_result(1'b1); else next_object;
                // shade
                `ISA_ST_SH_OFFSET:  st_d = `ISA_ST_SH_POINT;
                `ISA_ST_SH_POINT:   st_d = obj_kind_q == K_SPH ? `ISA_ST_SH_NORMAL_SUB : `ISA_ST_SH_LIGHT_VEC;
                `ISA_ST_SH_NORMAL_SUB:   st_d = `ISA_ST_SH_NORMAL_SCALE;
                `ISA_ST_SH_NORMAL_SCALE: st_d = `ISA_ST_SH_LIGHT_VEC;
                `ISA_ST_SH_LIGHT_VEC: begin
                    norm_pri_d = 1'b0;
                    call_dot(T_R, T_R, T_LEN, R_NORM);
                end
                `ISA_ST_SH_KD:      st_d = `ISA_ST_SH_CL;
                `ISA_ST_SH_CL:      st_d = `ISA_ST_SH_DIFFUSE;
                `ISA_ST_SH_DIFFUSE: begin
                    diff_d = 1'b1;
                    refl_step;
                end
                `ISA_ST_SH_REFL_K:  st_d = `ISA_ST_SH_REFL;
                `ISA_ST_SH_REFL: begin
                    dsign_d = y_sign;
                    dneg_d  = y_neg;
                    dpos_d  = y_pos;
                    spec_step;
                end
                `ISA_ST_SH_POW2:    st_d = `ISA_ST_SH_POW4;
                `ISA_ST_SH_POW4:    st_d = `ISA_ST_SH_POW5;
                `ISA_ST_SH_POW5:    st_d = `ISA_ST_SH_POW10;
                `ISA_ST_SH_POW10:   st_d = `ISA_ST_SH_POW20;
                `ISA_ST_SH_POW20:   st_d = `ISA_ST_SH_KS;
                `ISA_ST_SH_KS:      st_d = `ISA_ST_SH_SPEC;
                `ISA_ST_SH_SPEC: begin
                    spec_d = 1'b1;
                    local_step;
                end
                `ISA_ST_SH_LOCAL:   st_d = `ISA_ST_SH_COLOUR;
                `ISA_ST_SH_COLOUR: begin
                    col_d[ray_lvl] = 1'b1;
                    if (push_q) st_d = `ISA_ST_SH_CHILD_W; else unwind;
                end
                `ISA_ST_SH_CHILD_W: search_start(C_HIT, `ISA_REG_CUR_O, `ISA_REG_CUR_D);
                // unwind
                `ISA_ST_POP_ADD:    pop_next;
                `ISA_ST_POP_MOV: begin
                    col_d[sp_q - 3'd1] = 1'b1;
                    pop_next;
                end
                `ISA_ST_ROOT_BLACK: st_d = `ISA_ST_PIX_DONE;
                `ISA_ST_PIX_DONE:   st_d = `ISA_ST_IDLE;
                default:            st_d = `ISA_ST_IDLE;
            endcase
        end
    end

endmodule
`default_nettype wire
