#!/bin/sh
# The golden scenes: writes OUT/NAME.dump (stats --dump --no-times) of three
# tiny pipelines. Tools are called by name from $AUG_BIN (default bin/), so
# that pROv records hold no path. Regenerate the committed files with
#   sh tests/golden/scenes.sh tests/golden
# Meshes (committed, so that a gmsh upgrade does not move the goldens):
#   brick2.msh   gmsh -3 -setnumber N 2 -format msh41 -o brick2.msh scenes/brick.geo
#   square5.msh  scenes/square.geo with n = 5, gmsh -2 -format msh41
out=$(cd "${1:?usage: scenes.sh OUTDIR}" && pwd) || exit 2
here=$(cd "$(dirname "$0")" && pwd)
PATH="${AUG_BIN:-$here/../../bin}:$PATH"
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
cd "$here" || exit 2
set -e
# a 3-D planar cut: 2 x 2 x 4 brick, the plane x = 0.5 opened in 3 steps
meshload brick2.msh --fix fixed --load top:0,0,-1 | factor | cut --plane 1,0,0,0.5 --steps 3 \
    | solve-aug --method amps,refactor --check | stats --dump --no-times > "$out/cut3d.dump"
# a 2-D path cut, refined: 5 x 5 square, the line of cut.path
meshload square5.msh --fix fixed --load top:0,-0.01 | factor | cut --path cut.path --steps 3 \
    | refine | solve-aug --method amps,gmres --check | stats --dump --no-times > "$out/refine2d.dump"
# a constrained step: the 5 x 5 square cut along x = 0.5, the top edge held at step 2
meshload square5.msh --fix fixed --load right:0.01,0 | factor | cut --plane 1,0,0,0.5 --steps 3 --constrain top@2 \
    | solve-aug --method amps,rowupdate --check | stats --dump --no-times > "$out/constrain2d.dump"
