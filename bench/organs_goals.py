"""The bench goals of issue 15, judged on the per-step CSVs of bench/organs.sh.
  organs_goals.py DIR [OUT.csv]
Reads DIR/organs_SCENE_KIND_METHOD.csv (one solve-aug run each, every step
timed next to one full solve of the same factor, --time-full) and prints one
row per goal and scene: what was measured, the target, met or not. Ratios
come from one run; medians over the steps. Goals (issue 15, "Bench goals"):
  default_vs_full   organ meshes, one-node steps: auto's median step <= 1.0x
                    the median full solve timed next to it
  relres_10x        organ meshes: on every step auto's relres <= 10x
                    refactor's on the same step
  refined_10pct     organ meshes: auto refined (full solves) on < 10% of steps
  rate_2threads     brain: amps with --threads 2 (DIR/par_summary.csv of
                    bench/par_threads.sh) at >= 20 full-field updates per
                    second (1000 / median step)
  threads2_faster   organ meshes (par_summary.csv): the median step with
                    --threads 2 below the one with --threads 1
  beam_amps_2x      beam h=256 (both splits): rowupdate's median / amps's >= 2,
                    amps's relres <= 10x refactor's on every step
  auto_1p1          every scene and kind: auto's total time <= 1.1x the best
                    fixed method's total (amps, amps --background, refactor,
                    rowupdate, pcg: every run but auto*); shown beside it,
                    not judged: the same ratio with each run's total in
                    units of that run's median full solve
  auto_1p1_online   the same for autoon (auto --horizon 0: the online rule,
                    the stream's length that cut's pLAN gives auto ignored)
  auto_1p1_bg       the same for autobg (auto --background: the second core
                    for background jobs, which amps --background has)
  amps_10x_refactor bricks N=16/20 and the organs: refactor's median / amps's
                    >= 10
A goal without the runs it needs is not reported (a QUICK run has no beam
h=256)."""
import csv, glob, math, os, statistics, sys

ORGANS = ("brain", "bunny", "liver", "sphere3")


def num(r, k):
    try:
        return float(r.get(k, ""))
    except (TypeError, ValueError):
        return math.nan


def load(d):
    runs = {}
    for path in sorted(glob.glob(os.path.join(d, "organs_*_*_*.csv"))):
        parts = os.path.basename(path)[len("organs_"):-4].split("_")
        if len(parts) < 3:
            continue
        scene, kind, method = "_".join(parts[:-2]), parts[-2], parts[-1]
        rows = [r for r in csv.DictReader(open(path)) if r.get("method") not in ("factor", "", None)]
        if rows:
            runs[(scene, kind, method)] = rows
    return runs


def med(rows, k):
    v = [num(r, k) for r in rows if not math.isnan(num(r, k))]
    return statistics.median(v) if v else math.nan


def total(rows):
    return sum(num(r, "time_ms") for r in rows if not math.isnan(num(r, "time_ms")))


def worst_relres_ratio(rows, ref):
    rr = {r["step"]: num(r, "relres") for r in ref}
    q = [num(r, "relres") / rr[r["step"]] for r in rows if r["step"] in rr and rr[r["step"]] > 0]
    return max(q) if q else math.nan


def goals(runs):
    out = []

    def add(goal, scene, kind, measured, target, ok):
        out.append((goal, scene, kind, measured, target, "yes" if ok else "NO"))

    keys = sorted({(s, k) for s, k, _ in runs})
    for s, k in keys:
        auto, amps = runs.get((s, k, "auto")), runs.get((s, k, "amps"))
        ref, row = runs.get((s, k, "refactor")), runs.get((s, k, "rowupdate"))
        if s in ORGANS and auto:
            if k == "one":
                r = med(auto, "time_ms") / med(auto, "full_solve_ms")
                add("default_vs_full", s, k, "%.3gx" % r, "<= 1.0x", r <= 1.0)
            if ref:
                w = worst_relres_ratio(auto, ref)
                add("relres_10x", s, k, "%.3gx" % w, "<= 10x", w <= 10)
            nref = sum(1 for r in auto if num(r, "refine") > 0)
            add("refined_10pct", s, k, "%d of %d" % (nref, len(auto)), "< 10%", nref < 0.1 * len(auto))
        if s.startswith("beam_h256") and amps and row:
            r = med(row, "time_ms") / med(amps, "time_ms")
            w = worst_relres_ratio(amps, ref) if ref else math.nan
            add("beam_amps_2x", s, k, "%.3gx, relres %.3gx" % (r, w), ">= 2x, <= 10x", r >= 2 and w <= 10)
        fixed = {m: total(rows) for (s2, k2, m), rows in runs.items()
                 if s2 == s and k2 == k and not m.startswith("auto")}
        for goal, name in (("auto_1p1", "auto"), ("auto_1p1_online", "autoon"), ("auto_1p1_bg", "autobg")):
            a = runs.get((s, k, name))
            if a and fixed:
                best = min(fixed, key=fixed.get)
                r = total(a) / fixed[best]
                # beside it, each total in its own run's median full solves
                # (the machine's speed moves 10-30% between runs; judged on r)
                nf = {m: fixed[m] / med(runs[(s, k, m)], "full_solve_ms") for m in fixed}
                rn = total(a) / med(a, "full_solve_ms") / min(nf.values())
                add(goal, s, k, "%.3gx (best %s; %.3gx in full solves)" % (r, best, rn), "<= 1.1x", r <= 1.1)
        if (s in ORGANS or s.startswith("brick_n16") or s.startswith("brick_n20")) and amps and ref:
            r = med(ref, "time_ms") / med(amps, "time_ms")
            add("amps_10x_refactor", s, k, "%.3gx" % r, ">= 10x", r >= 10)
    return out


def par_goals(path):
    out = []
    if not os.path.exists(path):
        return out
    rows = list(csv.DictReader(open(path)))
    for sc in sorted({r["scene"] for r in rows}):
        t = {r["threads"]: num(r, "median_step_ms") for r in rows if r["scene"] == sc}
        if "1" in t and "2" in t:
            out.append(("threads2_faster", sc, "one", "%.3g -> %.3g ms (%.2fx)" % (t["1"], t["2"], t["1"] / t["2"]),
                        "2 threads faster", "yes" if t["2"] < t["1"] else "NO"))
        if sc == "brain" and "2" in t:
            hz = 1000 / t["2"]
            out.append(("rate_2threads", sc, "one", "%.3g Hz" % hz, ">= 20 Hz", "yes" if hz >= 20 else "NO"))
    return out


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    rows = goals(load(sys.argv[1])) + par_goals(os.path.join(sys.argv[1], "par_summary.csv"))
    head = ("goal", "scene", "kind", "measured", "target", "met")
    if len(sys.argv) > 2:
        with open(sys.argv[2], "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(head)
            w.writerows(rows)
    wid = [max(len(str(r[i])) for r in rows + [head]) for i in range(len(head))]
    for r in [head] + rows:
        print("  ".join(str(v).ljust(wid[i]) for i, v in enumerate(r)).rstrip())
    met = sum(1 for r in rows if r[5] == "yes")
    print("%d of %d goals met" % (met, len(rows)))


main()
