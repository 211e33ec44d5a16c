`default_nettype none
`include "isa.vh"
// ============================================================================
// fast_regfile_tb -- rtl/fast/fast_regfile.v against a model of its contract
// ============================================================================
// The model: one array per context of the 256 addresses and one scene
// array, as the header of fast_regfile.v says them (scene below ISA_REG_T0 and TRN0..7,
// the temporaries and stack levels below STACK_DEPTH per context, +0
// elsewhere, write-port writes outside a context's words dropped). Every
// word is written first (scene port, then each context's words through the
// write port); then CYCLES random cycles with a write, a scene write now
// and then, and two reads each, half the addresses near the tables' edges;
// each read's data, two edges later, must be the model's as of the read's
// edge (a word written in that edge reads old). Prints "mismatch ..." per
// difference and "done <reads> <mismatches>" at the end; +fault=N flips a
// bit of the model's N-th expected value (the checker's own test).
// ============================================================================
module fast_regfile_tb;
    parameter integer STACK_DEPTH = `ISA_DIM_STK_COUNT;
    parameter integer CTX_BITS    = 3;
    parameter integer CYCLES      = 20000;

    localparam integer CTXS    = 1 << CTX_BITS;
    localparam integer STK_END = `ISA_REG_STK0_O + STACK_DEPTH * `ISA_DIM_STK_STRIDE;

    reg                         clk = 1'b0;
    reg  [CTX_BITS-1:0]         r_ctx = 0, w_ctx = 0;
    reg  [`ISA_DIM_REG_BITS-1:0] ra_a = 0, ra_b = 0, wa = 0, swa = 0;
    reg                         we = 1'b0, swe = 1'b0;
    reg  [2:0]                  wmask = 3'b000;
    reg  [95:0]                 wd = 96'd0, swd = 96'd0;
    wire [95:0]                 rd_a, rd_b;

    fast_regfile #(.STACK_DEPTH(STACK_DEPTH), .CTX_BITS(CTX_BITS)) dut (
        .clk(clk), .r_ctx(r_ctx), .ra_a(ra_a), .ra_b(ra_b), .rd_a(rd_a), .rd_b(rd_b),
        .we(we), .w_ctx(w_ctx), .wa(wa), .wmask(wmask), .wd(wd),
        .swe(swe), .swa(swa), .swd(swd)
    );

    `include "tb_clock.vh"

    // The model.
    localparam integer NA      = 1 << `ISA_DIM_REG_BITS;
    localparam integer TRN_END = `ISA_REG_TRN0 + `ISA_DIM_TRN_COUNT * `ISA_DIM_TRN_STRIDE;
    reg [95:0] scene_m [0:NA-1];
    reg [95:0] ctx_m   [0:CTXS*NA-1];

    function is_scene(input integer a);
        is_scene = a < `ISA_REG_T0 || (a >= `ISA_REG_TRN0 && a < TRN_END);
    endfunction
    function is_ctx(input integer a);
        is_ctx = (a >= `ISA_REG_T0 && a < `ISA_REG_CUR_O) || (a >= `ISA_REG_STK0_O && a < STK_END);
    endfunction

    function [95:0] model_read(input integer ctx, input integer a);
        if (is_scene(a))    model_read = scene_m[a];
        else if (is_ctx(a)) model_read = ctx_m[ctx * NA + a];
        else                model_read = 96'd0;
    endfunction

    // An address: anywhere, or at a table's edge.
    function integer pick_addr(input integer r, input integer s);
        integer edges [0:13];
        begin
            edges[0] = 0; edges[1] = `ISA_REG_T0 - 1; edges[2] = `ISA_REG_T0;
            edges[3] = `ISA_REG_CUR_O - 1; edges[4] = `ISA_REG_CUR_O;
            edges[5] = `ISA_REG_STK0_O - 1; edges[6] = `ISA_REG_STK0_O;
            edges[7] = STK_END - 1; edges[8] = STK_END % NA; edges[9] = NA - 1;
            edges[10] = `ISA_REG_TRN0 - 1; edges[11] = `ISA_REG_TRN0;
            edges[12] = TRN_END - 1; edges[13] = TRN_END;
            pick_addr = (r % 2 == 0) ? edges[s % 14] : s % NA;
        end
    endfunction

    integer i, c, a, cycle, reads, mismatches, fault, seed;
    reg [95:0] exp_a [0:2];
    reg [95:0] exp_b [0:2];
    reg        chk   [0:2];
    reg [95:0] word;

    task check_port(input [95:0] got, input [95:0] want, input integer port);
        begin
            reads = reads + 1;
            if (reads == fault) want = want ^ 96'd1;
            if (got !== want) begin
                mismatches = mismatches + 1;
                $display("mismatch cycle %0d port %0d: got %h want %h", cycle, port, got, want);
            end
        end
    endtask

    initial begin
        if (!$value$plusargs("fault=%d", fault)) fault = -1;
        seed = 20111;
        reads = 0;
        mismatches = 0;
        for (i = 0; i < 3; i = i + 1) chk[i] = 1'b0;
        // Every scene word, then every context word.
        for (a = 0; a < NA; a = a + 1) begin
            fall;
            word = {$random(seed), $random(seed), $random(seed)};
            swe = 1'b1; swa = a; swd = word;
            scene_m[a] = word;
            rise;
        end
        swe = 1'b0;
        for (c = 0; c < CTXS; c = c + 1) begin
            for (a = 0; a < NA; a = a + 1) begin
                fall;
                word = {$random(seed), $random(seed), $random(seed)};
                we = 1'b1; w_ctx = c; wa = a; wmask = 3'b111; wd = word;
                ctx_m[c * NA + a] = is_ctx(a) ? word : 96'd0;
                rise;
            end
        end
        we = 1'b0;
        // Random cycles.
        for (cycle = 0; cycle < CYCLES + 2; cycle = cycle + 1) begin
            fall;
            if (chk[2]) begin
                check_port(rd_a, exp_a[2], 0);
                check_port(rd_b, exp_b[2], 1);
            end
            if (cycle < CYCLES) begin
                r_ctx = $random(seed);
                ra_a  = pick_addr($random(seed), $unsigned($random(seed)));
                ra_b  = pick_addr($random(seed), $unsigned($random(seed)));
                we    = $random(seed);
                w_ctx = ($random(seed) % 4 == 0) ? r_ctx : $random(seed);
                wa    = ($random(seed) % 4 == 0) ? ra_a : pick_addr($random(seed), $unsigned($random(seed)));
                wmask = $random(seed);
                wd    = {$random(seed), $random(seed), $random(seed)};
                swe   = ($random(seed) % 16 == 0);
                swa   = ($random(seed) % 2 == 0) ? ra_b : $random(seed);
                swd   = {$random(seed), $random(seed), $random(seed)};
                // Reads see the words as they are before this edge's writes.
                exp_a[0] = model_read(r_ctx, ra_a);
                exp_b[0] = model_read(r_ctx, ra_b);
                chk[0]   = 1'b1;
                if (we && is_ctx(wa)) begin
                    word = ctx_m[w_ctx * NA + wa];
                    for (i = 0; i < 3; i = i + 1)
                        if (wmask[i]) word[32*i +: 32] = wd[32*i +: 32];
                    ctx_m[w_ctx * NA + wa] = word;
                end
                if (swe) scene_m[swa] = swd;
            end else begin
                we = 1'b0; swe = 1'b0; chk[0] = 1'b0;
            end
            rise;
            exp_a[2] = exp_a[1]; exp_b[2] = exp_b[1]; chk[2] = chk[1];
            exp_a[1] = exp_a[0]; exp_b[1] = exp_b[0]; chk[1] = chk[0];
        end
        $display("done %0d %0d", reads, mismatches);
        $finish;
    end
endmodule
`default_nettype wire
