#!/bin/sh
# The refinement figures of thesis 003 (secs. 5.2-5.3) on the bundled square
# (2,500 vertices, 4,802 triangles, fixed at the bottom, pulled at the top):
#  flower (figs. 5.2-5.5): RUNS flower punches of random shape (cut in one step,
#       the punched piece pinned), run r refined to the aspect bound 6 ... 2
#       (thesis_tools.py bound; the thesis gives its bounds only as "about 3 in
#       runs 13-17") with the thesis's area-ratio gate 3% and no angle bound:
#       intersected elements, new elements before (the cut's split) and after
#       the subdivision, stiffness-update time (refine's UPDT build) and CG time
#       (Jacobi pcg; amps next to it; after the subdivision also IC(0) pcg: its
#       CG ms and its factorization ms apart), cond(K) before and after (factor's ARPACK
#       on the flattened mesh), mean aspect and area ratio of the step's
#       elements, the lowest frame rate 1000 / (refine + solve ms) of the cut.
#  scen (figs. 5.7-5.8): NCUT cuts of growing size in each of fig. 5.9's
#       scenarios (single, intersecting, multiple cuts): intersected and new
#       elements (the thesis's count: without the intersected ones), mean aspect
#       and area ratio before and after ACDM (the thesis's criterion: aspect 3
#       and area ratio 3%; and refine's default: aspect 3 and min angle 20).
#  gmsh (issue 11 item 4): on the same cuts, the elements refine's default
#       adds against a global gmsh re-mesh of the cut domain at size 1/49: seg =
#       the cut's pATH segments embedded (the cut's own vertices, Delaunay);
#       curve_del / curve_front = the path's curves embedded and discretised by
#       gmsh at 1/49 (Delaunay / Frontal-Delaunay): triangles, added (over the
#       uncut square meshed the same way; 4,802 for seg), min angle, max aspect,
#       triangles below the bound (angle < 20 or aspect > 3), time (refine's
#       remesh + bisect ms against gmsh's own meshing wall time, both medians
#       of REPS). A global re-mesh writes every triangle anew.
# Writes bench/out/thesis_flower.csv, thesis_scen.csv, thesis_gmsh.csv,
# thesis_acdm_claims.csv (the thesis's claims next to the measured figures),
# thesis_acdm.png. Env: RUNS (20), NCUT (6), REPS (3); QUICK=1: RUNS 6, NCUT 3, REPS 1.
cd "$(dirname "$0")/.." || exit 2
if [ "${QUICK:-0}" = 1 ]; then RUNS=${RUNS:-6} NCUT=${NCUT:-3} REPS=${REPS:-1}; fi
RUNS=${RUNS:-20}
NCUT=${NCUT:-6}
REPS=${REPS:-3}
OUT=bench/out; TMP=build/bench/thesis_acdm
mkdir -p $OUT $TMP
for t in meshload factor cut refine solve-aug stats; do
    [ -x bin/$t ] || { echo "thesis_acdm.sh: bin/$t missing (make first)" >&2; exit 1; }
done
command -v gmsh > /dev/null || { echo "thesis_acdm.sh: gmsh missing" >&2; exit 1; }
R="python3 bench/refine_tools.py"; T="python3 bench/thesis_tools.py"
make --no-print-directory -s build/scenes/square.msh > /dev/null || exit 1
bin/meshload build/scenes/square.msh --fix fixed --load top:0,1 | bin/factor --no-cond > $TMP/sq.aug || exit 1
q() { $T kv "$1" qUAl refine "$2" "${3:-sum}"; }
tm() { $T kv "$1" tIMe refine "$2" sum; }
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# cond(K) of the mesh at the end of stream $1 (ARPACK, factor)
cond() { $R flat "$1" $TMP/flat.aug && bin/factor $TMP/flat.aug > $TMP/fac.aug && $T kv $TMP/fac.aug cOND arpack-lanczos cond sum; }
# KEY of METHOD's step-1 row in solve-aug's stats --csv $1
sc() { awk -F, -v m="$2" -v k="$3" 'NR == 1 { for (i = 1; i <= NF; i++) h[$i] = i; next }
       $1 == 1 && $2 == m { printf "%.6g", $(h[k]) }' "$1"; }
# solve STREAM CSV [ARGS]: solve-aug --method pcg,amps ARGS, its stats --csv
solve() { st=$1 sc=$2; shift 2
          bin/solve-aug "$st" --method pcg,amps --on-singular report "$@" > $TMP/s.aug 2> $TMP/s.err &&
          bin/stats --csv < $TMP/s.aug > "$sc" || { echo "thesis_acdm.sh: solve-aug: $(cat $TMP/s.err)" >&2; exit 1; }; }

# ---- figs. 5.2-5.5: flower punches at decreasing aspect bounds
CF=$OUT/thesis_flower.csv
echo "run,bound,intersected,new_before,new_after,aspect0,aspect,aspect_max,area0,area,cond_before,cond_after,update_ms,refine_ms,cg_iters_before,cg_ms_before,cg_iters,cg_ms,pcg_ms,amps_ms,fps_pcg_before,fps_pcg,fps_amps,cg_ic_iters,cg_ic_ms,ic_factor_ms" > $CF
r=1
while [ $r -le "$RUNS" ]; do
    b=$($T bound $r "$RUNS")
    $R path flower $((200 + r)) $TMP/p.path || exit 1
    bin/cut $TMP/sq.aug --path $TMP/p.path --steps 1 --detached pin > $TMP/c.aug || exit 1
    bin/refine --max-aspect "$b" --area-ratio 0.03 --min-angle 0 $TMP/c.aug > $TMP/r.aug || exit 1
    solve $TMP/c.aug $TMP/c.csv
    solve $TMP/r.aug $TMP/r.csv
    solve $TMP/r.aug $TMP/ri.csv --pcg-prec ic
    rms=$(tm $TMP/r.aug time_ms) pms=$(sc $TMP/r.csv pcg time_ms) ams=$(sc $TMP/r.csv amps time_ms) pms0=$(sc $TMP/c.csv pcg time_ms)
    echo "$r,$b,$(q $TMP/r.aug intersected),$(q $TMP/r.aug cut_elems),$(q $TMP/r.aug elems_added),$(q $TMP/r.aug aspect_mean0 mean),$(q $TMP/r.aug aspect_mean mean),$(q $TMP/r.aug aspect_max max),$(q $TMP/r.aug area_ratio0 mean),$(q $TMP/r.aug area_ratio mean),$(cond $TMP/c.aug),$(cond $TMP/r.aug),$(tm $TMP/r.aug update_ms),$rms,$(sc $TMP/c.csv pcg iters),$(sc $TMP/c.csv pcg iter),$(sc $TMP/r.csv pcg iters),$(sc $TMP/r.csv pcg iter),$pms,$ams,$(awk -v a=$pms0 'BEGIN { printf "%.2f", 1000 / a }'),$(awk -v a=$rms -v b=$pms 'BEGIN { printf "%.2f", 1000 / (a + b) }'),$(awk -v a=$rms -v b=$ams 'BEGIN { printf "%.2f", 1000 / (a + b) }'),$(sc $TMP/ri.csv pcg iters),$(sc $TMP/ri.csv pcg iter),$(sc $TMP/ri.csv pcg ic_factor)" >> $CF
    echo "flower run $r (bound $b) done" >&2
    r=$((r + 1))
done
column -s, -t < $CF

# ---- figs. 5.7-5.8 and the gmsh re-mesh, on fig. 5.9's scenarios
CC=$OUT/thesis_scen.csv CG=$OUT/thesis_gmsh.csv
echo "scenario,cut,steps,intersected,new_cut,new_thesis,new_default,aspect0,aspect_thesis,aspect_default,area0,area_thesis,area_default,min_angle0,min_angle_thesis,min_angle_default,aspect_max_default" > $CC
G="seg curve_del curve_front"
hdr="scenario,cut,refine_added,refine_min_angle,refine_aspect_max,refine_bad,refine_mesh_ms,refine_ms"
for g in $G; do hdr="$hdr,${g}_total,${g}_added,${g}_min_angle,${g}_aspect_max,${g}_bad,${g}_ms"; done
echo "$hdr" > $CG
# gmsh GEO ALG: "triangles min_angle max_aspect bad ms" (ms the median of REPS)
gm() { (cat $1; echo "Mesh.Algorithm = $2;") > $TMP/ga.geo
       : > $TMP/gms
       k=1
       while [ $k -le "$REPS" ]; do
           gmsh -2 -format msh41 -v 4 -o $TMP/g.msh $TMP/ga.geo > $TMP/g.log 2>&1 || { echo "thesis_acdm.sh: gmsh failed on $1" >&2; return 1; }
           $T mshq $TMP/g.msh $TMP/g.log > $TMP/gq || return 1
           awk '{ print $5 }' $TMP/gq >> $TMP/gms
           k=$((k + 1))
       done
       echo "$(awk '{ print $1, $2, $3, $4 }' $TMP/gq) $(median < $TMP/gms)"; }
# the uncut square meshed the same way: the elements a re-mesh adds are counted from it
: > $TMP/empty.path
$T geo_curves $TMP/empty.path 0.020408163265306 $TMP/g0.geo || exit 1
set -- $(gm $TMP/g0.geo 5); base_del=$1
set -- $(gm $TMP/g0.geo 6); base_front=$1
for kind in single intersecting multiple; do
    steps=1; [ $kind = intersecting ] && steps=2; [ $kind = multiple ] && steps=4
    i=1
    while [ $i -le "$NCUT" ]; do
        $T scenario $kind $i $TMP/p.path || exit 1
        if ! bin/cut $TMP/sq.aug --path $TMP/p.path --steps $steps --detached pin > $TMP/c.aug 2> $TMP/err; then
            echo "thesis_acdm.sh: $kind $i: cut failed: $(cat $TMP/err)" >&2; i=$((i + 1)); continue
        fi
        bin/refine --max-aspect 3 --area-ratio 0.03 --min-angle 0 $TMP/c.aug > $TMP/t.aug || exit 1
        : > $TMP/ms
        k=1
        while [ $k -le "$REPS" ]; do
            bin/refine $TMP/c.aug > $TMP/d.aug || exit 1
            echo "$(tm $TMP/d.aug remesh_ms) $(tm $TMP/d.aug bisect_ms)" | awk '{ print $1 + $2 }' >> $TMP/ms
            k=$((k + 1))
        done
        d=$TMP/d.aug t=$TMP/t.aug
        echo "$kind,$i,$steps,$(q $d intersected),$(q $d cut_elems),$(q $t elems_added),$(q $d elems_added),$(q $d aspect_mean0 mean),$(q $t aspect_mean mean),$(q $d aspect_mean mean),$(q $d area_ratio0 mean),$(q $t area_ratio mean),$(q $d area_ratio mean),$(q $d min_angle0 min),$(q $t min_angle min),$(q $d min_angle min),$(q $d aspect_max max)" >> $CC
        $R geo $TMP/c.aug 0.020408163265306 $TMP/gs.geo || exit 1
        $T geo_curves $TMP/p.path 0.020408163265306 $TMP/gc.geo || exit 1
        row="$kind,$i,$(q $d elems_added),$(q $d min_angle min),$(q $d aspect_max max),$(q $d bad_left),$(median < $TMP/ms),$(tm $d time_ms)"
        for g in $G; do
            case $g in seg) f=$TMP/gs.geo a=5 b0=4802 ;; curve_del) f=$TMP/gc.geo a=5 b0=$base_del ;; curve_front) f=$TMP/gc.geo a=6 b0=$base_front ;; esac
            set -- $(gm $f $a) || exit 1
            row="$row,$1,$(($1 - b0)),$2,$3,$4,$5"
        done
        echo "$row" >> $CG
        echo "$kind $i done" >&2
        i=$((i + 1))
    done
done
column -s, -t < $CC
column -s, -t < $CG
awk -F, 'NR > 1 { n++; ok += $4 >= 20 - 1e-9 && $5 <= 3 + 1e-9
                  for (g = 0; g < 3; g++) { c = 9 + 6 * g; f[g] += $3 < $(c + 1); r[g] += $(c + 1)
                                            t[g] += $c; m[g] += ($(c + 4) == 0); ms[g] += $(c + 5) }
                  rms += $7; ra += $3 }
         END { split("segments-Delaunay curve-Delaunay curve-Frontal", nm, " ")
               printf "gmsh: refine meets min angle 20 and aspect 3 on %d of %d cuts, adds %.0f elements, %.1f ms mean (remesh + bisect)\n", ok, n, ra / n, rms / n
               for (g = 0; g < 3; g++)
                   printf "gmsh %s: adds %.0f elements mean (refine adds fewer on %d of %d cuts, refine / gmsh %.3f); writes %.0f triangles (all new), meets the bound on %d of %d, %.1f ms mean\n",
                          nm[g + 1], r[g] / n, f[g], n, ra / r[g], t[g] / n, m[g], n, ms[g] / n }' $CG

CL=$OUT/thesis_acdm_claims.csv
$T claims $CF $CC > $CL || exit 1
column -s, -t < $CL

if command -v gnuplot > /dev/null; then
    gnuplot <<EOF
set terminal pngcairo size 1600,1000 noenhanced
set output "$OUT/thesis_acdm.png"
set datafile separator ","
set multiplot layout 2,3
set title "fig. 5.2: lowest frame rate per cut and new elements"
set key top left font ",9"
set xlabel "run"; set ylabel "frames / s"; set y2label "new elements"; set ytics nomirror; set y2tics
plot "$CF" every ::1 using 1:22 with linespoints pt 7 title "pcg, subdivided", "" every ::1 using 1:23 with linespoints pt 5 title "amps, subdivided", \
     "" every ::1 using 1:21 with linespoints pt 4 title "pcg, cut only", 30 dt 2 title "30 FPS", \
     "" every ::1 using 1:4 axes x1y2 with boxes fs empty title "new, cut only", "" every ::1 using 1:5 axes x1y2 with impulses lw 3 title "new, subdivided"
unset y2tics; unset y2label; set ytics mirror
set title "fig. 5.3: stiffness-update and CG time"
set ylabel "ms"
plot "$CF" every ::1 using 1:13 with linespoints pt 7 title "stiffness update (UPDT)", "" every ::1 using 1:18 with linespoints pt 5 title "CG, subdivided", \
     "" every ::1 using 1:16 with linespoints pt 4 title "CG, cut only"
set title "fig. 5.4: cond(K) before and after the subdivision"
set logscale y; set ylabel "cond"
plot "$CF" every ::1 using 1:11 with linespoints pt 4 title "cut only", "" every ::1 using 1:12 with linespoints pt 7 title "subdivided"
unset logscale y
set title "fig. 5.5: mean aspect and area ratio per run"
set ylabel "aspect"; set y2label "area ratio"; set ytics nomirror; set y2tics
plot "$CF" every ::1 using 1:2 with lines dt 2 title "bound", "" every ::1 using 1:7 with linespoints pt 7 title "aspect", \
     "" every ::1 using 1:10 axes x1y2 with linespoints pt 5 title "area ratio"
unset y2tics; unset y2label; set ytics mirror
set title "figs. 5.7-5.8: new elements and mean aspect (single, intersecting, multiple)"
set xlabel "cut"; set ylabel "elements"; set y2label "aspect"; set ytics nomirror; set y2tics
plot "$CC" every ::1 using 0:4 with points pt 6 title "intersected", "" every ::1 using 0:6 with points pt 7 title "new (thesis criterion)", \
     "" every ::1 using 0:7 with points pt 5 title "new (default)", "" every ::1 using 0:8 axes x1y2 with lines title "aspect before", \
     "" every ::1 using 0:9 axes x1y2 with lines title "aspect after (thesis)"
unset y2tics; unset y2label; set ytics mirror
set title "refine vs a global gmsh re-mesh: elements added"
set logscale y; set ylabel "elements"; set key bottom right font ",9"
plot "$CG" every ::1 using 0:3 with points pt 7 title "refine (angle 20, aspect 3)", "" every ::1 using 0:10 with points pt 5 title "gmsh, cut segments, Delaunay", \
     "" every ::1 using 0:16 with points pt 9 title "gmsh, cut curves, Delaunay", "" every ::1 using 0:22 with points pt 11 title "gmsh, cut curves, Frontal", \
     "" every ::1 using 0:21 with points pt 4 title "gmsh, cut curves, Frontal: all triangles (all new)"
unset multiplot
EOF
fi
echo "thesis_acdm.sh: wrote $CF $CC $CG $CL $OUT/thesis_acdm.png"
