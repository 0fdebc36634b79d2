#!/bin/sh
# cut: time per cut step and update sizes (m, k) for the papers' advancing
# planar cut (issue 4, "Bench") on brick N = 16 (plane x = 0.5) and beam
# h = 256 (plane x = 2, along the beam), 32 steps at the default nodes per
# step (and at one node per step, the papers' experiment: *_1), against one full CHOLMOD solve of the same mesh measured in the same
# run (factor's step-0 solve, tIMe solve_ms). Goal: a cut step < 10% of a
# solve. Medians over REPS runs of every step (tIMe time_ms: the step's
# geometry, separation, detached-piece check and UPDT, without writing).
# Writes bench/out/cut.csv (per step), bench/out/cut_summary.csv, bench/out/cut.png.
# Env: REPS (default 3), STEPS (32).
cd "$(dirname "$0")/.." || exit 2
REPS=${REPS:-3}
STEPS=${STEPS:-32}
OUT=bench/out; TMP=build/bench/cut
mkdir -p $OUT $TMP
CSV=$OUT/cut.csv; SUM=$OUT/cut_summary.csv
for t in meshload factor cut; do
    [ -x bin/$t ] || { echo "cut.sh: bin/$t missing (make first)" >&2; exit 1; }
done
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
pct() { sort -g | awk -v p=$1 '{v[NR] = $1} END {i = int(p * NR + 0.999); if (i < 1) i = 1; print v[i]}'; }

echo "mesh,rep,step,time_ms,m,k,nnew,nmod" > $CSV
echo "mesh,nodes,steps,per_step_nodes,median_step_ms,p90_step_ms,median_m,max_m,k,solve_ms,step_over_solve,goal_lt_0.10" > $SUM
run() { # name, scene, plane, extra cut options
    name=$1; msh=build/scenes/$2.msh; plane=$3; extra=${4:-}
    make --no-print-directory -s $msh > /dev/null || { echo "cut.sh: cannot make $msh" >&2; exit 1; }
    bin/meshload $msh --fix fixed > $TMP/$name.aug || exit 1
    : > $TMP/solve_ms
    i=1
    while [ $i -le "$REPS" ]; do
        bin/factor --threads 1 --no-cond --no-factor $TMP/$name.aug > $TMP/f.aug || exit 1
        python3 bench/aug_kv.py $TMP/f.aug | awk '$1 == "tIMe" && $4 == "solve_ms" { print $5 }' >> $TMP/solve_ms
        bin/cut $TMP/$name.aug --plane $plane --steps $STEPS --stats $extra > $TMP/c.aug || exit 1
        python3 bench/aug_kv.py $TMP/c.aug | awk -v n=$name -v r=$i '
            $3 == "cut" { v[$2, $4] = $5; if ($2 > s) s = $2 }
            END { for (t = 1; t <= s; t++) printf "%s,%d,%d,%s,%s,%s,%s,%s\n", n, r, t, v[t, "time_ms"], v[t, "m"], v[t, "k"], v[t, "nnew"], v[t, "nmod"] }' >> $CSV
        i=$((i + 1))
    done
    nodes=$(python3 bench/aug_kv.py $TMP/$name.aug | awk '$1 == "NODE" { print $5 }')
    sol=$(median < $TMP/solve_ms)
    grep "^$name," $CSV | cut -d, -f4 > $TMP/t
    grep "^$name," $CSV | cut -d, -f5 > $TMP/m
    med=$(median < $TMP/t); p90=$(pct 0.9 < $TMP/t)
    mm=$(median < $TMP/m); mx=$(sort -g $TMP/m | tail -1)
    k=$(grep "^$name," $CSV | cut -d, -f6 | median)
    awk -v n=$name -v nn=$nodes -v st=$STEPS -v k=$k -v med=$med -v p90=$p90 -v mm=$mm -v mx=$mx -v sol=$sol 'BEGIN {
        r = med / sol; printf "%s,%s,%s,%d,%.4f,%.4f,%s,%s,%s,%.4f,%.4f,%s\n", n, nn, st, k / 3, med, p90, mm, mx, k, sol, r, r < 0.10 ? "yes" : "no" }' >> $SUM
    echo "$name done" >&2
}
run brick_n16 brick_n16 1,0,0,0.5
run beam_h256 beam_h256 1,0,0,2
# the papers' experiment: one node duplicated per step
run brick_n16_1 brick_n16 1,0,0,0.5 "--per-step 1"
run beam_h256_1 beam_h256 1,0,0,2 "--per-step 1"
column -s, -t < $SUM

if command -v gnuplot > /dev/null; then
    gnuplot <<GP
set terminal pngcairo size 1200,500
set output "$OUT/cut.png"
set datafile separator ","
set multiplot layout 1,2
set title "cut step time (all runs) vs 10% of a CHOLMOD solve"
set logscale y
set xlabel "cut step"
set ylabel "ms"
set key top left
b = system("awk -F, '\$1 == \"brick_n16\" { print \$10 * 0.1 }' $SUM")
h = system("awk -F, '\$1 == \"beam_h256\" { print \$10 * 0.1 }' $SUM")
plot "$CSV" using (strcol(1) eq "brick_n16" ? \$3 : 1/0):4 with points pt 7 title "brick N=16", \
     "$CSV" using (strcol(1) eq "beam_h256" ? \$3 : 1/0):4 with points pt 5 title "beam h=256", \
     b + 0 with lines lw 2 title "10% solve, brick", h + 0 with lines lw 2 dt 2 title "10% solve, beam"
unset logscale y
set title "update size per step"
set ylabel "DOFs"
plot "$CSV" using (strcol(1) eq "brick_n16" && \$2 == 1 ? \$3 : 1/0):5 with linespoints pt 7 title "m, brick", \
     "$CSV" using (strcol(1) eq "brick_n16" && \$2 == 1 ? \$3 : 1/0):6 with linespoints pt 6 title "k, brick", \
     "$CSV" using (strcol(1) eq "beam_h256" && \$2 == 1 ? \$3 : 1/0):5 with linespoints pt 5 title "m, beam", \
     "$CSV" using (strcol(1) eq "beam_h256" && \$2 == 1 ? \$3 : 1/0):6 with linespoints pt 4 title "k, beam"
unset multiplot
GP
fi
