`default_nettype none
// ============================================================================
// fast_delay -- WIDTH bits delayed by STAGES clock edges (a shift register)
// ============================================================================
// What a pipelined unit carries beside a sub-unit's stages (signs, special
// cases, exponents), so that the two arrive together. No reset, no enable:
// the fast processor's pipeline never stalls inside a unit. STAGES = 0 is a
// wire. Synthesis maps deep ones to shift-register LUTs (SRL16/SRLC32).
// ============================================================================
module fast_delay #(
    parameter integer WIDTH  = 1,
    parameter integer STAGES = 1
) (
    input  wire             clk,
    input  wire [WIDTH-1:0] d,
    output wire [WIDTH-1:0] q
);

    generate
        if (STAGES == 0) begin : g_wire
            assign q = d;
            wire unused_clk = clk;
        end else begin : g_regs
            reg [WIDTH-1:0] r [0:STAGES-1];
            integer i;
            always @(posedge clk) begin
                r[0] <= d;
                for (i = 1; i < STAGES; i = i + 1) r[i] <= r[i - 1];
            end
            assign q = r[STAGES - 1];
        end
    endgenerate

endmodule
`default_nettype wire
