#!/bin/sh
# The deformation experiments (issue 10; AMPS paper fig. 4, paper 000 figs.
# 5-6): update rate against the number of constrained nodes, on beam h=256
# and brick N=16 (and an organ mesh of ../shared/meshes when present), for
# amps, gmres, refactor (CHOLMOD re-factorization: cholmod_analyze, and so the
# ordering, only when the pattern changes, i.e. at the first step; numeric
# factorization every step) and pcg (Jacobi, --tol 1e-8), all on the same
# steps of one solve-aug run, against one full CHOLMOD solve of the same
# factor timed next to every step (--time-full).
#  - drag: for each size a box growing on the free end (bench/deform_boxes.py:
#    TARGETS nodes, rounded up to what a box holds), dragged by cut --steps
#    STEPS --drag BOX:d (u = (t/N) d, d 1% of the length, transverse), no cut:
#    the median update rate per method against the box's node count.
#  - progressive (the papers' figures): one run of PSTEPS steps, step t
#    constraining a box of about t PMAX / PSTEPS nodes to d (cut --constrain
#    BOX=d@t): the rate per step against the nodes constrained so far.
# Writes bench/out/deform.csv (per step), deform_summary.csv (per scene, size
# (drag: the box's nodes; progressive: the steps), method: median ms, rate, the first step's ms, ratios to the full solve and
# to amps, max relres, steps converged, refactor's analyses), deform.png,
# deform_progressive.png.
# Env: SCENES ("beam_h256 brick_n16"), TARGETS ("8 32 128 512 2048"), STEPS
# (16), PSTEPS (32), PMAX (1024), METHODS (amps,gmres,refactor,pcg), MESHES
# (../shared/meshes), ORGAN (liver_sofa_mor_4293n; "" for none); QUICK=1: a
# tiny run (brick_n4 beam_h16, 3 steps, small boxes, the 181-node liver).
cd "$(dirname "$0")/.." || exit 2
if [ "${QUICK:-0}" = 1 ]; then
    SCENES=${SCENES:-"brick_n4 beam_h16"}; TARGETS=${TARGETS:-"4 32"}; STEPS=${STEPS:-3}
    PSTEPS=${PSTEPS:-3}; PMAX=${PMAX:-30}; ORGAN=${ORGAN-liver_sofa_181n}
fi
SCENES=${SCENES:-"beam_h256 brick_n16"}
TARGETS=${TARGETS:-"8 32 128 512 2048"}
STEPS=${STEPS:-16}; PSTEPS=${PSTEPS:-32}; PMAX=${PMAX:-1024}
METHODS=${METHODS:-amps,gmres,refactor,pcg}
MESHES=${MESHES:-../shared/meshes}; ORGAN=${ORGAN-liver_sofa_mor_4293n}
OUT=bench/out; TMP=build/bench/deform; mkdir -p $OUT $TMP
for t in meshload factor cut solve-aug stats; do
    [ -x bin/$t ] || { echo "deform.sh: bin/$t missing (make first)" >&2; exit 1; }
done
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
CSV=$OUT/deform.csv; SUM=$OUT/deform_summary.csv
echo "scene,experiment,size,step,constrained,method,time_ms,relres,iters,m,full_solve_ms,converged,analyzed" > $CSV

# solve NAME EXPERIMENT SIZE CUT_STREAM: every method on its steps, rows into $CSV
solve() {
    maxit=20000
    bin/solve-aug --method $METHODS --tol 1e-8 --maxit $maxit --on-singular report --time-full \
        < $4 2>> $TMP/$1.err | bin/stats --csv > $TMP/s.csv || { echo "deform.sh: $1 $2 $3: solve-aug failed" >&2; return 1; }
    python3 bench/aug_kv.py $4 | awk '$1 == "sTAt" && $3 == "cut" && $4 == "nfix" { print $2, $5 }' > $TMP/nfix
    python3 - $TMP/s.csv $TMP/nfix $1 $2 $3 $DIM >> $CSV <<'PY'
import csv, sys
rows = csv.DictReader(open(sys.argv[1]))
nfix = dict(l.split() for l in open(sys.argv[2]))
sc, ex, size, dim = sys.argv[3], sys.argv[4], sys.argv[5], int(sys.argv[6])
# nodes constrained at each step: a drag's box from the first step on; in the
# progressive run the new constraints of the steps so far (all components of
# a node at once, never changed again: nfix / dim per step)
done, steps = 0, {}
for s in sorted(nfix, key=int):
    done += float(nfix[s]) / dim
    steps[s] = int(size) if ex == "drag" else int(done)
for r in rows:
    if r["method"] in ("factor", "cut"): continue  # factor's step 0, cut --stats' own rows
    print("%s,%s,%s,%s,%d,%s,%s,%s,%s,%s,%s,%s,%s" % (sc, ex, size, r["step"], steps.get(r["step"], 0), r["method"],
          r["time_ms"], r["relres"], r.get("iters", ""), r["m"], r.get("full_solve_ms", ""), r.get("converged", ""),
          r.get("analyzed", "")))
PY
}

# scene NAME MSH FIX: the drag sizes and the progressive run
scene() {
    name=$1; msh=$2; fix=$3
    bin/meshload $msh --fix $fix > $TMP/m.aug || { echo "deform.sh: $name: meshload failed" >&2; return; }
    bin/factor --no-cond < $TMP/m.aug > $TMP/f.aug || { echo "deform.sh: $name: factor failed" >&2; return; }
    DIM=$(bin/stats --dump $TMP/m.aug | awk '/ NODE /{p = 1} p && $1 == "dim" { print $2; exit }')
    : > $TMP/$name.err
    python3 bench/deform_boxes.py drag $TMP/m.aug $TARGETS > $TMP/boxes
    while read n box d; do
        bin/cut --steps $STEPS --drag "$box:$d" --stats < $TMP/f.aug > $TMP/c.aug ||
            { echo "deform.sh: $name: cut --drag ($n nodes) failed" >&2; continue; }
        solve $name drag $n $TMP/c.aug
        echo "deform.sh: $name: drag of $n nodes done" >&2
    done < $TMP/boxes
    t=1; cons=""
    while [ $t -le $PSTEPS ]; do
        want=$(( (t * PMAX + PSTEPS - 1) / PSTEPS ))
        line=$(python3 bench/deform_boxes.py drag $TMP/m.aug $want)
        [ -n "$line" ] || break
        set -- $line
        cons="$cons --constrain $2=$3@$t"
        t=$((t + 1))
    done
    p=$((t - 1))
    [ $p -ge 1 ] || return
    bin/cut --steps $p $cons --stats < $TMP/f.aug > $TMP/c.aug ||
        { echo "deform.sh: $name: progressive cut failed" >&2; return; }
    solve $name progressive $p $TMP/c.aug
    echo "deform.sh: $name: progressive ($p steps) done" >&2
}

for sc in $SCENES; do
    [ -f build/scenes/$sc.msh ] || make --no-print-directory -s build/scenes/$sc.msh > /dev/null ||
        { echo "deform.sh: cannot make build/scenes/$sc.msh" >&2; continue; }
    scene $sc build/scenes/$sc.msh fixed
done
if [ -n "$ORGAN" ] && [ -f "$MESHES/$ORGAN.msh" ]; then
    bin/meshload "$MESHES/$ORGAN.msh" > $TMP/o.aug && fix=$(python3 bench/deform_boxes.py fix $TMP/o.aug) &&
        scene $ORGAN "$MESHES/$ORGAN.msh" "$fix"
else
    echo "deform.sh: no organ mesh ($MESHES/$ORGAN.msh), row skipped" >&2
fi

python3 - $CSV $SUM <<'PY'
import csv, math, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
out = open(sys.argv[2], "w")
out.write("scene,experiment,size,method,steps,median_ms,rate_hz,first_ms,ratio_full_solve,amps_speedup,max_relres,"
          "converged,analyses\n")
def f(r, k):
    try: return float(r[k])
    except (KeyError, ValueError): return float("nan")
runs = {}
for r in rows:
    runs.setdefault((r["scene"], r["experiment"], r["size"]), {}).setdefault(r["method"], []).append(r)
for (sc, ex, size), by in runs.items():
    med = {m: statistics.median(f(r, "time_ms") for r in rs) for m, rs in by.items()}
    for m, rs in by.items():
        full = statistics.median(f(r, "full_solve_ms") for r in rs)
        an = sum(r["analyzed"] == "1" for r in rs)
        out.write("%s,%s,%s,%s,%d,%.4g,%.4g,%.4g,%.4g,%.4g,%.3g,%d,%s\n" % (sc, ex, size, m, len(rs), med[m], 1e3 / med[m],
                  f(rs[0], "time_ms"), med[m] / full, med[m] / med.get("amps", float("nan")),
                  max(f(r, "relres") for r in rs), sum(r["converged"] == "1" for r in rs), an if m == "refactor" else ""))
PY
column -s, -t < $SUM
command -v gnuplot > /dev/null || { echo "deform.sh: gnuplot not found, no plot" >&2; exit 0; }
# one panel per scene, one line per method
dplot=""; pplot=""; ns=0
for sc in $SCENES $ORGAN; do
    dl=""; pl=""
    for m in $(echo $METHODS | tr , ' '); do
        awk -F, -v s=$sc -v m=$m '$1 == s && $2 == "drag" && $4 == m { print $3, $7 }' $SUM | sort -g > $TMP/.d.$sc.$m.dat
        awk -F, -v s=$sc -v m=$m '$1 == s && $2 == "progressive" && $6 == m && $7 > 0 { print $5, 1000 / $7 }' $CSV > $TMP/.p.$sc.$m.dat
        [ -s $TMP/.d.$sc.$m.dat ] && dl="$dl${dl:+, }'$TMP/.d.$sc.$m.dat' using 1:2 with linespoints title '$m'"
        [ -s $TMP/.p.$sc.$m.dat ] && pl="$pl${pl:+, }'$TMP/.p.$sc.$m.dat' using 1:2 with linespoints title '$m'"
    done
    [ -n "$dl" ] || continue
    ns=$((ns + 1))
    dplot="$dplot
set title '$sc'; plot $dl"
    [ -n "$pl" ] && pplot="$pplot
set title '$sc'; plot $pl"
done
[ $ns -gt 0 ] && gnuplot <<GP
set terminal png size $((420 * ns + 60)),480 noenhanced
set output '$OUT/deform.png'
set multiplot layout 1,$ns title 'drag without a cut ($STEPS steps): median update rate against the dragged nodes'
set xlabel 'constrained (dragged) nodes'; set ylabel 'Hz'; set logscale xy; set key bottom left
$dplot
unset multiplot
set output '$OUT/deform_progressive.png'
set multiplot layout 1,$ns title 'constraints added step by step (AMPS fig. 4, paper 000 fig. 5): update rate per step'
set xlabel 'constrained nodes'; set logscale y; unset logscale x
$pplot
unset multiplot
GP
rm -f $TMP/.d.*.dat $TMP/.p.*.dat $TMP/c.aug $TMP/f.aug
