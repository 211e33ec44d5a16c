#!/usr/bin/env bash
# rtl/synth/equiv_lzc.sh -- prove rtl/fp/fp_lzc.v (a priority select) equal to
# the counting loop it replaced, for every (WIDTH, COUNT_W) the RTL
# instantiates (docs/rtl.md, "Synthesis"). Run from the repository root:
#
#   rtl/synth/equiv_lzc.sh
#
# For each pair, Yosys builds a miter of the two (miter -equiv: one output,
# high when the counts differ for some value) and SAT proves that output 0
# for all 2^WIDTH values (sat -prove, a proof, not a sample). A negative
# control then proves the same miter against a mutant of fp_lzc.v whose
# all-zero count is off by one (one input value of 2^WIDTH) and must find
# the counterexample. Exit status 0 only if every proof holds and the
# mutant fails. Not in CI (Yosys is not); YOSYS names the binary.
set -euo pipefail
yosys=${YOSYS:-yosys}
dir=target/synth/equiv-lzc
mkdir -p "$dir"

# The reference: fp_lzc.v's loop up to commit f47ab34, renamed.
cat >"$dir/fp_lzc_count.v" <<'V'
module fp_lzc_count #(
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
V

# The mutant for the negative control: an all-zero value counts WIDTH - 1.
sed 's/count = ALL_ZERO;/count = TOP;/' rtl/fp/fp_lzc.v >"$dir/fp_lzc_mutant.v"
if cmp -s rtl/fp/fp_lzc.v "$dir/fp_lzc_mutant.v"; then
    echo "$0: could not make the mutant (fp_lzc.v has no 'count = ALL_ZERO;')" >&2
    exit 1
fi

# The pairs: every fp_lzc instance under rtl/ (fp_itof, fp_add, fp_mul, fp_unpack).
pairs=$(grep -rhoE 'fp_lzc #\(\.WIDTH\([0-9]+\), \.COUNT_W\([0-9]+\)\)' rtl |
    sed -E 's/.*WIDTH\(([0-9]+)\), \.COUNT_W\(([0-9]+)\).*/\1:\2/' | sort -u -t: -k1,1n)
[ -n "$pairs" ] || { echo "$0: found no fp_lzc instance under rtl/" >&2; exit 1; }

# prove <design file> <width> <count_w>: 0 if the miter's trigger is proved 0.
prove() {
    "$yosys" -q -l "$dir/$(basename "$1" .v)-$2-$3.log" -p "
        read_verilog $1; read_verilog $dir/fp_lzc_count.v
        chparam -set WIDTH $2 -set COUNT_W $3 fp_lzc fp_lzc_count
        proc; opt_clean
        miter -equiv -flatten -make_outputs fp_lzc_count fp_lzc miter
        hierarchy -top miter
        sat -verify -prove trigger 0 -show-inputs -show-outputs miter" >/dev/null 2>&1
}

status=0
for p in $pairs; do
    w=${p%:*} c=${p#*:}
    if prove rtl/fp/fp_lzc.v "$w" "$c"; then
        echo "WIDTH=$w COUNT_W=$c: equal for all 2^$w values (proved)"
    else
        echo "WIDTH=$w COUNT_W=$c: NOT equal, see $dir/fp_lzc-$w-$c.log"
        status=1
    fi
    # The mutant must fail by a counterexample, not by a Yosys error.
    if prove "$dir/fp_lzc_mutant.v" "$w" "$c"; then
        echo "WIDTH=$w COUNT_W=$c: negative control FAILED: the mutant was proved equal"
        status=1
    elif grep -q "model found: FAIL" "$dir/fp_lzc_mutant-$w-$c.log"; then
        echo "WIDTH=$w COUNT_W=$c: negative control: the mutant is refused, as it must be"
    else
        echo "WIDTH=$w COUNT_W=$c: negative control did not run, see $dir/fp_lzc_mutant-$w-$c.log"
        status=1
    fi
done
exit $status
