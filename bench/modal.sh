#!/bin/sh
# Modal bench (issue 17, paper 004 Table 1): per scene a dynamic stream cut in
# STEPS steps, integrated by modal with its sub-domains (one per material)
# switching between FE and their snapshot subspaces, and full FE on the same
# frames in the same process (modal --check): per frame the hybrid's time and
# the FE frame's (fe_ms), their ratio (medians and totals), the relative L2
# error against FE (max, final), the interface gap, the system sizes (max / min
# before the first cut and after it), the ranks and the switch events; AMPS
# (solve-aug, FE with the principal-submatrix updates across the cuts) on the
# same cut steps as a second FE baseline; the hybrid with its FE parts
# factored by CHOLMOD at every cut (--fe-solver cholmod) against AMPS; and the three couplings (direct,
# dual Schur, projected PCG) timed on the same frames of one scene. Each scene
# twice: the default tolerances (--err-tol, --acc-tol 0.01) and tight ones
# (--err-tol 0.002 --acc-tol 0.002; rows SCENE_tight): speed
# against error.
# Scenes: the paper's cube (22^3 hexes, E 6e9 / 1e9), a steak-like slab of
# five layers (bone 9e9, muscle 3e9, fat 1e9; hexes), and, when
# ../shared/meshes is there, brain + CSF (tets; brain E 3 kPa, CSF 1 kPa,
# under gravity, supported on its lowest tenth) and the 3-layer sphere (tets; E
# 3 kPa, 30 kPa, 300 kPa; both with the Rayleigh damping of bench/dynamics.sh,
# alpha 0.1, beta 0.001; the hex scenes alpha 0, beta 1e-5). Paper 004 Table 1 (GTX 770 GPU; ours: one core):
# FPS ours / FEM 28/15 cube, 38/20 steak, 29/19 armadillo.
# Writes bench/out/modal.csv, modal_frames_SCENE.csv, modal_coupling.csv,
# modal_l2.png, modal_timeline.png, modal_speed.png.
# Env: SCENES, STEPS (6), LEAD (30 frames before the first cut), FRAMES (30 per
# step: a cut every 30 frames), QUICK=1 (cube_n8 and steak, 2 steps).
cd "$(dirname "$0")/.." || exit 2
B=bin; S=build/scenes; O=bench/out; T=build/bench/modal; mkdir -p $O $T
STEPS=${STEPS:-6}; LEAD=${LEAD:-30}; FRAMES=${FRAMES:-30}
if [ "${QUICK:-0}" = 1 ]; then SCENES=${SCENES:-"cube_n8 steak"}; STEPS=2; LEAD=12; FRAMES=6; fi
SCENES=${SCENES:-"cube steak organ_brain organ_sphere3"}
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
CSV=$O/modal.csv
echo "scene,elements,domains,nodes,frames,sys_max_before,sys_min_before,sys_max_after,sys_min_after,hybrid_ms_median,fe_ms_median,speedup_median,hybrid_ms_total,fe_ms_total,speedup_total,amps_frame_ms,l2_max,l2_final,gap_max,switches,ranks,paper_fps_ours,paper_fps_fem,hybrid_ms_total_cholmod" > $CSV
setup() { # scene -> "meshload args|h|cut args|paper fps ours|paper fps fem"
    case $1 in
        cube|cube_n*) [ -f $S/$1.msh ] || make -s $S/$1.msh > /dev/null 2>&1
            echo "$S/$1.msh --material hard:E=6e9,rho=1000 --material soft:E=1e9,rho=1000 --fix fixed --load top:1e6,0,0|2e-4|--plane 1,0,0,0.5 --advance 0,0,-1 --per-step 64|28|15" ;;
        steak) [ -f $S/steak.msh ] || make -s $S/steak.msh > /dev/null 2>&1
            echo "$S/steak.msh --material bone:E=9e9,rho=1900 --material muscle_bottom:E=3e9,rho=1060 --material muscle_top:E=3e9,rho=1060 --material fat_bottom:E=1e9,rho=900 --material fat_top:E=1e9,rho=900 --fix fixed --load tip:0,0,-1e5|2e-4|--plane 1,0,0,0.12 --advance 0,0,-1 --per-step 12|38|20" ;;
        organ_brain|organ_sphere3)
            case $1 in
                organ_brain) f=$(ls ../shared/meshes/brain_csf*.msh 2>/dev/null | head -1); mat="--material brain:E=3000,nu=0.45,rho=1040 --material csf:E=1000,nu=0.45,rho=1000" ;;
                *) f=$(ls ../shared/meshes/sphere3*.msh 2>/dev/null | head -1); mat="--material sphere_r85:E=3000,nu=0.45,rho=1000 --material shell_r85_r90:E=30000,nu=0.45,rho=1000 --material shell_r90_r95:E=300000,nu=0.45,rho=1000" ;;
            esac
            [ -n "$f" ] && [ -f "$f" ] || return 1
            box=$($B/meshload "$f" | $B/stats | awk '$1 == "bounding" {
                gsub(/[\[\],]/, " "); print $4 - 1, $7 - 1, $10 - 1, $5 + 1, $8 + 1, $10 + 0.1 * ($11 - $10) }' | tr ' ' ',')
            case $1 in organ_brain) ps=64 ;; *) ps=24 ;; esac
            echo "$f --fix box:$box $mat --gravity 0,0,-9.81|0.016666666666666666|--plane random --per-step $ps|-|-|0.1,0.001" ;;
        *) return 1 ;;
    esac
}
for sc in $SCENES; do
    cfg=$(setup $sc) || { echo "modal.sh: $sc not available, skipped" >&2; continue; }
    margs=$(echo "$cfg" | cut -d'|' -f1); h=$(echo "$cfg" | cut -d'|' -f2); cargs=$(echo "$cfg" | cut -d'|' -f3)
    pf=$(echo "$cfg" | cut -d'|' -f4); pe=$(echo "$cfg" | cut -d'|' -f5)
    ray=$(echo "$cfg" | cut -d'|' -f6); ray=${ray:-0,1e-5}
    # shellcheck disable=SC2086
    $B/meshload $margs > $T/m.aug 2> $T/err.txt || { echo "modal.sh: $sc: meshload failed: $(cat $T/err.txt)" >&2; continue; }
    $B/factor --dynamic $h --rayleigh $ray --no-cond $T/m.aug > $T/f.aug || { echo "modal.sh: $sc: factor failed" >&2; continue; }
    # shellcheck disable=SC2086
    $B/cut $cargs --steps $STEPS --detached keep < $T/f.aug > $T/c.aug || { echo "modal.sh: $sc: cut failed" >&2; continue; }
    for tol in default tight; do
    case $tol in default) topt="" ;; *) topt="--err-tol 0.002 --acc-tol 0.002" ;; esac
    # shellcheck disable=SC2086
    $B/modal --lead $LEAD --frames $FRAMES --check $topt < $T/c.aug > $T/s.aug 2> $T/err.txt ||
        { echo "modal.sh: $sc: modal failed: $(tail -1 $T/err.txt)" >&2; continue; }
    # the FE parts factored by CHOLMOD at every cut instead of AMPS (--fe-solver cholmod)
    chol=""
    [ $tol = default ] && $B/modal --lead $LEAD --frames $FRAMES --fe-solver cholmod < $T/c.aug > $T/ch.aug 2> $T/err.txt &&
        chol=$(python3 bench/aug_kv.py --records $T/ch.aug | awk '$1 == "tIMe" && $3 == "modal" {
            for (i = 4; i <= NF; i++) if ($i ~ /^time_ms=/) { split($i, a, "="); t += a[2] } } END { printf "%.1f", t }')
    [ $tol = default ] && { $B/solve-aug --method amps --frames $FRAMES --no-reactions < $T/c.aug > $T/a.aug 2> $T/err.txt ||
        echo "modal.sh: $sc: solve-aug failed: $(tail -1 $T/err.txt)" >&2; }
    ne=$($B/meshload $margs 2>/dev/null | $B/stats | awk '$1 == "elements" { print $2; exit }')
    python3 bench/aug_kv.py --records $T/s.aug > $T/kv.txt
    python3 bench/aug_kv.py --records $T/a.aug > $T/akv.txt 2>/dev/null
    suf=""; [ $tol = tight ] && suf="_tight"
    python3 - $T/kv.txt $T/akv.txt $sc$suf "$ne" "$pf" "$pe" $CSV $O/modal_frames_$sc$suf.csv "$chol" <<'PY'
import statistics, sys
kv = lambda l: dict((a.split("=")[0], float(a.split("=")[1])) for a in l[3:])
st, tm = {}, {}
for l in (x.split() for x in open(sys.argv[1])):
    if l[0] == "NODE": nn = int(l[4]); continue
    if l[2] != "modal": continue
    d = kv(l); d["step"] = int(l[1])
    (st if l[0] == "sTAt" else tm)[int(d["frame"])] = d
amps = [kv(l)["time_ms"] for l in (x.split() for x in open(sys.argv[2])) if l and l[0] == "tIMe" and l[2] == "amps" and "frame=" in " ".join(l)]
sc, ne, pf, pe, out, fcsv = sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6], open(sys.argv[7], "a"), sys.argv[8]
fr = sorted(st)
med = lambda v: statistics.median(v) if v else float("nan")
nd = int(st[fr[0]]["domains"])
before = [st[f]["n_sys"] for f in fr if st[f]["step"] == 0 and f > 1]
after = [st[f]["n_sys"] for f in fr if st[f]["step"] > 0]
hy = [tm[f]["time_ms"] for f in fr]; fe = [tm[f]["fe_ms"] for f in fr]
l2 = [st[f]["l2_err"] for f in fr]
gap = max(st[f]["gap"] for f in fr)
sw = sum(int(st[f]["events"]) for f in fr)
ranks = "/".join("%d" % st[fr[-1]].get("d%d_rank" % d, -1) for d in range(nd))
mx = lambda v: max(v) if v else float("nan")
mn = lambda v: min(v) if v else float("nan")
out.write("%s,%s,%d,%d,%d,%d,%d,%d,%d,%.3f,%.3f,%.2f,%.1f,%.1f,%.2f,%.3f,%.3g,%.3g,%.3g,%d,%s,%s,%s,%s\n" % (
    sc, ne, nd, nn, len(fr), mx(before), mn(before), mx(after), mn(after), med(hy), med(fe), med(fe) / med(hy),
    sum(hy), sum(fe), sum(fe) / sum(hy), med(amps), mx(l2), l2[-1], gap, sw, ranks, pf, pe, sys.argv[9]))
with open(fcsv, "w") as f:
    f.write("frame,step,time_ms,fe_ms,l2_err,gap,n_sys,reduced,events\n")
    for k in fr:
        s, t = st[k], tm[k]
        f.write("%d,%d,%.4f,%.4f,%.6g,%.3g,%d,%d,%d\n" % (k, s["step"], t["time_ms"], t["fe_ms"], s["l2_err"], s["gap"],
                                                          s["n_sys"], s["reduced"], s["events"]))
PY
    done
done
# the couplings on the same frames (cube_n8: every domain reduced and FE phases)
CC=$O/modal_coupling.csv
echo "scene,coupling,frames,frame_ms_median,frame_ms_total,iters_median,max_rel_to_direct" > $CC
csc=${COUPLING_SCENE:-cube_n8}
cfg=$(setup $csc) && {
    margs=$(echo "$cfg" | cut -d'|' -f1); h=$(echo "$cfg" | cut -d'|' -f2); cargs=$(echo "$cfg" | cut -d'|' -f3)
    # shellcheck disable=SC2086
    $B/meshload $margs | $B/factor --dynamic $h --rayleigh 0,1e-5 --no-cond | $B/cut $cargs --steps 2 > $T/cc.aug &&
    for cp in direct schur ppcg; do
        $B/modal --lead 12 --frames 8 --coupling $cp --maxit 100000 < $T/cc.aug > $T/cp_$cp.aug 2> $T/err.txt ||
            { echo "modal.sh: coupling $cp failed: $(tail -1 $T/err.txt)" >&2; continue; }
        d=$(python3 tests/py/frames_diff.py --tol 1 $T/cp_$cp.aug $T/cp_direct.aug | sed 's/.*max_rel=//')
        python3 bench/aug_kv.py --records $T/cp_$cp.aug | python3 -c '
import statistics, sys
t, it = [], []
for l in sys.stdin:
    l = l.split()
    if len(l) < 3 or l[2] != "modal": continue
    d = dict((a.split("=")[0], float(a.split("=")[1])) for a in l[3:])
    if l[0] == "tIMe": t.append(d["time_ms"])
    elif "iters" in d: it.append(d["iters"])
print("%s,%s,%d,%.3f,%.1f,%s,%s" % (sys.argv[1], sys.argv[2], len(t), statistics.median(t), sum(t),
      ("%.0f" % statistics.median(it)) if it else "", sys.argv[3]))' $csc $cp "$d" >> $CC
    done
}
cat $CSV $CC
command -v gnuplot > /dev/null || { echo "modal.sh: gnuplot not found, no PNG" >&2; exit 0; }
plots=""; tl=""
for f in $O/modal_frames_*.csv; do
    [ -f "$f" ] || continue
    n=$(basename $f .csv | sed 's/modal_frames_//')
    plots="$plots${plots:+, }\"$f\" using 1:(\$5 > 0 ? \$5 : 1e-16) with lines title \"$n\""
    tl="$tl${tl:+, }\"$f\" using 1:7 with steps title \"$n\""
done
awk -F, 'NR > 1 { print $1, $12, $15, ($22 == "-" ? 0 : $22 / $23) }' $CSV > $T/bars.dat
gnuplot <<EOF
set terminal pngcairo size 900,500; set datafile separator ","
set output "$O/modal_l2.png"; set title "modal: relative L2 error against full FE per frame"
set logscale y; set xlabel "frame"; set key outside
plot $plots
set output "$O/modal_timeline.png"; set title "modal: coupled system size per frame (switches and cuts)"
set ylabel "unknowns"; plot $tl
unset logscale; unset ylabel; set datafile separator " "
set output "$O/modal_speed.png"; set title "modal: FE time / hybrid time per frame (ours, one core) and paper 004 (GPU)"
set style data histogram; set style fill solid 0.6; set logscale y; unset xlabel
plot "$T/bars.dat" using 2:xtic(1) title "median", "" using 3 title "total", "" using 4 title "paper 004 FPS ratio"
EOF
