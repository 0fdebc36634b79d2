#!/usr/bin/env python3
"""Helpers of bench/thesis.sh (thesis 003 tables 5.1, 5.2, 5.4, figs. 5.16-5.20).
  thesis_tools.py kirigami FILE     a kirigami cut path (cut(1)): 20 slits, 5 rows
        of 4 gently curved cubic Beziers, every other row shifted by half a slit
  thesis_tools.py kv STREAM TYPE TAG KEY [sum|max|mean]   the named value of
        the records TYPE with tag TAG over the stream's steps
  thesis_tools.py steps LABEL STATS_CSV   one CSV row per (step, method) of a
        solve-aug run (stats --csv), the columns of STEP_COLS
  thesis_tools.py per_method STEPS_CSV LABEL   one row per method of LABEL's
        steps: n (max), iterations (max), time (max ms), cond (max), error (max)"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import aug_kv  # noqa: E402

STEP_COLS = ["n", "iters", "converged", "relres", "relres_t", "cond", "cond_k", "spd", "err_chol", "err_scaled",
             "ns_iters", "ic_shift", "time_ms", "iter", "cov", "decomp", "normalise", "recomp", "cg", "diag"]


def kirigami(out):
    lines = []
    for r in range(5):
        y = 0.14 + 0.18 * r
        off = 0.0 if r % 2 == 0 else 0.11
        for c in range(4):
            x0 = 0.06 + off + 0.22 * c
            if x0 + 0.16 > 0.97:
                x0 -= 0.9
                if x0 < 0.03:
                    x0 = 0.03
            x1 = x0 + 0.16
            b = 0.02 * (1 if (r + c) % 2 else -1)
            pts = [x0, y, x0 + 0.053, y + b, x0 + 0.107, y - b, x1, y]
            lines.append("bezier " + " ".join("%.6f" % v for v in pts))
    open(out, "w").write("\n".join(lines) + "\n")


def kv(path, typ, tag, key, how="sum"):
    vals = []
    for t, step, p in aug_kv.payloads(path, (typ,)):
        import struct
        name = p[:16].split(b"\0")[0].decode()
        if name != tag:
            continue
        n, = struct.unpack_from("<i", p, 16)
        for i in range(n):
            o = 24 + 24 * i
            if p[o:o + 16].split(b"\0")[0].decode() == key:
                vals.append(struct.unpack_from("<d", p, o + 16)[0])
    if not vals:
        return "nan"
    v = sum(vals) if how == "sum" else max(vals) if how == "max" else sum(vals) / len(vals)
    return "%.6g" % v


def steps(label, path):
    w = csv.writer(sys.stdout)
    for r in csv.DictReader(open(path)):
        if r["step"] in ("0", "") or r["method"] in ("factor", "refine", "cut"):
            continue
        w.writerow([label, r["step"], r["method"]] + [r.get(k, "") for k in STEP_COLS])


def per_method(path, label):
    rows = [r for r in csv.DictReader(open(path)) if r["label"] == label]
    out = csv.writer(sys.stdout)
    for m in sorted(set(r["method"] for r in rows), key=lambda m: [r["method"] for r in rows].index(m)):
        rs = [r for r in rows if r["method"] == m]

        def mx(k):
            v = [float(r[k]) for r in rs if r.get(k) not in (None, "", "nan")]
            return "%.4g" % max(v) if v else ""
        out.writerow([label, m, len(rs), mx("n"), mx("iters"), mx("time_ms"), mx("cond"), mx("cond_k"), mx("err_chol"),
                      mx("relres"), min(int(float(r["converged"] or 0)) for r in rs)])


def main():
    a = sys.argv[1:]
    if not a:
        raise SystemExit(__doc__)
    if a[0] == "kirigami":
        kirigami(a[1])
    elif a[0] == "kv":
        print(kv(*a[1:]))
    elif a[0] == "steps":
        steps(a[1], a[2])
    elif a[0] == "per_method":
        per_method(a[1], a[2])
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main()
