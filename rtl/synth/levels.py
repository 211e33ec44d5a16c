#!/usr/bin/env python3
"""rtl/synth/levels.py -- the deepest register-to-register path of a mapped
Xilinx netlist (docs/rtl.md, "Synthesis").

    python3 rtl/synth/levels.py target/synth/xc6v-pp-exact/netlist.json

The netlist is synth.sh's flattened `write_json` of `synth_xilinx`. This is
yosys' `ltp -noff` with the storage elements cut where the hardware cuts
them: `ltp` follows every input of a cell to every output, so a LUT RAM's
write data would reach its read data and the register file would close a
loop. Here a path starts at a flip-flop's Q, a registered DSP output, a block
RAM output or a top-level input, and ends at a flip-flop's D/CE/R/S, a LUT
RAM's write port (data, write enable, write address), a registered DSP
input, a block RAM input or a top-level output. Combinational arcs: LUTs,
MUXF7/8, CARRY4 (any input to any output), INV, a LUT RAM's read address to
its read data, a DSP48E1's unregistered inputs to P when it has no M or P
register.

It prints the path with the most cells (as ltp counts them) and, of the
register-to-register paths, the one with the most LUTs (the figure a
per-level delay multiplies), each with its cells by type, its first and last
cell and the nets that name its start and end.
"""
import json
import re
import sys
from collections import Counter, defaultdict

# LUT RAMs and shift registers: (read address ports, read data ports, write
# address ports). Every other input is the write port: a path ends there.
LUTRAM = {
    "RAM32M": (["ADDRA", "ADDRB", "ADDRC", "ADDRD"], ["DOA", "DOB", "DOC", "DOD"], ["ADDRD"]),
    "RAM64M": (["ADDRA", "ADDRB", "ADDRC", "ADDRD"], ["DOA", "DOB", "DOC", "DOD"], ["ADDRD"]),
    "RAM32X1D": (["A0", "A1", "A2", "A3", "A4", "DPRA0", "DPRA1", "DPRA2", "DPRA3", "DPRA4"],
                 ["SPO", "DPO"], ["A0", "A1", "A2", "A3", "A4"]),
    "RAM64X1D": (["A0", "A1", "A2", "A3", "A4", "A5",
                  "DPRA0", "DPRA1", "DPRA2", "DPRA3", "DPRA4", "DPRA5"], ["SPO", "DPO"],
                 ["A0", "A1", "A2", "A3", "A4", "A5"]),
    "RAM128X1D": (["A", "DPRA"], ["SPO", "DPO"], ["A"]),
    "RAM32X1S": (["A0", "A1", "A2", "A3", "A4"], ["O"], ["A0", "A1", "A2", "A3", "A4"]),
    "RAM64X1S": (["A0", "A1", "A2", "A3", "A4", "A5"], ["O"],
                 ["A0", "A1", "A2", "A3", "A4", "A5"]),
    "SRL16E": (["A0", "A1", "A2", "A3"], ["Q"], []),
    "SRLC32E": (["A"], ["Q", "Q31"], []),
}
COMB_ALL = re.compile(r"^(LUT[1-6]|MUXF[5-8]|CARRY4|INV|BUF|MUXCY|XORCY)$")
DSP_IN_REG = {"A": "AREG", "ACIN": "AREG", "B": "BREG", "BCIN": "BREG", "C": "CREG",
              "D": "DREG", "OPMODE": "OPMODEREG", "ALUMODE": "ALUMODEREG",
              "CARRYIN": "CARRYINREG", "INMODE": "INMODEREG"}


def param_int(cell, name):
    v = cell.get("parameters", {}).get(name, "0")
    if isinstance(v, int):
        return v
    v = v.strip()
    return int(v, 2) if set(v) <= {"0", "1"} else int(v)


def arcs(cell):
    """(combinational arcs as (in_port, out_port) pairs or None for all-to-all,
    source output ports, sink input ports) of a cell."""
    t = cell["type"]
    dirs = cell.get("port_directions", {})
    ins = [p for p, d in dirs.items() if d == "input"]
    outs = [p for p, d in dirs.items() if d == "output"]
    if COMB_ALL.match(t):
        return [(i, o) for i in ins for o in outs], [], []
    if t in LUTRAM:
        ra, rd, wa = LUTRAM[t]
        ra = [p for p in ra if p in dirs]
        rd = [p for p in rd if p in dirs]
        sinks = [p for p in ins if p not in ra or p in wa]
        return [(i, o) for i in ra for o in rd], rd, sinks
    if t == "DSP48E1":
        out_reg = param_int(cell, "MREG") or param_int(cell, "PREG")
        comb_in = [p for p in ins if p != "CLK" and not p.startswith("CE") and
                   not p.startswith("RST") and not param_int(cell, DSP_IN_REG.get(p, "_none"))]
        if out_reg:
            return [], outs, [p for p in ins if p not in ("CLK",)]
        in_reg = [p for p in ins if p not in comb_in]
        return [(i, o) for i in comb_in for o in outs], outs if in_reg else [], in_reg
    # Flip-flops, block RAMs and anything else: registered both ways.
    return [], outs, ins


def main(path):
    with open(path) as f:
        design = json.load(f)
    mods = {n: m for n, m in design["modules"].items()
            if not int(m.get("attributes", {}).get("blackbox", "0") or 0)
            and m.get("cells")}
    tops = [n for n, m in mods.items() if int(m.get("attributes", {}).get("top", "0") or 0)]
    top = mods[tops[0] if tops else next(iter(mods))]
    cells = top["cells"]
    netname = {}
    for n, nd in top["netnames"].items():
        if nd.get("hide_name"):
            continue
        for i, b in enumerate(nd["bits"]):
            if isinstance(b, int):
                netname.setdefault(b, f"{n}[{i}]" if len(nd["bits"]) > 1 else n)

    # Graph over nodes: a node is (cell, out_port) producing bits; edges from
    # each driving cell to each reading cell along combinational arcs.
    driver = {}  # bit -> (cell name, port)
    sources = set()  # bits that start a path
    # Top-level inputs start no path (register to register only).
    comb = {}
    sink_ports = {}
    for cn, c in cells.items():
        a, src_outs, sinks = arcs(c)
        comb[cn] = a
        sink_ports[cn] = set(sinks)
        for p, bits in c["connections"].items():
            if c.get("port_directions", {}).get(p) == "output":
                for b in bits:
                    if isinstance(b, int):
                        driver[b] = (cn, p)
                        if p in src_outs:
                            sources.add(b)
    # For each cell output bit: combinational fan-in bits.
    fanin = defaultdict(list)  # out bit -> [in bits]
    cell_of = {}
    for cn, c in cells.items():
        conns = c["connections"]
        by_out = defaultdict(list)
        for i, o in comb[cn]:
            by_out[o].extend(b for b in conns.get(i, []) if isinstance(b, int))
        for o, ibits in by_out.items():
            for ob in conns.get(o, []):
                if isinstance(ob, int):
                    fanin[ob].extend(ibits)
                    cell_of[ob] = cn
    # Longest paths by (LUT count) and by (cell count), memoised over bits.
    sys.setrecursionlimit(1_000_000)
    best = {}  # (bit, key) -> (value, prev bit)

    def weight(cn, key):
        t = cells[cn]["type"]
        if key == "cells":
            return 1
        return 1 if t.startswith("LUT") else 0

    order = []
    state = {}
    for start in list(fanin.keys()):
        stack = [(start, 0)]
        while stack:
            b, i = stack.pop()
            if i == 0:
                if state.get(b) == 2:
                    continue
                if state.get(b) == 1:
                    sys.exit(f"levels.py: combinational loop through net bit {b} "
                             f"({netname.get(b, '?')})")
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
    results = {}
    for key in ("cells", "luts"):
        val = {}
        prev = {}
        for b in order:
            w = weight(cell_of[b], key)
            bv, bp = 0, None
            for nb in fanin[b]:
                v = val.get(nb, 0) if nb in fanin else 0
                if nb not in fanin and nb not in sources:
                    continue  # constant or undriven
                if bp is None or v > bv:
                    bv, bp = v, nb
            val[b] = bv + w
            prev[b] = bp
        # Endpoints: bits read by a sink port (or a top-level output).
        ends = []
        for cn, c in cells.items():
            for p in sink_ports[cn]:
                for b in c["connections"].get(p, []):
                    if isinstance(b, int) and b in val:
                        ends.append((val[b], b, (cn, p), True))
        for p, pd in top["ports"].items():
            if pd["direction"] == "output":
                for b in pd["bits"]:
                    if isinstance(b, int) and b in val:
                        ends.append((val[b], b, (f"<output {p}>", p), False))
        ends.sort(key=lambda e: -e[0])
        reg_ends = [e for e in ends if e[3]]
        results[key] = (val, prev, ends, reg_ends)

    def trace(val, prev, b):
        path = []
        while b is not None and b in cell_of:
            path.append(b)
            b = prev[b]
        return list(reversed(path)), b

    def start_is_reg(b):
        d = driver.get(b)
        return d is not None and not d[0].startswith("<input")

    for key, title in (("cells", "most cells (ltp's count)"), ("luts", "most LUT levels")):
        val, prev, ends, reg_ends = results[key]
        # register to register: the start must be a register too
        for v, b, endname, _ in reg_ends:
            path, start = trace(val, prev, b)
            if start is not None and start_is_reg(start):
                break
        types = Counter(cells[cell_of[x]]["type"] for x in path)
        dcell, dport = driver[start]
        print(f"register-to-register path with the {title}: {len(path)} cells, "
              f"{sum(n for t, n in types.items() if t.startswith('LUT'))} LUTs")
        print("  by type: " + ", ".join(f"{t} {n}" for t, n in sorted(types.items())))
        print(f"  from {dcell} ({cells[dcell]['type'] if dcell in cells else 'port'}).{dport}"
              f" net {netname.get(start, start)}")
        ecell, eport = endname
        q = [netname[x] for o, bits in cells[ecell]["connections"].items()
             if cells[ecell].get("port_directions", {}).get(o) == "output"
             for x in bits if x in netname]
        print(f"  to   {ecell} ({cells[ecell]['type']}).{eport} net {netname.get(b, b)}"
              + (f", the cell that drives {q[0]}" if q else ""))
        named = [netname[x] for x in path if x in netname]
        if named:
            print("  named nets on the way: " + " -> ".join(named[:40]))
        if ends and not ends[0][3]:
            v, b, endname, _ = ends[0]
            print(f"  (paths to top-level outputs reach {v})")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: levels.py NETLIST.json (synth.sh's netlist.json)")
    main(sys.argv[1])
