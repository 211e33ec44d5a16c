#!/usr/bin/env python3
"""rtl/synth/report.py -- the resources and the deepest register-to-register
path of a mapped Xilinx netlist (docs/rtl.md, "Synthesis").

    python3 rtl/synth/report.py target/synth/xc6v-pp-exact/netlist.json

Resources as ISE counts them on Virtex-6 (the thesis' table): slice LUTs are
the logic LUTs (LUT1..LUT6 and INV) plus the LUTs that LUT RAMs and shift
registers occupy (RAM32M and RAM64M 4 each, RAM32X1D and RAM64X1D 2, ...);
the INVs on rst_n are counted once (yosys leaves one per flip-flop with an
asynchronous reset; a vendor mapper merges them, or folds them into the
flip-flop's reset). Flip-flops are the FD* cells, DSPs the DSP48E1s, block
RAMs the RAMB36E1s plus half the RAMB18E1s. Black boxes (the top's
pixel_processor) are counted and named.

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
LUTRAM_LUTS = {"RAM32M": 4, "RAM64M": 4, "RAM32X1D": 2, "RAM64X1D": 2, "RAM128X1D": 4,
               "RAM32X1S": 1, "RAM64X1S": 1, "RAM128X1S": 2, "SRL16E": 1, "SRLC32E": 1}
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
# Cell delays in ns, the slowest input of each: yosys' share/xilinx/cells_sim.v
# specify blocks (prjxray's measured 7-series timings, speed grade -1; the
# 7-series CLB is the Virtex-6 CLB, UG474). A net between two cells adds NET.
CELL_NS = {"LUT1": 0.127, "LUT2": 0.238, "LUT3": 0.407, "LUT4": 0.472, "LUT5": 0.631,
           "LUT6": 0.642, "INV": 0.127, "MUXF7": 0.296, "MUXF8": 0.273, "CARRY4": 0.642,
           "RAM32M": 0.642, "RAM64M": 0.642, "RAM32X1D": 0.642 + 0.223 + 0.174,
           "RAM64X1D": 0.642 + 0.223 + 0.174, "RAM128X1D": 0.642 + 0.296 + 0.174}
CARRY_CHAIN_NS = 0.313  # CI -> O[3]: a CARRY4 fed by the one below, no net between
DSP_MULT_NS, DSP_ADD_NS = 2.823, 1.523  # A -> P, with and without the multiplier
TCKO_NS, TSETUP_NS = 0.303, 0.453  # FDRE C -> Q; the slowest setup (RAM DI)
NETS_NS = (0.3, 0.8)  # net delay per hop: an assumed range, not a data-sheet figure
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


def resources(top, cells, netname):
    types = Counter(c["type"] for c in cells.values())
    reset_inv = sum(1 for c in cells.values() if c["type"] == "INV"
                    and netname.get(c["connections"]["I"][0]) == "rst_n")
    logic = sum(n for t, n in types.items() if re.match(r"^LUT[1-6]$", t))
    inv = types.get("INV", 0) - reset_inv + (1 if reset_inv else 0)
    mem = sum(LUTRAM_LUTS[t] * n for t, n in types.items() if t in LUTRAM_LUTS)
    ffs = sum(n for t, n in types.items() if re.match(r"^FD", t))
    bram = types.get("RAMB36E1", 0) + types.get("RAMB18E1", 0) / 2
    known = re.compile(r"^(LUT[1-6]|INV|FD\w*|RAMB\w*|DSP48E1|MUXF[78]|CARRY4|VCC|GND)$")
    print(f"slice LUTs {logic + inv + mem} (logic {logic}, INV {inv}"
          f" of which rst_n {1 if reset_inv else 0} for {reset_inv} in the netlist,"
          f" memory {mem}), flip-flops {ffs}, DSP48E1 {types.get('DSP48E1', 0)},"
          f" block RAM (36 Kb) {bram:g}; MUXF7 {types.get('MUXF7', 0)},"
          f" MUXF8 {types.get('MUXF8', 0)}, CARRY4 {types.get('CARRY4', 0)}")
    other = {t: n for t, n in types.items() if not known.match(t) and t not in LUTRAM_LUTS}
    if other:
        print("  other cells: " + ", ".join(f"{t} {n}" for t, n in sorted(other.items())))


def main(path):
    try:
        with open(path) as f:
            design = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"report.py: cannot read {path} as a yosys JSON netlist: {e}")
    if not isinstance(design, dict) or "modules" not in design:
        sys.exit(f"report.py: {path} is not a yosys JSON netlist (no \"modules\")")
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

    resources(top, cells, netname)

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

    def weight(cn, key, from_cn=None):
        t = cells[cn]["type"]
        if key == "cells":
            return 1
        if key == "luts":
            return 1 if t.startswith("LUT") else 0
        if t == "DSP48E1":
            mult = cells[cn].get("parameters", {}).get("USE_MULT", "MULTIPLY") != "NONE"
            ns = DSP_MULT_NS if mult else DSP_ADD_NS
        else:
            ns = CELL_NS.get(t, 0.642)
        if t == "CARRY4" and from_cn is not None and cells[from_cn]["type"] == "CARRY4":
            return CARRY_CHAIN_NS
        return ns + key  # key: the net delay per hop

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
                    sys.exit(f"report.py: combinational loop through net bit {b} "
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
    for key in ("cells", "luts") + NETS_NS:
        val = {}
        prev = {}
        for b in order:
            bv, bp = None, None
            for nb in fanin[b]:
                if nb in fanin:
                    if val[nb] is None:
                        continue  # no register starts a path to it
                    v0 = val[nb]
                elif nb in sources:
                    v0 = 0
                else:
                    continue  # a constant, a top-level input or undriven
                v = v0 + weight(cell_of[b], key, cell_of.get(nb))
                if bv is None or v > bv:
                    bv, bp = v, nb
            # Only paths that start at a register count: a bit reached from
            # top-level inputs and constants alone has none (counting those
            # let an input's longer path hide a register's at the same end).
            val[b] = bv
            prev[b] = bp
        # Endpoints: bits read by a sink port (or a top-level output).
        ends = []
        for cn, c in cells.items():
            for p in sink_ports[cn]:
                for b in c["connections"].get(p, []):
                    if isinstance(b, int) and val.get(b) is not None:
                        ends.append((val[b], b, (cn, p), True))
        for p, pd in top["ports"].items():
            if pd["direction"] == "output":
                for b in pd["bits"]:
                    if isinstance(b, int) and val.get(b) is not None:
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

    titles = [("cells", "most cells (ltp's count)"), ("luts", "most LUT levels")]
    titles += [(n, f"longest delay at {n} ns a net") for n in NETS_NS]
    for key, title in titles:
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
        if not isinstance(key, str):
            ns = v + TCKO_NS + TSETUP_NS + key
            print(f"  estimate: {v:.2f} ns of cells and nets + clock-to-out, last net and "
                  f"setup = {ns:.2f} ns, {1000 / ns:.0f} MHz")
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
        sys.exit("usage: report.py NETLIST.json (synth.sh's netlist.json)")
    main(sys.argv[1])
