`default_nettype none
`include "fp_defs.vh"
// ============================================================================
// fast_alu_tb -- rtl/fast/fast_alu.v under Icarus, cycle by cycle, against
// golden's results (tests/icarus.rs writes them from harness::check::alu_check's
// schedules)
// ============================================================================
// +vectors=FILE: one line a cycle, 13 hex words of 32 bits, first word
// first:
//   {20'b0, in_valid, in_ctx[4:0], in_op[5:0]}, a.x, a.y, a.z, b.x, b.y,
//   b.z, ix, iy,
//   {12'b0, exp_ready, out_valid, out_ctx[4:0], out_writes, lanes[2:0],
//    y_neg, y_pos, y_sign (3 bits each, bit i lane i)}, y.x, y.y, y.z
// the expected output port in that cycle (the lanes and flags compared only
// where `lanes` has them; the context, write bit and lanes only where
// out_valid). The cycle contract is the C++ driver's: inputs set with clk
// low, outputs sampled, then the rising edge. Prints "mismatch ..." per
// difference and "fast_alu_tb: N cycles, M mismatches" at the end.
// ============================================================================
module fast_alu_tb;
    parameter integer RECIP_METHOD = `FP_METHOD_EXACT;
    parameter integer SQRT_METHOD  = `FP_METHOD_EXACT;
    parameter integer EXPOSURE     = 1;
    parameter integer MAX_CYCLES   = 1 << 16;

    reg         clk = 1'b0;
    reg         rst_n = 1'b0;
    reg         in_valid = 1'b0;
    reg  [4:0]  in_ctx = 5'd0;
    reg  [5:0]  in_op = 6'd0;
    reg  [95:0] a = 96'd0, b = 96'd0;
    reg  [31:0] ix = 32'd0, iy = 32'd0;
    wire        exp_ready, out_valid, out_writes;
    wire [4:0]  out_ctx;
    wire [95:0] y;
    wire [2:0]  y_neg, y_pos, y_sign;

    fast_alu #(
        .RECIP_METHOD(RECIP_METHOD), .SQRT_METHOD(SQRT_METHOD), .EXPOSURE(EXPOSURE), .CTX_BITS(5)
    ) dut (
        .clk(clk), .rst_n(rst_n), .in_valid(in_valid), .in_ctx(in_ctx), .in_op(in_op),
        .a(a), .b(b), .ix(ix), .iy(iy), .exp_ready(exp_ready), .out_valid(out_valid),
        .out_ctx(out_ctx), .out_writes(out_writes), .y(y), .y_neg(y_neg), .y_pos(y_pos),
        .y_sign(y_sign)
    );

    `include "tb_clock.vh"

    reg [32*13-1:0] vec [0:MAX_CYCLES-1];
    reg [1023:0]    file;
    integer         n, i, lane, mismatches;
    reg [32*13-1:0] v;
    reg [31:0]      w_in, w_out;
    reg [2:0]       lanes;

    // Word k of a line (word 0 is the first in the file).
    function [31:0] word(input [32*13-1:0] line, input integer k);
        word = line[32*(12 - k) +: 32];
    endfunction

    initial begin
        if (!$value$plusargs("vectors=%s", file)) begin
            $display("fast_alu_tb: no +vectors=FILE");
            $finish;
        end
        for (i = 0; i < MAX_CYCLES; i = i + 1) vec[i] = {32*13{1'b1}};
        $readmemh(file, vec);
        n = 0;
        while (n < MAX_CYCLES && vec[n] !== {32*13{1'b1}}) n = n + 1;
        // Reset as the C++ driver does: two edges low, one high.
        for (i = 0; i < 3; i = i + 1) begin
            fall;
            if (i == 2) rst_n = 1'b1;
            rise;
        end
        mismatches = 0;
        for (i = 0; i < n; i = i + 1) begin
            fall;
            v = vec[i];
            w_in = word(v, 0);
            in_valid = w_in[11];
            in_ctx = w_in[10:6];
            in_op = w_in[5:0];
            a = {word(v, 3), word(v, 2), word(v, 1)};
            b = {word(v, 6), word(v, 5), word(v, 4)};
            ix = word(v, 7);
            iy = word(v, 8);
            w_out = word(v, 9);
            lanes = w_out[11:9];
            if (exp_ready !== w_out[19] || out_valid !== w_out[18]) begin
                mismatches = mismatches + 1;
                $display("mismatch cycle %0d: exp_ready %b out_valid %b, want %b %b",
                         i, exp_ready, out_valid, w_out[19], w_out[18]);
            end else if (out_valid) begin
                if ({out_ctx, out_writes} !== w_out[17:12]) begin
                    mismatches = mismatches + 1;
                    $display("mismatch cycle %0d: context %0d writes %b, want %h", i, out_ctx, out_writes, w_out);
                end
                for (lane = 0; lane < 3; lane = lane + 1) begin
                    if (lanes[lane] && (y[32*lane +: 32] !== word(v, 10 + lane)
                                        || y_neg[lane] !== w_out[6 + lane]
                                        || y_pos[lane] !== w_out[3 + lane]
                                        || y_sign[lane] !== w_out[lane])) begin
                        mismatches = mismatches + 1;
                        $display("mismatch cycle %0d lane %0d: y %h flags %b%b%b, want %h %b%b%b", i, lane,
                                 y[32*lane +: 32], y_neg[lane], y_pos[lane], y_sign[lane],
                                 word(v, 10 + lane), w_out[6 + lane], w_out[3 + lane], w_out[lane]);
                    end
                end
            end
            rise;
        end
        $display("fast_alu_tb: %0d cycles, %0d mismatches", n, mismatches);
        $finish;
    end
endmodule
`default_nettype wire
