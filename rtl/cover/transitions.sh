#!/usr/bin/env bash
# The controller's possible state transitions, proved with Yosys SAT.
#
# For every pair (from, to) of the ISA's states (rtl/pp/isa.vh), asks
# Yosys' SAT solver whether pp_ctrl's next-state logic can give st_d = to
# while st_q = from, for some value of its inputs (configuration, pixel,
# ALU flags) and its other registers (every flip-flop is cut and its output
# left free). "no model found" is a proof that the transition cannot happen
# in any cycle; "model found" makes the pair one of the transitions the
# coverage build counts (build.rs turns the table into cover points). The
# set over-approximates the reachable transitions: a pair found here may
# need register values no pixel reaches, which docs/coverage.md argues case
# by case when no run takes it.
#
# Usage: rtl/cover/transitions.sh [OUT]   (default rtl/cover/pp_ctrl.transitions)
# TRANSITIONS_JOBS=J runs J yosys at once (default: one per core).
# Needs yosys (Debian: apt-get install yosys): one SAT call per pair of
# states (103 x 103 = 10,609).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
rtl=$(cd "$here/.." && pwd)
out=${1:-$here/pp_ctrl.transitions}
command -v yosys >/dev/null || { echo "transitions.sh: yosys is not on PATH (Debian: apt-get install yosys)" >&2; exit 2; }

# The states: `define ISA_ST_<NAME> <id>.
mapfile -t states < <(sed -n 's/^`define ISA_ST_\([A-Z0-9_]*\) *\([0-9][0-9]*\).*/\1 \2/p' "$rtl/pp/isa.vh")
[ "${#states[@]}" -gt 0 ] || { echo "transitions.sh: no ISA_ST_ states in $rtl/pp/isa.vh" >&2; exit 2; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The from-states in JOBS contiguous chunks, one yosys each (default: one
# per core); their logs, concatenated in order, read as one.
jobs=${TRANSITIONS_JOBS:-$(nproc)}
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "transitions.sh: TRANSITIONS_JOBS=$jobs is not a positive count" >&2; exit 2; }
n=${#states[@]}
per=$(( (n + jobs - 1) / jobs ))
pids=()
for ((j = 0; j * per < n; j++)); do
    {
        echo "read_verilog -I$rtl/pp -I$rtl/fp $rtl/pp/pp_ctrl.v"
        echo "prep -top pp_ctrl"
        echo "flatten"
        echo "opt_clean"
        # Cut every flip-flop: st_q and the other registers become free inputs.
        echo 'delete t:$dff t:$adff t:$sdff t:$dffe t:$adffe t:$sdffe t:$sdffce'
        for f in "${states[@]:j*per:per}"; do
            for t in "${states[@]}"; do
                echo "sat -set st_q ${f#* } -set st_d ${t#* }"
            done
        done
    } > "$tmp/script.$j.ys"
    yosys -q -l "$tmp/log.$j" -s "$tmp/script.$j.ys" >/dev/null &
    pids+=($!)
done
for pid in "${pids[@]}"; do
    wait "$pid" || { echo "transitions.sh: a yosys run failed" >&2; exit 1; }
done
for ((j = 0; j < ${#pids[@]}; j++)); do cat "$tmp/log.$j"; done > "$tmp/log"

# The log, in order: two set-constraint lines then one verdict per call.
python3 - "$tmp/log" "$out" "$rtl/pp/pp_ctrl.v" "$rtl/pp/ctrl_flow.vh" "${states[@]}" <<'PY'
import re, sys
log, out, ctrl, flow, *states = sys.argv[1:]
ids = {int(s.split()[1]): s.split()[0] for s in states}
pairs, cur = [], []
for line in open(log):
    m = re.search(r"Import set-constraint: \\(st_q|st_d) = \d+'([01]+)", line)
    if m:
        cur.append(int(m.group(2), 2))
    elif "SAT solving finished - model found" in line:
        pairs.append((cur[0], cur[1], True)); cur = []
    elif "SAT solving finished - no model found" in line:
        pairs.append((cur[0], cur[1], False)); cur = []
n = len(ids)
if len(pairs) != n * n:
    sys.exit(f"transitions.sh: {len(pairs)} verdicts in the yosys log, expected {n * n}")
# FNV-1a 64 of pp_ctrl.v and of the functions it includes: build/cover.rs
# and tests/coverage.rs refuse a table made from another controller.
def fnv1a64(path):
    digest = 0xCBF29CE484222325
    for byte in open(path, "rb").read():
        digest = ((digest ^ byte) * 0x100000001B3) % 2**64
    return f"{digest:016x}"
with open(out, "w") as f:
    f.write("# pp_ctrl's possible state transitions (st_q -> st_d), proved with Yosys SAT\n")
    f.write("# by rtl/cover/transitions.sh; every pair of ISA states not listed has no model.\n")
    f.write(f"# pp_ctrl.v fnv1a64 {fnv1a64(ctrl)}\n")
    f.write(f"# ctrl_flow.vh fnv1a64 {fnv1a64(flow)}\n")
    f.write(f"# {sum(p[2] for p in pairs)} of {n * n} pairs\n")
    for a, b, ok in pairs:
        if ok:
            f.write(f"{ids[a]} {ids[b]}\n")
print(f"{sum(p[2] for p in pairs)} of {n * n} pairs possible -> {out}")
PY
