#!/usr/bin/env python3
"""Independent check of solve-aug's cgm-* methods (thesis 003 sec. 3.5), from
the specification only: for each STREAM (solve-aug --method cgm-X first, so
its fELD is cgm-X's x), the cut system K_t, f_t of the step is assembled from
scratch (tests/py/cutsys.py) and solved here (check_field.py's Cholesky); the
transformed matrix T is built by the definitions (COV eq. 3.21 summed over
rows, the textbook L D L' with pivots <= n macheps max COV_jj taken as 0, F of
eqs. 3.24-3.25 on D + eps I, T = L F L' by its entries; AS: the eigenvalues
of T are sqrt(lambda(COV) + eps)); its extreme eigenvalues by Householder
tridiagonalisation and Sturm bisection. Asserts, against the step's sTAt:
err_chol = ||x - u|| / ||u|| (1e-7 relative), lambda_max (1e-6), cond (1e-4;
AS 1e-2, its lambda_min known to macheps ||COV|| only; COV: inf), spd, and for
cgm-es that x solves T x = f_t to CG's relres_t times cond(T).

usage: cgm_check.py STREAM...   prints 'ok FILE ...' per stream; exit 1 on a failure"""
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import check_field  # noqa: E402
import cutsys  # noqa: E402


def dense(K, n):
    A = [[0.0] * n for _ in range(n)]
    for (i, j), v in K.items():
        A[i][j] = A[j][i] = v
    return A


def cov(A):
    """eq. 3.21: 1/(n-1) sum_i (x_i - xbar)' (x_i - xbar), x_i the rows of A"""
    n = len(A)
    xbar = [sum(A[i][j] for i in range(n)) / n for j in range(n)]
    D = [[A[i][j] - xbar[j] for j in range(n)] for i in range(n)]
    C = [[0.0] * n for _ in range(n)]
    for i in range(n):
        r = D[i]
        for a in range(n):
            ra = r[a] / (n - 1)
            if ra:
                Ca = C[a]
                for b in range(n):
                    Ca[b] += ra * r[b]
    return C


def ldl(M):
    n = len(M)
    tiny = n * 2.220446049250313e-16 * max(M[j][j] for j in range(n))
    L = [[0.0] * n for _ in range(n)]
    d = [0.0] * n
    for j in range(n):
        s = M[j][j] - sum(L[j][k] ** 2 * d[k] for k in range(j))
        L[j][j] = 1.0
        if not s > tiny:
            continue
        d[j] = s
        for i in range(j + 1, n):
            L[i][j] = (M[i][j] - sum(L[i][k] * L[j][k] * d[k] for k in range(j))) / s
    return L, d


def recompose(L, F):
    n = len(L)
    W = [[L[i][k] * F[k] for k in range(n)] for i in range(n)]
    return [[sum(W[i][k] * L[j][k] for k in range(max(i, j) + 1)) for j in range(n)] for i in range(n)]


def extreme_eigs(A):
    """(smallest, largest-magnitude, smallest-magnitude) eigenvalue of the
    symmetric A: Householder to tridiagonal, then Sturm-count bisection"""
    n = len(A)
    A = [row[:] for row in A]
    for k in range(n - 2):
        x = [A[i][k] for i in range(k + 1, n)]
        alpha = math.sqrt(sum(v * v for v in x))
        if alpha == 0:
            continue
        if x[0] > 0:
            alpha = -alpha
        v = x[:]
        v[0] -= alpha
        vn = sum(t * t for t in v)
        if vn == 0:
            continue
        m = len(v)
        # A22 := H A22 H, H = I - 2 v v' / v'v
        p = [2 * sum(A[k + 1 + i][k + 1 + j] * v[j] for j in range(m)) / vn for i in range(m)]
        K = sum(v[i] * p[i] for i in range(m)) / vn
        q = [p[i] - K * v[i] for i in range(m)]
        for i in range(m):
            Ai = A[k + 1 + i]
            for j in range(m):
                Ai[k + 1 + j] -= v[i] * q[j] + q[i] * v[j]
        A[k + 1][k] = A[k][k + 1] = alpha
        for i in range(k + 2, n):
            A[i][k] = A[k][i] = 0.0
    a = [A[i][i] for i in range(n)]
    b = [A[i + 1][i] for i in range(n - 1)]

    def below(x):  # eigenvalues < x (Sturm sequence)
        c, q = 0, 1.0
        for i in range(n):
            q = a[i] - x - (b[i - 1] ** 2 / q if i else 0.0)
            if q == 0:
                q = 1e-300
            c += q < 0
        return c

    r = max(abs(a[i]) + (abs(b[i]) if i < n - 1 else 0) + (abs(b[i - 1]) if i else 0) for i in range(n))

    def kth(k):  # the k-th smallest, 0-based
        lo, hi = -r, r
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                break
            if below(mid) > k:
                hi = mid
            else:
                lo = mid
        return 0.5 * (lo + hi)

    neg = below(0.0)
    lmin, lmax = kth(0), kth(n - 1)
    small = [kth(neg - 1)] if neg > 0 else []
    if neg < n:
        small.append(kth(neg))
    return lmin, (lmax if abs(lmax) >= abs(lmin) else lmin), min(small, key=abs)


def solve_dense(T, f):
    n = len(T)
    M = [T[i][:] + [f[i]] for i in range(n)]
    for k in range(n):
        p = max(range(k, n), key=lambda i: abs(M[i][k]))
        M[k], M[p] = M[p], M[k]
        for i in range(k + 1, n):
            m = M[i][k] / M[k][k]
            if m:
                Mi, Mk = M[i], M[k]
                for j in range(k, n + 1):
                    Mi[j] -= m * Mk[j]
    x = [0.0] * n
    for i in range(n - 1, -1, -1):
        x[i] = (M[i][n] - sum(M[i][j] * x[j] for j in range(i + 1, n))) / M[i][i]
    return x


def check(name):
    recs = augstream.records(open(name, "rb").read())
    cm = cutsys.CutMesh(augstream.mesh(recs))
    x = st = None
    for t, fl, s, p in recs:
        if t == "MDLT":
            cm.apply_mdlt(cutsys.mdlt(p, cm.dim, cm.nv))
        elif t == "BDLT":
            cm.apply_bdlt(cutsys.bdlt(p))
        elif t == "fELD" and s >= 1:
            kind, fdim, nodes, u = check_field.field(p)
            K, f = cm.assemble()
            n = len(f)
            x = [0.0] * n
            nodes = list(range(len(u) // cm.dim)) if nodes is None else nodes
            for q, v in enumerate(nodes):
                for c in range(cm.dim):
                    dof = v * cm.dim + c
                    if dof not in cm.fix:
                        x[cm.index(dof)] = u[q * cm.dim + c]
            break
    for t, fl, s, p in recs:
        if t == "sTAt" and s >= 1:
            tag, vals = augstream.kv(p)
            if tag.startswith("cgm-"):
                st = (tag, vals)
                break
    if x is None or st is None:
        return "no step-1 fELD or cgm-* sTAt"
    tag, v = st
    u = check_field.solve(K, f)
    d = math.sqrt(sum((x[i] - u[i]) ** 2 for i in range(n)) / sum(t * t for t in u))
    if not abs(v["err_chol"] - d) <= 1e-7 * d:
        return "err_chol %.17g, here %.17g" % (v["err_chol"], d)
    A = dense(K, n)
    C = cov(A)
    eps = v.get("eps", 0.0)
    if tag == "cgm-as":
        lmin_c, _, _ = extreme_eigs(C)
        lmax_c = extreme_eigs(C)[1]
        lmax, lsmall, spd = math.sqrt(lmax_c + eps), math.sqrt(max(lmin_c, 0.0) + eps), True
        T = None
    else:
        L, dd = ldl(C)
        F = dd if tag == "cgm-cov" else [(t + eps) ** v["p"] for t in dd] if tag == "cgm-es" else [math.log(t + eps) for t in dd]
        T = C if tag == "cgm-cov" else recompose(L, F)
        lo, lmax, lsmall = extreme_eigs(T)
        spd = all(t > 0 for t in F)
    if not abs(v["lambda_max"] - lmax) <= 1e-6 * abs(lmax):
        return "lambda_max %.10g, here %.10g" % (v["lambda_max"], lmax)
    if tag == "cgm-cov":
        if not (math.isinf(v["cond"]) and v["spd"] == 0):
            return "COV (rank n-1): cond %g, spd %g" % (v["cond"], v["spd"])
    else:
        c = abs(lmax / lsmall)
        tol = 1e-2 if tag == "cgm-as" else 1e-4
        if not abs(v["cond"] - c) <= tol * c:
            return "cond %.10g, here %.10g" % (v["cond"], c)
        if bool(v["spd"]) != spd:
            return "spd %g, here %s" % (v["spd"], spd)
    if tag == "cgm-es" and v["converged"] == 1:
        xr = solve_dense(T, f)
        e = math.sqrt(sum((x[i] - xr[i]) ** 2 for i in range(n)) / sum(t * t for t in xr))
        if not e <= 10 * v["relres_t"] * v["cond"]:
            return "x off T^-1 f by %g (relres_t %g, cond %g)" % (e, v["relres_t"], v["cond"])
    return "ok %s %s n=%d err_chol=%.4g cond=%.4g" % (name, tag, n, d, v["cond"])


def main():
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    bad = 0
    for name in sys.argv[1:]:
        msg = check(name)
        if not msg.startswith("ok "):
            msg, bad = "FAIL %s: %s" % (name, msg), 1
        print(msg)
    sys.exit(bad)


if __name__ == "__main__":
    main()
