#!/usr/bin/env python3
"""The largest relative difference between the frames (formats/stream.md 7.9
fRAM) of two streams, frame by frame: ||u_A - u_B|| / ||u_B|| (2-norm over
the written nodes; the nodes must be the same), also for v with --v. Only the
frames both have are compared (at least --min of them).

usage: frames_diff.py [--tol T] [--min N] [--v] A B
Prints 'ok frames=N max_rel=...' (exit 0) or the first frame over T (exit 1)."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402


def frames(path):
    """{frame: (nodes or None, u, v)}; a later record of the same frame wins"""
    out = {}
    for t, fl, s, p in augstream.records(open(path, "rb").read()):
        if t == "fRAM":
            try:
                fr, time, dim, nodes, u, v = augstream.frame(p)
            except augstream.StreamError as x:
                sys.exit("%s: %s" % (path, x))
            out[fr] = (nodes, u, v)
    return out


def rel(a, b):
    d = math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))
    n = math.sqrt(sum(y * y for y in b))
    return d / n if n > 0 else d


def main(argv):
    tol, least, use_v = 1e-12, 1, False
    args = []
    i = 0
    while i < len(argv):
        if argv[i] == "--tol":
            tol = float(argv[i + 1])
            i += 2
        elif argv[i] == "--min":
            least = int(argv[i + 1])
            i += 2
        elif argv[i] == "--v":
            use_v = True
            i += 1
        else:
            args.append(argv[i])
            i += 1
    if len(args) != 2:
        sys.exit(__doc__)
    A, B = frames(args[0]), frames(args[1])
    common = sorted(set(A) & set(B))
    if len(common) < least:
        print("only %d common frames (need %d)" % (len(common), least))
        return 1
    worst = 0.0
    for f in common:
        (na, ua, va), (nb, ub, vb) = A[f], B[f]
        if na != nb or len(ua) != len(ub):
            print("frame %d: different nodes" % f)
            return 1
        r = max(rel(ua, ub), rel(va, vb) if use_v else 0.0)
        if not r <= tol:
            print("frame %d: relative difference %.3g > %g" % (f, r, tol))
            return 1
        worst = max(worst, r)
    print("ok frames=%d max_rel=%.3g" % (len(common), worst))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
