`default_nettype none
`include "fp_defs.vh"
// ============================================================================
// fp_units -- every float unit and method side by side
// ============================================================================
// The single top of rtl/fp until the pixel processor exists: it makes
// `verilator --lint-only -Wall` over the whole tree see one design, and gives
// synthesis one module to report the units' cost from. The co-simulation
// verilates each unit on its own instead (build.rs).
// ============================================================================
module fp_units (
    input  wire        clk,
    input  wire        rst_n,
    input  wire [31:0] a,
    input  wire [31:0] b,
    input  wire        in_valid,
    output wire [31:0] sum,
    output wire [31:0] product,
    output wire [31:0] from_int,
    output wire [3:0]  out_valid,  // recip exact, recip fast, sqrt exact, sqrt fast
    output wire [31:0] recip_exact,
    output wire [31:0] recip_fast,
    output wire [31:0] sqrt_exact,
    output wire [31:0] sqrt_fast
);

    fp_add  u_add  (.a(a), .b(b), .y(sum));
    fp_mul  u_mul  (.a(a), .b(b), .y(product));
    fp_itof u_itof (.a(a), .y(from_int));

    fp_recip #(.METHOD(`FP_METHOD_EXACT)) u_recip_exact (
        .clk(clk), .rst_n(rst_n), .in_valid(in_valid), .a(a), .out_valid(out_valid[0]), .y(recip_exact)
    );
    fp_recip #(.METHOD(`FP_METHOD_FAST)) u_recip_fast (
        .clk(clk), .rst_n(rst_n), .in_valid(in_valid), .a(a), .out_valid(out_valid[1]), .y(recip_fast)
    );
    fp_sqrt #(.METHOD(`FP_METHOD_EXACT)) u_sqrt_exact (
        .clk(clk), .rst_n(rst_n), .in_valid(in_valid), .a(a), .out_valid(out_valid[2]), .y(sqrt_exact)
    );
    fp_sqrt #(.METHOD(`FP_METHOD_FAST)) u_sqrt_fast (
        .clk(clk), .rst_n(rst_n), .in_valid(in_valid), .a(a), .out_valid(out_valid[3]), .y(sqrt_fast)
    );

endmodule
`default_nettype wire
