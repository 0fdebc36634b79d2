"""Conformity of a mesh with cuts, for the test oracles: faces (edges of
tri3, triangles of tet4, quadrilaterals of hex8) in at most two elements with opposite
orientations; an open face (in one element) must lie on the outer boundary
of the uncut mesh or be one side of a cut, its other side a coincident open
face with the opposite orientation. A hanging node (T-junction) leaves an
open face that is neither."""
import math

# faces of a positive element, each oriented outward (tri3: edges counter-clockwise)
TRI = ((0, 1), (1, 2), (2, 0))
TET = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))
# gmsh hexahedron: bottom 0 1 2 3 counter-clockwise seen from above, top 4 5 6 7 above them
HEX = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))


def faces_of(c):
    return [tuple(c[i] for i in f) for f in {3: TRI, 4: TET, 8: HEX}[len(c)]]


def parity(f):
    """orientation of a face given by its nodes: the parity of the permutation
    sorting them (a quadrilateral: whether it runs from its least node towards
    the lesser of that node's two neighbours)"""
    if len(f) == 2:
        return f[0] > f[1]
    if len(f) == 4:
        i = f.index(min(f))
        return f[(i + 1) % 4] > f[(i + 3) % 4]
    return ((f[0] > f[1]) + (f[0] > f[2]) + (f[1] > f[2])) & 1


def same_cycle(f, g):
    """g is f up to a cyclic rotation"""
    return any(tuple(g[(i + k) % len(g)] for i in range(len(g))) == f for k in range(len(g)))


def face_map(conn):
    """{sorted node tuple: [(element, oriented face)]}"""
    fm = {}
    add = fm.setdefault
    for e, c in enumerate(conn):
        if len(c) == 3:
            a, b, d = c
            for f in ((a, b), (b, d), (d, a)):
                add(f if f[0] < f[1] else (f[1], f[0]), []).append((e, f))
        elif len(c) == 8:
            for f in faces_of(c):
                add(tuple(sorted(f)), []).append((e, f))
        else:
            a, b, d, g = c
            for f in ((b, d, g), (a, g, d), (a, b, g), (a, d, b)):
                add(tuple(sorted(f)), []).append((e, f))
    return fm


def shared_errors(fm):
    """the first face in three or more elements, or in two with one orientation"""
    for key, uses in fm.items():
        if len(uses) > 2:
            return "face %s in %d elements" % (key, len(uses))
        if len(uses) == 2 and parity(uses[0][1]) == parity(uses[1][1]):
            return "face %s in elements %d and %d with one orientation (they overlap)" % (key, uses[0][0], uses[1][0])
    return None


def geo_key(x, f):
    return tuple(sorted(x[v] for v in f))



def star_classes(x, conn, elems, P, joined):
    """the elements elems (each with a corner at point P) in classes connected
    through their coincident faces at P: the elements es of one face are joined
    where joined(key, es, i) is true for es[0] and es[i]; returns
    [(class elements, {nodes of the class at P})] in order of the first element"""
    up = {e: e for e in elems}

    def root(e):
        while up[e] != e:
            up[e] = up[up[e]]
            e = up[e]
        return e
    byface = {}
    for e in elems:
        for f in faces_of(conn[e]):
            if any(x[v] == P for v in f):
                byface.setdefault(geo_key(x, f), []).append(e)
    for key, es in byface.items():
        for i in range(1, len(es)):
            if joined(key, es, i):
                a, b = root(es[0]), root(es[i])
                up[max(a, b)] = min(a, b)
    classes = {}
    for e in elems:
        classes.setdefault(root(e), []).append(e)
    return [(es, {v for e in es for v in conn[e] if x[v] == P}) for r, es in sorted(classes.items())]

class FaceIndex:
    """faces given by their corner coordinates, for 'does this face lie in one
    of them' (points within tol of the face's line or plane and inside it)"""

    def __init__(self, polys, tol):
        self.polys, self.tol, self.grid, self.memo = polys, tol, {}, {}
        pts = [p for q in polys for p in q] or [(0.0, 0.0, 0.0)]
        dim = len(pts[0])
        self.lo = [min(p[k] for p in pts) for k in range(dim)]
        span = max(max(p[k] for p in pts) - self.lo[k] for k in range(dim)) or 1.0
        self.h = span / 32
        for i, q in enumerate(polys):
            a = self.cell([min(p[k] for p in q) for k in range(dim)])
            b = self.cell([max(p[k] for p in q) for k in range(dim)])
            for c in cells(a, b):
                self.grid.setdefault(c, []).append(i)

    def cell(self, p):
        return tuple(int(math.floor((p[k] - self.lo[k]) / self.h)) for k in range(len(p)))

    def find(self, pts):
        """index of a face holding every point of pts, or -1"""
        key = tuple(pts)
        if key not in self.memo:
            self.memo[key] = self.search(pts)
        return self.memo[key]

    def cover(self, pts):
        """the points of pts (tuples) lying in some face"""
        grid = {}
        for p in pts:
            grid.setdefault(self.cell(p), []).append(p)
        out = set()
        for i, q in enumerate(self.polys):
            a = self.cell([min(p[k] for p in q) for k in range(len(q[0]))])
            b = self.cell([max(p[k] for p in q) for k in range(len(q[0]))])
            for c in cells(tuple(v - 1 for v in a), tuple(v + 1 for v in b)):
                out.update(p for p in grid.get(c, ()) if p not in out and inside(p, q, self.tol))
        return out

    def search(self, pts):
        c = self.cell(pts[0])
        seen = set()
        for d in cells(tuple(v - 1 for v in c), tuple(v + 1 for v in c)):
            for i in self.grid.get(d, ()):
                if i not in seen:
                    seen.add(i)
                    if all(inside(p, self.polys[i], self.tol) for p in pts):
                        return i
        return -1


def cells(a, b):
    out = [()]
    for k in range(len(a)):
        out = [c + (v,) for c in out for v in range(a[k], b[k] + 1)]
    return out


def sub(p, q):
    return [p[k] - q[k] for k in range(len(p))]


def dot(u, v):
    return sum(u[k] * v[k] for k in range(len(u)))


def inside(p, q, tol):
    """p within tol of the segment (2 corners), triangle (3 corners) or plane
    quadrilateral (4 corners in cyclic order: its two triangles) q"""
    if len(q) == 4:
        return inside(p, q[:3], tol) or inside(p, [q[0], q[2], q[3]], tol)
    if len(q) == 2:
        u, w = sub(q[1], q[0]), sub(p, q[0])
        L2 = dot(u, u)
        t = dot(w, u) / L2
        d = [w[k] - t * u[k] for k in range(len(u))]
        return dot(d, d) <= tol * tol and -tol <= t * math.sqrt(L2) <= math.sqrt(L2) + tol
    u, v, w = sub(q[1], q[0]), sub(q[2], q[0]), sub(p, q[0])
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    nn = math.sqrt(dot(n, n))
    if abs(dot(w, n)) > tol * nn:
        return False
    # barycentric coordinates in the plane
    uu, uv, vv, wu, wv = dot(u, u), dot(u, v), dot(v, v), dot(w, u), dot(w, v)
    den = uu * vv - uv * uv
    b1, b2 = (vv * wu - uv * wv) / den, (uu * wv - uv * wu) / den
    h = tol * math.sqrt(max(uu, vv, dot(sub(v, u), sub(v, u)))) / nn  # tol over the least altitude
    return b1 >= -h and b2 >= -h and b1 + b2 <= 1 + h


def boundary_index(x, conn, tol):
    """FaceIndex of the open faces of an uncut mesh: its outer boundary"""
    fm = face_map(conn)
    return FaceIndex([[x[v] for v in uses[0][1]] for uses in fm.values() if len(uses) == 1], tol)


def open_faces(x, fm, outer, origin, on_cut=None):
    """the open faces of the mesh: (cut pairs {geo key: (elem1, face1, elem2, face2)},
    first error or None). outer: FaceIndex of the uncut boundary; origin[v]:
    the node v is a copy of (itself if none); two sides of a cut coincide,
    have opposite orientations and nodes of one origin at each point. With
    on_cut(points), an open face on the cut may lack its other side (a path cut
    that split the edge on one side only)."""
    side = {}
    for key, uses in fm.items():
        if len(uses) != 1:
            continue
        e, f = uses[0]
        pts = [x[v] for v in f]
        if outer.find(pts) >= 0:
            continue
        side.setdefault(geo_key(x, f), []).append((e, f))
    pairs = {}
    for g, s in side.items():
        if len(s) == 1 and on_cut and on_cut([x[v] for v in s[0][1]]):
            continue
        if len(s) != 2:
            e, f = s[0]
            return pairs, ("open face %s of element %d at %s is neither on the outer boundary nor one side of a cut"
                           " (a hanging node or a hole)" % (f, e, [x[v] for v in f]) if len(s) == 1 else
                           "%d open faces at %s" % (len(s), g))
        (e1, f1), (e2, f2) = s
        r2 = tuple(reversed(f2))
        k = next((k for k in range(len(f1)) if all(x[f1[i]] == x[r2[(i + k) % len(f1)]] for i in range(len(f1)))), -1)
        if k < 0:
            return pairs, "the two sides %s, %s of a cut at %s have one orientation" % (f1, f2, g)
        for i in range(len(f1)):
            if origin[f1[i]] != origin[r2[(i + k) % len(f1)]]:
                return pairs, "nodes %d and %d face each other across a cut but are no copies of one node" % (
                    f1[i], r2[(i + k) % len(f1)])
        pairs[g] = (e1, f1, e2, f2)
    return pairs, None
