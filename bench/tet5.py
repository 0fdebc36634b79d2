"""The beam and brick scenes (scenes/beam.geo, scenes/brick.geo) with every
cubic cell split into 5 tets instead of gmsh's 6 (the split the papers' counts
imply: 81,840 tets at beam h=1024, 80,000 at brick N=20), as gmsh MSH 4.1
ASCII with the same physical groups.
  tet5.py beam H OUT    5 x 5 x H nodes, unit spacing, fixed z = 0, tip z = H-1
  tet5.py brick N OUT   (N+1)^2 (2N+1) nodes on [0,1]^2 x [0,2], fixed z = 0, top z = 2
Cells alternate between the split and its mirror image in x ((i+j+k) odd), so
that neighbouring cells share their face diagonals (a conforming mesh): the
corner tets at 000, 110, 101, 011 and the central tet 100, 010, 001, 111."""
import sys

CANON = [((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)),
         ((1, 1, 0), (0, 1, 0), (1, 0, 0), (1, 1, 1)),
         ((1, 0, 1), (1, 0, 0), (0, 0, 1), (1, 1, 1)),
         ((0, 1, 1), (0, 1, 0), (0, 0, 1), (1, 1, 1)),
         ((1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1))]


def grid(nx, ny, nz, hx, hy, hz):
    def nid(i, j, k):
        return 1 + i + (nx + 1) * (j + (ny + 1) * k)
    xyz = [(i * hx, j * hy, k * hz) for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)]
    tets = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                odd = (i + j + k) % 2
                for t in CANON:
                    c = [nid(i + (1 - a if odd else a), j + b, k + cc) for a, b, cc in t]
                    p = [xyz[q - 1] for q in c]
                    u = [p[1][d] - p[0][d] for d in range(3)]
                    v = [p[2][d] - p[0][d] for d in range(3)]
                    w = [p[3][d] - p[0][d] for d in range(3)]
                    det = (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                           u[2] * (v[0] * w[1] - v[1] * w[0]))
                    if det < 0:
                        c[1], c[2] = c[2], c[1]
                    tets.append(c)
    return xyz, tets


def faces_on(xyz, tets, z):
    out = []
    for t in tets:
        for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
            tri = [t[q] for q in f]
            if all(xyz[q - 1][2] == z for q in tri):
                out.append(tri)
    return out


def write(path, xyz, tets, names, ztop):
    lo = [min(p[d] for p in xyz) for d in range(3)]
    hi = [max(p[d] for p in xyz) for d in range(3)]
    fix, top = faces_on(xyz, tets, 0.0), faces_on(xyz, tets, ztop)
    with open(path, "w") as f:
        f.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n")
        f.write('2 1 "%s"\n2 2 "%s"\n3 3 "%s"\n$EndPhysicalNames\n' % names)
        f.write("$Entities\n0 0 2 1\n")
        f.write("1 %g %g 0 %g %g 0 1 1 0\n" % (lo[0], lo[1], hi[0], hi[1]))
        f.write("2 %g %g %g %g %g %g 1 2 0\n" % (lo[0], lo[1], ztop, hi[0], hi[1], ztop))
        f.write("1 %g %g %g %g %g %g 1 3 0\n$EndEntities\n" % (lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]))
        n = len(xyz)
        f.write("$Nodes\n1 %d 1 %d\n3 1 0 %d\n" % (n, n, n))
        f.write("".join("%d\n" % (q + 1) for q in range(n)))
        f.write("".join("%.17g %.17g %.17g\n" % p for p in xyz))
        f.write("$EndNodes\n$Elements\n")
        ne = len(fix) + len(top) + len(tets)
        f.write("3 %d 1 %d\n" % (ne, ne))
        e = 1
        for dim, tag, typ, els in ((2, 1, 2, fix), (2, 2, 2, top), (3, 1, 4, tets)):
            f.write("%d %d %d %d\n" % (dim, tag, typ, len(els)))
            for c in els:
                f.write("%d %s\n" % (e, " ".join(map(str, c))))
                e += 1
        f.write("$EndElements\n")


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("beam", "brick"):
        sys.exit(__doc__)
    kind, size, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    if kind == "beam":
        xyz, tets = grid(4, 4, size - 1, 1.0, 1.0, 1.0)
        write(out, xyz, tets, ("fixed", "tip", "beam"), float(size - 1))
    else:
        xyz, tets = grid(size, size, 2 * size, 1.0 / size, 1.0 / size, 2.0 / (2 * size))
        write(out, xyz, tets, ("fixed", "top", "brick"), max(p[2] for p in xyz))
    print("%s: %d nodes, %d tets" % (out, len(xyz), len(tets)), file=sys.stderr)


main()
