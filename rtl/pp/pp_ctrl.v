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
// This FSM is golden::micro::program (golden/src/micro/program.rs) state by
// state; docs/rtl.md has the table of which program.rs function issues each
// state's instruction, and tests/state_table.rs checks it against golden's
// trace. What Rust does between two instructions (loops over objects,
// exclusions, the stack pointer, material and speed-up switches, branches
// on the flags of the value written in the same cycle) is next-state logic
// here and costs no cycle: the cycle rule of golden/src/micro/mod.rs, which
// the co-simulation checks per pixel.
//
// Shape (lowRISC Ibex, ibex_multdiv_slow.sv): the flops only reset and
// latch; one combinational block first sets every output and every next
// value to its default (no instruction; *_d = *_q), then one case (st_dec,
// st_q as this build decodes it: ctrl_flow.vh's decoded_st)
// holds each state's instruction and its next state together. A next-state
// choice that several states share is a pure function (it reads only its
// arguments) named after the program.rs function whose control flow it
// computes, applied to this cycle's registers by a continuous assign: a
// jump, the next {st, sp, call, kind, idx}, which the state copies.
//
// Sub-machines (thesis 4.7.1): DOT_1..3 (y.x = a.b) and NORM_* (y = v/|v|
// after a DOT) take their operands from call_q, which dot() call of
// program.rs they serve, and return by it; ISECT_1..4 takes its operands
// from the object under test. The two searches (nearest_hit, shadowed)
// share the object loop: ctx_q says which, and fixes the ray under test.
//
// A multi-cycle instruction (RECIP, RECIPY, SQRT, ROOTS, EXP) holds its state,
// and every other register, until alu_done; every other instruction is done
// in its cycle (alu.v).
// ============================================================================
module pp_ctrl #(
    parameter integer REFRACTION = 1   // 0: no refraction (no transparent sphere, no ISA_ST_RF_* state)
) (
    input  wire                            clk,
    input  wire                            rst_n,
    // The configuration word (layout: ISA_DIM_CFG_* in isa.vh).
    input  wire [`ISA_DIM_LANES*32-1:0]    cfg,
    // Pixels.
    input  wire                            start,
    input  wire [`ISA_DIM_COORD_BITS-1:0]  px,
    input  wire [`ISA_DIM_COORD_BITS-1:0]  py,
    output wire                            ready,
    output wire                            done,
    // The instruction of this cycle.
    output reg  [`ISA_DIM_OP_BITS-1:0]     op,
    output reg  [`ISA_DIM_REG_BITS-1:0]    la_a,
    output reg  [`ISA_DIM_REG_BITS-1:0]    la_b,
    output reg  [`ISA_DIM_REG_BITS-1:0]    la_w,
    output reg  [`ISA_DIM_LANES-1:0]       wmask,
    output wire [`ISA_DIM_ST_BITS-1:0]     state,
    output wire [$clog2(`ISA_DIM_STK_COUNT)-1:0] sp,
    output wire [31:0]                     ix,     // ITOF operands: px and -py
    output wire [31:0]                     iy,
    // From the ALU: the instruction completes this cycle, and the flags of
    // the value it writes.
    input  wire                            alu_done,
    input  wire [`ISA_DIM_LANES-1:0]       y_neg,
    input  wire [`ISA_DIM_LANES-1:0]       y_pos,
    input  wire [`ISA_DIM_LANES-1:0]       y_sign
);

    // ------------------------------------------------------------------------
    // Sizes, all from isa.vh
    // ------------------------------------------------------------------------
    localparam integer CW     = `ISA_DIM_COORD_BITS;
    localparam integer RW     = `ISA_DIM_REG_BITS;
    localparam integer SW     = `ISA_DIM_ST_BITS;
    localparam integer LN     = `ISA_DIM_LANES;
    localparam integer SPH_N  = `ISA_DIM_SPH_COUNT;
    localparam integer PLN_N  = `ISA_DIM_PLN_COUNT;
    localparam integer ROT_N  = `ISA_DIM_ROT_COUNT;
    localparam integer STK_N  = `ISA_DIM_STK_COUNT;
    localparam integer MB     = `ISA_DIM_CFG_MAT_BITS;
    localparam integer AB     = `ISA_DIM_CFG_AXIS_BITS;
    localparam integer OBJ_N  = SPH_N > PLN_N ? SPH_N : PLN_N;
    localparam integer OW     = $clog2(OBJ_N);      // an object index
    localparam integer SPW    = $clog2(STK_N);      // the stack pointer
    localparam integer RAW    = $clog2(ROT_N);      // a rotation axis
    localparam integer NSW    = `ISA_DIM_CFG_SPHERES_BITS;
    localparam integer NPW    = `ISA_DIM_CFG_PLANES_BITS;
    localparam integer DW     = `ISA_DIM_CFG_DEPTH_BITS;

    // Object kinds, search contexts.
    localparam       K_SPH = 1'b0, K_PLN = 1'b1;
    localparam       C_HIT = 1'b0, C_SHD = 1'b1;

    // The dot() call a DOT serves (program.rs), which fixes its operands and
    // where it returns.
    localparam integer CALLW = 4;
    localparam [CALLW-1:0] D_PRIMARY  = 4'd0,  // primary_ray: normalize(CUR_D, P), then nearest_hit
                           D_LIGHT    = 4'd1,  // shade: normalize(L, R), then shadowed
                           D_SPHERE   = 4'd2,  // sphere_u: b = v.d
                           D_DIFFUSE  = 4'd3,  // shade: n.l
                           D_REFLECT  = 4'd4,  // shade: d.n
                           D_SPECULAR = 4'd5,  // shade: r.l
                           D_RF_IN    = 4'd6,  // refract: d.n
                           D_RF_CHORD = 4'd7,  // refract: b = v.t
                           D_RF_OUT   = 4'd8;  // refract: t.n'

    // Where shade() resumes after a term (shade_next).
    localparam [1:0] S_DIFFUSE = 2'd0, S_REFLECT = 2'd1, S_SPECULAR = 2'd2, S_LOCAL = 2'd3;

    // Material bits (loader::MaterialBits::code).
    localparam integer MAT_DIFFUSE = 0, MAT_SPECULAR = 1, MAT_REFLECTIVE = 2;

    // Temporaries by role (program.rs, mod t).
    localparam [RW-1:0] T_P    = `ISA_REG_T0,
                        T_N    = `ISA_REG_T1,
                        T_R    = `ISA_REG_T2,
                        T_L    = `ISA_REG_T3,
                        T_LEN  = `ISA_REG_T4,
                        T_INV  = `ISA_REG_T5,
                        T_BEST = `ISA_REG_T6,
                        T_V    = `ISA_REG_T7,
                        T_G    = `ISA_REG_T8,
                        T_S    = `ISA_REG_T9,
                        T_Q    = `ISA_REG_T10,
                        T_U    = `ISA_REG_T11;

    localparam [LN-1:0] M_X = 1, M_Y = 2, M_Z = 4, M_XYZ = {LN{1'b1}};
    localparam [RW-1:0] R_PAR_D    = `ISA_REG_PAR_D;
    localparam [SW-1:0] ST_RF_NSUB = `ISA_ST_RF_NSUB;

    // ------------------------------------------------------------------------
    // The configuration
    // ------------------------------------------------------------------------
    wire [NSW-1:0]       n_sph     = cfg[`ISA_DIM_CFG_SPHERES_LSB +: NSW];
    wire [NPW-1:0]       n_pln     = cfg[`ISA_DIM_CFG_PLANES_LSB +: NPW];
    wire [DW-1:0]        max_depth = cfg[`ISA_DIM_CFG_DEPTH_LSB +: DW];
    wire                 bbox      = cfg[`ISA_DIM_CFG_BBOX_LSB];
    wire                 fast      = cfg[`ISA_DIM_CFG_FAST_PLANE_LSB];
    wire                 shortcut  = cfg[`ISA_DIM_CFG_SHORTCUT_LSB];
    wire                 cutoff    = cfg[`ISA_DIM_CFG_CUTOFF_LSB];
    wire [ROT_N-1:0]     rotate    = cfg[`ISA_DIM_CFG_ROTATE_LSB +: ROT_N];
    wire                 exposure  = cfg[`ISA_DIM_CFG_EXPOSURE_LSB];
    wire [SPH_N*MB-1:0]  sph_bits  = cfg[`ISA_DIM_CFG_SPH_BITS_LSB +: SPH_N*MB];
    wire [PLN_N*MB-1:0]  pln_bits  = cfg[`ISA_DIM_CFG_PLN_BITS_LSB +: PLN_N*MB];
    wire [PLN_N*AB-1:0]  pln_axis  = cfg[`ISA_DIM_CFG_PLN_AXIS_LSB +: PLN_N*AB];
    wire [PLN_N-1:0]     pln_neg   = cfg[`ISA_DIM_CFG_PLN_NEG_LSB +: PLN_N];
    // Without refraction no sphere is transparent: a build without it
    // draws a scene's glass opaque, so it is for scenes without glass.
    wire [SPH_N-1:0]     sph_trn   = REFRACTION != 0 ? cfg[`ISA_DIM_CFG_TRN_LSB +: SPH_N]
                                                     : {SPH_N{1'b0}};
    wire unused_trn = REFRACTION == 0 && ^cfg[`ISA_DIM_CFG_TRN_LSB +: SPH_N];
    // The word's spare bits.
    wire unused_cfg = ^{cfg[LN*32-1:`ISA_DIM_CFG_PLN_NEG_LSB + PLN_N],
                        cfg[`ISA_DIM_CFG_SPH_BITS_LSB - 1:`ISA_DIM_CFG_TRN_LSB + SPH_N],
                        cfg[`ISA_DIM_CFG_DEPTH_LSB - 1:`ISA_DIM_CFG_PLANES_LSB + NPW]};

    // ------------------------------------------------------------------------
    // Registers
    // ------------------------------------------------------------------------
    reg [SW-1:0]    st_q, st_d;
    reg [CW-1:0]    px_q, px_d, py_q, py_d;
    reg [SPW-1:0]   sp_q, sp_d;
    reg [RAW-1:0]   rot_q, rot_d;             // the rotation being applied
    reg [CALLW-1:0] call_q, call_d;           // the dot() call DOT_* and NORM_* serve
    reg             ctx_q, ctx_d;             // the search under way
    reg             kind_q, kind_d;           // the object under test
    reg [OW-1:0]    idx_q, idx_d;
    reg             found_q, found_d;         // nearest_hit: a hit so far; shadowed: true
    reg             facing_q, facing_d;       // shade: lit and n.l > 0 (the light reaches the surface)
    reg             best_kind_q, best_kind_d; // nearest_hit: the nearest hit so far
    reg [OW-1:0]    best_idx_q, best_idx_d;
    reg             excl_q, excl_d;           // obj is excluded from searches
    reg             obj_kind_q, obj_kind_d;   // the object being shaded (the last hit)
    reg [OW-1:0]    obj_idx_q, obj_idx_d;
    reg             push_q, push_d;           // its shading pushes a reflected ray
    reg             cut_q, cut_d;             // the weight cutoff refused the hit's child (CUT_CMP)
    reg             diff_q, diff_d;           // shade: the diffuse term is written
    reg             spec_q, spec_d;           // shade: the specular term is written
    reg [STK_N-1:0] col_q, col_d;             // the levels whose colour is written
    reg             refr_q, refr_d;           // its shading spawns a refracted child
    reg             rcut_q, rcut_d;           // the weight cutoff refused the refracted child (RF_CUT_CMP)
    reg [STK_N-1:0] pend_q, pend_d;           // per level: a refracted child is owed (after the reflected subtree)
    reg [STK_N*OW-1:0] pidx_q, pidx_d;        // per level: its sphere
    reg             rfneg_q, rfneg_d;         // refract: the chord's disc, or the exit's k', is < 0 (taken as 0)
    reg [LN-1:0]    dsign_q, dsign_d, dneg_q, dneg_d, dpos_q, dpos_d;  // DirFlags

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            st_q        <= `ISA_ST_IDLE;
            px_q        <= {CW{1'b0}};
            py_q        <= {CW{1'b0}};
            sp_q        <= {SPW{1'b0}};
            rot_q       <= {RAW{1'b0}};
            call_q      <= D_PRIMARY;
            ctx_q       <= C_HIT;
            kind_q      <= K_SPH;
            idx_q       <= {OW{1'b0}};
            found_q     <= 1'b0;
            facing_q    <= 1'b0;
            best_kind_q <= K_SPH;
            best_idx_q  <= {OW{1'b0}};
            excl_q      <= 1'b0;
            obj_kind_q  <= K_SPH;
            obj_idx_q   <= {OW{1'b0}};
            push_q      <= 1'b0;
            cut_q       <= 1'b0;
            diff_q      <= 1'b0;
            spec_q      <= 1'b0;
            col_q       <= {STK_N{1'b0}};
            refr_q      <= 1'b0;
            rcut_q      <= 1'b0;
            pend_q      <= {STK_N{1'b0}};
            pidx_q      <= {(STK_N*OW){1'b0}};
            rfneg_q     <= 1'b0;
            dsign_q     <= {LN{1'b0}};
            dneg_q      <= {LN{1'b0}};
            dpos_q      <= {LN{1'b0}};
        end else begin
            st_q        <= st_d;
            px_q        <= px_d;
            py_q        <= py_d;
            sp_q        <= sp_d;
            rot_q       <= rot_d;
            call_q      <= call_d;
            ctx_q       <= ctx_d;
            kind_q      <= kind_d;
            idx_q       <= idx_d;
            found_q     <= found_d;
            facing_q    <= facing_d;
            best_kind_q <= best_kind_d;
            best_idx_q  <= best_idx_d;
            excl_q      <= excl_d;
            obj_kind_q  <= obj_kind_d;
            obj_idx_q   <= obj_idx_d;
            push_q      <= push_d;
            cut_q       <= cut_d;
            diff_q      <= diff_d;
            spec_q      <= spec_d;
            col_q       <= col_d;
            refr_q      <= refr_d;
            rcut_q      <= rcut_d;
            pend_q      <= pend_d;
            pidx_q      <= pidx_d;
            rfneg_q     <= rfneg_d;
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
    // Addresses (golden::micro::isa::sphere, plane, corner, rot)
    // ------------------------------------------------------------------------
    // Register `field0` (an ISA_REG_SPH0_* / PLN0_* name) of sphere k, plane j.
    function [RW-1:0] sphere(input [OW-1:0] k, input [RW-1:0] field0);
        sphere = field0 + k * `ISA_DIM_SPH_STRIDE;
    endfunction
    function [RW-1:0] plane(input [OW-1:0] j, input [RW-1:0] field0);
        plane = field0 + j * `ISA_DIM_PLN_STRIDE;
    endfunction
    // Bounding-box corner s: lane i is the maximum iff bit i of s.
    function [RW-1:0] corner(input [LN-1:0] s);
        corner = `ISA_REG_BOX0 + s * `ISA_DIM_BOX_STRIDE;
    endfunction
    // ROTa_C, ROTa_S.
    function [RW-1:0] rot(input [RAW-1:0] a, input [RW-1:0] field0);
        rot = field0 + a * `ISA_DIM_ROT_STRIDE;
    endfunction

    wire [MB-1:0] obj_bits = bits(obj_kind_q, obj_idx_q, sph_bits, pln_bits);
    wire [RW-1:0] obj_mat  = obj_kind_q == K_SPH ? sphere(obj_idx_q, `ISA_REG_SPH0_MAT)
                                                 : plane(obj_idx_q, `ISA_REG_PLN0_MAT);
    wire [RW-1:0] obj_col  = obj_kind_q == K_SPH ? sphere(obj_idx_q, `ISA_REG_SPH0_COL)
                                                 : plane(obj_idx_q, `ISA_REG_PLN0_COL);
    wire [RW-1:0] obj_n    = obj_kind_q == K_SPH ? T_N : plane(obj_idx_q, `ISA_REG_PLN0_N);

    // The ray being shaded (program.rs, struct Shading): when pushing, the
    // child's level is current and the parent's is shaded.
    // A child is pushed for the reflected ray (push_q) or the refracted one
    // (refr_q): either way p goes to its origin.
    wire           child_q       = push_q || refr_q;
    wire [RW-1:0]  shading_o     = child_q ? `ISA_REG_PAR_O : `ISA_REG_CUR_O;
    wire [RW-1:0]  shading_d     = child_q ? `ISA_REG_PAR_D : `ISA_REG_CUR_D;
    wire [RW-1:0]  shading_col   = child_q ? `ISA_REG_PAR_COL : `ISA_REG_CUR_COL;
    wire [RW-1:0]  shading_w     = child_q ? `ISA_REG_PAR_W : `ISA_REG_CUR_W;
    wire [RW-1:0]  shading_p     = child_q ? `ISA_REG_CUR_O : T_P;
    wire [RW-1:0]  shading_r     = child_q ? `ISA_REG_CUR_D : T_R;
    wire [SPW-1:0] shading_level = child_q ? sp_q - 1'b1 : sp_q;

    // refract: sphere idx_q's registers (the jump into RF_NSUB sets it).
    wire [RW-1:0]  rf_c = sphere(idx_q, `ISA_REG_SPH0_C);
    wire [RW-1:0]  rf_r = sphere(idx_q, `ISA_REG_SPH0_R);
    wire [RW-1:0]  rf_t = `ISA_REG_TRN0 + idx_q * `ISA_DIM_TRN_STRIDE;
    wire           chord = REFRACTION != 0 && call_q == D_RF_CHORD;

    // The ray under test (the o, d of sphere_u, plane_u_checked, box_hit):
    // nearest_hit's is the current level's, shadowed's is (p, L).
    wire [RW-1:0] search_o = ctx_q == C_HIT ? `ISA_REG_CUR_O : shading_p;
    wire [RW-1:0] search_d = ctx_q == C_HIT ? `ISA_REG_CUR_D : T_L;

    // dot(y, a, b): the arguments of the dot() call being served.
    function [3*RW-1:0] dot_args(input [CALLW-1:0] call, input [RW-1:0] ray_d, input [RW-1:0] d,
                                 input [RW-1:0] r, input [RW-1:0] n);
        case (call)
            D_PRIMARY:  dot_args = {T_LEN, T_P, T_P};
            D_LIGHT:    dot_args = {T_LEN, T_R, T_R};
            D_SPHERE:   dot_args = {T_Q, T_V, ray_d};
            D_DIFFUSE:  dot_args = {T_V, n, T_L};
            D_REFLECT:  dot_args = {T_Q, d, n};
            D_RF_IN:    dot_args = {T_Q, R_PAR_D, T_N};
            D_RF_CHORD: dot_args = {T_Q, T_V, T_R};
            D_RF_OUT:   dot_args = {T_Q, T_R, T_N};
            default:    dot_args = {T_Q, r, T_L};
        endcase
    endfunction

    wire [RW-1:0] dot_y, dot_a, dot_b;
    assign {dot_y, dot_a, dot_b} = dot_args(call_q, search_d, shading_d, shading_r, obj_n);
    wire          normalize_primary = (call_q == D_PRIMARY);

    // The lanes a rotation about rot_q turns: u = rot + 1, v = rot + 2.
    wire [LN-1:0] rot_u = rot_q == 0 ? M_Y : rot_q == 1 ? M_Z : M_X;
    wire [LN-1:0] rot_v = rot_q == 0 ? M_Z : rot_q == 1 ? M_X : M_Y;
    wire [RW-1:0] rot_c = rot(rot_q, `ISA_REG_ROT0_C);
    wire [RW-1:0] rot_s = rot(rot_q, `ISA_REG_ROT0_S);

    // The destination of a test's u = -t: BEST for the first hit of a
    // nearest-hit search, else U (offer compares it with BEST).
    wire [RW-1:0] u_dst = (ctx_q == C_HIT && !found_q) ? T_BEST : T_U;

    // ------------------------------------------------------------------------
    // Next-state choices: the program's control flow between instructions
    // ------------------------------------------------------------------------
    // The direction flags the search decides with: those being latched this
    // cycle (NORM_SCALE, SH_REFL write the new direction), else the latched.
    wire          dir_latch = (st_q == `ISA_ST_NORM_SCALE) || (st_q == `ISA_ST_SH_REFL);
    wire [LN-1:0] dir_neg   = dir_latch ? y_neg : dneg_q;
    wire [LN-1:0] dir_pos   = dir_latch ? y_pos : dpos_q;

    // {found, k}: the first sphere k >= from, among spheres_other_than(skip):
    // the sphere loop's `continue`. Found at from = 0 is Rust's any_sphere.
    function [OW:0] spheres_other_than(input [OW:0] from, input [NSW-1:0] n, input skip,
                                        input [OW-1:0] skip_k);
        integer k;
        begin
            spheres_other_than = {(OW + 1){1'b0}};
            for (k = SPH_N - 1; k >= 0; k = k - 1)
                if (k >= from && k < n && !(skip && skip_k == k[OW-1:0]))
                    spheres_other_than = {1'b1, k[OW-1:0]};
        end
    endfunction

    // {found, j}: the first plane j >= from, not skipped, that
    // plane_u_checked does not refuse without an instruction (with the fast
    // plane test: a normal the direction does not oppose).
    function [OW:0] plane_u_checked(input [OW:0] from, input [NPW-1:0] n, input skip,
                                    input [OW-1:0] skip_j, input fast_on, input [PLN_N*AB-1:0] axis,
                                    input [PLN_N-1:0] neg, input [LN-1:0] dneg, input [LN-1:0] dpos);
        integer j;
        reg [LN-1:0] against;
        begin
            plane_u_checked = {(OW + 1){1'b0}};
            for (j = PLN_N - 1; j >= 0; j = j - 1) begin
                // DirFlags::opposes: a normal facing -axis needs d.axis > 0.
                against = neg[j] ? dpos : dneg;
                if (j >= from && j < n && !(skip && skip_j == j[OW-1:0]) &&
                    (!fast_on || against[axis[AB*j +: AB]]))
                    plane_u_checked = {1'b1, j[OW-1:0]};
            end
        end
    endfunction

    wire          skip_sph  = excl_q && obj_kind_q == K_SPH;
    wire          skip_pln  = excl_q && obj_kind_q == K_PLN;
    wire [OW:0]   sph_first = spheres_other_than({(OW + 1){1'b0}}, n_sph, skip_sph, obj_idx_q);
    wire [OW:0]   sph_next  = spheres_other_than({1'b0, idx_q} + 1'b1, n_sph, skip_sph, obj_idx_q);
    wire [OW:0]   pln_first = plane_u_checked({(OW + 1){1'b0}}, n_pln, skip_pln, obj_idx_q,
                                              fast, pln_axis, pln_neg, dir_neg, dir_pos);
    wire [OW:0]   pln_next  = plane_u_checked({1'b0, idx_q} + 1'b1, n_pln, skip_pln, obj_idx_q,
                                              fast, pln_axis, pln_neg, dir_neg, dir_pos);

    // Box test (box_hit, separated): lane i of the difference is
    // N_i d_j - F_j d_i with j = i + shift; it proves t_near_i > t_far_j if
    // it is > 0 where d_i and d_j have the same sign, < 0 where they differ.
    // sign_j is the direction's sign vector rotated by shift lanes.
    function separated(input [LN-1:0] pos, input [LN-1:0] neg, input [LN-1:0] sign,
                       input [LN-1:0] sign_j);
        separated = |((pos & ~(sign ^ sign_j)) | (neg & (sign ^ sign_j)));
    endfunction
    wire [LN-1:0] dsign_r1 = {dsign_q[0], dsign_q[LN-1:1]};              // lane i: sign of d_(i+1)
    wire [LN-1:0] dsign_r2 = {dsign_q[1:0], dsign_q[LN-1:2]};            // lane i: sign of d_(i+2)

    // run: shading the nearest hit pushes its reflected ray if the object
    // is reflective and the stack has a level left.
    // With the weight cutoff, cut() first (CUT_W, CUT_CMP) where a push
    // would follow, and no push if it refused (cut_q).
    wire [MB-1:0] best_bits = bits(best_kind_q, best_idx_q, sph_bits, pln_bits);
    wire          room      = ({1'b0, sp_q} + 1'b1 < max_depth);
    wire          run_push  = best_bits[MAT_REFLECTIVE] && room && !(cutoff && cut_q);
    // ... and its refracted child if it is a transparent sphere.
    wire          best_trn  = best_kind_q == K_SPH && sph_trn[best_idx_q];
    wire          run_refr  = best_trn && room && !(cutoff && rcut_q);
    wire          unused_best_terms = best_bits[MAT_DIFFUSE] ^ best_bits[MAT_SPECULAR];

    // run: the first state of shading a search's nearest hit (kind, idx):
    // with the cutoff on and a level left, cut() for its reflected child
    // (CUT_W) if it is reflective, else for its refracted one (RF_CUT_W) if
    // it is a transparent sphere; else SH_OFFSET.
    function [SW-1:0] shade_first(input on, input kind, input [OW-1:0] idx,
                                  input [SPH_N*MB-1:0] sph, input [PLN_N*MB-1:0] pln,
                                  input [SPH_N-1:0] trn, input room_on);
        reg [MB-1:0] b;
        begin
            b = bits(kind, idx, sph, pln);
            if (on && room_on && b[MAT_REFLECTIVE])
                shade_first = `ISA_ST_CUT_W;
            else if (on && room_on && kind == K_SPH && trn[idx])
                shade_first = `ISA_ST_RF_CUT_W;
            else
                shade_first = `ISA_ST_SH_OFFSET;
        end
    endfunction
    // The nearest hit so far, and the object under test (which becomes the
    // nearest hit in the cycle that decides: offer's first hit, HIT_KEEP).
    wire [SW-1:0] cut_best = shade_first(cutoff, best_kind_q, best_idx_q, sph_bits, pln_bits,
                                         sph_trn, room);
    wire [SW-1:0] cut_this = shade_first(cutoff, kind_q, idx_q, sph_bits, pln_bits, sph_trn, room);
    // cut(): the hit object's kr and its copy of the cutoff (lane z of its
    // R / Q register).
    wire [RW-1:0] best_mat = best_kind_q == K_SPH ? sphere(best_idx_q, `ISA_REG_SPH0_MAT)
                                                  : plane(best_idx_q, `ISA_REG_PLN0_MAT);
    wire [RW-1:0] best_cut = best_kind_q == K_SPH ? sphere(best_idx_q, `ISA_REG_SPH0_R)
                                                  : plane(best_idx_q, `ISA_REG_PLN0_Q);

    // The state after the pixel's colour is complete: the exposure (expose
    // in program.rs) when the scene has one, else PIX_DONE.
    wire [SW-1:0] pixel_end = exposure ? `ISA_ST_EXPO_MUL : `ISA_ST_PIX_DONE;

    // unwind: skip the levels above the highest one at or below `from` that
    // is coloured (a POP adds it into its parent) or whose parent owes a
    // refracted child (which takes that level next); their `if` issues
    // nothing. Then that POP, or the refracted child (RF_NSUB, its sphere
    // in idx); with no such level, `last` (or ROOT_BLACK if level 0 has no
    // colour): {st, sp, kind, idx}.
    function [SW+SPW+1+OW-1:0] unwind(input [SPW-1:0] from, input [STK_N-1:0] col,
                                      input [STK_N-1:0] pend, input [STK_N*OW-1:0] pidx,
                                      input [SW-1:0] last);
        integer   l;
        reg       found;
        reg [SPW-1:0] lvl, up;
        begin
            found = 1'b0;
            lvl   = {SPW{1'b0}};
            for (l = 1; l < STK_N; l = l + 1)
                if (l[SPW-1:0] <= from && (col[l] || pend[l - 1])) begin
                    found = 1'b1;
                    lvl   = l[SPW-1:0];
                end
            up = lvl - 1'b1;
            unwind[0 +: OW]             = pidx[OW*up +: OW];
            unwind[OW]                  = K_SPH;
            unwind[1 + OW +: SPW]       = lvl;
            if (found && col[lvl])
                unwind[1 + OW + SPW +: SW] = col[lvl - 1'b1] ? `ISA_ST_POP_ADD : `ISA_ST_POP_MOV;
            else if (found)
                unwind[1 + OW + SPW +: SW] = `ISA_ST_RF_NSUB;
            else
                unwind[1 + OW + SPW +: SW] = col[0] ? last : `ISA_ST_ROOT_BLACK;
        end
    endfunction
    // A jump from an unwind: {st, sp, call, kind, idx}.
    function [SW+SPW+CALLW+1+OW-1:0] unwind_jump(input [SW+SPW+1+OW-1:0] u, input [CALLW-1:0] call);
        unwind_jump = {u[1 + OW +: SW + SPW], call, u[0 +: 1 + OW]};
    endfunction

    // A jump: the next {st, sp, call, kind, idx}. `stay` keeps them all.
    localparam integer JW = SW + SPW + CALLW + 1 + OW;
    localparam integer J_IDX = 0, J_KIND = OW, J_CALL = OW + 1, J_ST = OW + 1 + CALLW + SPW;
    wire [JW-1:0] stay       = {st_q, sp_q, call_q, kind_q, idx_q};
    wire [SPW-1:0] sp_up       = sp_q - 1'b1;
    // The pending children as they stand after this cycle's SH_CHILD_W,
    // whose child's search may end (and unwind) in the same cycle.
    wire               owes_now = (st_q == `ISA_ST_SH_CHILD_W) && refr_q;
    wire [STK_N-1:0]   pend_now = owes_now ? (pend_q | ({{(STK_N - 1){1'b0}}, 1'b1} << sp_up)) : pend_q;
    reg  [STK_N*OW-1:0] pidx_now;
    always @* begin
        pidx_now = pidx_q;
        if (owes_now) pidx_now[OW*sp_up +: OW] = obj_idx_q;
    end
    wire [JW-1:0] unwind_now = unwind_jump(unwind(sp_q, col_q, pend_now, pidx_now, pixel_end), call_q);
    // After a POP at level sp: its parent's refracted child takes the level.
    wire [JW-1:0] refract_here = {ST_RF_NSUB, sp_q, call_q, K_SPH, pidx_q[OW*sp_up +: OW]};
    // The end of shading: the refracted child at once if it is the only one
    // (sp is already its level), else the unwinding.
    wire [JW-1:0] shade_end    = (refr_q && !push_q) ? {ST_RF_NSUB, sp_q, call_q, K_SPH, obj_idx_q}
                                                     : unwind_now;

    // bits, shade_next, nearest_hit_next, primary_ray_next, decoded_st
    // (shared with fast_ctrl).
    `include "ctrl_flow.vh"

    // The state the case below decodes (st_q, or none for a refraction
    // state without refraction).
    wire [SW-1:0] st_dec = decoded_st(st_q, REFRACTION != 0);

    // shadowed() has returned: lit = !shadowed (found_q from then on).
    wire [JW-1:0] shadowed_false = shade_next(S_DIFFUSE, 1'b1, diff_q, spec_q, obj_bits, push_q,
                                              stay, shade_end);
    wire [JW-1:0] shadowed_true  = shade_next(S_DIFFUSE, 1'b0, diff_q, spec_q, obj_bits, push_q,
                                              stay, shade_end);

    localparam [OW:0] NONE = {(OW + 1){1'b0}};
    wire          in_spheres = (kind_q == K_SPH);
    wire [OW:0]   after_sph  = in_spheres ? sph_next : NONE;
    wire [OW:0]   after_pln  = in_spheres ? pln_first : pln_next;

    // The search starts (nearest_hit, shadowed from the top).
    wire [JW-1:0] nearest_hit_start  = nearest_hit_next(stay, bbox, sph_first, 1'b1, pln_first, C_HIT,
                                                        1'b0, shortcut, cut_best, shadowed_false, unwind_now);
    wire [JW-1:0] shadowed_start     = nearest_hit_next(stay, bbox, sph_first, 1'b1, pln_first, C_SHD,
                                                        1'b0, shortcut, cut_best, shadowed_false, unwind_now);
    // The box refuses the ray: the sphere loop is skipped.
    wire [JW-1:0] box_hit_false      = nearest_hit_next(stay, 1'b0, NONE, 1'b1, pln_first, ctx_q,
                                                        found_q, shortcut, cut_best, shadowed_false, unwind_now);
    // Past the object under test (the loop's next iteration).
    wire [JW-1:0] nearest_hit_after  = nearest_hit_next(stay, 1'b0, after_sph, in_spheres, after_pln, ctx_q,
                                                        found_q, shortcut, cut_best, shadowed_false, unwind_now);
    // The same after HIT_KEEP, whose object becomes the nearest hit.
    wire [JW-1:0] nearest_hit_kept   = nearest_hit_next(stay, 1'b0, after_sph, in_spheres, after_pln, ctx_q,
                                                        found_q, shortcut, cut_this, shadowed_false, unwind_now);
    // offer: the first hit is the best where it was written (the search
    // goes on); a later one is compared (HIT_CMP).
    function [JW-1:0] offer(input found, input [JW-1:0] stay_j, input [JW-1:0] first_j);
        begin
            offer = first_j;
            if (found) begin
                offer = stay_j;
                offer[J_ST +: SW] = `ISA_ST_HIT_CMP;
            end
        end
    endfunction
    wire [JW-1:0] offer_next = offer(found_q, stay,
                                     nearest_hit_next(stay, 1'b0, after_sph, in_spheres, after_pln, ctx_q,
                                                      1'b1, shortcut, cut_this, shadowed_false, unwind_now));

    // ------------------------------------------------------------------------
    // The instruction and the next state of each state
    // ------------------------------------------------------------------------
    always @* begin
        // No instruction; the read ports on ZERO; every register kept.
        op          = `ISA_OP_NOP;
        la_a        = `ISA_REG_ZERO;
        la_b        = `ISA_REG_ZERO;
        la_w        = `ISA_REG_ZERO;
        wmask       = M_XYZ;
        st_d        = st_q;
        px_d        = px_q;
        py_d        = py_q;
        sp_d        = sp_q;
        rot_d       = rot_q;
        call_d      = call_q;
        ctx_d       = ctx_q;
        kind_d      = kind_q;
        idx_d       = idx_q;
        found_d     = found_q;
        facing_d    = facing_q;
        best_kind_d = best_kind_q;
        best_idx_d  = best_idx_q;
        excl_d      = excl_q;
        obj_kind_d  = obj_kind_q;
        obj_idx_d   = obj_idx_q;
        push_d      = push_q;
        cut_d       = cut_q;
        diff_d      = diff_q;
        spec_d      = spec_q;
        col_d       = col_q;
        refr_d      = refr_q;
        rcut_d      = rcut_q;
        pend_d      = pend_q;
        pidx_d      = pidx_q;
        rfneg_d     = rfneg_q;
        dsign_d     = dsign_q;
        dneg_d      = dneg_q;
        dpos_d      = dpos_q;

        case (st_dec)
            // Wait for a pixel; the edge that takes start latches it, and the
            // first instruction follows at once (no start cycle).
            `ISA_ST_IDLE: if (start) begin
                px_d    = px;
                py_d    = py;
                sp_d    = {SPW{1'b0}};
                col_d   = {STK_N{1'b0}};
                excl_d  = 1'b0;
                push_d  = 1'b0;
                cut_d   = 1'b0;
                refr_d  = 1'b0;
                rcut_d  = 1'b0;
                pend_d  = {STK_N{1'b0}};
                dsign_d = {LN{1'b0}};
                dneg_d  = {LN{1'b0}};
                dpos_d  = {LN{1'b0}};
                st_d    = `ISA_ST_PRI_ITOF;
            end

            // ---- primary_ray ----------------------------------------------
            // P = itof(<px, -py, 0>)
            `ISA_ST_PRI_ITOF: begin
                op = `ISA_OP_ITOF; la_w = T_P;
                st_d = `ISA_ST_PRI_HALF;
            end
            // P = P + CAM_HALF, then the rotations, then normalize
            `ISA_ST_PRI_HALF: begin
                op = `ISA_OP_ADD; la_w = T_P; la_a = T_P; la_b = `ISA_REG_CAM_HALF;
                {rot_d, st_d, call_d} = primary_ray_next(rotate, {(RAW + 1){1'b0}}, rot_q, call_q);
            end
            // N = P * ROTa_C
            `ISA_ST_ROT_COS: begin
                op = `ISA_OP_MUL; la_w = T_N; la_a = T_P; la_b = rot_c;
                st_d = `ISA_ST_ROT_SIN_U;
            end
            // R.u = ROTa_S.u * P.v
            `ISA_ST_ROT_SIN_U: begin
                op = `ISA_OP_MULR1; la_w = T_R; la_a = rot_s; la_b = T_P; wmask = rot_u;
                st_d = `ISA_ST_ROT_SIN_V;
            end
            // R.v = ROTa_S.v * P.u
            `ISA_ST_ROT_SIN_V: begin
                op = `ISA_OP_MULR2; la_w = T_R; la_a = rot_s; la_b = T_P; wmask = rot_v;
                st_d = `ISA_ST_ROT_ADD;
            end
            // P.uv = N + R, then the next rotation or normalize
            `ISA_ST_ROT_ADD: begin
                op = `ISA_OP_ADD; la_w = T_P; la_a = T_N; la_b = T_R; wmask = rot_u | rot_v;
                {rot_d, st_d, call_d} = primary_ray_next(rotate, {1'b0, rot_q} + 1'b1, rot_q, call_q);
            end

            // ---- dot: y.x = a.b, then back to the caller -----------------
            `ISA_ST_DOT_1: begin
                op = `ISA_OP_DOT1; la_a = dot_a; la_b = dot_b;
                st_d = `ISA_ST_DOT_2;
            end
            `ISA_ST_DOT_2: begin
                op = `ISA_OP_DOT2;
                st_d = `ISA_ST_DOT_3;
            end
            `ISA_ST_DOT_3: begin
                op = `ISA_OP_DOT3; la_w = dot_y; wmask = M_X;
                case (call_q)
                    D_PRIMARY, D_LIGHT:
                        st_d = `ISA_ST_NORM_ROOTS;
                    // sphere_u: b >= 0, the near root is not ahead.
                    D_SPHERE:
                        if (y_neg[0]) st_d = `ISA_ST_SPH_BD;
                        else {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_after;
                    // shade: n.l > 0 and a diffuse term, or on to the
                    // reflection and the (gated) highlight.
                    D_DIFFUSE: begin
                        facing_d = y_pos[0];
                        if (y_pos[0] && obj_bits[MAT_DIFFUSE]) st_d = `ISA_ST_SH_KD;
                        else {st_d, sp_d, call_d, kind_d, idx_d} =
                            shade_next(S_REFLECT, y_pos[0], diff_q, spec_q, obj_bits, push_q, stay, shade_end);
                    end
                    D_REFLECT:
                        st_d = `ISA_ST_SH_REFL_K;
                    D_RF_IN:
                        if (REFRACTION != 0) st_d = `ISA_ST_RF_COS2;
                    D_RF_CHORD:
                        if (REFRACTION != 0) st_d = `ISA_ST_RF_CBD;
                    D_RF_OUT:
                        if (REFRACTION != 0) st_d = `ISA_ST_RF_OCOS2;
                    // shade: r.l > 0, or no specular term.
                    default:
                        if (y_pos[0]) st_d = `ISA_ST_SH_POW2;
                        else {st_d, sp_d, call_d, kind_d, idx_d} =
                            shade_next(S_LOCAL, facing_q, diff_q, spec_q, obj_bits, push_q, stay, shade_end);
                endcase
            end

            // ---- normalize: y = v / |v| after dot(LEN, v, v) ----------------
            // LEN = <|v|, 1/(v.v)>
            `ISA_ST_NORM_ROOTS: begin
                op = `ISA_OP_ROOTS; la_w = T_LEN; la_a = T_LEN; wmask = M_X | M_Y;
                if (alu_done) st_d = `ISA_ST_NORM_INV;
            end
            // INV.x = |v| * 1/(v.v)
            `ISA_ST_NORM_INV: begin
                op = `ISA_OP_MULR1; la_w = T_INV; la_a = T_LEN; la_b = T_LEN; wmask = M_X;
                st_d = `ISA_ST_NORM_SCALE;
            end
            // y = v * INV.x; latch its DirFlags; then the search: nearest_hit
            // for the primary ray, shadowed for the light vector.
            `ISA_ST_NORM_SCALE: begin
                op   = `ISA_OP_MULX;
                la_w = normalize_primary ? `ISA_REG_CUR_D : T_L;
                la_a = normalize_primary ? T_P : T_R;
                la_b = T_INV;
                dsign_d = y_sign;
                dneg_d  = y_neg;
                dpos_d  = y_pos;
                ctx_d   = normalize_primary ? C_HIT : C_SHD;
                found_d = 1'b0;
                {st_d, sp_d, call_d, kind_d, idx_d} = normalize_primary ? nearest_hit_start : shadowed_start;
            end

            // ---- isect: the shared sub-graph ---------------------------------
            // spheres: b = c = w (in V), a = r*r; planes: b = o, c = n, a = q
            `ISA_ST_ISECT_1: begin
                op   = `ISA_OP_ISECT1;
                la_a = kind_q == K_SPH ? T_V : search_o;
                la_b = kind_q == K_SPH ? T_V : plane(idx_q, `ISA_REG_PLN0_N);
                st_d = `ISA_ST_ISECT_2;
            end
            `ISA_ST_ISECT_2: begin
                op   = `ISA_OP_ISECT2;
                la_w = T_G;
                la_a = chord ? T_R : search_d;
                la_b = kind_q == K_SPH ? T_V : plane(idx_q, `ISA_REG_PLN0_N);
                st_d = `ISA_ST_ISECT_3;
            end
            `ISA_ST_ISECT_3: begin
                op = `ISA_OP_ISECT3; la_a = T_G;
                st_d = `ISA_ST_ISECT_4;
            end
            // S = <a - b.c, c.d, 0>: a sphere's disc < 0 misses; a plane that
            // faces away (n.d >= 0) is refused unless the fast test decided.
            `ISA_ST_ISECT_4: begin
                op   = `ISA_OP_ISECT4;
                la_w = T_S;
                la_a = kind_q == K_SPH ? sphere(idx_q, `ISA_REG_SPH0_R) : plane(idx_q, `ISA_REG_PLN0_Q);
                if (chord) begin
                    // refract: the chord's disc < 0 (rounding) is taken as 0.
                    rfneg_d = y_neg[0];
                    st_d    = y_neg[0] ? `ISA_ST_RF_CS : `ISA_ST_RF_CSQRT;
                end else if (kind_q == K_SPH ? y_neg[0] : (!fast && !y_neg[1]))
                    {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_after;
                else
                    st_d = kind_q == K_SPH ? `ISA_ST_SPH_SQRT : `ISA_ST_PLN_RECIP;
            end

            // ---- box_hit: the far corner first -----------------------------
            // G = BOX(~s) - o
            `ISA_ST_BOX_FAR: begin
                op = `ISA_OP_SUB; la_w = T_G; la_a = corner(~dsign_q); la_b = search_o;
                st_d = `ISA_ST_BOX_BEHIND;
            end
            // S = G * d: a negative lane puts the box behind the ray
            `ISA_ST_BOX_BEHIND: begin
                op = `ISA_OP_MUL; la_w = T_S; la_a = T_G; la_b = search_d;
                if (|y_neg) {st_d, sp_d, call_d, kind_d, idx_d} = box_hit_false;
                else        st_d = `ISA_ST_BOX_NEAR;
            end
            // V = BOX(s) - o
            `ISA_ST_BOX_NEAR: begin
                op = `ISA_OP_SUB; la_w = T_V; la_a = corner(dsign_q); la_b = search_o;
                st_d = `ISA_ST_BOX_P1;
            end
            // Q = N_i d_(i+1)
            `ISA_ST_BOX_P1: begin
                op = `ISA_OP_MULR1; la_w = T_Q; la_a = T_V; la_b = search_d;
                st_d = `ISA_ST_BOX_Q1;
            end
            // U = d_i F_(i+1)
            `ISA_ST_BOX_Q1: begin
                op = `ISA_OP_MULR1; la_w = T_U; la_a = search_d; la_b = T_G;
                st_d = `ISA_ST_BOX_D1;
            end
            // Q = Q - U: entry i against exit i+1
            `ISA_ST_BOX_D1: begin
                op = `ISA_OP_SUB; la_w = T_Q; la_a = T_Q; la_b = T_U;
                if (separated(y_pos, y_neg, dsign_q, dsign_r1))
                    {st_d, sp_d, call_d, kind_d, idx_d} = box_hit_false;
                else
                    st_d = `ISA_ST_BOX_P2;
            end
            // Q = N_i d_(i+2)
            `ISA_ST_BOX_P2: begin
                op = `ISA_OP_MULR2; la_w = T_Q; la_a = T_V; la_b = search_d;
                st_d = `ISA_ST_BOX_Q2;
            end
            // U = d_i F_(i+2)
            `ISA_ST_BOX_Q2: begin
                op = `ISA_OP_MULR2; la_w = T_U; la_a = search_d; la_b = T_G;
                st_d = `ISA_ST_BOX_D2;
            end
            // Q = Q - U: entry i against exit i+2; else the first sphere
            `ISA_ST_BOX_D2: begin
                op = `ISA_OP_SUB; la_w = T_Q; la_a = T_Q; la_b = T_U;
                if (separated(y_pos, y_neg, dsign_q, dsign_r2))
                    {st_d, sp_d, call_d, kind_d, idx_d} = box_hit_false;
                else begin
                    st_d   = `ISA_ST_SPH_V;
                    kind_d = K_SPH;
                    idx_d  = sph_first[OW-1:0];
                end
            end

            // ---- sphere_u -----------------------------------------------------
            // V = o - c, then b = v.d
            `ISA_ST_SPH_V: begin
                op = `ISA_OP_SUB; la_w = T_V; la_a = search_o; la_b = sphere(idx_q, `ISA_REG_SPH0_C);
                st_d   = `ISA_ST_DOT_1;
                call_d = D_SPHERE;
            end
            // U = -b d
            `ISA_ST_SPH_BD: begin
                op = `ISA_OP_NMULX; la_w = T_U; la_a = search_d; la_b = T_Q;
                st_d = `ISA_ST_SPH_W;
            end
            // V = w = v - b d, then disc by ISECT
            `ISA_ST_SPH_W: begin
                op = `ISA_OP_ADD; la_w = T_V; la_a = T_V; la_b = T_U;
                st_d = `ISA_ST_ISECT_1;
            end
            // S.x = sqrt(disc)
            `ISA_ST_SPH_SQRT: begin
                op = `ISA_OP_SQRT; la_w = T_S; la_a = T_S; wmask = M_X;
                if (alu_done) st_d = `ISA_ST_SPH_T;
            end
            // u = sqrt(disc) + b = -t: behind the ray unless u < 0; a hit is
            // offered (nearest_hit) or blocks (shadowed: at once with the
            // shortcut, else if before the light)
            `ISA_ST_SPH_T: begin
                op = `ISA_OP_ADD; la_w = u_dst; la_a = T_S; la_b = T_Q; wmask = M_X;
                if (!y_neg[0])
                    {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_after;
                else if (ctx_q == C_HIT) begin
                    if (!found_q) {best_kind_d, best_idx_d} = {kind_q, idx_q};
                    found_d = 1'b1;
                    {st_d, sp_d, call_d, kind_d, idx_d} = offer_next;
                end else if (shortcut) begin
                    found_d = 1'b1;
                    {st_d, sp_d, call_d, kind_d, idx_d} = shadowed_true;
                end else
                    st_d = `ISA_ST_SHD_DIST;
            end

            // ---- plane_u --------------------------------------------------------
            // Q.x = 1 / (n.d)
            `ISA_ST_PLN_RECIP: begin
                op = `ISA_OP_RECIPY; la_w = T_Q; la_a = T_S; wmask = M_X;
                if (alu_done) st_d = `ISA_ST_PLN_T;
            end
            // u = -((q - n.o) * 1/(n.d)) = -t: ahead if u < 0 (assumed with
            // the fast test); offered, or checked against the light
            `ISA_ST_PLN_T: begin
                op = `ISA_OP_NMULX; la_w = u_dst; la_a = T_S; la_b = T_Q; wmask = M_X;
                if (!(fast || y_neg[0]))
                    {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_after;
                else if (ctx_q == C_HIT) begin
                    if (!found_q) {best_kind_d, best_idx_d} = {kind_q, idx_q};
                    found_d = 1'b1;
                    {st_d, sp_d, call_d, kind_d, idx_d} = offer_next;
                end else
                    st_d = `ISA_ST_SHD_DIST;
            end

            // ---- offer --------------------------------------------------------
            // G.x = u - u_best > 0: nearer than the best so far
            `ISA_ST_HIT_CMP: begin
                op = `ISA_OP_SUB; la_w = T_G; la_a = T_U; la_b = T_BEST; wmask = M_X;
                if (y_pos[0]) st_d = `ISA_ST_HIT_KEEP;
                else          {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_after;
            end
            // BEST.x = u
            `ISA_ST_HIT_KEEP: begin
                op = `ISA_OP_MOV; la_w = T_BEST; la_a = T_U; wmask = M_X;
                {best_kind_d, best_idx_d} = {kind_q, idx_q};
                {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_kept;
            end

            // ---- cut: the weight cutoff, before shading a hit that pushes --
            // U.z = CUR_W.z * kr: the child's weight
            `ISA_ST_CUT_W: begin
                op = `ISA_OP_MULZ; la_w = T_U; la_a = `ISA_REG_CUR_W; la_b = best_mat; wmask = M_Z;
                st_d = `ISA_ST_CUT_CMP;
            end
            // G.z = U.z - c < 0: the child is refused (run_push reads cut_q)
            `ISA_ST_CUT_CMP: begin
                op = `ISA_OP_SUB; la_w = T_G; la_a = T_U; la_b = best_cut; wmask = M_Z;
                cut_d = y_neg[2];
                st_d  = (best_trn && room) ? `ISA_ST_RF_CUT_W : `ISA_ST_SH_OFFSET;
            end
            // U.z = CUR_W.z * kt: the refracted child's weight
            `ISA_ST_RF_CUT_W: begin
                op = `ISA_OP_MULZ; la_w = T_U; la_a = `ISA_REG_CUR_W;
                la_b = `ISA_REG_TRN0 + best_idx_q * `ISA_DIM_TRN_STRIDE; wmask = M_Z;
                st_d = `ISA_ST_RF_CUT_CMP;
            end
            // G.z = U.z - c < 0: no refracted child (run_refr reads rcut_q)
            `ISA_ST_RF_CUT_CMP: begin
                op = `ISA_OP_SUB; la_w = T_G; la_a = T_U; la_b = best_cut; wmask = M_Z;
                rcut_d = y_neg[2];
                st_d   = `ISA_ST_SH_OFFSET;
            end

            // ---- before_light --------------------------------------------------
            // G.x = |light - p| + u > 0: the blocker is before the light
            `ISA_ST_SHD_DIST: begin
                op = `ISA_OP_ADD; la_w = T_G; la_a = T_U; la_b = T_LEN; wmask = M_X;
                if (y_pos[0]) begin
                    found_d = 1'b1;
                    {st_d, sp_d, call_d, kind_d, idx_d} = shadowed_true;
                end else
                    {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_after;
            end

            // ---- shade --------------------------------------------------------
            // V = -(d * u_best) = t d. The ray being shaded is still the
            // current level: run pushes the child (sp + 1) at this edge, and
            // the shaded object's bits and exclusion take effect.
            `ISA_ST_SH_OFFSET: begin
                op = `ISA_OP_NMULX; la_w = T_V; la_a = `ISA_REG_CUR_D; la_b = T_BEST;
                push_d     = run_push;
                refr_d     = run_refr;
                cut_d      = 1'b0;
                rcut_d     = 1'b0;
                sp_d       = sp_q + {{(SPW - 1){1'b0}}, run_push || run_refr};
                // The child's level may hold an earlier subtree's colour.
                if (run_push || run_refr) col_d[sp_q + 1'b1] = 1'b0;
                obj_kind_d = best_kind_q;
                obj_idx_d  = best_idx_q;
                excl_d     = 1'b1;
                diff_d     = 1'b0;
                spec_d     = 1'b0;
                facing_d   = 1'b0;
                st_d       = `ISA_ST_SH_POINT;
            end
            // p = o + t d
            `ISA_ST_SH_POINT: begin
                op = `ISA_OP_ADD; la_w = shading_p; la_a = shading_o; la_b = T_V;
                st_d = obj_kind_q == K_SPH ? `ISA_ST_SH_NORMAL_SUB : `ISA_ST_SH_LIGHT_VEC;
            end
            // N = p - c
            `ISA_ST_SH_NORMAL_SUB: begin
                op = `ISA_OP_SUB; la_w = T_N; la_a = shading_p; la_b = sphere(obj_idx_q, `ISA_REG_SPH0_C);
                st_d = `ISA_ST_SH_NORMAL_SCALE;
            end
            // N = (p - c) * 1/r
            `ISA_ST_SH_NORMAL_SCALE: begin
                op = `ISA_OP_MULY; la_w = T_N; la_a = T_N; la_b = sphere(obj_idx_q, `ISA_REG_SPH0_R);
                st_d = `ISA_ST_SH_LIGHT_VEC;
            end
            // R = light - p, then normalize(L, R)
            `ISA_ST_SH_LIGHT_VEC: begin
                op = `ISA_OP_SUB; la_w = T_R; la_a = `ISA_REG_LIGHT_POS; la_b = shading_p;
                st_d   = `ISA_ST_DOT_1;
                call_d = D_LIGHT;
            end
            // G.x = kd * (n.l)
            `ISA_ST_SH_KD: begin
                op = `ISA_OP_MULX; la_w = T_G; la_a = obj_mat; la_b = T_V; wmask = M_X;
                st_d = `ISA_ST_SH_CL;
            end
            // S = colour * light colour
            `ISA_ST_SH_CL: begin
                op = `ISA_OP_MUL; la_w = T_S; la_a = obj_col; la_b = `ISA_REG_LIGHT_COL;
                st_d = `ISA_ST_SH_DIFFUSE;
            end
            // S = S * G.x: the diffuse term
            `ISA_ST_SH_DIFFUSE: begin
                op = `ISA_OP_MULX; la_w = T_S; la_a = T_S; la_b = T_G;
                diff_d = 1'b1;
                {st_d, sp_d, call_d, kind_d, idx_d} =
                    shade_next(S_REFLECT, facing_q, 1'b1, spec_q, obj_bits, push_q, stay, shade_end);
            end
            // U = 2 (d.n) n
            `ISA_ST_SH_REFL_K: begin
                op = `ISA_OP_MUL2X; la_w = T_U; la_a = obj_n; la_b = T_Q;
                st_d = `ISA_ST_SH_REFL;
            end
            // r = d - U; latch its DirFlags
            `ISA_ST_SH_REFL: begin
                op = `ISA_OP_SUB; la_w = shading_r; la_a = shading_d; la_b = T_U;
                dsign_d = y_sign;
                dneg_d  = y_neg;
                dpos_d  = y_pos;
                {st_d, sp_d, call_d, kind_d, idx_d} =
                    shade_next(S_SPECULAR, facing_q, diff_q, spec_q, obj_bits, push_q, stay, shade_end);
            end
            // U.x = x^2, x^4, x^5, x^10, x^20 (x = r.l)
            `ISA_ST_SH_POW2: begin
                op = `ISA_OP_MUL; la_w = T_U; la_a = T_Q; la_b = T_Q; wmask = M_X;
                st_d = `ISA_ST_SH_POW4;
            end
            `ISA_ST_SH_POW4: begin
                op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_U; wmask = M_X;
                st_d = `ISA_ST_SH_POW5;
            end
            `ISA_ST_SH_POW5: begin
                op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_Q; wmask = M_X;
                st_d = `ISA_ST_SH_POW10;
            end
            `ISA_ST_SH_POW10: begin
                op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_U; wmask = M_X;
                st_d = `ISA_ST_SH_POW20;
            end
            `ISA_ST_SH_POW20: begin
                op = `ISA_OP_MUL; la_w = T_U; la_a = T_U; la_b = T_U; wmask = M_X;
                st_d = `ISA_ST_SH_KS;
            end
            // V.y = ks * x^20
            `ISA_ST_SH_KS: begin
                op = `ISA_OP_MULX; la_w = T_V; la_a = obj_mat; la_b = T_U; wmask = M_Y;
                st_d = `ISA_ST_SH_SPEC;
            end
            // G = light colour * V.y: the specular term
            `ISA_ST_SH_SPEC: begin
                op = `ISA_OP_MULY; la_w = T_G; la_a = `ISA_REG_LIGHT_COL; la_b = T_V;
                spec_d = 1'b1;
                {st_d, sp_d, call_d, kind_d, idx_d} =
                    shade_next(S_LOCAL, facing_q, diff_q, 1'b1, obj_bits, push_q, stay, shade_end);
            end
            // S = diffuse + specular
            `ISA_ST_SH_LOCAL: begin
                op = `ISA_OP_ADD; la_w = T_S; la_a = T_S; la_b = T_G;
                st_d = `ISA_ST_SH_COLOUR;
            end
            // ray colour = local * w, then the child's weight or unwind
            `ISA_ST_SH_COLOUR: begin
                op   = `ISA_OP_MUL;
                la_w = shading_col;
                la_a = (spec_q && !diff_q) ? T_G : T_S;
                la_b = shading_w;
                col_d[shading_level] = 1'b1;
                if (push_q) st_d = `ISA_ST_SH_CHILD_W;
                else if (refr_q) {st_d, sp_d, call_d, kind_d, idx_d} = shade_end;
                else {st_d, sp_d, call_d, kind_d, idx_d} =
                         unwind_jump(unwind(sp_q, col_d, pend_q, pidx_q, pixel_end), call_q);
            end
            // CUR_W = PAR_W * kr, then the child's nearest_hit
            `ISA_ST_SH_CHILD_W: begin
                op = `ISA_OP_MULZ; la_w = `ISA_REG_CUR_W; la_a = `ISA_REG_PAR_W; la_b = obj_mat;
                ctx_d   = C_HIT;
                found_d = 1'b0;
                // The hit's refracted child waits for this subtree.
                pend_d[sp_q - 1'b1]                 = refr_q;
                pidx_d[OW*sp_up +: OW]              = obj_idx_q;
                {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_start;
            end

            // ---- refract: the refracted child of a hit on sphere idx_q --------
            // p in CUR_O (this level's), d in PAR_D; TRN = <eta, ior, kt>.
            // N = p - c; the child's search skips the sphere; its colour is
            // unwritten; the level's parent owes it no longer.
            `ISA_ST_RF_NSUB: begin
                op = `ISA_OP_SUB; la_w = T_N; la_a = `ISA_REG_CUR_O; la_b = rf_c;
                obj_kind_d         = K_SPH;
                obj_idx_d          = idx_q;
                excl_d             = 1'b1;
                col_d[sp_q]        = 1'b0;
                pend_d[sp_q - 1'b1] = 1'b0;
                st_d = `ISA_ST_RF_NSCALE;
            end
            // N = n = (p - c) * 1/r, then Q.x = d.n
            `ISA_ST_RF_NSCALE: begin
                op = `ISA_OP_MULY; la_w = T_N; la_a = T_N; la_b = rf_r;
                st_d   = `ISA_ST_DOT_1;
                call_d = D_RF_IN;
            end
            // U.x = (d.n)^2, 1 - that, times eta twice, k = 1 - that
            `ISA_ST_RF_COS2: begin
                op = `ISA_OP_MUL; la_w = T_U; la_a = T_Q; la_b = T_Q; wmask = M_X;
                st_d = `ISA_ST_RF_SIN2;
            end
            `ISA_ST_RF_SIN2: begin
                op = `ISA_OP_SUB; la_w = T_U; la_a = `ISA_REG_ONE; la_b = T_U; wmask = M_X;
                st_d = `ISA_ST_RF_ETA1;
            end
            `ISA_ST_RF_ETA1: begin
                op = `ISA_OP_MULX; la_w = T_U; la_a = T_U; la_b = rf_t; wmask = M_X;
                st_d = `ISA_ST_RF_ETA2;
            end
            `ISA_ST_RF_ETA2: begin
                op = `ISA_OP_MULX; la_w = T_U; la_a = T_U; la_b = rf_t; wmask = M_X;
                st_d = `ISA_ST_RF_K;
            end
            // k < 0: total internal reflection
            `ISA_ST_RF_K: begin
                op = `ISA_OP_SUB; la_w = T_U; la_a = `ISA_REG_ONE; la_b = T_U; wmask = M_X;
                st_d = y_neg[0] ? `ISA_ST_RF_TIR_K : `ISA_ST_RF_SQRT;
            end
            `ISA_ST_RF_SQRT: begin
                op = `ISA_OP_SQRT; la_w = T_U; la_a = T_U; wmask = M_X;
                if (alu_done) st_d = `ISA_ST_RF_EDN;
            end
            // G.x = eta (d.n) + sqrt(k)
            `ISA_ST_RF_EDN: begin
                op = `ISA_OP_MULX; la_w = T_G; la_a = T_Q; la_b = rf_t; wmask = M_X;
                st_d = `ISA_ST_RF_COEF;
            end
            `ISA_ST_RF_COEF: begin
                op = `ISA_OP_ADD; la_w = T_G; la_a = T_G; la_b = T_U; wmask = M_X;
                st_d = `ISA_ST_RF_ED;
            end
            // R = t = eta d - G.x n
            `ISA_ST_RF_ED: begin
                op = `ISA_OP_MULX; la_w = T_V; la_a = `ISA_REG_PAR_D; la_b = rf_t;
                st_d = `ISA_ST_RF_CN;
            end
            `ISA_ST_RF_CN: begin
                op = `ISA_OP_MULX; la_w = T_S; la_a = T_N; la_b = T_G;
                st_d = `ISA_ST_RF_DIR;
            end
            `ISA_ST_RF_DIR: begin
                op = `ISA_OP_SUB; la_w = T_R; la_a = T_V; la_b = T_S;
                st_d = `ISA_ST_RF_CV;
            end
            // The chord: V = p - c, then Q.x = b = v.t
            `ISA_ST_RF_CV: begin
                op = `ISA_OP_SUB; la_w = T_V; la_a = `ISA_REG_CUR_O; la_b = rf_c;
                st_d   = `ISA_ST_DOT_1;
                call_d = D_RF_CHORD;
            end
            // U = -b t; V = w = v - b t, then disc by ISECT
            `ISA_ST_RF_CBD: begin
                op = `ISA_OP_NMULX; la_w = T_U; la_a = T_R; la_b = T_Q;
                st_d = `ISA_ST_RF_CW;
            end
            `ISA_ST_RF_CW: begin
                op = `ISA_OP_ADD; la_w = T_V; la_a = T_V; la_b = T_U;
                st_d = `ISA_ST_ISECT_1;
            end
            `ISA_ST_RF_CSQRT: begin
                op = `ISA_OP_SQRT; la_w = T_S; la_a = T_S; wmask = M_X;
                if (alu_done) st_d = `ISA_ST_RF_CS;
            end
            // S.x = s = sqrt(disc) - b (0 - b where disc < 0)
            `ISA_ST_RF_CS: begin
                op = `ISA_OP_SUB; la_w = T_S; la_a = rfneg_q ? `ISA_REG_ZERO : T_S; la_b = T_Q; wmask = M_X;
                st_d = `ISA_ST_RF_CST;
            end
            // CUR_O = p + s t: the exit point
            `ISA_ST_RF_CST: begin
                op = `ISA_OP_MULX; la_w = T_U; la_a = T_R; la_b = T_S;
                st_d = `ISA_ST_RF_EXIT;
            end
            `ISA_ST_RF_EXIT: begin
                op = `ISA_OP_ADD; la_w = `ISA_REG_CUR_O; la_a = `ISA_REG_CUR_O; la_b = T_U;
                st_d = `ISA_ST_RF_OSUB;
            end
            // N = n' = (exit - c) * 1/r, then Q.x = t.n'
            `ISA_ST_RF_OSUB: begin
                op = `ISA_OP_SUB; la_w = T_N; la_a = `ISA_REG_CUR_O; la_b = rf_c;
                st_d = `ISA_ST_RF_OSCALE;
            end
            `ISA_ST_RF_OSCALE: begin
                op = `ISA_OP_MULY; la_w = T_N; la_a = T_N; la_b = rf_r;
                st_d   = `ISA_ST_DOT_1;
                call_d = D_RF_OUT;
            end
            // U.x = k' = 1 - ior^2 (1 - cos^2); k' < 0 is taken as 0
            `ISA_ST_RF_OCOS2: begin
                op = `ISA_OP_MUL; la_w = T_U; la_a = T_Q; la_b = T_Q; wmask = M_X;
                st_d = `ISA_ST_RF_OSIN2;
            end
            `ISA_ST_RF_OSIN2: begin
                op = `ISA_OP_SUB; la_w = T_U; la_a = `ISA_REG_ONE; la_b = T_U; wmask = M_X;
                st_d = `ISA_ST_RF_OIOR1;
            end
            `ISA_ST_RF_OIOR1: begin
                op = `ISA_OP_MULY; la_w = T_U; la_a = T_U; la_b = rf_t; wmask = M_X;
                st_d = `ISA_ST_RF_OIOR2;
            end
            `ISA_ST_RF_OIOR2: begin
                op = `ISA_OP_MULY; la_w = T_U; la_a = T_U; la_b = rf_t; wmask = M_X;
                st_d = `ISA_ST_RF_OK;
            end
            `ISA_ST_RF_OK: begin
                op = `ISA_OP_SUB; la_w = T_U; la_a = `ISA_REG_ONE; la_b = T_U; wmask = M_X;
                rfneg_d = y_neg[0];
                st_d    = `ISA_ST_RF_OEDN;
            end
            // G.x = ior cos (- sqrt(k'))
            `ISA_ST_RF_OEDN: begin
                op = `ISA_OP_MULY; la_w = T_G; la_a = T_Q; la_b = rf_t; wmask = M_X;
                st_d = rfneg_q ? `ISA_ST_RF_OED : `ISA_ST_RF_OSQRT;
            end
            `ISA_ST_RF_OSQRT: begin
                op = `ISA_OP_SQRT; la_w = T_U; la_a = T_U; wmask = M_X;
                if (alu_done) st_d = `ISA_ST_RF_OCOEF;
            end
            `ISA_ST_RF_OCOEF: begin
                op = `ISA_OP_SUB; la_w = T_G; la_a = T_G; la_b = T_U; wmask = M_X;
                st_d = `ISA_ST_RF_OED;
            end
            // CUR_D = ior t - G.x n'; latch its DirFlags
            `ISA_ST_RF_OED: begin
                op = `ISA_OP_MULY; la_w = T_V; la_a = T_R; la_b = rf_t;
                st_d = `ISA_ST_RF_OCN;
            end
            `ISA_ST_RF_OCN: begin
                op = `ISA_OP_MULX; la_w = T_S; la_a = T_N; la_b = T_G;
                st_d = `ISA_ST_RF_ODIR;
            end
            `ISA_ST_RF_ODIR: begin
                op = `ISA_OP_SUB; la_w = `ISA_REG_CUR_D; la_a = T_V; la_b = T_S;
                dsign_d = y_sign;
                dneg_d  = y_neg;
                dpos_d  = y_pos;
                st_d    = `ISA_ST_RF_CHILD_W;
            end
            // Total internal reflection: CUR_D = d - 2 (d.n) n from p
            `ISA_ST_RF_TIR_K: begin
                op = `ISA_OP_MUL2X; la_w = T_U; la_a = T_N; la_b = T_Q;
                st_d = `ISA_ST_RF_TIR;
            end
            `ISA_ST_RF_TIR: begin
                op = `ISA_OP_SUB; la_w = `ISA_REG_CUR_D; la_a = `ISA_REG_PAR_D; la_b = T_U;
                dsign_d = y_sign;
                dneg_d  = y_neg;
                dpos_d  = y_pos;
                st_d    = `ISA_ST_RF_CHILD_W;
            end
            // CUR_W = PAR_W * kt, then the child's nearest_hit
            `ISA_ST_RF_CHILD_W: begin
                op = `ISA_OP_MULZ; la_w = `ISA_REG_CUR_W; la_a = `ISA_REG_PAR_W; la_b = rf_t;
                ctx_d   = C_HIT;
                found_d = 1'b0;
                {st_d, sp_d, call_d, kind_d, idx_d} = nearest_hit_start;
            end

            // ---- unwind ---------------------------------------------------------
            // PAR_COL = PAR_COL + CUR_COL, then the level below
            `ISA_ST_POP_ADD: begin
                op = `ISA_OP_ADD; la_w = `ISA_REG_PAR_COL; la_a = `ISA_REG_PAR_COL; la_b = `ISA_REG_CUR_COL;
                if (pend_q[sp_q - 1'b1]) {st_d, sp_d, call_d, kind_d, idx_d} = refract_here;
                else {st_d, sp_d, call_d, kind_d, idx_d} =
                         unwind_jump(unwind(sp_q - 1'b1, col_q, pend_q, pidx_q, pixel_end), call_q);
            end
            // PAR_COL = CUR_COL (the parent got no light), then the level below
            `ISA_ST_POP_MOV: begin
                op = `ISA_OP_MOV; la_w = `ISA_REG_PAR_COL; la_a = `ISA_REG_CUR_COL;
                col_d[sp_q - 1'b1] = 1'b1;
                if (pend_q[sp_q - 1'b1]) {st_d, sp_d, call_d, kind_d, idx_d} = refract_here;
                else {st_d, sp_d, call_d, kind_d, idx_d} =
                         unwind_jump(unwind(sp_q - 1'b1, col_d, pend_q, pidx_q, pixel_end), call_q);
            end
            // STK0_COL = ZERO: no light reached the pixel
            `ISA_ST_ROOT_BLACK: begin
                op = `ISA_OP_MOV; la_w = `ISA_REG_CUR_COL; la_a = `ISA_REG_ZERO;
                st_d = pixel_end;
            end

            // ---- expose: colour = 1 - e^(exposure * colour), at sp = 0 ------
            // U = STK0_COL * exposure (lane x of ROT0_S)
            `ISA_ST_EXPO_MUL: begin
                op = `ISA_OP_MULX; la_w = T_U; la_a = `ISA_REG_CUR_COL; la_b = `ISA_REG_ROT0_S;
                st_d = `ISA_ST_EXPO_EXP;
            end
            // U = e^U, every lane
            `ISA_ST_EXPO_EXP: begin
                op = `ISA_OP_EXP; la_w = T_U; la_a = T_U;
                if (alu_done) st_d = `ISA_ST_EXPO_SUB;
            end
            // STK0_COL = ONE - U
            `ISA_ST_EXPO_SUB: begin
                op = `ISA_OP_SUB; la_w = `ISA_REG_CUR_COL; la_a = `ISA_REG_ONE; la_b = T_U;
                st_d = `ISA_ST_PIX_DONE;
            end
            // Raise done; the pixel's colour leaves through read port A.
            `ISA_ST_PIX_DONE: begin
                la_a = `ISA_REG_STK0_COL;
                st_d = `ISA_ST_IDLE;
            end
            default: st_d = `ISA_ST_IDLE;
        endcase

        // Without refraction its registers hold 0: none of its logic.
        if (REFRACTION == 0) begin
            refr_d  = 1'b0;
            rcut_d  = 1'b0;
            pend_d  = {STK_N{1'b0}};
            pidx_d  = {(STK_N * OW){1'b0}};
            rfneg_d = 1'b0;
        end
    end

`ifdef PP_COVER
    // ------------------------------------------------------------------------
    // Coverage build only (cargo feature `coverage`, never for synthesis):
    // a cover point per state and per possible transition, made by build.rs
    // from rtl/cover/pp_ctrl.transitions (Yosys SAT, rtl/cover/transitions.sh).
    // ------------------------------------------------------------------------
    pp_ctrl_cover #(.SW(SW)) u_cover (.clk(clk), .rst_n(rst_n), .st_q(st_q), .st_d(st_d));
`endif

endmodule
`default_nettype wire
