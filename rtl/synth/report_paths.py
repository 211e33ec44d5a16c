#!/usr/bin/env python3
"""rtl/synth/report_paths.py -- the deepest register-to-register paths into
the registers of one part of a mapped Xilinx netlist, one per end signal
(docs/rtl.md, "Synthesis").

    python3 rtl/synth/report_paths.py target/synth/xc6v-fast-pp-exact/netlist.json u_ctrl. 5
    python3 rtl/synth/report_paths.py target/synth/xc6v-fast-pp-exact/netlist.json fast_ctrl.v 5

report.py names the single deepest path of the whole netlist; this lists,
for the end registers of one part, the deepest path into each signal (a
bus, its bit index dropped; buses that share a bit are one), the COUNT
deepest such signals, by LUT levels (ties: by delay at 0.8 ns a net). The
part: the registers whose output net names start with PREFIX (a flattened
instance path such as u_ctrl.; "" for all; a register that drives an input
port of the instance is named there too), or, for a PREFIX ending in .v,
the registers whose src attribute names that file anywhere in its
instance chain (the module's registers and its submodules'; the shift
registers yosys maps from its cell library keep no RTL file and are left
out). A 4th argument `delay` ranks by the delay estimate instead (ties:
LUTs). Paths start and end where report.py's do (its arcs(): flip-flops,
registered DSP and block RAM ports, LUT RAM and shift-register write
ports), and the delay is report.py's estimate. Each path is printed with its start and end nets (every name
yosys kept for the bit, up to four) and the named nets on the way.
"""
import json
import os
import re
import sys
from collections import Counter, defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.dont_write_bytecode = True  # no __pycache__ beside the scripts
import report  # noqa: E402  (arcs, delays)

NET_NS = 0.8


def main(path, prefix, count, by_delay=False):
    with open(path) as f:
        design = json.load(f)
    mods = {n: m for n, m in design["modules"].items()
            if not int(m.get("attributes", {}).get("blackbox", "0") or 0) and m.get("cells")}
    tops = [n for n, m in mods.items() if int(m.get("attributes", {}).get("top", "0") or 0)]
    top = mods[tops[0] if tops else next(iter(mods))]
    cells = top["cells"]
    names = defaultdict(list)  # bit -> every kept name
    for n, nd in top["netnames"].items():
        if nd.get("hide_name"):
            continue
        for i, b in enumerate(nd["bits"]):
            if isinstance(b, int):
                names[b].append(f"{n}[{i}]" if len(nd["bits"]) > 1 else n)

    driver, sources, sink_ports, fanin, cell_of = {}, set(), {}, defaultdict(list), {}
    for cn, c in cells.items():
        a, src_outs, sinks = report.arcs(c)
        sink_ports[cn] = set(sinks)
        conns = c["connections"]
        for p, bits in conns.items():
            if c.get("port_directions", {}).get(p) == "output":
                for b in bits:
                    if isinstance(b, int):
                        driver[b] = (cn, p)
                        if p in src_outs:
                            sources.add(b)
        by_out = defaultdict(list)
        for i, o in a:
            by_out[o].extend(b for b in conns.get(i, []) if isinstance(b, int))
        for o, ibits in by_out.items():
            for ob in conns.get(o, []):
                if isinstance(ob, int):
                    fanin[ob].extend(ibits)
                    cell_of[ob] = cn

    def ns(cn, from_cn):
        t = cells[cn]["type"]
        if t == "CARRY4" and from_cn is not None and cells[from_cn]["type"] == "CARRY4":
            return report.CARRY_CHAIN_NS
        if t == "DSP48E1":
            mult = cells[cn].get("parameters", {}).get("USE_MULT", "MULTIPLY") != "NONE"
            return (report.DSP_MULT_NS if mult else report.DSP_ADD_NS) + NET_NS
        return report.CELL_NS.get(t, 0.642) + NET_NS

    # Topological order over the combinational bits (iterative DFS).
    order, state = [], {}
    for start in list(fanin):
        stack = [(start, 0)]
        while stack:
            b, i = stack.pop()
            if i == 0:
                if state.get(b) == 2:
                    continue
                if state.get(b) == 1:
                    sys.exit(f"report_paths.py: combinational loop through bit {b}")
                state[b] = 1
            fi = fanin.get(b, [])
            if i < len(fi):
                stack.append((b, i + 1))
                nb = fi[i]
                if state.get(nb) != 2 and nb in fanin:
                    stack.append((nb, 0))
            else:
                state[b] = 2
                order.append(b)
    # Longest path by (LUTs, ns), or by (ns, LUTs), from register outputs only.
    order_key = (lambda v: (v[1], v[0])) if by_delay else (lambda v: v)
    val, prev = {}, {}
    for b in order:
        cn = cell_of[b]
        lut = 1 if cells[cn]["type"].startswith("LUT") else 0
        best, bp = None, None
        for nb in fanin[b]:
            if nb in fanin:
                if val[nb] is None:
                    continue
                v0 = val[nb]
            elif nb in sources:
                v0 = (0, 0.0)
            else:
                continue  # a constant, a top-level input or undriven
            v = (v0[0] + lut, v0[1] + ns(cn, cell_of.get(nb)))
            if best is None or order_key(v) > order_key(best):
                best, bp = v, nb
        val[b], prev[b] = best, bp

    def bus(n):
        return re.sub(r"\[\d+\]$", "", n)

    def label(b):
        ns_ = [n for n in names.get(b, []) if not n.startswith("$")] or names.get(b, [])
        return ns_

    # Endpoints: sink ports of cells whose outputs are named under prefix.
    # A signal is a bus, and buses that share a bit (aliases) are one.
    ends = []
    parent = {}

    def find(x):
        while parent.setdefault(x, x) != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    def rtl_files(c):
        files = [x.split(":")[0] for x in c.get("attributes", {}).get("src", "").split("|")]
        return [os.path.basename(f) for f in files if f and "share/yosys" not in f]

    def rtl_file(c):
        return (rtl_files(c) or ["?"])[-1]

    by_file = prefix.endswith(".v")
    for cn, c in cells.items():
        if not sink_ports[cn]:
            continue
        outs = [b for p, bits in c["connections"].items()
                if c.get("port_directions", {}).get(p) == "output" for b in bits if isinstance(b, int)]
        if by_file:
            inside = prefix in rtl_files(c)
            mine = ([n for b in outs for n in label(b)] or [f"<{cn}>"]) if inside else []
        else:
            mine = [n for b in outs for n in label(b) if n.startswith(prefix)]
        if mine:
            ends.append((cn, c, mine))
            for n in mine[1:]:
                parent[find(bus(n))] = find(bus(mine[0]))
    best_by_end = {}
    for cn, c, mine in ends:
        key = find(bus(mine[0]))
        for p in sink_ports[cn]:
            for b in c["connections"].get(p, []):
                if isinstance(b, int) and val.get(b) is not None:
                    if key not in best_by_end or order_key(val[b]) > order_key(best_by_end[key][0]):
                        best_by_end[key] = (val[b], b, cn, p, mine)
                elif isinstance(b, int) and b in sources:
                    v = (0, 0.0)
                    if key not in best_by_end:
                        best_by_end[key] = (v, b, cn, p, mine)
    ranked = sorted(best_by_end.items(), key=lambda kv: order_key(kv[1][0]), reverse=True)
    print(f"{len(ranked)} end signals under '{prefix}'; the {min(count, len(ranked))} deepest:")
    for rank, (key, (v, b, cn, p, mine)) in enumerate(ranked[:count], 1):
        path = []
        x = b
        while x is not None and x in cell_of:
            path.append(x)
            x = prev[x]
        path.reverse()
        start = x
        types = Counter(cells[cell_of[y]]["type"] for y in path)
        total = v[1] + report.TCKO_NS + report.TSETUP_NS + NET_NS
        dcell = driver.get(start, ("?", "?"))
        print(f"{rank}. {v[0]} LUTs, {len(path)} cells "
              f"({', '.join(f'{t} {n}' for t, n in sorted(types.items()))}); "
              f"{total:.2f} ns at {NET_NS} ns a net, {1000 / total:.0f} MHz")
        print(f"   from {' = '.join(label(start)[:4]) or start}"
              f" ({cells[dcell[0]]['type'] if dcell[0] in cells else '?'}.{dcell[1]})")
        print(f"   to   {' = '.join(mine[:4])} ({cells[cn]['type']}.{p}, D net "
              f"{' = '.join(label(b)[:2]) or b}; {rtl_file(cells[cn])})")
        on_way = []
        for y in path:
            for n in label(y)[:1]:
                if not on_way or on_way[-1] != n:
                    on_way.append(n)
        if on_way:
            print("   via  " + " -> ".join(on_way[:30]))


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3, 4, 5) or (len(sys.argv) == 5 and sys.argv[4] != "delay"):
        sys.exit("usage: report_paths.py NETLIST.json [PREFIX [COUNT [delay]]]")
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "",
         int(sys.argv[3]) if len(sys.argv) > 3 else 5, len(sys.argv) == 5)
