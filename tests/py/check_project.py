"""A cut path projected onto a membrane sheet (cut(1) --view, formats 5.3,
7.1), checked from the manual and the records only: usage
check_project.py IN OUT ux,uy,uz,vx,vy,vz SNAPTOL x0,y0,x1,y1 [x,y ...] (a
polyline in screen coordinates). The mesh of OUT's last step is replayed from its
MDLT records. Every new node lies on the original sheet: its screen point
(u.x, v.x) falls in an original triangle whose barycentric lift equals the
node to 1e-12 of the extent; it is a copy of its parent or on the path (to
1e-9, or SNAPTOL of the longest screen edge: split mode moves a point that
near an edge onto it; not checked without path points, as after refine); the sheet's area is unchanged (1e-12 relative); pATH points are on the
sheet too; every triangle is valid (area > 0)."""
import math
import struct
import sys

import augstream
import cutsys


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def seg_dist(p, a, b):
    d = (b[0] - a[0], b[1] - a[1])
    t = max(0.0, min(1.0, ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (d[0] ** 2 + d[1] ** 2)))
    return math.hypot(p[0] - a[0] - t * d[0], p[1] - a[1] - t * d[1])


def main():
    src, out, view, snap, path = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), sys.argv[5:]
    v6 = [float(s) for s in view.split(",")]
    u = [c / math.sqrt(dot(v6[:3], v6[:3])) for c in v6[:3]]
    v = [c / math.sqrt(dot(v6[3:], v6[3:])) for c in v6[3:]]
    pts = []
    for s in path:
        q = [float(c) for c in s.split(",")]
        pts += [(q[i], q[i + 1]) for i in range(0, len(q), 2)]
    m0 = augstream.mesh(augstream.records(open(src, "rb").read()))
    recs = augstream.records(open(out, "rb").read())
    cm = cutsys.CutMesh(augstream.mesh(recs))
    X0, T0 = list(m0["x"]), list(m0["conn"])
    if m0["etype"] != 1002 or m0["dim"] != 3:
        fail("%s is not a mem3 mesh" % src)
    ext = max(max(p[k] for p in X0) - min(p[k] for p in X0) for k in range(3))
    scr = [(dot(u, p), dot(v, p)) for p in X0]
    hmax = max(math.dist(scr[t[k]], scr[t[(k + 1) % 3]]) for t in T0 for k in range(3))
    area0 = sum(augstream.corners_measure([X0[i] for i in t]) for t in T0)
    parents, segs = [], []
    for t, fl, s, p in recs:
        if t == "MDLT":
            d = cutsys.mdlt(p, 3, 3)
            parents += list(d["parent"])
            cm.apply_mdlt(d)
        elif t == "pATH":
            dim, _, n = struct.unpack_from("<iiq", p, 0)
            if dim != 3:
                fail("pATH of step %d has dim %d" % (s, dim))
            q = struct.unpack_from("<%dd" % (6 * n), p, 16)
            segs += [q[i * 3:(i + 1) * 3] for i in range(2 * n)]

    def lift(q):
        best, bl, bt = -1e300, None, None
        for t in T0:
            a, b, c = (scr[i] for i in t)
            det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
            l1 = ((q[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (q[1] - a[1])) / det
            l2 = ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1])) / det
            lam = (1 - l1 - l2, l1, l2)
            if min(lam) > best:
                best, bl, bt = min(lam), lam, t
        return best, [sum(bl[k] * X0[bt[k]][r] for k in range(3)) for r in range(3)]

    nn0 = len(X0)
    worst = 0.0
    for j, x in enumerate(cm.x[nn0:]):
        q = (dot(u, x), dot(v, x))
        inside, y = lift(q)
        err = max(abs(a - b) for a, b in zip(x, y))
        worst = max(worst, err)
        if inside < -1e-9 or err > 1e-12 * ext:
            fail("new node %d at %s is not on the sheet (lift %s, inside %.3g)" % (nn0 + j, x, y, inside))
        par = cm.x[parents[j]]
        if len(pts) < 2:
            continue  # no path given (a refined stream): the sheet alone
        on_path = min(seg_dist(q, pts[i], pts[i + 1]) for i in range(len(pts) - 1))
        if max(abs(a - b) for a, b in zip(x, par)) > 0 and on_path > 1e-9 + snap * hmax:
            fail("new node %d is neither a copy of node %d nor on the path (%.3g off)" % (nn0 + j, parents[j], on_path))
    for x in segs:
        inside, y = lift((dot(u, x), dot(v, x)))
        if inside < -1e-9 or max(abs(a - b) for a, b in zip(x, y)) > 1e-12 * ext:
            fail("pATH point %s is not on the sheet" % (x,))
    areas = [augstream.corners_measure([cm.x[i] for i in t]) for t in cm.conn]
    if min(areas) <= 0:
        fail("a triangle of area %g" % min(areas))
    if abs(sum(areas) - area0) > 1e-12 * area0:
        fail("area %.17g, before the cut %.17g" % (sum(areas), area0))
    print("ok %s: %d new nodes on the sheet (max %.3g), %d pATH points, area %.15g" %
          (out, len(cm.x) - nn0, worst, len(segs), area0))


if __name__ == "__main__":
    main()
