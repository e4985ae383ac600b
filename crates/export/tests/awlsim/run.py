#!/usr/bin/env python3
"""Loads a generated group source (.awl, Windows-1252) into Awlsim 0.77.1, runs it for some
cycles with a virtual clock (Δ ms per cycle, so SFC 64 TIME_TCK and the timers advance by
exactly Δ) and prints the DB's fields after every cycle as JSON lines.

  run.py FILE.awl --db N --cycles K [--dt MS] [--set CYCLE:E0.7=1 ...] [--fields a.b,c.d]
         [--mnemonics de|en] [--ob1]

Without --ob1 a wrapper OB 1 calls FC --fc with INIT_SD = 1 in the first cycle only.
"""
import json
import sys

from awlsim_loader.common import *  # noqa: F401,F403
from awlsim_loader.core import *  # noqa: F401,F403
from awlsim_loader.awlcompiler import *  # noqa: F401,F403

T0 = 1000.0


def main():
    args = sys.argv[1:]
    path = args.pop(0)
    db, fc, cycles, dt, sets, fields, mn, ob1 = 1, 1, 10, 10, [], None, "de", False
    while args:
        a = args.pop(0)
        if a == "--db":
            db = int(args.pop(0))
        elif a == "--fc":
            fc = int(args.pop(0))
        elif a == "--cycles":
            cycles = int(args.pop(0))
        elif a == "--dt":
            dt = int(args.pop(0))
        elif a == "--set":
            sets.append(args.pop(0))
        elif a == "--fields":
            fields = args.pop(0).split(",")
        elif a == "--mnemonics":
            mn = args.pop(0)
        elif a == "--ob1":
            ob1 = True
    src = open(path, "rb").read().decode("cp1252")
    if not ob1:
        src += ("\r\nORGANIZATION_BLOCK OB 1\r\nVAR_TEMP\r\n  first : BOOL;\r\nEND_VAR\r\nBEGIN\r\n"
                "      L     MB 255\r\n      L     0\r\n      ==I\r\n      =     #first\r\n"
                "      L     1\r\n      T     MB 255\r\n"
                "      CALL  FC %d (INIT_SD := #first);\r\nEND_ORGANIZATION_BLOCK\r\n" % fc)
    project = Project.fromProjectOrRawAwlData(src.encode("utf-8"))
    parser = AwlParser()
    for s in project.getAwlSources():
        parser.parseSource(s)
    sim = AwlSim()
    sim.reset()
    cpu = sim.getCPU()
    cpu.getConf().setConfiguredMnemonics(
        S7CPUConfig.MNEMONICS_DE if mn == "de" else S7CPUConfig.MNEMONICS_EN)
    sim.load(parser.getParseTree())
    sim.build()
    state = {"now": T0}

    def upd(*_a):
        cpu.now = state["now"]
    cpu.updateTimestamp = upd
    sim.startup()
    dbo = cpu.getDB(db)
    inst = dbo.structInstance
    names = fields or [f.name for f in inst._struct.fields if f.name]
    for k in range(cycles):
        state["now"] = T0 + k * dt / 1000.0 + 1e-7
        for s in sets:
            c, rest = s.split(":", 1)
            if int(c) == k + 1:
                addr, val = rest.split("=")
                area, bit = addr[0], addr[1:]
                byte, b = (int(x) for x in bit.split("."))
                mem = (cpu.inputs if area in "EI" else cpu.outputs).getRawDataBytes()
                if int(val):
                    mem[byte] |= 1 << b
                else:
                    mem[byte] &= ~(1 << b) & 0xFF
        sim.runCycle()
        out = {}
        for n in names:
            try:
                v = inst.getFieldDataByName(n)
                out[n] = int.from_bytes(bytes(v.dataBytes), "big") if hasattr(v, "dataBytes") else str(v)
            except Exception as e:  # noqa
                out[n] = "?%s" % e
        out["A0"] = cpu.outputs.getRawDataBytes()[0]
        if k == 0 and "--layout" in sys.argv:
            print(json.dumps([(f.name, str(f.offset), str(f.dataType)) for f in inst._struct.fields if f.name]))
        print(json.dumps({"cycle": k + 1, "db": out}))


main()
