#!/usr/bin/env python3
"""The nodes a planar cut duplicated, step by step, against what cut(1)'s
options ask, computed here from the mesh alone (augstream.py, cutsys.py).

usage: cut_nodes.py OUT.aug --plane nx,ny,nz,d [--per-step K] [--advance dx,dy,dz]
                    [--polygon x,y,z,...] [--count]

The plane's nodes are the nodes within 1e-9 of it (the bundled bricks are cut
along mesh planes). With --polygon, only those whose projection onto the
plane lies strictly inside the projected polygon (barycentric signs of a fan
triangulation: convex polygons; a node within 1e-6 of an edge is an error of
the test case). --count prints that number and exits. Otherwise, for every
step's MDLT (parents: the duplicated nodes; one copy each on a plane):
- nnew = K on every step but the last, 1 <= nnew <= K on the last;
- the parents are distinct plane nodes, no node is duplicated twice, and at
  the end every plane node (inside the polygon) was duplicated;
- with --advance: the steps advance along the direction's component in the
  plane, a: the mean of a.x over each step's parents does not decrease, and
  every parent of a step lies at or before (1e-9) every parent of the next.
Prints 'ok steps=S nodes=N means=...'; exit 1 on the first failure."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402


def fail(msg):
    print("cut_nodes: %s: %s" % (sys.argv[1], msg))
    sys.exit(1)


def dot(a, b):
    return sum(p * q for p, q in zip(a, b))


def main():
    a = sys.argv[1:]
    o = {k: [float(t) for t in a[a.index(k) + 1].split(",")] for k in ("--plane", "--per-step", "--advance", "--polygon")
         if k in a}
    recs = augstream.records(open(a[0], "rb").read())
    m = augstream.mesh(recs)
    x = m["x"]
    n = o["--plane"][:3]
    ln = math.sqrt(dot(n, n))
    n, d = [c / ln for c in n], o["--plane"][3] / ln
    plane = [i for i, p in enumerate(x) if abs(dot(p, n) - d) <= 1e-9]
    if "--polygon" in o:
        # a basis (u, v) of the plane; the polygon's corners projected into it
        e = min(range(3), key=lambda k: abs(n[k]))
        u = [(1.0 if k == e else 0.0) - n[e] * n[k] for k in range(3)]
        u = [c / math.sqrt(dot(u, u)) for c in u]
        v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
        pts = o["--polygon"]
        q = [(dot(pts[i:i + 3], u), dot(pts[i:i + 3], v)) for i in range(0, len(pts), 3)]

        def side(p, s, t):
            return ((t[0] - s[0]) * (p[1] - s[1]) - (t[1] - s[1]) * (p[0] - s[0])) / math.dist(s, t)
        orient = 1 if sum(side(q[i], q[0], q[1]) for i in range(2, len(q))) > 0 else -1
        inside = []
        for i in plane:
            p = (dot(x[i], u), dot(x[i], v))
            ds = [orient * side(p, q[k], q[(k + 1) % len(q)]) for k in range(len(q))]
            if min(abs(t) for t in ds) < 1e-6:
                fail("node %d at %s lies on an edge of the polygon: choose another" % (i, x[i]))
            if min(ds) > 0:
                inside.append(i)
        plane = inside
    if "--count" in a:
        print(len(plane))
        return
    K = int(o["--per-step"][0]) if "--per-step" in o else (len(plane) + 63) // 64
    adv = None
    if "--advance" in o:
        w = o["--advance"]
        w = [w[k] - dot(w, n) * n[k] for k in range(3)]
        adv = [c / math.sqrt(dot(w, w)) for c in w]
    steps = [(s, cutsys.mdlt(p, m["dim"], m["nv"])["parent"]) for t, fl, s, p in recs if t == "MDLT"]
    if not steps:
        fail("no MDLT")
    seen, means, last = set(), [], None
    onplane = set(plane)
    for k, (s, par) in enumerate(steps):
        final = k == len(steps) - 1
        if not (len(par) == K or (final and 1 <= len(par) <= K)):
            fail("step %d duplicated %d nodes, --per-step %d" % (s, len(par), K))
        if len(set(par)) != len(par) or seen & set(par):
            fail("step %d: a node duplicated twice" % s)
        bad = [i for i in par if i not in onplane]
        if bad:
            fail("step %d: node %d at %s is not a node of the plane%s" % (s, bad[0], x[bad[0]],
                 " inside the polygon" if "--polygon" in o else ""))
        seen |= set(par)
        if adv:
            c = [dot(x[i], adv) for i in par]
            means.append(sum(c) / len(c))
            if last is not None and (means[-1] < means[-2] - 1e-12 or min(c) < last - 1e-9):
                fail("step %d: parents from %.6g (mean %.6g) along the advance, the step before reached %.6g "
                     "(mean %.6g)" % (s, min(c), means[-1], last, means[-2]))
            last = max(c)
    if seen != onplane:
        fail("%d of the %d nodes were never duplicated" % (len(onplane - seen), len(onplane)))
    print("ok steps=%d nodes=%d means=%s" % (len(steps), len(seen), " ".join("%.3g" % t for t in means)))


main()
