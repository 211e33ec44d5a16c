`default_nettype none
// ============================================================================
// fp_lzc -- leading-zero count, combinational
// ============================================================================
// count = number of zero bits above the highest set bit of value; WIDTH for
// an all-zero value. COUNT_W must hold WIDTH. Shared by fp_add, fp_mul,
// fp_itof and fp_unpack for their normalization shifts.
//
// A priority select, no adders: each set bit, scanned upwards, overrides the
// count with its own constant distance from the top, so the highest one wins.
// (A running `count = count + 1` over the zeros would synthesize as WIDTH
// chained incrementers, the longest path of fp_add and fp_mul.)
// rtl/synth/equiv_lzc.sh proves this equal to that counting loop with Yosys
// for every (WIDTH, COUNT_W) the RTL instantiates.
// ============================================================================
module fp_lzc #(
    parameter integer WIDTH   = 32,
    parameter integer COUNT_W = 6
) (
    input  wire [WIDTH-1:0]   value,
    output reg  [COUNT_W-1:0] count
);

    localparam integer       TOP_BIT  = WIDTH - 1;
    localparam [COUNT_W-1:0] ALL_ZERO = WIDTH[COUNT_W-1:0];    // no bit set
    localparam [COUNT_W-1:0] TOP      = TOP_BIT[COUNT_W-1:0];  // bit i set: TOP - i

    integer i;

    always @* begin
        count = ALL_ZERO;
        for (i = 0; i < WIDTH; i = i + 1) begin
            if (value[i]) count = TOP - i[COUNT_W-1:0];
        end
    end

endmodule
`default_nettype wire
