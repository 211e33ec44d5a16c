`default_nettype none
// Round-robin pick among N requesters, and the picked one's data: the
// first requester after the last grant, else the first of all. One-hot
// logic (each requester's index compared with `last` is a constant against
// a register, no adder), then an AND-OR multiplexer over the data.
// Combinational: the caller registers `last` (from `at`) and what it loads.
//
// rtl/top.v uses it twice: over its result slots into the out register,
// and, for fast processors, in each result group over its members' queue
// heads.
module rr_arbiter #(
    parameter integer N  = 4,   // requesters
    parameter integer IW = 2,   // an index's width: 2^IW >= N
    parameter integer DW = 8    // a requester's data width
) (
    input  wire [N-1:0]    req,
    input  wire [IW-1:0]   last,     // the last grant's index
    input  wire [N*DW-1:0] data,     // requester i's at [i*DW +: DW]
    output reg  [N-1:0]    grant,    // one-hot; zero without a request
    output reg  [IW-1:0]   at,       // the grant's index (0 without one)
    output wire            found,    // some requester asks
    output reg  [DW-1:0]   granted   // the granted requester's data (0 without one)
);

    reg     seen;
    integer i;

    assign found = |req;

    always @* begin
        grant = {N{1'b0}};
        seen  = 1'b0;
        for (i = 0; i < N; i = i + 1)
            if (req[i] && i > {{(32 - IW){1'b0}}, last} && !seen) begin
                grant[i] = 1'b1;
                seen     = 1'b1;
            end
        for (i = 0; i < N; i = i + 1)
            if (req[i] && !seen) begin
                grant[i] = 1'b1;
                seen     = 1'b1;
            end
        at      = {IW{1'b0}};
        granted = {DW{1'b0}};
        for (i = 0; i < N; i = i + 1) begin
            if (grant[i]) at = at | i[IW-1:0];
            granted = granted | ({DW{grant[i]}} & data[i*DW +: DW]);
        end
    end

endmodule
`default_nettype wire
