// The clock of the Icarus testbenches (pp_tb.v, top_tb.v), included inside
// the module: the drivers' cycle contract (harness/cpp/pixel_proc.cpp,
// top.cpp) in Verilog. Expects `reg clk`.

// clk low, settled: the outputs are this cycle's, and the inputs may
// change.
task fall;
    begin
        clk = 1'b0;
        #5;
    end
endtask

// The rising edge, after the inputs set since fall have settled (an
// input changed in the time step of the edge would race it).
task rise;
    begin
        #5;
        clk = 1'b1;
        #5;
    end
endtask
