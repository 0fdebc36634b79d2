#!/bin/sh
# Dynamics bench (issue 10): a progressive planar cut integrated in time,
# backward Euler with Rayleigh damping at h = 1/60 s and 1/500 s, every method
# on the same frames in one run (solve-aug --frames F --check): per method the
# median time of a frame's solve, its median per-step work, frames per second
# (frames per step F over F frame solves plus one step's work), the ratio to
# one full solve of the factor (timed by solve-aug in the same process), AMPS
# against warm-started Jacobi PCG (the thesis's solver, to 1e-8) and against
# refactor (CHOLMOD with a reused ordering) as ratios, the largest residual
# and err_direct; the energy per frame of the h = 1/60 run as a plot.
# Scenes: brick N=16 and beam h=256 (bundled .geo), and the organ meshes of
# ../shared/meshes when present (bunny, liver, brain + CSF; supported on their
# lowest tenth in z, under gravity; soft tissue: E = 3 kPa, nu = 0.45, rho = 1000).
# Writes bench/out/dynamics.csv, dynamics_frames_SCENE.csv, dynamics.png,
# dynamics_energy.png. Env: SCENES, STEPS (default 16), FRAMES (4), QUICK=1, MAT
# (meshload material options of the bundled grids; the organs keep soft tissue).
cd "$(dirname "$0")/.." || exit 2
B=bin; S=build/scenes; O=bench/out; T=build/bench/dynamics; mkdir -p $O $T
STEPS=${STEPS:-16}; FRAMES=${FRAMES:-4}
# the bundled grids' material (E = 1, rho = 1) makes A = M + h^2 K mass-dominated
# at these steps (h omega << 1) and warm-started PCG cheap; a stiff one
# (wave speed sqrt(E/rho) = 1000 per unit length) makes A stiffness-dominated
MAT=${MAT:-"--default-material E=1e6,nu=0.3,rho=1"}
METHODS=${METHODS:-amps,pcg,refactor,gmres}
if [ "${QUICK:-0}" = 1 ]; then SCENES=${SCENES:-brick_n8}; STEPS=4; FRAMES=2; fi
SCENES=${SCENES:-"brick_n16 beam_h256 organ_bunny organ_liver organ_brain"}
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
CSV=$O/dynamics.csv
echo "scene,n,h,method,frames,frame_ms,step_ms,fps,ratio_full_solve,amps_vs_pcg,amps_vs_refactor,max_relres,max_err_direct" > $CSV
mesh_of() { # scene -> meshload arguments (empty: not available)
    case $1 in
        organ_bunny) f=$(ls ../shared/meshes/*bunny*.msh 2>/dev/null | head -1) ;;
        organ_liver) f=$(ls ../shared/meshes/liver_sofa_mor*.msh 2>/dev/null | head -1) ;;
        organ_brain) f=$(ls ../shared/meshes/brain_csf*.msh 2>/dev/null | head -1) ;;
        *) [ -f $S/$1.msh ] || make -s $S/$1.msh > /dev/null 2>&1; f=$S/$1.msh ;;
    esac
    [ -n "$f" ] && [ -f "$f" ] || return 1
    case $1 in
        organ_*) # supported on its lowest tenth in z, under gravity, soft tissue (E 3 kPa, nu 0.45, rho 1000)
            box=$($B/meshload "$f" | $B/stats | awk '$1 == "bounding" {
                gsub(/[\[\],]/, " "); print $4 - 1, $7 - 1, $10 - 1, $5 + 1, $8 + 1, $10 + 0.1 * ($11 - $10) }' | tr ' ' ',')
            echo "$f --fix box:$box --default-material E=3000,nu=0.45,rho=1000 --gravity 0,0,-9.81" ;;
        beam*) echo "$f --fix fixed --load tip:0,1e-3,0 $MAT" ;;
        *) echo "$f --fix fixed --load top:0,0,-1 $MAT" ;;
    esac
}
for sc in $SCENES; do
    args=$(mesh_of $sc) || { echo "dynamics.sh: $sc not available, skipped" >&2; continue; }
    # the cut enters at the free end and advances towards the support (bench/solve.sh)
    case $sc in organ_*) plane="random" adv="";; beam*) plane="0,1,0,2" adv="--advance 0,0,-1";; *) plane="1,0,0,0.5" adv="--advance 0,0,-1";; esac
    $B/meshload $args > $T/m.aug 2> $T/err.txt || { echo "dynamics.sh: $sc: meshload failed: $(cat $T/err.txt)" >&2; continue; }
    for h in 0.016666666666666666 0.002; do
        $B/factor --dynamic $h --rayleigh 0.1,0.001 --no-cond $T/m.aug > $T/f.aug || { echo "dynamics.sh: $sc: factor failed" >&2; continue; }
        $B/cut --plane $plane $adv --per-step 1 --steps $STEPS --detached keep < $T/f.aug > $T/c.aug || { echo "dynamics.sh: $sc: cut failed" >&2; continue; }
        $B/solve-aug --method $METHODS --frames $FRAMES --check --tol 1e-8 < $T/c.aug > $T/s.aug 2> $T/err.txt ||
            { echo "dynamics.sh: $sc h=$h: solve-aug failed: $(tail -1 $T/err.txt)" >&2; continue; }
        python3 bench/aug_kv.py --records $T/s.aug > $T/kv.txt
        python3 - $T/kv.txt $sc $h $CSV $O/dynamics_frames_$sc.csv <<'PY'
import statistics, sys
lines = [l.split() for l in open(sys.argv[1])]
sc, h, out, fcsv = sys.argv[2], sys.argv[3], open(sys.argv[4], "a"), sys.argv[5]
n = ""
frame, step, stat = {}, {}, {}
energy = []
for l in lines:
    if l[0] == "NODE": continue
    typ, st, tag = l[0], int(l[1]), l[2]
    kv = dict((a.split("=")[0], float(a.split("=")[1])) for a in l[3:])
    if typ == "sTAt" and tag == "factor": n = int(kv.get("n", 0))
    if tag == "dynamics":
        if typ == "sTAt": energy.append((kv["frame"], kv["kinetic"], kv["potential"], kv["work"]))
        continue
    if typ == "tIMe" and "frame" in kv: frame.setdefault(tag, []).append(kv)
    elif typ == "tIMe" and st > 0: step.setdefault(tag, []).append(kv["time_ms"])
    elif typ == "sTAt" and "frame" in kv: stat.setdefault(tag, []).append(kv)
med = lambda v: statistics.median(v) if v else float("nan")
fr_ms = {m: med([r["time_ms"] for r in v]) for m, v in frame.items()}
st_ms = {m: med(v) for m, v in step.items()}
full = med([r["full_solve_ms"] for v in frame.values() for r in v])
F = max(1, round(len(next(iter(frame.values()))) / max(1, len(next(iter(step.values()), [1])))))
for m in frame:
    per = fr_ms[m] + st_ms.get(m, 0.0) / F
    rr = max((r.get("relres", float("nan")) for r in stat.get(m, [])), default=float("nan"))
    ed = max((r.get("err_direct", float("nan")) for r in stat.get(m, [])), default=float("nan"))
    vs = lambda b: (fr_ms[b] + st_ms.get(b, 0) / F) / per if b in fr_ms else float("nan")
    out.write("%s,%s,%s,%s,%d,%.4f,%.4f,%.1f,%.3f,%.2f,%.2f,%.3g,%.3g\n" % (
        sc, n, h, m, len(frame[m]), fr_ms[m], st_ms.get(m, float("nan")), 1000.0 / per, fr_ms[m] / full,
        vs("pcg") if m == "amps" else float("nan"), vs("refactor") if m == "amps" else float("nan"), rr, ed))
if h.startswith("0.0166"):
    with open(fcsv, "w") as f:
        f.write("frame,kinetic,potential,work,energy\n")
        for fr, k, p, w in energy: f.write("%d,%.17g,%.17g,%.17g,%.17g\n" % (fr, k, p, w, k + p - w))
PY
    done
done
cat $CSV
command -v gnuplot > /dev/null || { echo "dynamics.sh: gnuplot not found, no PNG" >&2; exit 0; }
awk -F, 'NR > 1 && $4 == "amps" { print $1 "_" $3, $9, $10 }' $CSV > $T/bars.dat
gnuplot <<EOF
set terminal pngcairo size 900,500; set output "$O/dynamics.png"
set title "AMPS per frame: ratio to one full solve, speed-up over warm-started PCG"
set style data histogram; set style fill solid 0.6; set xtics rotate by -30; set logscale y
plot "$T/bars.dat" using 2:xtic(1) title "frame / full solve", "" using 3 title "PCG time / AMPS time"
