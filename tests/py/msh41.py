"""Independent reader of gmsh ASCII MSH 4.1 files (PhysicalNames, Entities,
Nodes, Elements), for tests, and the mesh meshload must make of one
(formats/stream.md section 5, meshload(1)): used nodes in ascending tag order,
hexes or tets (or, without either, triangles) in ascending tag order, one material per
physical group of the top dimension plus "default", one set per physical
group plus "boundary"."""
import shlex

NV = {1: 2, 2: 3, 3: 4, 4: 4, 5: 8, 6: 6, 7: 5, 15: 1}
DIM = {1: 1, 2: 2, 3: 2, 4: 3, 5: 3, 6: 3, 7: 3, 15: 0}


def read(path):
    lines = open(path).read().split("\n")
    i, msh = 0, {"names": {}, "phys": {}, "nodes": {}, "elems": []}
    while i < len(lines):
        s = lines[i].strip()
        i += 1
        if s == "$MeshFormat":
            assert lines[i].split()[0] == "4.1" and lines[i].split()[1] == "0", "not ASCII MSH 4.1"
        elif s == "$PhysicalNames":
            for k in range(int(lines[i])):
                d, t, nm = shlex.split(lines[i + 1 + k])
                msh["names"][(int(d), int(t))] = nm
        elif s == "$Entities":
            counts = [int(v) for v in lines[i].split()]
            i += 1
            for d in range(4):
                for k in range(counts[d]):
                    v = lines[i].split()
                    i += 1
                    tag = int(v[0])
                    np_ = int(v[4] if d == 0 else v[7])
                    base = 5 if d == 0 else 8
                    msh["phys"][(d, tag)] = [abs(int(x)) for x in v[base:base + np_]]
        elif s == "$Nodes":
            nb = int(lines[i].split()[0])
            i += 1
            for b in range(nb):
                ed, et, par, n = (int(v) for v in lines[i].split())
                i += 1
                tags = [int(lines[i + k]) for k in range(n)]
                for k in range(n):
                    msh["nodes"][tags[k]] = tuple(float(v) for v in lines[i + n + k].split()[:3])
                i += 2 * n
        elif s == "$Elements":
            nb = int(lines[i].split()[0])
            i += 1
            for b in range(nb):
                ed, et, typ, n = (int(v) for v in lines[i].split())
                i += 1
                for k in range(n):
                    v = [int(x) for x in lines[i + k].split()]
                    msh["elems"].append((v[0], typ, (ed, et), tuple(v[1:])))
                i += n
    return msh


def expected(msh):
    """the mesh meshload should write, as a dict comparable with augstream.mesh()"""
    types = {e[1] for e in msh["elems"]}
    etype = 5 if 5 in types else 4 if 4 in types else 2
    dim = 2 if etype == 2 else 3
    els = sorted((e for e in msh["elems"] if e[1] == etype), key=lambda e: e[0])
    used = sorted({n for e in els for n in e[3]})
    new = {t: k for k, t in enumerate(used)}
    x = [msh["nodes"][t][:dim] for t in used]
    conn = [tuple(new[n] for n in e[3]) for e in els]
    groups = sorted({(d, t) for (d, _), ts in msh["phys"].items() for t in ts})

    def gname(d, t):
        return msh["names"].get((d, t)) or "physical_%d_%d" % (d, t)

    mats = [(t, gname(d, t)) for d, t in groups if d == dim]
    index = {t: k for k, (t, _) in enumerate(mats)}
    mat = []
    for e in els:
        ts = [t for t in msh["phys"].get(e[2], []) if t in index]
        assert len(ts) <= 1
        mat.append(index[ts[0]] if ts else len(mats))
    if len(mats) in mat:
        mats.append((0, "default"))
    sets, order = {}, []
    for d, t in groups:
        nm = gname(d, t)
        if nm not in sets:
            sets[nm] = set()
            order.append(nm)
        for e in msh["elems"]:
            if e[2][0] == d and t in msh["phys"].get(e[2], []):
                sets[nm].update(new[n] for n in e[3] if n in new)
    if "boundary" not in sets:
        faces = {}
        # hex8 faces in gmsh's node order (bottom 0123, top 4567), simplex faces: all nodes but one
        hexf = ((0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
        for c in conn:
            fs = [[c[i] for i in h] for h in hexf] if len(c) == 8 else [c[:j] + c[j + 1:] for j in range(len(c))]
            for f in fs:
                f = tuple(sorted(f))
                faces[f] = faces.get(f, 0) + 1
        sets["boundary"] = {n for f, k in faces.items() if k == 1 for n in f}
        order.append("boundary")
    return {"dim": dim, "etype": etype, "nv": len(conn[0]), "x": x, "conn": conn,
            "mats": mats, "mat": mat, "sets": {k: sorted(v) for k, v in sets.items()},
            "set_order": order, "tags": [e[0] for e in els]}


def retag(src, dst, fnode, felem):
    """copy the ASCII MSH 4.1 file src to dst with node tag t -> fnode(t) and
    element tag t -> felem(t) (the maps must be injective and positive)"""
    lines = open(src).read().split("\n")
    out, i = [], 0
    while i < len(lines):
        s = lines[i]
        out.append(s)
        i += 1
        if s.strip() == "$Nodes":
            nb, n, _, _ = (int(v) for v in lines[i].split())
            i += 1
            head, body = len(out), []
            tags = []
            for b in range(nb):
                body.append(lines[i])
                k = int(lines[i].split()[3])
                i += 1
                for j in range(k):
                    t = fnode(int(lines[i + j]))
                    tags.append(t)
                    body.append(str(t))
                body.extend(lines[i + k:i + 2 * k])
                i += 2 * k
            out.append("%d %d %d %d" % (nb, n, min(tags), max(tags)))
            out.extend(body)
            assert head
        elif s.strip() == "$Elements":
            nb, n, _, _ = (int(v) for v in lines[i].split())
            i += 1
            body, tags = [], []
            for b in range(nb):
                body.append(lines[i])
                k = int(lines[i].split()[3])
                i += 1
                for j in range(k):
                    v = [int(x) for x in lines[i + j].split()]
                    tags.append(felem(v[0]))
                    body.append(" ".join(str(x) for x in [felem(v[0])] + [fnode(y) for y in v[1:]]) + " ")
                i += k
            out.append("%d %d %d %d" % (nb, n, min(tags), max(tags)))
            out.extend(body)
    open(dst, "w").write("\n".join(out))


if __name__ == "__main__":
    import sys
    # msh41.py retag SRC DST a b c d: node tag t -> a*t + b (or a*(max+1-t) + b when a < 0), same for elements with c d
    if len(sys.argv) == 8 and sys.argv[1] == "retag":
        a, b, c, d = (int(v) for v in sys.argv[4:8])
        m = read(sys.argv[2])
        nmax = max(m["nodes"])
        emax = max(e[0] for e in m["elems"])
        retag(sys.argv[2], sys.argv[3],
              lambda t: a * t + b if a > 0 else -a * (nmax + 1 - t) + b,
              lambda t: c * t + d if c > 0 else -c * (emax + 1 - t) + d)
    else:
        sys.exit("usage: msh41.py retag SRC DST a b c d")
