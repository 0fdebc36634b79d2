#!/bin/sh
# blade: a curved scalpel stroke through brain + CSF (../shared/meshes, only
# when present; issue 13 "Bench"): cut --blade in STEPS steps, snap and split
# mode; per step the cut time (tIMe time_ms: geometry, surgery, separation,
# detached-piece check, UPDT) against one full CHOLMOD solve of K0 (factor's
# step-0 solve; goal: a step < 10% of it) and against the factorization,
# the update sizes m and k, the element quality of the cut mesh (and, split,
# after refine's 3-D pass on the STEPS-step cut, which refine follows with its
# look-ahead, and on the whole stroke cut in one step), and AMPS against
# refactor on the resulting steps (solve-aug --method amps,refactor, per step
# time_ms).
# Writes bench/out/blade.csv (per step), blade_solve.csv (per step and
# method), blade_summary.csv, blade.png.
# Env: MESHES (default ../shared/meshes), STEPS (64), SOLVE (1: AMPS and
# refactor; 0: skip).
cd "$(dirname "$0")/.." || exit 2
MESHES=${MESHES:-../shared/meshes}
STEPS=${STEPS:-64}
SOLVE=${SOLVE:-1}
OUT=bench/out; TMP=build/bench/blade
mkdir -p $OUT $TMP
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
f=$(ls $MESHES/brain_csf*.msh 2>/dev/null | head -1)
[ -n "$f" ] && [ -f "$f" ] || { echo "blade.sh: no brain_csf mesh in $MESHES, skipped" >&2; exit 0; }
for t in meshload factor cut refine solve-aug stats; do
    [ -x bin/$t ] || { echo "blade.sh: bin/$t missing (make first)" >&2; exit 1; }
done
CSV=$OUT/blade.csv; SOL=$OUT/blade_solve.csv; SUM=$OUT/blade_summary.csv
# fixed at the bottom slab; brain 3 kPa, CSF 1 kPa (as bench/modal.sh), gravity
box=$(bin/meshload "$f" | bin/stats | awk '$1 == "bounding" {
    gsub(/[\[\],]/, " "); print $4 - 1, $7 - 1, $10 - 1, $5 + 1, $8 + 1, $10 + 0.1 * ($11 - $10) }' | tr ' ' ',')
bin/meshload "$f" --fix box:$box --material brain:E=3000,nu=0.45,rho=1040 --material csf:E=1000,nu=0.45,rho=1000 \
    --gravity 0,0,-9.81 | bin/factor --threads 1 --no-cond > $TMP/f.aug || { echo "blade.sh: meshload | factor failed" >&2; exit 1; }
kv() { python3 bench/aug_kv.py "$1"; }
solve_ms=$(kv $TMP/f.aug | awk '$1 == "tIMe" && $4 == "solve_ms" { print $5 }')
factor_ms=$(kv $TMP/f.aug | awk '$1 == "tIMe" && $4 == "factor_ms" { print $5 }')
# the stroke: in from above the brain (z 74), down to z -30, bending forward in y
cat > $TMP/blade.txt <<'EOF'
blade -90 -30 80   90 -20 80
curve -90 -10 40   90 0 40
curve -90 30 10    90 35 10
blade -90 40 -30   90 45 -30
EOF
quality() { # stream -> aspect_mean,aspect_max,min_dihedral of the final mesh
    bin/stats "$1" | awk '/^quality \(final mesh/ { q = 1 } q && $1 == "aspect" { am = $6; ax = $8 } q && $1 == "min" && $2 == "dihedral" { print am "," ax "," $4; exit }'
}
echo "mode,step,time_ms,m,k,nnew,nmod,nadd,step_over_solve" > $CSV
echo "mode,step,method,time_ms" > $SOL
echo "mode,nodes,elements,steps,cut_steps,median_step_ms,max_step_ms,solve_ms,factor_ms,median_over_solve,goal_lt_0.10,median_m,max_m,total_k,aspect_mean,aspect_max,min_dihedral,amps_median_ms,refactor_median_ms" > $SUM
nodes=$(kv $TMP/f.aug | awk '$1 == "NODE" { print $5 }')
echo "input,$nodes,$(bin/stats $TMP/f.aug | awk '$1 == "elements" { print $2; exit }'),0,0,,,$solve_ms,$factor_ms,,,,,,$(bin/stats $TMP/f.aug | awk '/^quality/ { q = 1 } q && $1 == "aspect" { am = $6; ax = $8 } q && $1 == "min" && $2 == "dihedral" { print am "," ax "," $4; exit }'),," >> $SUM
for mode in snap split; do
    bin/cut $TMP/f.aug --blade $TMP/blade.txt --steps $STEPS --mode $mode --detached pin --stats > $TMP/c_$mode.aug \
        || { echo "blade.sh: cut --mode $mode failed" >&2; exit 1; }
    kv $TMP/c_$mode.aug | awk -v md=$mode -v sol=$solve_ms '
        $3 == "cut" { v[$2, $4] = $5; if ($2 > s) s = $2 }
        END { for (t = 1; t <= s; t++) printf "%s,%d,%s,%s,%s,%s,%s,%s,%.5f\n", md, t, v[t, "time_ms"], v[t, "m"], v[t, "k"],
              v[t, "nnew"], v[t, "nmod"], v[t, "nadd"], v[t, "time_ms"] / sol }' >> $CSV
    q=$(quality $TMP/c_$mode.aug)
    am=""; rm=""
    if [ "$SOLVE" = 1 ]; then
        bin/solve-aug --method amps,refactor --no-reactions $TMP/c_$mode.aug 2> $TMP/s.err | bin/stats --csv > $TMP/s_$mode.csv \
            || { echo "blade.sh: solve-aug ($mode) failed: $(cat $TMP/s.err)" >&2; exit 1; }
        awk -F, -v md=$mode 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            ($(c["method"]) == "amps" || $(c["method"]) == "refactor") && $(c["step"]) > 0 {
                print md "," $(c["step"]) "," $(c["method"]) "," $(c["time_ms"]) }' $TMP/s_$mode.csv >> $SOL
        am=$(awk -F, -v md=$mode '$1 == md && $3 == "amps" { print $4 }' $SOL | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }')
        rm=$(awk -F, -v md=$mode '$1 == md && $3 == "refactor" { print $4 }' $SOL | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }')
    fi
    ne=$(bin/stats $TMP/c_$mode.aug | awk '$1 == "final" && $2 == "mesh" { print $5 }')
    med() { sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
    tmed=$(awk -F, -v md=$mode '$1 == md && $5 > 0 { print $3 }' $CSV | med)
    mmed=$(awk -F, -v md=$mode '$1 == md && $5 > 0 { print $4 }' $CSV | med)
    awk -F, -v md=$mode -v nn=$nodes -v ne=$ne -v st=$STEPS -v sol=$solve_ms -v fac=$factor_ms -v q=$q -v am=$am -v rm=$rm \
        -v med=$tmed -v mm=$mmed '
        $1 == md && $5 > 0 { n++; k += $5; if ($3 > tx) tx = $3; if ($4 > mx) mx = $4 }
        END { printf "%s,%s,%s,%s,%d,%.4f,%.4f,%.3f,%.3f,%.5f,%s,%s,%s,%d,%s,%s,%s\n", md, nn, ne, st, n, med, tx, sol, fac,
                     med / sol, med / sol < 0.10 ? "yes" : "no", mm, mx, k, q, am, rm }' $CSV >> $SUM
    echo "blade.sh: $mode done" >&2
done
# split + refine: the whole stroke in one step, then refine's 3-D pass
bin/cut $TMP/f.aug --blade $TMP/blade.txt --steps 1 --mode split --detached pin | bin/refine > $TMP/r.aug \
    || { echo "blade.sh: split | refine failed" >&2; exit 1; }
q1=$(bin/cut $TMP/f.aug --blade $TMP/blade.txt --steps 1 --mode split --detached pin > $TMP/c1.aug && quality $TMP/c1.aug)
qr=$(quality $TMP/r.aug)
ner=$(bin/stats $TMP/r.aug | awk '$1 == "final" && $2 == "mesh" { print $5 }')
bin/refine $TMP/c_split.aug > $TMP/rs.aug || { echo "blade.sh: split ($STEPS steps) | refine failed" >&2; exit 1; }
echo "split+refine,$nodes,$(bin/stats $TMP/rs.aug | awk '$1 == "final" && $2 == "mesh" { print $5 }'),$STEPS,,,,$solve_ms,$factor_ms,,,,,,$(quality $TMP/rs.aug),," >> $SUM
echo "split_1step,$nodes,,1,1,,,$solve_ms,$factor_ms,,,,,,$q1,," >> $SUM
echo "split_1step+refine,$nodes,$ner,1,1,,,$solve_ms,$factor_ms,,,,,,$qr,," >> $SUM
column -s, -t < $SUM

if command -v gnuplot > /dev/null; then
    gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 1500,500
set output "$OUT/blade.png"
set multiplot layout 1,3
set title "blade cut step (brain + CSF, $STEPS steps) vs 10% of a solve"
set logscale y
set xlabel "cut step"
set ylabel "ms"
set key top left
plot "$CSV" using (strcol(1) eq "snap" ? \$2 : 1/0):3 with linespoints pt 7 title "snap", \
     "$CSV" using (strcol(1) eq "split" ? \$2 : 1/0):3 with linespoints pt 5 title "split", \
     $solve_ms * 0.1 with lines lw 2 title "10% of one solve"
unset logscale y
set title "update size per step"
set ylabel "DOFs"
plot "$CSV" using (strcol(1) eq "snap" ? \$2 : 1/0):4 with linespoints pt 7 title "m, snap", \
     "$CSV" using (strcol(1) eq "snap" ? \$2 : 1/0):5 with linespoints pt 6 title "k, snap", \
     "$CSV" using (strcol(1) eq "split" ? \$2 : 1/0):4 with linespoints pt 5 title "m, split", \
     "$CSV" using (strcol(1) eq "split" ? \$2 : 1/0):5 with linespoints pt 4 title "k, split"
set title "solve per step: AMPS vs refactor"
set ylabel "ms"
set key bottom right
set logscale y
plot "$SOL" using (strcol(1) eq "snap" && strcol(3) eq "amps" ? \$2 : 1/0):4 with linespoints pt 7 title "AMPS, snap", \
     "$SOL" using (strcol(1) eq "snap" && strcol(3) eq "refactor" ? \$2 : 1/0):4 with linespoints pt 6 title "refactor, snap", \
     "$SOL" using (strcol(1) eq "split" && strcol(3) eq "amps" ? \$2 : 1/0):4 with linespoints pt 5 title "AMPS, split", \
     "$SOL" using (strcol(1) eq "split" && strcol(3) eq "refactor" ? \$2 : 1/0):4 with linespoints pt 4 title "refactor, split"
GP
fi
