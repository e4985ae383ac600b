#!/usr/bin/env python3
"""Awlsim side of the proof that generated STL equals the simulator (export.md §5; run by
scripts/build-diff, which documents the whole design).

Usage: build-diff.py DIR [--sources SRC]

With --sources, the `.awl` files are read from SRC instead of DIR/<workspace>/ and a failed
build is ignored: the self-test of scripts/build-diff replays a hand-written source that way.

DIR holds the replay files `NNN-*.json` written by the build_replay example and, per
workspace, the generated `<group>.awl` files. For each replay file:

* the group sources (Windows-1252) are compiled by Awlsim 0.77.1 together with the harness's
  own OB 1 and a harness DB: OB 1 copies the harness DB's bit 0.0 into a temporary BOOL and
  calls every group FC with INIT_SD := that BOOL, in run order (Awlsim mishandles a DB bit or
  a constant passed to a BOOL parameter directly: the callee's temporaries then start at a
  bit offset);
* Awlsim's clock is the virtual clock: cycle k runs at t0 + k * Δ ms (+ 0.5 ms so that the
  floating-point seconds never round below the millisecond), so SFC 64 TIME_TCK and the S5
  timers follow virtual time;
* before each cycle the harness replays the writes of the test statements (or the random
  stimulus) to the process image, bit memory or the instance DB (by field name), and
  restarts: warm = INIT_SD for the next cycle; cold = a fresh Awlsim CPU with the same
  inputs (outputs, bit memory, timers and DBs back to their initial values);
* after each cycle it compares with the simulator: every instance's `CurrentState` and every
  message bit of the DB read through Awlsim's DB structure by name
  (`<Instance>.CurrentState`, `<Instance>.<MsgVar>` — never by offset), and every byte of
  the input, output and bit-memory areas (external message bits included).

The first difference fails the scenario with its cycle, time, what differs and both values.
Scenarios that cannot run are reported as SKIPPED with the reason; the summary line counts
them, and a skip that is not by design fails the run (no silent pass).
Exit status: 0 all ran scenarios agree and nothing was skipped but by design; 1 otherwise.
"""

import glob
import json
import os
import re
import sys
import time

from awlsim_loader.common import *  # noqa: F401,F403
from awlsim_loader.core import *  # noqa: F401,F403
from awlsim_loader.awlcompiler import *  # noqa: F401,F403

AREA_SIZE = 65536


class Mismatch(Exception):
    pass


class Skip(Exception):
    pass


def harness_source(fcs, dbno):
    lines = ["", "DATA_BLOCK DB %d" % dbno, "STRUCT", "  HG_INIT_SD : BOOL;", "END_STRUCT;",
             "BEGIN", "END_DATA_BLOCK", "",
             "ORGANIZATION_BLOCK OB 1", "VAR_TEMP", "  HG_OB1 : ARRAY [1..20] OF BYTE;",
             "  HG_INIT : BOOL;", "END_VAR", "BEGIN",
             "      U     DB%d.DBX 0.0;" % dbno, "      =     #HG_INIT;"]
    for fc in fcs:
        lines.append("      CALL FC %d (INIT_SD := #HG_INIT);" % fc)
    lines += ["END_ORGANIZATION_BLOCK", ""]
    return "\r\n".join(lines).encode("cp1252")


class Plc:
    """One Awlsim CPU loaded with the groups' sources."""

    def __init__(self, sc, sources, clock):
        self.sc = sc
        self.clock = clock
        text = b""
        fcs = []
        dbs = set()
        for name, data in sources:
            if not data.endswith(b"\n"):
                data += b"\r\n"
            src = data.decode("cp1252")
            m = re.findall(r"^\s*FUNCTION\s+FC\s*(\d+)\s*:", src, re.M | re.I)
            if len(m) != 1:
                raise Mismatch("%s: expected exactly one FUNCTION FC n, found %d" % (name, len(m)))
            fcs.append(int(m[0]))
            if re.search(r"^\s*ORGANIZATION_BLOCK", src, re.M | re.I):
                raise Mismatch("%s: has an ORGANIZATION_BLOCK although built without --with-ob1"
                               % name)
            dbs.update(int(n) for n in re.findall(r"^\s*DATA_BLOCK\s+DB\s*(\d+)", src, re.M | re.I))
            text += data
        self.hdb = max(dbs | {0}) + 1
        text += harness_source(fcs, self.hdb)
        self.text = text
        project = Project.fromProjectOrRawAwlData(text)
        parser = AwlParser()
        for s in project.getAwlSources():
            parser.parseSource(s)
        self.sim = AwlSim()
        self.sim.reset()
        cpu = self.cpu = self.sim.getCPU()
        cpu.getConf().setConfiguredMnemonics(
            S7CPUConfig.MNEMONICS_EN if sc.get("mnemonic") == "en" else S7CPUConfig.MNEMONICS_DE)
        specs = cpu.getSpecs()
        specs.setNrInputs(AREA_SIZE)
        specs.setNrOutputs(AREA_SIZE)
        specs.setNrFlags(AREA_SIZE)
        specs.setNrTimers(2048)
        specs.setNrCounters(2048)
        self.sim.load(parser.getParseTree())
        self.sim.build()
        cpu.updateTimestamp = self._update_timestamp
        self.sim.startup()
        # Per group: the instance DB (the one with the instances' fields).
        self.group_db = []
        for g in sc["groups"]:
            want = "%s.CurrentState" % g["instances"][0] if g["instances"] else None
            found = None
            for n in sorted(dbs):
                db = cpu.getDB(n)
                if db is not None and want in db.struct.name2field:
                    found = db
                    break
            if found is None:
                raise Mismatch("contract: no DB of %s has a field %s (CONTRACTS.md 1)"
                               % (g["awl"], want))
            self.group_db.append(found)
        for gi, g in enumerate(sc["groups"]):
            names = self.group_db[gi].struct.name2field
            for inst in g["instances"]:
                f = inst + ".CurrentState"
                if f not in names:
                    raise Mismatch("contract: the DB of group %s has no field %s" % (g["name"], f))
            for f in g["msgs"]:
                if f not in names:
                    raise Mismatch("contract: the DB of group %s has no field %s (a message "
                                   "variable)" % (g["name"], f))

    def _update_timestamp(self, *args):
        self.cpu.now = self.clock[0]

    def raw(self, area):
        cpu = self.cpu
        if area == "E":
            return cpu.inputs.getRawDataBytes()
        if area == "A":
            return cpu.outputs.getRawDataBytes()
        if area == "M":
            return cpu.flags.getRawDataBytes()
        if area.startswith("DB"):
            db = cpu.getDB(int(area[2:]))
            if db is None:
                raise Mismatch("the source has no %s, which a test statement writes" % area)
            return db.structInstance.memory.getRawDataBytes()
        raise Mismatch("cannot replay a write to area %s" % area)

    def field(self, gi, name):
        db = self.group_db[gi]
        f = db.struct.getField(name)
        return f, AwlMemoryObject_asScalar(db.structInstance.getFieldData(f, None))

    def write(self, w):
        bits = w["bits"]
        if "field" in w:
            db = self.group_db[w["group"]]
            try:
                f = db.struct.getField(w["field"])
            except Exception:
                raise Mismatch("contract: the DB has no field %s (a test statement sets it)"
                               % w["field"])
            mask = (1 << f.bitSize) - 1 if f.bitSize < 32 else 0xFFFFFFFF
            db.structInstance.setFieldData(
                f, make_AwlMemoryObject_fromScalar(bits & mask, f.bitSize), None)
            return
        mem = self.raw(w["area"])
        b = w["byte"]
        width = w["width"]
        if width.startswith("X"):
            bit = int(width[1:])
            if bits & 1:
                mem[b] |= 1 << bit
            else:
                mem[b] &= ~(1 << bit) & 0xFF
        else:
            n = {"B": 1, "W": 2, "D": 4}[width]
            for i in range(n):
                mem[b + i] = (bits >> (8 * (n - 1 - i))) & 0xFF

    def set_init_sd(self, v):
        self.cpu.getDB(self.hdb).structInstance.memory.getRawDataBytes()[0] = 1 if v else 0


def bit_diff(area, ours, theirs):
    """The first differing bit of two byte strings, as 'E 1.3: simulator 1, awlsim 0'."""
    n = max(len(ours), len(theirs))
    for i in range(n):
        a = ours[i] if i < len(ours) else 0
        b = theirs[i] if i < len(theirs) else 0
        if a != b:
            for bit in range(8):
                if (a ^ b) >> bit & 1:
                    return "%s %d.%d: simulator %d, awlsim %d (byte %s %d: simulator 16#%02X, " \
                           "awlsim 16#%02X)" % (area, i, bit, a >> bit & 1, b >> bit & 1,
                                                area + "B", i, a, b)
    return None


def describe_write(w):
    if "restart" in w:
        return "restart %s" % w["restart"]
    if "field" in w:
        return "%s := %d" % (w["field"], w["bits"])
    return "%s %d%s := %d" % (w["area"], w["byte"],
                              "." + w["width"][1:] if w["width"].startswith("X")
                              else " (" + w["width"] + ")", w["bits"])


def run_scenario(sc, base, src_dir=None):
    ws = sc["workspace"]
    sources = []
    for g in sc["groups"]:
        path = os.path.join(src_dir, g["awl"]) if src_dir else os.path.join(base, ws, g["awl"])
        try:
            with open(path, "rb") as fh:
                sources.append((ws + "/" + g["awl"], fh.read()))
        except OSError as e:
            raise Mismatch("cannot read the group source: %s" % e)
    dt = sc["cycle_ms"]
    t0 = sc["t0_ms"]
    clock = [(t0 + 0.5) / 1000.0]
    try:
        plc = Plc(sc, sources, clock)
    except Mismatch:
        raise
    except Exception as e:
        raise Mismatch("Awlsim does not compile the generated source: %s" % short_error(e))
    cycles = sc["cycles"]
    for k, c in enumerate(cycles, start=1):
        for w in c["before"]:
            if "restart" in w:
                if w["restart"] == "cold":
                    inputs = bytes(plc.raw("E"))
                    plc = Plc(sc, sources, clock)
                    plc.raw("E")[:len(inputs)] = inputs
            else:
                plc.write(w)
        plc.set_init_sd(c["init_sd"])
        clock[0] = (t0 + k * dt + 0.5) / 1000.0
        try:
            plc.sim.runCycle()
        except Exception as e:
            raise Mismatch(where(sc, k, dt, cycles) + "Awlsim stops with an error: %s"
                           % short_error(e))
        exp = c["expect"]
        for gi, g in enumerate(sc["groups"]):
            for inst, want in zip(g["instances"], exp["states"][gi]):
                _, got = plc.field(gi, inst + ".CurrentState")
                if got != want:
                    raise Mismatch(where(sc, k, dt, cycles) + "group %s, instance %s: CurrentState "
                                   "simulator %d, awlsim %d" % (g["name"], inst, want, got))
            for name, want in zip(g["msgs"], exp["msgs"][gi]):
                _, got = plc.field(gi, name)
                if (got & 1) != want:
                    raise Mismatch(where(sc, k, dt, cycles) + "group %s, message bit %s: "
                                   "simulator %d, awlsim %d" % (g["name"], name, want, got & 1))
        for area in ("E", "A", "M"):
            ours = bytes.fromhex(exp[area])
            raw = plc.raw(area)
            theirs = bytes(raw[:len(ours)])
            if theirs != ours or any(raw[len(ours):]):
                end = len(raw)
                while end > 0 and raw[end - 1] == 0:
                    end -= 1
                d = bit_diff(area, ours, bytes(raw[:end]))
                raise Mismatch(where(sc, k, dt, cycles) + d)
    return len(cycles)


def short_error(e):
    """Awlsim's error text without its CPU dump."""
    text = str(e).strip()
    cut = text.find("[S7-CPU]")
    if cut >= 0:
        text = text[:cut]
    return " ".join(line.strip() for line in text.splitlines() if line.strip())


def where(sc, k, dt, cycles):
    lines = ["first differing cycle %d (t = %d ms)%s:" % (
                 k, k * dt, ", INIT_SD = 1" if cycles[k - 1]["init_sd"] else "")]
    lo = max(1, k - 3)
    for j in range(lo, k + 1):
        ws = cycles[j - 1]["before"]
        if ws:
            lines.append("  before cycle %d: %s" % (j, "; ".join(describe_write(w) for w in ws)))
    return "\n".join(lines) + "\n  "


def main():
    args = sys.argv[1:]
    src_dir = None
    if "--sources" in args and args.index("--sources") + 1 < len(args):
        i = args.index("--sources")
        src_dir = args[i + 1]
        del args[i:i + 2]
    if len(args) != 1:
        print("usage: build-diff.py DIR [--sources SRC]", file=sys.stderr)
        return 2
    base = args[0]
    files = sorted(glob.glob(os.path.join(base, "[0-9][0-9][0-9]-*.json")))
    passed = failed = skipped = by_design = 0
    total_cycles = 0
    start = time.time()
    for path in files:
        with open(path) as fh:
            sc = json.load(fh)
        name = sc["name"]
        t = time.time()
        if "skip" in sc:
            if sc.get("by_design"):
                by_design += 1
                print("not applicable: %s: %s" % (name, sc["skip"]))
            else:
                skipped += 1
                print("SKIPPED: %s: %s" % (name, sc["skip"]))
            continue
        if sc.get("build_error") and not src_dir:
            if sc.get("refused_by_design") and sc["build_error"].startswith("build refused"):
                by_design += 1
                print("not applicable: %s: %s (a workspace of deliberate mistakes)"
                      % (name, sc["build_error"]))
            else:
                skipped += 1
                print("SKIPPED: %s: %s" % (name, sc["build_error"]))
            continue
        try:
            n = run_scenario(sc, base, src_dir)
        except Mismatch as m:
            failed += 1
            print("FAILED: %s\n  %s" % (name, str(m)))
            continue
        passed += 1
        total_cycles += n
        print("ok: %s: %d cycles agree (%.1f s)" % (name, n, time.time() - t))
    print("build-diff: %d scenarios agree (%d cycles), %d failed, %d skipped, %d not applicable; "
          "%.1f s" % (passed, total_cycles, failed, skipped, by_design, time.time() - start))
    return 0 if failed == 0 and skipped == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
