#!/bin/sh
# Stream throughput (issue 2, "Speed"), on brick N = 20 (18,081 nodes) and
# brick N = 28 (47,937 nodes, the ~50k-node mesh). Stages, MB/s = size of the
# uncompressed stream / median wall time:
#   copy      in memory: memcpy of the stream's bytes (the in-memory baseline)
#   pass      in memory: the stream library reads (CRC, checks) and rewrites
#             every record (bench/stream_pass.c) into fresh buffers, as a new
#             process does (page faults included)
#   pass_warm the same with buffers on pages already touched: the stream
#             layer's own speed; goal >= 1 GB/s
#   pass_z    pass on the --deflate stream (inflates on read)
#   cat       process: cat f | cat > /dev/null (pipe + process start-up)
#   meshload  process: meshload FILE.msh > /dev/null (gmsh parse, import, write)
#   stats     process: stats < f > /dev/null                 (if bin/stats exists)
#   pipeline  process: meshload FILE.msh | stats > /dev/null (if bin/stats exists)
# ratio_to_copy / ratio_to_cat compare within one run. Writes
# bench/out/stream_throughput.csv and .png. Env: SIZES (brick N values,
# default "20 28"), REPS (default 5; the in-memory stages run 20 REPS times).
cd "$(dirname "$0")/.." || exit 2
SIZES=${SIZES:-"20 28"}
REPS=${REPS:-5}
OUT=bench/out; TMP=build/bench
mkdir -p $OUT $TMP
CSV=$OUT/stream_throughput.csv
cc -O2 -std=c11 -D_GNU_SOURCE -Ilib -o $TMP/stream_pass bench/stream_pass.c lib/libaugcut.a -lz -lm ||
    { echo "stream_throughput: cannot build stream_pass" >&2; exit 1; }
now() { date +%s.%N; }
# median wall time of REPS runs of the shell command $1
median() {
    i=0; : > $TMP/times
    while [ $i -lt "$REPS" ]; do
        t0=$(now); sh -c "$1" || { echo "stream_throughput: failed: $1" >&2; exit 1; }
        echo "$(now) - $t0" | bc -l >> $TMP/times; i=$((i + 1))
    done
    sort -g $TMP/times | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'
}
echo "mesh,nodes,tets,bytes,stage,median_s,MB_per_s,ratio_to_copy,ratio_to_cat" > $CSV
for n in $SIZES; do
    msh=build/scenes/brick_n$n.msh
    make --no-print-directory -s $msh > /dev/null || exit 1
    aug=$TMP/brick_n$n.aug; zaug=$TMP/brick_n$n.z.aug
    bin/meshload $msh --fix fixed --load top:0,0,-1 > $aug || exit 1
    bin/meshload $msh --fix fixed --load top:0,0,-1 --deflate > $zaug || exit 1
    bytes=$(wc -c < $aug)
    nodes=$(( (n + 1) * (n + 1) * (2 * n + 1) )); tets=$((12 * n * n * n))
    set -- $($TMP/stream_pass -n $((20 * REPS)) $aug) $($TMP/stream_pass -n $((20 * REPS)) $zaug)
    tcopy=$1; tpass=$2; twarm=$3; tpassz=$5
    tcat=$(median "cat $aug | cat > /dev/null")
    row() { # stage, seconds
        printf '%s,%s,%s,%s,%s,%s,%.1f,%.2f,%.2f\n' brick_n$n $nodes $tets $bytes $1 $2 \
            "$(echo "$bytes / $2 / 1000000" | bc -l)" "$(echo "$2 / $tcopy" | bc -l)" \
            "$(echo "$2 / $tcat" | bc -l)" >> $CSV
    }
    row copy "$tcopy"
    row pass "$tpass"
    row pass_warm "$twarm"
    row pass_z "$tpassz"
    row cat "$tcat"
    row meshload "$(median "bin/meshload $msh --fix fixed --load top:0,0,-1 > /dev/null")"
    if [ -x bin/stats ]; then
        row stats "$(median "bin/stats < $aug > /dev/null")"
        row pipeline "$(median "bin/meshload $msh --fix fixed --load top:0,0,-1 | bin/stats > /dev/null")"
    else
        echo "stream_throughput: bin/stats missing, stats stages skipped" >&2
    fi
done
column -s, -t < $CSV
# pivot: one row per stage, one MB/s column per mesh
awk -F, 'NR > 1 { if (!($5 in seen)) { seen[$5] = 1; order[++ns] = $5 }
                  if (!($1 in mseen)) { mseen[$1] = 1; mesh[++nm] = $1 }
                  v[$5, $1] = $7 }
         END { printf "stage"; for (j = 1; j <= nm; j++) printf " %s", mesh[j]; print ""
               for (i = 1; i <= ns; i++) { printf "%s", order[i]
                   for (j = 1; j <= nm; j++) printf " %s", v[order[i], mesh[j]]; print "" } }' $CSV > $TMP/tp.dat
ncol=$(head -1 $TMP/tp.dat | wc -w)
if command -v gnuplot > /dev/null; then
    gnuplot <<GP
set terminal pngcairo size 900,500
set output "$OUT/stream_throughput.png"
set title "augcut stream throughput (median of $REPS runs; in-memory stages $((20 * REPS)))"
set ylabel "MB/s of the uncompressed stream"
set logscale y
set style data histograms
set style histogram clustered
set style fill solid 0.8
set key top right
plot for [i=2:$ncol] "$TMP/tp.dat" using i:xtic(1) title columnheader(i)
GP
fi
