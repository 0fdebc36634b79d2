#!/usr/bin/env python3
"""refine's 3-D bisection replayed split by split, independently of the C
library, for the option tests of refine(1) (--max-aspect3, --min-dihedral,
--levels3, --max-new).

usage: bisect3d_replay.py IN.aug OUT.aug [--max-aspect3 A] [--min-dihedral D]
                          [--levels3 N] [--max-new C]     (defaults 3, 0, 3, none)

IN: a 3-D stream whose step 1 is a cut step (its MDLT applied to the mesh:
the seeds are the tets it re-wired or added); OUT: refine's output. The
folded MDLT of step 1 lists the cut's new nodes first, then the refinement
nodes in the order refine made them. Each refinement node must be the exact
midpoint 0.5 (x_a + x_b) of an edge {a, b} of the mesh so far; the edge is
split with every tet around it (each tet -> the child keeping a and the child
keeping b, one level deeper than its parent), and
- the split lowers the worst R / (3 r) around the edge;
- some tet around the edge may start it: a seed or a child, at a level below
  N, bad (R / (3 r) > A, or a dihedral angle < D: refine_quality.py's
  formulas), whose first edge, longest first, whose split lowers the worst
  tet around it, is {a, b};
- at most C new nodes; qUAl bisections = the splits replayed.
At the end the replayed tets are the tets of OUT's mesh after step 1.
Prints 'ok splits=S seeds=N bad_seeds=B worst=W -> W'' (the worst R / (3 r) of
the seeds before, of the seeds' descendants after), or the first failure;
exit 1 on a failure."""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402
from refine_quality import dihedrals, tet_aspect  # noqa: E402


def fail(msg):
    print("bisect3d_replay: %s: %s" % (sys.argv[2], msg))
    sys.exit(1)


def main():
    a = sys.argv[1:]
    o = {k: float(a[a.index(k) + 1]) for k in ("--max-aspect3", "--min-dihedral", "--levels3", "--max-new") if k in a}
    A, D = o.get("--max-aspect3", 3.0), o.get("--min-dihedral", 0.0)
    N, cap = o.get("--levels3", 3), o.get("--max-new")
    rin = augstream.records(open(a[0], "rb").read())
    rout = augstream.records(open(a[1], "rb").read())
    cm = cutsys.CutMesh(augstream.mesh(rin))
    if cm.dim != 3:
        fail("not a 3-D mesh")
    md = [p for t, fl, s, p in rin if t == "MDLT" and s == 1]
    fo = [p for t, fl, s, p in rout if t == "MDLT" and s == 1]
    ql = [augstream.kv(p)[1] for t, fl, s, p in rout if t == "qUAl" and s == 1 and augstream.kv(p)[0] == "refine"]
    if len(md) != 1 or len(fo) != 1 or len(ql) != 1:
        fail("step 1 needs one MDLT in IN, one MDLT and one qUAl of refine in OUT")
    d, f, q = cutsys.mdlt(md[0], 3, 4), cutsys.mdlt(fo[0], 3, 4), ql[0]
    ne0 = len(cm.conn)
    cm.apply_mdlt(d)
    x, tets = cm.x, [tuple(c) for c in cm.conn]
    seeds = set(d["elem"]) | set(range(ne0, len(tets)))
    if [tuple(p) for p in f["x"][:len(d["x"])]] != [tuple(p) for p in d["x"]]:
        fail("the folded MDLT does not begin with the cut's new nodes")
    level = {t: 0 for t in range(len(tets))}
    queued = set(seeds)
    cache = {}

    def fig(c):
        if c not in cache:
            P = [x[v] for v in c]
            cache[c] = (tet_aspect(P), min(dihedrals(P)))
        return cache[c]

    def bad(c):
        asp, dh = fig(c)
        return (A > 0 and asp > A) or (D > 0 and dh < D)

    def children(c, u, w, m):
        return tuple(m if v == w else v for v in c), tuple(m if v == u else v for v in c)

    def star(u, w):
        return [t for t, c in enumerate(tets) if u in c and w in c]

    def improves(u, w, mid):
        """worst aspect around {u, w} now, and after its split at mid"""
        x.append(mid)
        m = len(x) - 1
        now = after = 0.0
        for t in star(u, w):
            now = max(now, fig(tets[t])[0])
            for ch in children(tets[t], u, w, m):
                after = max(after, tet_aspect([x[v] for v in ch]))
        x.pop()
        return now, after

    def midpoint(u, w):
        return tuple(0.5 * (x[u][k] + x[w][k]) for k in range(3))

    def first_improving(c):
        es = [(c[i], c[j]) for i in range(4) for j in range(i + 1, 4)]
        es = sorted(es, key=lambda e: -sum((x[e[1]][k] - x[e[0]][k]) * (x[e[1]][k] - x[e[0]][k]) for k in range(3)))
        for u, w in es:
            now, after = improves(u, w, midpoint(u, w))
            if after < now * (1 - 1e-9):
                return {u, w}
        return None

    worst0 = max(fig(tets[t])[0] for t in seeds)
    nbad = sum(bad(tets[t]) for t in seeds)
    refn = [tuple(p) for p in f["x"][len(d["x"]):]]
    if cap is not None and len(f["x"]) > max(cap, len(d["x"])):
        fail("%d new nodes, --max-new %g" % (len(f["x"]), cap))
    for j, X in enumerate(refn):
        edges = {(min(c[i], c[k]), max(c[i], c[k])) for c in tets for i in range(4) for k in range(i + 1, 4)}
        hit = [e for e in edges if midpoint(*e) == X]
        if len(hit) != 1:
            fail("refinement node %d at %s is the midpoint of %d edges of the mesh so far" % (j, X, len(hit)))
        u, w = hit[0]
        now, after = improves(u, w, X)
        if not after < now:
            fail("split %d of edge %s: worst R/(3r) around it %.6g -> %.6g, not lower" % (j, hit[0], now, after))
        st = star(u, w)
        if not any(t in queued and level[t] < N and bad(tets[t]) and first_improving(tets[t]) == {u, w} for t in st):
            fail("split %d of edge %s: no tet around it is a queued bad tet below level %g whose first improving "
                 "edge (longest first) it is" % (j, hit[0], N))
        x.append(X)
        m = len(x) - 1
        for t in st:
            c1, c2 = children(tets[t], u, w, m)
            lv = level[t] + 1
            tets[t] = c1
            tets.append(c2)
            level[t] = level[len(tets) - 1] = lv
            for s in (t, len(tets) - 1):
                if lv < N:
                    queued.add(s)
                else:
                    queued.discard(s)
    if q["bisections"] != len(refn):
        fail("qUAl bisections %g, %d splits replayed" % (q["bisections"], len(refn)))
    ref = augstream.mesh(rout)
    fine = cutsys.CutMesh(ref)
    for t, fl, s, p in rout:
        if t == "MDLT" and s == 1:
            fine.apply_mdlt(cutsys.mdlt(p, 3, 4))
    if sorted(tuple(sorted(c)) for c in fine.conn) != sorted(tuple(sorted(c)) for c in tets):
        fail("the replayed splits do not give OUT's tets")
    desc = [t for t in range(len(tets)) if level[t] > 0 or t in seeds]
    worst1 = max(fig(tets[t])[0] for t in desc)
    print("ok splits=%d seeds=%d bad_seeds=%d worst=%.4g -> %.4g" % (len(refn), len(seeds), nbad, worst0, worst1))


main()
