#!/usr/bin/env python3
"""Independent check of meshload --gravity (formats/stream.md 5.2, 5.8), from
`stats --dump` texts of meshload | factor only.

usage: gravity_check.py DUMP_G DUMP_0 gx,gy[,gz]

DUMP_G is the dump of a stream made with --gravity g, DUMP_0 of the same
command without it. From DUMP_G's NODE, MATL and ELEM the volume of every
element is computed here (tet4: det[p1-p0, p2-p0, p3-p0] / 6; tri3: the
cross product / 2), and its body force rho g |e| t (t: the material's
thickness in 2-D, 1 in 3-D) shared equally by its nodes. Checks: DUMP_G has
GRAV = g and the same LOAD as DUMP_0 (gravity is a body force, assembled per
element, not a nodal load); to 1e-12 relative to the largest entry: the load
vector FVEC of DUMP_G = FVEC of DUMP_0 + those shares at every free DOF
(DOFM); the sum of each component of the shares = g_c sum over materials of
rho t V. Prints one line per material "mat NAME rho R t T
volume V" (V: the total measure of its elements), then
"total c SUM" per component; exit 1 on a failure."""
import sys


def parse(path):
    """{type: [record]}: each record maps the key of a two-space line to its
    text, and an array "name[...]" to the numbers of its continuation lines
    ("    i: v v ...")"""
    recs, cur, arr = {}, None, None
    for line in open(path):
        line = line.rstrip("\n")
        if line.startswith("#"):
            cur, arr = {}, None
            recs.setdefault(line.split()[1], []).append(cur)
        elif line.startswith("    "):
            toks = line.split()
            if arr is not None and toks and toks[0].endswith(":"):
                cur[arr] += [float(v) for v in toks[1:]]
        elif line.startswith("  "):
            toks = line.split(None, 1)
            arr = toks[0].split("[")[0] if "[" in toks[0] else None
            if arr is not None:
                cur[arr] = []
            else:
                cur[toks[0]] = toks[1] if len(toks) > 1 else ""
    return recs


def mats_of(path):
    """the MATL blocks: [(name, rho, t)] in order"""
    out, inside = [], False
    for line in open(path):
        s = line.strip()
        if line.startswith("#"):
            inside = " MATL " in line
            continue
        if not inside:
            continue
        toks = s.split(None, 1)
        if toks[0] == "material":
            out.append({})
        elif out and len(toks) == 2:
            out[-1][toks[0]] = toks[1]
    return [(m["name"].strip('"'), float(m["rho"]), float(m["t"])) for m in out]


def measure(x, dim, c):
    p = [x[v * dim:(v + 1) * dim] for v in c]
    if dim == 2:
        return 0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
    a = [p[1][k] - p[0][k] for k in range(3)]
    b = [p[2][k] - p[0][k] for k in range(3)]
    d = [p[3][k] - p[0][k] for k in range(3)]
    return (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
            + a[2] * (b[0] * d[1] - b[1] * d[0])) / 6.0


def loads(recs):
    """FVEC by DOF (free DOFs of DOFM)"""
    mp, f = recs["DOFM"][0]["map"], recs["FVEC"][0]["v"]
    return {d: f[int(q)] for d, q in enumerate(mp) if q >= 0}


def main():
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    rg, r0 = parse(sys.argv[1]), parse(sys.argv[2])
    g = [float(v) for v in sys.argv[3].split(",")]
    node, elem = rg["NODE"][0], rg["ELEM"][0]
    dim, x = int(node["dim"]), node["x"]
    nv = int(elem["nv"])
    conn = [int(v) for v in elem["conn"]]
    mat = [int(v) for v in elem["mat"]]
    mats = mats_of(sys.argv[1])
    g = (g + [0.0])[:dim] if len(g) < dim else g[:dim]
    share = {}
    vol = [0.0] * len(mats)
    for e in range(len(mat)):
        c = conn[e * nv:(e + 1) * nv]
        name, rho, t = mats[mat[e]]
        V = measure(x, dim, c)
        vol[mat[e]] += V
        w = rho * V * (t if dim == 2 else 1.0) / nv
        for v in c:
            for k in range(dim):
                share[v * dim + k] = share.get(v * dim + k, 0.0) + w * g[k]
    lg, l0 = loads(rg), loads(r0)
    scale = max([abs(v) for v in lg.values()] + [1e-300])
    bad = 0
    gr = [float(v) for v in rg["GRAV"][0]["g"].split()] if "GRAV" in rg else None
    if gr is None or gr[:dim] != g or "GRAV" in r0:
        print("FAIL: GRAV %s, want %s (and none without --gravity)" % (gr, g))
        bad = 1
    if rg.get("LOAD", [{}])[0].get("value") != r0.get("LOAD", [{}])[0].get("value"):
        print("FAIL: --gravity changed LOAD")
        bad = 1
    for dof in sorted(set(lg) | set(l0)):
        want = l0.get(dof, 0.0) + share.get(dof, 0.0)
        got = lg.get(dof, 0.0)
        if abs(got - want) > 1e-12 * scale:
            print("FAIL dof %d: FVEC %.17g, want %.17g (without gravity %.17g + gravity %.17g)"
                  % (dof, got, want, l0.get(dof, 0.0), share.get(dof, 0.0)))
            bad = 1
            break
    for (name, rho, t), V in zip(mats, vol):
        print("mat %s rho %.17g t %.17g volume %.15f" % (name, rho, t, V))
    for k in range(dim):
        s = sum(share.get(d, 0.0) for d in range(k, len(x), dim))
        want = g[k] * sum(rho * (t if dim == 2 else 1.0) * V for (n, rho, t), V in zip(mats, vol))
        print("total %d %.15g" % (k, s))
        if abs(s - want) > 1e-12 * max(abs(want), scale):
            print("FAIL component %d: the gravity shares sum to %.17g, want %.17g" % (k, s, want))
            bad = 1
    sys.exit(bad)


main()
