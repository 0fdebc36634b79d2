"""check_meshload.py MSH STREAM [--fix GROUP]... [--load GROUP:fx,fy,fz]... [--output all|surface|GROUP]
Compares meshload's stream with an independent reading of the ASCII MSH 4.1
file: every coordinate, connectivity, material, set, constraint, load and the
output set. Prints the counts it checked; exit 1 on the first difference."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import msh41  # noqa: E402


def fail(msg):
    print("check_meshload: %s: %s" % (sys.argv[2], msg))
    sys.exit(1)


def main():
    msh_path, stream_path = sys.argv[1], sys.argv[2]
    opts = sys.argv[3:]
    exp = msh41.expected(msh41.read(msh_path))
    got = augstream.mesh(augstream.records(open(stream_path, "rb").read()))
    if got["types"][:2] != ["HEAD", "pROv"] or got["types"][-1] != "TAIL":
        fail("record order %s" % got["types"])
    want = ["NODE", "MATL", "ELEM"] + ["nSEt"] * len(exp["sets"]) + ["FIXD", "LOAD", "oUTs"]
    if got["types"][2:-1] != want:
        fail("records %s, want %s" % (got["types"][2:-1], want))
    for k in ("dim", "etype", "nv"):
        if got[k] != exp[k]:
            fail("%s %s, want %s" % (k, got[k], exp[k]))
    if got["x"] != exp["x"]:
        fail("coordinates differ (%d nodes, want %d)" % (len(got["x"]), len(exp["x"])))
    if got["conn"] != exp["conn"]:
        fail("connectivity differs (%d elements, want %d)" % (len(got["conn"]), len(exp["conn"])))
    gm = [(m[0], m[1]) for m in got["mats"]]
    if gm != exp["mats"]:
        fail("materials %s, want %s" % (gm, exp["mats"]))
    if got["mat"] != exp["mat"]:
        fail("element materials differ")
    if got["set_order"] != exp["set_order"] or got["sets"] != exp["sets"]:
        fail("sets %s, want %s" % ({k: len(v) for k, v in got["sets"].items()},
                                   {k: len(v) for k, v in exp["sets"].items()}))
    for e in range(len(got["conn"])):
        if not augstream.measure(got, e) > 0:
            fail("element %d has measure %g" % (e, augstream.measure(got, e)))
    dim = exp["dim"]
    fix, load, out = {}, {}, ("all", [])
    i = 0
    while i < len(opts):
        o, v = opts[i], opts[i + 1]
        i += 2
        if o == "--fix":
            for n in exp["sets"][v]:
                for c in range(dim):
                    fix[n * dim + c] = 0.0
        elif o == "--load":
            g, f = v.rsplit(":", 1)
            F = [float(s) for s in f.split(",")]
            nodes = exp["sets"][g]
            for n in nodes:
                for c in range(dim):
                    load[n * dim + c] = load.get(n * dim + c, 0.0) + F[c] / len(nodes)
        elif o == "--output":
            out = (v, exp["sets"]["boundary"] if v == "surface" else [] if v == "all" else exp["sets"][v])
    load = {k: v for k, v in load.items() if v != 0}
    if got["fix"] != fix:
        fail("FIXD has %d entries, want %d" % (len(got["fix"]), len(fix)))
    if sorted(got["load"]) != sorted(load) or any(abs(got["load"][k] - load[k]) > 1e-15 * abs(load[k])
                                                   for k in load):
        fail("LOAD differs (%d entries, want %d)" % (len(got["load"]), len(load)))
    kind = {"all": 0, "surface": 1}.get(out[0], 2)
    if got["out"] != (kind, out[0], list(out[1])):
        fail("oUTs (%d, %s, %d nodes), want (%d, %s, %d nodes)" % (
            got["out"][0], got["out"][1], len(got["out"][2]), kind, out[0], len(out[1])))
    print("%s: %d nodes, %d %s, %d materials, %d sets (%s), %d fixed dofs, %d loaded dofs: as in the .msh" % (
        os.path.basename(msh_path), len(got["x"]), len(got["conn"]), {2: "triangles", 4: "tets", 5: "hexes"}[got["etype"]],
        len(got["mats"]), len(got["sets"]), " ".join("%s:%d" % (k, len(got["sets"][k])) for k in got["set_order"]),
        len(fix), len(load)))


main()
