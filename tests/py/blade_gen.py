#!/usr/bin/env python3
"""A seeded random blade file (cut(1) BLADE FILE) for a mesh: the blade, a
segment of random direction and half-length 0.4..1.2 R (R the half diagonal
of the mesh's box), enters from outside the box and moves towards and past
its centre (ending inside it, a partial cut, or beyond), over 2 to 4 keys
with a slight turn; curved: Bezier control lines between the keys.

usage: blade_gen.py STREAM SEED straight|curved > BFILE"""
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def rand_unit(r):
    while True:
        v = [r.uniform(-1, 1) for _ in range(3)]
        if 1e-2 < sum(c * c for c in v) <= 1:
            return unit(v)


def main():
    if len(sys.argv) != 4:
        raise SystemExit(__doc__)
    m = augstream.mesh(augstream.records(open(sys.argv[1], "rb").read()))
    r = random.Random(int(sys.argv[2]))
    curved = sys.argv[3] == "curved"
    x = m["x"]
    lo = [min(p[k] for p in x) for k in range(3)]
    hi = [max(p[k] for p in x) for k in range(3)]
    c = [(lo[k] + hi[k]) / 2 for k in range(3)]
    R = math.dist(lo, hi) / 2
    u = rand_unit(r)
    w = rand_unit(r)
    wu = sum(w[k] * u[k] for k in range(3))
    w = unit([w[k] - wu * u[k] for k in range(3)])
    off = [r.uniform(-0.3, 0.3) * R for _ in range(3)]
    off = [off[k] - sum(off[j] * w[j] for j in range(3)) * w[k] for k in range(3)]
    s = [c[k] + off[k] - 1.2 * R * w[k] for k in range(3)]
    f = r.uniform(-0.2, 1.3)
    e = [c[k] + off[k] + f * R * w[k] for k in range(3)]
    L = R * r.uniform(0.4, 1.2)
    nkey = r.randint(2, 4)
    for i in range(nkey):
        t = i / (nkey - 1)
        ang = r.uniform(-0.15, 0.15)
        d = unit([u[k] * math.cos(ang) + w[k] * math.sin(ang) * 0.3 for k in range(3)])
        p = [s[k] + t * (e[k] - s[k]) for k in range(3)]
        if curved and i > 0:
            for j in range(r.randint(1, 2)):
                q = [p[k] - (e[k] - s[k]) / (nkey - 1) * (1 - (j + 1) / 3) + r.uniform(-0.25, 0.25) * R for k in range(3)]
                print("curve %s" % " ".join("%.6f" % v for v in [q[k] - L * d[k] for k in range(3)] + [q[k] + L * d[k] for k in range(3)]))
        print("blade %s" % " ".join("%.6f" % v for v in [p[k] - L * d[k] for k in range(3)] + [p[k] + L * d[k] for k in range(3)]))


main()
