"""Helpers of bench/organs.sh.
  organs_tools.py box MSH
      "x0 y0 z0 x1 y1 z1": the bounding box of the nodes of a gmsh MSH 4.1 file
  organs_tools.py summary SCENE KIND OUT CSV...
      per method of the stats --csv files (one solve-aug run each, the method
      renamed by the file's suffix _NAME.csv): steps, median step, median full
      solve timed next to it, their ratio, the ratio to the best fixed method
      (every method but auto) and to auto, the total over the steps and its
      ratio to the best fixed method's total (total_over_best: on auto's row
      the goal of issue 15, <= 1.1), max and median relres and max relres
      over refactor's, steps refined, auto's re-factorizations and
      background swaps; rows appended to OUT (header when OUT is empty). A
      step is a row of solve-aug's method (the stream's other records, e.g.
      refine's per-step rows, are not steps).
  organs_tools.py median_run OUT CSV...
      copies to OUT the run (stats --csv of one solve-aug run) whose total
      time over its steps is the median of the runs given (the repeated
      rounds of organs.sh)."""
import csv
import shutil, math, os, statistics, sys

COLS = ("scene,kind,n,method,steps,median_ms,full_solve_ms,ratio_full,ratio_best_fixed,ratio_auto,"
        "total_ms,total_over_best,max_relres,median_relres,relres_over_refactor,refined_steps,refactor_steps,"
        "swaps")
# the methods of solve-aug (sTAt tags of its per-step rows)
SOLVE = ("auto", "amps", "gmres", "refactor", "rowupdate", "pcg", "cgm-cov", "cgm-es", "cgm-log", "cgm-as")


def box(path):
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    with open(path) as f:
        for line in f:
            if line.startswith("$Nodes"):
                break
        nblocks = int(f.readline().split()[0])
        for _ in range(nblocks):
            _, _, param, cnt = map(int, f.readline().split())
            for _ in range(cnt):
                f.readline()
            for _ in range(cnt):
                p = list(map(float, f.readline().split()[:3]))
                for d in range(3):
                    lo[d], hi[d] = min(lo[d], p[d]), max(hi[d], p[d])
    print(" ".join("%.9g" % v for v in lo + hi))


def num(r, k):
    try:
        return float(r.get(k, ""))
    except ValueError:
        return math.nan


def summary(scene, kind, out, files):
    runs = {}
    n = ""
    for path in files:
        name = os.path.basename(path)[:-4].rsplit("_", 1)[-1]
        rows = list(csv.DictReader(open(path)))
        for r in rows:
            if r["method"] == "factor" and not n:
                n = r.get("n", "")
        rs = [r for r in rows if r["method"] in SOLVE]
        if rs:
            runs[name] = rs
    med = {m: statistics.median(num(r, "time_ms") for r in rs) for m, rs in runs.items()}
    tot = {m: sum(num(r, "time_ms") for r in rs) for m, rs in runs.items()}
    fixed = [v for m, v in med.items() if not m.startswith("auto")]
    best = min(fixed) if fixed else math.nan
    tfixed = [v for m, v in tot.items() if not m.startswith("auto")]
    tbest = min(tfixed) if tfixed else math.nan
    rref = max((num(r, "relres") for r in runs.get("refactor", [])), default=math.nan)
    new = not os.path.exists(out) or os.path.getsize(out) == 0
    with open(out, "a") as f:
        if new:
            f.write(COLS + "\n")
        for m, rs in runs.items():
            full = [num(r, "full_solve_ms") for r in rs if not math.isnan(num(r, "full_solve_ms"))]
            full = statistics.median(full) if full else math.nan
            rr = [num(r, "relres") for r in rs if not math.isnan(num(r, "relres"))]
            mx = max(rr) if rr else math.nan
            refined = sum(1 for r in rs if num(r, "refine") > 0)
            refac = sum(1 for r in rs if num(r, "choice") == 1)
            swaps = sum(1 for r in rs if num(r, "swapped") == 1)
            f.write("%s,%s,%s,%s,%d,%.4g,%.4g,%.4g,%.4g,%.4g,%.5g,%.4g,%.3g,%.3g,%.3g,%d,%d,%d\n" % (
                scene, kind, n, m, len(rs), med[m], full, med[m] / full if full else math.nan,
                med[m] / best, med[m] / med["auto"] if "auto" in med else math.nan,
                tot[m], tot[m] / tbest, mx,
                statistics.median(rr) if rr else math.nan, mx / rref if rref > 0 else math.nan,
                refined, refac, swaps))


def median_run(out, files):
    """copy to out the run (a stats --csv file) whose total time over its
    solve rows is the median of the runs (the lower middle of an even count)"""
    def total(path):
        return sum(num(r, "time_ms") for r in csv.DictReader(open(path)) if r["method"] in SOLVE)
    ranked = sorted(files, key=lambda f: (total(f), f))
    shutil.copyfile(ranked[(len(ranked) - 1) // 2], out)


def main():
    if len(sys.argv) >= 4 and sys.argv[1] == "median_run":
        median_run(sys.argv[2], sys.argv[3:])
    elif len(sys.argv) >= 3 and sys.argv[1] == "box":
        box(sys.argv[2])
    elif len(sys.argv) >= 6 and sys.argv[1] == "summary":
        summary(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:])
    else:
        sys.exit(__doc__)


main()
