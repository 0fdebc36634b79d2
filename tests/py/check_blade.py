#!/usr/bin/env python3
"""Independent check of a 3-D blade or surface cut (cut(1) --blade, --surface;
formats/stream.md 7.1, 7.2, 7.6), written from the man page and the format.

usage: check_blade.py IN.aug OUT.aug [--stl FILE]

IN: a 3-D stream (meshload | factor, perhaps cut already: its steps are
replayed and its open faces, and the faces inside them, count as cut before); OUT: IN through one cut --blade
BFILE or --surface FILE (an ASCII STL given again as --stl, or a blade file)
stage, whose pROv says --steps, --mode, --snap-tol. The swept surface of each
step is built here from the blade file as cut(1) defines it (positions by the
Bernstein form, quads of consecutive sample times split along a_i-b_j); a
surface is taken whole. At every step, on the mesh rebuilt from the MDLT and
BDLT records:
- every element positive, the volume unchanged (1e-12), true conformity
  (interior faces in two elements with opposite orientations, an open face on
  the outer boundary or one of two coincident sides of a cut whose nodes are
  copies of one node);
- snap: no element is added, every new node is a copy at its parent; every
  face open across a cut lies between two elements whose centroid segment
  crosses the surface swept so far (so within one element of it), and at
  every point on the cut (a surface: at the last step) the elements around it, joined through the coincident
  faces the surface does not cross, form classes of one node each, distinct
  classes distinct nodes (the separation is complete and no more);
- split: every inserted node (not at its parent) lies on the surface (to
  1e-9 of the longest edge h), every open cut face's corners and centroid
  within --snap-tol times h of the surface (a snapped node lies within the
  tolerance times its edge);
- K_t and f_t accumulated from K_0 and the UPDT records (k = 3 * new nodes)
  equal the cut system assembled here from scratch (tests/py/cutsys.py), entry
  by entry within 1e-12 * max|K|.
Prints 'ok steps=S nodes=N elements=E cut_faces=F max_m=M min_vol_ratio=R'
(R: the least element volume over the least one of the input) or the first
failure ('FAIL step N: ...'), exit 1."""
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import conform  # noqa: E402
import cutsys  # noqa: E402

REL = 1e-12


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def sub(a, b):
    return [a[k] - b[k] for k in range(3)]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def seg_point_dist(a, b, p):
    e = sub(b, a)
    ee = dot(e, e)
    t = max(0.0, min(1.0, dot(sub(p, a), e) / ee)) if ee > 0 else 0.0
    return math.dist(p, [a[k] + t * e[k] for k in range(3)])


def point_tri(p, t):
    """distance of p from triangle t: the plane's when the foot lies inside
    (barycentric coordinates by areas), else the nearest of the three sides"""
    a, b, c = t
    n = cross(sub(b, a), sub(c, a))
    nn = math.sqrt(dot(n, n))
    d = dot(sub(p, a), n) / nn
    f = [p[k] - d * n[k] / nn for k in range(3)]
    w = [dot(cross(sub(b, f), sub(c, f)), n), dot(cross(sub(c, f), sub(a, f)), n), dot(cross(sub(a, f), sub(b, f)), n)]
    if min(w) >= 0:
        return abs(d)
    return min(seg_point_dist(a, b, p), seg_point_dist(b, c, p), seg_point_dist(c, a, p))


def crosses(p, q, t, eps):
    """cut(1): the segment pq crosses triangle t when exactly one of its ends
    lies more than eps on the + side of t's plane and the crossing lies in t"""
    a, b, c = t
    n = cross(sub(b, a), sub(c, a))
    nn = math.sqrt(dot(n, n))
    dp, dq = dot(sub(p, a), n) / nn, dot(sub(q, a), n) / nn
    if (dp > eps) == (dq > eps):
        return False
    s = min(1.0, max(0.0, dp / (dp - dq)))
    x = [p[k] + s * (q[k] - p[k]) for k in range(3)]
    # inside by signed sub-areas against the area, within 1e-9 of it
    w = [dot(cross(sub(b, x), sub(c, x)), n), dot(cross(sub(c, x), sub(a, x)), n), dot(cross(sub(a, x), sub(b, x)), n)]
    return min(w) >= -1e-9 * nn * nn


class Grid:
    """triangles bucketed by their boxes, for the distance and crossing queries"""

    def __init__(self, h):
        self.h, self.cells, self.tris, self.boxes = h, {}, [], []

    def keys(self, lo, hi):
        a = [int(math.floor(v / self.h)) for v in lo]
        b = [int(math.floor(v / self.h)) for v in hi]
        return [(i, j, k) for i in range(a[0], b[0] + 1) for j in range(a[1], b[1] + 1) for k in range(a[2], b[2] + 1)]

    def add(self, t, box):
        i = len(self.tris)
        self.tris.append(t)
        self.boxes.append(([min(p[k] for p in t) for k in range(3)], [max(p[k] for p in t) for k in range(3)]))
        lo = [max(min(p[k] for p in t), box[0][k]) for k in range(3)]
        hi = [min(max(p[k] for p in t), box[1][k]) for k in range(3)]
        if any(lo[k] > hi[k] for k in range(3)):
            return
        for c in self.keys(lo, hi):
            self.cells.setdefault(c, []).append(i)

    def near(self, lo, hi):
        """the triangles whose boxes meet the box [lo, hi]"""
        s = set()
        for c in self.keys(lo, hi):
            s.update(self.cells.get(c, ()))
        bx = self.boxes
        return [self.tris[i] for i in sorted(s)
                if all(bx[i][0][k] <= hi[k] and bx[i][1][k] >= lo[k] for k in range(3))]

    def dist(self, p, lim):
        """the distance of p to the nearest triangle if it is below lim, else 2 lim + 1"""
        ts = self.near([v - lim for v in p], [v + lim for v in p])
        return min([point_tri(p, t) for t in ts] + [2 * lim + 1])


def bernstein(P, u):
    n = len(P) - 1
    return [sum(math.comb(n, i) * u ** i * (1 - u) ** (n - i) * P[i][k] for i in range(n + 1)) for k in range(6)]


class Blade:
    """cut(1) BLADE FILE: keys at tau = i / (keys - 1), the curve lines between
    two keys their Bezier control positions"""

    def __init__(self, path):
        self.keys, self.ctrl, pend = [], [], []
        for line in open(path):
            w = line.split("#")[0].split()
            if not w:
                continue
            v = [float(x) for x in w[1:]]
            if w[0] == "curve":
                pend.append(v)
            else:
                if self.keys:
                    self.ctrl.append(pend)
                pend = []
                self.keys.append(v)

    def at(self, tau):
        ni = len(self.keys) - 1
        i = min(ni - 1, max(0, int(math.floor(tau * ni))))
        return bernstein([self.keys[i]] + self.ctrl[i] + [self.keys[i + 1]], tau * ni - i)

    def sweep(self, t0, t1):
        ni = len(self.keys) - 1
        ts = {t0, t1}
        for i in range(ni):
            sub_ = 16 if self.ctrl[i] else 1
            ts.update(t for t in ((i + j / sub_) / ni for j in range(sub_ + 1)) if t0 < t < t1)
        ts = sorted(ts)
        out = []
        for u, v in zip(ts, ts[1:]):
            p, q = self.at(u), self.at(v)
            for t in ((p[:3], p[3:], q[3:]), (p[:3], q[3:], q[:3])):
                n = cross(sub(t[1], t[0]), sub(t[2], t[0]))
                l2 = max(dot(sub(t[i], t[j]), sub(t[i], t[j])) for i, j in ((0, 1), (1, 2), (2, 0)))
                if dot(n, n) > 1e-24 * l2 * l2:
                    out.append(t)
        return out


def stl_ascii(path):
    v = [[float(x) for x in line.split()[1:4]] for line in open(path) if line.split()[:1] == ["vertex"]]
    return [tuple(v[i:i + 3]) for i in range(0, len(v), 3)]


def options(prov):
    args = prov.split("\n", 1)[1].split(" ")[1:]
    o, i = {}, 0
    while i < len(args):
        if args[i].startswith("--") and i + 1 < len(args) and not args[i + 1].startswith("--"):
            o[args[i]] = args[i + 1]
            i += 2
        else:
            o[args[i]] = ""
            i += 1
    return o


def main():
    a = sys.argv[1:]
    stl = None
    if "--stl" in a:
        i = a.index("--stl")
        stl = a[i + 1]
        a = a[:i] + a[i + 2:]
    if len(a) != 2:
        raise SystemExit(__doc__)
    rin = augstream.records(open(a[0], "rb").read())
    rout = augstream.records(open(a[1], "rb").read())
    # cut's pROv comes first (formats/stream.md: each stage puts its own before the input's)
    prov = [p.decode() for t, f, s, p in rout if t == "pROv" and " --blade " in p.decode() + " "
            or t == "pROv" and " --surface " in p.decode()][0]
    o = options(prov)
    nsteps = int(o["--steps"])
    mode = o.get("--mode", "snap")
    tol = float(o.get("--snap-tol", "0.2"))  # cut(1): the default of --blade and --surface
    m = augstream.mesh(rin)
    cm = cutsys.CutMesh(m)
    if cm.dim != 3:
        fail("not a 3-D mesh")
    x0 = list(cm.x)
    lo = [min(p[k] for p in x0) for k in range(3)]
    hi = [max(p[k] for p in x0) for k in range(3)]
    scale = max(hi[k] - lo[k] for k in range(3))
    eps = 1e-12 * scale
    h = max(math.dist(x0[c[i]], x0[c[j]]) for c in cm.conn for i in range(len(c)) for j in range(i))
    box = ([v - h for v in lo], [v + h for v in hi])
    grid = Grid(2 * h)
    if "--blade" in o:
        blade = Blade(o["--blade"])
        per_step = [blade.sweep((k - 1) / nsteps, k / nsteps) for k in range(1, nsteps + 1)]
    else:
        per_step = [stl_ascii(stl)] + [[] for _ in range(nsteps - 1)]  # whole: at the last step at the latest
    K, f = cm.assemble()
    for t, fl, s, p in rin:
        if t == "KMAT" and cutsys.kmat(p)[0] == 0:
            K = cutsys.kmat(p)[2]
        if t == "FVEC":
            f = cutsys.fvec(p)[1]
    err = cutsys.check(cm, K, f, REL)
    if err:
        fail("K_0: " + err)
    outer = conform.boundary_index(x0, cm.conn, 1e-10 * scale)
    origin, inserted = list(range(len(x0))), {}
    mesh0 = {"x": cm.x, "conn": cm.conn, "nv": cm.nv}
    vol0 = sum(augstream.measure(mesh0, e) for e in range(len(cm.conn)))
    # the steps of IN (an earlier cut): replayed, their open faces cut before
    old = sorted({s for t, fl, s, p in rin if t == "MDLT"})
    for step in old:
        recs = {t: p for t, fl, s, p in rin if s == step}
        d = cutsys.mdlt(recs["MDLT"], 3, cm.nv)
        nb = len(cm.x)
        cm.apply_mdlt(d)
        if "BDLT" in recs:
            cm.apply_bdlt(cutsys.bdlt(recs["BDLT"]))
        for q, par in enumerate(d["parent"]):
            origin.append(origin[par] if cm.x[nb + q] == cm.x[par] else inserted.setdefault(cm.x[nb + q], nb + q))
        err = cutsys.apply_updt(K, f, cutsys.updt(recs["UPDT"]))
        if err:
            fail("step %d of the input: %s" % (step, err))
    before, e = conform.open_faces(cm.x, conform.face_map(cm.conn), outer, origin)
    if e:
        fail("the input: " + e)
    # the input's cut faces, for faces a split later divides: a face inside one of them is old
    old_idx = conform.FaceIndex([[cm.x[v] for v in uses[1]] for uses in before.values()], 1e-10 * scale)

    def is_old(g, f1):
        return g in before or (before and old_idx.find([cm.x[v] for v in f1]) >= 0)
    steps = sorted({s for t, fl, s, p in rout if t == "MDLT"} - set(old))
    if len(steps) != nsteps:
        fail("%d MDLT records for --steps %d" % (len(steps), nsteps))
    pairs, maxm, ncut = {}, 0, 0
    cen = [None] * len(cm.conn)
    minvol = min(augstream.measure({"x": cm.x, "conn": cm.conn, "nv": cm.nv}, e) for e in range(len(cm.conn)))
    worst = 1.0

    def centroid(e):
        if e >= len(cen) or cen[e] is None:
            c = cm.conn[e]
            v = [sum(cm.x[q][k] for q in c) / len(c) for k in range(3)]
            if e < len(cen):
                cen[e] = v
            return v
        return cen[e]

    def cut_snap(e1, e2, key=None):
        if key in before:
            return True
        p, q = centroid(e1), centroid(e2)
        lo_ = [min(p[k], q[k]) - eps for k in range(3)]
        hi_ = [max(p[k], q[k]) + eps for k in range(3)]
        return any(crosses(p, q, t, eps) for t in grid.near(lo_, hi_))

    for si, step in enumerate(steps):
        where = "step %d: " % step
        for t in per_step[si] if "--blade" in o or si == 0 else []:
            grid.add(t, box)
        recs = {t: p for t, fl, s, p in rout if s == step}
        d = cutsys.mdlt(recs["MDLT"], 3, cm.nv)
        nn_before = len(cm.x)
        try:
            cm.apply_mdlt(d)
            if "BDLT" in recs:
                cm.apply_bdlt(cutsys.bdlt(recs["BDLT"]))
        except cutsys.Bad as e:
            fail(where + str(e))
        for q, par in enumerate(d["parent"]):  # nodes inserted at one point (two sides of a cut) share an origin
            v = nn_before + q
            origin.append(origin[par] if cm.x[v] == cm.x[par] else inserted.setdefault(cm.x[v], v))
        mesh = {"x": cm.x, "conn": cm.conn, "nv": cm.nv}
        vols = [augstream.measure(mesh, e) for e in range(len(cm.conn))]
        if min(vols) <= 0:
            fail(where + "element %d has volume %g" % (vols.index(min(vols)), min(vols)))
        worst = min(worst, min(vols) / minvol)
        if abs(sum(vols) - vol0) > REL * vol0:
            fail(where + "volume %.17g, was %.17g" % (sum(vols), vol0))
        fm = conform.face_map(cm.conn)
        e = conform.shared_errors(fm)
        if e:
            fail(where + e)
        pairs, e = conform.open_faces(cm.x, fm, outer, origin)
        if e:
            fail(where + e)
        ncut = len(pairs)
        if mode == "snap":
            if d["cadd"]:
                fail(where + "snap mode adds %d elements" % len(d["cadd"]))
            for q, par in enumerate(d["parent"]):
                if cm.x[nn_before + q] != cm.x[par]:
                    fail(where + "new node %d is no copy of its parent %d" % (nn_before + q, par))
            for g, (e1, f1, e2, f2) in pairs.items():
                if not is_old(g, f1) and not cut_snap(e1, e2):
                    fail(where + "the face %s between elements %d and %d is open, but the segment between their"
                         " centroids does not cross the surface" % (list(g), e1, e2))
            if "--blade" in o or si == len(steps) - 1:  # a surface is checked whole, at its end
                star_check(cm, pairs, cut_snap, where)
        else:
            for q, par in enumerate(d["parent"]):
                v = nn_before + q
                if cm.x[v] != cm.x[par] and grid.dist(cm.x[v], 1e-9 * h) > 1e-9 * h:
                    fail(where + "inserted node %d at %s is not on the surface" % (v, cm.x[v]))
            for g, (e1, f1, e2, f2) in pairs.items():
                if is_old(g, f1):
                    continue
                P = [cm.x[v] for v in f1]
                lim = tol * h + 1e-9 * h
                for p in P + [[sum(c[k] for c in P) / 3 for k in range(3)]]:
                    dd = grid.dist(p, lim)
                    if dd > lim:
                        fail(where + "cut face %s: point %s is %g from the surface (tolerance %g)" % (f1, p, dd, lim))
        u = cutsys.updt(recs["UPDT"])
        if u[1] != 3 * len(d["parent"]):
            fail(where + "k = %d for %d new nodes" % (u[1], len(d["parent"])))
        err = cutsys.apply_updt(K, f, u)
        if err:
            fail(where + err)
        maxm = max(maxm, u[0])
        err = cutsys.check(cm, K, f, REL, full=si == 0 or si == len(steps) - 1)
        if err:
            fail(where + "the accumulated updates against an independent assembly: " + err)
    print("ok steps=%d nodes=%d elements=%d cut_faces=%d max_m=%d min_vol_ratio=%.3g"
          % (len(steps), len(cm.x), len(cm.conn), ncut, maxm, worst))


def star_check(cm, pairs, cut, where):
    """snap: at every point of a cut face, the elements with a corner there in
    classes joined through coincident faces that the surface does not cross;
    one node per class, distinct classes distinct nodes"""
    x, conn = cm.x, cm.conn
    pts = {x[v] for g in pairs for v in pairs[g][1]}
    at = {}
    for e, c in enumerate(conn):
        for v in c:
            if x[v] in pts:
                at.setdefault(x[v], set()).add(e)
    for P, es in at.items():
        classes = conform.star_classes(x, conn, sorted(es), P,
                                       lambda key, fe, i: len(fe) == 2 and not cut(fe[0], fe[1], key))
        used = {}
        for ce, nodes in classes:
            if len(nodes) != 1:
                fail(where + "at %s the elements %s hang together across faces the surface does not cross but hold"
                     " the nodes %s" % (P, ce[:6], sorted(nodes)))
            v = nodes.pop()
            if v in used:
                fail(where + "node %d at %s is shared by elements %d and %d, which the surface separates"
                     % (v, P, used[v], ce[0]))
            used[v] = ce[0]


main()
