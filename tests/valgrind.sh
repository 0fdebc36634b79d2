#!/bin/sh
# make check-valgrind: every tool under valgrind memcheck on a small pipeline
# (meshload | factor | cut | refine | solve-aug with every method | stats in
# each mode), 3-D and 2-D. A run fails on any invalid access or use of
# uninitialised memory and on any definite leak (--errors-for-leak-kinds=
# definite, --error-exitcode); reachable memory at exit is not an error.
# OMP_THREAD_LIMIT is set so that the tools do not re-execute themselves
# (lib/cli/threads_env.c), which would leave valgrind's view.
cd "$(dirname "$0")/.." || exit 2
B=$PWD/bin S=$PWD/build/scenes G=$PWD/tests/golden
out=build/valgrind; rm -rf $out; mkdir -p $out
export OMP_THREAD_LIMIT=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
VG="valgrind -q --tool=memcheck --leak-check=full --errors-for-leak-kinds=definite --show-leak-kinds=definite --error-exitcode=99 --track-origins=yes"
pass=0; fail=0; n=0
vg() { # $1 stdin file or -, $2 stdout file, then the tool and its arguments
    in=$1; o=$2; shift 2; n=$((n + 1)); log=$out/$n.$1.log
    if [ "$in" = - ]; then $VG --log-file=$log "$B/$@" > "$o"; else $VG --log-file=$log "$B/$@" < "$in" > "$o"; fi
    rc=$?
    if [ $rc -eq 0 ] && [ ! -s $log ]; then pass=$((pass + 1))
    else fail=$((fail + 1)); echo "FAIL valgrind $* (exit $rc)"; head -40 $log | sed 's/^/    /'; fi
}
vg - $out/m3.aug meshload $S/brick_n4.msh --fix fixed --load top:0,0,-1
vg $out/m3.aug $out/f3.aug factor --mass consistent
vg $out/f3.aug $out/c3.aug cut --plane 1,0,0,0.5 --steps 3 --pull 0.1 --constrain top@2
vg $out/c3.aug $out/r3.aug refine
vg $out/r3.aug $out/s3.aug solve-aug --method amps,gmres,refactor,rowupdate,pcg --check
vg - $out/m2.aug meshload $G/square5.msh --fix fixed --load top:0,-0.01
vg $out/m2.aug $out/f2.aug factor
vg $out/f2.aug $out/c2.aug cut --path $G/cut.path --steps 3 --detached pin
vg $out/c2.aug $out/r2.aug refine
vg $out/r2.aug $out/s2.aug solve-aug --method amps,gmres,refactor,rowupdate,pcg --check --background
for f in s3 s2; do
    vg $out/$f.aug /dev/null stats
    vg $out/$f.aug /dev/null stats --dump --no-times
    vg $out/$f.aug /dev/null stats --csv
    vg $out/$f.aug /dev/null stats --vtk $out/$f.vtu
    vg $out/$f.aug /dev/null stats --vtk $out/$f.pvd
    vg $out/$f.aug /dev/null stats --mtx $out/$f
done
vg $out/f3.aug /dev/null stats --mtx $out/f3 --step 0
echo "valgrind: $pass passed, $fail failed"
[ $fail -eq 0 ]
