#!/usr/bin/env bash
# Verilator's and the C++ compiler's speed levers on the pixel processor
# (docs/perf.md, "Verilator's speed levers"), measured in one run with the
# bare clock loop (bare_main.cpp, harness/design/cpp/bare.h) on the same pixels:
# every lever is built first, then each round runs every build in turn, so
# a drift of the shared machine's speed spreads over all of them. Prints a
# table of each lever's median M RTL cycles/s and its speed against the
# baseline, the flags build.rs uses. Run from the repository root:
#
#   benches/levers/levers.sh [SCENE] [WxH] [ROUNDS] [LEVER ...]
#
# Defaults: reference 160x120 5, every lever. Builds land in target/levers/.
# The profile-guided levers train on PGO_TRAIN (default mirror) at WxH.
# Verilator from PATH or VERILATOR_ROOT; the scene writes come from
# `cargo run --release --example scene_writes`.
set -euo pipefail
cd "$(dirname "$0")/../.."

scene=${1:-reference} size=${2:-160x120} rounds=${3:-5}
shift $(($# < 3 ? $# : 3))
case $size in
*x*) width=${size%x*} height=${size#*x} ;;
*) echo "$0: size '$size' is not WxH" >&2; exit 2 ;;
esac
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "$0: rounds '$rounds' is not a positive number" >&2; exit 2; }

verilator=verilator
[ -n "${VERILATOR_ROOT:-}" ] && verilator=$VERILATOR_ROOT/bin/verilator
command -v "$verilator" >/dev/null || { echo "$0: no verilator (PATH or VERILATOR_ROOT)" >&2; exit 2; }

out=target/levers
mkdir -p "$out"
cargo run --release --quiet --example scene_writes -- "$scene" "$size" >"$out/writes.txt"
# Profile-guided builds train on another scene (PGO_TRAIN, default mirror),
# so that they are not measured on what they were trained on.
train=${PGO_TRAIN:-mirror}
cargo run --release --quiet --example scene_writes -- "$train" "$size" >"$out/train.txt"

# What build.rs does: Verilator -O3, X's fast, the model's code at -O2 and
# its slow (once-run) code at -O0.
base="-O3 --x-assign fast --x-initial fast"
# name | Verilator flags | OPT_FAST | OPT_SLOW
all_levers=(
    "baseline|$base|-O2|-O0"
    "gcc-O3|$base|-O3|-O0"
    "gcc-Os|$base|-Os|-O0"
    "march-native|$base|-O2 -march=native|-O0"
    "pgo|$base|-O2|-O0"
    "pgo-O3|$base|-O3|-O0"
    "verilator-O0|-O0 --x-assign fast --x-initial fast|-O2|-O0"
    "x-default|-O3|-O2|-O0"
    "fno-table|$base -fno-table|-O2|-O0"
    "fno-dfg|$base -fno-dfg|-O2|-O0"
    "fno-inline|$base -fno-inline|-O2|-O0"
    "fno-life|$base -fno-life|-O2|-O0"
    "fno-merge-cond|$base -fno-merge-cond|-O2|-O0"
    "fno-expand|$base -fno-expand|-O2|-O0"
)
levers=()
if [ $# -eq 0 ]; then
    levers=("${all_levers[@]}")
else
    for want in baseline "$@"; do
        found=
        for l in "${all_levers[@]}"; do [ "${l%%|*}" = "$want" ] && found=$l; done
        [ -n "$found" ] || { echo "$0: no lever '$want' (levers: $(printf '%s ' "${all_levers[@]%%|*}"))" >&2; exit 2; }
        [[ " ${levers[*]%%|*} " == *" $want "* ]] || levers+=("$found")
    done
fi

# Builds lever $1 with Verilator flags $2, OPT_FAST $3, OPT_SLOW $4 (extra
# CFLAGS in $5) into $out/$1; prints the executable's path.
build() {
    local name=$1 vflags=$2 fast=$3 slow=$4 cflags=${5:-}
    local dir=$out/$name
    local extra=()
    [ -z "$cflags" ] || extra=(-LDFLAGS "$cflags")
    rm -rf "$dir"
    # shellcheck disable=SC2086
    { "$verilator" --cc --exe $vflags --no-timing -Wno-fatal \
        --top-module pixel_processor --prefix Vpp -Mdir "$dir" \
        -Irtl/pp -Irtl/fp -DPP_TRACE -GRECIP_METHOD=0 -GSQRT_METHOD=0 \
        -CFLAGS "-std=c++17 -I$PWD/harness/design/cpp $cflags" "${extra[@]}" \
        rtl/pp/*.v rtl/fp/*.v "$PWD/benches/levers/bare_main.cpp" &&
        make -s -j 2 -C "$dir" -f Vpp.mk "OPT_FAST=$fast" "OPT_SLOW=$slow" "OPT_GLOBAL=-O2"; } \
        >"$dir.log" 2>&1 || { echo "$0: building $name failed, see $dir.log" >&2; exit 1; }
    echo "$dir/Vpp"
}

declare -A exe
for l in "${levers[@]}"; do
    IFS='|' read -r name vflags fast slow <<<"$l"
    echo "building $name" >&2
    if [[ $name == pgo* ]]; then
        # g++ profile-guided: instrument, train on the training scene,
        # rebuild with the profile.
        prof=$PWD/$out/$name.profile
        rm -rf "$prof"
        # Both builds in the same directory: gcc finds a profile by the
        # object file's path.
        gen=$(build "$name" "$vflags" "$fast" "$slow" "-fprofile-generate -fprofile-dir=$prof")
        "$gen" "$out/train.txt" "$width" "$height" 1 >/dev/null
        exe[$name]=$(build "$name" "$vflags" "$fast" "$slow" "-fprofile-use -fprofile-dir=$prof -fprofile-partial-training -Wno-missing-profile")
    else
        exe[$name]=$(build "$name" "$vflags" "$fast" "$slow")
    fi
done

declare -A runs
for r in $(seq "$rounds"); do
    echo "round $r of $rounds" >&2
    for l in "${levers[@]}"; do
        name=${l%%|*}
        runs[$name]+="$("${exe[$name]}" "$out/writes.txt" "$width" "$height" 1) "$'\n'
    done
done

# Median seconds of a lever's runs; every run must have the same cycles.
median() {
    printf '%s' "${runs[$1]}" | awk 'NF == 2 { print }' | sort -k2 -g | awk -v name="$1" '
        { c[NR] = $1; s[NR] = $2 }
        END {
            for (i = 2; i <= NR; i++) if (c[i] != c[1]) { print name ": runs disagree on cycles" > "/dev/stderr"; exit 1 }
            print c[1], s[int((NR + 1) / 2)]
        }'
}
read -r base_cycles base_s < <(median baseline)
[[ ${base_cycles:-} =~ ^[0-9]+$ ]] || { echo "$0: no baseline runs" >&2; exit 1; }
echo "$scene $size: $((width * height)) pixels, $base_cycles RTL cycles a run; median of $rounds rounds, one thread"
echo "| lever | Verilator | OPT_FAST | M RTL cycles/s | speed / baseline |"
echo "|---|---|---|---|---|"
for l in "${levers[@]}"; do
    IFS='|' read -r name vflags fast slow <<<"$l"
    read -r cycles s < <(median "$name")
    [ "$cycles" = "$base_cycles" ] || { echo "$0: $name ran $cycles cycles, the baseline $base_cycles" >&2; exit 1; }
    awk -v n="$name" -v v="$vflags" -v f="$fast" -v c="$cycles" -v s="$s" -v b="$base_s" \
        'BEGIN { printf "| %s | `%s` | `%s` | %.3f | %.3f |\n", n, v, f, c / s / 1e6, b / s }'
done
