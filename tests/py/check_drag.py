#!/usr/bin/env python3
"""Independent checks of cut --drag and deformation-only steps (formats/stream.md
7.1, 7.7), from the specification only.

usage: check_drag.py STREAM N [--only] [--rigid] TARGET:d...

TARGET:d as cut's --drag (a set name, or box:LO,HI with dim numbers each, then
dim displacement components). For every fELD of cut step t (1..N, the first
cut step of the stream is 1), every component of every original node of the
target (a set of the stream's nSEt, or the nodes of NODE inside the box) must
hold exactly (t/N) d_c, computed here as (t / N) * d_c in binary64.
--only: the steps are deformation-only: per step exactly the records MDLT
(nnew = nmod = nadd = 0), BDLT (if any), UPDT (k = 0), pATH (nseg = 0), in
that order, and the stream has N of them.
--rigid: moreover every node of every field holds (t/N) d of the first target
to 1e-10 relative (dragging the whole support with no load is a rigid
translation). Prints "ok STREAM fields=F nodes=P"; exit 1 on a failure."""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402


def fail(msg):
    print("FAIL %s: %s" % (sys.argv[1], msg))
    sys.exit(1)


def target(m, spec):
    """(nodes, d) of one TARGET:d"""
    dim = m["dim"]
    where, d = spec.rsplit(":", 1)
    d = [float(v) for v in d.split(",")]
    if len(d) != dim:
        raise SystemExit("%s: want %d components" % (spec, dim))
    if where.startswith("box:"):
        b = [float(v) for v in where[4:].split(",")]
        lo, hi = b[:dim], b[dim:]
        nodes = [i for i, x in enumerate(m["x"]) if all(lo[c] <= x[c] <= hi[c] for c in range(dim))]
    else:
        nodes = m["sets"][where]
    return nodes, d


def steps(recs):
    """{step: [(type, payload)]} of the per-step records of cut (MDLT BDLT UPDT pATH)"""
    out = {}
    for t, fl, s, p in recs:
        if t in ("MDLT", "BDLT", "UPDT", "pATH"):
            out.setdefault(s, []).append((t, p))
    return out


def check_only(recs, n, dim):
    st = steps(recs)
    if sorted(st) != list(range(1, n + 1)):
        fail("steps %s, want 1..%d" % (sorted(st), n))
    for s, rs in sorted(st.items()):
        types = [t for t, p in rs]
        if types not in (["MDLT", "BDLT", "UPDT", "pATH"], ["MDLT", "UPDT", "pATH"]):
            fail("step %d: records %s" % (s, types))
        md = rs[0][1]
        nnew, = struct.unpack_from("<q", md, 0)
        if nnew:
            fail("step %d: MDLT adds %d nodes" % (s, nnew))
        pos = 8 + nnew * (4 + 8 * dim)
        nmod, = struct.unpack_from("<q", md, pos)
        nadd, = struct.unpack_from("<q", md, pos + 8)
        if nmod or nadd or len(md) != pos + 24:
            fail("step %d: MDLT nmod %d nadd %d (%d bytes)" % (s, nmod, nadd, len(md)))
        up = rs[-2][1]
        m, k = struct.unpack_from("<ii", up, 0)
        if k != 0:
            fail("step %d: UPDT k = %d" % (s, k))
        nseg, = struct.unpack_from("<q", rs[-1][1], 8)
        if nseg:
            fail("step %d: pATH of %d segments" % (s, nseg))


def main():
    args = sys.argv[1:]
    if len(args) < 3:
        raise SystemExit(__doc__)
    only, rigid = "--only" in args, "--rigid" in args
    args = [a for a in args if a not in ("--only", "--rigid")]
    recs = augstream.records(open(args[0], "rb").read())
    n = int(args[1])
    m = augstream.mesh(recs)
    dim = m["dim"]
    targets = [target(m, a) for a in args[2:]]
    if only:
        check_only(recs, n, dim)
    first = min((s for t, fl, s, p in recs if t == "UPDT"), default=1)
    nf = npre = 0
    for t, fl, s, p in recs:
        if t != "fELD" or s < first:
            continue
        step = s - first + 1
        kind, fdim, count, indexed = struct.unpack_from("<iiqi", p, 0)
        pos = 24
        nodes = list(range(count))
        if indexed:
            nodes = list(struct.unpack_from("<%di" % count, p, pos))
            pos += 4 * count
        u = struct.unpack_from("<%dd" % (count * dim), p, pos)
        at = {v: q for q, v in enumerate(nodes)}
        for tn, d in targets:
            for v in tn:
                if v not in at:
                    continue
                for c in range(dim):
                    want = (step / n) * d[c]
                    got = u[at[v] * dim + c]
                    if got != want:
                        fail("step %d: node %d component %d holds %.17g, want (%d/%d) %.17g = %.17g"
                             % (s, v, c, got, step, n, d[c], want))
                npre += 1
        if rigid:
            d = targets[0][1]
            w = [(step / n) * dc for dc in d]
            scale = max(abs(x) for x in w)
            for q in range(count):
                for c in range(dim):
                    if abs(u[q * dim + c] - w[c]) > 1e-10 * scale:
                        fail("step %d: node %d component %d = %.17g, not the translation %.17g"
                             % (s, nodes[q], c, u[q * dim + c], w[c]))
        nf += 1
    if nf != n:
        fail("%d fields of cut steps, want %d" % (nf, n))
    print("ok %s fields=%d nodes=%d" % (args[0], nf, npre))


main()
