`default_nettype none
`include "fast_defs.vh"
// ============================================================================
// fast_fp_tb -- the fast processor's pipelined units under Icarus Verilog
// ============================================================================
// Streams the vectors of +vectors=FILE (one per line, hex: a, b, golden's
// a + b, a * b, float(a as an integer), 1 / a and sqrt(a) (exact), e^a;
// tests/icarus.rs writes them) through fast_fp_add, fast_fp_mul,
// fast_fp_itof, fast_fp_recip, fast_fp_sqrt and fast_fp_exp, one vector
// every cycle, back to back, and compares each
// result with golden's the unit's latency (fast_defs.vh) later. Prints one
// line per mismatch (the first few) and then
//   fast_fp_tb: N vectors, add mismatches A, mul mismatches M, itof
//   mismatches I, recip mismatches R, sqrt mismatches S, exp mismatches E
// ============================================================================
module fast_fp_tb;
    parameter integer MAX = 1 << 17;  // vectors the file may hold

    reg clk;
    `include "tb_clock.vh"

    reg  [31:0] vec_a   [0:MAX-1];
    reg  [31:0] vec_b   [0:MAX-1];
    reg  [31:0] vec_add [0:MAX-1];
    reg  [31:0] vec_mul [0:MAX-1];
    reg  [31:0] vec_itof [0:MAX-1];
    reg  [31:0] vec_recip [0:MAX-1];
    reg  [31:0] vec_sqrt [0:MAX-1];
    reg  [31:0] vec_exp [0:MAX-1];
    reg  [255:0] line   [0:MAX-1];
    reg  [31:0] a, b;
    wire [31:0] y_add, y_mul, y_itof, y_recip, y_sqrt, y_exp;

    fast_fp_add   u_add   (.clk(clk), .a(a), .b(b), .y(y_add));
    fast_fp_mul   u_mul   (.clk(clk), .a(a), .b(b), .y(y_mul));
    fast_fp_itof  u_itof  (.clk(clk), .a(a), .y(y_itof));
    fast_fp_recip u_recip (.clk(clk), .a(a), .y(y_recip));
    fast_fp_sqrt  u_sqrt  (.clk(clk), .a(a), .y(y_sqrt));
    fast_fp_exp   u_exp   (.clk(clk), .a(a), .y(y_exp));

    integer n, i, edge_no, bad_add, bad_mul, bad_itof, bad_recip, bad_sqrt, bad_exp, k;
    reg [1023:0] file;

    initial begin
        if (!$value$plusargs("vectors=%s", file)) begin
            $display("fast_fp_tb: no +vectors=FILE");
            $finish;
        end
        for (i = 0; i < MAX; i = i + 1) line[i] = {256{1'bx}};
        $readmemh(file, line);
        n = 0;
        while (n < MAX && line[n][0] !== 1'bx) begin
            {vec_a[n], vec_b[n], vec_add[n], vec_mul[n], vec_itof[n], vec_recip[n], vec_sqrt[n], vec_exp[n]} = line[n];
            n = n + 1;
        end
        bad_add = 0;
        bad_mul = 0;
        bad_itof = 0;
        bad_recip = 0;
        bad_sqrt = 0;
        bad_exp = 0;
        a = 32'd0;
        b = 32'd0;
        fall;
        // Before edge e (from 1) vector e - 1 enters; after edge e the add
        // result of vector e - FAST_ADD_LATENCY is out, the mul result of
        // e - FAST_MUL_LATENCY, and so on.
        for (edge_no = 1; edge_no < n + `FAST_SQRT_LATENCY + `FAST_ADD_LATENCY; edge_no = edge_no + 1) begin
            if (edge_no - 1 < n) begin
                a = vec_a[edge_no - 1];
                b = vec_b[edge_no - 1];
            end else begin
                a = 32'd0;
                b = 32'd0;
            end
            rise;
            fall;
            k = edge_no - `FAST_ADD_LATENCY;
            if (k >= 0 && k < n && y_add !== vec_add[k]) begin
                bad_add = bad_add + 1;
                if (bad_add <= 5)
                    $display("add %h + %h: rtl %h golden %h", vec_a[k], vec_b[k], y_add, vec_add[k]);
            end
            k = edge_no - `FAST_MUL_LATENCY;
            if (k >= 0 && k < n && y_mul !== vec_mul[k]) begin
                bad_mul = bad_mul + 1;
                if (bad_mul <= 5)
                    $display("mul %h * %h: rtl %h golden %h", vec_a[k], vec_b[k], y_mul, vec_mul[k]);
            end
            k = edge_no - `FAST_ITOF_LATENCY;
            if (k >= 0 && k < n && y_itof !== vec_itof[k]) begin
                bad_itof = bad_itof + 1;
                if (bad_itof <= 5)
                    $display("itof %h: rtl %h golden %h", vec_a[k], y_itof, vec_itof[k]);
            end
            k = edge_no - `FAST_RECIP_LATENCY;
            if (k >= 0 && k < n && y_recip !== vec_recip[k]) begin
                bad_recip = bad_recip + 1;
                if (bad_recip <= 5)
                    $display("recip %h: rtl %h golden %h", vec_a[k], y_recip, vec_recip[k]);
            end
            k = edge_no - `FAST_SQRT_LATENCY;
            if (k >= 0 && k < n && y_sqrt !== vec_sqrt[k]) begin
                bad_sqrt = bad_sqrt + 1;
                if (bad_sqrt <= 5)
                    $display("sqrt %h: rtl %h golden %h", vec_a[k], y_sqrt, vec_sqrt[k]);
            end
            k = edge_no - `FAST_EXP_LATENCY;
            if (k >= 0 && k < n && y_exp !== vec_exp[k]) begin
                bad_exp = bad_exp + 1;
                if (bad_exp <= 5)
                    $display("exp %h: rtl %h golden %h", vec_a[k], y_exp, vec_exp[k]);
            end
        end
        $display("fast_fp_tb: %0d vectors, add mismatches %0d, mul mismatches %0d, itof mismatches %0d, recip mismatches %0d, sqrt mismatches %0d, exp mismatches %0d",
                 n, bad_add, bad_mul, bad_itof, bad_recip, bad_sqrt, bad_exp);
        $finish;
    end
endmodule
`default_nettype wire
