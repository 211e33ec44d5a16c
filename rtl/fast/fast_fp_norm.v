`default_nettype none
// ============================================================================
// fast_fp_norm -- normalize a significand in three registered stages
// ============================================================================
// The normalization fp_add, fp_mul and fp_itof do in one step: shift value
// left until its top bit is set, and lower the exponent by the same count:
//   y = value << lz,   exp = base - lz,   lz = leading zeros of value.
// For value = 0, y = 0 and exp is unspecified: the callers override that
// result.
//
// y and exp appear LATENCY = 3 clock edges after the inputs; a new value may
// enter every cycle. A leading-zero count over 28 or 48 bits in one step is
// a mux chain as long as the word (fp_lzc: the compact units' longest path),
// so it is split by bytes:
//   1. each byte, from the top: whether it has a bit set, and its own count
//      (fp_lzc over 8 bits, shared with the compact units);
//   2. the first byte with a bit set: lz = 8 * its index + its count;
//   3. the shift and the exponent, in parallel.
// ============================================================================
module fast_fp_norm #(
    parameter integer WIDTH   = 28,
    parameter integer COUNT_W = 5
) (
    input  wire                      clk,
    input  wire        [WIDTH-1:0]   value,
    input  wire signed [11:0]        base,
    output reg         [WIDTH-1:0]   y,
    output reg  signed [11:0]        exp
);

    localparam integer BYTES = (WIDTH + 7) / 8;
    localparam integer PADW  = BYTES * 8;
    // The value padded with zeros below to whole bytes: the same leading
    // zeros, unless it is 0. (A zero-width replication is not Verilog-2005,
    // hence the two cases.)
    wire [PADW-1:0] padded;
    generate
        if (PADW == WIDTH) begin : g_whole_bytes
            assign padded = value;
        end else begin : g_padded
            assign padded = {value, {(PADW - WIDTH){1'b0}}};
        end
    endgenerate

    // ------------------------------------------------------------------------
    // Stage 1: per byte (byte 0 is the top one)
    // ------------------------------------------------------------------------
    wire [BYTES-1:0]   byte_set;
    wire [BYTES*4-1:0] byte_lz;
    genvar g;
    generate
        for (g = 0; g < BYTES; g = g + 1) begin : g_byte
            wire [7:0] bits = padded[PADW - 1 - 8 * g -: 8];
            assign byte_set[g] = |bits;
            fp_lzc #(.WIDTH(8), .COUNT_W(4)) u_lzc (.value(bits), .count(byte_lz[4 * g +: 4]));
        end
    endgenerate

    reg        [WIDTH-1:0]   s1_value;
    reg signed [11:0]        s1_base;
    reg        [BYTES-1:0]   s1_set;
    reg        [BYTES*4-1:0] s1_lz;

    always @(posedge clk) begin
        s1_value <= value;
        s1_base  <= base;
        s1_set   <= byte_set;
        s1_lz    <= byte_lz;
    end

    // ------------------------------------------------------------------------
    // Stage 2: the first byte with a bit set (a byte with one has count <= 7)
    // ------------------------------------------------------------------------
    reg [COUNT_W-1:0] lz;
    integer k;
    always @* begin
        lz = {COUNT_W{1'b0}};
        for (k = BYTES - 1; k >= 0; k = k - 1)
            if (s1_set[k]) lz = (k[COUNT_W-1:0] << 3) | {{(COUNT_W - 3){1'b0}}, s1_lz[4 * k +: 3]};
    end

    reg        [WIDTH-1:0]   s2_value;
    reg signed [11:0]        s2_base;
    reg        [COUNT_W-1:0] s2_lz;
    // Bit 3 of a byte's count is set only for a byte without a bit set,
    // which stage 2 never picks.
    wire unused_lz = ^{s1_lz};

    always @(posedge clk) begin
        s2_value <= s1_value;
        s2_base  <= s1_base;
        s2_lz    <= lz;
    end

    // ------------------------------------------------------------------------
    // Stage 3: shift; the exponent
    // ------------------------------------------------------------------------
    always @(posedge clk) begin
        y   <= s2_value << s2_lz;
        exp <= s2_base - {{(12 - COUNT_W){1'b0}}, s2_lz};
    end

endmodule
`default_nettype wire
