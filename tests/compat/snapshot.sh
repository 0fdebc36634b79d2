#!/bin/sh
# Before/after comparison for behaviour-preserving refactors: runs every shell
# test and the bundled pipelines (every method) with each tool wrapped, and
# writes one sorted line per tool run (tool, arguments, exit code, digest of
# its output stream less tIMe/pROv records, or of stats --dump --no-times).
#   sh tests/compat/snapshot.sh OUT.txt     then   diff BEFORE.txt AFTER.txt
cd "$(dirname "$0")/../.." || exit 2
out=${1:?usage: snapshot.sh OUT.txt}
root=$PWD; wrap=$(mktemp -d); log=$(mktemp); T=$(mktemp -d)
for t in bin/*; do [ -x "$t" ] && [ "${t%.c}" = "$t" ] && ln -s "$root/tests/compat/wrap.sh" "$wrap/$(basename "$t")"; done
export AUG_REAL_BIN="$root/bin" AUG_ROOT="$root" AUG_SNAP_LOG="$log"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
# the bundled pipelines, every method
S=build/scenes; B=$wrap; export AUG_SNAP_TEST=pipelines
$B/meshload $S/brick_n4.msh --fix fixed --load top:0,0,-1 | $B/factor > $T/snap_b.aug
$B/cut $T/snap_b.aug --plane 1,0,0,0.5 --steps 8 --pull 0.1 > $T/snap_c.aug
$B/solve-aug $T/snap_c.aug --method amps,gmres,refactor,rowupdate,pcg --check > $T/snap_s.aug
$B/stats --dump --no-times $T/snap_s.aug > /dev/null
$B/solve-aug $T/snap_c.aug --method amps --background --bg-lag 2 --output surface > $T/snap_o.aug
$B/stats --dump --no-times $T/snap_o.aug > /dev/null
$B/meshload $S/square.msh --fix left --load right:0.01,0 | $B/factor --no-cond > $T/snap_q.aug
printf 'bezier 0.1 0.2 0.4 0.9 0.6 -0.1 0.9 0.6\ncircle 0.6 0.6 0.15\n' > $T/snap_p.txt
$B/cut $T/snap_q.aug --path $T/snap_p.txt --steps 10 --detached pin --pull 0.01 | $B/refine > $T/snap_r.aug
$B/solve-aug $T/snap_r.aug --method amps,gmres,refactor,rowupdate,pcg --check > $T/snap_rs.aug
$B/stats --dump --no-times $T/snap_rs.aug > /dev/null
$B/meshload $S/beam_h4.msh --fix fixed --load tip:0,-1,0 | $B/factor | $B/cut --plane 1,0,0,2 --advance 0,0,1 --steps 6 --per-step 2 | $B/refine | $B/solve-aug --method amps,refactor --check | $B/stats --dump --no-times > /dev/null
rm -rf "$T"
# every shell test
for t in tests/*.test; do
    export AUG_SNAP_TEST=$(basename "$t" .test)
    tmp=$(mktemp -d)
    (cd "$tmp" && TMP="$tmp" AUG_BIN="$wrap" AUG_DATA="$root/tests/data" AUG_SCENES="$root/build/scenes" \
        sh "$root/$t") > "$tmp/.out" 2>&1 || echo "$AUG_SNAP_TEST: FAILED" >> "$log"
    rm -rf "$tmp"
done
sort "$log" > "$out"
rm -rf "$wrap" "$log"
echo "snapshot: $(wc -l < "$out") tool runs in $out"
