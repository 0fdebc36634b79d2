#!/usr/bin/env python3
"""Free fall in a dynamic stream (formats/stream.md 7.9): after the last step,
the mesh replayed (tests/py/cutsys.py) is split into its element-connected
pieces; for every piece without a constrained DOF its centre of mass (nodal
masses rho V / (dim + 1) summed from its elements) is taken per whole-mesh
frame of the last step, and its second differences must equal h^2 g
(both integrators move the centre of mass of a free piece under a uniform
body force exactly so) to --rel relative. Prints 'ok pieces=N frames=N
max_rel=...' or the first failure (exit 1).

usage: dyn_fall.py [--rel R] GX,GY[,GZ] STREAM"""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402


def main():
    args = sys.argv[1:]
    rel = cutsys.rel_option(args, 1e-9)
    if len(args) != 2:
        raise SystemExit(__doc__)
    g = [float(x) for x in args[0].split(",")]
    recs = augstream.records(open(args[1], "rb").read())
    cm = cutsys.CutMesh(augstream.mesh(recs))
    dyn = [p for t, fl, s, p in recs if t == "DYNP"][0]
    h = struct.unpack_from("<d", dyn, 8)[0]
    last = max(s for t, fl, s, p in recs if t == "fRAM")
    for t, fl, s, p in recs:
        if t == "MDLT":
            cm.apply_mdlt(cutsys.mdlt(p, cm.dim, cm.nv))
        elif t == "BDLT":
            cm.apply_bdlt(cutsys.bdlt(p))
    dim, nn = cm.dim, len(cm.x)
    par = list(range(nn))

    def find(a):
        while par[a] != a:
            par[a] = par[par[a]]
            a = par[a]
        return a
    mass = [0.0] * nn
    for e, conn in enumerate(cm.conn):
        P = [cm.x[v] for v in conn]
        mat = cm.mats[cm.mat[e]]
        vol = abs(augstream.corners_measure(P)) * (mat[5] if dim == 2 else 1.0)
        for v in conn:
            mass[v] += mat[4] * vol / len(conn)
            par[find(v)] = find(conn[0])
    pieces = {}
    for v in range(nn):
        if mass[v] > 0:
            pieces.setdefault(find(v), []).append(v)
    free = [ns for ns in pieces.values() if not any(v * dim + c in cm.fix for v in ns for c in range(dim))]
    if not free:
        print("FAIL: no free piece")
        sys.exit(1)
    coms = []
    for t, fl, s, p in recs:
        if t != "fRAM" or s != last:
            continue
        fr, fdim, count, time, indexed = struct.unpack_from("<iiqdi", p, 0)
        if indexed or count != nn:
            continue
        u, _ = augstream.arr("d", p, 32, count * dim)
        coms.append([[sum(mass[v] * u[v * dim + c] for v in ns) / sum(mass[v] for v in ns) for c in range(dim)]
                     for ns in free])
    worst, gn = 0.0, max(abs(x) for x in g) * h * h
    for k in range(2, len(coms)):
        for q in range(len(free)):
            for c in range(dim):
                d2 = coms[k][q][c] - 2 * coms[k - 1][q][c] + coms[k - 2][q][c]
                err = abs(d2 - g[c] * h * h) / gn
                worst = max(worst, err)
                if not err <= rel:
                    print("FAIL: piece %d, component %d: second difference %.17g, h^2 g = %.17g" % (q, c, d2, g[c] * h * h))
                    sys.exit(1)
    if len(coms) < 3:
        print("FAIL: fewer than 3 frames of the last step")
        sys.exit(1)
    print("ok pieces=%d frames=%d max_rel=%.3g" % (len(free), len(coms), worst))


main()
