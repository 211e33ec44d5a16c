`default_nettype none
// ============================================================================
// fp_lzc -- leading-zero count, combinational
// ============================================================================
// count = number of zero bits above the highest set bit of value; WIDTH for
// an all-zero value. COUNT_W must hold WIDTH. Shared by fp_add, fp_mul,
// fp_itof and fp_unpack for their normalization shifts.
// ============================================================================
module fp_lzc #(
    parameter integer WIDTH   = 32,
    parameter integer COUNT_W = 6
) (
    input  wire [WIDTH-1:0]   value,
    output reg  [COUNT_W-1:0] count
);

    integer i;
    reg     found;

    always @* begin
        count = {COUNT_W{1'b0}};
        found = 1'b0;
        for (i = WIDTH - 1; i >= 0; i = i - 1) begin
            if (value[i]) found = 1'b1;
            if (!found) count = count + 1'b1;
        end
    end

endmodule
`default_nettype wire
