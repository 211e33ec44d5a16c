// The stimulus of the processor and top testbenches (pp_tb.v, top_tb.v,
// fast_pp_tb.v, fast_top_tb.v), included inside the module after their
// `writes` and `pixels` arrays: the scene-port writes and the pixel
// coordinates the Rust test wrote ($readmemh), named by plusargs.

reg [1023:0] scene_file, pixel_file;
integer      n_writes, n_pixels;

// +scene=FILE +writes=N +pixels=FILE +count=M into `writes` and `pixels`;
// without them, the usage (with the testbench's own options, `more`) and
// the end of the simulation.
task load_stimulus(input [8*64-1:0] more);
    begin
        if (!$value$plusargs("scene=%s", scene_file) || !$value$plusargs("writes=%d", n_writes) ||
            !$value$plusargs("pixels=%s", pixel_file) || !$value$plusargs("count=%d", n_pixels)) begin
            $display("ERROR: usage: +scene=FILE +writes=N +pixels=FILE +count=M%0s", more);
            $finish;
        end
        $readmemh(scene_file, writes, 0, n_writes - 1);
        $readmemh(pixel_file, pixels, 0, n_pixels - 1);
    end
endtask
