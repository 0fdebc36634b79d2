#!/usr/bin/env python3
"""factor's cOND against the inertia of K, computed here: K - s I is positive
definite iff s < lambda_min, and s I - K iff s > lambda_max (Sylvester), each
decided by a Cholesky factorization of our own (check_field.Envelope, on
KMAT which 0 as written). cOND's Lanczos values are Ritz values: lambda_max
lies in [theta, theta (1 + T)], lambda_min in [theta / (1 + T), theta] (its
Ritz value of K^-1 is theta^-1), T the cOND tol (factor(1), --cond-tol). So:
- K - s I fails at s = lambda_min (1 + e), and passes at lambda_min / (1 + T) / (1 + e);
- s I - K fails at s = lambda_max (1 - e), and passes at lambda_max (1 + T) (1 + e);
e = 1e-7 for rounding; cond = lambda_max / lambda_min to 1e-12; converged 1.
With --tol T2 the brackets use T2 instead of the record's (a tighter claim).

usage: cond_check.py STREAM [--tol T2]
Prints 'ok n=.. lambda_max=.. lambda_min=.. cond=.. tol=..'; exit 1 on a failure."""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402
from check_field import Envelope  # noqa: E402


def pd(K, n, diag, sign):
    """is sign K + diag I positive definite?"""
    A = {k: sign * v for k, v in K.items()}
    for i in range(n):
        A[(i, i)] = A.get((i, i), 0.0) + diag
    try:
        Envelope(A, n)
    except ValueError:
        return False
    return True


def main():
    args = sys.argv[1:]
    recs = augstream.records(open(args[0], "rb").read())
    ks = [cutsys.kmat(p) for t, fl, s, p in recs if t == "KMAT"]
    cs = [augstream.kv(p)[1] for t, fl, s, p in recs if t == "cOND"]
    K = [k for k in ks if k[0] == 0]
    if len(K) != 1 or len(cs) != 1:
        sys.exit("cond_check: %s: want one KMAT (which 0) and one cOND" % args[0])
    _, n, K = K[0]
    c = cs[0]
    T = float(args[args.index("--tol") + 1]) if "--tol" in args else c["tol"]
    lmax, lmin, e = c["lambda_max"], c["lambda_min"], 1e-7
    bad = []
    if c["converged"] != 1:
        bad.append("converged %g" % c["converged"])
    if not abs(c["cond"] - lmax / lmin) <= 1e-12 * c["cond"]:
        bad.append("cond %.17g, lambda_max / lambda_min %.17g" % (c["cond"], lmax / lmin))
    if pd(K, n, -lmin * (1 + e), 1):
        bad.append("K - s I is positive definite at s = lambda_min (1 + %g): lambda_min %.17g is too small" % (e, lmin))
    if not pd(K, n, -lmin / (1 + T) / (1 + e), 1):
        bad.append("K - s I is not positive definite at s = lambda_min / (1 + %g): lambda_min %.17g is too large"
                   % (T, lmin))
    if pd(K, n, lmax * (1 - e), -1):
        bad.append("s I - K is positive definite at s = lambda_max (1 - %g): lambda_max %.17g is too large" % (e, lmax))
    if not pd(K, n, lmax * (1 + T) * (1 + e), -1):
        bad.append("s I - K is not positive definite at s = lambda_max (1 + %g): lambda_max %.17g is too small"
                   % (T, lmax))
    if bad:
        print("cond_check: %s: %s" % (args[0], "; ".join(bad)))
        sys.exit(1)
    print("ok n=%d lambda_max=%.10g lambda_min=%.10g cond=%.10g tol=%g" % (n, lmax, lmin, c["cond"], T))


main()
