#!/bin/sh
# The fuzz seed corpus fuzz/corpus/: small real streams of the bundled scenes
# (brick N = 1, beam h = 2, the square at 4 x 4 nodes), one per stage of the
# pipelines, so that every record type starts out valid behind its CRC.
# Also the text inputs of cut (path, blade and STL files) for fuzz_inputs.c.
# Run from the repository root after `make all`: sh fuzz/make_corpus.sh
set -eu
B=bin; OUT=fuzz/corpus; T=${TMPDIR:-/tmp}/augcut-corpus.$$; O=$T/corpus
# written aside and moved in only when every stage succeeded
mkdir -p "$OUT" "$T" "$O"
trap 'rm -rf "$T"' EXIT
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
gmsh -3 -setnumber N 1 -format msh41 -v 0 -o "$T/brick.msh" scenes/brick.geo > /dev/null
gmsh -3 -setnumber h 2 -format msh41 -v 0 -o "$T/beam.msh" scenes/beam.geo > /dev/null
sed 's/^n = 50;/n = 4;/' scenes/square.geo > "$T/square.geo"
gmsh -2 -format msh41 -v 0 -o "$T/square.msh" "$T/square.geo" > /dev/null

# 3-D: mesh, factor with mass matrices, planar cut with constraints, solve, refine
$B/meshload "$T/brick.msh" --fix fixed --load top:0,0,-1 --output top > "$O/brick_mesh.aug"
$B/factor --mass consistent --lumped-mass < "$O/brick_mesh.aug" > "$O/brick_factor.aug"
$B/cut --plane 1,0,0,0.5 --steps 2 --pull 0.1 --stats --constrain 'box:0,0,1.9,1,1,2@2' \
    < "$O/brick_factor.aug" > "$O/brick_cut.aug"
$B/solve-aug --method amps,gmres < "$O/brick_cut.aug" > "$O/brick_solve.aug"
$B/refine < "$O/brick_cut.aug" > "$O/brick_refine.aug"
# a cut that detaches a piece and pins it (MDLT flags, BDLT), the whole field
$B/meshload "$T/beam.msh" --fix fixed --load tip:0,1,0 --output surface |
    $B/factor --simplicial --no-cond |
    $B/cut --plane 0,0,1,0.5 --steps 2 --detached pin > "$O/beam_pin.aug"
$B/solve-aug --method refactor,rowupdate,pcg --output all < "$O/beam_pin.aug" > "$O/beam_solve.aug"

# 2-D: a path cut (pATH), solved, refined (qUAl)
printf 'polyline 0.1 0.5 0.5 0.5 0.9 0.6\n' > "$T/path"
$B/meshload "$T/square.msh" --fix fixed --load top:0,-1,0 --material square:E=2,nu=0.25,t=0.5 |
    $B/factor | $B/cut --path "$T/path" --steps 2 > "$O/square_cut.aug"
$B/solve-aug < "$O/square_cut.aug" > "$O/square_solve.aug"
$B/refine --min-angle 20 < "$O/square_cut.aug" > "$O/square_refine.aug"

# the text inputs of cut for fuzz/fuzz_inputs.c: its first byte picks the
# reader ('0' path, '1' blade, '2' STL), the rest is the file
{ printf '0'; printf 'line 0.1 0.2 0.9 0.3\npolyline 0 0 0.5 0.5 1 0.2\nbezier 0 0 0.2 0.8 0.5 -0.3 0.7 0.6 1 0\n'
  printf 'rbezier 0 0 1 0.5 1 2 1 0 1\narc 1 0 1 1 0 1 0.7071\ncircle 0.5 0.5 0.2\n'; } > "$O/input_path.txt"
{ printf '1'; printf '# a curved stroke\nblade 0 0 1 1 0 1\ncurve 0 0.5 0.5 1 0.4 0.5\nblade 0 1 0 1 1 0\n'; } > "$O/input_blade.txt"
{ printf '2'; printf 'solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n'
  printf 'facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n'; } > "$O/input_stl.txt"

# deflated records (every payload of 64 bytes and more) and every record type,
# MODE included, from the stream unit test
build/tests/stream_io > /dev/null
AUG_WRITE_SEED="$O/all_records_deflated.aug" build/tests/stream_io
du -cb "$O"/* | tail -1
rm -f "$OUT"/*
mv "$O"/* "$OUT"/
