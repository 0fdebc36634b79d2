#!/bin/sh
# Runs every test: unit binaries (normal and ASan/UBSan builds), shell tests
# tests/*.test, and the pipeline tests again with the ASan/UBSan tools
# (--asan-only: the ASan unit tests and every shell test with those tools). Each unit binary prints "PASS name" /
# "FAIL name: why" lines; each shell test passes when it exits 0. Ends with
# "N passed, N failed".
#
# The tests run AUG_JOBS at a time (default: the number of cores); each test
# itself is single-threaded (OMP/OpenBLAS pinned to one thread), so two run
# side by side on the 2-core machine. Results are reported in the fixed order
# below whatever order they finish in, and build/test.log is that order too.
cd "$(dirname "$0")/.." || exit 2
B=build
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
# OpenBLAS picks its kernels by CPU (on an AVX-512 machine SkylakeX's), and
# their rounding moves decisions taken at rounding level (a correction sweep
# or not: sTAt correct, refine), which tests/golden.test compares exactly:
# on any x86 CPU with AVX2 the tests take Haswell's kernels, those of the
# machine the golden dumps were written on (OPENBLAS_CORETYPE given wins)
if [ -z "${OPENBLAS_CORETYPE:-}" ] && grep -qw avx2 /proc/cpuinfo 2> /dev/null; then
    export OPENBLAS_CORETYPE=Haswell
fi
export AUG_DATA="$PWD/tests/data" AUG_SCENES="$PWD/$B/scenes" AUG_ROOT="$PWD" AUG_TSAN_BIN="$PWD/$B/tsan/bin"

# --item DIR IDX KIND MODE PATH PREFIX: run one test, write DIR/IDX.{pf,msg,log}
# (KIND unit|shell, MODE plain|asan)
if [ "$1" = "--item" ]; then
    dir=$2 idx=$3 kind=$4 mode=$5 path=$6 prefix=$7
    export AUG_BIN="$PWD/bin"
    if [ "$mode" = asan ]; then
        # (no address-space cap holds ASan's shadow: one allocation above
        # 4 GiB fails instead, as meshload's cap on its gmsh child would)
        export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:max_allocation_size_mb=4096:allocator_may_return_null=1
        export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
        export LSAN_OPTIONS="print_suppressions=0"
        [ "$kind" = shell ] && export AUG_BIN="$PWD/$B/asan/bin"
    fi
    msg=$dir/$idx.msg log=$dir/$idx.log; : > "$msg"; : > "$log"
    if [ "$kind" = unit ]; then
        # a missing binary, or one that passes nothing, fails
        if [ ! -x "$path" ]; then
            echo "${prefix}FAIL $(basename "$path"): not built ($path)" > "$msg"; echo "0 1" > "$dir/$idx.pf"; exit 0
        fi
        out=$("$path" 2>&1); rc=$?
        printf '%s\n' "$out" > "$log"
        p=$(printf '%s\n' "$out" | grep -c '^PASS ')
        f=$(printf '%s\n' "$out" | grep -c '^FAIL ')
        printf '%s\n' "$out" | grep '^FAIL ' | sed "s|^|$prefix|" >> "$msg"
        if [ $rc -ne 0 ] && [ $f -eq 0 ]; then
            { echo "${prefix}FAIL $(basename "$path"): exit $rc"; printf '%s\n' "$out" | tail -5; } >> "$msg"; f=1
        elif [ $p -eq 0 ] && [ $f -eq 0 ]; then
            echo "${prefix}FAIL $(basename "$path"): ran no test" >> "$msg"; f=1
        fi
        echo "$p $f" > "$dir/$idx.pf"
    else
        name=$prefix$(basename "$path" .test)
        tmp=$(mktemp -d); t0=$(date +%s)
        if (cd "$tmp" && TMP="$tmp" sh "$AUG_ROOT/$path") > "$tmp/.out" 2>&1; then
            echo "1 0" > "$dir/$idx.pf"; echo "PASS $name ($(( $(date +%s) - t0 )) s)" > "$log"
        else
            echo "0 1" > "$dir/$idx.pf"
            { echo "FAIL $name"; tail -15 "$tmp/.out" | sed 's/^/    /'; } > "$msg"
            { echo "FAIL $name"; cat "$tmp/.out"; } > "$log"
        fi
        rm -rf "$tmp"
    fi
    exit 0
fi

asan_only=0; [ "$1" = "--asan-only" ] && asan_only=1
jobs=${AUG_JOBS:-$(getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)}
res=$(mktemp -d); trap 'rm -rf "$res"' EXIT INT TERM
list=$res/items; : > "$list"; n=0
item() { n=$((n + 1)); printf '%04d %s %s %s %s\n' $n "$1" "$2" "$3" "$4" >> "$list"; }

# Shell tests again with every tool built with ASan+UBSan (build/asan/bin, LSan
# on, no suppressions). make check runs the pipeline tests only: the other
# (usage, error, damaged-stream) tests add about 2 minutes under ASan; make
# check-asan (--asan-only) runs every shell test.
ASAN_TESTS="cut_detach cut_path cut_plane cut_solve golden progress refine_pipeline solve_output
            solve_pipeline solve_singular stats_mtx stats_pipeline stats_pvd stats_vtk modal_fe modal_switch"
[ $asan_only -eq 1 ] && ASAN_TESTS=$(for t in tests/*.test; do basename "$t" .test; done)

fail0=0
for tool in bin/*.c; do
    [ -x "$B/asan/bin/$(basename "$tool" .c)" ] || { echo "asan: FAIL $(basename "$tool" .c): not built"; fail0=$((fail0 + 1)); }
done
if [ $asan_only -eq 0 ]; then
    for u in tests/unit/*.c; do item unit plain "$B/tests/$(basename "$u" .c)" "-"; done
fi
for u in tests/unit/*.c; do item unit asan "$B/asan/tests/$(basename "$u" .c)" "asan:"; done
if [ $asan_only -eq 0 ]; then
    for t in tests/*.test; do item shell plain "$t" "-"; done
fi
for t in $ASAN_TESTS; do item shell asan "tests/$t.test" "asan:"; done

# the prefix "-" is none, "asan:" is "asan: "
sed 's/ -$/ ""/; s/ asan:$/ "asan: "/' "$list" |
    xargs -P "$jobs" -L 1 sh -c 'exec sh tests/run.sh --item "$0" "$@"' "$res"

log=$B/test.log; : > $log
pass=0; fail=$fail0
while read -r idx kind mode path prefix; do
    if [ -f "$res/$idx.pf" ]; then
        read -r p f < "$res/$idx.pf"
        cat "$res/$idx.msg"; cat "$res/$idx.log" >> $log
    else
        p=0 f=1; echo "FAIL $path: no result (runner died)"
    fi
    pass=$((pass + p)); fail=$((fail + f))
done < "$list"
[ $pass -gt 0 ] || { echo "FAIL: no test ran"; fail=$((fail + 1)); }
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
