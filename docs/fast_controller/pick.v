// NORM_SCALE's flag-dependent plane pick, one cycle: registered flags and
// precomputed (registered) static inputs -> next {st, idx} registered.
module pick (
    input wire clk,
    input wire [2:0] yn_i, yp_i, ys_i,
    input wire [5:0] ok_i,          // plane j < n, not excluded (static)
    input wire [11:0] axis_i,       // per plane axis
    input wire [5:0] pneg_i,        // per plane facing -1
    input wire fast_i,
    input wire use_pln_i,           // static: the start goes to the planes (no sphere, no shortcut end)
    input wire [8:0] alt_st_i,      // static alternative (BOX_FAR/SPH_V/clear/unwind...) when no plane
    input wire [2:0] alt_idx_i,
    input wire [6:0] alt_pa_i,      // its la_b
    output reg [8:0] st_q,
    output reg [2:0] idx_q,
    output reg [6:0] pa_q,
    output reg [6:0] pa_box_q
);
    reg [2:0] yn, yp, ys; reg [5:0] ok; reg [11:0] axis; reg [5:0] pneg; reg fast, use_pln;
    reg [8:0] alt_st; reg [2:0] alt_idx; reg [6:0] alt_pa;
    always @(posedge clk) begin
        yn<=yn_i; yp<=yp_i; ys<=ys_i; ok<=ok_i; axis<=axis_i; pneg<=pneg_i; fast<=fast_i; use_pln<=use_pln_i;
        alt_st<=alt_st_i; alt_idx<=alt_idx_i; alt_pa<=alt_pa_i;
    end
    integer j;
    reg [5:0] e; reg [2:0] against; reg found; reg [2:0] idx;
    always @* begin
        for (j = 0; j < 6; j = j + 1) begin
            against = pneg[j] ? yp : yn;
            e[j] = ok[j] & (!fast | against[axis[2*j +: 2]]);
        end
        found = 0; idx = 0;
        for (j = 5; j >= 0; j = j - 1) if (e[j]) begin found = 1; idx = j; end
    end
    always @(posedge clk) begin
        st_q  <= (use_pln && found) ? 9'd26 : alt_st;
        idx_q <= (use_pln && found) ? idx : alt_idx;
        pa_q  <= (use_pln && found) ? {2'b01, idx, 2'b00} : alt_pa;
        pa_box_q <= 7'd66 + {4'b0, ~ys};
    end
endmodule

// The generic final choice: cond = inv ^ |(yn & mn | yp & mp); next = cond ? a1 : a0,
// plus the flag latches.
module choose #(parameter W = 100) (
    input wire clk,
    input wire [2:0] yn_i, yp_i, ys_i,
    input wire [2:0] mn_i, mp_i,
    input wire inv_i, latch_dir_i, latch_facing_i, latch_cut_i,
    input wire [W-1:0] a0_i, a1_i,
    input wire [8:0] dir_i, input wire facing_i, cut_i,
    output reg [W-1:0] nx_q,
    output reg [8:0] dir_q, output reg facing_q, cut_q
);
    reg [2:0] yn, yp, ys, mn, mp; reg inv, ld, lf, lc; reg [W-1:0] a0, a1; reg [8:0] dir; reg facing, cut;
    always @(posedge clk) begin
        yn<=yn_i; yp<=yp_i; ys<=ys_i; mn<=mn_i; mp<=mp_i; inv<=inv_i; ld<=latch_dir_i; lf<=latch_facing_i; lc<=latch_cut_i;
        a0<=a0_i; a1<=a1_i; dir<=dir_i; facing<=facing_i; cut<=cut_i;
    end
    wire cond = inv ^ |((yn & mn) | (yp & mp));
    always @(posedge clk) begin
        nx_q <= cond ? a1 : a0;
        dir_q <= ld ? {ys, yn, yp} : dir;
        facing_q <= lf ? yp[0] : facing;
        cut_q <= lc ? yn[2] : cut;
    end
endmodule
