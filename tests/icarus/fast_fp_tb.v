`default_nettype none
`include "fast_defs.vh"
// ============================================================================
// fast_fp_tb -- the fast processor's pipelined units under Icarus Verilog
// ============================================================================
// Streams the vectors of +vectors=FILE (one per line, hex: a, b, golden's
// a + b, golden's a * b; tests/icarus.rs writes them) through fast_fp_add
// and fast_fp_mul, one pair every cycle, back to back, and compares each
// result with golden's the unit's latency (fast_defs.vh) later. Prints one
// line per mismatch (the first few) and then
//   fast_fp_tb: N vectors, add mismatches A, mul mismatches M
// ============================================================================
module fast_fp_tb;
    parameter integer MAX = 1 << 16;  // vectors the file may hold

    reg clk;
    `include "tb_clock.vh"

    reg  [31:0] vec_a   [0:MAX-1];
    reg  [31:0] vec_b   [0:MAX-1];
    reg  [31:0] vec_add [0:MAX-1];
    reg  [31:0] vec_mul [0:MAX-1];
    reg  [127:0] line   [0:MAX-1];
    reg  [31:0] a, b;
    wire [31:0] y_add, y_mul;

    fast_fp_add u_add (.clk(clk), .a(a), .b(b), .y(y_add));
    fast_fp_mul u_mul (.clk(clk), .a(a), .b(b), .y(y_mul));

    integer n, i, edge_no, bad_add, bad_mul, k;
    reg [1023:0] file;

    initial begin
        if (!$value$plusargs("vectors=%s", file)) begin
            $display("fast_fp_tb: no +vectors=FILE");
            $finish;
        end
        for (i = 0; i < MAX; i = i + 1) line[i] = {128{1'bx}};
        $readmemh(file, line);
        n = 0;
        while (n < MAX && line[n][0] !== 1'bx) begin
            {vec_a[n], vec_b[n], vec_add[n], vec_mul[n]} = line[n];
            n = n + 1;
        end
        bad_add = 0;
        bad_mul = 0;
        a = 32'd0;
        b = 32'd0;
        fall;
        // Before edge e (from 1) vector e - 1 enters; after edge e the add
        // result of vector e - FAST_ADD_LATENCY is out, the mul result of
        // e - FAST_MUL_LATENCY.
        for (edge_no = 1; edge_no < n + `FAST_ADD_LATENCY + `FAST_MUL_LATENCY; edge_no = edge_no + 1) begin
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
        end
        $display("fast_fp_tb: %0d vectors, add mismatches %0d, mul mismatches %0d", n, bad_add, bad_mul);
        $finish;
    end
endmodule
`default_nettype wire
