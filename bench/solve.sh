#!/bin/sh
# solve-aug bench (AMPS figs 6-8, table 3; paper 000 figs 4-7, 9-11): per scene a
# planar cut of STEPS steps solved by every method in one run; per step time,
# residual, closure sizes and GMRES iterations (bench/out/solve_SCENE.csv), a
# summary of medians and ratios (bench/out/solve_summary.csv) against one full
# CHOLMOD solve of the same factor, timed by solve-aug next to every step
# (--time-full: the ratio is taken under the same machine load), PNG plots.
# SCENES / STEPS / METHODS may be set in the environment; QUICK=1 runs brick_n8 only.
cd "$(dirname "$0")/.." || exit 2
B=bin; S=build/scenes; O=bench/out; mkdir -p $O
if [ "${QUICK:-0}" = 1 ]; then SCENES=${SCENES:-brick_n8}; STEPS=${STEPS:-16}; fi
STEPS=${STEPS:-64}
METHODS=${METHODS:-amps,gmres,refactor,rowupdate,pcg}
SCENES=${SCENES:-"beam_h64 beam_h256 beam_h1024 brick_n8 brick_n12 brick_n16 brick_n20"}
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
echo "scene,n,method,steps,median_ms,rate_hz,ratio_full_solve,amps_speedup,max_relres,median_iters,max_closure,converged" > $O/solve_summary.csv
for sc in $SCENES; do
    [ -f $S/$sc.msh ] || { echo "solve.sh: $S/$sc.msh missing, skipped" >&2; continue; }
    case $sc in beam*) load="tip:0,1e-3,0";; *) load="top:0,0,-1";; esac
    case $sc in beam*) plane="0,1,0,2";; *) plane="1,0,0,0.5";; esac
    # the papers' experiment: one node duplicated per step, the cut entering at
    # the free end (top) and advancing towards the fixed face
    steps=$STEPS; maxit=20000
    case $sc in beam_h1024) steps=$((STEPS < 16 ? STEPS : 16)); maxit=2000;; esac
    [ -f build/scenes/$sc.msh ] || make -s build/scenes/$sc.msh > /dev/null
    $B/meshload $S/$sc.msh --fix fixed --load $load | $B/factor --no-cond > $O/.f.aug || { echo "solve.sh: $sc: factor failed" >&2; continue; }
    $B/cut --plane $plane --advance 0,0,-1 --per-step 1 --steps $steps --pull 0.1 < $O/.f.aug > $O/.c.aug || { echo "solve.sh: $sc: cut failed" >&2; continue; }
    $B/solve-aug --method $METHODS --tol 1e-8 --maxit $maxit --on-singular report --time-full < $O/.c.aug 2>$O/solve_$sc.err |
        $B/stats --csv > $O/solve_$sc.csv || { echo "solve.sh: $sc: solve-aug failed" >&2; continue; }
    # AMPS alone (a scene runs one method: its memo and S2 stay in cache, as
    # they do not between the baselines' steps above), and AMPS with
    # background re-factorization (paper 000 sec. 3.6), each against the full
    # solve timed next to its own steps
    $B/solve-aug --method amps --time-full < $O/.c.aug 2>>$O/solve_$sc.err | $B/stats --csv |
        sed '2,$ s/,amps,/,amps_alone,/' > $O/solve_${sc}_alone.csv
    $B/solve-aug --method amps --background --time-full < $O/.c.aug 2>>$O/solve_$sc.err | $B/stats --csv |
        sed '2,$ s/,amps,/,amps_bg,/' > $O/solve_${sc}_bg.csv
    python3 - $O/solve_$sc.csv $sc $O/solve_summary.csv $O/solve_${sc}_alone.csv $O/solve_${sc}_bg.csv <<'PY'
import csv, statistics, sys, math
rows = list(csv.DictReader(open(sys.argv[1])))
for extra in sys.argv[4:]:
    try: rows += [r for r in csv.DictReader(open(extra)) if r["method"] in ("amps_alone", "amps_bg")]
    except OSError: pass
sc, out = sys.argv[2], open(sys.argv[3], "a")
n = next((r["n"] for r in rows if r["method"] == "factor"), "")
def f(r, k):
    try: return float(r[k])
    except (KeyError, ValueError): return float("nan")
by = {}
for r in rows:
    if r["method"] != "factor": by.setdefault(r["method"], []).append(r)
med = {m: statistics.median([f(r, "time_ms") for r in rs]) for m, rs in by.items()}
for m, rs in by.items():
    # one full CHOLMOD solve with the same factor, timed next to every step of
    # this method's run
    full = [f(r, "full_solve_ms") for r in rs if r.get("full_solve_ms")]
    full = statistics.median(full) if full else float("nan")
    it = [f(r, "iters") for r in rs]
    cl = [v for r in rs for v in (f(r, "closure_v"), f(r, "closure_j")) if not math.isnan(v)]
    rr = [f(r, "relres") for r in rs]
    # max_relres over every step; converged: steps that met their tolerance
    # (iterative methods) or were not singular (direct ones)
    conv = sum(1 for r in rs if r.get("converged") == "1")
    out.write("%s,%s,%s,%d,%.4g,%.4g,%.4g,%.4g,%.3g,%s,%s,%d\n" % (sc, n, m, len(rs), med[m], 1e3 / med[m],
              med[m] / full, med[m] / med.get("amps", float("nan")), max(rr),
              statistics.median(it), int(max(cl)) if cl else "", conv))
PY
    if command -v gnuplot > /dev/null; then
        for m in $(echo $METHODS,amps_alone,amps_bg | tr , ' '); do
            awk -F, -v m=$m 'FNR == 1 { delete c; for (i = 1; i <= NF; i++) c[$i] = i; next }
                $c["method"] == m { print $c["step"], 1000 / $c["time_ms"], $c["relres"], $c["iters"] }' \
                $O/solve_$sc.csv $O/solve_${sc}_alone.csv $O/solve_${sc}_bg.csv > $O/.solve_$sc.$m.dat
        done
        awk -F, 'FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            $c["method"] == "amps" { print $c["step"], $c["reach"], $c["memo"], $c["schur"], $c["solve"], $c["full_solve_ms"] }' \
            $O/solve_$sc.csv > $O/.solve_$sc.phases.dat
        plots=""; rplots=""
        for m in $(echo $METHODS,amps_alone,amps_bg | tr , ' '); do
            plots="$plots${plots:+, }'$O/.solve_$sc.$m.dat' using 1:2 with linespoints title '$m'"
            rplots="$rplots${rplots:+, }'$O/.solve_$sc.$m.dat' using 1:3 with linespoints title '$m'"
        done
        gnuplot <<GP
set terminal png size 800,500 noenhanced
set output '$O/solve_${sc}_rate.png'
set title 'update rate per cut step, $sc'; set xlabel 'cut step'; set ylabel 'Hz'; set logscale y
plot $plots
set output '$O/solve_${sc}_phases.png'
set title 'AMPS time per phase, $sc'; set ylabel 'ms'; unset logscale y; set key top left
plot '$O/.solve_$sc.phases.dat' using 1:2 with lines title 'reach (V columns)', \\
     '' using 1:3 with lines title 'memo (H''K^-1H)', '' using 1:4 with lines title 'schur (S2)', \\
     '' using 1:5 with lines title 'solve (back-substitution)', '' using 1:6 with lines title 'one full CHOLMOD solve'
set logscale y; set key default
set output '$O/solve_${sc}_relres.png'
set title 'relative residual per cut step, $sc'; set ylabel '||K a - f|| / ||f||'
plot $rplots
GP
    fi
done
rm -f $O/.f.aug $O/.c.aug $O/.solve_*.dat
column -s, -t < $O/solve_summary.csv
