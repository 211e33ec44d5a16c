#!/usr/bin/env python3
"""rtl/cover/untoggled.py -- the fast processor's untoggled bits, by cause.

    python3 rtl/cover/untoggled.py DIR/coverage.dat [--list]

Reads a Verilator coverage.dat (`rtcosim coverage ... --out DIR` writes
the merged one), takes every toggle point of the fast processor
(hierarchy TOP.fast_pp...) that never toggled, and puts each in the first
class below whose hierarchy and signal patterns it matches; prints the
count per class and every bit no class explains ("unexplained"). --list
prints each class's signals too. docs/coverage.md, "Untoggled bits of the
fast processor", states the figures and the argument behind each class.
Exits 1 if any bit is unexplained.
"""
import re
import sys
from collections import Counter, OrderedDict, defaultdict

# (class, why, hierarchy regex, signal regex). First match wins. The
# hierarchy has array indices replaced by [*].
CLASSES = [
    ("fault",
     "the self-test fault port: zero unless --fault injects a flip",
     r"^TOP\.fast_pp$", r"^(wd_flip|fault_xor|fault_state)$"),
    ("special",
     "special results (NaN, infinity, zero payloads) and the side bands "
     "that carry them: no valid scene produces one inside the processor; "
     "the units' own checks drive them (docs/fast.md)",
     r"\.(u_add|u_mul|u_recip|u_sqrt|g_exp\.u_exp|u_round)(\.|$)|\.u_alu\.\*\.u_round$",
     r"(special|^ovr_y$|^s[12]_ovr_y$|^s5_side$)"),
    ("special",
     "",
     r"\.(u_add\.u_side|u_mul\.u_side[35]|u_recip\.u_side14|u_sqrt\.u_side19|u_exp\.u_special17)$",
     r"^[dq]$"),
    ("coordinates",
     "pixel coordinates, their index and their conversion to float above "
     "the largest image run (x < 128, y < 64 in the fuzzer and the "
     "directed scenes; the 80x60 builtins): bits only larger images set "
     "(sides up to 4,096), and the index bits above 2^24, which no image "
     "reaches",
     r"^TOP\.fast_pp(\.u_alu)?$",
     r"^(ix|s[12]_ix|in_ix|itof_[xy](_al)?|head_[xy]|in_[xy]|inq|out_[xy]|"
     r"trace_p[xy]|trace_take_p[xy]|turn_p[xy]|res_tag)$"),
    ("coordinates", "",
     r"\.u_alu\.(u_itof_\*|u_itof_\*\.u_norm)$", r".*"),
    ("coordinates", "",
     r"\.(u_alu\.u_itof_al|u_to_res)$", r"^[dq]$"),
    ("counters",
     "cycle counters' high bits (a run of 2^19 cycles or a pixel of 2^16 "
     "cycles never happens here) and a pixel's cycle count's low 5 bits, "
     "the same for every pixel (a context's turn comes every 32 cycles)",
     r"^TOP\.fast_pp$", r"^(now_q|turn_taken|w_taken|out_cycles)$"),
    ("encodings",
     "fields wider than the codes they carry: state ids (below 128 of 512), "
     "opcodes and ALU controls (the top bit unused), the mapped lane word "
     "(la_w[5]), the configuration word's spare bits, the output queue's "
     "count and flags (never more than one result waits), the negation the "
     "program never issues (NEG), and in colour words (out_rgb, the "
     "exponential's exp_al) the sign (a colour is never negative) and the "
     "exponent's top bit where it stays below 2.0",
     r"^TOP\.fast_pp(\.u_alu(\.u_decode)?|\.u_ctrl(\.u_map\*)?)?$",
     r"^(state|back_state|trace_state|op|in_op|dec_ctrl|s1_ctrl|ctrl|packed_ctrl|"
     r"neg_a|la_w|cfg|cfg_q|unused_cfg|held_q|outq_many|outq_n|out_rgb|exp_al)$"),
    ("encodings", "",
     r"\.u_to_back$|\.u_alu\.u_side$|\.u_exp_al$", r"^[dq]$"),
    ("controller records",
     "the controller's packed per-stage records (next states, jump targets "
     "by state id, operand descriptors of register addresses, unwinding "
     "plans) and the delay lines that carry them: the bits of state ids "
     "and addresses that no state or register of the program reaches",
     r"^TOP\.fast_pp\.u_ctrl$", r".*"),
    ("controller records", "",
     r"\.u_ctrl\.u_carry[12]$|^TOP\.fast_pp\.u_to_alu$", r"^[dq]$"),
    ("exponent guards",
     "guard bits of the 12-bit exponent arithmetic (sign and overflow) "
     "that in-range operands never set",
     r"\.u_alu(\.|$)",
     r"^(base|s[12]_base|s4_base|exp_sum|s5_exp|s19_exp|w_exp|norm_exp|s17_exp|exp)$"),
    ("exponential internals",
     "bits of fp_exp's argument reduction and polynomial terms that the "
     "scenes' exposures (colour times 2^e, a narrow argument range) never "
     "set; fast_fp_exp is proven over all 2^32 inputs alone (docs/fast.md)",
     r"\.g_exp\.u_exp$", r".*"),
    ("datapath guards",
     "guard, sticky and carry bits of the units' internal products that "
     "stay constant for every operand the scenes give; each unit is checked "
     "alone over its edge cases and exhaustively where unary (docs/fast.md)",
     r"\.u_alu\.", r"^(s3_big_sig|small_sig0|byte_lz|s1_lz|s2_lz|padded|"
     r"y0_corr|s9_hi|m_y1|s13_hi|s7_y0_sq|s9_t|s15_sticky|s19_sticky)$"),
    ("datapath guards", "",
     r"\.u_sqrt\.g_exact\.u_bounds$", r"^[dq]$"),
]


def points(path):
    text = open(path, encoding="latin-1").read()
    for m in re.finditer(r"C '([^']*)' (\d+)", text):
        fields = {}
        for part in m.group(1).split("\x01"):
            if "\x02" in part:
                k, v = part.split("\x02", 1)
                fields[k] = v
        yield fields, int(m.group(2))


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    listing = "--list" in argv[2:]
    rules = [(c, w, re.compile(h), re.compile(s)) for c, w, h, s in CLASSES]
    why = OrderedDict()
    for c, w, _, _ in CLASSES:
        if w:
            why.setdefault(c, w)
    counts = Counter()
    signals = defaultdict(Counter)
    unexplained = []
    total = missed = 0
    for f, count in points(argv[1]):
        if not f.get("page", "").startswith("v_toggle"):
            continue
        hier = re.sub(r"\[\d+\]", "[*]", f.get("h", ""))
        if not hier.startswith("TOP.fast_pp"):
            continue
        total += 1
        if count:
            continue
        missed += 1
        signal = re.sub(r"\[\d+\]", "", f.get("o", ""))
        for c, _, h, s in rules:
            if h.search(hier) and s.search(signal):
                counts[c] += 1
                signals[c][f"{hier} {signal}"] += 1
                break
        else:
            unexplained.append(f"{hier} {f.get('o', '')}")
    print(f"fast processor toggle points: {total}, never toggled: {missed}")
    for c, w in why.items():
        print(f"{counts[c]:6}  {c}: {w}")
        if listing:
            for name, n in sorted(signals[c].items()):
                print(f"          {n:4} {name}")
    print(f"{len(unexplained):6}  unexplained")
    for u in unexplained:
        print(f"          {u}")
    return 1 if unexplained else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
