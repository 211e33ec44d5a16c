#!/bin/bash
# How the run time divides with the shard count (docs/scale.md): the shards
# of N = 1, 2, 4 run one after another, each on one thread (a one-CPU array
# task), and each shard's wall time is printed; then the merge of the N = 4
# shards, and whether it equals the unsharded (N = 1) outputs.
#   bash docs/scale/measure.sh [RTCOSIM] [WORKDIR]
set -euo pipefail
RTCOSIM=${1:-rtcosim}
WORK=${2:-$(mktemp -d)}
SWEEP=(sweep --scenes reference,mirror,box_room --size 200x150 --depths 1,2,4,8 --cutoffs 0 --threads 1)
FUZZ=(fuzz --seed 1 --count 2000 --threads 1 --failures "$WORK/failures")
seconds() { /usr/bin/time -f %e "$@" 2>&1 >/dev/null | tail -1; }
for tool in sweep fuzz; do
    if [ $tool = sweep ]; then args=("${SWEEP[@]}"); else args=("${FUZZ[@]}"); fi
    for n in 1 2 4; do
        times=()
        for ((k = 0; k < n; k++)); do
            times+=("$(seconds "$RTCOSIM" "${args[@]}" --out "$WORK/$tool-$n" --shard $k/$n)")
        done
        echo "$tool N=$n: shard wall times ${times[*]} s"
    done
    echo "$tool merge of N=4: $(seconds "$RTCOSIM" merge "$WORK/$tool-4" --out "$WORK/$tool-merged-4") s"
    "$RTCOSIM" merge "$WORK/$tool-1" --out "$WORK/$tool-merged-1" >/dev/null 2>&1
    for f in "$WORK/$tool-merged-1"/*; do
        cmp -s "$f" "$WORK/$tool-merged-4/$(basename "$f")" || { echo "$tool: $(basename "$f") differs"; exit 1; }
    done
    echo "$tool: the merges of N=1 and N=4 are identical ($(ls "$WORK/$tool-merged-4" | tr '\n' ' '))"
done
