#!/bin/sh
# make mutate: each mutant of tests/mutate/mutants.txt applied to a scratch copy
# of the tree (one copy, built once; per mutant only the changed file is
# rebuilt), run against every unit test and the shell tests it names (all shell
# tests when it names none, or with MUTATE_FULL=1), then reverted. Prints one
# line per mutant, KILLED or SURVIVED (equivalent ones say so), and the score.
# MUTATE_ONLY=name,name runs just those.
cd "$(dirname "$0")/../.." || exit 2
root=$PWD; scratch=${MUTATE_DIR:-/tmp/augcut-mutate.$$}
rm -rf "$scratch"; mkdir -p "$scratch"
git ls-files -z | xargs -0 tar cf - | (cd "$scratch" && tar xf -)
cp -r build/scenes "$scratch/scenes_built" 2>/dev/null
cd "$scratch" || exit 2
mkdir -p build && cp -r scenes_built build/scenes 2>/dev/null
make all scenes > build.log 2>&1 || { echo "mutate: the unmutated tree does not build"; tail build.log; exit 1; }
/usr/bin/python3 - "$root" "$scratch" <<'PY'
import os, subprocess, sys, time
root, scratch = sys.argv[1], sys.argv[2]
blocks, cur = [], None
for line in open(os.path.join(root, "tests/mutate/mutants.txt")):
    line = line.rstrip("\n")
    if line.startswith("## "):
        cur = {"name": line[3:].split(":")[0], "what": line[3:]}
        blocks.append(cur)
    elif cur is not None and ":" in line and not line.startswith("#"):
        k, v = line.split(":", 1)
        cur[k.strip()] = v.strip().replace("\\n", "\n")
env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", AUG_BIN=scratch + "/bin",
           AUG_DATA=scratch + "/tests/data", AUG_SCENES=scratch + "/build/scenes", AUG_ROOT=scratch)
full = os.environ.get("MUTATE_FULL") == "1"
def tests_fail(b):
    units = sorted(os.listdir(scratch + "/build/tests"))
    for u in units:
        p = subprocess.run([scratch + "/build/tests/" + u], env=env, capture_output=True, text=True)
        if p.returncode != 0 or "\nFAIL " in "\n" + p.stdout:
            return "unit " + u
    shell = b.get("tests", "").split() if not full else []
    if not shell:
        shell = sorted(f[:-5] for f in os.listdir(scratch + "/tests") if f.endswith(".test"))
    for t in shell:
        d = subprocess.run(["mktemp", "-d"], capture_output=True, text=True).stdout.strip()
        p = subprocess.run(["sh", scratch + "/tests/%s.test" % t], cwd=d, env=dict(env, TMP=d),
                           capture_output=True, text=True)
        subprocess.run(["rm", "-rf", d])
        if p.returncode != 0:
            return "shell " + t
    return None
only = [x for x in os.environ.get("MUTATE_ONLY", "").split(",") if x]
if only:
    blocks = [b for b in blocks if b["name"] in only]
killed = survived = equiv = 0
for b in blocks:
    path = os.path.join(scratch, b["file"])
    src = open(path).read()
    if src.count(b["find"]) != 1:
        print("BROKEN    %-28s the find text occurs %d times in %s" % (b["name"], src.count(b["find"]), b["file"]))
        survived += 1
        continue
    open(path, "w").write(src.replace(b["find"], b["replace"]))
    t0 = time.time()
    built = subprocess.run(["make", "all"], cwd=scratch, capture_output=True).returncode == 0
    why = "does not build" if not built else tests_fail(b)
    open(path, "w").write(src)
    os.utime(path, None)
    if why:
        killed += 1
        print("KILLED    %-28s by %s (%.0f s)" % (b["name"], why, time.time() - t0))
    elif "equivalent" in b:
        equiv += 1
        print("EQUIV     %-28s %s" % (b["name"], b["equivalent"]))
    else:
        survived += 1
        print("SURVIVED  %-28s %s" % (b["name"], b["what"]))
    sys.stdout.flush()
subprocess.run(["make", "all"], cwd=scratch, capture_output=True)
print("mutate: %d killed, %d survived, %d equivalent of %d" % (killed, survived, equiv, len(blocks)))
sys.exit(1 if survived else 0)
PY
rc=$?
cd "$root" && rm -rf "$scratch"
exit $rc
