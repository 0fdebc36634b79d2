#!/usr/bin/env python3
"""Boxes for bench/deform.sh, from the NODE and FIXD records of a mesh stream.

  deform_boxes.py fix MESH.aug
      box:LO,HI selecting the nodes within 10% of the low end of the longest
      axis of the bounding box (a support for meshes without a fixed group)
  deform_boxes.py drag MESH.aug COUNT...
      per COUNT one line "NODES BOX D": a box growing on the free end (the end
      of the longest axis away from the fixed nodes' centroid) holding NODES
      nodes, the least count >= COUNT the box can hold, and the displacement D
      of the drag (1% of that axis' length, along the next axis). The box is
      {x: |x_t - c_t| <= r (both transverse axes, c the end face's centre),
      distance from the end <= r}; r grows with COUNT. Counts that give the
      same box are printed once; a COUNT above half the nodes is left out."""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from aug_kv import payloads  # noqa: E402


def read(path):
    """(dim, coordinates, fixed node indices) of NODE and FIXD"""
    x, fixed, dim = [], set(), 3
    for typ, step, p in payloads(path, ("NODE", "FIXD")):
        if typ == "NODE":
            dim, _, nn = struct.unpack_from("<iiq", p, 0)
            v = struct.unpack_from("<%dd" % (nn * dim), p, 16)
            x = [v[i * dim:(i + 1) * dim] for i in range(nn)]
        else:
            (n,) = struct.unpack_from("<q", p, 0)
            fixed = {d // dim for d in struct.unpack_from("<%di" % n, p, 8)}
    return dim, x, fixed


def spec(lo, hi):
    return "box:" + ",".join("%.17g" % v for v in list(lo) + list(hi))


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in ("fix", "drag"):
        sys.exit(__doc__)
    dim, x, fixed = read(sys.argv[2])
    lo = [min(p[c] for p in x) for c in range(dim)]
    hi = [max(p[c] for p in x) for c in range(dim)]
    ext = [hi[c] - lo[c] for c in range(dim)]
    ax = max(range(dim), key=lambda c: ext[c])
    L, eps = ext[ax], 1e-9 * max(ext)
    big = 1e3 * max(ext)
    if sys.argv[1] == "fix":
        a = [v - big for v in lo]
        b = [v + big for v in hi]
        b[ax] = lo[ax] + 0.1 * L
        print(spec(a, b))
        return
    fc = sum(x[i][ax] for i in fixed) / len(fixed) if fixed else lo[ax]
    top = hi[ax] - fc >= fc - lo[ax]          # the free end is at hi[ax]
    end = hi[ax] if top else lo[ax]
    tr = [c for c in range(dim) if c != ax]
    face = [p for p in x if abs(p[ax] - end) <= 1e-6 * L] or x
    cen = [sum(p[c] for p in face) / len(face) for c in range(dim)]
    dist = sorted(max([abs(p[ax] - end)] + [abs(p[c] - cen[c]) for c in tr]) for p in x)
    d = [0.0] * dim
    d[tr[0]] = 0.01 * L
    seen = set()
    for w in sys.argv[3:]:
        want = int(w)
        if want < 1 or want > len(x) // 2:
            continue
        r = dist[want - 1]
        n = sum(1 for s in dist if s <= r + eps)
        if n in seen:
            continue
        seen.add(n)
        a = [cen[c] - r - eps for c in range(dim)]
        b = [cen[c] + r + eps for c in range(dim)]
        a[ax], b[ax] = (end - r - eps, end + eps) if top else (end - eps, end + r + eps)
        print(n, spec(a, b), ",".join("%.17g" % v for v in d))


main()
