#!/bin/sh
# make check-fuzz: the fuzz targets of make fuzz build and run: each one over
# every seed of fuzz/corpus, then 200 mutations (new inputs go to a scratch
# directory, fuzz/corpus is left alone). make check builds the targets too
# and runs this as tests/fuzz_targets.test. Ends with "N passed, N failed".
cd "$(dirname "$0")/.." || exit 2
B=build
pass=0; fail=0
for t in $B/fuzz/fuzz_*; do
    [ -x "$t" ] || continue
    name=$(basename "$t")
    tmp=$(mktemp -d)
    if "$t" -runs=200 -seed=1 -timeout=30 -rss_limit_mb=2048 "$tmp" fuzz/corpus > "$tmp/.log" 2>&1; then
        pass=$((pass + 1)); echo "PASS $name"
    else
        fail=$((fail + 1)); echo "FAIL $name"; tail -30 "$tmp/.log" | sed 's/^/    /'
    fi
    rm -rf "$tmp"
done
[ $pass -gt 0 ] || { echo "FAIL: no fuzz target in $B/fuzz (make fuzz-build)"; fail=$((fail + 1)); }
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
