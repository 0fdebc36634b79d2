#!/usr/bin/env python3
"""Independent check of the time frames of a dynamic stream (formats/stream.md
6.6 DYNP, 7.9 fRAM), from the specification only: the mesh of every step is
replayed (tests/py/cutsys.py), K and M are assembled here over every DOF of it
(no constraint elimination; M consistent or row-sum lumped as DYNP says), and
each pair of consecutive whole-mesh frames (u0, v0) -> (u1, v1) must satisfy
the integrator on the DOFs that are free at the later frame's step,

    A (u1 - u0) = h M v0 + g h^2 (f - K u0),   A = M + a h D + b h^2 K,
    D = alpha M + beta K,  (a, b, g) = (1, 1, 1) Euler, (1/2, 1/4, 1/2) Newmark,

to --rel relative (2-norm over those DOFs, against the norm of the right-hand
side), and the velocity v1 = (u1 - u0)/h (Euler), 2 (u1 - u0)/h - v0 (Newmark)
on every DOF; new nodes of a step start from the state of their parent.
Every rEAC of a checked frame (formats/stream.md 7.10) must hold, at each
constrained DOF, r = M a + D v1 + K u1 - f with a = (v1 - v0)/h, to --rel
relative to the largest |r|.
With --energy FILE: per frame 'frame time kinetic potential work' (1/2 v'Mv,
1/2 u'Ku, f'u over the free DOFs). With --momentum: per frame the linear
momentum sum_j m_j v_j (m_j the row sums of M) and sum_j m_j |v_j|.

usage: check_dyn.py [--rel R] [--energy FILE] [--momentum FILE] STREAM
Prints 'ok FILE frames=N max_rel=...' or the first failure (exit 1)."""
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402


def mass(P, dim, mat, lumped):
    """element mass of the simplex with corners P: rho * measure (* t in 2-D
    and for the 3-D membrane triangle)
    shared as 1/(nv) (lumped) or (1 + delta_ab) / ((nv)(nv+1)) (consistent);
    of the trilinear hex (8 corners): rho sum_q det J N_a N_b over the 2x2x2
    Gauss points (cutsys.hex_points), lumped: its row sums"""
    rho, t = mat[4], mat[5]
    if len(P) == 8:
        m8 = [[0.0] * 8 for _ in range(8)]
        for w, N, _ in cutsys.hex_points(P):
            for x in range(8):
                for y in range(8):
                    m8[x][y] += rho * w * N[x] * N[y]
        Me = [[0.0] * 24 for _ in range(24)]
        for x in range(8):
            for y in range(8):
                v = (sum(m8[x]) if x == y else 0.0) if lumped else m8[x][y]
                for i in range(3):
                    Me[x * 3 + i][y * 3 + i] = v
        return Me
    mem3 = dim == 3 and len(P) == 3  # the membrane triangle (formats 5.3): t A, 3 corners
    w = rho * abs(augstream.corners_measure(P)) * (t if dim == 2 or mem3 else 1.0)
    nv = len(P)
    Me = [[0.0] * (nv * dim) for _ in range(nv * dim)]
    for x in range(nv):
        for y in range(nv):
            v = (w / nv if x == y else 0.0) if lumped else w * (2.0 if x == y else 1.0) / (nv * (nv + 1))
            for i in range(dim):
                Me[x * dim + i][y * dim + i] = v
    return Me


def assemble(cm, lumped):
    """K and M over every DOF (dicts of rows: {i: {j: v}})"""
    dim, nv = cm.dim, cm.nv
    K, M = {}, {}
    for e, conn in enumerate(cm.conn):
        P = [cm.x[v] for v in conn]
        mat = cm.mats[cm.mat[e]]
        Ke = cutsys.stiffness(P, dim, mat, cm.kf[cm.mat[e]])
        Me = mass(P, dim, mat, lumped)
        dofs = [conn[a] * dim + c for a in range(nv) for c in range(dim)]
        for a, da in enumerate(dofs):
            rk, rm = K.setdefault(da, {}), M.setdefault(da, {})
            for b, db in enumerate(dofs):
                rk[db] = rk.get(db, 0.0) + Ke[a][b]
                if Me[a][b]:
                    rm[db] = rm.get(db, 0.0) + Me[a][b]
    return K, M


def mult(A, x, i):
    return sum(v * x[j] for j, v in A.get(i, {}).items())


def frame(p):
    """fRAM (7.9): frame, time, dim, nodes or None, u, v (augstream.frame)"""
    try:
        return augstream.frame(p)
    except augstream.StreamError as x:
        raise cutsys.Bad(str(x))


def main():
    args = sys.argv[1:]
    rel, efile, pfile = cutsys.rel_option(args, 1e-10), None, None
    for opt in ("--energy", "--momentum"):
        if opt in args:
            i = args.index(opt)
            val = args[i + 1]
            del args[i:i + 2]
            if opt == "--energy":
                efile = open(val, "w")
            else:
                pfile = open(val, "w")
    if len(args) != 1:
        raise SystemExit(__doc__)
    name = args[0]
    recs = augstream.records(open(name, "rb").read())
    cm = cutsys.CutMesh(augstream.mesh(recs))
    dyn = [p for t, fl, s, p in recs if t == "DYNP"]
    if len(dyn) != 1:
        print("FAIL %s: %d DYNP records" % (name, len(dyn)))
        sys.exit(1)
    integ, mkind, h, alpha, beta, cM, cK = struct.unpack_from("<ii5d", dyn[0], 0)
    aD, aK, g = (1.0, 1.0, 1.0) if integ == 0 else (0.5, 0.25, 0.5)
    if abs(cM - (1 + aD * h * alpha)) > 1e-14 * cM or abs(cK - (aD * h * beta + aK * h * h)) > 1e-14 * cK:
        print("FAIL %s: DYNP cM, cK are not the integrator's" % name)
        sys.exit(1)
    dim = cm.dim
    mats, prev, nf, worst, msg, parents, F = None, None, 0, 0.0, None, [], {}
    nr, last = 0, None  # last: (frame, u1, v1, a) of the latest checked frame
    for t, fl, s, p in recs:
        if t == "rEAC" and last is not None:
            rdim, rfr, rtime, n, nset = struct.unpack_from("<iidqq", p, 0)
            dofs, pos = cutsys.arr("i", p, 32, n)
            rv, pos = cutsys.arr("d", p, pos, n)
            lf, u1_, v1_, acc = last
            if rfr != lf:
                continue
            K, M = mats
            ref = []
            for dof in dofs:
                Ma, Mv, Ku, Kv = mult(M, acc, dof), mult(M, v1_, dof), mult(K, u1_, dof), mult(K, v1_, dof)
                ref.append(Ma + alpha * Mv + beta * Kv + Ku - F.get(dof, 0.0))
            if sorted(dofs) != sorted(cm.fix):
                msg = "frame %d: rEAC DOFs are not the constrained DOFs" % rfr
                break
            if not ref:  # a free body: no constrained DOF
                nr += 1
                continue
            sc = max(map(abs, ref)) or 1.0
            err = max(abs(a - b) for a, b in zip(rv, ref)) / sc
            if not err <= rel:
                msg = "frame %d: reaction differs from M a + D v + K u - f by %.3g relative" % (rfr, err)
                break
            nr += 1
            continue
        if t == "MDLT":
            d = cutsys.mdlt(p, dim, cm.nv)
            cm.apply_mdlt(d)
            parents += d["parent"]
            mats = None
        elif t == "BDLT":
            cm.apply_bdlt(cutsys.bdlt(p))
        if t != "fRAM":
            continue
        fr, time, fdim, nodes, u1, v1 = frame(p)
        if nodes is not None:
            continue
        if fdim != dim or len(u1) != len(cm.x) * dim:
            msg = "frame %d: %d values, the mesh has %d nodes" % (fr, len(u1), len(cm.x))
            break
        if abs(time - fr * h) > 1e-12 * max(1.0, time):
            msg = "frame %d at time %.17g, not frame * h" % (fr, time)
            break
        if mats is None:
            mats = assemble(cm, mkind == 2)
        F = cm.forces()  # LOAD, BDLT loads and the body force (GRAV)
        K, M = mats
        ndof = len(u1)
        if prev is not None:
            pfr, u0, v0 = prev
            for q in parents:  # new nodes start from their parent's state
                for c in range(dim):
                    u0.append(u0[q * dim + c])
                    v0.append(v0[q * dim + c])
            if fr != pfr + 1 or len(u0) != ndof:
                msg = "frame %d follows frame %d (%d of %d values)" % (fr, pfr, len(u0), ndof)
                break
            du = [a - b for a, b in zip(u1, u0)]
            r2 = b2 = 0.0
            for i in range(ndof):
                if i in cm.fix:
                    continue
                Mdu, Kdu = mult(M, du, i), mult(K, du, i)
                lhs = cM * Mdu + cK * Kdu
                rhs = h * mult(M, v0, i) + g * h * h * (F.get(i, 0.0) - mult(K, u0, i))
                r2 += (lhs - rhs) ** 2
                b2 += rhs * rhs
            e = math.sqrt(r2 / b2) if b2 > 0 else math.sqrt(r2)
            for i in range(ndof):
                vv = du[i] / h if integ == 0 else 2 * du[i] / h - v0[i]
                if abs(vv - v1[i]) > 1e-9 * max(1e-300, max(abs(vv), max(map(abs, v1)))):
                    msg = "frame %d: velocity of DOF %d is %.17g, the integrator gives %.17g" % (fr, i, v1[i], vv)
                    break
            if msg:
                break
            nf += 1
            if not e <= rel:
                msg = "frame %d (step %d): A du - rhs is %.3g relative (> %g)" % (fr, s, e, rel)
                break
            worst = max(worst, e)
            last = (fr, u1, v1, [(a - b) / h for a, b in zip(v1, v0)])
        parents = []
        if efile:
            free = [i for i in range(ndof) if i not in cm.fix]
            ke = 0.5 * sum(v1[i] * mult(M, v1, i) for i in free)
            pe = 0.5 * sum(u1[i] * mult(K, u1, i) for i in free)
            w = sum(F.get(i, 0.0) * u1[i] for i in free)
            efile.write("%d %.17g %.17g %.17g %.17g\n" % (fr, time, ke, pe, w))
        if pfile:
            mrow = [sum(M.get(i, {}).values()) for i in range(ndof)]
            P = [sum(mrow[n * dim + c] * v1[n * dim + c] for n in range(ndof // dim)) for c in range(dim)]
            S = sum(mrow[i] * abs(v1[i]) for i in range(ndof))
            pfile.write("%d %s %.17g\n" % (fr, " ".join("%.17g" % x for x in P), S))
        prev = (fr, u1, v1)
    if msg:
        print("FAIL %s: %s" % (name, msg))
        sys.exit(1)
    print("ok %s frames=%d reactions=%d max_rel=%.3g" % (name, nf, nr, worst))


main()
