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
// sp, call, the search and shading registers: the 90 bits of S) travels
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
//   1        the state after the turn
//   2 .. 4   (P1) searches and priorities from S and the scene constants,
//            in three steps: masks and tables (thermometers, decoders, the
//            material bits, the stack's room); the priority picks (the next
//            sphere and plane, the highest coloured level); the unwindings'
//            states
//   5  (P2)  the jumps built from them (pp_ctrl's nearest_hit_next,
//            shade_next, offer), and per state which jump each candidate
//            next state (A0, A1) takes, the candidates' other fields, the
//            condition that will choose between them as a code over the
//            flags (cond = inv ^ |(y_neg & mn | y_pos & mp)), and which
//            flags the state latches (direction, facing, cut)
//   6  (P3)  the candidates, whole
//   7  (P4a1) each candidate's plan from its state id (opcode, mask, and
//            per address field its register or a code naming its operand
//            source; a variant code where the call or the rotation axis
//            changes a field)
//   8  (P4a2) the variant's fields from the call and the axis; each
//            candidate's operand sources
//   9  (P4b) each candidate's micro-op, logical addresses: the picks
//   10 (P5)  physical addresses (rtl/pp/mem_ctrl.v, each with its own sp)
//   11 .. LAT+2         carried (shift registers)
//   LAT+2    (C1)  the flags arrive: the condition, the latches, and for
//            NORM_SCALE the planes the fresh direction leaves open (the
//            fast plane test) and BOX_FAR's corner
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
    parameter integer STACK_DEPTH = `ISA_DIM_STK_COUNT,
    parameter integer REFRACTION  = 1     // 0: no refraction (no transparent sphere, no ISA_ST_RF_* state)
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
    localparam integer SW     = 7;   // a state id: all are below 128 (golden's isa test), 7-bit decodes
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
    localparam integer CALLW  = 4;

    // Positions of the ring (see the header).
    localparam integer POS_C1 = LATENCY + 2;
    localparam integer CARRY1 = POS_C1 - 10;         // positions 11 .. LAT+2
    localparam integer CARRY2 = K - (LATENCY + 4);   // positions LAT+4 .. K-1

    localparam       K_SPH = 1'b0, K_PLN = 1'b1;
    localparam       C_HIT = 1'b0, C_SHD = 1'b1;
    localparam [CALLW-1:0] D_PRIMARY  = 4'd0, D_LIGHT    = 4'd1, D_SPHERE   = 4'd2,
                           D_DIFFUSE  = 4'd3, D_REFLECT  = 4'd4, D_SPECULAR = 4'd5;
    // refract's three dot() calls: d.n, the chord's b = v.t, t.n'.
    localparam [CALLW-1:0] D_RF_IN = 4'd6, D_RF_CHORD = 4'd7, D_RF_OUT = 4'd8;
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
    // Refraction (pp_ctrl's refr_q, rcut_q, rfneg_q, pend_q, pidx_q): the
    // shaded hit spawns a refracted child; the cutoff refused it; the
    // chord's disc or the exit's k' is < 0; per level, a refracted child
    // owed after the reflected subtree, and its sphere.
    localparam integer S_REFR  = S_DPOS + LN;
    localparam integer S_RCUT  = S_REFR + 1;
    localparam integer S_RFNEG = S_RCUT + 1;
    localparam integer S_PEND  = S_RFNEG + 1;
    localparam integer S_PIDX  = S_PEND + STK_N;
    localparam integer SWD     = S_PIDX + STK_N * OW;

    // An unwinding's jump, {st, sp, kind, idx} (the call stays).
    localparam integer UJ_IDX  = 0;
    localparam integer UJ_KIND = UJ_IDX + OW;
    localparam integer UJ_SP   = UJ_KIND + 1;
    localparam integer UJ_ST   = UJ_SP + SPW;
    localparam integer UJW     = UJ_ST + SW;

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
    localparam [SW-1:0]  ST_SH_POINT = `ISA_ST_SH_POINT;
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
    // Without refraction no sphere is transparent: a build without it
    // draws a scene's glass opaque, so it is for scenes without glass.
    wire [SPH_N-1:0]     sph_trn   = REFRACTION != 0 ? cfg[`ISA_DIM_CFG_TRN_LSB +: SPH_N]
                                                     : {SPH_N{1'b0}};
    wire unused_trn = REFRACTION == 0 && ^cfg[`ISA_DIM_CFG_TRN_LSB +: SPH_N];
    wire unused_cfg = ^{cfg[LN*32-1:`ISA_DIM_CFG_PLN_NEG_LSB + PLN_N],
                        cfg[`ISA_DIM_CFG_SPH_BITS_LSB - 1:`ISA_DIM_CFG_TRN_LSB + SPH_N],
                        cfg[`ISA_DIM_CFG_DEPTH_LSB - 1:`ISA_DIM_CFG_PLANES_LSB + NPW]};

    wire [SW-1:0] pixel_end = exposure ? `ISA_ST_EXPO_MUL : `ISA_ST_PIX_DONE;

    // ------------------------------------------------------------------------
    // Pure functions of the control flow: pp_ctrl's, one text with it
    // (bits, shade_next, nearest_hit_next, primary_ray_next; decoded_st is
    // pp_ctrl's alone), then the ring's own
    // ------------------------------------------------------------------------
    `include "ctrl_flow.vh"

    // Bit k set for every object k > i: the loops' next candidates (a
    // thermometer: each bit a function of i, no comparator).
    function [OBJ_N-1:0] above(input [OW-1:0] i);
        above = ({OBJ_N{1'b1}} << i) << 1;
    endfunction

    // Bit k set for k = i (the excluded object), if skip.
    function [OBJ_N-1:0] skipped(input skip, input [OW-1:0] i);
        skipped = skip ? {{(OBJ_N - 1){1'b0}}, 1'b1} << i : {OBJ_N{1'b0}};
    endfunction

    // {found, k}: the lowest set bit.
    function [OW:0] first_of(input [OBJ_N-1:0] m);
        integer k;
        begin
            first_of = {(OW + 1){1'b0}};
            for (k = OBJ_N - 1; k >= 0; k = k - 1)
                if (m[k]) first_of = {1'b1, k[OW-1:0]};
        end
    endfunction

    // Planes as objects (the high object bits 0).
    function [OBJ_N-1:0] pln_pad(input [PLN_N-1:0] m);
        pln_pad = {{(OBJ_N - PLN_N){1'b0}}, m};
    endfunction

    // The direction flag the fast plane test reads for a plane (against =
    // neg ? dpos : dneg, bit axis), as an index into {dpos, dneg}; 7 (no
    // flag: the test refuses) for an axis past z, which no scene has.
    function [2:0] flag_index(input neg, input [AB-1:0] axis);
        if (axis > 2'd2)  flag_index = 3'd7;
        else if (neg)     flag_index = {1'b0, axis} + 3'd3;
        else              flag_index = {1'b0, axis};
    endfunction

    // Which planes the fast plane test passes for a direction with these
    // flags (DirFlags::opposes); every plane without the test.
    function [PLN_N-1:0] planes_facing(input fast_on, input [3*PLN_N-1:0] sel,
                                       input [LN-1:0] dneg, input [LN-1:0] dpos);
        integer j;
        reg [7:0] f;
        begin
            f = {2'b00, dpos, dneg};
            for (j = 0; j < PLN_N; j = j + 1)
                planes_facing[j] = !fast_on || f[sel[3*j +: 3]];
        end
    endfunction

    // Stack levels, as masks of l's bits (no adder: an l - 1 or l + 1 would
    // put a carry chain before the decode): the bit of level l; levels
    // 0..l; levels below l. The level below l is level_bit(l) >> 1 and the
    // level above level_bit(l) << 1, for l >= 1 and l < STK_N - 1: where a
    // pop, a child or its parent is, they are.
    function [STK_N-1:0] level_bit(input [SPW-1:0] l);
        level_bit = {{(STK_N - 1){1'b0}}, 1'b1} << l;
    endfunction
    function [STK_N-1:0] at_or_below(input [SPW-1:0] l);
        at_or_below = ~(({STK_N{1'b1}} << l) << 1);
    endfunction
    function [STK_N-1:0] levels_below(input [SPW-1:0] l);
        levels_below = ~({STK_N{1'b1}} << l);
    endfunction

    // unwind (pp_ctrl), in three steps. m: the levels at or below `from`
    // that are coloured or whose parent owes a refracted child. The highest
    // of levels 1.. in m, one-hot and as a number (0: none).
    function [STK_N-1:0] highest(input [STK_N-1:0] m);
        integer l;
        begin
            highest = {STK_N{1'b0}};
            for (l = 1; l < STK_N; l = l + 1)
                if (m[l]) highest = {{(STK_N - 1){1'b0}}, 1'b1} << l;
        end
    endfunction
    function [SPW-1:0] highest_level(input [STK_N-1:0] m);
        integer l;
        begin
            highest_level = {SPW{1'b0}};
            for (l = 1; l < STK_N; l = l + 1)
                if (m[l]) highest_level = l[SPW-1:0];
        end
    endfunction
    // Then {st, sp, kind, idx}: at a coloured level, its POP (POP_ADD where
    // the level below has a colour); at another, the refracted child its
    // parent owes (RF_NSUB on the sphere in pidx); with none, `last`, or
    // ROOT_BLACK if level 0 has no colour. col: the levels whose colour a
    // POP may take. With `rf` (the shaded hit's own refracted child is
    // next), RF_NSUB at `here` on sphere `obj` instead.
    function [UJW-1:0] unwound(input [STK_N-1:0] h, input [SPW-1:0] lvl, input [STK_N-1:0] col,
                               input [STK_N*OW-1:0] pidx, input [SW-1:0] last, input rf,
                               input [SPW-1:0] here, input [OW-1:0] obj);
        integer l;
        begin
            unwound[UJ_KIND]        = K_SPH;
            unwound[UJ_IDX +: OW]   = {OW{1'b0}};
            for (l = 1; l < STK_N; l = l + 1)   // h is one-hot: an AND-OR
                unwound[UJ_IDX +: OW] = unwound[UJ_IDX +: OW] | ({OW{h[l]}} & pidx[OW*(l - 1) +: OW]);
            unwound[UJ_SP +: SPW]   = lvl;
            if (rf) begin
                unwound[UJ_ST +: SW]  = `ISA_ST_RF_NSUB;
                unwound[UJ_SP +: SPW] = here;
                unwound[UJ_IDX +: OW] = obj;
            end
            else if (|(h & col))
                unwound[UJ_ST +: SW] = |(h & (col << 1)) ? `ISA_ST_POP_ADD : `ISA_ST_POP_MOV;
            else if (|h)
                unwound[UJ_ST +: SW] = `ISA_ST_RF_NSUB;
            else
                unwound[UJ_ST +: SW] = col[0] ? last : `ISA_ST_ROOT_BLACK;
        end
    endfunction

    // An unwinding's jump as a jump, with the call `call`.
    function [JW-1:0] uj_jump(input [UJW-1:0] u, input [CALLW-1:0] call);
        uj_jump = {u[UJ_ST +: SW], u[UJ_SP +: SPW], call, u[UJ_KIND], u[UJ_IDX +: OW]};
    endfunction

    // Register addresses (golden::micro::isa::sphere, plane, corner, rot),
    // placed bit by bit, not added: a group's first register has its low
    // two bits clear (sphere and plane fields are 0..3 past it, the
    // stride 4), so object k's field is the field's address with k in
    // bits 2 and up; a corner and a rotation register are tables of their
    // 3-bit argument; a sphere's TRN register is TRN0 with k in its low
    // bits (static checks below).
    function [RW-1:0] sphere(input [OW-1:0] k, input [RW-1:0] field0);
        sphere = field0 | {{(RW - OW - 2){1'b0}}, k, 2'b00};
    endfunction
    function [RW-1:0] plane(input [OW-1:0] j, input [RW-1:0] field0);
        plane = field0 | {{(RW - OW - 2){1'b0}}, j, 2'b00};
    endfunction
    function [RW-1:0] trn(input [OW-1:0] k);
        trn = `ISA_REG_TRN0 | {{(RW - OW){1'b0}}, k};
    endfunction
    function [RW-1:0] corner(input [LN-1:0] sgn);
        case (sgn)
            3'd0: corner = `ISA_REG_BOX0 + 0 * `ISA_DIM_BOX_STRIDE;
            3'd1: corner = `ISA_REG_BOX0 + 1 * `ISA_DIM_BOX_STRIDE;
            3'd2: corner = `ISA_REG_BOX0 + 2 * `ISA_DIM_BOX_STRIDE;
            3'd3: corner = `ISA_REG_BOX0 + 3 * `ISA_DIM_BOX_STRIDE;
            3'd4: corner = `ISA_REG_BOX0 + 4 * `ISA_DIM_BOX_STRIDE;
            3'd5: corner = `ISA_REG_BOX0 + 5 * `ISA_DIM_BOX_STRIDE;
            3'd6: corner = `ISA_REG_BOX0 + 6 * `ISA_DIM_BOX_STRIDE;
            default: corner = `ISA_REG_BOX0 + 7 * `ISA_DIM_BOX_STRIDE;
        endcase
    endfunction
    function [RW-1:0] rot_reg(input [RAW-1:0] axis, input [RW-1:0] field0);
        case (axis)
            2'd0:    rot_reg = field0 + 0 * `ISA_DIM_ROT_STRIDE;
            2'd1:    rot_reg = field0 + 1 * `ISA_DIM_ROT_STRIDE;
            default: rot_reg = field0 + 2 * `ISA_DIM_ROT_STRIDE;
        endcase
    endfunction

    // The micro-op of a state (pp_ctrl's instruction of each state), with
    // logical addresses, in three steps, so that no path both decodes the
    // state and picks an operand, and none decodes more than a few inputs:
    //   P4a1 plan(st): of the state id alone, the opcode, the lane mask, and
    //        per address field either its register (a constant of the
    //        state) or which operand source it reads (a code); where the
    //        call or the rotation axis changes a field, a variant code;
    //   P4a2 with_variant(plan, call, rot): those fields filled in from the
    //        call and the axis; operands(s): the sources, every address
    //        that depends on more of S (the object, the level, the
    //        context, the direction), each a small function of a few bits;
    //   P4b  micro_op: each field its constant (code 0) or its source.
    // The sources of each field, by code (0: the constant).
    localparam integer SELW = 4, WSELW = 3;
    localparam [SELW-1:0]  A_CONST = 0, A_ROT_S = 1, A_OBJ_N = 2, A_OBJ_MAT = 3, A_OBJ_COL = 4,
                           A_SHADE_O = 5, A_SHADE_D = 6, A_SHADE_P = 7, A_SHADE_R = 8,
                           A_SEARCH_O = 9, A_SEARCH_D = 10, A_ISECT_1 = 11, A_ISECT_4 = 12,
                           A_CORNER_NEAR = 13, A_CORNER_FAR = 14, A_COLOUR = 15;
    localparam integer A_N = 16;
    localparam [SELW-1:0]  B_CONST = 0, B_ROT_C = 1, B_OBJ_N = 2, B_OBJ_MAT = 3, B_SHADE_P = 4,
                           B_SHADE_W = 5, B_SEARCH_O = 6, B_SEARCH_D = 7, B_ISECT_N = 8,
                           B_SPH_C = 9, B_OBJ_SPH_C = 10, B_OBJ_SPH_R = 11, B_BEST_MAT = 12,
                           B_BEST_CUT = 13, B_TRN = 14, B_BEST_TRN = 15;
    localparam integer B_N = 16;
    localparam [WSELW-1:0] W_CONST = 0, W_U_DST = 1, W_SHADE_P = 2, W_SHADE_R = 3, W_SHADE_COL = 4;
    localparam integer W_N = 5;
    // A plan: {op, mask, a code, a register, b code, b register, w code, w register}.
    localparam integer PL_W   = 0;
    localparam integer PL_WS  = PL_W + RW;
    localparam integer PL_B   = PL_WS + WSELW;
    localparam integer PL_BS  = PL_B + RW;
    localparam integer PL_A   = PL_BS + SELW;
    localparam integer PL_AS  = PL_A + RW;
    localparam integer PL_M   = PL_AS + SELW;
    localparam integer PL_OP  = PL_M + LN;
    localparam integer PLW    = PL_OP + OPW;
    // A plan of P4a1 carries a variant code above it: which fields the
    // call or the rotation axis sets (P4a2).
    localparam integer VARW = 3;
    localparam [VARW-1:0]  V_NONE = 0, V_DOT_1 = 1, V_DOT_3 = 2, V_NORM_SCALE = 3, V_ROT_U = 4,
                           V_ROT_V = 5, V_ROT_UV = 6, V_RF_CS = 7;
    localparam integer PLVW   = PLW + VARW;
    // The operand sources: {w's codes W_N-1 .. 1, b's B_N-1 .. 1, a's A_N-1 .. 1}.
    localparam integer SRC_A  = 0;
    localparam integer SRC_B  = SRC_A + (A_N - 1) * RW;
    localparam integer SRC_W  = SRC_B + (B_N - 1) * RW;
    localparam integer SRCW   = SRC_W + (W_N - 1) * RW;

    function [PLVW-1:0] plan(input [SW-1:0] st);
        reg [OPW-1:0]   o;
        reg [RW-1:0]    a, b, w;
        reg [SELW-1:0]  as, bs;
        reg [WSELW-1:0] ws;
        reg [LN-1:0]    m;
        reg [VARW-1:0]  v;
        begin
            v  = V_NONE;
            o  = `ISA_OP_NOP;
            a  = `ISA_REG_ZERO;
            b  = `ISA_REG_ZERO;
            w  = `ISA_REG_ZERO;
            as = A_CONST;
            bs = B_CONST;
            ws = W_CONST;
            m  = M_XYZ;
            case (st)
                `ISA_ST_PRI_ITOF:  begin o = `ISA_OP_ITOF; w = T_P; end
                `ISA_ST_PRI_HALF:  begin o = `ISA_OP_ADD; w = T_P; a = T_P; b = `ISA_REG_CAM_HALF; end
                `ISA_ST_ROT_COS:   begin o = `ISA_OP_MUL; w = T_N; a = T_P; bs = B_ROT_C; end
                `ISA_ST_ROT_SIN_U: begin o = `ISA_OP_MULR1; w = T_R; as = A_ROT_S; b = T_P; v = V_ROT_U; end
                `ISA_ST_ROT_SIN_V: begin o = `ISA_OP_MULR2; w = T_R; as = A_ROT_S; b = T_P; v = V_ROT_V; end
                `ISA_ST_ROT_ADD:   begin o = `ISA_OP_ADD; w = T_P; a = T_N; b = T_R; v = V_ROT_UV; end
                `ISA_ST_DOT_1:      begin o = `ISA_OP_DOT1; v = V_DOT_1; end
                `ISA_ST_DOT_2:      o = `ISA_OP_DOT2;
                `ISA_ST_DOT_3:      begin o = `ISA_OP_DOT3; m = M_X; v = V_DOT_3; end
                `ISA_ST_NORM_ROOTS: begin o = `ISA_OP_ROOTS; w = T_LEN; a = T_LEN; m = M_X | M_Y; end
                `ISA_ST_NORM_INV:   begin o = `ISA_OP_MULR1; w = T_INV; a = T_LEN; b = T_LEN; m = M_X; end
                `ISA_ST_NORM_SCALE: begin o = `ISA_OP_MULX; b = T_INV; v = V_NORM_SCALE; end
                `ISA_ST_ISECT_1:    begin o = `ISA_OP_ISECT1; as = A_ISECT_1; bs = B_ISECT_N; end
                `ISA_ST_ISECT_2:    begin o = `ISA_OP_ISECT2; w = T_G; as = A_SEARCH_D; bs = B_ISECT_N; end
                `ISA_ST_ISECT_3:    begin o = `ISA_OP_ISECT3; a = T_G; end
                `ISA_ST_ISECT_4:    begin o = `ISA_OP_ISECT4; w = T_S; as = A_ISECT_4; end
                `ISA_ST_BOX_FAR:    begin o = `ISA_OP_SUB; w = T_G; bs = B_SEARCH_O; as = A_CORNER_FAR; end
                `ISA_ST_BOX_BEHIND: begin o = `ISA_OP_MUL; w = T_S; a = T_G; bs = B_SEARCH_D; end
                `ISA_ST_BOX_NEAR:   begin o = `ISA_OP_SUB; w = T_V; bs = B_SEARCH_O; as = A_CORNER_NEAR; end
                `ISA_ST_BOX_P1:     begin o = `ISA_OP_MULR1; w = T_Q; a = T_V; bs = B_SEARCH_D; end
                `ISA_ST_BOX_Q1:     begin o = `ISA_OP_MULR1; w = T_U; as = A_SEARCH_D; b = T_G; end
                `ISA_ST_BOX_D1:     begin o = `ISA_OP_SUB; w = T_Q; a = T_Q; b = T_U; end
                `ISA_ST_BOX_P2:     begin o = `ISA_OP_MULR2; w = T_Q; a = T_V; bs = B_SEARCH_D; end
                `ISA_ST_BOX_Q2:     begin o = `ISA_OP_MULR2; w = T_U; as = A_SEARCH_D; b = T_G; end
                `ISA_ST_BOX_D2:     begin o = `ISA_OP_SUB; w = T_Q; a = T_Q; b = T_U; end
                `ISA_ST_SPH_V:      begin o = `ISA_OP_SUB; w = T_V; as = A_SEARCH_O; bs = B_SPH_C; end
                `ISA_ST_SPH_BD:     begin o = `ISA_OP_NMULX; w = T_U; as = A_SEARCH_D; b = T_Q; end
                `ISA_ST_SPH_W:      begin o = `ISA_OP_ADD; w = T_V; a = T_V; b = T_U; end
                `ISA_ST_SPH_SQRT:   begin o = `ISA_OP_SQRT; w = T_S; a = T_S; m = M_X; end
                `ISA_ST_SPH_T:      begin o = `ISA_OP_ADD; ws = W_U_DST; a = T_S; b = T_Q; m = M_X; end
                `ISA_ST_PLN_RECIP:  begin o = `ISA_OP_RECIPY; w = T_Q; a = T_S; m = M_X; end
                `ISA_ST_PLN_T:      begin o = `ISA_OP_NMULX; ws = W_U_DST; a = T_S; b = T_Q; m = M_X; end
                `ISA_ST_HIT_CMP:    begin o = `ISA_OP_SUB; w = T_G; a = T_U; b = T_BEST; m = M_X; end
                `ISA_ST_HIT_KEEP:   begin o = `ISA_OP_MOV; w = T_BEST; a = T_U; m = M_X; end
                `ISA_ST_CUT_W:      begin o = `ISA_OP_MULZ; w = T_U; a = `ISA_REG_CUR_W; bs = B_BEST_MAT; m = M_Z; end
                `ISA_ST_CUT_CMP:    begin o = `ISA_OP_SUB; w = T_G; a = T_U; bs = B_BEST_CUT; m = M_Z; end
                `ISA_ST_SHD_DIST:   begin o = `ISA_OP_ADD; w = T_G; a = T_U; b = T_LEN; m = M_X; end
                `ISA_ST_SH_OFFSET:  begin o = `ISA_OP_NMULX; w = T_V; a = `ISA_REG_CUR_D; b = T_BEST; end
                `ISA_ST_SH_POINT:   begin o = `ISA_OP_ADD; ws = W_SHADE_P; as = A_SHADE_O; b = T_V; end
                `ISA_ST_SH_NORMAL_SUB:   begin o = `ISA_OP_SUB; w = T_N; as = A_SHADE_P; bs = B_OBJ_SPH_C; end
                `ISA_ST_SH_NORMAL_SCALE: begin o = `ISA_OP_MULY; w = T_N; a = T_N; bs = B_OBJ_SPH_R; end
                `ISA_ST_SH_LIGHT_VEC: begin o = `ISA_OP_SUB; w = T_R; a = `ISA_REG_LIGHT_POS; bs = B_SHADE_P; end
                `ISA_ST_SH_KD:       begin o = `ISA_OP_MULX; w = T_G; as = A_OBJ_MAT; b = T_V; m = M_X; end
                `ISA_ST_SH_CL:       begin o = `ISA_OP_MUL; w = T_S; as = A_OBJ_COL; b = `ISA_REG_LIGHT_COL; end
                `ISA_ST_SH_DIFFUSE:  begin o = `ISA_OP_MULX; w = T_S; a = T_S; b = T_G; end
                `ISA_ST_SH_REFL_K:   begin o = `ISA_OP_MUL2X; w = T_U; as = A_OBJ_N; b = T_Q; end
                `ISA_ST_SH_REFL:     begin o = `ISA_OP_SUB; ws = W_SHADE_R; as = A_SHADE_D; b = T_U; end
                `ISA_ST_SH_POW2:     begin o = `ISA_OP_MUL; w = T_U; a = T_Q; b = T_Q; m = M_X; end
                `ISA_ST_SH_POW4:     begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_U; m = M_X; end
                `ISA_ST_SH_POW5:     begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_Q; m = M_X; end
                `ISA_ST_SH_POW10:    begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_U; m = M_X; end
                `ISA_ST_SH_POW20:    begin o = `ISA_OP_MUL; w = T_U; a = T_U; b = T_U; m = M_X; end
                `ISA_ST_SH_KS:       begin o = `ISA_OP_MULX; w = T_V; as = A_OBJ_MAT; b = T_U; m = M_Y; end
                `ISA_ST_SH_SPEC:     begin o = `ISA_OP_MULY; w = T_G; a = `ISA_REG_LIGHT_COL; b = T_V; end
                `ISA_ST_SH_LOCAL:    begin o = `ISA_OP_ADD; w = T_S; a = T_S; b = T_G; end
                `ISA_ST_SH_COLOUR:   begin o = `ISA_OP_MUL; ws = W_SHADE_COL; as = A_COLOUR; bs = B_SHADE_W; end
                `ISA_ST_SH_CHILD_W:  begin o = `ISA_OP_MULZ; w = `ISA_REG_CUR_W; a = `ISA_REG_PAR_W; bs = B_OBJ_MAT; end
                `ISA_ST_POP_ADD: begin
                    o = `ISA_OP_ADD; w = `ISA_REG_PAR_COL; a = `ISA_REG_PAR_COL; b = `ISA_REG_CUR_COL;
                end
                `ISA_ST_POP_MOV:    begin o = `ISA_OP_MOV; w = `ISA_REG_PAR_COL; a = `ISA_REG_CUR_COL; end
                `ISA_ST_ROOT_BLACK: begin o = `ISA_OP_MOV; w = `ISA_REG_CUR_COL; a = `ISA_REG_ZERO; end
                `ISA_ST_EXPO_MUL:   begin o = `ISA_OP_MULX; w = T_U; a = `ISA_REG_CUR_COL; b = `ISA_REG_ROT0_S; end
                `ISA_ST_EXPO_EXP:   begin o = `ISA_OP_EXP; w = T_U; a = T_U; end
                `ISA_ST_EXPO_SUB:   begin o = `ISA_OP_SUB; w = `ISA_REG_CUR_COL; a = `ISA_REG_ONE; b = T_U; end
                `ISA_ST_PIX_DONE:   a = `ISA_REG_STK0_COL;
                // refract (sphere idx; TRN = <eta, ior, kt>)
                `ISA_ST_RF_NSUB:   begin o = `ISA_OP_SUB; w = T_N; a = `ISA_REG_CUR_O; bs = B_SPH_C; end
                `ISA_ST_RF_NSCALE: begin o = `ISA_OP_MULY; w = T_N; a = T_N; bs = B_OBJ_SPH_R; end
                `ISA_ST_RF_COS2:   begin o = `ISA_OP_MUL; w = T_U; a = T_Q; b = T_Q; m = M_X; end
                `ISA_ST_RF_SIN2:   begin o = `ISA_OP_SUB; w = T_U; a = `ISA_REG_ONE; b = T_U; m = M_X; end
                `ISA_ST_RF_ETA1:   begin o = `ISA_OP_MULX; w = T_U; a = T_U; bs = B_TRN; m = M_X; end
                `ISA_ST_RF_ETA2:   begin o = `ISA_OP_MULX; w = T_U; a = T_U; bs = B_TRN; m = M_X; end
                `ISA_ST_RF_K:      begin o = `ISA_OP_SUB; w = T_U; a = `ISA_REG_ONE; b = T_U; m = M_X; end
                `ISA_ST_RF_SQRT:   begin o = `ISA_OP_SQRT; w = T_U; a = T_U; m = M_X; end
                `ISA_ST_RF_EDN:    begin o = `ISA_OP_MULX; w = T_G; a = T_Q; bs = B_TRN; m = M_X; end
                `ISA_ST_RF_COEF:   begin o = `ISA_OP_ADD; w = T_G; a = T_G; b = T_U; m = M_X; end
                `ISA_ST_RF_ED:     begin o = `ISA_OP_MULX; w = T_V; a = `ISA_REG_PAR_D; bs = B_TRN; end
                `ISA_ST_RF_CN:     begin o = `ISA_OP_MULX; w = T_S; a = T_N; b = T_G; end
                `ISA_ST_RF_DIR:    begin o = `ISA_OP_SUB; w = T_R; a = T_V; b = T_S; end
                `ISA_ST_RF_CV:     begin o = `ISA_OP_SUB; w = T_V; a = `ISA_REG_CUR_O; bs = B_SPH_C; end
                `ISA_ST_RF_CBD:    begin o = `ISA_OP_NMULX; w = T_U; a = T_R; b = T_Q; end
                `ISA_ST_RF_CW:     begin o = `ISA_OP_ADD; w = T_V; a = T_V; b = T_U; end
                `ISA_ST_RF_CSQRT:  begin o = `ISA_OP_SQRT; w = T_S; a = T_S; m = M_X; end
                `ISA_ST_RF_CS:     begin o = `ISA_OP_SUB; w = T_S; b = T_Q; m = M_X; v = V_RF_CS; end
                `ISA_ST_RF_CST:    begin o = `ISA_OP_MULX; w = T_U; a = T_R; b = T_S; end
                `ISA_ST_RF_EXIT:   begin o = `ISA_OP_ADD; w = `ISA_REG_CUR_O; a = `ISA_REG_CUR_O; b = T_U; end
                `ISA_ST_RF_OSUB:   begin o = `ISA_OP_SUB; w = T_N; a = `ISA_REG_CUR_O; bs = B_SPH_C; end
                `ISA_ST_RF_OSCALE: begin o = `ISA_OP_MULY; w = T_N; a = T_N; bs = B_OBJ_SPH_R; end
                `ISA_ST_RF_OCOS2:  begin o = `ISA_OP_MUL; w = T_U; a = T_Q; b = T_Q; m = M_X; end
                `ISA_ST_RF_OSIN2:  begin o = `ISA_OP_SUB; w = T_U; a = `ISA_REG_ONE; b = T_U; m = M_X; end
                `ISA_ST_RF_OIOR1:  begin o = `ISA_OP_MULY; w = T_U; a = T_U; bs = B_TRN; m = M_X; end
                `ISA_ST_RF_OIOR2:  begin o = `ISA_OP_MULY; w = T_U; a = T_U; bs = B_TRN; m = M_X; end
                `ISA_ST_RF_OK:     begin o = `ISA_OP_SUB; w = T_U; a = `ISA_REG_ONE; b = T_U; m = M_X; end
                `ISA_ST_RF_OEDN:   begin o = `ISA_OP_MULY; w = T_G; a = T_Q; bs = B_TRN; m = M_X; end
                `ISA_ST_RF_OSQRT:  begin o = `ISA_OP_SQRT; w = T_U; a = T_U; m = M_X; end
                `ISA_ST_RF_OCOEF:  begin o = `ISA_OP_SUB; w = T_G; a = T_G; b = T_U; m = M_X; end
                `ISA_ST_RF_OED:    begin o = `ISA_OP_MULY; w = T_V; a = T_R; bs = B_TRN; end
                `ISA_ST_RF_OCN:    begin o = `ISA_OP_MULX; w = T_S; a = T_N; b = T_G; end
                `ISA_ST_RF_ODIR:   begin o = `ISA_OP_SUB; w = `ISA_REG_CUR_D; a = T_V; b = T_S; end
                `ISA_ST_RF_TIR_K:  begin o = `ISA_OP_MUL2X; w = T_U; a = T_N; b = T_Q; end
                `ISA_ST_RF_TIR:    begin o = `ISA_OP_SUB; w = `ISA_REG_CUR_D; a = `ISA_REG_PAR_D; b = T_U; end
                `ISA_ST_RF_CHILD_W: begin
                    o = `ISA_OP_MULZ; w = `ISA_REG_CUR_W; a = `ISA_REG_PAR_W; bs = B_TRN;
                end
                `ISA_ST_RF_CUT_W:  begin o = `ISA_OP_MULZ; w = T_U; a = `ISA_REG_CUR_W; bs = B_BEST_TRN; m = M_Z; end
                `ISA_ST_RF_CUT_CMP: begin o = `ISA_OP_SUB; w = T_G; a = T_U; bs = B_BEST_CUT; m = M_Z; end
                default: ;
            endcase
            plan = {v, o, m, as, a, bs, b, ws, w};
        end
    endfunction

    // P4a2: the fields of a plan that its variant code `v` leaves to the
    // call, the rotation axis and rfneg (in plan, every such field is its
    // default: register ZERO, code 0, mask XYZ).
    function [PLW-1:0] with_variant(input [PLVW-1:0] p, input [CALLW-1:0] call,
                                    input [RAW-1:0] rot, input rfneg);
        reg [LN-1:0] rot_u, rot_v;
        begin
            rot_u = rot == 0 ? M_Y : rot == 1 ? M_Z : M_X;
            rot_v = rot == 0 ? M_Z : rot == 1 ? M_X : M_Y;
            with_variant = p[PLW-1:0];
            case (p[PLW +: VARW])
                V_DOT_1:
                    case (call)
                        D_PRIMARY: begin with_variant[PL_A +: RW] = T_P; with_variant[PL_B +: RW] = T_P; end
                        D_LIGHT:   begin with_variant[PL_A +: RW] = T_R; with_variant[PL_B +: RW] = T_R; end
                        D_SPHERE:  begin with_variant[PL_A +: RW] = T_V; with_variant[PL_BS +: SELW] = B_SEARCH_D; end
                        D_DIFFUSE: begin with_variant[PL_AS +: SELW] = A_OBJ_N; with_variant[PL_B +: RW] = T_L; end
                        D_REFLECT: begin
                            with_variant[PL_AS +: SELW] = A_SHADE_D;
                            with_variant[PL_BS +: SELW] = B_OBJ_N;
                        end
                        D_RF_IN:    if (REFRACTION != 0) begin with_variant[PL_A +: RW] = `ISA_REG_PAR_D; with_variant[PL_B +: RW] = T_N; end
                        D_RF_CHORD: if (REFRACTION != 0) begin with_variant[PL_A +: RW] = T_V; with_variant[PL_B +: RW] = T_R; end
                        D_RF_OUT:   if (REFRACTION != 0) begin with_variant[PL_A +: RW] = T_R; with_variant[PL_B +: RW] = T_N; end
                        default:   begin with_variant[PL_AS +: SELW] = A_SHADE_R; with_variant[PL_B +: RW] = T_L; end
                    endcase
                V_DOT_3:
                    case (call)
                        D_PRIMARY, D_LIGHT: with_variant[PL_W +: RW] = T_LEN;
                        D_DIFFUSE:          with_variant[PL_W +: RW] = T_V;
                        default:            with_variant[PL_W +: RW] = T_Q;
                    endcase
                V_NORM_SCALE: begin
                    with_variant[PL_W +: RW] = call == D_PRIMARY ? `ISA_REG_CUR_D : T_L;
                    with_variant[PL_A +: RW] = call == D_PRIMARY ? T_P : T_R;
                end
                V_ROT_U:  with_variant[PL_M +: LN] = rot_u;
                V_ROT_V:  with_variant[PL_M +: LN] = rot_v;
                V_ROT_UV: with_variant[PL_M +: LN] = rot_u | rot_v;
                // refract: s = sqrt(disc) - b, or 0 - b where disc < 0
                V_RF_CS:  with_variant[PL_A +: RW] = rfneg ? `ISA_REG_ZERO : T_S;
                default: ;
            endcase
        end
    endfunction

    function [SRCW-1:0] operands(input [SWD-1:0] s);
        reg [RAW-1:0]   rot;
        reg             ctx, kind, found, okind, push, bkind, chord;
        reg [OW-1:0]    idx, oidx, bidx;
        reg [LN-1:0]    dsign;
        reg [RW-1:0]    shading_o, shading_d, shading_col, shading_w, shading_p, shading_r;
        reg [RW-1:0]    search_o, search_d, obj_n, obj_mat, obj_col;
        begin
            rot   = s[S_ROT +: RAW];
            ctx   = s[S_CTX];
            kind  = s[J_KIND];
            idx   = s[J_IDX +: OW];
            found = s[S_FOUND];
            okind = s[S_OKIND];
            oidx  = s[S_OIDX +: OW];
            bkind = s[S_BKIND];
            bidx  = s[S_BIDX +: OW];
            // A child is pushed for the reflected ray or the refracted one:
            // either way the shaded ray is the parent's.
            push  = s[S_PUSH] || s[S_REFR];
            chord = REFRACTION != 0 && s[J_CALL +: CALLW] == D_RF_CHORD;
            dsign = s[S_DSIGN +: LN];

            shading_o   = push ? `ISA_REG_PAR_O : `ISA_REG_CUR_O;
            shading_d   = push ? `ISA_REG_PAR_D : `ISA_REG_CUR_D;
            shading_col = push ? `ISA_REG_PAR_COL : `ISA_REG_CUR_COL;
            shading_w   = push ? `ISA_REG_PAR_W : `ISA_REG_CUR_W;
            shading_p   = push ? `ISA_REG_CUR_O : T_P;
            shading_r   = push ? `ISA_REG_CUR_D : T_R;
            search_o    = ctx == C_HIT ? `ISA_REG_CUR_O : shading_p;
            search_d    = ctx == C_HIT ? `ISA_REG_CUR_D : T_L;
            obj_n       = okind == K_SPH ? T_N : plane(oidx, `ISA_REG_PLN0_N);
            obj_mat     = okind == K_SPH ? sphere(oidx, `ISA_REG_SPH0_MAT)
                                         : plane(oidx, `ISA_REG_PLN0_MAT);
            obj_col     = okind == K_SPH ? sphere(oidx, `ISA_REG_SPH0_COL)
                                         : plane(oidx, `ISA_REG_PLN0_COL);

            // In code order, highest first (the enumerations above).
            operands = {
                // w: W_SHADE_COL .. W_U_DST
                shading_col, shading_r, shading_p, (ctx == C_HIT && !found) ? T_BEST : T_U,
                // b: B_BEST_TRN .. B_ROT_C
                trn(bidx), trn(idx),
                bkind == K_SPH ? sphere(bidx, `ISA_REG_SPH0_R) : plane(bidx, `ISA_REG_PLN0_Q),
                bkind == K_SPH ? sphere(bidx, `ISA_REG_SPH0_MAT) : plane(bidx, `ISA_REG_PLN0_MAT),
                sphere(oidx, `ISA_REG_SPH0_R), sphere(oidx, `ISA_REG_SPH0_C), sphere(idx, `ISA_REG_SPH0_C),
                kind == K_SPH ? T_V : plane(idx, `ISA_REG_PLN0_N),
                search_d, search_o, shading_w, shading_p, obj_mat, obj_n, rot_reg(rot, `ISA_REG_ROT0_C),
                // a: A_COLOUR .. A_ROT_S
                (s[S_SPEC] && !s[S_DIFF]) ? T_G : T_S, corner(~dsign), corner(dsign),
                kind == K_SPH ? sphere(idx, `ISA_REG_SPH0_R) : plane(idx, `ISA_REG_PLN0_Q),
                kind == K_SPH ? T_V : search_o,
                chord ? T_R : search_d, search_o, shading_r, shading_p, shading_d, shading_o, obj_col, obj_mat, obj_n,
                rot_reg(rot, `ISA_REG_ROT0_S)};
        end
    endfunction

    // P4b: {op, a, b, w, mask}, each address its register or its source.
    function [UW-1:0] micro_op(input [PLW-1:0] p, input [SRCW-1:0] src);
        reg [(1 << SELW)*RW-1:0]  a_of, b_of;   // every code used (static check below)
        reg [(1 << WSELW)*RW-1:0] w_of;
        begin
            a_of = {src[SRC_A +: (A_N - 1) * RW], p[PL_A +: RW]};
            b_of = {src[SRC_B +: (B_N - 1) * RW], p[PL_B +: RW]};
            w_of = {{((1 << WSELW) - W_N) * RW{1'b0}}, src[SRC_W +: (W_N - 1) * RW], p[PL_W +: RW]};
            micro_op = {p[PL_OP +: OPW],
                        a_of[RW*p[PL_AS +: SELW] +: RW],
                        b_of[RW*p[PL_BS +: SELW] +: RW],
                        w_of[RW*p[PL_WS +: WSELW] +: RW],
                        p[PL_M +: LN]};
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
    assign state    = {{(`ISA_DIM_ST_BITS - SW){1'b0}}, st0};

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
    // Scene constants, registered from the configuration word (it changes
    // only while every context is idle, at least two cycles before a take's
    // first precompute)
    // ------------------------------------------------------------------------
    reg [SPH_N-1:0]    sph_lt_n_q;  // k < n_sph
    reg [PLN_N-1:0]    pln_lt_n_q;  // j < n_pln
    reg [STK_N-1:0]    room_at_q;   // l + 1 < max_depth: a level above l exists
    reg [3*PLN_N-1:0]  pln_sel_q;   // the direction flag each plane's fast test reads
    integer kc;
    always @(posedge clk) begin
        for (kc = 0; kc < SPH_N; kc = kc + 1) sph_lt_n_q[kc] <= (kc < n_sph);
        for (kc = 0; kc < PLN_N; kc = kc + 1) begin
            pln_lt_n_q[kc] <= (kc < n_pln);
            // DirFlags::opposes: a normal facing -axis needs d.axis > 0.
            pln_sel_q[3*kc +: 3] <= flag_index(pln_neg[kc], pln_axis[AB*kc +: AB]);
        end
        for (kc = 0; kc < STK_N; kc = kc + 1) room_at_q[kc] <= (kc + 1 < max_depth);
    end

    // ------------------------------------------------------------------------
    // Position 1: the state after the turn; hold: the next turn repeats it
    // ------------------------------------------------------------------------
    // cw1: the turn was SH_CHILD_W of a hit that also has a refracted
    // child, which the parent's level now owes (pp_ctrl's owes_now).
    reg [SWD-1:0] s1;
    reg           h1, cw1;
    always @(posedge clk) begin
        if (initial_sweep || (is_free && !take)) s1 <= S_IDLE;
        else if (take)                           s1 <= S_TAKEN;
        else                                     s1 <= s0;
        h1  <= !issue;
        cw1 <= !initial_sweep && st0 == `ISA_ST_SH_CHILD_W && s0[S_REFR];
    end

    // ------------------------------------------------------------------------
    // P1a: masks, tables, material bits (registers and scene constants only)
    // ------------------------------------------------------------------------
    wire [SPW-1:0]   sp1    = s1[J_SP +: SPW];
    wire             okind1 = s1[S_OKIND];
    wire [OW-1:0]    oidx1  = s1[S_OIDX +: OW];
    wire [STK_N-1:0] col1   = s1[S_COL +: STK_N];
    wire [STK_N-1:0] pend1  = s1[S_PEND +: STK_N];
    wire [STK_N*OW-1:0] pidx1 = s1[S_PIDX +: STK_N * OW];
    wire             child1 = s1[S_PUSH] || s1[S_REFR];
    wire [OBJ_N-1:0] gt1    = above(s1[J_IDX +: OW]);
    wire [STK_N-1:0] below1      = level_bit(sp1) >> 1;
    wire [STK_N-1:0] col_mov1    = col1 | below1;
    wire [STK_N-1:0] col_colour1 = col1 | level_bit(sp1);
    // SH_CHILD_W: the parent's level owes the refracted child (refr) on
    // the shaded sphere; pend_now1, pidx_now1: as they stand after
    // SH_CHILD_W's turn when cw1, for the search that may end in it.
    wire [STK_N-1:0] pend_cw1    = (pend1 & ~below1) | (s1[S_REFR] ? below1 : {STK_N{1'b0}});
    reg  [STK_N*OW-1:0] pidx_cw1;
    integer kp;
    always @* begin
        pidx_cw1 = pidx1;
        for (kp = 0; kp < STK_N; kp = kp + 1)
            if (below1[kp]) pidx_cw1[OW*kp +: OW] = oidx1;
    end
    wire [STK_N-1:0]    pend_now1 = cw1 ? (pend1 | below1) : pend1;
    wire [STK_N*OW-1:0] pidx_now1 = cw1 ? pidx_cw1 : pidx1;
    wire             best_trn1 = s1[S_BKIND] == K_SPH && sph_trn[s1[S_BIDX +: OW]];
    wire             this_trn1 = s1[J_KIND] == K_SPH && sph_trn[s1[J_IDX +: OW]];
    wire [OBJ_N-1:0] pln_skip1   = skipped(s1[S_EXCL] && okind1 == K_PLN, oidx1);
    wire [PLN_N-1:0] pln_base1   = pln_lt_n_q & ~pln_skip1[PLN_N-1:0];
    wire             unused_pln_skip1 = ^pln_skip1[OBJ_N-1:PLN_N];
    wire [SPH_N-1:0] sph_base1   = sph_lt_n_q & ~skipped(s1[S_EXCL] && okind1 == K_SPH, oidx1);
    wire [PLN_N-1:0] facing1     = planes_facing(fast, pln_sel_q, s1[S_DNEG +: LN], s1[S_DPOS +: LN]);

    reg [SWD-1:0]    s2;
    reg              h2;
    reg [SPH_N-1:0]  sph_open_first2, sph_open_next2;
    reg [PLN_N-1:0]  pln_open_first2, pln_open_next2, pln_base2;
    reg [MB-1:0]     obj_bits2, best_bits2, this_bits2;
    reg              best_trn2, this_trn2;
    reg              room2;
    reg [SPW-1:0]    sp_inc2;
    // The four unwindings: now (sp, col, pend as after SH_CHILD_W),
    // POP_ADD (sp - 1, col), POP_MOV (sp - 1, col with level sp - 1),
    // SH_COLOUR without a push (sp, col with level sp); after a POP, the
    // refracted child owed at sp too. m: the levels to look at; c: the
    // colours a POP may take; p: the owed children's spheres.
    reg [STK_N-1:0]  uw_m_now2, uw_m_add2, uw_m_mov2, uw_m_col2;
    reg [STK_N-1:0]  uw_c_now2, uw_c_add2, uw_c_mov2, uw_c_col2;
    reg [STK_N*OW-1:0] uw_p_now2, uw_p2;
    reg [STK_N-1:0]  col_shade2;   // SH_COLOUR: col with the shaded level's bit
    reg [STK_N-1:0]  col_mov2;     // POP_MOV: col with level sp - 1
    reg [STK_N-1:0]  col_push2;    // SH_OFFSET with a child: col without level sp + 1
    reg [STK_N-1:0]  col_nsub2;    // RF_NSUB: col without level sp
    reg [STK_N-1:0]  pend_nsub2;   // RF_NSUB: pend without level sp - 1
    reg [STK_N-1:0]  pend_cw2;     // SH_CHILD_W: pend, pidx with level sp - 1 written
    reg [STK_N*OW-1:0] pidx_cw2;
    reg [RAW+SW+CALLW-1:0] prn_first2, prn_after2;
    always @(posedge clk) begin
        s2              <= s1;
        h2              <= h1;
        sph_open_first2 <= sph_base1;
        sph_open_next2  <= sph_base1 & gt1[SPH_N-1:0];
        pln_open_first2 <= pln_base1 & facing1;
        pln_open_next2  <= pln_base1 & facing1 & gt1[PLN_N-1:0];
        pln_base2       <= pln_base1;
        obj_bits2       <= bits(okind1, oidx1, sph_bits, pln_bits);
        best_bits2      <= bits(s1[S_BKIND], s1[S_BIDX +: OW], sph_bits, pln_bits);
        this_bits2      <= bits(s1[J_KIND], s1[J_IDX +: OW], sph_bits, pln_bits);
        best_trn2       <= best_trn1;
        this_trn2       <= this_trn1;
        room2           <= room_at_q[sp1];
        sp_inc2         <= sp1 + 1'b1;
        uw_m_now2       <= (col1 | (pend_now1 << 1)) & at_or_below(sp1);
        uw_m_add2       <= (col1 & levels_below(sp1)) | ((pend1 << 1) & at_or_below(sp1));
        uw_m_mov2       <= (col_mov1 & levels_below(sp1)) | ((pend1 << 1) & at_or_below(sp1));
        uw_m_col2       <= (col_colour1 | (pend1 << 1)) & at_or_below(sp1);
        uw_c_now2       <= col1;
        uw_c_add2       <= col1 & levels_below(sp1);
        uw_c_mov2       <= col_mov1 & levels_below(sp1);
        uw_c_col2       <= col_colour1;
        uw_p_now2       <= pidx_now1;
        uw_p2           <= pidx1;
        col_shade2      <= child1 ? col_mov1 : col_colour1;
        col_mov2        <= col_mov1;
        col_push2       <= col1 & ~(level_bit(sp1) << 1);
        col_nsub2       <= col1 & ~level_bit(sp1);
        pend_nsub2      <= pend1 & ~below1;
        pend_cw2        <= pend_cw1;
        pidx_cw2        <= pidx_cw1;
        prn_first2      <= primary_ray_next(rotate, {(RAW + 1){1'b0}}, s1[S_ROT +: RAW], s1[J_CALL +: CALLW]);
        prn_after2      <= primary_ray_next(rotate, {1'b0, s1[S_ROT +: RAW]} + 1'b1, s1[S_ROT +: RAW],
                                            s1[J_CALL +: CALLW]);
    end

    // ------------------------------------------------------------------------
    // P1b: priorities
    // ------------------------------------------------------------------------
    reg [SWD-1:0]    s3;
    reg              h3;
    reg [OW:0]       sph_first3, sph_next3, pln_first3, pln_next3;
    reg [PLN_N-1:0]  pln_base3;
    reg [MB-1:0]     obj_bits3;
    // With the cutoff, cut() before shading a hit: for its reflected child
    // (cut_*), else for its refracted one (rcut_*); the best hit or the
    // object under test.
    reg              cut_best3, cut_this3, rcut_best3, rcut_this3;
    reg              run_push3, run_refr3, rf_cut3, rf_end3;
    reg [SPW-1:0]    sp_inc3;
    reg [STK_N-1:0]  uw_h_now3, uw_h_add3, uw_h_mov3, uw_h_col3;   // the highest level of m, one-hot
    reg [SPW-1:0]    uw_l_now3, uw_l_add3, uw_l_mov3, uw_l_col3;   // ... and its number (0: none)
    reg [STK_N-1:0]  uw_c_now3, uw_c_add3, uw_c_mov3, uw_c_col3;
    reg [STK_N*OW-1:0] uw_p_now3, uw_p3;
    reg [STK_N-1:0]  col_shade3, col_mov3, col_push3, col_nsub3, pend_nsub3, pend_cw3;
    reg [STK_N*OW-1:0] pidx_cw3;
    reg [RAW+SW+CALLW-1:0] prn_first3, prn_after3;
    always @(posedge clk) begin
        s3         <= s2;
        h3         <= h2;
        sph_first3 <= first_of(sph_open_first2);
        sph_next3  <= first_of(sph_open_next2);
        pln_first3 <= first_of(pln_pad(pln_open_first2));
        pln_next3  <= first_of(pln_pad(pln_open_next2));
        pln_base3  <= pln_base2;
        obj_bits3  <= obj_bits2;
        cut_best3  <= cutoff && best_bits2[MAT_REFLECTIVE] && room2;
        cut_this3  <= cutoff && this_bits2[MAT_REFLECTIVE] && room2;
        rcut_best3 <= cutoff && best_trn2 && room2;
        rcut_this3 <= cutoff && this_trn2 && room2;
        run_push3  <= best_bits2[MAT_REFLECTIVE] && room2 && !(cutoff && s2[S_CUT]);
        run_refr3  <= best_trn2 && room2 && !(cutoff && s2[S_RCUT]);
        rf_cut3    <= best_trn2 && room2;
        rf_end3    <= s2[S_REFR] && !s2[S_PUSH];
        sp_inc3    <= sp_inc2;
        uw_h_now3  <= highest(uw_m_now2);
        uw_h_add3  <= highest(uw_m_add2);
        uw_h_mov3  <= highest(uw_m_mov2);
        uw_h_col3  <= highest(uw_m_col2);
        uw_l_now3  <= highest_level(uw_m_now2);
        uw_l_add3  <= highest_level(uw_m_add2);
        uw_l_mov3  <= highest_level(uw_m_mov2);
        uw_l_col3  <= highest_level(uw_m_col2);
        uw_c_now3  <= uw_c_now2;
        uw_c_add3  <= uw_c_add2;
        uw_c_mov3  <= uw_c_mov2;
        uw_c_col3  <= uw_c_col2;
        uw_p_now3  <= uw_p_now2;
        uw_p3      <= uw_p2;
        col_shade3 <= col_shade2;
        col_mov3   <= col_mov2;
        col_push3  <= col_push2;
        col_nsub3  <= col_nsub2;
        pend_nsub3 <= pend_nsub2;
        pend_cw3   <= pend_cw2;
        pidx_cw3   <= pidx_cw2;
        prn_first3 <= prn_first2;
        prn_after3 <= prn_after2;
    end

    // ------------------------------------------------------------------------
    // P1c: the unwindings' jumps, the first state of shading, the pushed
    // stack pointer
    // ------------------------------------------------------------------------
    // shade_first (pp_ctrl): cut() for the reflected child, for the
    // refracted one, or SH_OFFSET.
    function [SW-1:0] shade_first(input cut, input rcut);
        shade_first = cut ? `ISA_ST_CUT_W : rcut ? `ISA_ST_RF_CUT_W : `ISA_ST_SH_OFFSET;
    endfunction

    reg [SWD-1:0]    s4;
    reg              h4;
    reg [OW:0]       sph_first4, sph_next4, pln_first4, pln_next4;
    reg [PLN_N-1:0]  pln_base4;
    reg [MB-1:0]     obj_bits4;
    reg [SW-1:0]     first_best4, first_this4;
    reg              run_push4, run_refr4, rf_cut4;
    reg [SPW-1:0]    sp_offset4;
    // now, POP_ADD, POP_MOV, SH_COLOUR (its refracted child first), and
    // shading's end (shade_end: the refracted child first if it is the
    // only child, else now).
    reg [UJW-1:0]    uw_now4, uw_add4, uw_mov4, uw_col4, uw_end4;
    reg [STK_N-1:0]  col_shade4, col_mov4, col_push4, col_nsub4, pend_nsub4, pend_cw4;
    reg [STK_N*OW-1:0] pidx_cw4;
    reg [RAW+SW+CALLW-1:0] prn_first4, prn_after4;
    wire [SPW-1:0]   sp3   = s3[J_SP +: SPW];
    wire [OW-1:0]    oidx3 = s3[S_OIDX +: OW];
    always @(posedge clk) begin
        s4          <= s3;
        h4          <= h3;
        sph_first4  <= sph_first3;
        sph_next4   <= sph_next3;
        pln_first4  <= pln_first3;
        pln_next4   <= pln_next3;
        pln_base4   <= pln_base3;
        obj_bits4   <= obj_bits3;
        first_best4 <= shade_first(cut_best3, rcut_best3);
        first_this4 <= shade_first(cut_this3, rcut_this3);
        run_push4   <= run_push3;
        run_refr4   <= run_refr3;
        rf_cut4     <= rf_cut3;
        sp_offset4  <= (run_push3 || run_refr3) ? sp_inc3 : sp3;
        uw_now4     <= unwound(uw_h_now3, uw_l_now3, uw_c_now3, uw_p_now3, pixel_end, 1'b0, sp3, oidx3);
        uw_add4     <= unwound(uw_h_add3, uw_l_add3, uw_c_add3, uw_p3, pixel_end, 1'b0, sp3, oidx3);
        uw_mov4     <= unwound(uw_h_mov3, uw_l_mov3, uw_c_mov3, uw_p3, pixel_end, 1'b0, sp3, oidx3);
        uw_col4     <= unwound(uw_h_col3, uw_l_col3, uw_c_col3, uw_p3, pixel_end, rf_end3, sp3, oidx3);
        uw_end4     <= unwound(uw_h_now3, uw_l_now3, uw_c_now3, uw_p_now3, pixel_end, rf_end3, sp3, oidx3);
        col_shade4  <= col_shade3;
        col_mov4    <= col_mov3;
        col_push4   <= col_push3;
        col_nsub4   <= col_nsub3;
        pend_nsub4  <= pend_nsub3;
        pend_cw4    <= pend_cw3;
        pidx_cw4    <= pidx_cw3;
        prn_first4  <= prn_first3;
        prn_after4  <= prn_after3;
    end

    // ------------------------------------------------------------------------
    // P2: the jumps (pp_ctrl's), and per state which of them each candidate
    // takes, the candidates' other fields, the condition's code, the latches
    // ------------------------------------------------------------------------
    localparam [OW:0] NONE = {(OW + 1){1'b0}};
    wire [JW-1:0] stay4      = s4[0 +: JW];
    wire [JW-1:0] unwind_j4  = uj_jump(uw_now4, s4[J_CALL +: CALLW]);
    wire [JW-1:0] shade_end4 = uj_jump(uw_end4, s4[J_CALL +: CALLW]);
    wire          chord4     = REFRACTION != 0 && s4[J_CALL +: CALLW] == D_RF_CHORD;
    wire          diff4      = s4[S_DIFF];
    wire          spec4      = s4[S_SPEC];
    wire          push4      = s4[S_PUSH];
    wire          face4      = s4[S_FACE];
    wire          ctx4       = s4[S_CTX];
    wire          found4     = s4[S_FOUND];
    wire          kind4      = s4[J_KIND];
    wire [SW-1:0] st4        = s4[J_ST +: SW];
    wire [CALLW-1:0] call4   = s4[J_CALL +: CALLW];
    wire          in_sph4    = (kind4 == K_SPH);
    wire [OW:0]   after_sph4 = in_sph4 ? sph_next4 : NONE;
    wire [OW:0]   after_pln4 = in_sph4 ? pln_first4 : pln_next4;
    wire [JW-1:0] shd_false4 = shade_next(S_DIFFUSE, 1'b1, diff4, spec4, obj_bits4, push4, stay4, shade_end4);
    wire          prim4      = (call4 == D_PRIMARY);
    wire [LN-1:0] dsign4     = s4[S_DSIGN +: LN];
    wire [LN-1:0] same1_4    = ~(dsign4 ^ {dsign4[0], dsign4[LN-1:1]});
    wire [LN-1:0] same2_4    = ~(dsign4 ^ {dsign4[1:0], dsign4[LN-1:2]});

    // Where a candidate's jump comes from (P3 selects by it).
    localparam integer JSW = 5;
    localparam [JSW-1:0] J_NEXT      = 5'd0,   // stay, st = the code's fixed successor
                         J_NH_AFTER  = 5'd1,
                         J_BOX_FALSE = 5'd2,
                         J_OFFER     = 5'd3,
                         J_SHD_TRUE  = 5'd4,
                         J_SHD_FALSE = 5'd5,
                         J_NH_KEPT   = 5'd6,
                         J_NH_START  = 5'd7,
                         J_DIFF_LIT  = 5'd8,
                         J_DIFF_DARK = 5'd9,
                         J_SPEC_NONE = 5'd10,
                         J_SH_DIFF   = 5'd11,
                         J_SH_REFL   = 5'd12,
                         J_SH_SPEC   = 5'd13,
                         J_UNWIND    = 5'd14,
                         J_PRN_FIRST = 5'd15,
                         J_PRN_AFTER = 5'd16,
                         J_POP_ADD   = 5'd17,
                         J_POP_MOV   = 5'd18,
                         J_COLOUR    = 5'd19,
                         J_SPH_V     = 5'd20,   // SPH_V on sph_first
                         J_PLANE     = 5'd21,   // ISECT_1 on a plane (j inserted at C2)
                         J_OFFSET    = 5'd22,   // SH_POINT, sp after the push
                         J_DOT_SPH   = 5'd23,   // DOT_1, call SPHERE
                         J_DOT_LIGHT = 5'd24,   // DOT_1, call LIGHT
                         J_DOT_RF_IN = 5'd25,   // DOT_1, call RF_IN
                         J_DOT_CHORD = 5'd26,   // DOT_1, call RF_CHORD
                         J_DOT_RF_OUT = 5'd27;  // DOT_1, call RF_OUT

    reg [JSW-1:0]   src0, src1;
    reg [SW-1:0]    nst0, nst1;
    reg [SWD-1:0]   r0, r1;      // the candidates' fields outside the jump (S's, updated)
    reg [LN-1:0]    mn, mp;
    reg             inv;
    reg             ld_dir, ld_facing, ld_cut;
    reg             ns_planes;   // NORM_SCALE: cond = a plane the fresh direction leaves open
    reg             box_corner;  // NORM_SCALE: A0 is BOX_FAR, its corner from the fresh signs
    always @* begin
        src0       = J_NEXT;
        nst0       = st4;
        r0         = s4;
        mn         = {LN{1'b0}};
        mp         = {LN{1'b0}};
        inv        = 1'b0;
        ld_dir     = 1'b0;
        ld_facing  = 1'b0;
        ld_cut     = 1'b0;
        ns_planes  = 1'b0;
        box_corner = 1'b0;
        src1       = J_NEXT;
        nst1       = st4;
        r1         = s4;
        if (!h4) begin
            case (st4)
                `ISA_ST_PRI_ITOF:  nst0 = `ISA_ST_PRI_HALF;
                `ISA_ST_PRI_HALF: begin
                    src0 = J_PRN_FIRST;
                    r0[S_ROT +: RAW] = prn_first4[CALLW + SW +: RAW];
                end
                `ISA_ST_ROT_COS:   nst0 = `ISA_ST_ROT_SIN_U;
                `ISA_ST_ROT_SIN_U: nst0 = `ISA_ST_ROT_SIN_V;
                `ISA_ST_ROT_SIN_V: nst0 = `ISA_ST_ROT_ADD;
                `ISA_ST_ROT_ADD: begin
                    src0 = J_PRN_AFTER;
                    r0[S_ROT +: RAW] = prn_after4[CALLW + SW +: RAW];
                end
                `ISA_ST_DOT_1: nst0 = `ISA_ST_DOT_2;
                `ISA_ST_DOT_2: nst0 = `ISA_ST_DOT_3;
                `ISA_ST_DOT_3:
                    case (call4)
                        D_PRIMARY, D_LIGHT: nst0 = `ISA_ST_NORM_ROOTS;
                        D_SPHERE: begin
                            mn   = M_X;                     // b < 0: the near root may be ahead
                            nst1 = `ISA_ST_SPH_BD;
                            src0 = J_NH_AFTER;
                        end
                        D_DIFFUSE: begin
                            mp = M_X;                       // n.l > 0
                            ld_facing = 1'b1;
                            if (obj_bits4[MAT_DIFFUSE]) nst1 = `ISA_ST_SH_KD;
                            else                        src1 = J_DIFF_LIT;
                            src0 = J_DIFF_DARK;
                        end
                        D_REFLECT:  nst0 = `ISA_ST_SH_REFL_K;
                        D_RF_IN:    if (REFRACTION != 0) nst0 = `ISA_ST_RF_COS2;
                        D_RF_CHORD: if (REFRACTION != 0) nst0 = `ISA_ST_RF_CBD;
                        D_RF_OUT:   if (REFRACTION != 0) nst0 = `ISA_ST_RF_OCOS2;
                        default: begin
                            mp   = M_X;                     // r.l > 0
                            nst1 = `ISA_ST_SH_POW2;
                            src0 = J_SPEC_NONE;
                        end
                    endcase
                `ISA_ST_NORM_ROOTS: nst0 = `ISA_ST_NORM_INV;
                `ISA_ST_NORM_INV:   nst0 = `ISA_ST_NORM_SCALE;
                `ISA_ST_NORM_SCALE: begin
                    ld_dir = 1'b1;
                    r0[S_CTX]   = prim4 ? C_HIT : C_SHD;
                    r0[S_FOUND] = 1'b0;
                    r1[S_CTX]   = prim4 ? C_HIT : C_SHD;
                    r1[S_FOUND] = 1'b0;
                    if (sph_first4[OW]) begin
                        if (bbox) begin
                            nst0       = `ISA_ST_BOX_FAR;
                            box_corner = 1'b1;
                        end else
                            src0 = J_SPH_V;
                    end else if (!prim4 && shortcut)
                        src0 = J_SHD_FALSE;
                    else begin
                        ns_planes = 1'b1;
                        src1      = J_PLANE;
                        src0      = prim4 ? J_UNWIND : J_SHD_FALSE;
                    end
                end
                `ISA_ST_ISECT_1: nst0 = `ISA_ST_ISECT_2;
                `ISA_ST_ISECT_2: nst0 = `ISA_ST_ISECT_3;
                `ISA_ST_ISECT_3: nst0 = `ISA_ST_ISECT_4;
                `ISA_ST_ISECT_4: begin
                    // miss: a sphere's disc < 0; a plane facing away, unless
                    // the fast test decided
                    if (kind4 == K_SPH) mn = M_X;
                    else if (!fast) begin
                        mn  = M_Y;
                        inv = 1'b1;
                    end
                    if (chord4) begin
                        // refract's chord: disc < 0 (rounding) is taken as 0
                        r0[S_RFNEG] = 1'b0;
                        r1[S_RFNEG] = 1'b1;
                        nst1 = `ISA_ST_RF_CS;
                        nst0 = `ISA_ST_RF_CSQRT;
                    end else begin
                        src1 = J_NH_AFTER;
                        nst0 = kind4 == K_SPH ? `ISA_ST_SPH_SQRT : `ISA_ST_PLN_RECIP;
                    end
                end
                `ISA_ST_BOX_FAR: nst0 = `ISA_ST_BOX_BEHIND;
                `ISA_ST_BOX_BEHIND: begin
                    mn   = M_XYZ;
                    src1 = J_BOX_FALSE;
                    nst0 = `ISA_ST_BOX_NEAR;
                end
                `ISA_ST_BOX_NEAR: nst0 = `ISA_ST_BOX_P1;
                `ISA_ST_BOX_P1:   nst0 = `ISA_ST_BOX_Q1;
                `ISA_ST_BOX_Q1:   nst0 = `ISA_ST_BOX_D1;
                `ISA_ST_BOX_D1: begin
                    mp   = same1_4;
                    mn   = ~same1_4;
                    src1 = J_BOX_FALSE;
                    nst0 = `ISA_ST_BOX_P2;
                end
                `ISA_ST_BOX_P2: nst0 = `ISA_ST_BOX_Q2;
                `ISA_ST_BOX_Q2: nst0 = `ISA_ST_BOX_D2;
                `ISA_ST_BOX_D2: begin
                    mp   = same2_4;
                    mn   = ~same2_4;
                    src1 = J_BOX_FALSE;
                    src0 = J_SPH_V;
                end
                `ISA_ST_SPH_V:    src0 = J_DOT_SPH;
                `ISA_ST_SPH_BD:   nst0 = `ISA_ST_SPH_W;
                `ISA_ST_SPH_W:    nst0 = `ISA_ST_ISECT_1;
                `ISA_ST_SPH_SQRT: nst0 = `ISA_ST_SPH_T;
                `ISA_ST_SPH_T: begin
                    mn   = M_X;                             // u < 0: ahead
                    src0 = J_NH_AFTER;
                    if (ctx4 == C_HIT) begin
                        if (!found4) {r1[S_BKIND], r1[S_BIDX +: OW]} = {kind4, s4[J_IDX +: OW]};
                        r1[S_FOUND] = 1'b1;
                        src1 = J_OFFER;
                    end else if (shortcut) begin
                        r1[S_FOUND] = 1'b1;
                        src1 = J_SHD_TRUE;
                    end else
                        nst1 = `ISA_ST_SHD_DIST;
                end
                `ISA_ST_PLN_RECIP: nst0 = `ISA_ST_PLN_T;
                `ISA_ST_PLN_T: begin
                    if (fast) inv = 1'b1;                   // assumed ahead
                    else      mn  = M_X;
                    src0 = J_NH_AFTER;
                    if (ctx4 == C_HIT) begin
                        if (!found4) {r1[S_BKIND], r1[S_BIDX +: OW]} = {kind4, s4[J_IDX +: OW]};
                        r1[S_FOUND] = 1'b1;
                        src1 = J_OFFER;
                    end else
                        nst1 = `ISA_ST_SHD_DIST;
                end
                `ISA_ST_HIT_CMP: begin
                    mp   = M_X;                             // nearer than the best
                    nst1 = `ISA_ST_HIT_KEEP;
                    src0 = J_NH_AFTER;
                end
                `ISA_ST_HIT_KEEP: begin
                    {r0[S_BKIND], r0[S_BIDX +: OW]} = {kind4, s4[J_IDX +: OW]};
                    src0 = J_NH_KEPT;
                end
                `ISA_ST_CUT_W: nst0 = `ISA_ST_CUT_CMP;
                `ISA_ST_CUT_CMP: begin
                    ld_cut = 1'b1;
                    nst0   = rf_cut4 ? `ISA_ST_RF_CUT_W : `ISA_ST_SH_OFFSET;
                end
                `ISA_ST_RF_CUT_W: nst0 = `ISA_ST_RF_CUT_CMP;
                `ISA_ST_RF_CUT_CMP: begin
                    mn   = M_Z;                             // w kt < c: no refracted child
                    r1[S_RCUT] = 1'b1;
                    nst0 = `ISA_ST_SH_OFFSET;
                    nst1 = `ISA_ST_SH_OFFSET;
                end
                `ISA_ST_SHD_DIST: begin
                    mp   = M_X;                             // the blocker is before the light
                    r1[S_FOUND] = 1'b1;
                    src1 = J_SHD_TRUE;
                    src0 = J_NH_AFTER;
                end
                `ISA_ST_SH_OFFSET: begin
                    r0[S_PUSH]       = run_push4;
                    r0[S_REFR]       = run_refr4;
                    r0[S_CUT]        = 1'b0;
                    r0[S_RCUT]       = 1'b0;
                    // the child's level may hold an earlier subtree's colour
                    if (run_push4 || run_refr4) r0[S_COL +: STK_N] = col_push4;
                    r0[S_OKIND]      = s4[S_BKIND];
                    r0[S_OIDX +: OW] = s4[S_BIDX +: OW];
                    r0[S_EXCL]       = 1'b1;
                    r0[S_DIFF]       = 1'b0;
                    r0[S_SPEC]       = 1'b0;
                    r0[S_FACE]       = 1'b0;
                    src0             = J_OFFSET;
                end
                `ISA_ST_SH_POINT:
                    nst0 = s4[S_OKIND] == K_SPH ? `ISA_ST_SH_NORMAL_SUB : `ISA_ST_SH_LIGHT_VEC;
                `ISA_ST_SH_NORMAL_SUB:   nst0 = `ISA_ST_SH_NORMAL_SCALE;
                `ISA_ST_SH_NORMAL_SCALE: nst0 = `ISA_ST_SH_LIGHT_VEC;
                `ISA_ST_SH_LIGHT_VEC:    src0 = J_DOT_LIGHT;
                `ISA_ST_SH_KD: nst0 = `ISA_ST_SH_CL;
                `ISA_ST_SH_CL: nst0 = `ISA_ST_SH_DIFFUSE;
                `ISA_ST_SH_DIFFUSE: begin
                    r0[S_DIFF] = 1'b1;
                    src0 = J_SH_DIFF;
                end
                `ISA_ST_SH_REFL_K: nst0 = `ISA_ST_SH_REFL;
                `ISA_ST_SH_REFL: begin
                    ld_dir = 1'b1;
                    src0   = J_SH_REFL;
                end
                `ISA_ST_SH_POW2:  nst0 = `ISA_ST_SH_POW4;
                `ISA_ST_SH_POW4:  nst0 = `ISA_ST_SH_POW5;
                `ISA_ST_SH_POW5:  nst0 = `ISA_ST_SH_POW10;
                `ISA_ST_SH_POW10: nst0 = `ISA_ST_SH_POW20;
                `ISA_ST_SH_POW20: nst0 = `ISA_ST_SH_KS;
                `ISA_ST_SH_KS:    nst0 = `ISA_ST_SH_SPEC;
                `ISA_ST_SH_SPEC: begin
                    r0[S_SPEC] = 1'b1;
                    src0 = J_SH_SPEC;
                end
                `ISA_ST_SH_LOCAL: nst0 = `ISA_ST_SH_COLOUR;
                `ISA_ST_SH_COLOUR: begin
                    // col[shading_level] = 1: the level below sp when pushing
                    r0[S_COL +: STK_N] = col_shade4;
                    if (push4) nst0 = `ISA_ST_SH_CHILD_W;
                    else       src0 = J_COLOUR;
                end
                `ISA_ST_SH_CHILD_W: begin
                    r0[S_CTX]   = C_HIT;
                    r0[S_FOUND] = 1'b0;
                    // the hit's refracted child waits for this subtree
                    r0[S_PEND +: STK_N]      = pend_cw4;
                    r0[S_PIDX +: STK_N * OW] = pidx_cw4;
                    src0 = J_NH_START;
                end
                // refract: the refracted child of a hit on sphere idx
                `ISA_ST_RF_NSUB: begin
                    r0[S_OKIND]         = K_SPH;
                    r0[S_OIDX +: OW]    = s4[J_IDX +: OW];
                    r0[S_EXCL]          = 1'b1;
                    r0[S_COL +: STK_N]  = col_nsub4;
                    r0[S_PEND +: STK_N] = pend_nsub4;
                    nst0 = `ISA_ST_RF_NSCALE;
                end
                `ISA_ST_RF_NSCALE: src0 = J_DOT_RF_IN;
                `ISA_ST_RF_COS2:   nst0 = `ISA_ST_RF_SIN2;
                `ISA_ST_RF_SIN2:   nst0 = `ISA_ST_RF_ETA1;
                `ISA_ST_RF_ETA1:   nst0 = `ISA_ST_RF_ETA2;
                `ISA_ST_RF_ETA2:   nst0 = `ISA_ST_RF_K;
                `ISA_ST_RF_K: begin
                    mn   = M_X;                             // k < 0: total internal reflection
                    nst1 = `ISA_ST_RF_TIR_K;
                    nst0 = `ISA_ST_RF_SQRT;
                end
                `ISA_ST_RF_SQRT:   nst0 = `ISA_ST_RF_EDN;
                `ISA_ST_RF_EDN:    nst0 = `ISA_ST_RF_COEF;
                `ISA_ST_RF_COEF:   nst0 = `ISA_ST_RF_ED;
                `ISA_ST_RF_ED:     nst0 = `ISA_ST_RF_CN;
                `ISA_ST_RF_CN:     nst0 = `ISA_ST_RF_DIR;
                `ISA_ST_RF_DIR:    nst0 = `ISA_ST_RF_CV;
                `ISA_ST_RF_CV:     src0 = J_DOT_CHORD;
                `ISA_ST_RF_CBD:    nst0 = `ISA_ST_RF_CW;
                `ISA_ST_RF_CW:     nst0 = `ISA_ST_ISECT_1;
                `ISA_ST_RF_CSQRT:  nst0 = `ISA_ST_RF_CS;
                `ISA_ST_RF_CS:     nst0 = `ISA_ST_RF_CST;
                `ISA_ST_RF_CST:    nst0 = `ISA_ST_RF_EXIT;
                `ISA_ST_RF_EXIT:   nst0 = `ISA_ST_RF_OSUB;
                `ISA_ST_RF_OSUB:   nst0 = `ISA_ST_RF_OSCALE;
                `ISA_ST_RF_OSCALE: src0 = J_DOT_RF_OUT;
                `ISA_ST_RF_OCOS2:  nst0 = `ISA_ST_RF_OSIN2;
                `ISA_ST_RF_OSIN2:  nst0 = `ISA_ST_RF_OIOR1;
                `ISA_ST_RF_OIOR1:  nst0 = `ISA_ST_RF_OIOR2;
                `ISA_ST_RF_OIOR2:  nst0 = `ISA_ST_RF_OK;
                `ISA_ST_RF_OK: begin
                    mn   = M_X;                             // k' < 0 (rounding): taken as 0
                    r0[S_RFNEG] = 1'b0;
                    r1[S_RFNEG] = 1'b1;
                    nst0 = `ISA_ST_RF_OEDN;
                    nst1 = `ISA_ST_RF_OEDN;
                end
                `ISA_ST_RF_OEDN:   nst0 = s4[S_RFNEG] ? `ISA_ST_RF_OED : `ISA_ST_RF_OSQRT;
                `ISA_ST_RF_OSQRT:  nst0 = `ISA_ST_RF_OCOEF;
                `ISA_ST_RF_OCOEF:  nst0 = `ISA_ST_RF_OED;
                `ISA_ST_RF_OED:    nst0 = `ISA_ST_RF_OCN;
                `ISA_ST_RF_OCN:    nst0 = `ISA_ST_RF_ODIR;
                `ISA_ST_RF_ODIR: begin
                    ld_dir = 1'b1;
                    nst0   = `ISA_ST_RF_CHILD_W;
                end
                `ISA_ST_RF_TIR_K:  nst0 = `ISA_ST_RF_TIR;
                `ISA_ST_RF_TIR: begin
                    ld_dir = 1'b1;
                    nst0   = `ISA_ST_RF_CHILD_W;
                end
                `ISA_ST_RF_CHILD_W: begin
                    r0[S_CTX]   = C_HIT;
                    r0[S_FOUND] = 1'b0;
                    src0 = J_NH_START;
                end
                `ISA_ST_POP_ADD: src0 = J_POP_ADD;
                `ISA_ST_POP_MOV: begin
                    r0[S_COL +: STK_N] = col_mov4;
                    src0 = J_POP_MOV;
                end
                `ISA_ST_ROOT_BLACK: nst0 = pixel_end;
                `ISA_ST_EXPO_MUL:   nst0 = `ISA_ST_EXPO_EXP;
                `ISA_ST_EXPO_EXP:   nst0 = `ISA_ST_EXPO_SUB;
                `ISA_ST_EXPO_SUB:   nst0 = `ISA_ST_PIX_DONE;
                default:            nst0 = ST_IDLE;
            endcase
        end
    end

    // A jump with st replaced; with {st, sp} replaced.
    function [JW-1:0] with_st(input [JW-1:0] j, input [SW-1:0] st);
        begin
            with_st = j;
            with_st[J_ST +: SW] = st;
        end
    endfunction
    function [JW-1:0] with_st_sp(input [JW-1:0] j, input [SW+SPW-1:0] st_sp);
        begin
            with_st_sp = j;
            {with_st_sp[J_ST +: SW], with_st_sp[J_SP +: SPW]} = st_sp;
        end
    endfunction
    function [JW-1:0] with_prn(input [JW-1:0] j, input [SW+CALLW-1:0] st_call);
        begin
            with_prn = j;
            {with_prn[J_ST +: SW], with_prn[J_CALL +: CALLW]} = st_call;
        end
    endfunction
    function [JW-1:0] with_object(input [JW-1:0] j, input [SW-1:0] st, input kind, input [OW-1:0] idx);
        begin
            with_object = j;
            with_object[J_ST +: SW]  = st;
            with_object[J_KIND]      = kind;
            with_object[J_IDX +: OW] = idx;
        end
    endfunction
    function [JW-1:0] with_call(input [JW-1:0] j, input [SW-1:0] st, input [CALLW-1:0] call);
        begin
            with_call = j;
            with_call[J_ST +: SW]      = st;
            with_call[J_CALL +: CALLW] = call;
        end
    endfunction

    reg [SWD-1:0]   s5;
    reg [JSW-1:0]   src0_5, src1_5;
    reg [SW-1:0]    nst0_5, nst1_5;
    reg [SWD-1:0]   r0_5, r1_5;
    reg [LN-1:0]    mn5, mp5;
    reg             inv5, ld_dir5, ld_facing5, ld_cut5, ns_planes5, box_corner5;
    reg [PLN_N-1:0] pln_open5;
    // The jumps.
    reg [JW-1:0]    j_nh_after5, j_box_false5, j_offer5, j_shd_true5, j_shd_false5, j_nh_kept5,
                    j_nh_start5, j_diff_lit5, j_diff_dark5, j_spec_none5, j_sh_diff5, j_sh_refl5,
                    j_sh_spec5, j_unwind5, j_prn_first5, j_prn_after5, j_pop_add5, j_pop_mov5,
                    j_colour5, j_sph_v5, j_plane5, j_offset5, j_dot_sph5, j_dot_light5,
                    j_dot_rf_in5, j_dot_chord5, j_dot_rf_out5;
    always @(posedge clk) begin
        s5          <= s4;
        src0_5      <= src0;
        src1_5      <= src1;
        nst0_5      <= nst0;
        nst1_5      <= nst1;
        r0_5        <= r0;
        r1_5        <= r1;
        mn5         <= mn;
        mp5         <= mp;
        inv5        <= inv;
        ld_dir5     <= ld_dir;
        ld_facing5  <= ld_facing;
        ld_cut5     <= ld_cut;
        ns_planes5  <= ns_planes;
        box_corner5 <= box_corner;
        pln_open5   <= pln_base4;
        j_nh_after5  <= nearest_hit_next(stay4, 1'b0, after_sph4, in_sph4, after_pln4, ctx4,
                                         found4, shortcut, first_best4, shd_false4, unwind_j4);
        j_box_false5 <= nearest_hit_next(stay4, 1'b0, NONE, 1'b1, pln_first4, ctx4,
                                         found4, shortcut, first_best4, shd_false4, unwind_j4);
        // offer: the first hit stays in the search; a later one is compared.
        j_offer5     <= found4 ? with_st(stay4, `ISA_ST_HIT_CMP)
                               : nearest_hit_next(stay4, 1'b0, after_sph4, in_sph4, after_pln4, ctx4,
                                                  1'b1, shortcut, first_this4, shd_false4, unwind_j4);
        j_shd_true5  <= shade_next(S_DIFFUSE, 1'b0, diff4, spec4, obj_bits4, push4, stay4, shade_end4);
        j_shd_false5 <= shd_false4;
        j_nh_kept5   <= nearest_hit_next(stay4, 1'b0, after_sph4, in_sph4, after_pln4, ctx4,
                                         found4, shortcut, first_this4, shd_false4, unwind_j4);
        j_nh_start5  <= nearest_hit_next(stay4, bbox, sph_first4, 1'b1, pln_first4, C_HIT,
                                         1'b0, shortcut, first_best4, shd_false4, unwind_j4);
        j_diff_lit5  <= shade_next(S_REFLECT, 1'b1, diff4, spec4, obj_bits4, push4, stay4, shade_end4);
        j_diff_dark5 <= shade_next(S_REFLECT, 1'b0, diff4, spec4, obj_bits4, push4, stay4, shade_end4);
        j_spec_none5 <= shade_next(S_LOCAL, face4, diff4, spec4, obj_bits4, push4, stay4, shade_end4);
        j_sh_diff5   <= shade_next(S_REFLECT, face4, 1'b1, spec4, obj_bits4, push4, stay4, shade_end4);
        j_sh_refl5   <= shade_next(S_SPECULAR, face4, diff4, spec4, obj_bits4, push4, stay4, shade_end4);
        j_sh_spec5   <= shade_next(S_LOCAL, face4, diff4, 1'b1, obj_bits4, push4, stay4, shade_end4);
        j_unwind5    <= unwind_j4;
        j_prn_first5 <= with_prn(stay4, prn_first4[0 +: SW + CALLW]);
        j_prn_after5 <= with_prn(stay4, prn_after4[0 +: SW + CALLW]);
        j_pop_add5   <= uj_jump(uw_add4, call4);
        j_pop_mov5   <= uj_jump(uw_mov4, call4);
        j_colour5    <= uj_jump(uw_col4, call4);
        j_sph_v5     <= with_object(stay4, `ISA_ST_SPH_V, K_SPH, sph_first4[OW-1:0]);
        j_plane5     <= with_object(stay4, `ISA_ST_ISECT_1, K_PLN, {OW{1'b0}});
        j_offset5    <= with_st_sp(stay4, {ST_SH_POINT, sp_offset4});
        j_dot_sph5   <= with_call(stay4, `ISA_ST_DOT_1, D_SPHERE);
        j_dot_light5 <= with_call(stay4, `ISA_ST_DOT_1, D_LIGHT);
        // (Without refraction no code selects these: 0, none of its logic.)
        j_dot_rf_in5 <= REFRACTION != 0 ? with_call(stay4, `ISA_ST_DOT_1, D_RF_IN) : {JW{1'b0}};
        j_dot_chord5 <= REFRACTION != 0 ? with_call(stay4, `ISA_ST_DOT_1, D_RF_CHORD) : {JW{1'b0}};
        j_dot_rf_out5 <= REFRACTION != 0 ? with_call(stay4, `ISA_ST_DOT_1, D_RF_OUT) : {JW{1'b0}};
    end
    wire unused_next4 = ^{sph_next4[OW], pln_next4[OW]};

    // ------------------------------------------------------------------------
    // P3: the candidates: their jumps selected
    // ------------------------------------------------------------------------
    // An AND-OR over the codes: indexing js by JW * src would put an adder
    // in the path.
    function [JW-1:0] jump_of(input [JSW-1:0] src, input [SW-1:0] nst, input [JW-1:0] stay_j,
                              input [28*JW-1:0] js);
        integer k;
        begin
            jump_of = src == J_NEXT ? with_st(stay_j, nst) : {JW{1'b0}};
            for (k = 1; k < 28; k = k + 1)
                jump_of = jump_of | ({JW{src == k[JSW-1:0]}} & js[JW*k +: JW]);
        end
    endfunction
    wire [28*JW-1:0] jumps5 = {j_dot_rf_out5, j_dot_chord5, j_dot_rf_in5, j_dot_light5, j_dot_sph5, j_offset5, j_plane5, j_sph_v5, j_colour5,
                               j_pop_mov5, j_pop_add5, j_prn_after5, j_prn_first5, j_unwind5,
                               j_sh_spec5, j_sh_refl5, j_sh_diff5, j_spec_none5, j_diff_dark5,
                               j_diff_lit5, j_nh_start5, j_nh_kept5, j_shd_false5, j_shd_true5,
                               j_offer5, j_box_false5, j_nh_after5, {JW{1'b0}}};

    // Without refraction the candidates' refraction fields are 0, and so
    // is every copy of them around the ring: none of its logic.
    localparam [SWD-1:0] RF_KEEP = REFRACTION != 0 ? {SWD{1'b1}}
                                                   : {{(SWD - S_REFR){1'b0}}, {S_REFR{1'b1}}};
    reg [SWD-1:0]   a0_c, a1_c;
    reg [LN-1:0]    mn_c, mp_c;
    reg             inv_c, ld_dir_c, ld_facing_c, ld_cut_c, ns_planes_c, box_corner_c;
    reg [PLN_N-1:0] pln_open_c;
    always @(posedge clk) begin
        a0_c         <= RF_KEEP & {r0_5[SWD-1:JW], jump_of(src0_5, nst0_5, s5[0 +: JW], jumps5)};
        a1_c         <= RF_KEEP & {r1_5[SWD-1:JW], jump_of(src1_5, nst1_5, s5[0 +: JW], jumps5)};
        mn_c         <= mn5;
        mp_c         <= mp5;
        inv_c        <= inv5;
        ld_dir_c     <= ld_dir5;
        ld_facing_c  <= ld_facing5;
        ld_cut_c     <= ld_cut5;
        ns_planes_c  <= ns_planes5;
        box_corner_c <= box_corner5;
        pln_open_c   <= pln_open5;
    end
    wire unused_r_jumps = ^{r0_5[JW-1:0], r1_5[JW-1:0], s5[SWD-1:JW]};

    // ------------------------------------------------------------------------
    // P4a1, P4a2, P4b, P5: the candidates' micro-ops, then their physical
    // addresses
    // ------------------------------------------------------------------------
    localparam integer CODE_W = 2 * LN + 6 + PLN_N;   // mn, mp, inv, latches, ns, box, open
    wire [CODE_W-1:0] code_c = {mn_c, mp_c, inv_c, ld_dir_c, ld_facing_c, ld_cut_c, ns_planes_c,
                                box_corner_c, pln_open_c};

    reg [SWD-1:0]    a0_e, a1_e;
    reg [PLVW-1:0]   plan0_e, plan1_e;
    reg [CODE_W-1:0] code_e;
    always @(posedge clk) begin
        a0_e    <= a0_c;
        a1_e    <= a1_c;
        plan0_e <= plan(a0_c[J_ST +: SW]);
        plan1_e <= plan(a1_c[J_ST +: SW]);
        code_e  <= code_c;
    end

    reg [SWD-1:0]    a0_d, a1_d;
    reg [PLW-1:0]    plan0_d, plan1_d;
    reg [SRCW-1:0]   opd0_d, opd1_d;
    reg [CODE_W-1:0] code_d;
    always @(posedge clk) begin
        a0_d    <= a0_e;
        a1_d    <= a1_e;
        plan0_d <= with_variant(plan0_e, a0_e[J_CALL +: CALLW], a0_e[S_ROT +: RAW], a0_e[S_RFNEG]);
        plan1_d <= with_variant(plan1_e, a1_e[J_CALL +: CALLW], a1_e[S_ROT +: RAW], a1_e[S_RFNEG]);
        opd0_d  <= operands(a0_e);
        opd1_d  <= operands(a1_e);
        code_d  <= code_e;
    end

    reg [SWD-1:0]    a0_u, a1_u;
    reg [UW-1:0]     l0_u, l1_u;
    reg [CODE_W-1:0] code_u;
    always @(posedge clk) begin
        a0_u   <= a0_d;
        a1_u   <= a1_d;
        l0_u   <= micro_op(plan0_d, opd0_d);
        l1_u   <= micro_op(plan1_d, opd1_d);
        code_u <= code_d;
    end

    wire [RW-1:0] p0_a, p0_b, p0_w, p1_a, p1_b, p1_w;
    mem_ctrl #(.STACK_DEPTH(STACK_DEPTH)) u_map0 (
        .sp   (a0_u[J_SP +: SPW]),
        .la_a (l0_u[U_A +: RW]),
        .la_b (l0_u[U_B +: RW]),
        .la_w (l0_u[U_W +: RW]),
        .pa_a (p0_a),
        .pa_b (p0_b),
        .pa_w (p0_w)
    );
    mem_ctrl #(.STACK_DEPTH(STACK_DEPTH)) u_map1 (
        .sp   (a1_u[J_SP +: SPW]),
        .la_a (l1_u[U_A +: RW]),
        .la_b (l1_u[U_B +: RW]),
        .la_w (l1_u[U_W +: RW]),
        .pa_a (p1_a),
        .pa_b (p1_b),
        .pa_w (p1_w)
    );

    localparam integer BW = 2 * SWD + 2 * UW + CODE_W;   // the bundle carried to C1
    reg [BW-1:0] b_p;
    always @(posedge clk)
        b_p <= {a0_u, a1_u,
               l0_u[U_OP +: OPW], p0_a, p0_b, p0_w, l0_u[U_MASK +: LN],
               l1_u[U_OP +: OPW], p1_a, p1_b, p1_w, l1_u[U_MASK +: LN],
               code_u};

    // ------------------------------------------------------------------------
    // Carried to C1 (positions 11 .. LAT+2)
    // ------------------------------------------------------------------------
    wire [BW-1:0] bc;
    fast_delay #(.WIDTH(BW), .STAGES(CARRY1)) u_carry1 (.clk(clk), .d(b_p), .q(bc));

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
        open_c2 <= c_open & planes_facing(fast, pln_sel_q, y_neg, y_pos);
    end

    // ------------------------------------------------------------------------
    // C2: NORM_SCALE's plane, the choice
    // ------------------------------------------------------------------------
    wire [OW:0]    plane_c2 = first_of(pln_pad(open_c2));
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

`ifdef PP_COVER
    // ------------------------------------------------------------------------
    // Coverage build only (cargo feature `coverage`, never for synthesis): a
    // cover point per state and per possible transition of a context, turn
    // to turn, made by build.rs from rtl/cover/pp_ctrl.transitions and
    // rtl/cover/fast_ctrl.transitions.
    // ------------------------------------------------------------------------
    fast_ctrl_cover #(.SW(SW), .CTX_BITS(CTX_BITS)) u_cover (
        .clk(clk), .rst_n(rst_n), .sweeping(initial_sweep), .turn_ctx(turn_q), .st(st0));
`endif

    // Static checks: the round trip fits the ring; the address placements
    // above hold for isa.vh's layout; the operand codes fill their fields
    // (micro_op's a_of and b_of).
    localparam integer SPH_LAST = `ISA_REG_SPH0_C + (SPH_N - 1) * `ISA_DIM_SPH_STRIDE;
    localparam integer PLN_LAST = `ISA_REG_PLN0_N + (PLN_N - 1) * `ISA_DIM_PLN_STRIDE;
    generate
        if (`ISA_DIM_SPH_STRIDE != 4 || `ISA_DIM_PLN_STRIDE != 4 || (`ISA_REG_SPH0_C % 32) != 0 ||
            (`ISA_REG_PLN0_N % 32) != 0 || SPH_LAST >= `ISA_REG_SPH0_C + 32 ||
            PLN_LAST >= `ISA_REG_PLN0_N + 32 || `ISA_DIM_TRN_STRIDE != 1 ||
            (`ISA_REG_TRN0 % (1 << OW)) != 0 || `ISA_DIM_TRN_COUNT > (1 << OW) ||
            A_N != (1 << SELW) || B_N != (1 << SELW)) begin : g_layout_not_placeable
            isa_layout_breaks_fast_ctrl_address_placement u_error ();
        end
    endgenerate

    generate
        if (CARRY2 < 0 || CARRY1 < 1) begin : g_ring_too_short
            ring_too_short_for_the_alu_latency u_error ();
        end
    endgenerate

endmodule
`default_nettype wire
