#!/usr/bin/env python3
"""Helpers of bench/refine.sh (thesis 003, sec. 5.1-5.3).
  refine_tools.py path PATTERN SEED FILE   a cut path file (cut(1)) of a random
        pattern: single (one cubic Bezier), intersecting (two crossing cubics),
        flower (a punch of k rational quadratic arcs), many (six cubics)
  refine_tools.py flat IN OUT      the mesh at the end of IN's steps (MDLT and BDLT
        applied, constraints inherited from parents) as a stream of mesh records,
        for factor: cond(K) and solve time of the cut or refined mesh
  refine_tools.py geo IN H FILE    a gmsh .geo: the unit square with IN's pATH
        segments embedded (OpenCASCADE fragments), mesh size H, Delaunay
  refine_tools.py mshq MSH         "triangles min_angle max_aspect mean_aspect" of
        the triangles of an ASCII MSH 4.1 file (tests/py/msh41.py)"""
import math
import os
import random
import struct
import sys
import zlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "py"))
import augstream  # noqa: E402

SIG = b"\x89AUG\r\n\x1a\n"


def cubic_crossing(rnd, cx, cy, ang, L, wob):
    pts = []
    for i in range(4):
        t = (i / 3.0 - 0.5) * L
        pts += [cx + t * math.cos(ang) + wob * (rnd.random() - 0.5), cy + t * math.sin(ang) + wob * (rnd.random() - 0.5)]
    return "bezier " + " ".join("%.6f" % v for v in pts)


def path(pattern, seed, out):
    rnd = random.Random(seed)
    lines = []
    if pattern == "single":
        lines.append(cubic_crossing(rnd, 0.5 + 0.1 * (rnd.random() - 0.5), 0.5 + 0.1 * (rnd.random() - 0.5),
                                    math.pi * rnd.random(), 0.6, 0.3))
    elif pattern == "intersecting":
        a = math.pi * rnd.random()
        for k in range(2):
            lines.append(cubic_crossing(rnd, 0.5 + 0.1 * (rnd.random() - 0.5), 0.5 + 0.1 * (rnd.random() - 0.5),
                                        a + k * (math.pi / 3 + math.pi / 3 * rnd.random()), 0.6, 0.15))
    elif pattern == "flower":
        c = (0.5 + 0.04 * (rnd.random() - 0.5), 0.5 + 0.04 * (rnd.random() - 0.5))
        k = rnd.choice((4, 5, 6))
        r0 = 0.16 + 0.05 * rnd.random()
        r1 = r0 * (1.35 + 0.2 * rnd.random())
        ph = 2 * math.pi * rnd.random()
        for i in range(k):
            a0, a1 = ph + 2 * math.pi * i / k, ph + 2 * math.pi * (i + 1) / k
            am = (a0 + a1) / 2
            p = [(c[0] + r * math.cos(a), c[1] + r * math.sin(a)) for r, a in ((r0, a0), (r1, am), (r0, a1))]
            lines.append("arc %.17g %.17g %.17g %.17g %.17g %.17g %.17g" % (p[0] + p[1] + p[2] + (math.cos(math.pi / k),)))
    elif pattern == "many":
        for k in range(6):
            lines.append(cubic_crossing(rnd, 0.2 + 0.6 * rnd.random(), 0.2 + 0.6 * rnd.random(),
                                        math.pi * rnd.random(), 0.25 + 0.2 * rnd.random(), 0.08))
    else:
        sys.exit("refine_tools.py: unknown pattern " + pattern)
    open(out, "w").write("\n".join(lines) + "\n")


def rec(t, p):
    body = struct.pack("<IiQ", 0, -1, len(p)) + p
    return struct.pack("<Q", len(body)) + t.encode() + body + struct.pack("<I", zlib.crc32(t.encode() + body) & 0xffffffff)


def flat(src, dst):
    recs = augstream.records(open(src, "rb").read())
    m = augstream.mesh(recs)
    dim, nv = m["dim"], m["nv"]
    x = [list(p) for p in m["x"]]
    conn, mat = [list(c) for c in m["conn"]], list(m["mat"])
    fix, load = dict(m.get("fix", {})), dict(m.get("load", {}))
    matl = [r[3] for r in recs if r[0] == "MATL"][0]
    for typ, fl, step, p in recs:
        if typ == "MDLT":
            pos = 0
            nnew, = struct.unpack_from("<q", p, pos)
            pos += 8
            par, pos = augstream.arr("i", p, pos, nnew)
            xn, pos = augstream.arr("d", p, pos, nnew * dim)
            nmod, = struct.unpack_from("<q", p, pos)
            pos += 8
            el, pos = augstream.arr("i", p, pos, nmod)
            cn, pos = augstream.arr("i", p, pos, nmod * nv)
            nadd, = struct.unpack_from("<q", p, pos)
            pos += 8
            ca, pos = augstream.arr("i", p, pos, nadd * nv)
            ma, pos = augstream.arr("i", p, pos, nadd)
            nn = len(x)
            for i in range(nnew):
                x.append(xn[i * dim:(i + 1) * dim])
                for c in range(dim):
                    if par[i] * dim + c in fix:
                        fix[(nn + i) * dim + c] = fix[par[i] * dim + c]
            for k, e in enumerate(el):
                conn[e] = cn[k * nv:(k + 1) * nv]
            for k in range(nadd):
                conn.append(ca[k * nv:(k + 1) * nv])
                mat.append(ma[k])
        elif typ == "BDLT":
            nf, = struct.unpack_from("<q", p, 0)
            dof, pos = augstream.arr("i", p, 8, nf)
            val, pos = augstream.arr("d", p, pos, nf)
            nl, = struct.unpack_from("<q", p, pos)
            ldof, pos = augstream.arr("i", p, pos + 8, nl)
            lval, pos = augstream.arr("d", p, pos, nl)
            fix.update(zip(dof, val))
            load.update(zip(ldof, lval))
    out = bytearray(SIG)
    out += rec("HEAD", struct.pack("<II", 1, 0) + b"refine_tools")
    out += rec("NODE", struct.pack("<iiq", dim, 0, len(x)) + struct.pack("<%dd" % (len(x) * dim), *[v for p in x for v in p]))
    out += rec("MATL", matl)
    ne = len(conn)
    out += rec("ELEM", struct.pack("<iiq", m["etype"], nv, ne) + struct.pack("<%di" % (ne * nv), *[v for c in conn for v in c]) +
               struct.pack("<%di" % ne, *mat))
    for t, d in (("FIXD", fix), ("LOAD", load)):
        k = sorted(d)
        out += rec(t, struct.pack("<q", len(k)) + struct.pack("<%di" % len(k), *k) + struct.pack("<%dd" % len(k), *[d[i] for i in k]))
    out += rec("TAIL", struct.pack("<Q", 6))
    open(dst, "wb").write(out)


def geo(src, h, dst):
    recs = augstream.records(open(src, "rb").read())
    segs = []
    for typ, fl, step, p in recs:
        if typ == "pATH":
            d, _, n = struct.unpack_from("<iiq", p, 0)
            v, _ = augstream.arr("d", p, 16, n * 2 * d)
            segs += [tuple(v[4 * i:4 * i + 4]) for i in range(n)]
    pts, lines = {}, []
    def pt(x, y):
        k = (round(x, 12), round(y, 12))
        if k not in pts:
            pts[k] = len(pts) + 1
        return pts[k]
    for s in segs:
        a, b = pt(s[0], s[1]), pt(s[2], s[3])
        if a != b:
            lines.append((a, b))
    lines = sorted(set(tuple(sorted(l)) for l in lines))
    w = ['SetFactory("OpenCASCADE");', "Mesh.Algorithm = 5; // Delaunay",
         "Mesh.CharacteristicLengthMin = %g;" % float(h), "Mesh.CharacteristicLengthMax = %g;" % float(h),
         "Rectangle(1) = {0, 0, 0, 1, 1};"]
    for (x, y), i in pts.items():
        w.append("Point(%d) = {%.17g, %.17g, 0, %g};" % (100 + i, x, y, float(h)))
    for k, (a, b) in enumerate(lines):
        w.append("Line(%d) = {%d, %d};" % (100 + k, 100 + a, 100 + b))
    if lines:
        w.append("BooleanFragments{ Surface{1}; Delete; }{ Curve{100:%d}; Delete; }" % (99 + len(lines)))
    open(dst, "w").write("\n".join(w) + "\n")


def mshq(path):
    import msh41
    m = msh41.read(path)
    x = m["nodes"]
    tris = [e[3] for e in m["elems"] if e[1] == 2]
    amin, amax, asum = 180.0, 0.0, 0.0
    for t in tris:
        P = [x[i] for i in t]
        L = [math.dist(P[i][:2], P[(i + 1) % 3][:2]) for i in range(3)]
        asp = max(L) / min(L)
        amax = max(amax, asp)
        asum += asp
        for i in range(3):
            a, b, c = L[(i + 1) % 3], L[(i + 2) % 3], L[i]
            cs = max(-1.0, min(1.0, (a * a + b * b - c * c) / (2 * a * b)))
            amin = min(amin, math.degrees(math.acos(cs)))
    print(len(tris), "%.4f" % amin, "%.4f" % amax, "%.4f" % (asum / max(1, len(tris))))


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "path":
        path(sys.argv[2], int(sys.argv[3]), sys.argv[4])
    elif cmd == "flat":
        flat(sys.argv[2], sys.argv[3])
    elif cmd == "geo":
        geo(sys.argv[2], sys.argv[3], sys.argv[4])
    elif cmd == "mshq":
        mshq(sys.argv[2])
    else:
        sys.exit(__doc__)
