#!/usr/bin/env python3
"""Element quality of refine's steps, computed here from the refined mesh
(augstream.py, cutsys.py: the MDLT/BDLT records replayed), for the option
tests of refine(1).

usage: refine_quality.py OUT.aug [--min-angle D] [--max-aspect A] [--max-new N]
                         [--midpoints yes|no] [--bad-left] [--area-limited]

For every step with refine's qUAl, on the elements the folded step wrote (the
MDLT's re-wired and added elements, in the mesh after the step):
- 2-D and sheets (mem3): the angles (law of cosines) and longest / shortest edge; 3-D: the six
  dihedral angles (between the two faces at each edge, from the other two
  corners projected normal to the edge) and R / (3 r) (circumcentre solved
  here, r = 3 V / surface); their minimum and maximum equal qUAl's min_angle
  (min_dihedral), aspect_max and aspect_mean to 1e-9, nodes_added and elems_added the MDLT's
  counts;
- --min-angle D (2-D): no written triangle has an angle below D, except in a
  corner between two constrained edges (open: boundary or cut) sharper than D;
- --bad-left (2-D): qUAl bad_left is the number of written triangles above the
  aspect bound A (--max-aspect, default 3) or below the angle D, whatever
  kept them (a sharp corner, --max-new, refine --area-ratio);
- --area-limited: refine ran with --area-ratio, which leaves bad triangles
  anywhere: no angle bound is checked, D only counts for --bad-left;
- --max-new N: nodes_added <= max(N, cut_nodes);
- --midpoints yes: every new node that is not the cut's own (the first
  cut_nodes) and not a copy (coincident with an older node) is the midpoint
  of two older nodes (plain bisection, --no-flip); no: at least one is not
  (centroids of the Lepp-Delaunay refinement).
Prints one line per step, 'step S written=W min_angle=.. aspect_max=..
nodes_added=.. capped=.. bisections=.. flips=..', then 'ok'; exit 1 on the
first failure."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402


def fail(msg):
    print("refine_quality: %s: %s" % (sys.argv[1], msg))
    sys.exit(1)


def sub(a, b):
    return [a[k] - b[k] for k in range(len(a))]


def dot(a, b):
    return sum(a[k] * b[k] for k in range(len(a)))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def tri_angles(P):
    """the three angles (degrees) of a triangle, law of cosines"""
    L = [math.dist(P[(i + 1) % 3], P[(i + 2) % 3]) for i in range(3)]  # L[i] opposite corner i
    out = []
    for i in range(3):
        a, b, c = L[i], L[(i + 1) % 3], L[(i + 2) % 3]
        out.append(math.degrees(math.acos(max(-1.0, min(1.0, (b * b + c * c - a * a) / (2 * b * c))))))
    return out


def tri_aspect(P):
    L = [math.dist(P[i], P[(i + 1) % 3]) for i in range(3)]
    return max(L) / min(L)


def dihedrals(P):
    """the six dihedral angles (degrees) of a tetrahedron"""
    out = []
    for i in range(4):
        for j in range(i + 1, 4):
            k, l = [q for q in range(4) if q not in (i, j)]
            e = sub(P[j], P[i])
            ee = dot(e, e)
            u, v = sub(P[k], P[i]), sub(P[l], P[i])
            u = [u[c] - dot(u, e) / ee * e[c] for c in range(3)]
            v = [v[c] - dot(v, e) / ee * e[c] for c in range(3)]
            cs = dot(u, v) / math.sqrt(dot(u, u) * dot(v, v))
            out.append(math.degrees(math.acos(max(-1.0, min(1.0, cs)))))
    return out


def tet_aspect(P):
    """R / (3 r): circumcentre c from 2 (p_i - p_0) . c = |p_i|^2 - |p_0|^2 (Cramer),
    inradius r = 3 V / total face area"""
    A = [[2 * (P[i][k] - P[0][k]) for k in range(3)] for i in (1, 2, 3)]
    b = [dot(P[i], P[i]) - dot(P[0], P[0]) for i in (1, 2, 3)]

    def det(M):
        return dot(M[0], cross(M[1], M[2]))
    D = det(A)
    c = []
    for k in range(3):
        M = [row[:] for row in A]
        for i in range(3):
            M[i][k] = b[i]
        c.append(det(M) / D)
    R = math.dist(c, P[0])
    V = abs(dot(sub(P[1], P[0]), cross(sub(P[2], P[0]), sub(P[3], P[0])))) / 6
    S = 0.0
    for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
        n = cross(sub(P[f[1]], P[f[0]]), sub(P[f[2]], P[f[0]]))
        S += 0.5 * math.sqrt(dot(n, n))
    return R / (3 * (3 * V / S))


def open_edges(conn):
    """2-D: {sorted edge: count of triangles}"""
    cnt = {}
    for c in conn:
        for i in range(3):
            e = tuple(sorted((c[i], c[(i + 1) % 3])))
            cnt[e] = cnt.get(e, 0) + 1
    return cnt


def main():
    a = sys.argv[1:]
    opt = {}
    for key in ("--min-angle", "--max-aspect", "--max-new", "--midpoints"):
        if key in a:
            opt[key] = a[a.index(key) + 1]
    bad_left = "--bad-left" in a
    limited = "--area-limited" in a
    D = float(opt.get("--min-angle", 0))
    A = float(opt.get("--max-aspect", 3))
    recs = augstream.records(open(a[0], "rb").read())
    m = augstream.mesh(recs)
    cm = cutsys.CutMesh(m)
    dim, nv = cm.dim, cm.nv
    tri = nv == 3  # 2-D and sheets (mem3: triangles in 3-D)
    qual = {s: augstream.kv(p)[1] for t, fl, s, p in recs if t == "qUAl" and augstream.kv(p)[0] == "refine"}
    if not qual:
        fail("no qUAl of refine")
    for t, fl, s, p in recs:
        if t == "BDLT":
            cm.apply_bdlt(cutsys.bdlt(p))
        if t != "MDLT":
            continue
        d = cutsys.mdlt(p, dim, nv)
        nn0, ne0 = len(cm.x), len(cm.conn)
        cm.apply_mdlt(d)
        if s not in qual:
            continue
        q = qual[s]
        written = list(d["elem"]) + list(range(ne0, len(cm.conn)))
        mina, maxa, suma, figs = 180.0 if written else 0.0, 0.0, 0.0, []
        for e in written:
            P = [cm.x[v] for v in cm.conn[e]]
            ang = tri_angles(P) if tri else dihedrals(P)
            asp = tri_aspect(P) if tri else tet_aspect(P)
            figs.append((e, ang, asp))
            mina, maxa, suma = min(mina, min(ang)), max(maxa, asp), suma + asp
        key = "min_angle" if tri else "min_dihedral"
        if not written:  # no element written: no quality figures (not 0)
            if key in q or "aspect_max" in q:
                fail("step %d: qUAl %s / aspect_max over no written element" % (s, key))
        elif not (abs(q[key] - mina) <= 1e-9 * max(1.0, mina) and abs(q["aspect_max"] - maxa) <= 1e-9 * max(1.0, maxa)):
            fail("step %d: qUAl %s %.17g aspect_max %.17g, the written elements have %.17g and %.17g"
                 % (s, key, q[key], q["aspect_max"], mina, maxa))
        elif not abs(q["aspect_mean"] - suma / len(written)) <= 1e-9 * max(1.0, suma / len(written)):
            fail("step %d: qUAl aspect_mean %.17g, the %d written elements %.17g"
                 % (s, q["aspect_mean"], len(written), suma / len(written)))
        if q["nodes_added"] != len(d["parent"]) or q["elems_added"] != len(d["cadd"]):
            fail("step %d: qUAl nodes_added %g elems_added %g, MDLT %d and %d"
                 % (s, q["nodes_added"], q["elems_added"], len(d["parent"]), len(d["cadd"])))
        if dim == 2 and (D > 0 or bad_left):
            cnt = open_edges(cm.conn)
            nbad = 0
            for e, ang, asp in figs:
                c = cm.conn[e]
                bad = (A > 0 and asp > A) or min(ang) < D
                nbad += bad
                for i in range(3):
                    if ang[i] >= D:
                        continue
                    e1 = tuple(sorted((c[i], c[(i + 1) % 3])))
                    e2 = tuple(sorted((c[i], c[(i + 2) % 3])))
                    if D > 0 and not limited and not (cnt[e1] == 1 and cnt[e2] == 1):
                        fail("step %d: triangle %d %s has an angle of %.6g degrees < %g (not a corner between "
                             "two open edges)" % (s, e, c, ang[i], D))
            if bad_left and q["bad_left"] != nbad:
                fail("step %d: qUAl bad_left %g, %d written triangles above aspect %g or below %g degrees"
                     % (s, q["bad_left"], nbad, A, D))
        if "--max-new" in opt and not q["nodes_added"] <= max(int(opt["--max-new"]), q["cut_nodes"]):
            fail("step %d: nodes_added %g > --max-new %s (cut_nodes %g)" % (s, q["nodes_added"], opt["--max-new"],
                                                                          q["cut_nodes"]))
        if "--midpoints" in opt:
            hmax = max(math.dist(cm.x[c[i]], cm.x[c[j]]) for c in cm.conn for i in range(nv) for j in range(i))
            nonmid = 0
            for k in range(len(d["parent"])):
                v = nn0 + k
                X = cm.x[v]
                near = [w for w in range(v) if math.dist(cm.x[w], X) <= hmax]
                if k < q["cut_nodes"] or any(cm.x[w] == X for w in near):
                    continue  # the cut's own node, or a copy
                mid = any(math.dist([2 * X[c] - cm.x[w][c] for c in range(dim)], cm.x[u]) <= 1e-12 * hmax
                          for w in near for u in near if u < w)
                nonmid += not mid
            if opt["--midpoints"] == "yes" and nonmid:
                fail("step %d: %d refinement nodes are not the midpoint of two older nodes" % (s, nonmid))
            if opt["--midpoints"] == "no" and not nonmid:
                fail("step %d: every refinement node is a midpoint (no centroid)" % s)
        print("step %d written=%d %s=%.6g aspect_max=%.6g nodes_added=%d capped=%d bisections=%d flips=%d"
              % (s, len(written), key, mina, maxa, q["nodes_added"], q["capped"], q["bisections"], q["flips"]))
    print("ok")


if __name__ == "__main__":
    main()
