"""check_refine.py IN OUT [--max-aspect A] [--min-angle DEG]
Checks refine's output OUT against its input IN, both read independently of the
C library (augstream.py, cutsys.py, conform.py): every record that is not
per-step is passed through unchanged and in order; per step, MDLT/BDLT/UPDT
(and a dynamic stream's UPKM) are rewritten, everything else is kept in order, and one qUAl and one tIMe with tag
"refine" follow. At every step, the folded MDLTs and BDLTs applied to the mesh
give a conformal mesh (each edge or face in at most two elements, with opposite
orientations: tets too), every element positive, the total area (volume)
unchanged, and every open edge or face on the outer boundary of the original
mesh, or one side of a cut, or inside an open face of the cut's own mesh of
that step (IN's MDLTs replayed): no hanging node; UPDT k = dim * new nodes, and
K_t and f_t accumulated from K_0 (KMAT, checked against an assembly, or
assembled) and the UPDTs equal the system assembled from scratch on the refined
mesh to 1e-12 * max|K| (not in a dynamic stream, whose UPDTs update A:
tests/py/check_dyn.py). In 2-D at the end: every open edge lies on the outer
boundary or on a pATH segment, every pATH segment is a union of mesh edges on
both sides (one side along the outer boundary; an edge on the segment's
line covers the part of it the edge overlaps), and no triangle exceeds the aspect bound (with --min-angle: has
an angle below DEG) except in a corner between two open edges too sharp for
any triangle. Prints a summary; exit 1 on the first failure."""
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import conform  # noqa: E402
import cutsys  # noqa: E402


def fail(msg):
    print("check_refine: %s: %s" % (sys.argv[2], msg))
    sys.exit(1)


def mdlt(p, dim, nv):
    pos = 0
    nnew, = struct.unpack_from("<q", p, pos)
    pos += 8
    parent, pos = augstream.arr("i", p, pos, nnew)
    x, pos = augstream.arr("d", p, pos, nnew * dim)
    nmod, = struct.unpack_from("<q", p, pos)
    pos += 8
    elem, pos = augstream.arr("i", p, pos, nmod)
    conn, pos = augstream.arr("i", p, pos, nmod * nv)
    nadd, = struct.unpack_from("<q", p, pos)
    pos += 8
    cadd, pos = augstream.arr("i", p, pos, nadd * nv)
    madd, pos = augstream.arr("i", p, pos, nadd)
    pos += 8
    if pos != len(p):
        fail("MDLT payload size")
    return parent, x, elem, conn, cadd, madd


def main():
    a = sys.argv[1:]
    bound = 3.0
    if "--max-aspect" in a:
        bound = float(a[a.index("--max-aspect") + 1])
    min_angle = float(a[a.index("--min-angle") + 1]) if "--min-angle" in a else 0.0
    rin = augstream.records(open(a[0], "rb").read())
    rout = augstream.records(open(a[1], "rb").read())
    # 1. records that are not per-step: the same, in order (refine adds one pROv)
    nin = [r for r in rin if r[2] < 0 and r[0] not in ("TAIL", "HEAD")]
    nout = [r for r in rout if r[2] < 0 and r[0] not in ("TAIL", "HEAD")]
    provs = [i for i, r in enumerate(nout) if r[0] == "pROv" and r[3].split(b"\n")[1].split(b" ")[0].endswith(b"refine")]
    if len(provs) != 1:
        fail("expected one pROv of refine, found %d" % len(provs))
    del nout[provs[0]]
    if nin != nout:
        fail("records that are not per-step differ")
    # 2. per step: the same records in order, MDLT/BDLT/UPDT rewritten, + qUAl, tIMe
    steps = sorted({r[2] for r in rin if r[2] >= 0})
    qual = {}
    for s in steps:
        si = [r for r in rin if r[2] == s]
        so = [r for r in rout if r[2] == s]
        has_md = any(r[0] == "MDLT" for r in si)
        extra = [r for r in so if r[0] in ("qUAl", "tIMe") and augstream.kv(r[3])[0] == "refine"]
        if has_md and len(extra) != 2:
            fail("step %d: %d qUAl/tIMe records of refine" % (s, len(extra)))
        so = [r for r in so if r not in extra]
        kept = [r for r in si if not (has_md and r[0] in ("fELD", "rEAC"))]  # of the unrefined mesh
        ti = [r[0] for r in kept]
        if ti != [r[0] for r in so]:
            fail("step %d: record order %s -> %s" % (s, ti, [r[0] for r in so]))
        for r, q in zip(kept, so):
            # (UPKM: a dynamic stream's K and M update, rewritten for the
            # refined mesh like UPDT; tests/py/check_dyn.py checks its values)
            if r[0] not in ("MDLT", "BDLT", "UPDT", "UPKM") and r != q:
                fail("step %d: %s changed" % (s, r[0]))
        for r in extra:
            if r[0] == "qUAl":
                qual[s] = augstream.kv(r[3])[1]
    # 3. the refined mesh of every step, against the cut's own mesh of that step
    m = augstream.mesh(rout)
    dim, nv = m["dim"], m["nv"]
    fine, coarse = cutsys.CutMesh(m), cutsys.CutMesh(augstream.mesh(rin))
    x, conn = fine.x, fine.conn
    area0 = sum(augstream.measure({"x": x, "conn": conn, "nv": nv}, e) for e in range(len(conn)))
    lo = [min(p[k] for p in x) for k in range(dim)]
    hi = [max(p[k] for p in x) for k in range(dim)]
    tol = 1e-10 * max(hi[k] - lo[k] for k in range(dim))
    outer = conform.boundary_index(x, conn, tol)
    origin, inserted = list(range(len(x))), {}
    Kacc, facc = fine.assemble()
    K0 = [k[2] for k in (cutsys.kmat(p) for typ, fl, s, p in rout if typ == "KMAT") if k[0] == 0]
    dynamic = any(typ == "DYNP" for typ, fl, s, p in rout)
    f0 = [cutsys.fvec(p)[1] for typ, fl, s, p in rout if typ == "FVEC"]
    if K0:
        Kacc, facc = K0[0], f0[0]
        err = cutsys.check(fine, Kacc, facc, 1e-12)
        if err:
            fail("K_0 (KMAT) against an independent assembly: " + err)
    segs = []
    fm = conform.face_map(conn)
    vols = [augstream.measure({"x": x, "conn": conn, "nv": nv}, e) for e in range(len(conn))]
    for s in steps:
        rec = {typ: p for typ, fl, st, p in rout if st == s}
        crec = {typ: p for typ, fl, st, p in rin if st == s}
        if "pATH" in rec:
            d, _, n = struct.unpack_from("<iiq", rec["pATH"], 0)
            v, _ = augstream.arr("d", rec["pATH"], 16, n * 2 * d)
            if d == 2:
                segs += [tuple(v[4 * i:4 * i + 4]) for i in range(n)]
        if "MDLT" not in rec:
            continue
        try:
            cd = cutsys.mdlt(crec["MDLT"], dim, nv)
            coarse.apply_mdlt(cd)
            if "BDLT" in crec:
                coarse.apply_bdlt(cutsys.bdlt(crec["BDLT"]))
            d = cutsys.mdlt(rec["MDLT"], dim, nv)
            nn = len(x)
            fine.apply_mdlt(d)
            if "BDLT" in rec:
                fine.apply_bdlt(cutsys.bdlt(rec["BDLT"]))
        except (cutsys.Bad, struct.error) as e:
            fail("step %d: %s" % (s, e))
        for q, par in enumerate(d["parent"]):
            origin.append(origin[par] if x[nn + q] == x[par] else inserted.setdefault(x[nn + q], nn + q))
        # conformal, every element positive, open faces on the boundary or on the cut's own open faces
        mesh = {"x": x, "conn": conn, "nv": nv}
        vols = [augstream.measure(mesh, e) for e in range(len(conn))]
        if min(vols) <= 0:
            fail("step %d: element %d has measure %g" % (s, vols.index(min(vols)), min(vols)))
        if abs(sum(vols) - area0) > 1e-10 * area0:
            fail("step %d: total measure %.17g, was %.17g" % (s, sum(vols), area0))
        fm = conform.face_map(conn)
        err = conform.shared_errors(fm)
        if err:
            fail("step %d: %s" % (s, err))
        cfm = conform.face_map(coarse.conn)
        crack = conform.FaceIndex([[coarse.x[v] for v in u[0][1]] for u in cfm.values()
                                   if len(u) == 1 and outer.find([coarse.x[v] for v in u[0][1]]) < 0], tol)
        _, err = conform.open_faces(x, fm, outer, origin, lambda pts: crack.find(pts) >= 0)
        if err:
            fail("step %d: %s" % (s, err))
        try:
            u = cutsys.updt(rec["UPDT"])
        except (cutsys.Bad, struct.error, KeyError) as e:
            fail("step %d: UPDT: %s" % (s, e))
        if u[1] != dim * len(d["parent"]):
            fail("step %d: UPDT k = %d for %d new nodes" % (s, u[1], len(d["parent"])))
        err = cutsys.apply_updt(Kacc, facc, u)
        if err:
            fail("step %d: UPDT: %s" % (s, err))
        # a dynamic stream's UPDT updates A = cM M + cK K, not K: its values
        # are tests/py/check_dyn.py's (the geometry above is checked here)
        err = None if dynamic else cutsys.check(fine, Kacc, facc, 1e-12, full=s == steps[-1])
        if err:
            fail("step %d: K_t and f_t of the updates against an assembly on the refined mesh: %s" % (s, err))
    faces = fm
    if nv == 4:
        print("check_refine: %d steps, %d nodes, %d tets, volume %.15g, conformal, K_t of the updates" % (len(steps), len(x), len(conn), sum(vols)))
        return
    # 2-D: open edges on the outer boundary or on a cut segment
    def on_seg(p, sg, tol=1e-9, line=False):
        ux, uy, vx, vy = sg
        L = math.hypot(vx - ux, vy - uy)
        d = abs((vx - ux) * (p[1] - uy) - (vy - uy) * (p[0] - ux)) / L
        t = ((p[0] - ux) * (vx - ux) + (p[1] - uy) * (vy - uy)) / (L * L)
        return d <= tol * max(1.0, L) and (line or -tol <= t <= 1 + tol), t
    cell = 0.02
    grid = {}
    for i, sg in enumerate(segs):
        for gx in range(int(min(sg[0], sg[2]) / cell) - 1, int(max(sg[0], sg[2]) / cell) + 2):
            for gy in range(int(min(sg[1], sg[3]) / cell) - 1, int(max(sg[1], sg[3]) / cell) + 2):
                grid.setdefault((gx, gy), []).append(i)
    on_edges = {}
    for key, uses in faces.items():
        pa, pb = x[key[0]], x[key[1]]
        cand = set(grid.get((int(pa[0] / cell), int(pa[1] / cell)), []))
        for i in cand:
            # an edge on the segment's line covers the part of the segment
            # it overlaps (an edge of an earlier step's lip may run past a
            # segment that starts inside it)
            oa, ta = on_seg(pa, segs[i], 1e-9, True)
            ob, tb = on_seg(pb, segs[i], 1e-9, True)
            if oa and ob and max(ta, tb) > 0 and min(ta, tb) < 1:
                ta, tb = min(max(ta, 0.0), 1.0), min(max(tb, 0.0), 1.0)
                for e, f in uses:
                    third = [v for v in conn[e] if v not in key][0]
                    sg = segs[i]
                    side = (sg[2] - sg[0]) * (x[third][1] - sg[1]) - (sg[3] - sg[1]) * (x[third][0] - sg[0]) > 0
                    on_edges.setdefault((i, side), []).append((min(ta, tb), max(ta, tb)))
        if len(uses) == 1:
            outer = any(pa[k] == pb[k] and pa[k] in (lo[k], hi[k]) for k in range(2))
            if not outer and not any(on_seg(pa, segs[i])[0] and on_seg(pb, segs[i])[0] for i in cand):
                fail("open edge %s (%s - %s) neither on the boundary nor on the cut" % (key, pa, pb))
    for i in range(len(segs)):
        sg = segs[i]
        # a segment along the outer boundary has the mesh on one side only
        outer = any(sg[k] == sg[k + 2] and sg[k] in (lo[k], hi[k]) for k in range(2))
        covered = []
        for side in (False, True):
            reach = 0.0
            for t0, t1 in sorted(on_edges.get((i, side), [])):
                if t0 <= reach + 1e-9:
                    reach = max(reach, t1)
            covered.append(reach >= 1 - 1e-9)
            if reach < 1 - 1e-9 and not outer:
                fail("pATH segment %d %s is not covered by edges on one side (to %.3g)" % (i, segs[i], reach))
        if outer and not any(covered):
            fail("pATH segment %d %s on the boundary is not covered by edges" % (i, segs[i]))
    # aspect bound (and min angle), except corners between two open edges
    # sharper than 2 asin(1/2A) (or than the min angle)
    thmin = max(2 * math.asin(1 / (2 * bound)), math.radians(min_angle))
    worst, sharp, amin = 0.0, 0, 180.0
    for e, c in enumerate(conn):
        P = [x[v] for v in c]
        L = [math.dist(P[i], P[(i + 1) % 3]) for i in range(3)]
        asp = max(L) / min(L)
        angs = []
        for i in range(3):
            u = [P[(i + 1) % 3][k] - P[i][k] for k in range(2)]
            w = [P[(i + 2) % 3][k] - P[i][k] for k in range(2)]
            angs.append(math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u[0] * w[0] + u[1] * w[1]))
        small = math.degrees(min(angs)) < min_angle * (1 - 1e-9)
        if asp <= bound * (1 + 1e-9) and not small:
            worst = max(worst, asp)
            amin = min(amin, math.degrees(min(angs)))
            continue
        corner = False
        for i in range(3):
            e1 = len(faces[tuple(sorted((c[i], c[(i + 1) % 3])))]) == 1
            e2 = len(faces[tuple(sorted((c[i], c[(i + 2) % 3])))]) == 1
            corner = corner or (angs[i] < thmin and e1 and e2)
        if not corner:
            fail("triangle %d has aspect %.4g > %g or an angle %.4g < %g" % (e, asp, bound, math.degrees(min(angs)), min_angle))
        sharp += 1
    for s, q in qual.items():
        if q.get("aspect_max", 0) > bound * (1 + 1e-9) and not sharp:
            fail("step %d: qUAl aspect_max %g" % (s, q["aspect_max"]))
    print("check_refine: %d steps, %d nodes, %d triangles, area %.15g, %d cut segments, max aspect %.4f, "
          "min angle %.4f, %d triangles in sharp corners" % (len(steps), len(x), len(conn), sum(vols), len(segs),
                                                            worst, amin, sharp))


main()
