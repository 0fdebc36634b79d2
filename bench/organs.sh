#!/bin/sh
# solve-aug on real meshes (issue 15 item 7): per scene an oblique planar cut
# solved by each method in its own run (auto, the default; amps; ampsbg, that
# is amps --background; refactor; rowupdate; METHODS may add pcg; autoon,
# auto without the stream's length (--horizon 0: the online rule; auto takes
# it from cut's pLAN); autobg, auto with the second
# core for background jobs, as ampsbg has it), each step
# timed next to one full solve of
# the same factor (--time-full), so the ratios come from one run:
#  - the organs of ../shared/meshes, only those present (MESHES may point
#    elsewhere): brain + CSF (23.8k nodes, two materials), bunny (8k), liver
#    (4.3k), the 3-layer sphere3; soft-tissue materials in Pa (kPa range,
#    nu 0.45-0.49, stiffness jumps of 1e3), gravity, the bottom 10% fixed,
#    pieces cut loose dropped; 64 one-node steps and 16 steps of 8 nodes,
#    the cut advancing from the top (--advance 0,0,-1): cut's default
#    advance starts next to the constrained nodes, and in the fixed bottom a
#    step only copies constrained nodes (m = 0, no update: 39 of sphere3's
#    and 21 of the brain's 64 one-node steps were such, their medians a bare
#    back-substitution);
#  - analogs of AMPS (paper 001) fig. 7 (update rate per step) and fig. 8
#    (phase breakdown per step) on the brain: organs_brain_rate.png,
#    organs_brain_phases.png;
#  - the thesis's 2-D square, two crossing Bezier cuts in 8 steps, refined to
#    20 degrees (refine --min-angle 20; refactor every step wins), and the same
#    cuts in SQLONG (32) shorter steps, square2d_long (AMPS wins);
#  - the beam and brick cells split into 5 tets (bench/tet5.py, the split the
#    papers' counts imply) next to gmsh's 6-tet split.
# Per-step CSVs bench/out/organs_SCENE_KIND_METHOD.csv; medians and ratios in
# bench/out/organs_summary.csv (organs_tools.py summary: medians, totals over
# the steps, auto's total over the best fixed method's); PNGs with gnuplot.
# QUICK=1: liver and sphere3 only, 8 + 4 steps, the 2-D square in 4 and 16 steps,
# beam h=64 and brick N=8 (a few minutes; the full run: beam h=256, bricks N=16
# and N=20, the sizes of the goals of issue 15); SCENES, STEPS1, STEPSM, SQSTEPS,
# SQLONG, METHODS, SPLIT_SCENES may be set (SCENES=none, SPLIT_SCENES=none and
# SQUARE=0 skip the organs, the split scenes and both squares); REPEAT (default
# 3, QUICK 1): the rounds of which the median run by total is kept.
# PREFAULT=MIB (default 0): every solve-aug run takes --prefault MIB (the heap
# touched once before the first step, solve-aug(1)), as a real-time scene
# would run it; the columns prefault_ms and minflt of the CSVs show its cost
# and the page faults left in the steps.
cd "$(dirname "$0")/.." || exit 2
B=bin; S=build/scenes; O=bench/out; T=${TMPDIR:-/tmp}/organs.$$; mkdir -p $O $T
trap 'rm -rf $T' EXIT
MESHES=${MESHES:-../shared/meshes}
METHODS=${METHODS:-auto,amps,ampsbg,refactor,rowupdate}
TOOLS="python3 bench/organs_tools.py"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
if [ "${QUICK:-0}" = 1 ]; then
    SCENES=${SCENES:-"liver sphere3"}; STEPS1=${STEPS1:-8}; STEPSM=${STEPSM:-4}; SQSTEPS=${SQSTEPS:-4}; SQLONG=${SQLONG:-16}
    SPLIT_SCENES=${SPLIT_SCENES:-"beam_h64 brick_n8"}; REPEAT=${REPEAT:-1}
fi
SCENES=${SCENES:-"brain bunny liver sphere3"}
STEPS1=${STEPS1:-64}; STEPSM=${STEPSM:-16}; SQSTEPS=${SQSTEPS:-8}; SQLONG=${SQLONG:-32}
REPEAT=${REPEAT:-3}
SPLIT_SCENES=${SPLIT_SCENES:-"beam_h256 brick_n16 brick_n20"}
for t in meshload factor cut refine solve-aug stats; do
    [ -x $B/$t ] || { echo "organs.sh: $B/$t missing (make first)" >&2; exit 1; }
done
SUM=$O/organs_summary.csv; : > $SUM
# the goals read every organs_SCENE_KIND_METHOD.csv in $O: those of an
# earlier run (a scene skipped or left out of SCENES now) would be counted
# beside this run's summary
rm -f $O/organs_*_*_*.csv
status=0

# each method of METHODS (and extra runs "name:options") on stream $2, in
# REPEAT rounds (each round runs every method once, so that a slow spell of
# the machine hits them alike; round r starts at the r-th method, so that
# no method holds the same slot in every round: consecutive runs on this
# machine differ by up to 20% in every phase, the full solve timed next to
# the steps too, 4.8 to 5.8 ms on the liver); per method the round whose total over the
# steps is the median is kept as $O/organs_$1_NAME.csv (organs_tools.py
# median_run), then the summary rows of scene $1 kind $3
solve_all() {
    s_sc=$1 s_in=$2 s_kind=$3; shift 3
    s_files="" s_bad=""
    s_r=1
    # one run a line (an extra run's options hold blanks)
    s_all=$(printf '%s\n' $(echo $METHODS | tr , ' ') "$@")
    s_cnt=$(printf '%s\n' "$s_all" | wc -l)
    while [ $s_r -le $REPEAT ]; do
        s_k=$(( (s_r - 1) % s_cnt ))
        s_order=$(printf '%s\n' "$s_all" | tail -n +$((s_k + 1)); printf '%s\n' "$s_all" | head -n $s_k)
        while IFS= read -r s_m; do
            s_name=${s_m%%:*}; s_opts=""; case $s_m in *:*) s_opts=${s_m#*:};; esac
            [ "$s_m" = ampsbg ] && s_opts="--method amps --background"
            [ -n "$s_opts" ] || s_opts="--method $s_m"
            case " $s_bad " in *" $s_name "*) continue;; esac
            # shellcheck disable=SC2086
            if ! $B/solve-aug $s_opts --time-full --prefault ${PREFAULT:-0} --on-singular report < $s_in 2> $T/err | $B/stats --csv > $T/r_${s_name}_$s_r.csv 2>> $T/err
            then echo "organs.sh: $s_sc $s_kind $s_name: $(tail -1 $T/err)" >&2; status=1; s_bad="$s_bad $s_name"; fi
        done <<EOF
$s_order
EOF
        s_r=$((s_r + 1))
    done
    for s_m in $(echo $METHODS | tr , ' ') "$@"; do
        s_name=${s_m%%:*}
        case " $s_bad " in *" $s_name "*) continue;; esac
        s_f=$O/organs_${s_sc}_${s_kind}_$s_name.csv
        $TOOLS median_run $s_f $T/r_${s_name}_*.csv && s_files="$s_files $s_f"
        rm -f $T/r_${s_name}_*.csv
    done
    [ -n "$s_files" ] && $TOOLS summary "$s_sc" "$s_kind" $SUM $s_files
}

# organ NAME FILE materials...: the pipeline up to the factor, then both cuts
organ() {
    name=$1 msh=$MESHES/$2; shift 2
    [ -f "$msh" ] || { echo "organs.sh: $msh not present, $name skipped" >&2; return 0; }
    set -- $($TOOLS box "$msh") "$@"
    x0=$1 y0=$2 z0=$3 x1=$4 y1=$5 z1=$6; shift 6
    fix=$(awk -v a=$x0 -v b=$y0 -v c=$z0 -v d=$x1 -v e=$y1 -v f=$z1 \
        'BEGIN { printf "box:%g,%g,%g,%g,%g,%g", a - 1, b - 1, c - 1, d + 1, e + 1, c + 0.1 * (f - c) }')
    # an oblique plane through the centre of the box
    plane=$(awk -v a=$x0 -v b=$y0 -v c=$z0 -v d=$x1 -v e=$y1 -v f=$z1 \
        'BEGIN { nx = 0.8; ny = 0.5; nz = 0.33; printf "%g,%g,%g,%g", nx, ny, nz, nx * (a + d) / 2 + ny * (b + e) / 2 + nz * (c + f) / 2 }')
    $B/meshload "$msh" --fix $fix --gravity 0,0,-9.81 "$@" | $B/factor --no-cond > $T/f.aug ||
        { echo "organs.sh: $name: meshload | factor failed" >&2; status=1; return 0; }
    for kind in one multi; do
        if [ $kind = one ]; then per=1 steps=$STEPS1; else per=8 steps=$STEPSM; fi
        $B/cut --plane $plane --advance 0,0,-1 --per-step $per --steps $steps --pull 0.01 --detached drop < $T/f.aug > $T/c.aug 2> $T/err ||
            { echo "organs.sh: $name $kind: cut failed: $(tail -1 $T/err)" >&2; status=1; continue; }
        solve_all $name $T/c.aug $kind "autoon:--method auto --horizon 0" "autobg:--method auto --background"
    done
}

for sc in $SCENES; do
    case $sc in
    brain) organ brain brain_csf_colin27_23797n.msh --material brain:E=3000,nu=0.45,rho=1000 \
               --material csf:E=3,nu=0.49,rho=1000;;
    bunny) organ bunny bunny_tetwild_7958n.msh --default-material E=10000,nu=0.45,rho=1000;;
    liver) organ liver liver_sofa_mor_4293n.msh --default-material E=5000,nu=0.47,rho=1000;;
    sphere3) organ sphere3 sphere3_simnibs_4556n.msh --material sphere_r85:E=3000,nu=0.45,rho=1000 \
                 --material shell_r85_r90:E=3,nu=0.49,rho=1000 --material shell_r90_r95:E=10000,nu=0.47,rho=1000;;
    none) ;;
    *) echo "organs.sh: unknown scene $sc" >&2; status=1;;
    esac
done

# the 2-D square of the thesis, two crossing cubic Bezier cuts, refined
[ "${SQUARE:-1}" = 1 ] && make --no-print-directory -s $S/square.msh > /dev/null 2>&1
if [ "${SQUARE:-1}" = 1 ] && [ -f $S/square.msh ]; then
    python3 bench/refine_tools.py path intersecting 1 $T/p.path &&
    $B/meshload $S/square.msh --fix fixed --load top:0,1 | $B/factor --no-cond > $T/sqf.aug ||
        { echo "organs.sh: square2d failed" >&2; status=1; }
    for sq in square2d:$SQSTEPS square2d_long:$SQLONG; do
        $B/cut --path $T/p.path --steps ${sq#*:} --detached pin < $T/sqf.aug | $B/refine --min-angle 20 > $T/sq.aug &&
            solve_all ${sq%%:*} $T/sq.aug refined "autoon:--method auto --horizon 0" "autobg:--method auto --background" ||
            { echo "organs.sh: ${sq%%:*} failed" >&2; status=1; }
    done
fi

# 5-tet against 6-tet cells: the same scene, cut and load on both splits
for sc in $SPLIT_SCENES; do
    case $sc in
    beam_h*) kind=beam size=${sc#beam_h} load="tip:0,1e-3,0" plane="0,1,0,2";;
    brick_n*) kind=brick size=${sc#brick_n} load="top:0,0,-1" plane="1,0,0,0.5";;
    none) continue;;
    *) echo "organs.sh: unknown split scene $sc" >&2; status=1; continue;;
    esac
    make --no-print-directory -s $S/$sc.msh > /dev/null 2>&1
    python3 bench/tet5.py $kind $size $T/${sc}_tet5.msh 2> /dev/null ||
        { echo "organs.sh: tet5.py $kind $size failed" >&2; status=1; continue; }
    for split in 6 5; do
        msh=$S/$sc.msh; [ $split = 5 ] && msh=$T/${sc}_tet5.msh
        $B/meshload $msh --fix fixed --load $load | $B/factor --no-cond |
            $B/cut --plane $plane --advance 0,0,-1 --per-step 1 --steps $STEPS1 --pull 0.1 > $T/c.aug ||
            { echo "organs.sh: $sc tet$split failed" >&2; status=1; continue; }
        solve_all ${sc}_tet$split $T/c.aug one "autoon:--method auto --horizon 0" "autobg:--method auto --background"
    done
done

if command -v gnuplot > /dev/null && [ -f $O/organs_brain_one_auto.csv ]; then
    plots=""
    for m in $(echo $METHODS | tr , ' '); do
        f=$O/organs_brain_one_$m.csv; [ -f $f ] || continue
        awk -F, 'FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            $c["method"] != "factor" { print $c["step"], 1000 / $c["time_ms"], 1000 / $c["full_solve_ms"] }' $f > $T/rate.$m.dat
        plots="$plots${plots:+, }'$T/rate.$m.dat' using 1:2 with linespoints title '$m'"
    done
    gnuplot <<GP
set terminal png size 900,500 noenhanced
set output '$O/organs_brain_rate.png'
set title 'brain + CSF, one node per step: update rate per step (AMPS fig. 7 analog)'
set xlabel 'cut step'; set ylabel 'full-field updates per second'; set logscale y; set key outside
plot $plots, '$T/rate.amps.dat' using 1:3 with lines dashtype 2 title '1 / full solve'
GP
    awk -F, 'FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        $c["method"] == "amps" { print $c["step"], $c["reach"] + 0, $c["memo"] + 0, $c["schur"] + 0, $c["solve"] + 0,
            $c["time_ms"] - $c["reach"] - $c["memo"] - $c["schur"] - $c["solve"], $c["full_solve_ms"] }' \
        $O/organs_brain_one_amps.csv > $T/phases.dat
    gnuplot <<GP
set terminal png size 900,500 noenhanced
set output '$O/organs_brain_phases.png'
set title 'brain + CSF, AMPS step phases (AMPS fig. 8 analog)'
set xlabel 'cut step'; set ylabel 'ms'; set style data histograms; set style histogram rowstacked
set style fill solid 0.8 border -1; set boxwidth 0.9; set key outside
plot '$T/phases.dat' using 2:xtic(1) title 'reach (V columns)', '' using 3 title 'memo H''K^-1H', \
     '' using 4 title 'S2 (Schur)', '' using 5 title 'solve', '' using 6 title 'refine + rest', \
     '' using 7 with lines lw 2 title 'one full solve'
GP
fi
column -s, -t < $SUM 2> /dev/null || cat $SUM
# issue 15's goals on these CSVs (and par_threads.sh's summary when present)
python3 bench/organs_goals.py $O $O/organs_goals.csv || status=1
exit $status
