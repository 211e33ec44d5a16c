`default_nettype none
`include "isa.vh"
// ============================================================================
// fast_ctrl -- the fast processor's controller: 2^CTX_BITS pixel contexts in
//              a ring, one turn each per revolution, one micro-op a turn
// ============================================================================
// The same controller FSM as the compact processor's (rtl/pp/pp_ctrl.v: the
// same states, the same micro-op per state, the same next state per state
// and flags; golden::micro::program is the spec of both), reorganized so
// that no next-state decision waits on logic after the ALU's flags
// (docs/fast_controller.md is the analysis this follows).
//
// The ring. The contexts take turns in a fixed rotation: cycle t is the
// turn of context t mod K (K = 2^CTX_BITS). A context's whole state (st,
// sp, call, the search and shading registers: the 54 bits of S) travels
// round a ring of K register positions, so position p holds the context
// whose turn was p cycles ago; nothing is indexed by context and nothing is
// read twice. At position 0 (the issue register) the context's micro-op
// leaves for the register file (addresses) and, two edges later, the ALU;
// its result and flags come back LAT + 2 edges after the turn. Meanwhile
// the ring works out everything the next turn needs that does not depend
// on those flags:
//
//   0        issue: the micro-op out; or the done turn (the colour is read
//            through port A), the take of a waiting pixel (S reset, st =
//            PRI_ITOF), an idle turn, an EXP that lets its turn pass
//            (another EXP issued one or two cycles before): `hold`
//   1  (P1)  searches and priorities from S and the scene constants: the
//            next sphere and plane, unwinding, the material bits, the
//            stack's room, the next rotation
//   2  (P2)  the jumps built from them (pp_ctrl's nearest_hit_next,
//            shade_next, offer)
//   3  (P3)  per state: the two candidate next states A0 and A1 (whole S),
//            the condition that will choose between them as a code over
//            the flags (cond = inv ^ |(y_neg & mn | y_pos & mp)), and which
//            flags the state latches (direction, facing, cut)
//   4  (P4)  each candidate's micro-op, logical addresses
//   5  (P5)  physical addresses (rtl/pp/mem_ctrl.v, each with its own sp)
//   6 .. LAT+2          carried (shift registers)
//   LAT+2    (C1)  the flags arrive: the condition, the latches, and for
//            NORM_SCALE the planes the fresh direction leaves eligible
//            (the fast plane test) and BOX_FAR's corner
//   LAT+3    (C2)  NORM_SCALE's plane pick; the candidate chosen
//   LAT+4 .. K-1   carried; then position 0 again
//
// so K >= LAT + 4 (static check below). A held turn chooses S itself.
//
// Reset clears only a counter: for the first K cycles every turn writes
// an idle context into the ring (no datapath reset), and nothing issues
// (sweeping).
// ============================================================================
module fast_ctrl #(
    parameter integer LATENCY     = 27,   // the ALU's (fast_alu LATENCY)
    parameter integer CTX_BITS    = 5,
    parameter integer STACK_DEPTH = `ISA_DIM_STK_COUNT
) (
    input  wire                              clk,
    input  wire                              rst_n,
    // The configuration word (isa.vh ISA_DIM_CFG_*); changes only while
    // every context is idle.
    input  wire [`ISA_DIM_LANES*32-1:0]      cfg,
    // High for the K cycles after reset in which the ring is swept.
    output wire                              sweeping,
    // This turn.
    output wire [CTX_BITS-1:0]               turn_ctx,
    input  wire                              take_ok,    // a pixel waits and its result has room
    output wire                              take,       // this turn takes it
    output wire                              done,       // this turn is a done turn (rd_a: colour, 2 edges on)
    output wire                              issue,      // a micro-op issues (the ALU's in_valid, 2 edges on)
    output wire [`ISA_DIM_OP_BITS-1:0]       op,
    output wire [`ISA_DIM_REG_BITS-1:0]      pa_a,
    output wire [`ISA_DIM_REG_BITS-1:0]      pa_b,
    output wire [`ISA_DIM_REG_BITS-1:0]      pa_w,
    output wire [`ISA_DIM_LANES-1:0]         wmask,
    output wire [`ISA_DIM_ST_BITS-1:0]       state,
    // The flags of the micro-op of the turn LATENCY + 2 cycles ago.
    input  wire [`ISA_DIM_LANES-1:0]         y_neg,
    input  wire [`ISA_DIM_LANES-1:0]         y_pos,
    input  wire [`ISA_DIM_LANES-1:0]         y_sign
);

    // ------------------------------------------------------------------------
    // Sizes
    // ------------------------------------------------------------------------
    localparam integer K      = 1 << CTX_BITS;
    localparam integer RW     = `ISA_DIM_REG_BITS;
    localparam integer SW     = `ISA_DIM_ST_BITS;
    localparam integer LN     = `ISA_DIM_LANES;
    localparam integer OPW    = `ISA_DIM_OP_BITS;
    localparam integer SPH_N  = `ISA_DIM_SPH_COUNT;
    localparam integer PLN_N  = `ISA_DIM_PLN_COUNT;
    localparam integer ROT_N  = `ISA_DIM_ROT_COUNT;
    localparam integer STK_N  = `ISA_DIM_STK_COUNT;
    localparam integer MB     = `ISA_DIM_CFG_MAT_BITS;
    localparam integer AB     = `ISA_DIM_CFG_AXIS_BITS;
    localparam integer OBJ_N  = SPH_N > PLN_N ? SPH_N : PLN_N;
    localparam integer OW     = $clog2(OBJ_N);
    localparam integer SPW    = $clog2(STK_N);
    localparam integer RAW    = $clog2(ROT_N);
    localparam integer NSW    = `ISA_DIM_CFG_SPHERES_BITS;
    localparam integer NPW    = `ISA_DIM_CFG_PLANES_BITS;
    localparam integer DW     = `ISA_DIM_CFG_DEPTH_BITS;
    localparam integer CALLW  = 3;

    // Positions of the ring (see the header).
    localparam integer POS_C1 = LATENCY + 2;
    localparam integer CARRY1 = POS_C1 - 6;          // positions 7 .. LAT+2
    localparam integer CARRY2 = K - (LATENCY + 4);   // positions LAT+4 .. K-1

    localparam       K_SPH = 1'b0, K_PLN = 1'b1;
    localparam       C_HIT = 1'b0, C_SHD = 1'b1;
    localparam [CALLW-1:0] D_PRIMARY  = 3'd0, D_LIGHT    = 3'd1, D_SPHERE   = 3'd2,
                           D_DIFFUSE  = 3'd3, D_REFLECT  = 3'd4, D_SPECULAR = 3'd5;
    localparam [1:0] S_DIFFUSE = 2'd0, S_REFLECT = 2'd1, S_SPECULAR = 2'd2, S_LOCAL = 2'd3;
    localparam integer MAT_DIFFUSE = 0, MAT_SPECULAR = 1, MAT_REFLECTIVE = 2;

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

    // ------------------------------------------------------------------------
    // A context's state S, packed. Its low JW bits are a jump, pp_ctrl's
    // {st, sp, call, kind, idx}.
    // ------------------------------------------------------------------------
    localparam integer J_IDX   = 0;
    localparam integer J_KIND  = J_IDX + OW;
    localparam integer J_CALL  = J_KIND + 1;
    localparam integer J_SP    = J_CALL + CALLW;
    localparam integer J_ST    = J_SP + SPW;
    localparam integer JW      = J_ST + SW;
    localparam integer S_ROT   = JW;
    localparam integer S_CTX   = S_ROT + RAW;
    localparam integer S_FOUND = S_CTX + 1;
    localparam integer S_FACE  = S_FOUND + 1;
    localparam integer S_BKIND = S_FACE + 1;
    localparam integer S_BIDX  = S_BKIND + 1;
    localparam integer S_EXCL  = S_BIDX + OW;
    localparam integer S_OKIND = S_EXCL + 1;
    localparam integer S_OIDX  = S_OKIND + 1;
    localparam integer S_PUSH  = S_OIDX + OW;
    localparam integer S_CUT   = S_PUSH + 1;
    localparam integer S_DIFF  = S_CUT + 1;
    localparam integer S_SPEC  = S_DIFF + 1;
    localparam integer S_COL   = S_SPEC + 1;
    localparam integer S_DSIGN = S_COL + STK_N;
    localparam integer S_DNEG  = S_DSIGN + LN;
    localparam integer S_DPOS  = S_DNEG + LN;
    localparam integer SWD     = S_DPOS + LN;

    // A micro-op: {op, a, b, w, wmask}.
    localparam integer U_MASK = 0;
    localparam integer U_W    = U_MASK + LN;
    localparam integer U_B    = U_W + RW;
    localparam integer U_A    = U_B + RW;
    localparam integer U_OP   = U_A + RW;
    localparam integer UW     = U_OP + OPW;

    localparam [SW-1:0] ST_IDLE     = `ISA_ST_IDLE;
    localparam [SW-1:0] ST_PIX_DONE = `ISA_ST_PIX_DONE;

    // A fresh pixel: st = PRI_ITOF, every other field 0 (pp_ctrl's IDLE
    // takes the same for the fields it resets; the rest are written before
    // they are read).
    localparam [SW-1:0]  ST_PRI_ITOF = `ISA_ST_PRI_ITOF;
    localparam [SWD-1:0] S_TAKEN   = {{(SWD - JW){1'b0}}, ST_PRI_ITOF, {(JW - SW){1'b0}}};
    localparam [SWD-1:0] S_IDLE    = {SWD{1'b0}};  // st = IDLE = 0

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
    wire unused_cfg = ^{cfg[LN*32-1:`ISA_DIM_CFG_PLN_NEG_LSB + PLN_N],
                        cfg[`ISA_DIM_CFG_SPH_BITS_LSB - 1:`ISA_DIM_CFG_EXPOSURE_LSB + 1],
                        cfg[`ISA_DIM_CFG_DEPTH_LSB - 1:`ISA_DIM_CFG_PLANES_LSB + NPW]};

    wire [SW-1:0] pixel_end = exposure ? `ISA_ST_EXPO_MUL : `ISA_ST_PIX_DONE;

    // ------------------------------------------------------------------------
    // Pure functions of the control flow (pp_ctrl's, argument for argument)
    // ------------------------------------------------------------------------
    function [MB-1:0] bits(input kind, input [OW-1:0] idx, input [SPH_N*MB-1:0] sph,
                           input [PLN_N*MB-1:0] pln);
        bits = kind == K_SPH ? sph[MB*idx +: MB] : pln[MB*idx +: MB];
    endfunction

    // {found, k}: the first sphere k >= from, k < n, not the skipped one.
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

    // Which planes j >= from a search may test: j < n, not the skipped one.
    function [PLN_N-1:0] planes_open(input [OW:0] from, input [NPW-1:0] n, input skip,
                                     input [OW-1:0] skip_j);
        integer j;
        begin
            for (j = 0; j < PLN_N; j = j + 1)
                planes_open[j] = (j >= from) && (j < n) && !(skip && skip_j == j[OW-1:0]);
        end
    endfunction

    // Which planes the fast plane test passes for a direction with these
    // flags (DirFlags::opposes: a normal facing -axis needs d.axis > 0);
    // every plane without the test.
    function [PLN_N-1:0] planes_facing(input fast_on, input [PLN_N*AB-1:0] axis,
                                       input [PLN_N-1:0] neg, input [LN-1:0] dneg,
                                       input [LN-1:0] dpos);
        integer j;
        reg [LN-1:0] against;
        begin
            for (j = 0; j < PLN_N; j = j + 1) begin
                against = neg[j] ? dpos : dneg;
                planes_facing[j] = !fast_on || against[axis[AB*j +: AB]];
            end
        end
    endfunction

    // {found, j}: the lowest set bit.
    function [OW:0] first_of(input [PLN_N-1:0] m);
        integer j;
        begin
            first_of = {(OW + 1){1'b0}};
            for (j = PLN_N - 1; j >= 0; j = j - 1)
                if (m[j]) first_of = {1'b1, j[OW-1:0]};
        end
    endfunction

    function cut_first(input on, input [MB-1:0] b, input room);
        cut_first = on && b[MAT_REFLECTIVE] && room;
    endfunction

    // unwind (pp_ctrl): {st, sp}.
    function [SW+SPW-1:0] unwind(input [SPW-1:0] from, input [STK_N-1:0] col, input [SW-1:0] last);
        integer   l;
        reg       found;
        reg [SPW-1:0] lvl;
        begin
            found = 1'b0;
            lvl   = {SPW{1'b0}};
            for (l = 1; l < STK_N; l = l + 1)
                if (l[SPW-1:0] <= from && col[l]) begin
                    found = 1'b1;
                    lvl   = l[SPW-1:0];
                end
            unwind[0 +: SPW] = lvl;
            if (found)
                unwind[SPW +: SW] = col[lvl - 1'b1] ? `ISA_ST_POP_ADD : `ISA_ST_POP_MOV;
            else
                unwind[SPW +: SW] = col[0] ? last : `ISA_ST_ROOT_BLACK;
        end
    endfunction

    function [STK_N-1:0] with_level(input [STK_N-1:0] col, input [SPW-1:0] l);
        begin
            with_level    = col;
            with_level[l] = 1'b1;
        end
    endfunction

    // shade_next (pp_ctrl).
    function [JW-1:0] shade_next(input [1:0] from, input lit, input diff, input spec,
                                 input [MB-1:0] mat, input push, input [JW-1:0] stay_j,
                                 input [JW-1:0] unwind_j);
        begin
            shade_next = stay_j;
            if (from <= S_DIFFUSE && lit && (mat[MAT_DIFFUSE] || mat[MAT_SPECULAR])) begin
                shade_next[J_ST +: SW]      = `ISA_ST_DOT_1;
                shade_next[J_CALL +: CALLW] = D_DIFFUSE;
            end
            else if (from <= S_REFLECT && (push || (lit && mat[MAT_SPECULAR]))) begin
                shade_next[J_ST +: SW]      = `ISA_ST_DOT_1;
                shade_next[J_CALL +: CALLW] = D_REFLECT;
            end
            else if (from <= S_SPECULAR && lit && mat[MAT_SPECULAR]) begin
                shade_next[J_ST +: SW]      = `ISA_ST_DOT_1;
                shade_next[J_CALL +: CALLW] = D_SPECULAR;
            end
            else if (diff && spec)
                shade_next[J_ST +: SW] = `ISA_ST_SH_LOCAL;
            else if (diff || spec)
                shade_next[J_ST +: SW] = `ISA_ST_SH_COLOUR;
            else if (push)
                shade_next[J_ST +: SW] = `ISA_ST_SH_CHILD_W;
            else
                shade_next = unwind_j;
        end
    endfunction

    // nearest_hit_next (pp_ctrl).
    function [JW-1:0] nearest_hit_next(input [JW-1:0] stay_j, input box, input [OW:0] sph,
                                       input leaving_spheres, input [OW:0] pln, input ctx,
                                       input found, input shortcut_on, input cut,
                                       input [JW-1:0] clear_j, input [JW-1:0] unwind_j);
        begin
            nearest_hit_next = stay_j;
            if (sph[OW] && box)
                nearest_hit_next[J_ST +: SW] = `ISA_ST_BOX_FAR;
            else if (sph[OW]) begin
                nearest_hit_next[J_ST +: SW]  = `ISA_ST_SPH_V;
                nearest_hit_next[J_KIND]      = K_SPH;
                nearest_hit_next[J_IDX +: OW] = sph[OW-1:0];
            end
            else if (leaving_spheres && ctx == C_SHD && shortcut_on)
                nearest_hit_next = clear_j;
            else if (pln[OW]) begin
                nearest_hit_next[J_ST +: SW]  = `ISA_ST_ISECT_1;
                nearest_hit_next[J_KIND]      = K_PLN;
                nearest_hit_next[J_IDX +: OW] = pln[OW-1:0];
            end
            else if (ctx == C_SHD)
                nearest_hit_next = clear_j;
            else if (found)
                nearest_hit_next[J_ST +: SW] = cut ? `ISA_ST_CUT_W : `ISA_ST_SH_OFFSET;
            else
                nearest_hit_next = unwind_j;
        end
    endfunction

    // primary_ray_next (pp_ctrl): {rot, st, call}.
    function [RAW+SW+CALLW-1:0] primary_ray_next(input [ROT_N-1:0] on, input [RAW:0] from,
                                                 input [RAW-1:0] axis, input [CALLW-1:0] call);
        integer a;
        begin
            primary_ray_next[CALLW + SW +: RAW] = axis;
            primary_ray_next[CALLW +: SW]       = `ISA_ST_DOT_1;
            primary_ray_next[0 +: CALLW]        = D_PRIMARY;
            for (a = ROT_N - 1; a >= 0; a = a - 1)
                if (a >= from && on[a]) begin
                    primary_ray_next[CALLW + SW +: RAW] = a[RAW-1:0];
                    primary_ray_next[CALLW +: SW]       = `ISA_ST_ROT_COS;
                    primary_ray_next[0 +: CALLW]        = call;
                end
        end
    endfunction

    // Register addresses (golden::micro::isa::sphere, plane, corner, rot):
    // functions, so that each argument keeps its own width.
    function [RW-1:0] sphere(input [OW-1:0] k, input [RW-1:0] field0);
        sphere = field0 + k * `ISA_DIM_SPH_STRIDE;
    endfunction
    function [RW-1:0] plane(input [OW-1:0] j, input [RW-1:0] field0);
        plane = field0 + j * `ISA_DIM_PLN_STRIDE;
    endfunction
    function [RW-1:0] corner(input [LN-1:0] sgn);
        corner = `ISA_REG_BOX0 + sgn * `ISA_DIM_BOX_STRIDE;
    endfunction
    function [RW-1:0] rot_reg(input [RAW-1:0] axis, input [RW-1:0] field0);
        rot_reg = field0 + axis * `ISA_DIM_ROT_STRIDE;
    endfunction

    // The micro-op of state s (pp_ctrl's instruction of each state), with
    // logical addresses.
    function [UW-1:0] micro_op(input [SWD-1:0] s);
        reg [SW-1:0]    st;
        reg [RAW-1:0]   rot;
        reg [CALLW-1:0] call;
        reg             ctx, kind, found, okind, push;
        reg [OW-1:0]    idx, oidx;
        reg [LN-1:0]    dsign;
        reg [OPW-1:0]   o;
        reg [RW-1:0]    a, b, w;
        reg [LN-1:0]    m;
        reg [RW-1:0]    shading_o, shading_d, shading_col, shading_w, shading_p, shading_r;
        reg [RW-1:0]    search_o, search_d, obj_n, obj_mat, obj_col, u_dst, rot_s;
        reg [LN-1:0]    rot_u, rot_v;
        begin
            st    = s[J_ST +: SW];
            rot   = s[S_ROT +: RAW];
            call  = s[J_CALL +: CALLW];
            ctx   = s[S_CTX];
            kind  = s[J_KIND];
            idx   = s[J_IDX +: OW];
            found = s[S_FOUND];
            okind = s[S_OKIND];
            oidx  = s[S_OIDX +: OW];
            push  = s[S_PUSH];
            dsign = s[S_DSIGN +: LN];

            shading_o   = push ? `ISA_REG_PAR_O : `ISA_REG_CUR_O;
            shading_d   = push ? `ISA_REG_PAR_D : `ISA_REG_CUR_D;
            shading_col = push ? `ISA_REG_PAR_COL : `ISA_REG_CUR_COL;
            shading_w   = push ? `ISA_REG_PAR_W : `ISA_REG_CUR_W;
            shading_p   = push ? `ISA_REG_CUR_O : T_P;
            shading_r   = push ? `ISA_REG_CUR_D : T_R;
            search_o    = ctx == C_HIT ? `ISA_REG_CUR_O : shading_p;
            search_d    = ctx == C_HIT ? `ISA_REG_CUR_D : T_L;
            obj_n       = okind == K_SPH ? T_N
                                         : plane(oidx, `ISA_REG_PLN0_N);
            obj_mat     = okind == K_SPH ? sphere(oidx, `ISA_REG_SPH0_MAT)
                                         : plane(oidx, `ISA_REG_PLN0_MAT);
            obj_col     = okind == K_SPH ? sphere(oidx, `ISA_REG_SPH0_COL)
                                         : plane(oidx, `ISA_REG_PLN0_COL);
            u_dst       = (ctx == C_HIT && !found) ? T_BEST : T_U;
            rot_u       = rot == 0 ? M_Y : rot == 1 ? M_Z : M_X;
            rot_v       = rot == 0 ? M_Z : rot == 1 ? M_X : M_Y;
            rot_s       = rot_reg(rot, `ISA_REG_ROT0_S);

            o = `ISA_OP_NOP;
            a = `ISA_REG_ZERO;
            b = `ISA_REG_ZERO;
            w = `ISA_REG_ZERO;
            m = M_XYZ;
            case (st)
                `ISA_ST_PRI_ITOF:  begin o = `ISA_OP_ITOF; w = T_P; end
                `ISA_ST_PRI_HALF:  begin o = `ISA_OP_ADD; w = T_P; a = T_P; b = `ISA_REG_CAM_HALF; end
                `ISA_ST_ROT_COS:   begin
                    o = `ISA_OP_MUL; w = T_N; a = T_P;
                    b = rot_reg(rot, `ISA_REG_ROT0_C);
                end
                `ISA_ST_ROT_SIN_U: begin o = `ISA_OP_MULR1; w = T_R; a = rot_s; b = T_P; m = rot_u; end
                `ISA_ST_ROT_SIN_V: begin o = `ISA_OP_MULR2; w = T_R; a = rot_s; b = T_P; m = rot_v; end
                `ISA_ST_ROT_ADD:   begin o = `ISA_OP_ADD; w = T_P; a = T_N; b = T_R; m = rot_u | rot_v; end
                `ISA_ST_DOT_1: begin
                    o = `ISA_OP_DOT1;
                    case (call)
                        D_PRIMARY: begin a = T_P; b = T_P; end
                        D_LIGHT:   begin a = T_R; b = T_R; end
                        D_SPHERE:  begin a = T_V; b = search_d; end
                        D_DIFFUSE: begin a = obj_n; b = T_L; end
                        D_REFLECT: begin a = shading_d; b = obj_n; end
                        default:   begin a = shading_r; b = T_L; end
                    endcase
                end
                `ISA_ST_DOT_2: o = `ISA_OP_DOT2;
                `ISA_ST_DOT_3: begin
                    o = `ISA_OP_DOT3; m = M_X;
                    case (call)
                        D_PRIMARY, D_LIGHT: w = T_LEN;
                        D_DIFFUSE:          w = T_V;
                        default:            w = T_Q;
                    endcase
                end
                `ISA_ST_NORM_ROOTS: begin o = `ISA_OP_ROOTS; w = T_LEN; a = T_LEN; m = M_X | M_Y; end
                `ISA_ST_NORM_INV:   begin o = `ISA_OP_MULR1; w = T_INV; a = T_LEN; b = T_LEN; m = M_X; end
                `ISA_ST_NORM_SCALE: begin
                    o = `ISA_OP_MULX;
                    w = call == D_PRIMARY ? `ISA_REG_CUR_D : T_L;
                    a = call == D_PRIMARY ? T_P : T_R;
                    b = T_INV;
                end
                `ISA_ST_ISECT_1: begin
                    o = `ISA_OP_ISECT1;
                    a = kind == K_SPH ? T_V : search_o;
                    b = kind == K_SPH ? T_V : plane(idx, `ISA_REG_PLN0_N);
                end
                `ISA_ST_ISECT_2: begin
                    o = `ISA_OP_ISECT2; w = T_G; a = search_d;
                    b = kind == K_SPH ? T_V : plane(idx, `ISA_REG_PLN0_N);
                end
                `ISA_ST_ISECT_3: begin o = `ISA_OP_ISECT3; a = T_G; end
                `ISA_ST_ISECT_4: begin
                    o = `ISA_OP_ISECT4; w = T_S;
                    a = kind == K_SPH ? sphere(idx, `ISA_REG_SPH0_R)
                                      : plane(idx, `ISA_REG_PLN0_Q);
                end
                `ISA_ST_BOX_FAR:    begin
                    o = `ISA_OP_SUB; w = T_G; b = search_o;
                    a = corner(~dsign);
                end
                `ISA_ST_BOX_BEHIND: begin o = `ISA_OP_MUL; w = T_S; a = T_G; b = search_d; end
                `ISA_ST_BOX_NEAR:   begin
                    o = `ISA_OP_SUB; w = T_V; b = search_o;
                    a = corner(dsign);
                end
                `ISA_ST_BOX_P1: begin o = `ISA_OP_MULR1; w = T_Q; a = T_V; b = search_d; end
                `ISA_ST_BOX_Q1: begin o = `ISA_OP_MULR1; w = T_U; a = search_d; b = T_G; end
                `ISA_ST_BOX_D1: begin o = `ISA_OP_SUB; w = T_Q; a = T_Q; b = T_U; end
                `ISA_ST_BOX_P2: begin o = `ISA_OP_MULR2; w = T_Q; a = T_V; b = search_d; end
                `ISA_ST_BOX_Q2: begin o = `ISA_OP_MULR2; w = T_U; a = search_d; b = T_G; end
                `ISA_ST_BOX_D2: begin o = `ISA_OP_SUB; w = T_Q; a = T_Q; b = T_U; end
                `ISA_ST_SPH_V:  begin
                    o = `ISA_OP_SUB; w = T_V; a = search_o;
                    b = sphere(idx, `ISA_REG_SPH0_C);
                end
                `ISA_ST_SPH_BD:     begin o = `ISA_OP_NMULX; w = T_U; a = search_d; b = T_Q; end
                `ISA_ST_SPH_W:      begin o = `ISA_OP_ADD; w = T_V; a = T_V; b = T_U; end
                `ISA_ST_SPH_SQRT:   begin o = `ISA_OP_SQRT; w = T_S; a = T_S; m = M_X; end
                `ISA_ST_SPH_T:      begin o = `ISA_OP_ADD; w = u_dst; a = T_S; b = T_Q; m = M_X; end
                `ISA_ST_PLN_RECIP:  begin o = `ISA_OP_RECIPY; w = T_Q; a = T_S; m = M_X; end
                `ISA_ST_PLN_T:      begin o = `ISA_OP_NMULX; w = u_dst; a = T_S; b = T_Q; m = M_X; end
                `ISA_ST_HIT_CMP:    begin o = `ISA_OP_SUB; w = T_G; a = T_U; b = T_BEST; m = M_X; end
                `ISA_ST_HIT_KEEP:   begin o = `ISA_OP_MOV; w = T_BEST; a = T_U; m = M_X; end
                `ISA_ST_CUT_W: begin
                    o = `ISA_OP_MULZ; w = T_U; a = `ISA_REG_CUR_W; m = M_Z;
                    b = s[S_BKIND] == K_SPH
                        ? sphere(s[S_BIDX +: OW], `ISA_REG_SPH0_MAT)
                        : plane(s[S_BIDX +: OW], `ISA_REG_PLN0_MAT);
                end
                `ISA_ST_CUT_CMP: begin
                    o = `ISA_OP_SUB; w = T_G; a = T_U; m = M_Z;
                    b = s[S_BKIND] == K_SPH
                        ? sphere(s[S_BIDX +: OW], `ISA_REG_SPH0_R)
                        : plane(s[S_BIDX +: OW], `ISA_REG_PLN0_Q);
                end
                `ISA_ST_SHD_DIST:   begin o = `ISA_OP_ADD; w = T_G; a = T_U; b = T_LEN; m = M_X; end
                `ISA_ST_SH_OFFSET:  begin o = `ISA_OP_NMULX; w = T_V; a = `ISA_REG_CUR_D; b = T_BEST; end
                `ISA_ST_SH_POINT:   begin o = `ISA_OP_ADD; w = shading_p; a = shading_o; b = T_V; end
                `ISA_ST_SH_NORMAL_SUB: begin
                    o = `ISA_OP_SUB; w = T_N; a = shading_p;
                    b = sphere(oidx, `ISA_REG_SPH0_C);
                end
                `ISA_ST_SH_NORMAL_SCALE: begin
                    o = `ISA_OP_MULY; w = T_N; a = T_N;
                    b = sphere(oidx, `ISA_REG_SPH0_R);
                end
                `ISA_ST_SH_LIGHT_VEC: begin o = `ISA_OP_SUB; w = T_R; a = `ISA_REG_LIGHT_POS; b = shading_p; end
                `ISA_ST_SH_KD:       begin o = `ISA_OP_MULX; w = T_G; a = obj_mat; b = T_V; m = M_X; end
                `ISA_ST_SH_CL:       begin o = `ISA_OP_MUL; w = T_S; a = obj_col; b = `ISA_REG_LIGHT_COL; end
                `ISA_ST_SH_DIFFUSE:  begin o = `ISA_OP_MULX; w = T_S; a = T_S; b = T_G; end
                `ISA_ST_SH_REFL_K:   begin o = `ISA_OP_MUL2X; w = T_U; a = obj_n; b = T_Q; end
                `ISA_ST_SH_REFL:     begin o = `ISA_OP_SUB; w = shading_r; a = shading_d; b = T_U; end
                `ISA_ST_SH_POW2:     begin o = `ISA_OP_MUL; w = T_U; a = T_Q; b = T_Q; m = M_X; end
                `ISA_ST_SH_POW4:     begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_U; m = M_X; end
                `ISA_ST_SH_POW5:     begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_Q; m = M_X; end
                `ISA_ST_SH_POW10:    begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_U; m = M_X; end
                `ISA_ST_SH_POW20:    begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_U; m = M_X; end
                `ISA_ST_SH_KS:       begin o = `ISA_OP_MULX; w = T_V; a = obj_mat; b = T_U; m = M_Y; end
                `ISA_ST_SH_SPEC:     begin o = `ISA_OP_MULY; w = T_G; a = `ISA_REG_LIGHT_COL; b = T_V; end
                `ISA_ST_SH_LOCAL:    begin o = `ISA_OP_ADD; w = T_S; a = T_S; b = T_G; end
                `ISA_ST_SH_COLOUR: begin
                    o = `ISA_OP_MUL; w = shading_col; b = shading_w;
                    a = (s[S_SPEC] && !s[S_DIFF]) ? T_G : T_S;
                end
                `ISA_ST_SH_CHILD_W: begin o = `ISA_OP_MULZ; w = `ISA_REG_CUR_W; a = `ISA_REG_PAR_W; b = obj_mat; end
                `ISA_ST_POP_ADD: begin
                    o = `ISA_OP_ADD; w = `ISA_REG_PAR_COL; a = `ISA_REG_PAR_COL; b = `ISA_REG_CUR_COL;
                end
                `ISA_ST_POP_MOV:    begin o = `ISA_OP_MOV; w = `ISA_REG_PAR_COL; a = `ISA_REG_CUR_COL; end
                `ISA_ST_ROOT_BLACK: begin o = `ISA_OP_MOV; w = `ISA_REG_CUR_COL; a = `ISA_REG_ZERO; end
                `ISA_ST_EXPO_MUL:   begin o = `ISA_OP_MULX; w = T_U; a = `ISA_REG_CUR_COL; b = `ISA_REG_ROT0_S; end
                `ISA_ST_EXPO_EXP:   begin o = `ISA_OP_EXP; w = T_U; a = T_U; end
                `ISA_ST_EXPO_SUB:   begin o = `ISA_OP_SUB; w = `ISA_REG_CUR_COL; a = `ISA_REG_ONE; b = T_U; end
                `ISA_ST_PIX_DONE:   a = `ISA_REG_STK0_COL;
                default: ;
            endcase
            micro_op = {o, a, b, w, m};
        end
    endfunction

    // ------------------------------------------------------------------------
    // Position 0: the issue register, the turn counter, the EXP history
    // ------------------------------------------------------------------------
    reg [SWD-1:0]      s0;
    reg [UW-1:0]       u0;
    reg [CTX_BITS-1:0] turn_q;
    reg [CTX_BITS:0]   init_q;     // counts to K after reset
    reg [1:0]          exp_q;      // an EXP issued 1, 2 cycles ago

    wire initial_sweep = !init_q[CTX_BITS];
    wire [SW-1:0] st0  = s0[J_ST +: SW];
    wire is_free       = (st0 == ST_IDLE) || (st0 == ST_PIX_DONE);
    wire is_exp        = (u0[U_OP +: OPW] == `ISA_OP_EXP);
    wire exp_wait      = is_exp && (|exp_q);

    assign sweeping = initial_sweep;
    assign turn_ctx = turn_q;
    assign take     = !initial_sweep && is_free && take_ok;
    assign done     = !initial_sweep && (st0 == ST_PIX_DONE);
    assign issue    = !initial_sweep && !is_free && !exp_wait;
    assign op       = u0[U_OP +: OPW];
    assign pa_a     = u0[U_A +: RW];
    assign pa_b     = u0[U_B +: RW];
    assign pa_w     = u0[U_W +: RW];
    assign wmask    = u0[U_MASK +: LN];
    assign state    = st0;

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            turn_q <= {CTX_BITS{1'b0}};
            init_q <= {(CTX_BITS + 1){1'b0}};
            exp_q  <= 2'b00;
        end else begin
            turn_q <= turn_q + 1'b1;
            if (initial_sweep) init_q <= init_q + 1'b1;
            exp_q  <= {exp_q[0], issue && is_exp};
        end
    end

    // ------------------------------------------------------------------------
    // Position 1: the state after the turn; hold: the next turn repeats it
    // ------------------------------------------------------------------------
    reg [SWD-1:0] s1;
    reg           h1;
    always @(posedge clk) begin
        if (initial_sweep || (is_free && !take)) s1 <= S_IDLE;
        else if (take)                           s1 <= S_TAKEN;
        else                                     s1 <= s0;
        h1 <= !issue;
    end

    // ------------------------------------------------------------------------
    // P1: searches and priorities (registers and scene constants only)
    // ------------------------------------------------------------------------
    wire [SPW-1:0] sp1   = s1[J_SP +: SPW];
    wire [OW-1:0]  idx1  = s1[J_IDX +: OW];
    wire           okind1 = s1[S_OKIND];
    wire [OW-1:0]  oidx1 = s1[S_OIDX +: OW];
    wire           skip_sph1 = s1[S_EXCL] && okind1 == K_SPH;
    wire           skip_pln1 = s1[S_EXCL] && okind1 == K_PLN;
    wire [OW:0]    idx_up1 = {1'b0, idx1} + 1'b1;
    wire           room1   = ({1'b0, sp1} + 1'b1 < max_depth);
    wire [MB-1:0]  best_bits1 = bits(s1[S_BKIND], s1[S_BIDX +: OW], sph_bits, pln_bits);
    wire [MB-1:0]  this_bits1 = bits(s1[J_KIND], idx1, sph_bits, pln_bits);
    wire [PLN_N-1:0] facing1  = planes_facing(fast, pln_axis, pln_neg, s1[S_DNEG +: LN], s1[S_DPOS +: LN]);
    wire [SPW-1:0] sp_dn1  = sp1 - 1'b1;

    reg [SWD-1:0]    s2;
    reg              h2;
    reg [MB-1:0]     obj_bits2;
    reg [OW:0]       sph_first2, sph_next2, pln_first2, pln_next2;
    reg [PLN_N-1:0]  pln_open2;     // NORM_SCALE: planes the search may test, before the fast test
    reg              cut_best2, cut_this2, run_push2;
    reg [SW+SPW-1:0] unwind_now2, unwind_pop_add2, unwind_pop_mov2, unwind_colour2;
    reg [RAW+SW+CALLW-1:0] prn_first2, prn_after2;
    always @(posedge clk) begin
        s2          <= s1;
        h2          <= h1;
        obj_bits2   <= bits(okind1, oidx1, sph_bits, pln_bits);
        sph_first2  <= spheres_other_than({(OW + 1){1'b0}}, n_sph, skip_sph1, oidx1);
        sph_next2   <= spheres_other_than(idx_up1, n_sph, skip_sph1, oidx1);
        pln_first2  <= first_of(planes_open({(OW + 1){1'b0}}, n_pln, skip_pln1, oidx1) & facing1);
        pln_next2   <= first_of(planes_open(idx_up1, n_pln, skip_pln1, oidx1) & facing1);
        pln_open2   <= planes_open({(OW + 1){1'b0}}, n_pln, skip_pln1, oidx1);
        cut_best2   <= cut_first(cutoff, best_bits1, room1);
        cut_this2   <= cut_first(cutoff, this_bits1, room1);
        run_push2   <= best_bits1[MAT_REFLECTIVE] && room1 && !(cutoff && s1[S_CUT]);
        unwind_now2     <= unwind(sp1, s1[S_COL +: STK_N], pixel_end);
        unwind_pop_add2 <= unwind(sp_dn1, s1[S_COL +: STK_N], pixel_end);
        unwind_pop_mov2 <= unwind(sp_dn1, with_level(s1[S_COL +: STK_N], sp_dn1), pixel_end);
        unwind_colour2  <= unwind(sp1, with_level(s1[S_COL +: STK_N], sp1), pixel_end);
        prn_first2  <= primary_ray_next(rotate, {(RAW + 1){1'b0}}, s1[S_ROT +: RAW], s1[J_CALL +: CALLW]);
        prn_after2  <= primary_ray_next(rotate, {1'b0, s1[S_ROT +: RAW]} + 1'b1, s1[S_ROT +: RAW],
                                        s1[J_CALL +: CALLW]);
    end

    // ------------------------------------------------------------------------
    // P2: the jumps
    // ------------------------------------------------------------------------
    localparam [OW:0] NONE = {(OW + 1){1'b0}};
    wire [JW-1:0] stay2      = s2[0 +: JW];
    wire [JW-1:0] unwind_j2  = {unwind_now2, s2[J_CALL +: CALLW], s2[J_KIND], s2[J_IDX +: OW]};
    wire          diff2      = s2[S_DIFF];
    wire          spec2      = s2[S_SPEC];
    wire          push2      = s2[S_PUSH];
    wire          face2      = s2[S_FACE];
    wire          ctx2       = s2[S_CTX];
    wire          found2     = s2[S_FOUND];
    wire          in_sph2    = (s2[J_KIND] == K_SPH);
    wire [OW:0]   after_sph2 = in_sph2 ? sph_next2 : NONE;
    wire [OW:0]   after_pln2 = in_sph2 ? pln_first2 : pln_next2;
    wire [JW-1:0] shd_false2 = shade_next(S_DIFFUSE, 1'b1, diff2, spec2, obj_bits2, push2, stay2, unwind_j2);

    reg [SWD-1:0]    s3;
    reg              h3;
    reg [MB-1:0]     obj_bits3;
    reg [OW:0]       sph_first3;
    reg [PLN_N-1:0]  pln_open3;
    reg [JW-1:0]     shd_false3, shd_true3, nh_start3, box_false3, nh_after3, nh_kept3, offer3;
    reg [JW-1:0]     diffuse_lit3, diffuse_dark3, spec_none3, sh_diffuse3, sh_refl3, sh_spec3;
    reg [JW-1:0]     unwind_j3;
    reg [SW+SPW-1:0] unwind_pop_add3, unwind_pop_mov3, unwind_colour3;
    reg              run_push3;
    reg [RAW+SW+CALLW-1:0] prn_first3, prn_after3;
    always @(posedge clk) begin
        s3            <= s2;
        h3            <= h2;
        obj_bits3     <= obj_bits2;
        sph_first3    <= sph_first2;
        pln_open3     <= pln_open2;
        shd_false3    <= shd_false2;
        shd_true3     <= shade_next(S_DIFFUSE, 1'b0, diff2, spec2, obj_bits2, push2, stay2, unwind_j2);
        nh_start3     <= nearest_hit_next(stay2, bbox, sph_first2, 1'b1, pln_first2, C_HIT,
                                          1'b0, shortcut, cut_best2, shd_false2, unwind_j2);
        box_false3    <= nearest_hit_next(stay2, 1'b0, NONE, 1'b1, pln_first2, ctx2,
                                          found2, shortcut, cut_best2, shd_false2, unwind_j2);
        nh_after3     <= nearest_hit_next(stay2, 1'b0, after_sph2, in_sph2, after_pln2, ctx2,
                                          found2, shortcut, cut_best2, shd_false2, unwind_j2);
        nh_kept3      <= nearest_hit_next(stay2, 1'b0, after_sph2, in_sph2, after_pln2, ctx2,
                                          found2, shortcut, cut_this2, shd_false2, unwind_j2);
        // offer: the first hit stays in the search; a later one is compared.
        if (found2) begin
            offer3             <= stay2;
            offer3[J_ST +: SW] <= `ISA_ST_HIT_CMP;
        end else
            offer3 <= nearest_hit_next(stay2, 1'b0, after_sph2, in_sph2, after_pln2, ctx2,
                                       1'b1, shortcut, cut_this2, shd_false2, unwind_j2);
        diffuse_lit3  <= shade_next(S_REFLECT, 1'b1, diff2, spec2, obj_bits2, push2, stay2, unwind_j2);
        diffuse_dark3 <= shade_next(S_REFLECT, 1'b0, diff2, spec2, obj_bits2, push2, stay2, unwind_j2);
        spec_none3    <= shade_next(S_LOCAL, face2, diff2, spec2, obj_bits2, push2, stay2, unwind_j2);
        sh_diffuse3   <= shade_next(S_REFLECT, face2, 1'b1, spec2, obj_bits2, push2, stay2, unwind_j2);
        sh_refl3      <= shade_next(S_SPECULAR, face2, diff2, spec2, obj_bits2, push2, stay2, unwind_j2);
        sh_spec3      <= shade_next(S_LOCAL, face2, diff2, 1'b1, obj_bits2, push2, stay2, unwind_j2);
        unwind_j3       <= unwind_j2;
        unwind_pop_add3 <= unwind_pop_add2;
        unwind_pop_mov3 <= unwind_pop_mov2;
        unwind_colour3  <= unwind_colour2;
        run_push3     <= run_push2;
        prn_first3    <= prn_first2;
        prn_after3    <= prn_after2;
    end

    // ------------------------------------------------------------------------
    // P3: per state, the candidates A0 (cond = 0) and A1 (cond = 1), the
    // condition's code and the latches
    // ------------------------------------------------------------------------
    reg [SWD-1:0]   a0, a1;
    reg [LN-1:0]    mn, mp;
    reg             inv;
    reg             ld_dir, ld_facing, ld_cut;
    reg             ns_planes;   // NORM_SCALE: cond = a plane the fresh direction leaves open
    reg             box_corner;  // NORM_SCALE: A0 is BOX_FAR, its corner from the fresh signs
    reg [SWD-1:0]   common;

    wire [SW-1:0]   st3   = s3[J_ST +: SW];
    wire [CALLW-1:0] call3 = s3[J_CALL +: CALLW];
    wire            ctx3   = s3[S_CTX];
    wire            found3 = s3[S_FOUND];
    wire            kind3  = s3[J_KIND];
    wire [LN-1:0]   dsign3 = s3[S_DSIGN +: LN];
    wire [LN-1:0]   dsign_r1_3 = {dsign3[0], dsign3[LN-1:1]};
    wire [LN-1:0]   dsign_r2_3 = {dsign3[1:0], dsign3[LN-1:2]};
    wire [LN-1:0]   same1_3 = ~(dsign3 ^ dsign_r1_3);
    wire [LN-1:0]   same2_3 = ~(dsign3 ^ dsign_r2_3);
    wire            prim3   = (call3 == D_PRIMARY);

    always @* begin
        common     = s3;
        mn         = {LN{1'b0}};
        mp         = {LN{1'b0}};
        inv        = 1'b0;
        ld_dir     = 1'b0;
        ld_facing  = 1'b0;
        ld_cut     = 1'b0;
        ns_planes  = 1'b0;
        box_corner = 1'b0;
        a0         = s3;
        a1         = s3;
        if (!h3) begin
            case (st3)
                `ISA_ST_PRI_ITOF: a0[J_ST +: SW] = `ISA_ST_PRI_HALF;
                `ISA_ST_PRI_HALF: {a0[S_ROT +: RAW], a0[J_ST +: SW], a0[J_CALL +: CALLW]} = prn_first3;
                `ISA_ST_ROT_COS:   a0[J_ST +: SW] = `ISA_ST_ROT_SIN_U;
                `ISA_ST_ROT_SIN_U: a0[J_ST +: SW] = `ISA_ST_ROT_SIN_V;
                `ISA_ST_ROT_SIN_V: a0[J_ST +: SW] = `ISA_ST_ROT_ADD;
                `ISA_ST_ROT_ADD:  {a0[S_ROT +: RAW], a0[J_ST +: SW], a0[J_CALL +: CALLW]} = prn_after3;
                `ISA_ST_DOT_1: a0[J_ST +: SW] = `ISA_ST_DOT_2;
                `ISA_ST_DOT_2: a0[J_ST +: SW] = `ISA_ST_DOT_3;
                `ISA_ST_DOT_3:
                    case (call3)
                        D_PRIMARY, D_LIGHT: a0[J_ST +: SW] = `ISA_ST_NORM_ROOTS;
                        D_SPHERE: begin
                            mn = M_X;                       // b < 0: the near root may be ahead
                            a1[J_ST +: SW] = `ISA_ST_SPH_BD;
                            a0[0 +: JW]    = nh_after3;
                        end
                        D_DIFFUSE: begin
                            mp = M_X;                       // n.l > 0
                            ld_facing = 1'b1;
                            if (obj_bits3[MAT_DIFFUSE]) a1[J_ST +: SW] = `ISA_ST_SH_KD;
                            else                        a1[0 +: JW]    = diffuse_lit3;
                            a0[0 +: JW] = diffuse_dark3;
                        end
                        D_REFLECT: a0[J_ST +: SW] = `ISA_ST_SH_REFL_K;
                        default: begin
                            mp = M_X;                       // r.l > 0
                            a1[J_ST +: SW] = `ISA_ST_SH_POW2;
                            a0[0 +: JW]    = spec_none3;
                        end
                    endcase
                `ISA_ST_NORM_ROOTS: a0[J_ST +: SW] = `ISA_ST_NORM_INV;
                `ISA_ST_NORM_INV:   a0[J_ST +: SW] = `ISA_ST_NORM_SCALE;
                `ISA_ST_NORM_SCALE: begin
                    ld_dir = 1'b1;
                    common[S_CTX]   = prim3 ? C_HIT : C_SHD;
                    common[S_FOUND] = 1'b0;
                    a0 = common;
                    a1 = common;
                    if (sph_first3[OW]) begin
                        if (bbox) begin
                            a0[J_ST +: SW] = `ISA_ST_BOX_FAR;
                            box_corner     = 1'b1;
                        end else begin
                            a0[J_ST +: SW]  = `ISA_ST_SPH_V;
                            a0[J_KIND]      = K_SPH;
                            a0[J_IDX +: OW] = sph_first3[OW-1:0];
                        end
                    end else if (!prim3 && shortcut)
                        a0[0 +: JW] = shd_false3;
                    else begin
                        ns_planes       = 1'b1;
                        a1[J_ST +: SW]  = `ISA_ST_ISECT_1;
                        a1[J_KIND]      = K_PLN;
                        a0[0 +: JW]     = prim3 ? unwind_j3 : shd_false3;
                    end
                end
                `ISA_ST_ISECT_1: a0[J_ST +: SW] = `ISA_ST_ISECT_2;
                `ISA_ST_ISECT_2: a0[J_ST +: SW] = `ISA_ST_ISECT_3;
                `ISA_ST_ISECT_3: a0[J_ST +: SW] = `ISA_ST_ISECT_4;
                `ISA_ST_ISECT_4: begin
                    // miss: a sphere's disc < 0; a plane facing away, unless
                    // the fast test decided
                    if (kind3 == K_SPH) mn = M_X;
                    else if (!fast) begin
                        mn  = M_Y;
                        inv = 1'b1;
                    end
                    a1[0 +: JW]    = nh_after3;
                    a0[J_ST +: SW] = kind3 == K_SPH ? `ISA_ST_SPH_SQRT : `ISA_ST_PLN_RECIP;
                end
                `ISA_ST_BOX_FAR: a0[J_ST +: SW] = `ISA_ST_BOX_BEHIND;
                `ISA_ST_BOX_BEHIND: begin
                    mn = M_XYZ;
                    a1[0 +: JW]    = box_false3;
                    a0[J_ST +: SW] = `ISA_ST_BOX_NEAR;
                end
                `ISA_ST_BOX_NEAR: a0[J_ST +: SW] = `ISA_ST_BOX_P1;
                `ISA_ST_BOX_P1:   a0[J_ST +: SW] = `ISA_ST_BOX_Q1;
                `ISA_ST_BOX_Q1:   a0[J_ST +: SW] = `ISA_ST_BOX_D1;
                `ISA_ST_BOX_D1: begin
                    mp = same1_3;
                    mn = ~same1_3;
                    a1[0 +: JW]    = box_false3;
                    a0[J_ST +: SW] = `ISA_ST_BOX_P2;
                end
                `ISA_ST_BOX_P2: a0[J_ST +: SW] = `ISA_ST_BOX_Q2;
                `ISA_ST_BOX_Q2: a0[J_ST +: SW] = `ISA_ST_BOX_D2;
                `ISA_ST_BOX_D2: begin
                    mp = same2_3;
                    mn = ~same2_3;
                    a1[0 +: JW]     = box_false3;
                    a0[J_ST +: SW]  = `ISA_ST_SPH_V;
                    a0[J_KIND]      = K_SPH;
                    a0[J_IDX +: OW] = sph_first3[OW-1:0];
                end
                `ISA_ST_SPH_V: begin
                    a0[J_ST +: SW]      = `ISA_ST_DOT_1;
                    a0[J_CALL +: CALLW] = D_SPHERE;
                end
                `ISA_ST_SPH_BD:   a0[J_ST +: SW] = `ISA_ST_SPH_W;
                `ISA_ST_SPH_W:    a0[J_ST +: SW] = `ISA_ST_ISECT_1;
                `ISA_ST_SPH_SQRT: a0[J_ST +: SW] = `ISA_ST_SPH_T;
                `ISA_ST_SPH_T: begin
                    mn = M_X;                               // u < 0: ahead
                    a0[0 +: JW] = nh_after3;
                    if (ctx3 == C_HIT) begin
                        if (!found3) {a1[S_BKIND], a1[S_BIDX +: OW]} = {kind3, s3[J_IDX +: OW]};
                        a1[S_FOUND] = 1'b1;
                        a1[0 +: JW] = offer3;
                    end else if (shortcut) begin
                        a1[S_FOUND] = 1'b1;
                        a1[0 +: JW] = shd_true3;
                    end else
                        a1[J_ST +: SW] = `ISA_ST_SHD_DIST;
                end
                `ISA_ST_PLN_RECIP: a0[J_ST +: SW] = `ISA_ST_PLN_T;
                `ISA_ST_PLN_T: begin
                    if (fast) inv = 1'b1;                   // assumed ahead
                    else      mn  = M_X;
                    a0[0 +: JW] = nh_after3;
                    if (ctx3 == C_HIT) begin
                        if (!found3) {a1[S_BKIND], a1[S_BIDX +: OW]} = {kind3, s3[J_IDX +: OW]};
                        a1[S_FOUND] = 1'b1;
                        a1[0 +: JW] = offer3;
                    end else
                        a1[J_ST +: SW] = `ISA_ST_SHD_DIST;
                end
                `ISA_ST_HIT_CMP: begin
                    mp = M_X;                               // nearer than the best
                    a1[J_ST +: SW] = `ISA_ST_HIT_KEEP;
                    a0[0 +: JW]    = nh_after3;
                end
                `ISA_ST_HIT_KEEP: begin
                    {a0[S_BKIND], a0[S_BIDX +: OW]} = {kind3, s3[J_IDX +: OW]};
                    a0[0 +: JW] = nh_kept3;
                end
                `ISA_ST_CUT_W: a0[J_ST +: SW] = `ISA_ST_CUT_CMP;
                `ISA_ST_CUT_CMP: begin
                    ld_cut = 1'b1;
                    a0[J_ST +: SW] = `ISA_ST_SH_OFFSET;
                end
                `ISA_ST_SHD_DIST: begin
                    mp = M_X;                               // the blocker is before the light
                    a1[S_FOUND] = 1'b1;
                    a1[0 +: JW] = shd_true3;
                    a0[0 +: JW] = nh_after3;
                end
                `ISA_ST_SH_OFFSET: begin
                    a0[S_PUSH]         = run_push3;
                    a0[S_CUT]          = 1'b0;
                    a0[J_SP +: SPW]    = s3[J_SP +: SPW] + {{(SPW - 1){1'b0}}, run_push3};
                    a0[S_OKIND]        = s3[S_BKIND];
                    a0[S_OIDX +: OW]   = s3[S_BIDX +: OW];
                    a0[S_EXCL]         = 1'b1;
                    a0[S_DIFF]         = 1'b0;
                    a0[S_SPEC]         = 1'b0;
                    a0[S_FACE]         = 1'b0;
                    a0[J_ST +: SW]     = `ISA_ST_SH_POINT;
                end
                `ISA_ST_SH_POINT:
                    a0[J_ST +: SW] = s3[S_OKIND] == K_SPH ? `ISA_ST_SH_NORMAL_SUB : `ISA_ST_SH_LIGHT_VEC;
                `ISA_ST_SH_NORMAL_SUB:   a0[J_ST +: SW] = `ISA_ST_SH_NORMAL_SCALE;
                `ISA_ST_SH_NORMAL_SCALE: a0[J_ST +: SW] = `ISA_ST_SH_LIGHT_VEC;
                `ISA_ST_SH_LIGHT_VEC: begin
                    a0[J_ST +: SW]      = `ISA_ST_DOT_1;
                    a0[J_CALL +: CALLW] = D_LIGHT;
                end
                `ISA_ST_SH_KD: a0[J_ST +: SW] = `ISA_ST_SH_CL;
                `ISA_ST_SH_CL: a0[J_ST +: SW] = `ISA_ST_SH_DIFFUSE;
                `ISA_ST_SH_DIFFUSE: begin
                    a0[S_DIFF]  = 1'b1;
                    a0[0 +: JW] = sh_diffuse3;
                end
                `ISA_ST_SH_REFL_K: a0[J_ST +: SW] = `ISA_ST_SH_REFL;
                `ISA_ST_SH_REFL: begin
                    ld_dir      = 1'b1;
                    a0[0 +: JW] = sh_refl3;
                end
                `ISA_ST_SH_POW2:  a0[J_ST +: SW] = `ISA_ST_SH_POW4;
                `ISA_ST_SH_POW4:  a0[J_ST +: SW] = `ISA_ST_SH_POW5;
                `ISA_ST_SH_POW5:  a0[J_ST +: SW] = `ISA_ST_SH_POW10;
                `ISA_ST_SH_POW10: a0[J_ST +: SW] = `ISA_ST_SH_POW20;
                `ISA_ST_SH_POW20: a0[J_ST +: SW] = `ISA_ST_SH_KS;
                `ISA_ST_SH_KS:    a0[J_ST +: SW] = `ISA_ST_SH_SPEC;
                `ISA_ST_SH_SPEC: begin
                    a0[S_SPEC]  = 1'b1;
                    a0[0 +: JW] = sh_spec3;
                end
                `ISA_ST_SH_LOCAL: a0[J_ST +: SW] = `ISA_ST_SH_COLOUR;
                `ISA_ST_SH_COLOUR: begin
                    // col[shading_level] = 1: the level below sp when pushing
                    a0[S_COL +: STK_N] = with_level(s3[S_COL +: STK_N],
                                                    s3[S_PUSH] ? s3[J_SP +: SPW] - 1'b1 : s3[J_SP +: SPW]);
                    if (s3[S_PUSH]) a0[J_ST +: SW] = `ISA_ST_SH_CHILD_W;
                    else            {a0[J_ST +: SW], a0[J_SP +: SPW]} = unwind_colour3;
                end
                `ISA_ST_SH_CHILD_W: begin
                    a0[S_CTX]   = C_HIT;
                    a0[S_FOUND] = 1'b0;
                    a0[0 +: JW] = nh_start3;
                end
                `ISA_ST_POP_ADD: {a0[J_ST +: SW], a0[J_SP +: SPW]} = unwind_pop_add3;
                `ISA_ST_POP_MOV: begin
                    a0[S_COL +: STK_N] = with_level(s3[S_COL +: STK_N], s3[J_SP +: SPW] - 1'b1);
                    {a0[J_ST +: SW], a0[J_SP +: SPW]} = unwind_pop_mov3;
                end
                `ISA_ST_ROOT_BLACK: a0[J_ST +: SW] = pixel_end;
                `ISA_ST_EXPO_MUL:   a0[J_ST +: SW] = `ISA_ST_EXPO_EXP;
                `ISA_ST_EXPO_EXP:   a0[J_ST +: SW] = `ISA_ST_EXPO_SUB;
                `ISA_ST_EXPO_SUB:   a0[J_ST +: SW] = `ISA_ST_PIX_DONE;
                default:            a0[J_ST +: SW] = ST_IDLE;
            endcase
        end
    end

    reg [SWD-1:0]   a0_4, a1_4;
    reg [LN-1:0]    mn4, mp4;
    reg             inv4, ld_dir4, ld_facing4, ld_cut4, ns_planes4, box_corner4;
    reg [PLN_N-1:0] pln_open4;
    always @(posedge clk) begin
        a0_4        <= a0;
        a1_4        <= a1;
        mn4         <= mn;
        mp4         <= mp;
        inv4        <= inv;
        ld_dir4     <= ld_dir;
        ld_facing4  <= ld_facing;
        ld_cut4     <= ld_cut;
        ns_planes4  <= ns_planes;
        box_corner4 <= box_corner;
        pln_open4   <= pln_open3;
    end

    // ------------------------------------------------------------------------
    // P4, P5: the candidates' micro-ops, then their physical addresses
    // ------------------------------------------------------------------------
    localparam integer CODE_W = 2 * LN + 6 + PLN_N;   // mn, mp, inv, latches, ns, box, open
    wire [CODE_W-1:0] code4 = {mn4, mp4, inv4, ld_dir4, ld_facing4, ld_cut4, ns_planes4, box_corner4,
                               pln_open4};

    reg [SWD-1:0]    a0_5, a1_5;
    reg [UW-1:0]     l0_5, l1_5;
    reg [CODE_W-1:0] code5;
    always @(posedge clk) begin
        a0_5  <= a0_4;
        a1_5  <= a1_4;
        l0_5  <= micro_op(a0_4);
        l1_5  <= micro_op(a1_4);
        code5 <= code4;
    end

    wire [RW-1:0] p0_a, p0_b, p0_w, p1_a, p1_b, p1_w;
    mem_ctrl #(.STACK_DEPTH(STACK_DEPTH)) u_map0 (
        .sp   (a0_5[J_SP +: SPW]),
        .la_a (l0_5[U_A +: RW]),
        .la_b (l0_5[U_B +: RW]),
        .la_w (l0_5[U_W +: RW]),
        .pa_a (p0_a),
        .pa_b (p0_b),
        .pa_w (p0_w)
    );
    mem_ctrl #(.STACK_DEPTH(STACK_DEPTH)) u_map1 (
        .sp   (a1_5[J_SP +: SPW]),
        .la_a (l1_5[U_A +: RW]),
        .la_b (l1_5[U_B +: RW]),
        .la_w (l1_5[U_W +: RW]),
        .pa_a (p1_a),
        .pa_b (p1_b),
        .pa_w (p1_w)
    );

    localparam integer BW = 2 * SWD + 2 * UW + CODE_W;   // the bundle carried to C1
    reg [BW-1:0] b6;
    always @(posedge clk)
        b6 <= {a0_5, a1_5,
               l0_5[U_OP +: OPW], p0_a, p0_b, p0_w, l0_5[U_MASK +: LN],
               l1_5[U_OP +: OPW], p1_a, p1_b, p1_w, l1_5[U_MASK +: LN],
               code5};

    // ------------------------------------------------------------------------
    // Carried to C1 (positions 7 .. LAT+2)
    // ------------------------------------------------------------------------
    wire [BW-1:0] bc;
    fast_delay #(.WIDTH(BW), .STAGES(CARRY1)) u_carry1 (.clk(clk), .d(b6), .q(bc));

    wire [SWD-1:0]    c_a0, c_a1;
    wire [UW-1:0]     c_u0, c_u1;
    wire [LN-1:0]     c_mn, c_mp;
    wire              c_inv, c_ld_dir, c_ld_facing, c_ld_cut, c_ns, c_box;
    wire [PLN_N-1:0]  c_open;
    assign {c_a0, c_a1, c_u0, c_u1, c_mn, c_mp, c_inv, c_ld_dir, c_ld_facing, c_ld_cut, c_ns, c_box,
            c_open} = bc;

    // ------------------------------------------------------------------------
    // C1: the flags
    // ------------------------------------------------------------------------
    function [SWD-1:0] latch(input [SWD-1:0] s, input ld_dir_on, input ld_facing_on, input ld_cut_on,
                             input [LN-1:0] fneg, input [LN-1:0] fpos, input [LN-1:0] fsign);
        begin
            latch = s;
            if (ld_dir_on) begin
                latch[S_DSIGN +: LN] = fsign;
                latch[S_DNEG +: LN]  = fneg;
                latch[S_DPOS +: LN]  = fpos;
            end
            if (ld_facing_on) latch[S_FACE] = fpos[0];
            if (ld_cut_on)    latch[S_CUT]  = fneg[2];
        end
    endfunction

    wire [RW-1:0] far_corner = corner(~y_sign);

    reg [SWD-1:0]   a0_c2, a1_c2;
    reg [UW-1:0]    u0_c2, u1_c2;
    reg             cond_c2, ns_c2;
    reg [PLN_N-1:0] open_c2;
    always @(posedge clk) begin
        a0_c2   <= latch(c_a0, c_ld_dir, c_ld_facing, c_ld_cut, y_neg, y_pos, y_sign);
        a1_c2   <= latch(c_a1, c_ld_dir, c_ld_facing, c_ld_cut, y_neg, y_pos, y_sign);
        u0_c2   <= c_u0;
        if (c_box) u0_c2[U_A +: RW] <= far_corner;
        u1_c2   <= c_u1;
        cond_c2 <= c_inv ^ (|((y_neg & c_mn) | (y_pos & c_mp)));
        ns_c2   <= c_ns;
        open_c2 <= c_open & planes_facing(fast, pln_axis, pln_neg, y_neg, y_pos);
    end

    // ------------------------------------------------------------------------
    // C2: NORM_SCALE's plane, the choice
    // ------------------------------------------------------------------------
    wire [OW:0]    plane_c2 = first_of(open_c2);
    wire           cond     = ns_c2 ? plane_c2[OW] : cond_c2;
    reg [SWD-1:0]  s_next;
    reg [UW-1:0]   u_next;
    always @* begin
        if (cond) begin
            s_next = a1_c2;
            u_next = u1_c2;
            if (ns_c2) begin
                s_next[J_IDX +: OW] = plane_c2[OW-1:0];
                u_next[U_B +: RW]   = plane(plane_c2[OW-1:0], `ISA_REG_PLN0_N);
            end
        end else begin
            s_next = a0_c2;
            u_next = u0_c2;
        end
    end

    // ------------------------------------------------------------------------
    // Carried back to position 0
    // ------------------------------------------------------------------------
    wire [SWD+UW-1:0] back;
    fast_delay #(.WIDTH(SWD + UW), .STAGES(CARRY2)) u_carry2 (
        .clk (clk),
        .d   ({s_next, u_next}),
        .q   (back)
    );
    always @(posedge clk) {s0, u0} <= back;

    // Static checks: the round trip fits the ring.
    generate
        if (CARRY2 < 0 || CARRY1 < 1) begin : g_ring_too_short
            ring_too_short_for_the_alu_latency u_error ();
        end
    endgenerate

endmodule
`default_nettype wire
