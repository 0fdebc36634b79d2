#!/bin/sh
# factor on the AMPS papers' beam (h = 4 ... 1024) and brick (N = 4 ... 20)
# series (issue 3, "Bench"): assembly, CHOLMOD analyze / factor / solve times
# (medians of REPS runs of the tool; tIMe records), nnz(L), flops, the ordering
# CHOLMOD chose, cond(K) (cOND record, ARPACK), with the AMPS paper's table 2
# condition numbers side by side (the paper gives the ends of each series only:
# beam 1.14e3 at h = 4 to 3.29e12 at h = 1024, brick 2.19e3 to 1.18e5; Matlab
# condest, a 1-norm estimate, on its own tet split) and the growth exponent of
# cond(K) in h fitted by least squares in log-log (paper: its two ends give
# h^3.93). Assembly against factorization: the goal is assemble < 25% of
# factor on brick N = 20. Scenes: clamped at the "fixed" face, unit load on
# "tip" (beam) / "top" (brick), E = 1, nu = 0.3 (meshload's defaults).
# Writes bench/out/factor.csv and bench/out/factor.png.
# Env: BEAMS (default "4 16 64 256 1024"), BRICKS ("4 8 12 16 20"), REPS (3),
# THREADS (1).
cd "$(dirname "$0")/.." || exit 2
BEAMS=${BEAMS:-"4 16 64 256 1024"}
BRICKS=${BRICKS:-"4 8 12 16 20"}
REPS=${REPS:-3}
THREADS=${THREADS:-1}
OUT=bench/out; TMP=build/bench/factor
mkdir -p $OUT $TMP
CSV=$OUT/factor.csv
for t in meshload factor stats; do
    [ -x bin/$t ] || { echo "factor.sh: bin/$t missing (make first)" >&2; exit 1; }
done

# value of key $2 in the first named-value record of type $3 (default any) of
# stream $1 (bench/aug_kv.py seeks over the large payloads)
val() { [ -f "$1.kv" ] || python3 bench/aug_kv.py "$1" > "$1.kv" || exit 1
        awk -v k="$2" -v t="${3:-}" '(t == "" || $1 == t) && $4 == k { print $5; exit }' "$1.kv"; }
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

echo "series,size,nodes,n,nnz_K,nnz_L,flops,ordering,is_super,assemble_ms,analyze_ms,factor_ms,solve_ms,cond_ms,write_ms,assemble_over_factor,lambda_min,lambda_max,cond,cond_converged,paper_cond,relres" > $CSV
run_series() { # series name, scene prefix, load set, sizes, "size:paper_cond ..." (table 2)
    series=$1; prefix=$2; load=$3; sizes=$4; papers=$5
    for s in $sizes; do
        msh=build/scenes/${prefix}$s.msh
        make --no-print-directory -s $msh > /dev/null || { echo "factor.sh: cannot make $msh" >&2; exit 1; }
        mesh=$TMP/$series$s.aug
        bin/meshload $msh --fix fixed --load $load > $mesh || exit 1
        # run 1: everything (FACT written, cond estimated); runs 2..REPS: timings only
        rm -f $TMP/*.kv
        bin/factor --threads $THREADS $mesh > $TMP/out1.aug || { echo "factor.sh: factor failed on $msh" >&2; exit 1; }
        for k in assemble_ms analyze_ms factor_ms solve_ms; do val $TMP/out1.aug $k tIMe > $TMP/$k; done
        i=2
        while [ $i -le "$REPS" ]; do
            rm -f $TMP/outr.aug.kv
            bin/factor --threads $THREADS --no-cond --no-factor $mesh > $TMP/outr.aug || exit 1
            for k in assemble_ms analyze_ms factor_ms solve_ms; do val $TMP/outr.aug $k tIMe >> $TMP/$k; done
            i=$((i + 1))
        done
        asm=$(median < $TMP/assemble_ms); an=$(median < $TMP/analyze_ms)
        fac=$(median < $TMP/factor_ms); sol=$(median < $TMP/solve_ms)
        o=$TMP/out1.aug
        nodes=$(val $mesh nn NODE)
        paper=NA
        for p in $papers; do [ "${p%%:*}" = "$s" ] && paper=${p#*:}; done
        printf '%s,%s,%s,%s,%s,%s,%s,%s,%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%s,%s,%s,%s,%s,%s\n' \
            $series $s $nodes "$(val $o n sTAt)" "$(val $o nnz_K)" "$(val $o nnz_L)" "$(val $o flops)" \
            "$(val $o ordering sTAt)" "$(val $o is_super)" $asm $an $fac $sol "$(val $o cond_ms)" \
            "$(val $o write_ms)" "$(awk -v a=$asm -v b=$fac 'BEGIN {print a / b}')" "$(val $o lambda_min)" \
            "$(val $o lambda_max)" "$(val $o cond cOND)" "$(val $o converged cOND)" $paper \
            "$(val $o relres)" >> $CSV
        echo "$series $s done" >&2
    done
}
# the paper's series ends: beam h = 4 and 1024; brick 250 (ours N = 4: 225) and
# 18,081 vertices (N = 20)
run_series beam beam_h tip:0,-1,0 "$BEAMS" "4:1.14e3 1024:3.29e12"
run_series brick brick_n top:0,0,-1 "$BRICKS" "4:2.19e3 20:1.18e5"
column -s, -t < $CSV

# growth of cond(K): least-squares slope of log cond against log h (beam) and
# log N (brick), and the paper's from its two ends
awk -F, 'NR > 1 && $19 > 0 { x = log($2); y = log($19); s = $1
             n[s]++; sx[s] += x; sy[s] += y; sxx[s] += x * x; sxy[s] += x * y
             if (!(s in x0)) { x0[s] = $2 } ; x1[s] = $2 }
         END { for (s in n) if (n[s] > 1) {
                 b = (n[s] * sxy[s] - sx[s] * sy[s]) / (n[s] * sxx[s] - sx[s] * sx[s])
                 printf "%s: cond(K) ~ size^%.2f (least squares over %d sizes, %s..%s)\n", s, b, n[s], x0[s], x1[s] } }' $CSV
awk 'BEGIN { printf "paper (AMPS table 2, ends of the series): beam ~ h^%.2f; brick ~ N^%.2f if its series spans N = 4..20\n", log(3.29e12 / 1.14e3) / log(1024 / 4), log(1.18e5 / 2.19e3) / log(20 / 4) }'
awk -F, '$1 == "brick" { last = $0 } END { split(last, f, ","); if (f[2] != "")
    printf "brick N=%s: assembly %.1f ms = %.1f%% of factorization %.1f ms (goal < 25%%)\n", f[2], f[10], 100 * f[16], f[12] }' $CSV

if command -v gnuplot > /dev/null; then
    gnuplot <<GP
set terminal pngcairo size 1200,500
set output "$OUT/factor.png"
set datafile separator ","
set datafile missing "NA"
set multiplot layout 1,2
set title "cond(K): augcut (ARPACK) vs AMPS table 2 (series ends)"
set logscale xy
set xlabel "beam h / brick N"
set ylabel "cond(K)"
set key top left
plot "$CSV" using (strcol(1) eq "beam" ? \$2 : 1/0):19 with linespoints pt 7 title "beam (augcut)", \
     "$CSV" using (strcol(1) eq "beam" ? \$2 : 1/0):21 with points pt 6 ps 2 title "beam (paper)", \
     "$CSV" using (strcol(1) eq "brick" ? \$2 : 1/0):19 with linespoints pt 5 title "brick (augcut)", \
     "$CSV" using (strcol(1) eq "brick" ? \$2 : 1/0):21 with points pt 4 ps 2 title "brick (paper)"
set title "factor times (median of $REPS runs, $THREADS thread(s))"
set xlabel "free DOFs n"
set ylabel "ms"
plot "$CSV" using 4:10 with points pt 7 title "assemble", \
     "$CSV" using 4:11 with points pt 5 title "analyze", \
     "$CSV" using 4:12 with points pt 9 title "factor", \
     "$CSV" using 4:13 with points pt 11 title "solve", \
     "$CSV" using 4:14 with points pt 13 title "cond estimate"
unset multiplot
GP
fi
