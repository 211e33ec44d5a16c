// ============================================================================
// isa.vh -- the pixel processor's instruction set: the single source of truth
// ============================================================================
// ALU opcodes, register-file addresses and controller FSM state ids, shared
// by the Verilog pixel processor and the golden micro-op model: golden's
// build.rs parses this file into golden::micro::isa (op, reg, state, dim and
// the name tables), and a golden test re-reads it to catch drift.
//
// Grammar (build.rs refuses anything else, naming file:line):
//   `define ISA_OP_<NAME>  <decimal>   ALU opcode           (ISA_DIM_OP_BITS wide)
//   `define ISA_REG_<NAME> <decimal>   register address     (ISA_DIM_REG_BITS wide)
//   `define ISA_ST_<NAME>  <decimal>   controller FSM state (ISA_DIM_ST_BITS wide)
//   `define ISA_DIM_<NAME> <decimal>   a size, width, count or stride (not a code)
// one per line, an optional trailing // comment, codes unique within a kind.
//
// Register arrays: a pair ISA_DIM_<G>_COUNT / ISA_DIM_<G>_STRIDE declares
// group <G>; the ISA_REG_<G>0... names are element 0, and element k of
// register <G>0<rest> lives at ISA_REG_<G>0<rest> + k * ISA_DIM_<G>_STRIDE
// and is named <G>k<rest> (SPH0_C -> SPH3_C at 0 + 3*4 = 12).
//
// Operands: A = read port 1, B = read port 2 (vector registers, 3 float32
// lanes x, y, z), F = the ALU's internal vector register (thesis 4.2, eq. 30).
// Y = the destination register; only the lanes in the instruction's 3-bit
// lane mask (bit 0 = x) are written. Every operation is IEEE-754 binary32,
// round to nearest even, one rounding per operation, lanes independent.
// The controller may branch on the sign, zero-ness and NaN-ness of any lane
// of the value written in the same cycle (combinational flags, thesis 4.2).
// ============================================================================
`ifndef ISA_VH
`define ISA_VH

// ---------------------------------------------------------------------------
// Widths
// ---------------------------------------------------------------------------
`define ISA_DIM_OP_BITS 6    // opcode field
`define ISA_DIM_REG_BITS 8   // register address (256 vector registers; 136 named)
`define ISA_DIM_ST_BITS 9    // controller FSM state id
`define ISA_DIM_ST_NONE 1    // an id no state has, below 128: a controller without refraction decodes the RF_* ids as it (ctrl_flow.vh)
`define ISA_DIM_COORD_BITS 12  // pixel coordinates px, py (images up to 4096 x 4096)
`define ISA_DIM_LANES 3        // lanes of a vector register (x, y, z: one float32 each) and of a lane mask

// ---------------------------------------------------------------------------
// ALU opcodes. Single-cycle unless noted.
// ---------------------------------------------------------------------------
`define ISA_OP_NOP 0      // no operation, no write (start, done and idle cycles)
`define ISA_OP_ADD 1      // Y = A + B
`define ISA_OP_SUB 2      // Y = A - B
`define ISA_OP_MUL 4      // Y = A * B, componentwise
`define ISA_OP_NMUL 5     // Y = -(A * B)
`define ISA_OP_MULX 6     // Y = A * <B.x, B.x, B.x>
`define ISA_OP_MULY 7     // Y = A * <B.y, B.y, B.y>
`define ISA_OP_MULZ 8     // Y = A * <B.z, B.z, B.z>
`define ISA_OP_NMULX 9    // Y = -(A * <B.x, B.x, B.x>)
`define ISA_OP_MULR1 10   // Y = A * <B.y, B.z, B.x> (B rotated one lane)
`define ISA_OP_MULR2 11   // Y = A * <B.z, B.x, B.y> (B rotated two lanes)
`define ISA_OP_MUL2X 3    // Y = p + p, p = A * <B.x, B.x, B.x>: the product doubled (exact)
`define ISA_OP_MOV 12     // Y = A
`define ISA_OP_NEG 13     // Y = -A (sign flip, exact)
`define ISA_OP_ITOF 14    // Y = int-to-float of the controller's <px, -py, 0>
`define ISA_OP_DOT1 16    // F = A * B                      (dot product, cycle 1)
`define ISA_OP_DOT2 17    // F.x = F.x + F.y                (cycle 2)
`define ISA_OP_DOT3 18    // Y.x = F.x + F.z                (cycle 3: Y.x = A.B)
`define ISA_OP_ISECT1 20  // F = -(A * B)                   [A = b, B = c]
`define ISA_OP_ISECT2 21  // Y = A * B [A = d, B = c]; F = <F.x + F.y, F.y, F.z>
`define ISA_OP_ISECT3 22  // F = <A.x + A.y, F.x + F.z, A.z> [A = g, ISECT2's Y]
`define ISA_OP_ISECT4 23  // Y = F = <A.x + F.y, F.x + F.z, 0> [A.x = a]
`define ISA_OP_RECIP 24   // Y.x = 1 / A.x; multi-cycle: fp_recip latency + 1
`define ISA_OP_RECIPY 25  // Y.x = 1 / A.y; multi-cycle: fp_recip latency + 1
`define ISA_OP_SQRT 26    // Y.x = sqrt(A.x); multi-cycle: fp_sqrt latency + 1
`define ISA_OP_ROOTS 27   // Y.x = sqrt(A.x), Y.y = 1 / A.x: fp_sqrt and fp_recip at once;
                          // multi-cycle: max(fp_sqrt, fp_recip latency) + 1
`define ISA_OP_EXP 28     // Y = e^A, every lane (three fp_exp units at once); multi-cycle: fp_exp latency + 1

// ---------------------------------------------------------------------------
// Register file (7-bit addresses). Scene registers are written once per
// scene through the scene port and only read by the controller.
// ---------------------------------------------------------------------------
// Spheres k = 0..7 at 0 + 4k.
`define ISA_DIM_SPH_COUNT 8
`define ISA_DIM_SPH_STRIDE 4
`define ISA_REG_SPH0_C 0       // centre
`define ISA_REG_SPH0_R 1       // <r*r, 1/r, c> (scene.derived: radius_sq, inv_radius; c = render.weight_cutoff)
`define ISA_REG_SPH0_COL 2     // colour
`define ISA_REG_SPH0_MAT 3     // <kd, ks, kr>: diffuse, specular, reflection
// Planes p = 0..5 at 32 + 4p.
`define ISA_DIM_PLN_COUNT 6
`define ISA_DIM_PLN_STRIDE 4
`define ISA_REG_PLN0_N 32      // normal: facing * unit(axis), +0 elsewhere
`define ISA_REG_PLN0_Q 33      // <facing * offset, 0, c>: n.p = q on the plane; c = render.weight_cutoff
`define ISA_REG_PLN0_COL 34    // colour
`define ISA_REG_PLN0_MAT 35    // <kd, ks, kr>
// Lane z of every object's SPHk_R / PLNj_Q (no instruction reads it
// otherwise) holds the scene's weight cutoff c: CUT_CMP compares the child
// weight with the hit object's copy, so the cutoff needs no register address.
// Light and camera.
`define ISA_REG_LIGHT_POS 56   // light position
`define ISA_REG_LIGHT_COL 57   // light colour
`define ISA_REG_EYE 58         // origin of every primary ray
`define ISA_REG_CAM_HALF 59    // <-width/2, height/2, distance>
// Camera rotation about axis a = 0 (x), 1 (y), 2 (z) at 60 + 2a; with
// u = a+1, v = a+2 (mod 3), (c, s) = cos, sin of the angle (scene.derived):
`define ISA_DIM_ROT_COUNT 3
`define ISA_DIM_ROT_STRIDE 2
`define ISA_REG_ROT0_C 60      // lane a: 1, lanes u, v: c
`define ISA_REG_ROT0_S 61      // lane a: 0, lane u: -s, lane v: s (ROT0_S lane x: the exposure, below)
// Lane a of ROTa_S is never read by a write (ROT_SIN_U/V write lanes u and
// v only), so lane x of ROT0_S holds the scene's exposure (render.exposure,
// 0 when off): EXPO_MUL multiplies the pixel's colour by it (MULX).
// Bounding box corners k = 0..7 at 66 + k: lane i is the box maximum if bit i
// of k is set, else the minimum (BOX0 = minimum, BOX7 = maximum corner).
`define ISA_DIM_BOX_COUNT 8
`define ISA_DIM_BOX_STRIDE 1
`define ISA_REG_BOX0 66        // corner k (scene.derived: bbox_min, bbox_max)
// Constants.
`define ISA_REG_ZERO 74        // <0, 0, 0>
`define ISA_REG_ONE 75         // <1, 1, 1>

// Temporaries (the golden model's pixel program names their roles).
`define ISA_REG_T0 76
`define ISA_REG_T1 77
`define ISA_REG_T2 78
`define ISA_REG_T3 79
`define ISA_REG_T4 80
`define ISA_REG_T5 81
`define ISA_REG_T6 82
`define ISA_REG_T7 83
`define ISA_REG_T8 84
`define ISA_REG_T9 85
`define ISA_REG_T10 86
`define ISA_REG_T11 87

// Ray stack, addressed by the controller only through the stack pointer sp:
// the memory controller maps CUR_<f> to STK<sp>_<f> and PAR_<f> to
// STK<sp-1>_<f>, i.e. address STK0_O + level * STK_STRIDE + field. Writes
// (and trace events) carry the decoded STK address, never CUR/PAR. The
// root ray's origin and weight are constants: STK0_O decodes to EYE and
// STK0_W to ONE.
`define ISA_REG_CUR_O 88       // current ray: origin
`define ISA_REG_CUR_D 89       // current ray: unit direction
`define ISA_REG_CUR_COL 90     // current ray: colour gathered so far
`define ISA_REG_CUR_W 91       // current ray: weight <w, w, w>, w = product of the ancestors' kr
`define ISA_REG_PAR_O 92       // parent ray: origin
`define ISA_REG_PAR_D 93       // parent ray: direction
`define ISA_REG_PAR_COL 94     // parent ray: colour
`define ISA_REG_PAR_W 95       // parent ray: weight
// Stack levels l = 0..7 at 96 + 4l; STK0_COL is the pixel's colour when done.
`define ISA_DIM_STK_COUNT 8
`define ISA_DIM_STK_STRIDE 4
`define ISA_REG_STK0_O 96
`define ISA_REG_STK0_D 97
`define ISA_REG_STK0_COL 98
`define ISA_REG_STK0_W 99
// Transparent spheres k = 0..7 at 128 + k (refraction): what the refracted
// child reads of sphere k. Written only for a scene with a transparent
// sphere (ISA_DIM_CFG_TRN_LSB).
`define ISA_DIM_TRN_COUNT 8
`define ISA_DIM_TRN_STRIDE 1
`define ISA_REG_TRN0 128       // <1/ior, ior, kt>: the index ratios in and out, the transmission

// ---------------------------------------------------------------------------
// The configuration word: the controller's per-scene switches and counts
// (golden::micro::loader::Config), written through the scene port with
// scene_cfg = 1 as one 96-bit value (lane x = bits 31:0). Bit offsets:
// ---------------------------------------------------------------------------
`define ISA_DIM_CFG_SPHERES_LSB 0    // ISA_DIM_CFG_SPHERES_BITS bits: spheres in the scene (0..8)
`define ISA_DIM_CFG_SPHERES_BITS 4  // width of the sphere count
`define ISA_DIM_CFG_PLANES_LSB 4     // ISA_DIM_CFG_PLANES_BITS bits: planes (0..6)
`define ISA_DIM_CFG_PLANES_BITS 3   // width of the plane count
`define ISA_DIM_CFG_DEPTH_LSB 8      // ISA_DIM_CFG_DEPTH_BITS bits: stack levels used (1..8)
`define ISA_DIM_CFG_DEPTH_BITS 4    // width of the stack depth
`define ISA_DIM_CFG_BBOX_LSB 12      // 1 bit: bounding box test (thesis 3.10.1)
`define ISA_DIM_CFG_FAST_PLANE_LSB 13  // 1 bit: fast plane test (3.10.2)
`define ISA_DIM_CFG_SHORTCUT_LSB 14  // 1 bit: shadow shortcut (3.10.3)
`define ISA_DIM_CFG_CUTOFF_LSB 15    // 1 bit: weight cutoff (3.8, end): CUT_W, CUT_CMP before a push
`define ISA_DIM_CFG_ROTATE_LSB 16    // ISA_DIM_ROT_COUNT bits: rotate the primary ray about x, y, z
`define ISA_DIM_CFG_EXPOSURE_LSB 19  // 1 bit: exposure (thesis 3.7): EXPO_MUL, EXPO_EXP, EXPO_SUB before PIX_DONE
`define ISA_DIM_CFG_TRN_LSB 20       // 1 bit per sphere k at + k: transparent (transmission > 0): a refracted child
`define ISA_DIM_CFG_SPH_BITS_LSB 32  // ISA_DIM_CFG_MAT_BITS per sphere k at + MAT_BITS * k
`define ISA_DIM_CFG_PLN_BITS_LSB 56  // ISA_DIM_CFG_MAT_BITS per plane j at + MAT_BITS * j
`define ISA_DIM_CFG_MAT_BITS 3       // an object's material bits: diffuse (bit 0), specular, reflective
`define ISA_DIM_CFG_PLN_AXIS_LSB 74  // ISA_DIM_CFG_AXIS_BITS per plane j at + AXIS_BITS * j: its axis (0 = x)
`define ISA_DIM_CFG_AXIS_BITS 2     // width of a plane's axis
`define ISA_DIM_CFG_PLN_NEG_LSB 86   // 1 bit per plane j at + j: facing is -1

// ---------------------------------------------------------------------------
// Controller FSM states (9-bit ids). A multi-cycle instruction stays in its
// state until out_valid; its write is reported with that state's id.
// ---------------------------------------------------------------------------
`define ISA_ST_IDLE 0             // wait for a pixel (not counted); start: latch px, py, sp = 0
`define ISA_ST_PIX_DONE 2         // raise done; STK0_COL holds the pixel (the done cycle)
// Primary ray.
`define ISA_ST_PRI_ITOF 10        // T = itof(<px, -py, 0>)
`define ISA_ST_PRI_HALF 11        // T = T + CAM_HALF: camera-space direction
`define ISA_ST_ROT_COS 12         // rotation about a: C = T * ROTa_C
`define ISA_ST_ROT_SIN_U 13       //   S.u = ROTa_S.u * T.v (MULR1, lane u)
`define ISA_ST_ROT_SIN_V 14       //   S.v = ROTa_S.v * T.u (MULR2, lane v)
`define ISA_ST_ROT_ADD 15         //   T.uv = C + S
// Sub-machines: dot product and normalize.
`define ISA_ST_DOT_1 20           // F = A * B
`define ISA_ST_DOT_2 21           // F.x = F.x + F.y
`define ISA_ST_DOT_3 22           // Y.x = F.x + F.z
`define ISA_ST_NORM_ROOTS 23      // LEN = <|v| = sqrt(v.v), 1/(v.v)> (ROOTS)
`define ISA_ST_NORM_INV 24        // INV.x = |v| * 1/(v.v) = 1/|v|
`define ISA_ST_NORM_SCALE 25      // v * 1/|v|; latches the direction's sign flags
// Sub-machine: the shared intersection sub-graph (thesis eq. 29, 30):
// spheres (b = c = w, a = r*r) and planes (b = o, c = n, a = q).
`define ISA_ST_ISECT_1 26
`define ISA_ST_ISECT_2 27
`define ISA_ST_ISECT_3 28
`define ISA_ST_ISECT_4 29
// Bounding box slab test (thesis 3.10.1).
`define ISA_ST_BOX_FAR 31         // far-corner offsets  F = BOX(~s) - o (first)
`define ISA_ST_BOX_BEHIND 32      // F * d: a negative lane = box behind the ray
`define ISA_ST_BOX_NEAR 30        // near-corner offsets N = BOX(s) - o
`define ISA_ST_BOX_P1 33          // N * rot1(d)
`define ISA_ST_BOX_Q1 34          // d * rot1(F)
`define ISA_ST_BOX_D1 35          // entry i vs exit i+1
`define ISA_ST_BOX_P2 36          // N * rot2(d)
`define ISA_ST_BOX_Q2 37          // d * rot2(F)
`define ISA_ST_BOX_D2 38          // entry i vs exit i+2
// Sphere and plane tests.
`define ISA_ST_SPH_V 40            // v = o - c (then b = v.d by DOT; b >= 0 ends the test)
`define ISA_ST_SPH_BD 41           // -b d
`define ISA_ST_SPH_W 42            // w = v - b d (then disc = r*r - w.w by ISECT)
`define ISA_ST_SPH_SQRT 43         // sqrt(disc)
`define ISA_ST_SPH_T 44            // u = sqrt(disc) + b = -t
`define ISA_ST_PLN_RECIP 45        // 1 / (n.d)
`define ISA_ST_PLN_T 46            // u = -((q - n.o) * 1/(n.d)) = -t
`define ISA_ST_HIT_CMP 47          // u - u_best > 0: nearer than the best so far
`define ISA_ST_HIT_KEEP 48         // u_best = u
`define ISA_ST_SHD_DIST 49         // shadow ray: dist + u > 0: blocker before the light
// Weight cutoff (with ISA_DIM_CFG_CUTOFF_LSB set, before shading a hit that
// would push a reflected ray): no child whose weight w * kr < c.
`define ISA_ST_CUT_W 50            // U.z = CUR_W.z * kr: the child's weight (SH_CHILD_W's product)
`define ISA_ST_CUT_CMP 51          // G.z = U.z - c (hit object's R/Q lane z) < 0: no child
// Shading.
`define ISA_ST_SH_OFFSET 60        // t * d = -(d * u_best)
`define ISA_ST_SH_POINT 61         // p = o + t * d
`define ISA_ST_SH_NORMAL_SUB 62    // sphere: p - c
`define ISA_ST_SH_NORMAL_SCALE 63  // sphere: n = (p - c) * 1/r
`define ISA_ST_SH_LIGHT_VEC 64     // light - p
`define ISA_ST_SH_KD 65            // kd * (n.l)
`define ISA_ST_SH_CL 66            // colour * light colour
`define ISA_ST_SH_DIFFUSE 67       // kd * (n.l) * (colour * light colour)
`define ISA_ST_SH_REFL_K 68        // k = (d.n) n + (d.n) n (MUL2X)
`define ISA_ST_SH_REFL 70          // r = d - k; latches the direction's sign flags
`define ISA_ST_SH_POW2 71          // x^2 (x = r.l)
`define ISA_ST_SH_POW4 72          // x^4
`define ISA_ST_SH_POW5 73          // x^5
`define ISA_ST_SH_POW10 74         // x^10
`define ISA_ST_SH_POW20 75         // x^20
`define ISA_ST_SH_KS 76            // ks * x^20
`define ISA_ST_SH_SPEC 77          // ks * x^20 * light colour
`define ISA_ST_SH_LOCAL 78         // diffuse + specular
`define ISA_ST_SH_COLOUR 79        // ray colour = w * local
`define ISA_ST_SH_CHILD_W 80       // child weight = w * kr
// Unwinding the stack.
`define ISA_ST_POP_ADD 84          // PAR_COL = PAR_COL + CUR_COL
`define ISA_ST_POP_MOV 85          // PAR_COL = CUR_COL (the parent got no light)
`define ISA_ST_ROOT_BLACK 86       // STK0_COL = ZERO (no light reached the pixel)
// The refracted child of a hit on transparent sphere k (docs/scenes.md,
// "Refraction"), spawned into level sp when the hit's reflected subtree has
// been added into its colour, or at once without one: p in CUR_O (SH_POINT
// wrote it there), d in PAR_D, eta = TRNk.x, ior = TRNk.y, kt = TRNk.z.
// These are the ids from 90 up, and only these: a controller built
// without refraction (REFRACTION = 0) decodes none of them (ctrl_flow.vh,
// decoded_st). Every state id is below 128: a 7-bit id keeps the fast
// controller's decodes of it within 4 LUT levels (docs/fast.md).
// Into the sphere (Snell, eta):
`define ISA_ST_RF_NSUB 90          // N = p - c
`define ISA_ST_RF_NSCALE 91        // N = n = (p - c) * 1/r (then Q.x = d.n by DOT)
`define ISA_ST_RF_COS2 92          // U.x = (d.n)^2
`define ISA_ST_RF_SIN2 93          // U.x = 1 - (d.n)^2
`define ISA_ST_RF_ETA1 94          // U.x = U.x * eta (MULX)
`define ISA_ST_RF_ETA2 95          // U.x = U.x * eta: eta^2 sin^2
`define ISA_ST_RF_K 96             // U.x = k = 1 - eta^2 sin^2; k < 0: total internal reflection
`define ISA_ST_RF_SQRT 97          // U.x = sqrt(k)
`define ISA_ST_RF_EDN 98           // G.x = (d.n) * eta
`define ISA_ST_RF_COEF 99          // G.x = eta (d.n) + sqrt(k)
`define ISA_ST_RF_ED 100           // V = d * eta
`define ISA_ST_RF_CN 101           // S = n * G.x
`define ISA_ST_RF_DIR 102          // R = t = eta d - (eta (d.n) + sqrt k) n
// Across it: the far root of the sphere test from p along t.
`define ISA_ST_RF_CV 103           // V = p - c (then Q.x = b = v.t by DOT)
`define ISA_ST_RF_CBD 104          // U = -b t
`define ISA_ST_RF_CW 105           // V = w = v - b t (then S.x = disc = r*r - w.w by ISECT)
`define ISA_ST_RF_CSQRT 106        // S.x = sqrt(disc)
`define ISA_ST_RF_CS 107           // S.x = s = sqrt(disc) - b
`define ISA_ST_RF_CST 108          // U = t * s
`define ISA_ST_RF_EXIT 109         // CUR_O = p + s t: the exit point
// Out of it (Snell, ior, against the inward normal).
`define ISA_ST_RF_OSUB 110         // N = exit - c
`define ISA_ST_RF_OSCALE 111       // N = n' (then Q.x = t.n' = cos by DOT)
`define ISA_ST_RF_OCOS2 112        // U.x = cos^2
`define ISA_ST_RF_OSIN2 113        // U.x = 1 - cos^2
`define ISA_ST_RF_OIOR1 114        // U.x = U.x * ior (MULY)
`define ISA_ST_RF_OIOR2 115        // U.x = U.x * ior: ior^2 sin^2
`define ISA_ST_RF_OK 116           // U.x = k' = 1 - ior^2 sin^2; k' < 0 (by rounding only): taken as 0
`define ISA_ST_RF_OSQRT 117        // U.x = sqrt(k')
`define ISA_ST_RF_OEDN 118         // G.x = cos * ior
`define ISA_ST_RF_OCOEF 119        // G.x = ior cos - sqrt(k') (skipped when k' is taken as 0)
`define ISA_ST_RF_OED 120          // V = t * ior
`define ISA_ST_RF_OCN 121          // S = n' * G.x
`define ISA_ST_RF_ODIR 122         // CUR_D = ior t - (ior cos - sqrt k') n'; latches the direction's sign flags
// Total internal reflection at the entry: the mirror ray from p.
`define ISA_ST_RF_TIR_K 123        // U = 2 (d.n) n (MUL2X)
`define ISA_ST_RF_TIR 124          // CUR_D = d - 2 (d.n) n; latches the direction's sign flags
`define ISA_ST_RF_CHILD_W 125      // CUR_W = PAR_W * kt (MULZ)
// Weight cutoff of the refracted child (with ISA_DIM_CFG_CUTOFF_LSB set, at
// the hit): no child whose weight w * kt < c.
`define ISA_ST_RF_CUT_W 126        // U.z = CUR_W.z * kt (MULZ)
`define ISA_ST_RF_CUT_CMP 127      // G.z = U.z - c < 0: no refracted child
// Exposure (thesis 3.7; with ISA_DIM_CFG_EXPOSURE_LSB set, after the
// unwinding, before PIX_DONE): STK0_COL = 1 - e^(exposure * STK0_COL).
`define ISA_ST_EXPO_MUL 87         // U = STK0_COL * exposure (MULX, ROT0_S lane x)
`define ISA_ST_EXPO_EXP 88         // U = e^U (EXP, every lane)
`define ISA_ST_EXPO_SUB 89         // STK0_COL = ONE - U

`endif
