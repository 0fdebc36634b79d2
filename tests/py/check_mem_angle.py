"""Angles of a refined membrane (refine(1) --min-angle on mem3), from the
records only: usage check_mem_angle.py IN OUT MIN. The mesh after each step is
replayed from OUT's MDLT records; every triangle any step writes has every
angle >= MIN degrees, except at a corner between two edges that no flip in
the triangle's plane can move: each a boundary edge (a lip, the sheet's edge)
or a fold (the triangle across it not coplanar, normals 1e-10 apart), or on
an edge of IN's original triangles (refine flips within an original triangle
only) -- a corner bisection keeps in a child (refine(1), mem3)."""
import math
import sys

import augstream
import cutsys


def sub(a, b):
    return [a[k] - b[k] for k in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    n = math.sqrt(sum(c * c for c in a))
    return [c / n for c in a]


def main():
    src, out, amin = sys.argv[1], sys.argv[2], float(sys.argv[3])
    m0 = augstream.mesh(augstream.records(open(src, "rb").read()))
    X0, T0 = list(m0["x"]), list(m0["conn"])
    segs = {tuple(sorted((t[k], t[(k + 1) % 3]))) for t in T0 for k in range(3)}
    ext = max(max(p[k] for p in X0) - min(p[k] for p in X0) for k in range(3))

    def on_seg(q, a, b):
        d = sub(b, a)
        w = sub(q, a)
        t = sum(x * y for x, y in zip(w, d)) / sum(x * x for x in d)
        if t < -1e-12 or t > 1 + 1e-12:
            return False
        return max(abs(w[k] - t * d[k]) for k in range(3)) <= 1e-9 * ext

    def original_edge(p, q):
        return any(on_seg(p, X0[a], X0[b]) and on_seg(q, X0[a], X0[b]) for a, b in segs)

    recs = augstream.records(open(out, "rb").read())
    cm = cutsys.CutMesh(augstream.mesh(recs))
    checked = exempt = 0
    for t, fl, s, p in recs:
        if t != "MDLT":
            continue
        d = cutsys.mdlt(p, 3, 3)
        ne0 = len(cm.conn)
        cm.apply_mdlt(d)
        X, T = cm.x, cm.conn
        edges = {}
        for e, c in enumerate(T):
            for k in range(3):
                edges.setdefault(frozenset((c[k], c[(k + 1) % 3])), []).append(e)
        normal = {}

        def nrm(e):
            if e not in normal:
                c = T[e]
                normal[e] = unit(cross(sub(X[c[1]], X[c[0]]), sub(X[c[2]], X[c[0]])))
            return normal[e]

        def stiff(e, a, b):
            o = [f for f in edges[frozenset((a, b))] if f != e]
            return (not o or sum(x * y for x, y in zip(nrm(e), nrm(o[0]))) < 1 - 1e-10
                    or original_edge(X[a], X[b]))

        for e in list(d["elem"]) + list(range(ne0, len(T))):
            c = T[e]
            for k in range(3):
                p0, p1, p2 = X[c[k]], X[c[(k + 1) % 3]], X[c[(k + 2) % 3]]
                u, v = sub(p1, p0), sub(p2, p0)
                cs = sum(x * y for x, y in zip(u, v)) / math.sqrt(sum(x * x for x in u) * sum(x * x for x in v))
                ang = math.degrees(math.acos(max(-1.0, min(1.0, cs))))
                checked += 1
                if ang >= amin:
                    continue
                if stiff(e, c[k], c[(k + 1) % 3]) and stiff(e, c[(k + 2) % 3], c[k]):
                    exempt += 1
                    continue
                print("FAIL step %d: triangle %d has an angle of %.4g degrees at node %d" % (s, e, ang, c[k]))
                sys.exit(1)
    print("ok %s: %d corners >= %g degrees, %d between two edges no flip moves" % (out, checked - exempt, amin, exempt))


main()
