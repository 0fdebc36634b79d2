#!/bin/sh
# Memory soak (issue 12): peak RSS (VmHWM) of solve-aug --method amps, without
# and with --background, every EVERY steps of a STEPS-step planar cut, one node
# a step. The mesh is the 1 x 1 x 2 brick of scenes/brick.geo in NX x NY x NZ
# cells (default 8 x 20 x 48, about brick N=16's 9,537 nodes), so that its mid
# plane x = 0.5 has (NY+1)(NZ+1) = 1,029 nodes to cut (brick N=16's has 561).
# The peak is read from /proc/PID/status when the step's sTAt record reaches
# this script, which may be up to a step after the step itself. Without the
# background job the memory grows as AMPS's own arrays must (S2's LU, the
# memo's G and V); with it, it is bounded by the background period.
# Writes bench/out/memory.csv and bench/out/memory.png (gnuplot).
# Env: STEPS (default 1000), EVERY (100), NX NY NZ, MODES ("amps amps_bg").
cd "$(dirname "$0")/.." || exit 2
STEPS=${STEPS:-1000}; EVERY=${EVERY:-100}
NX=${NX:-8}; NY=${NY:-20}; NZ=${NZ:-48}
MODES=${MODES:-"amps amps_bg"}
OUT=bench/out; TMP=build/bench/memory; CSV=$OUT/memory.csv
for t in gmsh python3; do
    command -v $t > /dev/null || { echo "memory.sh: $t not found, skipped" >&2; exit 0; }
done
[ -r /proc/self/status ] || { echo "memory.sh: no /proc/PID/status, skipped" >&2; exit 0; }
for t in meshload factor cut solve-aug; do
    [ -x bin/$t ] || { echo "memory.sh: bin/$t missing (make first)" >&2; exit 1; }
done
mkdir -p $OUT $TMP
cat > $TMP/brick.geo <<EOF
Point(1) = {0, 0, 0};
l[] = Extrude {1, 0, 0} { Point{1}; Layers{$NX}; };
s[] = Extrude {0, 1, 0} { Curve{l[1]}; Layers{$NY}; };
v[] = Extrude {0, 0, 2} { Surface{s[1]}; Layers{$NZ}; };
Physical Surface("fixed", 1) = {s[1]};
Physical Surface("top", 2) = {v[0]};
Physical Volume("brick", 3) = {v[1]};
EOF
gmsh -3 -format msh41 -v 0 -o $TMP/brick.msh $TMP/brick.geo > /dev/null || { echo "memory.sh: gmsh failed" >&2; exit 1; }
bin/meshload $TMP/brick.msh --fix fixed --load top:0,0,-1 | bin/factor --no-cond > $TMP/f.aug || exit 1
bin/cut --plane 1,0,0,0.5 --per-step 1 --steps $STEPS --pull 0.1 < $TMP/f.aug > $TMP/c.aug || exit 1
rm -f $TMP/f.aug

echo "mode,step,peak_rss_mb,rss_mb,m,k,base_step,elapsed_s" > $CSV
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
for mode in $MODES; do
    case $mode in amps) opt="";; amps_bg) opt="--background";; *) echo "memory.sh: mode $mode?" >&2; exit 1;; esac
    python3 - $mode $EVERY bin/solve-aug $TMP/c.aug --method amps $opt >> $CSV <<'PY' || { echo "memory.sh: $mode failed" >&2; exit 1; }
# runs solve-aug, reads its stream as it comes (framing of formats/stream.md)
# and prints one CSV row at step 1 and every EVERY-th step: VmHWM, VmRSS
import struct, subprocess, sys, time, zlib
mode, every, cmd = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
t0 = time.time()
p = subprocess.Popen(cmd, stdout=subprocess.PIPE)
f = p.stdout
def vm():
    kv = {}
    for line in open("/proc/%d/status" % p.pid):
        k, _, v = line.partition(":")
        if k in ("VmHWM", "VmRSS"): kv[k] = int(v.split()[0]) / 1024.0
    return kv
if f.read(8) != b"\x89AUG\r\n\x1a\n": sys.exit("memory.sh: not an augcut stream")
while True:
    h = f.read(12)
    if len(h) < 12: break
    (blen,) = struct.unpack_from("<Q", h, 0)
    typ = h[8:12].decode("ascii", "replace")
    body = f.read(blen)
    f.read(4)
    if typ != "sTAt": continue
    flags, step = struct.unpack_from("<Ii", body, 0)
    if step != 1 and step % every: continue
    q = zlib.decompress(body[16:]) if flags & 1 else body[16:]
    if q[:16].split(b"\0")[0] != b"amps": continue
    kv = {}
    for i in range(struct.unpack_from("<i", q, 16)[0]):
        kv[q[24 + 24 * i:40 + 24 * i].split(b"\0")[0].decode()] = struct.unpack_from("<d", q, 40 + 24 * i)[0]
    m = vm()
    print("%s,%d,%.1f,%.1f,%d,%d,%d,%.1f" % (mode, step, m["VmHWM"], m["VmRSS"], kv.get("m", -1),
          kv.get("k", -1), kv.get("base_step", -1), time.time() - t0), flush=True)
sys.exit(p.wait())
PY
done
column -s, -t < $CSV
command -v gnuplot > /dev/null || { echo "memory.sh: gnuplot not found, no plot" >&2; exit 0; }
gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 900,500; set output "$OUT/memory.png"
set xlabel "cut step"; set ylabel "MB"; set key top left
set title "solve-aug --method amps, brick 1 x 1 x 2 in $NX x $NY x $NZ cells, one node a step"
plot "$CSV" using (strcol(1) eq "amps" ? \$2 : 1/0):3 with linespoints pt 7 title "amps: peak RSS", \
     "$CSV" using (strcol(1) eq "amps_bg" ? \$2 : 1/0):3 with linespoints pt 5 title "amps --background: peak RSS", \
     "$CSV" using (strcol(1) eq "amps_bg" ? \$2 : 1/0):4 with points pt 4 title "amps --background: RSS at the step"
GP
