#!/usr/bin/env python3
"""Independent check of written fields (formats/stream.md 7.3), from the
specification only: for every fELD of each stream, the cut system of its step
(the mesh replayed from NODE/ELEM/FIXD/LOAD and the MDLT/BDLT records up to
that step, K_t and f_t assembled from scratch, tests/py/cutsys.py) is solved
here, by a Cholesky factorization of K_t in reverse Cuthill-McKee order with
one step of iterative refinement, and the field must equal the solution on
its nodes (constrained DOFs: their values) to --rel relative, in the 2-norm
over the written nodes.

usage: check_field.py [--rel R] STREAM...   (default R = 1e-10)

Streams with the same steps (one cut solved by several methods) share the
solves. Prints one line per stream, 'ok FILE fields=N max_rel=...', or the
first failure; exit 1 on a failure."""
import hashlib
import math
import operator
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402


def rcm(n, nbr):
    """reverse Cuthill-McKee order of the graph nbr (lists), every component"""
    deg = [len(a) for a in nbr]
    seen, order = [False] * n, []
    for s in sorted(range(n), key=deg.__getitem__):
        if seen[s]:
            continue
        seen[s] = True
        q, h = [s], 0
        while h < len(q):
            v = q[h]
            h += 1
            for w in sorted((w for w in nbr[v] if not seen[w]), key=deg.__getitem__):
                seen[w] = True
                q.append(w)
        order += q
    return order[::-1]


class Envelope:
    """A = L L' of a symmetric positive definite matrix (upper dict) in the
    order perm, L held row by row over its envelope"""

    def __init__(self, K, n):
        nbr = [[] for _ in range(n)]
        for (i, j) in K:
            if i != j:
                nbr[i].append(j)
                nbr[j].append(i)
        self.perm = rcm(n, nbr)
        inv = [0] * n
        for k, v in enumerate(self.perm):
            inv[v] = k
        rows = [{} for _ in range(n)]
        for (i, j), v in K.items():
            a, b = inv[i], inv[j]
            if a < b:
                a, b = b, a
            rows[a][b] = rows[a].get(b, 0.0) + v
        self.first, self.L = [], []
        mul = operator.mul
        for i in range(n):
            fi = min(rows[i]) if rows[i] else i
            r = [0.0] * (i - fi + 1)
            for j, v in rows[i].items():
                r[j - fi] = v
            for j in range(fi, i):
                fj = self.first[j]
                k0 = max(fi, fj)
                Lj = self.L[j]
                s = r[j - fi] - sum(map(mul, r[k0 - fi:j - fi], Lj[k0 - fj:j - fj]))
                r[j - fi] = s / Lj[j - fj]
            d = r[i - fi] - sum(map(mul, r[:i - fi], r[:i - fi]))
            if not d > 0:
                raise ValueError("K_t is not positive definite (pivot %d of %d)" % (i, n))
            r[i - fi] = math.sqrt(d)
            self.first.append(fi)
            self.L.append(r)

    def solve(self, b):
        n, mul = len(b), operator.mul
        y = [b[v] for v in self.perm]
        for i in range(n):  # L y = b
            fi, r = self.first[i], self.L[i]
            y[i] = (y[i] - sum(map(mul, r[:i - fi], y[fi:i]))) / r[i - fi]
        for i in range(n - 1, -1, -1):  # L' x = y, by columns of L'
            fi, r = self.first[i], self.L[i]
            y[i] /= r[i - fi]
            yi = y[i]
            for k in range(fi, i):
                y[k] -= r[k - fi] * yi
        x = [0.0] * n
        for k, v in enumerate(self.perm):
            x[v] = y[k]
        return x


def matvec(K, x):
    y = [0.0] * len(x)
    for (i, j), v in K.items():
        y[i] += v * x[j]
        if i != j:
            y[j] += v * x[i]
    return y


def solve(K, f):
    """K^-1 f with one step of iterative refinement"""
    F = Envelope(K, len(f))
    x = F.solve(f)
    r = [a - b for a, b in zip(f, matvec(K, x))]
    return [a + b for a, b in zip(x, F.solve(r))]


def field(p):
    """fELD (7.3): (kind, dim, nodes or None, values)"""
    kind, dim, count, indexed = struct.unpack_from("<iiqi", p, 0)
    pos = 24
    nodes = None
    if indexed:
        nodes, pos = cutsys.arr("i", p, pos, count)
    u, pos = cutsys.arr("d", p, pos, count * dim)
    if pos != len(p):
        raise cutsys.Bad("fELD payload size")
    return kind, dim, nodes, u


def main():
    args = sys.argv[1:]
    rel = cutsys.rel_option(args, 1e-10)
    if not args:
        raise SystemExit(__doc__)
    solved, bad = {}, 0
    for name in args:
        recs = augstream.records(open(name, "rb").read())
        cm = cutsys.CutMesh(augstream.mesh(recs))
        h = hashlib.sha1(b"".join(p for t, fl, s, p in recs if t in ("NODE", "MATL", "ELEM", "FIXD", "LOAD")))
        dim, nf, worst, msg = cm.dim, 0, 0.0, None
        for t, fl, s, p in recs:
            if t in ("MDLT", "BDLT"):
                h.update(t.encode() + p)
                if t == "MDLT":
                    cm.apply_mdlt(cutsys.mdlt(p, dim, cm.nv))
                else:
                    cm.apply_bdlt(cutsys.bdlt(p))
            if t != "fELD":
                continue
            kind, fdim, nodes, u = field(p)
            nodes = list(range(len(u) // dim)) if nodes is None else nodes
            if kind != 0 or fdim != dim or any(not 0 <= v < len(cm.x) for v in nodes):
                msg = "step %d: fELD kind %d, dim %d, nodes outside the mesh of %d" % (s, kind, fdim, len(cm.x))
                break
            key = h.hexdigest()
            if key not in solved:
                K, f = cm.assemble()
                try:
                    solved[key] = solve(K, f)
                except ValueError as e:
                    msg = "step %d: %s" % (s, e)
                    break
            a = solved[key]
            d2 = r2 = 0.0
            for q, v in enumerate(nodes):
                for c in range(dim):
                    dof = v * dim + c
                    ref = cm.fix[dof] if dof in cm.fix else a[cm.index(dof)]
                    d2 += (u[q * dim + c] - ref) ** 2
                    r2 += ref * ref
            e = math.sqrt(d2 / r2) if r2 > 0 else math.sqrt(d2)
            nf += 1
            if not e <= rel:
                msg = "step %d: the field differs from the solution of K_t by %.3g relative (> %g)" % (s, e, rel)
                break
            worst = max(worst, e)
        if msg:
            print("FAIL %s: %s" % (name, msg))
            bad = 1
        else:
            print("ok %s fields=%d max_rel=%.3g" % (name, nf, worst))
    sys.exit(bad)


if __name__ == "__main__":
    main()
