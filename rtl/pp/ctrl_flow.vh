// The control flow's pure functions, one text for both controllers:
// included inside pp_ctrl (rtl/pp/pp_ctrl.v) and fast_ctrl
// (rtl/fast/fast_ctrl.v), which give them the same localparams (the state
// word's fields J_ST, J_CALL, J_KIND, J_IDX and widths JW, SW, CALLW, OW,
// RAW, MB; object kinds K_SPH, K_PLN; contexts C_SHD; calls D_*; shading
// terms S_*; material bits MAT_*; SPH_N, PLN_N, ROT_N) and isa.vh's state
// ids. Each reads only its arguments and those constants; their spec is
// golden::micro::program.
//
// No include guard: each controller module includes it once, and a guard
// would leave the second module of one compilation without its functions.

    // Material bits of object (kind, idx) (program.rs bits).
    function [MB-1:0] bits(input kind, input [OW-1:0] idx, input [SPH_N*MB-1:0] sph,
                           input [PLN_N*MB-1:0] pln);
        bits = kind == K_SPH ? sph[MB*idx +: MB] : pln[MB*idx +: MB];
    endfunction

    // shade, from the term `from` on (n.l and diffuse, reflected direction,
    // specular, local colour): the next term the object's bits and `lit`
    // call for, else the colour, the child's weight, or the unwinding.
    // Before n.l (from S_DIFFUSE), `lit` is !shadowed; after it, the light
    // reaches the surface: lit and n.l > 0 (facing_q).
    function [JW-1:0] shade_next(input [1:0] from, input lit, input diff, input spec,
                                 input [MB-1:0] mat, input push, input [JW-1:0] stay_j,
                                 input [JW-1:0] unwind_j);
        begin
            shade_next = stay_j;
            // n.l, once for both terms: both are gated on n.l > 0.
            if (from <= S_DIFFUSE && lit && (mat[MAT_DIFFUSE] || mat[MAT_SPECULAR])) begin
                shade_next[J_ST +: SW]      = `ISA_ST_DOT_1;
                shade_next[J_CALL +: CALLW] = D_DIFFUSE;
            end
            // r = d - 2 (d.n) n if a child is pushed or the specular term needs it.
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

    // nearest_hit, shadowed: the next object of the search, else its end.
    // `sph` is the next sphere ({0, x} once the sphere loop is over) and
    // `box` tests the bounding box before it; leaving the spheres, the shadow
    // shortcut ends a shadow search; `pln` is the next plane. At the end,
    // shadowed returns false, nearest_hit its hit (shade it, from
    // `shade_st`: cut() first, or SH_OFFSET) or none.
    function [JW-1:0] nearest_hit_next(input [JW-1:0] stay_j, input box, input [OW:0] sph,
                                       input leaving_spheres, input [OW:0] pln, input ctx,
                                       input found, input shortcut_on, input [SW-1:0] shade_st,
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
                nearest_hit_next[J_ST +: SW] = shade_st;
            else
                nearest_hit_next = unwind_j;
        end
    endfunction

    // primary_ray: the next rotation at or after axis `from` that the scene
    // applies, else normalize: the next {rot, st, call}.
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

    // The state a controller decodes: st, or, in a build without
    // refraction (refraction = 0), no state (ISA_DIM_ST_NONE, below 128 as
    // every id is) for a refraction state (the ids from ISA_ST_RF_NSUB up):
    // their arms are then none of its logic, nor is anything only they reach.
    function [SW-1:0] decoded_st(input [SW-1:0] st, input refraction);
        decoded_st = (refraction || st < `ISA_ST_RF_NSUB) ? st : `ISA_DIM_ST_NONE;
    endfunction
