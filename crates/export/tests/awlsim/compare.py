#!/usr/bin/env python3
"""Runs a generated group source in Awlsim 0.77.1 and compares it cycle by cycle with what the
simulator did (a scenario written by crates/analysis/tests/build_awl.rs):

  {"awl": "G.awl", "db": 1, "dt": 10, "mnemonics": "de",
   "fields": ["Inst.CurrentState", ...],            DB members compared (by name)
   "bytes": [["A", 0, 8], ["M", 0, 16]],             memory compared (area, first, count)
   "cycles": [{"set": [["M", 1, 0, 1], ...],         inputs before the cycle (area byte bit v)
               "fields": [0, 1, ...], "bytes": [[...], [...]]}, ...]}

With "sdf": the symbol table `build` wrote (System Data Format) is loaded first, for a
symbolic source. The source must bring its own OB 1 (`--with-ob1`). Virtual clock: Δ ms per cycle, so SFC 64
TIME_TCK and the timers advance exactly like the simulator's clock. Exit 1 at the first
difference (printed), 0 when every cycle agrees.
"""
import csv
import json
import sys

from awlsim_loader.common import *  # noqa: F401,F403
from awlsim_loader.core import *  # noqa: F401,F403
from awlsim_loader.awlcompiler import *  # noqa: F401,F403

T0 = 1000.0


def main():
    sc = json.load(open(sys.argv[1]))
    src = open(sc["awl"], "rb").read().decode("cp1252")
    project = Project.fromProjectOrRawAwlData(src.encode("utf-8"))
    parser = AwlParser()
    for s in project.getAwlSources():
        parser.parseSource(s)
    sim = AwlSim()
    sim.reset()
    cpu = sim.getCPU()
    cpu.getConf().setConfiguredMnemonics(
        S7CPUConfig.MNEMONICS_DE if sc.get("mnemonics", "de") == "de" else S7CPUConfig.MNEMONICS_EN)
    specs = cpu.getSpecs()
    specs.setNrInputs(65536)
    specs.setNrOutputs(65536)
    specs.setNrFlags(65536)
    specs.setNrTimers(2048)
    specs.setNrCounters(2048)
    if sc.get("sdf"):
        text = open(sc["sdf"], "rb").read().decode("cp1252")
        rows = ['"%s";"%s";"%s";"%s"' % tuple(f.strip() for f in row)
                for row in csv.reader(text.splitlines()) if row]
        symtab = SymTabParser_CSV.parseText("\r\n".join(rows) + "\r\n", autodetectFormat=False,
                                            mnemonics=cpu.getConf().getConfiguredMnemonics())
        sim.loadSymbolTable(symtab)
    sim.load(parser.getParseTree())
    sim.build()
    clock = {"now": T0}

    def upd(*_a):
        cpu.now = clock["now"]
    cpu.updateTimestamp = upd
    sim.startup()
    inst = cpu.getDB(sc["db"]).structInstance
    areas = {"E": cpu.inputs, "A": cpu.outputs, "M": cpu.flags}
    for k, cyc in enumerate(sc["cycles"]):
        clock["now"] = T0 + (k + 1) * sc["dt"] / 1000.0 + 1e-7
        for area, byte, bit, v in cyc["set"]:
            mem = areas[area].getRawDataBytes()
            if v:
                mem[byte] |= 1 << bit
            else:
                mem[byte] &= ~(1 << bit) & 0xFF
        sim.runCycle()
        for name, want in zip(sc["fields"], cyc["fields"]):
            v = inst.getFieldDataByName(name)
            got = int.from_bytes(bytes(v.dataBytes), "big")
            if got != want:
                print("cycle %d: %s is %d in Awlsim, %d in the simulator" % (k + 1, name, got, want))
                return 1
        for (area, first, count), want in zip(sc["bytes"], cyc["bytes"]):
            mem = areas[area].getRawDataBytes()
            got = [mem[i] for i in range(first, first + count)]
            if got != want:
                print("cycle %d: %s bytes %d.. are %s in Awlsim, %s in the simulator"
                      % (k + 1, area, first, got, want))
                return 1
    print("%d cycles agree" % len(sc["cycles"]))
    return 0


sys.exit(main())
