#!/usr/bin/env python3
"""Helpers of bench/thesis.sh (thesis 003 tables 5.1, 5.2, 5.4, figs. 5.16-5.20).
  thesis_tools.py kirigami FILE     a kirigami cut path (cut(1)): 20 slits, 5 rows
        of 4 gently curved cubic Beziers, every other row shifted by half a slit
  thesis_tools.py kv STREAM TYPE TAG KEY [sum|max|min|mean]   the named value of
        the records TYPE with tag TAG over the stream's steps
  thesis_tools.py steps LABEL STATS_CSV   one CSV row per (step, method) of a
        solve-aug run (stats --csv), the columns of STEP_COLS
  thesis_tools.py per_method STEPS_CSV LABEL   one row per method of LABEL's
        steps: n (max), iterations (max), time (max ms), cond (max), error (max),
        pcg's CG and IC(0) factorization times (max ms)
  thesis_tools.py scenario KIND I FILE   cut I (1..) of fig. 5.9's scenarios,
        growing with I: single (one cubic Bezier of length 0.25 + 0.1 I),
        intersecting (two crossing cubics of that length), multiple (four
        cubics of half that length at random places)
  thesis_tools.py bound RUN RUNS   the aspect bound of flower run RUN of RUNS
        (figs. 5.2-5.5): 6 at run 1 down to 2 at run RUNS, linearly
  thesis_tools.py mshq MSH LOG   "triangles min_angle max_aspect bad mesh_ms" of a
        gmsh run: bad = triangles with an angle below 20 degrees or aspect above
        3, mesh_ms = gmsh's own "Done meshing 2D" wall time from its -v 4 LOG
  thesis_tools.py geo_curves PATH H FILE   a gmsh .geo: the unit square with the
        cut path's own curves embedded (bezier lines as gmsh Bezier curves, arcs
        as circles; OpenCASCADE fragments), mesh size H, Frontal-Delaunay: a
        global re-mesh that discretises the cut curve itself at size H
  thesis_tools.py claims FLOWER_CSV SCEN_CSV   the thesis's claims of secs.
        5.2-5.3 next to the measured figures, one CSV row each"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import aug_kv  # noqa: E402

STEP_COLS = ["n", "iters", "converged", "relres", "relres_t", "cond", "cond_k", "spd", "err_chol", "err_scaled",
             "ns_iters", "ic_shift", "time_ms", "iter", "cov", "decomp", "normalise", "recomp", "cg", "diag",
             "ic_factor"]


def kirigami(out):
    lines = []
    for r in range(5):
        y = 0.14 + 0.18 * r
        off = 0.0 if r % 2 == 0 else 0.11
        for c in range(4):
            x0 = 0.06 + off + 0.22 * c
            if x0 + 0.16 > 0.97:
                x0 -= 0.9
                if x0 < 0.03:
                    x0 = 0.03
            x1 = x0 + 0.16
            b = 0.02 * (1 if (r + c) % 2 else -1)
            pts = [x0, y, x0 + 0.053, y + b, x0 + 0.107, y - b, x1, y]
            lines.append("bezier " + " ".join("%.6f" % v for v in pts))
    open(out, "w").write("\n".join(lines) + "\n")


def scenario(kind, i, out):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import random
    import refine_tools
    rnd = random.Random(500 + 17 * i + {"single": 0, "intersecting": 1, "multiple": 2}[kind])
    L = 0.25 + 0.1 * i
    lines = []
    if kind == "single":
        lines.append(refine_tools.cubic_crossing(rnd, 0.5, 0.5, math.pi * rnd.random(), L, 0.3 * L))
    elif kind == "intersecting":
        a = math.pi * rnd.random()
        for k in range(2):
            lines.append(refine_tools.cubic_crossing(rnd, 0.5 + 0.05 * (rnd.random() - 0.5), 0.5 + 0.05 * (rnd.random() - 0.5),
                                                     a + k * (math.pi / 3 + math.pi / 3 * rnd.random()), L, 0.15 * L))
    elif kind == "multiple":
        for k in range(4):
            lines.append(refine_tools.cubic_crossing(rnd, 0.25 + 0.5 * rnd.random(), 0.25 + 0.5 * rnd.random(),
                                                     math.pi * rnd.random(), L / 2, 0.15 * L))
    else:
        raise SystemExit("thesis_tools.py: unknown scenario " + kind)
    open(out, "w").write("\n".join(lines) + "\n")


def mshq(msh, log):
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "py"))
    import msh41
    m = msh41.read(msh)
    x = m["nodes"]
    amin, amax, bad, nt = 180.0, 0.0, 0, 0
    for e in m["elems"]:
        if e[1] != 2:
            continue
        nt += 1
        P = [x[i] for i in e[3]]
        L = [math.dist(P[i][:2], P[(i + 1) % 3][:2]) for i in range(3)]
        asp = max(L) / min(L)
        ang = []
        for i in range(3):
            a, b, c = L[(i + 1) % 3], L[(i + 2) % 3], L[i]
            ang.append(math.degrees(math.acos(max(-1.0, min(1.0, (a * a + b * b - c * c) / (2 * a * b))))))
        amin, amax = min(amin, min(ang)), max(amax, asp)
        bad += min(ang) < 20 or asp > 3
    ms = "nan"
    for line in open(log, errors="replace"):
        if "Done meshing 2D" in line and "Wall" in line:
            ms = "%.3f" % (1e3 * float(line.split("Wall")[1].split("s")[0]))
    print(nt, "%.4f" % amin, "%.4f" % amax, bad, ms)


def geo_curves(path, h, out):
    h = float(h)
    w = ['SetFactory("OpenCASCADE");', "Mesh.Algorithm = 6; // Frontal-Delaunay",
         "Mesh.CharacteristicLengthMin = %g;" % h, "Mesh.CharacteristicLengthMax = %g;" % h,
         "Rectangle(1) = {0, 0, 0, 1, 1};"]
    np_, curves = [0], []

    def pt(x, y):
        np_[0] += 1
        w.append("Point(%d) = {%.17g, %.17g, 0, %g};" % (100 + np_[0], x, y, h))
        return 100 + np_[0]
    for line in open(path):
        f = line.split()
        if not f:
            continue
        v = [float(t) for t in f[1:]]
        c = 100 + len(curves)
        if f[0] == "bezier":
            ids = [pt(v[2 * i], v[2 * i + 1]) for i in range(len(v) // 2)]
            w.append("Bezier(%d) = {%s};" % (c, ", ".join(map(str, ids))))
        elif f[0] == "arc":  # rational quadratic P0 P1 P2 w: the circular arc through P0, its midpoint, P2
            (ax, ay), (bx, by), (cx, cy), wt = v[0:2], v[2:4], v[4:6], v[6]
            mx, my = (ax + cx) / 2, (ay + cy) / 2  # the arc's midpoint: B(1/2) = (P0 + 2 w P1 + P2) / (2 + 2 w)
            qx, qy = (ax + 2 * wt * bx + cx) / (2 + 2 * wt), (ay + 2 * wt * by + cy) / (2 + 2 * wt)
            # centre: on the chord's bisector, equidistant from P0 and the midpoint
            dx, dy = qx - mx, qy - my
            dl = math.hypot(dx, dy)
            half = math.hypot(cx - ax, cy - ay) / 2
            R = (half * half + dl * dl) / (2 * dl)
            ox, oy = qx - dx / dl * R, qy - dy / dl * R
            i0, io, i2 = pt(ax, ay), pt(ox, oy), pt(cx, cy)
            w.append("Circle(%d) = {%d, %d, %d};" % (c, i0, io, i2))
        else:
            raise SystemExit("thesis_tools.py: geo_curves: path line %s not supported" % f[0])
        curves.append(c)
    if curves:
        w.append("BooleanFragments{ Surface{1}; Delete; }{ Curve{100:%d}; Delete; }" % (99 + len(curves)))
    open(out, "w").write("\n".join(w) + "\n")


def claims(flower, scen):
    fr = list(csv.DictReader(open(flower)))
    sr = list(csv.DictReader(open(scen)))
    f = lambda rs, k: [float(r[k]) for r in rs if r.get(k) not in (None, "", "nan")]
    mean = lambda v: sum(v) / len(v) if v else float("nan")
    w = csv.writer(sys.stdout)
    w.writerow(["figure", "claim", "thesis", "measured"])
    fps = f(fr, "fps_pcg")
    w.writerow(["5.2", "lowest FPS with the subdivision (pcg)", "20.66-30.35", "%.2f-%.2f" % (min(fps), max(fps))])
    fa = f(fr, "fps_amps")
    w.writerow(["5.2", "lowest FPS with the subdivision (amps)", "", "%.2f-%.2f" % (min(fa), max(fa))])
    best = max(fr, key=lambda r: float(r["fps_pcg"]))
    w.writerow(["5.2", "run of the highest lowest-FPS (thesis: 15)", "15", "%s (bound %s)" % (best["run"], best["bound"])])
    w.writerow(["5.2", "mean intersected elements per cut", "100", "%.0f" % mean(f(fr, "intersected"))])
    w.writerow(["5.2", "mean new elements per cut (subdivided)", "522", "%.0f" % mean(f(fr, "new_after"))])
    w.writerow(["5.2", "mean new elements per cut (no subdivision)", "", "%.0f" % mean(f(fr, "new_before"))])
    mid = [r for r in fr if 13 <= int(r["run"]) <= 17]
    w.writerow(["5.5", "mean aspect ratio runs 13-17", "about 3", "%.2f" % mean(f(mid, "aspect"))])
    mid = [r for r in fr if 13 <= int(r["run"]) <= 18]
    w.writerow(["5.5", "mean area ratio runs 13-18", "about 0.03", "%.3f" % mean(f(mid, "area"))])
    lo = sum(1 for r in fr if float(r["cond_after"]) < float(r["cond_before"]))
    w.writerow(["5.4", "subdivision lowers cond(K)", "every run", "%d of %d runs" % (lo, len(fr))])
    for kind in ("single", "intersecting", "multiple"):
        rs = [r for r in sr if r["scenario"] == kind]
        w.writerow(["5.8", kind + ": mean aspect after ACDM (thesis criterion)", "< 4", "%.2f" % mean(f(rs, "aspect_thesis"))])
        w.writerow(["5.8", kind + ": aspect after / before", {"intersecting": "0.15", "multiple": "0.36"}.get(kind, ""),
                    "%.2f" % (mean(f(rs, "aspect_thesis")) / mean(f(rs, "aspect0")))])
        w.writerow(["5.8", kind + ": mean area ratio after ACDM", "0.0111-0.0260",
                    "%.3f-%.3f" % (min(f(rs, "area_thesis")), max(f(rs, "area_thesis")))])


def kv(path, typ, tag, key, how="sum"):
    vals = []
    for t, step, p in aug_kv.payloads(path, (typ,)):
        import struct
        name = p[:16].split(b"\0")[0].decode()
        if name != tag:
            continue
        n, = struct.unpack_from("<i", p, 16)
        for i in range(n):
            o = 24 + 24 * i
            if p[o:o + 16].split(b"\0")[0].decode() == key:
                vals.append(struct.unpack_from("<d", p, o + 16)[0])
    if not vals:
        return "nan"
    v = sum(vals) if how == "sum" else max(vals) if how == "max" else min(vals) if how == "min" else sum(vals) / len(vals)
    return "%.6g" % v


def steps(label, path):
    w = csv.writer(sys.stdout)
    for r in csv.DictReader(open(path)):
        if r["step"] in ("0", "") or r["method"] in ("factor", "refine", "cut"):
            continue
        w.writerow([label, r["step"], r["method"]] + [r.get(k, "") for k in STEP_COLS])


def per_method(path, label):
    rows = [r for r in csv.DictReader(open(path)) if r["label"] == label]
    out = csv.writer(sys.stdout)
    for m in sorted(set(r["method"] for r in rows), key=lambda m: [r["method"] for r in rows].index(m)):
        rs = [r for r in rows if r["method"] == m]

        def mx(k):
            v = [float(r[k]) for r in rs if r.get(k) not in (None, "", "nan")]
            return "%.4g" % max(v) if v else ""
        out.writerow([label, m, len(rs), mx("n"), mx("iters"), mx("time_ms"), mx("cond"), mx("cond_k"), mx("err_chol"),
                      mx("relres"), min(int(float(r["converged"] or 0)) for r in rs), mx("iter"), mx("ic_factor")])


def main():
    a = sys.argv[1:]
    if not a:
        raise SystemExit(__doc__)
    if a[0] == "kirigami":
        kirigami(a[1])
    elif a[0] == "kv":
        print(kv(*a[1:]))
    elif a[0] == "steps":
        steps(a[1], a[2])
    elif a[0] == "per_method":
        per_method(a[1], a[2])
    elif a[0] == "scenario":
        scenario(a[1], int(a[2]), a[3])
    elif a[0] == "bound":
        r, n = int(a[1]), int(a[2])
        print("%.4g" % (6 - 4 * (r - 1) / max(1, n - 1)))
    elif a[0] == "mshq":
        mshq(a[1], a[2])
    elif a[0] == "geo_curves":
        geo_curves(a[1], a[2], a[3])
    elif a[0] == "claims":
        claims(a[1], a[2])
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main()
