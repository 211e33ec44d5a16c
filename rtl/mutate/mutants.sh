#!/usr/bin/env bash
# Mutants of the pixel processor, MCY-style, with Yosys' `mutate`
# (docs/mutation.md). Run from anywhere; paths are the checkout's.
#
#   rtl/mutate/mutants.sh list [COUNT [SEED]]
#       samples COUNT mutations (default 1200, seed 1) over every module of
#       the pixel processor with `mutate -list` and writes them, numbered
#       from 1, to rtl/mutate/pixel_processor.mutants with the hash of the
#       RTL they were listed on and the Yosys version.
#   rtl/mutate/mutants.sh netlist OUT.v [ID...]
#       writes one Verilog netlist carrying the listed mutants (all of them,
#       or the IDs given) behind a 16-bit input port `mutsel`: mutant ID is
#       active while mutsel == ID, and mutsel == 0 is the design as written.
#       Every module gets the port and passes it down, so a mutant of a module
#       is active in each of its instances, as a bug in its source would be.
#       Beside it, OUT.fp_add.v and the like: each float unit of the same
#       mutated design on its own (fp_add, fp_mul, fp_itof, fp_exp, fp_recip,
#       fp_sqrt, with the processor's parameters; black boxes aside), with
#       the same `mutsel`, for the judge's float-unit edge cases.
#   rtl/mutate/mutants.sh equiv ID...
#       asks Yosys, per mutant, whether the mutated module and the original
#       can differ in any output or next state for any inputs and any register
#       values (equiv_make, equiv_struct, equiv_simple, equiv_induct: every
#       flip-flop a cut point). "equivalent" is a proof that no run can tell
#       the mutant from the design; "not-proved" says some signal stands
#       unproven (it may differ, or only for register values no run reaches);
#       "timeout" that the proof took more than MUTATE_EQUIV_SECONDS (120).
#   rtl/mutate/mutants.sh miter ID...
#       asks Yosys, per mutant of a float unit (or of fp_round, fp_lzc,
#       fp_unpack: then in every unit that holds it), whether the unit's
#       OUTPUTS (y, and out_valid for the multi-cycle units) can differ for
#       any input sequence, on the unit as the judge gets it (`netlist`'s
#       OUT.<unit>.v): a miter of two copies, mutsel tied to 0 and to ID.
#       Internal signals are not compared, so a mutant of a bit no output
#       reads is equivalent. Flip-flops outside the forward cone of mutsel
#       are shared by the two copies (they compute the same function of the
#       same inputs), then `opt` merges the common logic: a mutant whose
#       logic reaches no output leaves nothing. The rest is SAT: `sat -prove`
#       for fp_add, fp_mul and fp_itof, and for fp_recip, fp_sqrt and fp_exp
#       temporal induction from the all-zero state (the reset state; the
#       datapath registers are loaded before they are read) up to
#       MUTATE_MITER_STEPS (12; 26 for the fast units, all pipelines) steps.
#       A mutant of a flip-flop's clock gets
#       clk2fflogic and a clock that toggles every step. Prints one line per
#       mutant, "ID VERDICT UNIT: DETAIL; UNIT: DETAIL ...": VERDICT over its
#       units is equivalent (DETAIL "cone": the change reaches no output, or
#       "SAT"), differs (DETAIL the counterexample: the operands, or for a
#       multi-cycle unit the `a` at each in_valid step before the difference
#       (the unit samples the first it sees idle) and the first step where y
#       differs, at out_valid or between results), timeout, or not-proved
#       (the induction did not close in MUTATE_MITER_STEPS).
#       MUTATE_MITER_SECONDS (300) bounds each Yosys run; MUTATE_MITER_KEEP=DIR
#       keeps its scripts and logs (log.ID.UNIT) in DIR.
#
# The RTL is read as the harness verilates it: `PP_TRACE` defined (the trace
# and fault ports kept), both methods exact, STACK_DEPTH the default, then
# `prep`. The prepared design is cached in $MUTATE_CACHE (default
# target/mutate/) under the hash of the RTL.
#
#   MUTATE_DESIGN=fast_pp  the fast pixel processor (rtl/fast/fast_pp.v,
#       with the exponential) instead of the compact one (pixel_processor,
#       the default): its sources add rtl/fast, its list is
#       rtl/mutate/fast_pp.mutants, its float units cut beside the netlist
#       are fast_fp_add ... fast_fp_exp, and `miter` proves on those
#       (induction to 26 steps, past their deepest pipeline).
#
#   MUTATE_BLACKBOX="fp_recip fp_sqrt"  (list) makes those modules black boxes (their
#       ports and parameters only; their RTL is compiled beside the netlist,
#       unmutated), which skips their seed tables' three minutes of
#       elaboration. Yosys names cells with a counter over the whole design,
#       so a list is only good for the design it was listed on: the smoke
#       test's list (rtl/mutate/smoke.mutants) is listed with these boxes,
#       and its header names them for netlist and equiv.
#   MUTATE_LIST=FILE  the list to write or read (default
#       rtl/mutate/pixel_processor.mutants).
#   rtl/mutate/mutants.sh hash  prints the RTL's hash (the lists' header).
# Needs yosys (Debian: apt-get install yosys) and python3.
set -euo pipefail
export LC_ALL=C  # the sources in one order everywhere (the hash)
here=$(cd "$(dirname "$0")" && pwd)
rtl=$(cd "$here/.." && pwd)
root=$(cd "$rtl/.." && pwd)
top=${MUTATE_DESIGN:-pixel_processor}
case $top in
pixel_processor)
    src_dirs="rtl/fp rtl/pp"
    units="fp_add fp_mul fp_itof fp_exp fp_recip fp_sqrt" ;;
fast_pp)
    src_dirs="rtl/fp rtl/pp rtl/fast"
    units="fast_fp_add fast_fp_mul fast_fp_itof fast_fp_exp fast_fp_recip fast_fp_sqrt" ;;
*) echo "mutants.sh: MUTATE_DESIGN '$top' is neither pixel_processor nor fast_pp" >&2; exit 2 ;;
esac
export MUTATE_UNITS=$units
list_file=${MUTATE_LIST:-$here/$top.mutants}
cache=${MUTATE_CACHE:-$root/target/mutate}
blackbox=${MUTATE_BLACKBOX:-}

die() { echo "mutants.sh: $*" >&2; exit 2; }
usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2; exit 2; }
command -v python3 >/dev/null || die "python3 is not on PATH"
need_yosys() { command -v yosys >/dev/null || die "yosys is not on PATH (Debian: apt-get install yosys)"; }

# The sources, in a fixed order, relative to the checkout (the `-src`
# attributes, and so the list, name rtl/...).
cd "$root"
sources=()
headers=()
includes=""
for d in $src_dirs; do
    sources+=("$d"/*.v)
    headers+=("$d"/*.vh)
    includes+=" -I$d"
done

# FNV-1a 64 over the names and contents of the sources and of the headers
# they include (isa.vh's state ids, the latencies of fp_defs.vh and
# fast_defs.vh): the list's RTL.
rtl_hash() {
    python3 - "${sources[@]}" "${headers[@]}" <<'PY'
import sys
h = 0xcbf29ce484222325
for path in sys.argv[1:]:
    for b in path.encode() + b"\0" + open(path, "rb").read():
        h = ((h ^ b) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
print(f"{h:016x}")
PY
}

# The prepared design (RTLIL), cached: prints its path.
design() {
    need_yosys
    local hash key il read="" f m
    hash=$(rtl_hash)
    key=$top-$hash${blackbox:+-$(echo "$blackbox" | tr ' ' '-')}
    il=$cache/design-$key.il
    if [ ! -s "$il" ]; then
        mkdir -p "$cache"
        for f in "${sources[@]}"; do
            m=${f##*/}
            m=${m%.v}
            if [[ " $blackbox " == *" $m "* ]]; then
                # The module's header (its includes, parameters and ports, up
                # to the first line that is ");") as a black box.
                python3 - "$f" > "$cache/$m.box.v" <<'PY' || die "no module header ending in ');' in $f"
import sys
text = open(sys.argv[1]).read().split("\n")
start = next(i for i, l in enumerate(text) if l.startswith("module "))
end = next(i for i, l in enumerate(text) if i > start and l == ");")
text[start] = "(* blackbox *)\n" + text[start]
print("\n".join(text[: end + 1]) + "\nendmodule")
PY
                read+=" $cache/$m.box.v"
            else
                read+=" $f"
            fi
        done
        {
            echo "read_verilog -defer -DPP_TRACE$includes$read"
            echo "hierarchy -top $top -chparam RECIP_METHOD 0 -chparam SQRT_METHOD 0"
            echo "prep -top $top"
            echo "write_rtlil $il.tmp"
        } > "$cache/prep.ys"
        if [ -z "$blackbox" ]; then
            echo "mutants.sh: preparing the design (yosys prep; about 3 minutes, the seed tables)" >&2
        fi
        yosys -q -l "$cache/prep.log" -s "$cache/prep.ys" >/dev/null || { tail -20 "$cache/prep.log" >&2; die "yosys prep failed"; }
        mv "$il.tmp" "$il"
    fi
    echo "$il"
}

# The list's mutation lines ("ID mutate ..."), all or the IDs given.
mutations() {
    [ -s "$list_file" ] || die "$list_file is missing: run rtl/mutate/mutants.sh list"
    python3 - "$list_file" "$@" <<'PY'
import sys
path, *ids = sys.argv[1:]
lines = {}
for n, line in enumerate(open(path), 1):
    if line.startswith("#") or not line.strip():
        continue
    i, _, rest = line.strip().partition(" ")
    if not i.isdigit() or not rest.startswith("mutate "):
        sys.exit(f"mutants.sh: {path}:{n}: not 'ID mutate ...': {line.strip()}")
    lines[int(i)] = rest
for i in ids:
    if not i.isdigit() or int(i) not in lines:
        sys.exit(f"mutants.sh: no mutant {i} in {path} (1..{max(lines)})")
for i in (map(int, ids) if ids else sorted(lines)):
    print(i, lines[i])
PY
}

cmd=${1:-}
[ -n "$cmd" ] || usage
# A list is read with the black boxes it was listed with.
if [ "$cmd" != list ] && [ -s "$list_file" ]; then
    blackbox=$(sed -n 's/^# black boxes: //p' "$list_file")
fi
shift
case $cmd in
hash) rtl_hash ;;
list)
    count=${1:-1200} seed=${2:-1}
    [[ $count =~ ^[1-9][0-9]*$ && $count -le 65535 ]] || die "COUNT '$count' is not in 1..65535"
    [[ $seed =~ ^[0-9]+$ ]] || die "SEED '$seed' is not a number"
    il=$(design)
    tmp=$(mktemp)
    trap 'rm -f "$tmp"' EXIT
    yosys -q -p "read_rtlil $il; mutate -list $count -seed $seed -o $tmp" >/dev/null
    unwritable=' -port (RD_ARST|RD_SRST|RD_CLK|RD_EN|WR_CLK) '
    {
        echo "# Mutants of $top (PP_TRACE, exact methods), listed by"
        echo "# ${blackbox:+MUTATE_BLACKBOX=\"$blackbox\" }${MUTATE_DESIGN:+MUTATE_DESIGN=$top }rtl/mutate/mutants.sh list $count $seed: yosys mutate -list $count -seed $seed."
        echo "# rtl fnv1a64 $(rtl_hash)"
        echo "# $(yosys -V)"
        [ -z "$blackbox" ] || echo "# black boxes: $blackbox"
        echo "# Left out: mutations of a memory's clock, read-enable or read-reset ports"
        echo "# (write_verilog cannot write such a memory; every read port of these designs"
        echo "# is asynchronous, its enable the constant 1): $(grep -cE "$unwritable" "$tmp" || true)."
        grep -vE "$unwritable" "$tmp" | awk '{ print NR, $0 }'
    } > "$list_file"
    echo "mutants.sh: $(grep -vc '^#' "$list_file") mutants in $list_file"
    ;;
netlist)
    [ $# -ge 1 ] || usage
    out=$1
    shift
    il=$(design)
    want=$(grep '^# rtl fnv1a64 ' "$list_file" | cut -d' ' -f4)
    [ "$want" = "$(rtl_hash)" ] || die "$list_file was listed on other RTL (fnv1a64 $want, now $(rtl_hash)): run rtl/mutate/mutants.sh list"
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    # mutsel into every module (black boxes aside) and down through every
    # instance of one.
    python3 - "$il" "$tmp/unbox.ys" "$tmp/units" > "$tmp/ports.ys" <<'PY'
import os, re, sys
modules, boxes, inst, cur, attrs = [], set(), [], None, []
for line in open(sys.argv[1]):
    stripped = line.strip()
    if stripped.startswith("attribute "):
        attrs.append(stripped.split()[1])
        continue
    m = re.match(r"module (\S+)", line)
    if m:
        cur = m.group(1)
        if "\\blackbox" in attrs:
            boxes.add(cur)
        else:
            modules.append(cur)
    c = re.match(r"\s+cell (\S+) (\S+)", line)
    if c and (c.group(1).startswith("\\") or c.group(1).startswith("$paramod")):
        inst.append((cur, c.group(1), c.group(2)))
    attrs = []
for m in modules:
    print(f"add -input mutsel 16 {m}")
for m, t, c in inst:
    if t not in boxes:
        print(f"cd {m}\nconnect -port {c} mutsel mutsel\ncd ..")
# A black box given parameters is a derived module, $paramod\NAME\P=V...:
# after flattening, its instances become NAME again with their parameters,
# so that the netlist instantiates the RTL module.
# Each float unit cut from the mutated design: (its module, its name).
with open(sys.argv[3], "w") as units:
    for m in modules:
        name = m.split("\\")[1] if m.startswith("$paramod") else m.lstrip("\\")
        if name in os.environ["MUTATE_UNITS"].split():
            print(m, name, file=units)
with open(sys.argv[2], "w") as unbox:
    for b in sorted(boxes):
        if not b.startswith("$paramod\\"):
            continue
        name, *params = b.split("\\")[1:]
        for p in params:
            key, _, value = p.partition("=")
            bits = value.split("'", 1)[1]
            print(f"setparam -set {key} {int(bits, 2)} t:{b}", file=unbox)
        print(f"chtype -map {b} {name}", file=unbox)
PY
    {
        echo "read_rtlil $il"
        cat "$tmp/ports.ys"
        mutations "$@" | while read -r id mut; do echo "${mut%% -src*} -ctrl mutsel 16 $id"; done
        # $pmux as trees of $mux: write_verilog makes a wide $pmux (fp_exp's
        # table) a function that Verilator expands into tens of MB of C++.
        echo "pmuxtree"
        echo "design -save mutated"
        # The float units, one netlist each, their top renamed to the RTL's
        # module name (fp_recip, not its derived $paramod name).
        while read -r module name; do
            echo "design -load mutated"
            echo "hierarchy -top $module"
            echo "flatten"
            [ "$module" = "$name" ] || [ "$module" = "\\$name" ] || echo "rename $module $name"
            echo "opt_clean"
            echo "splitnets -driver"
            echo "write_verilog -noattr ${out%.v}.$name.v"
        done < "$tmp/units"
        echo "design -load mutated"
        # One module, its wires driven bit by bit by different cells split:
        # whole, or passing through ports, Verilator sees loops through them
        # (UNOPTFLAT) and settles them by iterating, 50 times slower.
        echo "flatten"
        echo "hierarchy -top $top"
        cat "$tmp/unbox.ys"
        echo "opt_clean"
        echo "splitnets -driver"
        echo "write_verilog -noattr $out"
    } > "$tmp/netlist.ys"
    yosys -q -l "$tmp/log" -s "$tmp/netlist.ys" >/dev/null || { tail -20 "$tmp/log" >&2; die "yosys failed making the netlist"; }
    echo "mutants.sh: $(mutations "$@" | wc -l) mutants behind mutsel in $out"
    ;;
equiv)
    [ $# -ge 1 ] || usage
    il=$(design)
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    limit=${MUTATE_EQUIV_SECONDS:-120}
    [[ $limit =~ ^[1-9][0-9]*$ ]] || die "MUTATE_EQUIV_SECONDS '$limit' is not a number of seconds"
    # Memories as flip-flops, asynchronous resets as synchronous: cells the
    # equiv_ passes know.
    yosys -q -p "read_rtlil $il; memory_map; async2sync; write_rtlil $tmp/mapped.il" >/dev/null ||
        die "yosys failed mapping the design's memories"
    # Per mutant, Yosys with a time limit: the mutated module's hierarchy
    # and a mutated copy, paired signal by signal (equiv_make: registers of
    # the same name are cut points, so the proof holds for any register
    # values), structurally merged where equal (equiv_struct), the rest
    # proved by SAT (equiv_simple, equiv_induct). First with the submodules
    # kept as instances (the same unmutated module in both, merged once
    # their inputs are proved equal: seconds even for the ALU, whose float
    # units would otherwise be flattened in), then, if that does not prove
    # it, flattened (a submodule that ignores what the mutant changes).
    # Prints "ID equivalent", "ID not-proved" (some signal stands unproven:
    # it may differ, or differ only for register values no run reaches) or
    # "ID timeout" (the flattened proof ran out of time).
    # prove FLATTEN MODULE MUTATION: 0 proved, 1 not proved, 124 timeout.
    prove() {
        local flatten=$1 module=$2 mut=$3 status=0
        {
            echo "read_rtlil $tmp/mapped.il"
            echo "hierarchy -top $module"
            echo "copy $module mutant_gate"
            echo "${mut/ -module $module / -module mutant_gate }"
            [ "$flatten" = 0 ] || echo "flatten $module mutant_gate"
            echo "equiv_make $module mutant_gate mutant_equiv"
            echo "hierarchy -top mutant_equiv"
            echo "equiv_struct"
            echo "equiv_simple -seq 2"
            echo "equiv_induct -seq 2"
            echo "equiv_status"
        } > "$tmp/equiv.ys"
        timeout "$limit" yosys -q -l "$tmp/log" -s "$tmp/equiv.ys" >/dev/null 2>&1 || status=$?
        if [ "$status" -eq 124 ]; then
            return 124
        elif [ "$status" -ne 0 ]; then
            tail -20 "$tmp/log" >&2
            die "yosys failed on the equivalence of mutant $id"
        elif grep -q "Equivalence successfully proven" "$tmp/log"; then
            return 0
        elif grep -qE "Found [0-9]+ unproven" "$tmp/log"; then
            return 1
        fi
        die "mutant $id: no equiv_status verdict in Yosys' log"
    }
    mutations "$@" | while read -r id mut; do
        module=$(sed -E 's/.* -module ([^ ]+) .*/\1/' <<<"$mut")
        mut=${mut%% -src*}
        # A mutation of a memory's port names a memory cell, which
        # memory_map (above) has turned into flip-flops: not proved here.
        cell=$(sed -E 's/.* -cell ([^ ]+).*/\1/' <<<"$mut")
        if grep -qxF "  cell \$mem_v2 \\$cell" "$il"; then
            echo "mutant $id: a port of memory $cell: equiv maps memories to flip-flops, so it cannot apply this mutation" >&2
            echo "$id not-proved"
            continue
        fi
        status=0
        prove 0 "$module" "$mut" || prove 1 "$module" "$mut" || status=$?
        case $status in
        0) echo "$id equivalent" ;;
        124) echo "$id timeout" ;;
        *) echo "$id not-proved" ;;
        esac
    done
    ;;
miter)
    [ $# -ge 1 ] || usage
    limit=${MUTATE_MITER_SECONDS:-300}
    # Induction must outrun a pipeline: the fast units' longest is 22 deep.
    case $top in fast_pp) steps=${MUTATE_MITER_STEPS:-26} ;; *) steps=${MUTATE_MITER_STEPS:-12} ;; esac
    [[ $limit =~ ^[1-9][0-9]*$ ]] || die "MUTATE_MITER_SECONDS '$limit' is not a number of seconds"
    [[ $steps =~ ^[1-9][0-9]*$ ]] || die "MUTATE_MITER_STEPS '$steps' is not a number of steps"
    il=$(design)
    if [ -n "${MUTATE_MITER_KEEP:-}" ]; then
        tmp=$MUTATE_MITER_KEEP
        mkdir -p "$tmp"
    else
        tmp=$(mktemp -d)
        trap 'rm -rf "$tmp"' EXIT
    fi
    # The float units cut from the mutated design, as the judge gets them.
    "$0" netlist "$tmp/n.v" "$@" >/dev/null
    # Which float units (the judge's: fp_add ... fp_exp, or the fast
    # processor's fast_fp_add ... fast_fp_exp) hold each module, as
    # themselves or through their submodules (fp_round, fp_lzc, ...).
    python3 - "$il" > "$tmp/units" <<'PY'
import os, re, sys
units = tuple(os.environ["MUTATE_UNITS"].split())
children, cur = {}, None
for line in open(sys.argv[1]):
    m = re.match(r"module (\S+)", line)
    if m:
        cur = m.group(1).lstrip("\\")
        children[cur] = set()
    c = re.match(r"\s+cell (\S+) ", line)
    if c and (not c.group(1).startswith("$") or c.group(1).startswith("$paramod")):
        children[cur].add(c.group(1).lstrip("\\"))
def below(m):
    out = {m}
    for c in children.get(m, ()):
        out |= below(c)
    return out
name = lambda m: m.split("\\")[1] if m.startswith("$paramod") else m
for m in children:
    print(m, *sorted(name(u) for u in children if name(u) in units and m in below(u)))
PY
    # miter_unit ID UNIT CLK: proves the unit's outputs equal with mutsel 0
    # and mutsel ID. Prints "equivalent DETAIL", "differs INPUTS",
    # "not-proved DETAIL" or "timeout".
    miter_unit() {
        local id=$1 unit=$2 clk=$3 status=0 seq=0 log=$tmp/log.$1.$2
        # The multi-cycle units and the pipelines hold state: induction.
        case $unit in fp_recip | fp_sqrt | fp_exp | fast_fp_*) seq=1 ;; esac
        # The toggled clock below is wired to the multi-cycle units' ports.
        case $unit:$clk in fast_fp_*:1) echo "not-proved $unit: a mutant of a pipeline's clock (the miter drives the multi-cycle units' clock only)"; return ;; esac
        # The unit as the judge gets it, its ROM as logic, and every flip-flop
        # outside the forward cone of mutsel marked: those compute the same
        # function of the same inputs in both copies, so they are shared.
        {
            echo "read_verilog $tmp/n.$unit.v"
            echo "hierarchy -top $unit"
            echo "proc"
            echo "memory"
            # A mutant of a clock: flip-flops on a global clock, and the
            # unit's clock a toggle (below), so that either edge counts.
            if [ "$clk" = 1 ]; then echo "clk2fflogic"; else echo "async2sync"; fi
            echo "opt_clean"
            echo "autoname"
            echo "setattr -set mutant_shared 1 t:\$*dff* t:\$ff %u w:mutsel %co* %d"
            echo "write_rtlil $tmp/work.il"
        } > "$tmp/work.ys"
        timeout "$limit" yosys -q -l "$log" -s "$tmp/work.ys" >/dev/null 2>&1 || status=$?
        [ "$status" -ne 124 ] || { echo "timeout $unit: ${limit} s"; return; }
        [ "$status" -eq 0 ] || { tail -20 "$log" >&2; die "yosys failed preparing the miter of mutant $id in $unit"; }
        # gate.Q := gold.Q for each shared flip-flop (its gate copy then
        # drives nothing and goes).
        python3 - "$tmp/work.il" > "$tmp/shared.ys" <<'PY'
import re, sys
attrs, cell, out = [], None, []
for line in open(sys.argv[1]):
    s = line.strip()
    if s.startswith("attribute "):
        attrs.append(s.split()[1])
        continue
    if s.startswith("cell "):
        cell = "\\mutant_shared" in attrs
    elif cell and s.startswith("connect \\Q "):
        sig = s[len("connect \\Q "):]
        for name, hi, lo in re.findall(r"\\(\S+)(?: \[(\d+)(?::(\d+))?\])?", sig):
            rng = f"[{hi}:{lo or hi}]" if hi else ""
            out.append(f"connect -set gate.{name}{rng} gold.{name}{rng}")
    elif s == "end":
        cell = None
    attrs = []
print("\n".join(out))
PY
        {
            echo "read_rtlil $tmp/work.il"
            echo "rename $unit gold"
            echo "copy gold gate"
            echo "delete -port gold/w:mutsel gate/w:mutsel"
            echo "cd gold"
            echo "connect -set mutsel 16'd0"
            echo "cd .."
            echo "cd gate"
            echo "connect -set mutsel 16'd$id"
            echo "cd .."
            echo "miter -equiv -flatten -make_outputs -ignore_gold_x gold gate miter"
            echo "hierarchy -top miter"
            echo "cd miter"
            cat "$tmp/shared.ys"
            echo "cd .."
            if [ "$clk" = 1 ]; then
                # The clock as the harness drives it: a toggle, one edge per
                # step (from 0, so steps 2, 4, ... are rising edges).
                echo "read_rtlil $tmp/clock.il"
                echo "hierarchy -top clocked"
                echo "flatten"
                echo "hierarchy -top clocked"
                echo "rename clocked miter"
            fi
            echo "opt -full"
            echo "opt_clean -purge"
            echo "tee -q -o $tmp/cells select -count miter/w:trigger %ci* miter/c:* %i"
            if [ "$seq" = 1 ]; then
                echo "sat -tempinduct -prove trigger 0 -set-init-zero -maxsteps $steps -show-inputs -show-outputs"
            else
                echo "sat -prove trigger 0 -show-inputs -show-outputs"
            fi
        } > "$tmp/miter.ys"
        [ "$clk" = 0 ] || cat > "$tmp/clock.il" <<'IL'
module \clocked
  wire input 1 \in_rst_n
  wire input 2 \in_in_valid
  wire width 32 input 3 \in_a
  wire output 4 \trigger
  wire \clk
  wire \clk_n
  cell $ff $clock
    parameter \WIDTH 1
    connect \D \clk_n
    connect \Q \clk
  end
  cell $not $clock_n
    parameter \A_SIGNED 0
    parameter \A_WIDTH 1
    parameter \Y_WIDTH 1
    connect \A \clk
    connect \Y \clk_n
  end
  cell \miter \unit
    connect \in_clk \clk
    connect \in_rst_n \in_rst_n
    connect \in_in_valid \in_in_valid
    connect \in_a \in_a
    connect \trigger \trigger
  end
end
IL
        status=0
        timeout "$limit" yosys -q -l "$log" -s "$tmp/miter.ys" >/dev/null 2>&1 || status=$?
        [ "$status" -ne 124 ] || { echo "timeout $unit: ${limit} s"; return; }
        [ "$status" -eq 0 ] || { tail -20 "$log" >&2; die "yosys failed on the miter of mutant $id in $unit"; }
        if grep -qE "no model found: SUCCESS|Induction step proven: SUCCESS" "$log"; then
            if grep -q "^0 objects" "$tmp/cells"; then
                echo "equivalent $unit: cone (the change reaches no output: nothing left of the miter)"
            else
                echo "equivalent $unit: SAT"
            fi
        elif grep -qE "model found: FAIL|model found for base case: FAIL" "$log"; then
            python3 - "$log" "$unit" <<'PY'
import re, sys
rows, outs = {}, {}
for line in open(sys.argv[1]):
    m = re.match(r"\s+(\d+|\S*)\s+\\(in|gold|gate)_(\S+)\s+\S+\s+([0-9a-fA-Fx]+)\s+[01x]+\s*$", line)
    if m:
        t = m.group(1) or "0"
        if not t.isdigit():
            continue  # the initial state's row ("init"): zero
        if m.group(2) == "in":
            rows.setdefault(t, {})[m.group(3)] = m.group(4)
        else:
            outs.setdefault(t, {})[m.group(2) + "_" + m.group(3)] = m.group(4)
steps = sorted(rows, key=int)
if len(steps) <= 1:
    r = rows.get(steps[0], {}) if steps else {}
    o = outs.get(steps[0], {}) if steps else {}
    print("differs " + sys.argv[2] + ": " + " ".join(f"{k}=0x{v}" for k, v in sorted(r.items()))
          + f" (y 0x{o.get('gold_y', '?')}, mutant 0x{o.get('gate_y', '?')})")
else:
    # The first step where an output differs, and whether out_valid is up.
    bad = next((t for t in sorted(outs, key=int)
                if any(outs[t].get("gold_" + k) != outs[t].get("gate_" + k) for k in ("y", "out_valid"))), None)
    o = outs.get(bad, {})
    pipeline = all("in_valid" not in rows[t] for t in steps)
    if pipeline:
        # A pipeline (a fast unit): an operation enters every step.
        where = ""
        ops = [f"step {t}: " + " ".join(f"{k}=0x{v}" for k, v in sorted(rows[t].items()))
               for t in steps if int(t) < int(bad or 0)]
    else:
        where = ("at out_valid" if o.get("gold_out_valid") == "1" else "between results (out_valid low)")
        ops = [f"step {t}: a=0x{rows[t].get('a', '?')}" for t in steps
               if rows[t].get("in_valid") == "1" and rows[t].get("rst_n") == "1" and int(t) < int(bad or 0)]
    resets = [t for t in steps if rows[t].get("rst_n") == "0" and int(t) < int(bad or 0)]
    print("differs " + sys.argv[2] + " from zero state: " + ("" if pipeline else "in_valid ") + ", ".join(ops)
          + (f"; rst_n low at {','.join(resets)}" if resets else "")
          + f"; step {bad}: y 0x{o.get('gold_y', '?')}, mutant 0x{o.get('gate_y', '?')} {where}")
PY
        else
            echo "not-proved $unit: induction did not close in $steps steps"
        fi
    }
    mutations "$@" | while read -r id mut; do
        module=$(sed -E 's/.* -module ([^ ]+) .*/\1/' <<<"$mut")
        module=${module#\\}
        clk=0
        [[ $mut != *" -port CLK "* ]] || clk=1
        units=$(M=$module awk '$1 == ENVIRON["M"] { $1 = ""; print }' "$tmp/units")
        [ -n "${units// /}" ] || { echo "$id not-a-float-unit $module"; continue; }
        verdict=equivalent details=()
        for unit in $units; do
            r=$(miter_unit "$id" "$unit" "$clk")
            details+=("${r#* }")
            case $r in
            differs*) verdict=differs ;;
            timeout*) [ "$verdict" = differs ] || verdict=timeout ;;
            not-proved*) [ "$verdict" != equivalent ] || verdict=not-proved ;;
            esac
        done
        echo "$id $verdict $(printf '%s; ' "${details[@]}" | sed 's/; $//')"
    done
    ;;
*) usage ;;
esac
