#!/bin/sh
# AMPS on one and two threads (issue 15 item 4; the analog of paper 001 fig. 9,
# single- against 32-core update rates on its 50,737-node brain): the organs
# of ../shared/meshes (SCENES, default brain liver sphere3: brain + CSF 23.8k
# nodes, liver 4.3k, sphere3 4.6k, the materials and oblique planes of
# bench/organs.sh, advancing from the top as there: every step changes K),
# 64 one-node steps, solve-aug --method amps --time-full
# with --threads 1 and --threads 2 in alternation, ROUNDS times (default 2),
# so both see the same machine load. With --threads 2 the full-field
# back-substitution over L' runs on two cores (lib/solve/par_*.c) and so do
# both triangular solves of the --time-full reference; with 1 thread the
# reference is cholmod_solve2 on one core.
# Out: bench/out/par_SCENE_tN_rR.csv (per step, stats --csv),
# bench/out/par_SCENE_rate.csv (per step: the median over the rounds of the
# step ms and the rate 1000/ms for each thread count, and the speedup),
# bench/out/par_summary.csv (per scene and thread count: median step ms,
# median full solve ms, their ratio, median rate in Hz; the geometric mean of
# the per-step speedups, as the paper gives), bench/out/par_brain_rate.png.
# STEPS may be set (default 64); PREFAULT=MIB (default 0) gives every run
# --prefault MIB (bench/organs.sh).
cd "$(dirname "$0")/.." || exit 2
B=bin; O=bench/out; T=${TMPDIR:-/tmp}/par_threads.$$; mkdir -p $O $T
trap 'rm -rf $T' EXIT
MESHES=${MESHES:-../shared/meshes}; STEPS=${STEPS:-64}; ROUNDS=${ROUNDS:-2}
SCENES=${SCENES:-"brain liver sphere3"}
# no thread variables exported: the tools set them as for any user
# (lib/cli/threads_env.c: OpenMP 1, OpenBLAS N, lowered to 1 in the steps
# when the pool runs, lib/solve/solver.c)
unset OMP_NUM_THREADS OPENBLAS_NUM_THREADS OMP_THREAD_LIMIT
for t in meshload factor cut solve-aug stats; do
    [ -x $B/$t ] || { echo "par_threads.sh: $B/$t missing (make first)" >&2; exit 1; }
done
SUM=$O/par_summary.csv
echo "scene,threads,steps,rounds,median_step_ms,median_full_ms,step_over_full,median_rate_hz,median_reach_ms,median_memo_ms,median_solve_ms,geomean_speedup" > $SUM
status=0

# scene NAME FILE materials...: the pipeline of bench/organs.sh (the bottom 10%
# fixed, gravity, the oblique plane through the centre, one node per step),
# then ROUNDS alternations of --threads 1 and 2
scene() {
    name=$1 msh=$MESHES/$2; shift 2
    [ -f "$msh" ] || { echo "par_threads.sh: $msh not present, $name skipped" >&2; return 0; }
    set -- $(python3 bench/organs_tools.py box "$msh") "$@"
    x0=$1 y0=$2 z0=$3 x1=$4 y1=$5 z1=$6; shift 6
    fix=$(awk -v a=$x0 -v b=$y0 -v c=$z0 -v d=$x1 -v e=$y1 -v f=$z1 \
        'BEGIN { printf "box:%g,%g,%g,%g,%g,%g", a - 1, b - 1, c - 1, d + 1, e + 1, c + 0.1 * (f - c) }')
    plane=$(awk -v a=$x0 -v b=$y0 -v c=$z0 -v d=$x1 -v e=$y1 -v f=$z1 \
        'BEGIN { nx = 0.8; ny = 0.5; nz = 0.33; printf "%g,%g,%g,%g", nx, ny, nz, nx * (a + d) / 2 + ny * (b + e) / 2 + nz * (c + f) / 2 }')
    $B/meshload "$msh" --fix $fix --gravity 0,0,-9.81 "$@" | $B/factor --no-cond |
        $B/cut --plane $plane --advance 0,0,-1 --per-step 1 --steps $STEPS --pull 0.01 --detached drop > $T/c.aug ||
        { echo "par_threads.sh: $name pipeline failed" >&2; status=1; return 0; }
    files=""
    r=1
    while [ $r -le $ROUNDS ]; do
        for th in 1 2; do
            f=$O/par_${name}_t${th}_r$r.csv
            $B/solve-aug --method amps --time-full --threads $th --prefault ${PREFAULT:-0} < $T/c.aug | $B/stats --csv > $f ||
                { echo "par_threads.sh: $name --threads $th failed" >&2; status=1; return 0; }
            files="$files $th:$f"
        done
        r=$((r + 1))
    done
    # shellcheck disable=SC2086
    python3 - $name $O/par_${name}_rate.csv $SUM $files <<'PY' || status=1
import csv, math, statistics as st, sys
name, rate_out, sum_out = sys.argv[1:4]
runs = {1: [], 2: []}
for a in sys.argv[4:]:
    th, path = a.split(":", 1)
    rows = [r for r in csv.DictReader(open(path)) if r["method"] == "amps" and r["time_ms"]]
    runs[int(th)].append({int(r["step"]): r for r in rows})
steps = sorted(set.intersection(*[set(d) for th in runs for d in runs[th]]))
def med(th, step, key):
    return st.median(float(d[step][key]) for d in runs[th])
with open(rate_out, "w") as f:
    f.write("step,t1_ms,t2_ms,t1_hz,t2_hz,speedup,t1_full_ms,t2_full_ms\n")
    sp = []
    for s in steps:
        a, b = med(1, s, "time_ms"), med(2, s, "time_ms")
        sp.append(a / b)
        f.write("%d,%.4f,%.4f,%.2f,%.2f,%.4f,%.4f,%.4f\n" % (s, a, b, 1e3 / a, 1e3 / b, a / b,
                med(1, s, "full_solve_ms"), med(2, s, "full_solve_ms")))
gm = math.exp(sum(math.log(x) for x in sp) / len(sp))
with open(sum_out, "a") as f:
    for th in (1, 2):
        def m(key):
            return st.median(med(th, s, key) for s in steps)
        ms = m("time_ms")
        f.write("%s,%d,%d,%d,%.3f,%.3f,%.3f,%.2f,%.3f,%.3f,%.3f,%.4f\n" % (
            name, th, len(steps), len(runs[th]), ms, m("full_solve_ms"), ms / m("full_solve_ms"),
            st.median(1e3 / med(th, s, "time_ms") for s in steps), m("reach"), m("memo"), m("solve"), gm))
PY
}

for sc in $SCENES; do
    case $sc in
    brain) scene brain brain_csf_colin27_23797n.msh --material brain:E=3000,nu=0.45,rho=1000 \
               --material csf:E=3,nu=0.49,rho=1000;;
    liver) scene liver liver_sofa_mor_4293n.msh --default-material E=5000,nu=0.47,rho=1000;;
    sphere3) scene sphere3 sphere3_simnibs_4556n.msh --material sphere_r85:E=3000,nu=0.45,rho=1000 \
                 --material shell_r85_r90:E=3,nu=0.49,rho=1000 --material shell_r90_r95:E=10000,nu=0.47,rho=1000;;
    *) echo "par_threads.sh: unknown scene $sc" >&2; status=1;;
    esac
done
cat $SUM
if command -v gnuplot > /dev/null && [ -f $O/par_brain_rate.csv ]; then
    gnuplot <<GP
set terminal png size 900,500 noenhanced
set output '$O/par_brain_rate.png'
set datafile separator ','
set key autotitle columnhead top right
set xlabel 'cut step (one node each)'
set ylabel 'full-field updates per second'
set title 'AMPS on the brain + CSF (23.8k nodes): 1 vs 2 threads (paper 001 fig. 9 analog)'
plot '$O/par_brain_rate.csv' using 1:4 with linespoints title '1 thread', \
     '' using 1:5 with linespoints title '2 threads', \
     '' using 1:(1000/\$8) with lines dt 2 title 'full solve, 2 threads'
GP
fi
exit $status
