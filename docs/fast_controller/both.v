// Generic final choice with NORM_SCALE's plane pick folded in, one cycle.
module both #(parameter W = 80) (
    input wire clk,
    input wire [2:0] yn_i, yp_i, ys_i,
    input wire [2:0] mn_i, mp_i,
    input wire inv_i, ns_i, box_i,
    input wire [5:0] ok_i, input wire [11:0] axis_i, input wire [5:0] pneg_i, input wire fast_i,
    input wire [W-1:0] a0_i, a1_i,   // a1 for NORM_SCALE: the plane candidate with idx/pa bits to fill
    output reg [W-1:0] nx_q
);
    reg [2:0] yn, yp, ys, mn, mp; reg inv, ns, box; reg [5:0] ok; reg [11:0] axis; reg [5:0] pneg; reg fast;
    reg [W-1:0] a0, a1;
    always @(posedge clk) begin
        yn<=yn_i; yp<=yp_i; ys<=ys_i; mn<=mn_i; mp<=mp_i; inv<=inv_i; ns<=ns_i; box<=box_i;
        ok<=ok_i; axis<=axis_i; pneg<=pneg_i; fast<=fast_i; a0<=a0_i; a1<=a1_i;
    end
    integer j;
    reg [5:0] e; reg [2:0] against; reg found; reg [2:0] idx; reg cond; reg [W-1:0] a1x, a0x;
    always @* begin
        for (j = 0; j < 6; j = j + 1) begin
            against = pneg[j] ? yp : yn;
            e[j] = ok[j] & (!fast | against[axis[2*j +: 2]]);
        end
        found = 0; idx = 0;
        for (j = 5; j >= 0; j = j - 1) if (e[j]) begin found = 1; idx = j; end
        a1x = a1; a1x[2:0] = idx; a1x[13:11] = idx;     // idx and pa_b[4:2]
        a0x = a0; if (box) a0x[26:20] = 7'd66 + {4'b0, ~ys};  // BOX_FAR's corner
        cond = ns ? found : inv ^ |((yn & mn) | (yp & mp));
    end
    always @(posedge clk) nx_q <= cond ? a1x : a0x;
endmodule
