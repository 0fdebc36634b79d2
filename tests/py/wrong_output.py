#!/usr/bin/env python3
"""Plausible but wrong tool output for tests/oracle_mutants.test and
tests/field_oracle.test: valid streams (CRCs and TAIL recomputed) that a
weak oracle accepts, each made from a right one.

usage: wrong_output.py KIND IN [ARG] > OUT
  steps-empty     every MDLT, UPDT and pATH emptied: the steps duplicate nothing
  hanging-node    step 1 also splits an element away from the cut at the midpoint
                  of an interior edge, leaving a hanging node (a T-junction); its
                  UPDT recomputed to fit that mesh, the later steps dropped
  extra-copy      step 1 also copies node 0, which no element takes
  prov-from IN2   the cut's pROv and pLAN replaced by IN2's: the steps of another
                  command line
  updt-scale S    E[0, 0] of step S's UPDT times 1 + 1e-9
  field-scale S   the fELD of step S times 1 + 1e-8
"""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402
from craft import build  # noqa: E402


def mdlt_bytes(d, dim):
    """MDLT payload (formats/stream.md 7.1) of the dict cutsys.mdlt decodes"""
    n, nm, na = len(d["parent"]), len(d["elem"]), len(d["cadd"])
    return (struct.pack("<q%di" % n, n, *d["parent"]) + struct.pack("<%dd" % (n * dim), *sum(map(list, d["x"]), []))
            + struct.pack("<q%di" % nm, nm, *d["elem"]) + struct.pack("<%di" % sum(map(len, d["conn"])), *sum(map(list, d["conn"]), []))
            + struct.pack("<q%di" % sum(map(len, d["cadd"])), na, *sum(map(list, d["cadd"]), []))
            + struct.pack("<%di" % (na + 2), *d["madd"], d["flags"], 0))


def updt_for(m, d, bd):
    """the UPDT (7.2) of a first step with MDLT d and BDLT payload bd on the uncut
    mesh m, from the cut systems assembled before and after it"""
    cm = cutsys.CutMesh(m)
    Kb, fb = cm.assemble()
    cm.apply_mdlt(d)
    if bd:
        cm.apply_bdlt(cutsys.bdlt(bd))
    Ka, fa = cm.assemble()
    n0, n = len(fb), len(fa)
    delta = {key: Ka.get(key, 0.0) - Kb.get(key, 0.0) for key in set(Ka) | set(Kb)}
    H = sorted({i for key, v in delta.items() if v != 0 for i in key if i < n0} |
               {i for i in range(n0) if fa[i] != fb[i]})
    g = H + list(range(n0, n))
    s = len(g)
    E = [-delta.get((min(g[a], g[b]), max(g[a], g[b])), 0.0) for b in range(s) for a in range(s)]
    df = [fa[i] - (fb[i] if i < n0 else 0.0) for i in g]
    return struct.pack("<ii%di%dd%dd" % (len(H), s * s, s), len(H), n - n0, *H, *E, *df)


def hanging(recs, m):
    dim, nv = m["dim"], m["nv"]
    i = next(k for k, r in enumerate(recs) if r[0] == "MDLT")
    step = recs[i][2]
    d = cutsys.mdlt(recs[i][3], dim, nv)
    conn = list(m["conn"])
    for e, c in zip(d["elem"], d["conn"]):
        conn[e] = c
    conn += d["cadd"]
    touched = set(d["elem"]) | set(range(len(m["conn"]), len(conn)))
    near = {v for e in touched for v in conn[e]}
    faces = {}
    for e, c in enumerate(conn):
        for j in range(nv):
            faces.setdefault(tuple(sorted(c[:j] + c[j + 1:])), []).append(e)
    inner = [e for e in range(len(m["conn"])) if e not in touched and not near & set(conn[e]) and
             all(len(faces[tuple(sorted(conn[e][:j] + conn[e][j + 1:]))]) == 2 for j in range(nv))]
    e = inner[0]
    c = conn[e]
    a, b = c[0], c[1]
    x = m["x"] + d["x"]
    n = len(x)
    d["parent"].append(a)
    d["x"].append(tuple((x[a][k] + x[b][k]) / 2 for k in range(dim)))
    k = sum(1 for q in d["elem"] if q < e)
    d["elem"].insert(k, e)
    d["conn"].insert(k, tuple(n if v == b else v for v in c))
    d["cadd"].append(tuple(n if v == a else v for v in c))
    d["madd"].append(m["mat"][e])
    recs[i][3] = mdlt_bytes(d, dim)
    bd = next((r[3] for r in recs if r[0] == "BDLT" and r[2] == step), None)
    next(r for r in recs if r[0] == "UPDT" and r[2] == step)[3] = updt_for(m, d, bd)
    return [r for r in recs if r[2] <= step]


def scale(recs, typ, step, at, factor):
    """the f64 values of the step's record typ from offset at(payload) on, times factor"""
    r = next(r for r in recs if r[0] == typ and r[2] == step)
    p = bytearray(r[3])
    lo, hi = at(p)
    n = (hi - lo) // 8
    struct.pack_into("<%dd" % n, p, lo, *[v * factor for v in struct.unpack_from("<%dd" % n, p, lo)])
    r[3] = bytes(p)


def field_values(p):
    """the displacements of a fELD (7.3)"""
    count, indexed = struct.unpack_from("<qi", p, 8)
    return 24 + 4 * count * indexed, len(p)


def first_e(p):
    """E[0, 0] of an UPDT (7.2)"""
    o = 8 + 4 * struct.unpack_from("<i", p, 0)[0]
    return o, o + 8


def cut_prov(recs):
    return next(r for r in recs if r[0] == "pROv" and r[3].split(b"\n", 1)[1].split(b" ")[0].endswith(b"cut"))


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    kind = sys.argv[1]
    recs = [list(r) for r in augstream.records(open(sys.argv[2], "rb").read())]
    m = augstream.mesh(recs)
    dim, nv = m["dim"], m["nv"]
    if kind == "steps-empty":
        empty = {"MDLT": struct.pack("<qqqii", 0, 0, 0, 0, 0), "UPDT": struct.pack("<ii", 0, 0),
                 "pATH": struct.pack("<iiq", dim, 0, 0)}
        for r in recs:
            r[3] = empty.get(r[0], r[3])
    elif kind == "hanging-node":
        recs = hanging(recs, m)
    elif kind == "extra-copy":
        r = next(r for r in recs if r[0] == "MDLT")
        d = cutsys.mdlt(r[3], dim, nv)
        d["parent"].append(0)
        d["x"].append(m["x"][0])
        r[3] = mdlt_bytes(d, dim)
    elif kind == "prov-from":
        other = augstream.records(open(sys.argv[3], "rb").read())
        cut_prov(recs)[3] = cut_prov(other)[3]
        plan = [r for r in other if r[0] == "pLAN"]
        for r in recs:
            if r[0] == "pLAN" and plan:
                r[3] = plan[0][3]
    elif kind == "updt-scale":
        scale(recs, "UPDT", int(sys.argv[3]), first_e, 1 + 1e-9)
    elif kind == "field-scale":
        scale(recs, "fELD", int(sys.argv[3]), field_values, 1 + 1e-8)
    else:
        raise SystemExit(__doc__)
    sys.stdout.buffer.write(build([tuple(r) for r in recs]))


if __name__ == "__main__":
    main()
