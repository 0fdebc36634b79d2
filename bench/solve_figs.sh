#!/bin/sh
# The remaining solve-aug figures (run after solve.sh, which writes
# bench/out/solve_summary.csv):
#  - closure sizes against the number of DOFs (AMPS fig. 8 / paper 000 fig. 9):
#    the largest closure of H in L (amps) and of struct(J) (gmres) per scene,
#    bench/out/solve_closure.png;
#  - GMRES iterations per cut step for each preconditioner (paper 000 figs.
#    5-7): none, D and the tridiagonal SPAI on the same steps,
#    bench/out/solve_gmres_prec.csv and .png.
# SCENE (default brick_n12) and STEPS (default 32) may be set.
cd "$(dirname "$0")/.." || exit 2
B=bin; S=build/scenes; O=bench/out; mkdir -p $O
SCENE=${SCENE:-brick_n12}; STEPS=${STEPS:-32}
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
if [ -f $O/solve_summary.csv ] && command -v gnuplot > /dev/null; then
    for m in amps gmres; do
        for kind in beam brick; do
            awk -F, -v m=$m -v k=$kind 'NR > 1 && $3 == m && index($1, k) == 1 && $11 != "" { print $2, $11 }' \
                $O/solve_summary.csv > $O/.clos.$m.$kind.dat
        done
    done
    gnuplot <<GP
set terminal png size 800,500 noenhanced
set output '$O/solve_closure.png'
set title 'largest closure against the number of DOFs (64 cut steps)'
set xlabel 'DOFs n'; set ylabel 'closure size (rows)'; set logscale xy; set key top left
plot '$O/.clos.amps.brick.dat' with linespoints title 'amps, closure of H in L (bricks)', \
     '$O/.clos.amps.beam.dat' with linespoints title 'amps, closure of H in L (beams)', \
     '$O/.clos.gmres.brick.dat' with linespoints title 'gmres, closure of struct(J) (bricks)', \
     '$O/.clos.gmres.beam.dat' with linespoints title 'gmres, closure of struct(J) (beams)'
GP
    rm -f $O/.clos.*.dat
fi
[ -f $S/$SCENE.msh ] || make -s $S/$SCENE.msh > /dev/null
case $SCENE in beam*) load="tip:0,1e-3,0"; plane="0,1,0,2";; *) load="top:0,0,-1"; plane="1,0,0,0.5";; esac
$B/meshload $S/$SCENE.msh --fix fixed --load $load | $B/factor --no-cond |
    $B/cut --plane $plane --advance 0,0,-1 --per-step 1 --steps $STEPS --pull 0.1 > $O/.g.aug ||
    { echo "solve_figs.sh: $SCENE: pipeline failed" >&2; exit 1; }
echo "step,prec,iters,converged,relres,time_ms" > $O/solve_gmres_prec.csv
for p in none D spai; do
    $B/solve-aug --method gmres --gmres-prec $p --tol 1e-8 --on-singular report < $O/.g.aug 2>/dev/null |
        $B/stats --csv | awk -F, -v p=$p 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            $c["method"] == "gmres" { print $c["step"] "," p "," $c["iters"] "," $c["converged"] "," $c["relres"] "," $c["time_ms"] }' \
        >> $O/solve_gmres_prec.csv
done
rm -f $O/.g.aug
if command -v gnuplot > /dev/null; then
    for p in none D spai; do
        awk -F, -v p=$p '$2 == p { print $1, $3 }' $O/solve_gmres_prec.csv > $O/.gp.$p.dat
    done
    gnuplot <<GP
set terminal png size 800,500 noenhanced
set output '$O/solve_gmres_prec.png'
set title 'GMRES iterations per cut step to relres 1e-8, $SCENE'
set xlabel 'cut step'; set ylabel 'iterations'; set key top left
plot '$O/.gp.none.dat' with linespoints title 'no preconditioner', \
     '$O/.gp.D.dat' with linespoints title 'D (diagonal of the factor)', \
     '$O/.gp.spai.dat' with linespoints title 'tridiagonal SPAI'
GP
    rm -f $O/.gp.*.dat
fi
python3 - $O/solve_gmres_prec.csv <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("GMRES on the same steps, per preconditioner (median iterations, time; steps converged):")
for p in ("none", "D", "spai"):
    rs = [r for r in rows if r["prec"] == p]
    if not rs: continue
    print("  %-5s %8.1f its %9.2f ms  %d/%d converged" % (p, statistics.median(float(r["iters"]) for r in rs),
          statistics.median(float(r["time_ms"]) for r in rs), sum(r["converged"] == "1" for r in rs), len(rs)))
PY
