#!/usr/bin/env python3
"""2-D thickness: two streams of one load-driven plane-stress scene (no
prescribed non-zero values) that differ only in the thickness t of every
material, A with t = 1 and B with t, compared record by record
(augstream.py, cutsys.py), independently of the C library:
- MATL: B's t is the given t, everything else as A;
- K and the update terms scale with t: KMAT (which 0) of B = t KMAT of A,
  entry by entry, to 1e-14 max|K|; every UPDT's E of B = t E of A (df: the
  loads, the same);
- the displacement scales as 1/t: every fELD of B equals A's / t to 1e-12
  relative (max norm), step by step;
- cOND: lambda_max and lambda_min of B are t times A's to 1e-9, cond the same.

usage: thickness.py A.aug B.aug T
Prints 'ok records=.. fields=.. updates=..'; exit 1 on the first failure."""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402
from check_field import field  # noqa: E402


def fail(msg):
    print("thickness: %s" % msg)
    sys.exit(1)


def close(a, b, rel, what):
    s = max([abs(v) for v in b] + [0.0])
    d = max([abs(x - y) for x, y in zip(a, b)] + [0.0])
    if len(a) != len(b) or not d <= rel * s or not s > 0:
        fail("%s: max difference %.3g of max %.3g (%d and %d entries)" % (what, d, s, len(a), len(b)))


def main():
    ra, rb = (augstream.records(open(f, "rb").read()) for f in sys.argv[1:3])
    t = float(sys.argv[3])
    ma, mb = augstream.mesh(ra), augstream.mesh(rb)
    if [m[:5] for m in ma["mats"]] != [m[:5] for m in mb["mats"]] or \
            any(m[5] != 1 for m in ma["mats"]) or any(m[5] != t for m in mb["mats"]):
        fail("MATL: %s and %s, want t = 1 and t = %g" % (ma["mats"], mb["mats"], t))
    keep = [r[0] for r in ra if r[0] not in ("pROv", "tIMe")]
    if keep != [r[0] for r in rb if r[0] not in ("pROv", "tIMe")]:
        fail("the streams do not have the same records")
    nf = nu = 0
    pa = [r for r in ra if r[0] not in ("pROv", "tIMe")]
    pb = [r for r in rb if r[0] not in ("pROv", "tIMe")]
    for (typ, _, step, p), (_, _, _, q) in zip(pa, pb):
        if typ == "KMAT":
            wa, n, Ka = cutsys.kmat(p)
            wb, n2, Kb = cutsys.kmat(q)
            if wa == 0:
                if n != n2 or Ka.keys() != Kb.keys():
                    fail("KMAT patterns differ")
                keys = sorted(Ka)
                close([t * Ka[k] for k in keys], [Kb[k] for k in keys], 1e-14, "KMAT of t = %g vs t KMAT of t = 1" % t)
        elif typ == "fELD":
            _, _, na, ua = field(p)
            _, _, nb, ub = field(q)
            if na != nb:
                fail("step %d: fields of different nodes" % step)
            close([v / t for v in ua], list(ub), 1e-12, "step %d: the field of t = %g vs 1/t the field of t = 1" % (step, t))
            nf += 1
        elif typ == "UPDT":
            ua, ub = cutsys.updt(p), cutsys.updt(q)
            if ua[:3] != ub[:3]:
                fail("step %d: UPDT H differs" % step)
            if any(ua[3]):
                close([t * v for v in ua[3]], list(ub[3]), 1e-13, "step %d: UPDT E of t = %g vs t E of t = 1" % (step, t))
            nu += 1
        elif typ == "cOND":
            ca, cb = augstream.kv(p)[1], augstream.kv(q)[1]
            for k in ("lambda_max", "lambda_min"):
                if not abs(cb[k] - t * ca[k]) <= 1e-9 * t * ca[k]:
                    fail("cOND %s %.17g, t times that of t = 1 is %.17g" % (k, cb[k], t * ca[k]))
            if not abs(cb["cond"] - ca["cond"]) <= 1e-9 * ca["cond"]:
                fail("cOND cond %.17g and %.17g" % (cb["cond"], ca["cond"]))
    if not nf:
        fail("no fELD")
    print("ok records=%d fields=%d updates=%d" % (len(pa), nf, nu))


main()
