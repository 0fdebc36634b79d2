#!/usr/bin/env python3
"""Compares the fELD records of two streams of the same steps: on every step
>= 1 the second stream's field (an output set, or another method or mode)
equals the first's on its nodes to TOL relative (max abs difference over max
abs value); with SET = top, the second lists every node of the original set
"top"; SET = all: both cover every node.
usage: field_cmp.py FULL.aug OTHER.aug SET TOL"""
import sys
sys.path.insert(0, __import__("os").path.dirname(__file__))
import augstream, struct
def fields(path):
    out = {}
    for typ, flags, step, p in augstream.records(open(path, "rb").read()):
        if typ != "fELD" or step < 1:
            continue
        kind, dim, count, indexed = struct.unpack_from("<iiqi", p, 0)
        pos = 24
        nodes = list(struct.unpack_from("<%di" % count, p, pos)) if indexed else list(range(count))
        pos += 4 * count if indexed else 0
        u = struct.unpack_from("<%dd" % (count * dim), p, pos)
        out[step] = (dim, nodes, u)
    return out
full, part = fields(sys.argv[1]), fields(sys.argv[2])
want, tol = sys.argv[3], float(sys.argv[4])
recs = augstream.records(open(sys.argv[2], "rb").read())
m = augstream.mesh(recs)
bad = 0
if not full or sorted(part) != sorted(full):
    print("%s: steps %s, full %s" % (sys.argv[2], sorted(part), sorted(full))); sys.exit(1)
for step in sorted(full):
    dim, nodes, u = part[step]
    fdim, fnodes, fu = full[step]
    if want == "top":
        top = m["sets"].get("top")   # the original set; node copies inherit membership
        if not top or not set(top) <= set(nodes):
            print("step %d: the output does not list the nodes of set top" % step); bad = 1
    num = den = 0.0
    for i, nd in enumerate(nodes):
        for c in range(dim):
            num = max(num, abs(u[i * dim + c] - fu[nd * dim + c]))
            den = max(den, abs(fu[nd * dim + c]))
    if not (len(nodes) > 0 and num <= tol * den):
        print("step %d %s: max |u_set - u_full| = %.3g (max |u| %.3g, tol %g)" % (step, want, num, den, tol)); bad = 1
if want == "all" and any(len(part[k][1]) != len(full[k][1]) for k in full):
    print("the field does not cover every node"); bad = 1
sys.exit(bad)
