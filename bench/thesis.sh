#!/bin/sh
# The conditioning study of thesis 003 (sec. 3.5, ch. 5), measured with the
# error the thesis never reports. On the bundled square (2,500 vertices, 4,802
# triangles, fixed at the bottom, pulled at the top):
#  t52: tables 5.1-5.2: four cut patterns x VARIANTS random shapes (cut only,
#       no refine, as the thesis's "no optimisation"): intersected elements,
#       mean aspect and area ratio of the split elements, cond(K_t) (factor's
#       ARPACK on the cut mesh), pcg (Jacobi, IC(0), IC(0) on the AMD
#       ordering) iterations and CG ms, the IC(0) factorization ms apart,
#       refactor and amps ms, the lowest solver-bound frame rate 1000 / (the
#       slowest step's ms) of each, and the thesis's numbers.
#  t54: table 5.4: VARIANTS54 random single cuts: K_t as it is (the thesis's
#       "L1-norm", pcg), the log and the p = 1/2 normalisations (cgm-log,
#       cgm-es), COV (cgm-cov): cond of the matrix solved, CG iterations and ms
#       (CG capped at MAXIT54), error against CHOLMOD.
#  kiri: figs. 5.16-5.20: a kirigami of 20 slits (cut steps): per step the
#       dimension of K_t and pcg (Jacobi, IC(0), IC(0) on AMD)/refactor/amps ms
#       (figs. 5.17-5.18); kiri_dense: at steps KSTEPS the dense variants on
#       that step's K_t (the cuts before it made part of the mesh, the step's
#       slit the update).
#  kiri_s: the same kirigami on a KS x KS square (AS-CGM's Newton-Schulz at 6 n^3
#       flops per step is hours at n = 5,000): every variant, every step, with
#       the time split of fig. 5.20 (cov, decomp, normalise, recomp, cg).
# Writes bench/out/thesis_t52.csv, thesis_t54.csv, thesis_kiri.csv,
# thesis_kiri_s.csv, thesis_methods.csv (per method of each part: max n,
# iterations, ms, cond, error), thesis.png (the panels of the parts run).
# Env: VARIANTS (10), VARIANTS54 (3), MAXIT54 (3000), KSTEPS ("1 10 20"), KS (16),
# PARTS ("t52 t54 kiri kiri_dense kiri_s": the parts to run; the others' CSVs
# are kept from an earlier run).
# The refinement figures (5.2-5.5, 5.7-5.8, the gmsh re-mesh) are thesis_acdm.sh.
cd "$(dirname "$0")/.." || exit 2
VARIANTS=${VARIANTS:-10}
VARIANTS54=${VARIANTS54:-3}
MAXIT54=${MAXIT54:-3000}
KSTEPS=${KSTEPS:-"1 10 20"}
KS=${KS:-16}
PARTS=${PARTS:-"t52 t54 kiri kiri_dense kiri_s"}
part() { case " $PARTS " in *" $1 "*) return 0 ;; esac; return 1; }
OUT=bench/out; TMP=build/bench/thesis
mkdir -p $OUT $TMP
: > $TMP/started # the files this run writes are newer (the final message)
for t in meshload factor cut refine solve-aug stats; do
    [ -x bin/$t ] || { echo "thesis.sh: bin/$t missing (make first)" >&2; exit 1; }
done
R="python3 bench/refine_tools.py"; T="python3 bench/thesis_tools.py"
make --no-print-directory -s build/scenes/square.msh > /dev/null || exit 1
bin/meshload build/scenes/square.msh --fix fixed --load top:0,1 | bin/factor --no-cond > $TMP/sq.aug || exit 1
STEPCOLS="label,step,method,n,iters,converged,relres,relres_t,cond,cond_k,spd,err_chol,err_scaled,ns_iters,ic_shift,time_ms,iter,cov,decomp,normalise,recomp,cg,diag,ic_factor"
# solve LABEL STREAM OUTCSV ARGS...: solve-aug ARGS on STREAM, its per-step rows appended to OUTCSV
solve() { l=$1 s=$2 o=$3; shift 3
    bin/solve-aug "$s" --on-singular report "$@" > $TMP/s.aug 2> $TMP/s.err || { echo "thesis.sh: $l: $(cat $TMP/s.err)" >&2; return 1; }
    bin/stats --csv < $TMP/s.aug > $TMP/s.csv && $T steps "$l" $TMP/s.csv >> "$o"; }
col() { awk -F, -v m="$2" -v k="$3" 'NR == 1 { for (i = 1; i <= NF; i++) h[$i] = i; next }
        $3 == m { v = $(h[k]); if (v != "" && (n++ == 0 || v + 0 > x)) x = v + 0 } END { printf "%.6g", n ? x : 0 }' "$1"; }
sumc() { awk -F, -v m="$2" -v k="$3" 'NR == 1 { for (i = 1; i <= NF; i++) h[$i] = i; next }
        $3 == m { s += $(h[k]) } END { printf "%.6g", s }' "$1"; }

# pcg_as LABEL STREAM OUTCSV NAME PREC: pcg --pcg-prec PREC on STREAM, its rows
# appended to OUTCSV as method NAME
pcg_as() { pl=$1 po=$3 pn=$4
    : > $TMP/pa.csv
    solve "$1" "$2" $TMP/pa.csv --method pcg --pcg-prec "$5" || return 1 # solve sets l, s, o
    sed "s/^$pl,\([0-9]*\),pcg,/$pl,\1,$pn,/" $TMP/pa.csv >> "$po"; rm -f $TMP/pa.csv; }

# ---- tables 5.1-5.2
C52=$OUT/thesis_t52.csv
part t52 && echo "pattern,variant,intersected,aspect_mean,area_ratio,cond,pcg_iters,pcg_ms,pcg_ic_iters,pcg_ic_ms,refactor_ms,amps_ms,fps_pcg,fps_pcg_ic,fps_refactor,fps_amps,thesis_intersected,thesis_aspect,thesis_area,thesis_cond,thesis_cg_ms,thesis_fps,pcg_icamd_iters,pcg_icamd_ms,fps_pcg_icamd,pcg_ic_factor_ms,pcg_icamd_factor_ms" > $C52
part t52 && for pat in single intersecting flower many; do
    case $pat in
        single) th="151,4.26,0.16,1.37e5,68.21,13.39" ;; intersecting) th="152,4.64,0.37,5.08e5,74.27,12.48" ;;
        flower) th="151,14.08,0.06,5.65e5,114.04,8.30" ;; many) th="152,14.90,0.33,1.42e6,193.50,4.99" ;;
    esac
    steps=1; [ $pat = intersecting ] && steps=2; [ $pat = many ] && steps=6
    v=1
    while [ $v -le "$VARIANTS" ]; do
        $R path $pat $v $TMP/p.path || exit 1
        if ! bin/cut $TMP/sq.aug --path $TMP/p.path --steps $steps --detached pin > $TMP/c.aug 2> $TMP/err; then
            echo "thesis.sh: $pat $v: cut failed: $(cat $TMP/err)" >&2; v=$((v + 1)); continue
        fi
        bin/refine --max-aspect 0 --min-angle 0 $TMP/c.aug > $TMP/q.aug || exit 1
        $R flat $TMP/c.aug $TMP/flat.aug && bin/factor $TMP/flat.aug > $TMP/fac.aug || exit 1
        : > $TMP/r.csv
        solve x $TMP/c.aug $TMP/r.csv --method pcg,refactor,amps || exit 1
        : > $TMP/ri.csv
        solve y $TMP/c.aug $TMP/ri.csv --method pcg --pcg-prec ic || exit 1
        sed -i 's/^y,\([0-9]*\),pcg,/x,\1,pcg_ic,/' $TMP/ri.csv; cat $TMP/ri.csv >> $TMP/r.csv; rm -f $TMP/ri.csv
        pcg_as x $TMP/c.aug $TMP/r.csv pcg_icamd ic-amd || exit 1
        (echo "$STEPCOLS"; cat $TMP/r.csv) > $TMP/rh.csv
        fps() { awk -v t="$(col $TMP/rh.csv $1 time_ms)" 'BEGIN { printf "%.2f", (t > 0 ? 1000 / t : 0) }'; }
        echo "$pat,$v,$($T kv $TMP/q.aug qUAl refine intersected sum),$($T kv $TMP/q.aug qUAl refine aspect_mean0 mean),$($T kv $TMP/q.aug qUAl refine area_ratio0 mean),$($T kv $TMP/fac.aug cOND arpack-lanczos cond sum),$(sumc $TMP/rh.csv pcg iters),$(sumc $TMP/rh.csv pcg iter),$(sumc $TMP/rh.csv pcg_ic iters),$(sumc $TMP/rh.csv pcg_ic iter),$(sumc $TMP/rh.csv refactor time_ms),$(sumc $TMP/rh.csv amps time_ms),$(fps pcg),$(fps pcg_ic),$(fps refactor),$(fps amps),$th,$(sumc $TMP/rh.csv pcg_icamd iters),$(sumc $TMP/rh.csv pcg_icamd iter),$(fps pcg_icamd),$(sumc $TMP/rh.csv pcg_ic ic_factor),$(sumc $TMP/rh.csv pcg_icamd ic_factor)" >> $C52
        echo "t52 $pat $v done" >&2
        v=$((v + 1))
    done
done
part t52 && column -s, -t < $C52

# ---- table 5.4: single cuts, K_t as is, log and p = 1/2 normalisation, COV
C54=$OUT/thesis_t54.csv
part t54 && echo "$STEPCOLS" > $C54
v=1
while part t54 && [ $v -le "$VARIANTS54" ]; do
    $R path single $((100 + v)) $TMP/p.path || exit 1
    bin/cut $TMP/sq.aug --path $TMP/p.path --steps 1 > $TMP/c.aug || exit 1
    solve "single$v" $TMP/c.aug $C54 --method pcg,cgm-es,cgm-log,cgm-cov,refactor --maxit $MAXIT54 || exit 1
    echo "t54 $v done" >&2
    v=$((v + 1))
done

# ---- figs. 5.16-5.20: the kirigami
CK=$OUT/thesis_kiri.csv
$T kirigami $TMP/k.path
bin/cut $TMP/sq.aug --path $TMP/k.path --steps 20 > $TMP/k.aug || exit 1
: > $TMP/kd.csv
[ -f $CK ] && grep '^kiri_step' $CK > $TMP/kd.csv # the kiri_dense rows of an earlier run
if part kiri; then
    echo "$STEPCOLS" > $CK
    solve kiri $TMP/k.aug $CK --method pcg,refactor,amps || exit 1
    pcg_as kiri $TMP/k.aug $CK pcg_ic ic || exit 1
    pcg_as kiri $TMP/k.aug $CK pcg_icamd ic-amd || exit 1
    part kiri_dense || cat $TMP/kd.csv >> $CK
elif part kiri_dense; then
    [ -f $CK ] || echo "$STEPCOLS" > $CK
    sed -i '/^kiri_step/d' $CK
fi
for k in $KSTEPS; do
    part kiri_dense || break # step k alone: the slits before it flattened into the mesh
    head -n $((k - 1)) $TMP/k.path > $TMP/k0.path
    if [ $k -gt 1 ]; then
        bin/cut $TMP/sq.aug --path $TMP/k0.path --steps $((k - 1)) > $TMP/k0.aug && $R flat $TMP/k0.aug $TMP/kf.aug &&
            bin/factor --no-cond $TMP/kf.aug > $TMP/kb.aug || exit 1
    else
        cp $TMP/sq.aug $TMP/kb.aug
    fi
    sed -n "${k}p" $TMP/k.path > $TMP/k1.path
    bin/cut $TMP/kb.aug --path $TMP/k1.path --steps 1 > $TMP/kk.aug || exit 1
    solve "kiri_step$k" $TMP/kk.aug $CK --method pcg,cgm-es,cgm-log,refactor --maxit $MAXIT54 || exit 1
    echo "kiri step $k done" >&2
done

# ---- the kirigami on a KS x KS square: every variant, AS-CGM included
CS=$OUT/thesis_kiri_s.csv
if part kiri_s; then
echo "$STEPCOLS" > $CS
sed "s/^n = 50;/n = $KS;/" scenes/square.geo > $TMP/s.geo
gmsh -2 -format msh41 -v 0 -o $TMP/s.msh $TMP/s.geo > /dev/null 2>&1 || { echo "thesis.sh: gmsh failed" >&2; exit 1; }
bin/meshload $TMP/s.msh --fix fixed --load top:0,1 | bin/factor --no-cond > $TMP/ss.aug || exit 1
bin/cut $TMP/ss.aug --path $TMP/k.path --steps 20 > $TMP/sk.aug || exit 1
solve kiri_s $TMP/sk.aug $CS --method pcg,cgm-es,cgm-as,cgm-log,cgm-cov,refactor,amps || exit 1
: > $TMP/sic.csv
solve kiri_s $TMP/sk.aug $TMP/sic.csv --method pcg --pcg-prec ic || exit 1
sed 's/^kiri_s,\([0-9]*\),pcg,/kiri_s,\1,pcg_ic,/' $TMP/sic.csv >> $CS; rm -f $TMP/sic.csv
pcg_as kiri_s $TMP/sk.aug $CS pcg_icamd ic-amd || exit 1
echo "kiri_s done" >&2
fi

# ---- per method of each part
CM=$OUT/thesis_methods.csv
echo "label,method,steps,n_max,iters_max,ms_max,cond_max,cond_k_max,err_chol_max,relres_max,all_converged,cg_ms_max,ic_factor_ms_max" > $CM
for f in $C54 $CK $CS; do
    [ -f $f ] || continue
    for l in $(awk -F, 'NR > 1 { print $1 }' $f | sort -u); do $T per_method $f $l >> $CM; done
done
column -s, -t < $CM

# thesis.png: the panels of the parts this run ran (PARTS), none left empty
GP=$TMP/thesis.gp np=0
: > $GP
if part t52; then np=$((np + 2)); cat >> $GP <<EOF
set title "tables 5.1-5.2: cond(K_t) per run"
set logscale y; set xlabel "run (single, intersecting, flower, many)"; set ylabel "cond"
plot "$C52" every ::1 using 0:6 with points pt 7 title "measured", "" every ::1 using 0:20 with points pt 4 title "thesis"
set title "tables 5.1-5.2: CG ms per run (IC(0) factorization apart)"
set ylabel "ms"
plot "$C52" every ::1 using 0:8 with points pt 7 title "pcg Jacobi", "" every ::1 using 0:10 with points pt 5 title "pcg IC(0) CG", \
     "" every ::1 using 0:24 with points pt 13 title "pcg IC(0) AMD CG", \
     "" every ::1 using 0:26 with points pt 1 title "IC(0) factorization", "" every ::1 using 0:27 with points pt 2 title "IC(0) AMD factorization", \
     "" every ::1 using 0:11 with points pt 9 title "refactor", "" every ::1 using 0:12 with points pt 11 title "amps", \
     "" every ::1 using 0:21 with points pt 4 title "thesis CG"
unset logscale y
EOF
fi
if part kiri; then np=$((np + 2)); cat >> $GP <<EOF
set title "fig. 5.17: dimension of K_t per kirigami step"
unset logscale y; set xlabel "step"; set ylabel "n"
plot "< grep '^kiri,[0-9]*,pcg,' $CK" using 2:4 with linespoints pt 7 title "K_t"
set title "fig. 5.18: solver-bound frame rate 1000 / ms"
set logscale y; set ylabel "frames / s"
plot "< grep '^kiri,[0-9]*,pcg,' $CK" using 2:(1000/\$16) with linespoints title "pcg Jacobi", \
     "< grep '^kiri,[0-9]*,pcg_ic,' $CK" using 2:(1000/\$16) with linespoints title "pcg IC(0)", \
     "< grep '^kiri,[0-9]*,pcg_icamd,' $CK" using 2:(1000/\$16) with linespoints title "pcg IC(0) AMD", \
     "< grep '^kiri,[0-9]*,refactor,' $CK" using 2:(1000/\$16) with linespoints title "refactor", \
     "< grep '^kiri,[0-9]*,amps,' $CK" using 2:(1000/\$16) with linespoints title "amps", 30 dt 2 title "30 FPS"
unset logscale y
EOF
fi
if part kiri_s; then np=$((np + 2)); cat >> $GP <<EOF
set title "small kirigami: error against CHOLMOD"
set logscale y; set xlabel "step"; set ylabel "||x - u|| / ||u||"
plot "< grep ',cgm-es,' $CS" using 2:12 with linespoints title "cgm-es", "< grep ',cgm-as,' $CS" using 2:12 with linespoints title "cgm-as", \
     "< grep ',cgm-log,' $CS" using 2:12 with linespoints title "cgm-log", "< grep ',cgm-cov,' $CS" using 2:12 with linespoints title "cgm-cov", \
     "< grep ',pcg,' $CS" using 2:(\$7 > 0 ? \$7 : 1e-16) with linespoints title "pcg relres"
set title "fig. 5.20: small kirigami time split (ms, step sums)"
unset logscale y; set style data histograms; set style histogram rowstacked; set style fill solid; set boxwidth 0.6
set ylabel "ms"; set xlabel ""
plot "< for m in cgm-es cgm-as; do awk -F, -v m=\$m '\$3 == m { c += \$18; d += \$19; n += \$20; r += \$21; g += \$22 } END { print m \",\" c \",\" d \",\" n \",\" r \",\" g }' $CS; done" \
     using 2:xtic(1) title "cov", "" using 3 title "decomp", "" using 4 title "normalise", "" using 5 title "recomp", "" using 6 title "cg"
EOF
fi
PNG=""
if [ $np -gt 0 ] && command -v gnuplot > /dev/null; then
    cols=$np; [ $np -gt 3 ] && cols=$(( np == 4 ? 2 : 3 )); rows=$(( (np + cols - 1) / cols ))
    { echo "set terminal pngcairo size $((cols * 540)),$((rows * 500)) noenhanced"
      echo "set output \"$OUT/thesis.png\""
      echo 'set datafile separator ","'
      echo "set multiplot layout $rows,$cols"
      cat $GP
      echo "unset multiplot"; } | gnuplot && PNG=" $OUT/thesis.png"
elif [ $np -eq 0 ]; then
    echo "thesis.sh: PARTS=\"$PARTS\" has no plotted part (t52, kiri, kiri_s): no thesis.png" >&2
fi
# the CSVs this run wrote (PARTS: the others are an earlier run's, or none)
W=""
for f in $C52 $C54 $CK $CS $CM; do [ -f $f ] && [ $f -nt $TMP/started ] && W="$W $f"; done
echo "thesis.sh: wrote$W$PNG"
