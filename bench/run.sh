#!/bin/sh
# Runs every bench script in turn (make bench); each writes CSV + PNG to bench/out/.
# One line per script; a failing script is reported and the others still run.
cd "$(dirname "$0")/.." || exit 2
status=0
run() { echo "== $1"; sh "bench/$1" || { echo "bench: $1 failed" >&2; status=1; }; }
run stream_throughput.sh
run factor.sh
run cut.sh
run solve.sh
run solve_figs.sh
run refine.sh
run memory.sh
run deform.sh
run dynamics.sh
run modal.sh
run blade.sh
run thesis.sh
run thesis_acdm.sh
run par_threads.sh # before organs.sh, whose goals table reads its summary
run organs.sh
exit $status
