#!/usr/bin/env python3
"""Independent check of a cut stream (formats/stream.md 7.1, 7.2, 7.6, 7.7;
cut(1)), written from the specification only.

usage: check_cut.py IN.aug OUT.aug

IN: an uncut stream (meshload, perhaps factor); OUT: IN through one or more
cuts, whose command lines (their pROv records) say what each step must do.
- every record of IN but HEAD and TAIL is in OUT byte for byte, in order,
  right after HEAD and the cut stages' pROv; then one pLAN (4.4) whose steps
  are the stages' (first = the input's last step + 1, last = first - 1 +
  the sum of their --steps: a second cut extends the first one's plan in
  place); then per step MDLT [BDLT] UPDT pATH (ancillary sTAt/tIMe
  allowed), steps consecutive;
- at every step, on the mesh rebuilt from MDLT/BDLT: every element positive,
  the volume (area) unchanged, true conformity (a face in at most two elements
  with opposite orientations; an open face on the outer boundary of IN's mesh
  or one side of a cut whose other side is a coincident open face of nodes
  that are copies of the same nodes: no hanging node);
- the requested nodes were duplicated. Planar cuts (--plane, random planes
  drawn again from the seed as GSL's mt19937 does, --polygon applied): the
  step's parents are exactly the next --per-step K cut nodes in advance order
  (nodes of the faces between elements whose centroids lie on the two sides,
  within one longest edge of the plane), each copy at its parent, the star of
  each split into its classes along the cut faces with the - side keeping
  the node and one copy per other class, only those nodes re-wired, and the
  faces it opens exactly the cut faces at the duplicated nodes (pATH = their
  edges). Path cuts (--path, the path file read here): every pATH point
  within one longest edge of the step's part of the path, pATH not empty
  where that part runs more than three longest edges deep inside the mesh,
  copies on a cut segment, inserted nodes on the step's segments next to
  their parent, every pATH segment a mesh edge, and at every node on the cut
  so far its star split into classes along the cut edges, one node a class;
- a step that drops a piece (MDLT flag 4) separates it first (7.1): a
  face-connected piece holding a node the step's BDLT constrains in full,
  whose own nodes are all constrained in full, holds no node of another
  element; the copies that separate it follow the cut's own (planar: after
  the copies of the cut nodes), each at its parent, constrained in full and
  held only by such pieces; a cut node a drop split already needs no copy;
- K_t and f_t accumulated from K_0 (KMAT of IN, or assembled here when IN has
  none) and the UPDT records (k = dim * new nodes) equal the cut system
  assembled here (tet4, hex8, tri3 plane stress) on the step's mesh at every step,
  entry by entry within 1e-12 * max|K|: the sum of the element terms of every
  element, summed afresh at the first and the last step, in between with the
  terms of every element whose nodes, material or constraints changed
  replaced (cutsys.CutMesh.element_sum). K_0 of IN is checked the same.
Prints one line 'ok steps=S ...' or the first failure ('FAIL step N: ...'),
exit 1."""
import math
import os
import random
import struct
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import conform  # noqa: E402
import cutsys  # noqa: E402
import pathfile  # noqa: E402

SIG = b"\x89AUG\r\n\x1a\n"
REL = 1e-12


def raw_records(data):
    """[(type, step, payload, body)] with the exact body bytes"""
    if data[:8] != SIG:
        raise SystemExit("bad signature")
    pos, out = 8, []
    while pos < len(data):
        n, = struct.unpack_from("<Q", data, pos)
        typ = data[pos + 8:pos + 12].decode()
        body = data[pos + 12:pos + 12 + n]
        flags, step, rawlen = struct.unpack_from("<IiQ", body, 0)
        p = body[16:]
        if flags & 1:
            p = zlib.decompress(p)
        out.append((typ, step, p, body))
        pos += 16 + n
    return out


def fail(msg):
    print("FAIL " + msg)
    sys.exit(1)


def stage_of(prov):
    """the options of one cut command line (pROv: version line, argv)"""
    args = prov.split("\n", 1)[1].split(" ")[1:]
    valued = {"--plane", "--advance", "--polygon", "--per-step", "--seed", "--path", "--mode", "--snap-tol",
              "--steps", "--pull", "--detached", "--constrain"}
    o, i = {}, 0
    while i < len(args):
        a = args[i]
        if "=" in a and a.startswith("--"):
            k, v = a.split("=", 1)
        elif a in valued:
            k, v = a, args[i + 1]
            i += 1
        else:
            k, v = a, ""
        o[k] = v
        i += 1
    return o


def gsl_uniform(seed):
    """gsl_rng_uniform of GSL's mt19937 seeded with gsl_rng_set(r, seed)"""
    s = seed or 4357
    mt = [s & 0xffffffff]
    for i in range(1, 624):
        mt.append((1812433253 * (mt[-1] ^ (mt[-1] >> 30)) + i) & 0xffffffff)
    r = random.Random()
    r.setstate((3, tuple(mt) + (624,), None))
    return lambda: r.getrandbits(32) / 4294967296.0


def random_plane(x, dim, seed):
    """cut(1) --plane random: a normal uniform on the sphere (circle) through a
    point of the middle half of the bounding box"""
    u = gsl_uniform(seed)
    lo = [min(p[k] for p in x) for k in range(dim)]
    hi = [max(p[k] for p in x) for k in range(dim)]
    while True:
        n = [2 * u() - 1 if k < dim else 0.0 for k in range(3)]
        s = n[0] * n[0] + n[1] * n[1] + n[2] * n[2]
        if not (s > 1 or s < 1e-4):
            break
    d = 0.0
    for k in range(dim):
        n[k] /= math.sqrt(s)
        d += n[k] * (lo[k] + (0.25 + 0.5 * u()) * (hi[k] - lo[k]))
    return n[:dim], d


def seg_dist(a, b, p):
    """distance of p to the segment ab"""
    e = [b[k] - a[k] for k in range(len(p))]
    ee = sum(c * c for c in e)
    t = max(0.0, min(1.0, sum((p[k] - a[k]) * e[k] for k in range(len(p))) / ee)) if ee > 0 else 0.0
    return math.dist(p, [a[k] + t * e[k] for k in range(len(p))])


def dot(a, b):
    s = 0.0
    for k in range(len(a)):
        s += a[k] * b[k]
    return s


def in_plane(n, v, scale):
    """v without its normal component, normalised; None when it (nearly) vanishes"""
    vn = dot(v, n)
    out = [v[k] - vn * n[k] for k in range(len(n))]
    s = math.sqrt(dot(out, out))
    return [c / s for c in out] if s > 1e-9 * scale else None


def polygon_nodes(n, poly, x, nodes):
    """cut(1) --polygon: the nodes whose projection onto the plane lies inside
    the projected polygon (even-odd rule; within 1e-9 of its size of an edge
    counts as inside)"""
    ax = min(range(3), key=lambda k: abs(n[k]))
    u = [(1.0 if k == ax else 0.0) - n[ax] * n[k] for k in range(3)]
    u = [c / math.sqrt(dot(u, u)) for c in u]
    v = [n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]]
    q = [(dot(poly[i:i + 3], u), dot(poly[i:i + 3], v)) for i in range(0, len(poly), 3)]
    tol = 1e-9 * max(math.dist(a, q[0]) for a in q)

    def inside(p):
        c = False
        for i in range(len(q)):
            a, b = q[i], q[i - 1]
            e = (b[0] - a[0], b[1] - a[1])
            ee = e[0] ** 2 + e[1] ** 2  # 0: a repeated vertex (in projection)
            t = max(0.0, min(1.0, ((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / ee)) if ee > 0 else 0.0
            if math.dist(p, (a[0] + t * e[0], a[1] + t * e[1])) <= tol:
                return True
            if (a[1] > p[1]) != (b[1] > p[1]) and p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]:
                c = not c
        return c
    return [i for i in nodes if inside((dot(x[i], u), dot(x[i], v)))]


class Plane:
    """a planar cut stage planned on the mesh at its start (cut(1)): sides by
    centroid, cut nodes in advance order, K per step"""

    def __init__(self, cm, o):
        dim, nv, x = cm.dim, cm.nv, cm.x
        if o["--plane"] == "random":
            n, d = random_plane(x, dim, int(o.get("--seed", "1")))
        else:
            v = [float(t) for t in o["--plane"].split(",")]
            n, d = v[:dim], v[3]
        ln = math.sqrt(dot(n, n))
        self.n, self.d = [c / ln for c in n], d / ln
        self.ne = len(cm.conn)
        self.side, self.ambiguous = [], 0
        for c in cm.conn:
            cen = [0.0] * dim
            for a in range(nv):
                for k in range(dim):
                    cen[k] += x[c[a]][k] / nv
            s = dot(cen, self.n)
            self.side.append(s > self.d)
            self.ambiguous += abs(s - self.d) <= 1e-12
        fm = conform.face_map(cm.conn)
        mark = set()
        for key, uses in fm.items():
            if len(uses) == 2 and self.side[uses[0][0]] != self.side[uses[1][0]]:
                mark.update(key)
        lo = [min(p[k] for p in x) for k in range(dim)]
        hi = [max(p[k] for p in x) for k in range(dim)]
        scale = math.sqrt(sum((hi[k] - lo[k]) ** 2 for k in range(dim))) or 1.0
        cut = sorted(mark)
        adv = None
        if "--advance" in o:
            adv = in_plane(self.n, [float(t) for t in o["--advance"].split(",")][:dim], 1.0)
        else:
            fixed = sorted({dof // dim for dof in cm.fix})
            cc = [sum(x[i][k] for i in cut) / len(cut) for k in range(dim)]
            if fixed:
                cf = [sum(x[i][k] for i in fixed) / len(fixed) for k in range(dim)]
                adv = in_plane(self.n, [cc[k] - cf[k] for k in range(dim)], scale)
            if adv is None:
                best = -1
                for ax in range(dim):
                    a = in_plane(self.n, [1.0 if k == ax else 0.0 for k in range(dim)], 1.0)
                    if a is None:
                        continue
                    s = [dot(x[i], a) for i in cut]
                    if max(s) - min(s) > best * (1 + 1e-12):
                        best, adv = max(s) - min(s), a
        q = 1e-9 * scale
        self.order = sorted(cut, key=lambda i: (int(math.floor(dot(x[i], adv) / q + 0.5)), i))
        if "--polygon" in o:
            self.order = polygon_nodes(self.n, [float(t) for t in o["--polygon"].split(",")], x, self.order)
        self.per = int(o["--per-step"]) if "--per-step" in o else (len(self.order) + 63) // 64
        self.next = 0
        self.cutset = mark

    def rank(self, e):
        return (self.side[e] if e < self.ne else 1, e)

    def cut_face(self, e1, e2):
        return e1 < self.ne and e2 < self.ne and self.side[e1] != self.side[e2]


class Checker:
    def __init__(self, m):
        self.cm = cutsys.CutMesh(m)
        cm = self.cm
        self.dim, self.nv = cm.dim, cm.nv
        lo = [min(p[k] for p in cm.x) for k in range(self.dim)]
        hi = [max(p[k] for p in cm.x) for k in range(self.dim)]
        self.tol = 1e-10 * max(hi[k] - lo[k] for k in range(self.dim))
        self.outer = conform.boundary_index(cm.x, cm.conn, self.tol)
        self.h = max(math.dist(cm.x[c[i]], cm.x[c[j]]) for c in cm.conn for i in range(self.nv) for j in range(i))
        self.origin = list(range(len(cm.x)))
        self.vol0 = self.volume()
        self.pairs, self.inserted = {}, {}
        self.fm = conform.face_map(cm.conn)
        self.segs = []  # cut segments of the path stages so far
        self.any_drop = False  # a step so far dropped a piece (flag 4)
        self.cutidx = None
        self.step = 0

    def volume(self):
        cm = self.cm
        mesh = {"x": cm.x, "conn": cm.conn, "nv": self.nv}
        vols = [augstream.measure(mesh, e) for e in range(len(cm.conn))]
        e = min(range(len(vols)), key=vols.__getitem__)
        if not vols[e] > 0:
            self.fail("element %d has measure %g" % (e, vols[e]))
        return sum(vols)

    def fail(self, msg):
        fail("step %d: %s" % (self.step, msg))

    def check_dropped(self, fm):
        """a dropped piece shares no node with the rest of the mesh (7.1): of
        the face-connected pieces at a node the step's BDLT constrains in full
        (self.newly), one whose own nodes are all constrained in full (a
        dropped piece, not a region --constrain holds inside the body nor a
        pinned one) holds no node of another element (else, fixed, it still
        hangs on the body and holds it there by its stiffness); its elements
        are self.dropped"""
        self.dropped = set()
        if not self.newly:
            return
        conn = self.cm.conn
        root = list(range(len(conn)))

        def find(a):
            while root[a] != a:
                root[a] = root[root[a]]
                a = root[a]
            return a
        for uses in fm.values():
            if len(uses) == 2:
                a, b = find(uses[0][0]), find(uses[1][0])
                if a != b:
                    root[a] = b
        pieces = {}
        for e in range(len(conn)):
            pieces.setdefault(find(e), []).append(e)
        users = {}
        for e, c in enumerate(conn):
            for v in c:
                users.setdefault(v, set()).add(find(e))
        for els in pieces.values():
            nodes = {v for e in els for v in conn[e]}
            if not nodes & self.newly:
                continue
            own = [v for v in nodes if len(users[v]) == 1]
            if not own or not all(self.held(v) for v in own):
                continue
            shared = sorted(v for v in nodes if len(users[v]) > 1)
            if shared:
                self.fail("element %d of a dropped piece holds node %d, which other elements hold too: "
                          "the piece still hangs on the mesh" % (els[0], shared[0]))
            self.dropped.update(els)

    def held(self, v):
        """every component of node v constrained"""
        return all(v * self.dim + c in self.cm.fix for c in range(self.dim))

    def drop_copy(self, v, p, node_elems):
        """new node v (parent p) that separates a dropped piece (formats 7.1): at
        its parent, constrained in full, held only by the step's dropped elements"""
        if self.cm.x[v] != self.cm.x[p] or not self.held(v):
            return False
        es = node_elems.get(v, ())
        return bool(es) and all(e in self.dropped for e in es)

    def star_classes(self, P, cut, node_elems, at, elems=None):
        """the elements with a corner at point P (or those of elems), in classes
        connected through coincident faces at P that cut(key, e1, e2) does not
        report: [(class elements, node of the class at P)]; fails where one
        class has two nodes at P or two classes one node"""
        x, conn = self.cm.x, self.cm.conn
        if elems is None:
            elems = sorted({e for v in at[P] for e in node_elems.get(v, ())})
        classes = conform.star_classes(x, conn, elems, P, lambda key, es, i: not cut(key, es[0], es[i]))
        out, used = [], {}
        for es, nodes in classes:
            if len(nodes) != 1:
                self.fail("at %s the elements %s hang together across uncut faces but hold the nodes %s"
                          % (P, es[:6], sorted(nodes)))
            v = nodes.pop()
            if v in used:
                self.fail("node %d at %s is shared by elements %d and %d, which the cut separates"
                          % (v, P, used[v], es[0]))
            used[v] = es[0]
            out.append((es, v))
        return out

    def adjacency(self):
        x = self.cm.x
        node_elems, at = {}, {}
        for e, c in enumerate(self.cm.conn):
            for v in c:
                node_elems.setdefault(v, []).append(e)
        for v, p in enumerate(x):
            at.setdefault(p, []).append(v)
        return node_elems, at

    def plane_step(self, pl, d, conn_before, fm_before, pairs_before, seg):
        """the step duplicated the next K cut nodes of the plane, each as cut(1) says"""
        x, conn = self.cm.x, self.cm.conn
        nn0 = len(x) - len(d["parent"])
        want = sorted(pl.order[pl.next:pl.next + pl.per])
        wanted = set(want)
        # on a drop step, after the cut's copies (of the cut nodes), the copies
        # that separate the dropped pieces (of nodes the cut did not reach)
        node_elems, at = self.adjacency()
        ncut = len(d["parent"])
        if d["flags"] & 4:
            ncut = next((q for q, p in enumerate(d["parent"]) if p not in wanted), ncut)
            for q in range(ncut, len(d["parent"])):
                p = d["parent"][q]
                if p in wanted or not self.drop_copy(nn0 + q, p, node_elems):
                    self.fail("new node %d (parent %d) is neither a copy of a cut node nor one that "
                              "separates a dropped piece" % (nn0 + q, p))
        parents = sorted(set(d["parent"][:ncut]))
        for q, p in enumerate(d["parent"][:ncut]):
            if p >= nn0 or x[nn0 + q] != x[p]:
                self.fail("new node %d is no copy of a node of the mesh before the step (parent %d)" % (nn0 + q, p))
            if p not in pl.cutset:
                self.fail("node %d is duplicated but lies on no face between the two sides of the plane" % p)
            if abs(dot(x[p], pl.n) - pl.d) > self.h:
                self.fail("node %d is duplicated %g away from the plane" % (p, abs(dot(x[p], pl.n) - pl.d)))
        if d["cadd"]:
            self.fail("a planar cut adds %d elements" % len(d["cadd"]))
        # a cut node that an earlier drop separated may need no copy (its star
        # then holds one class, checked below); else each of the next K has copies
        if not self.any_drop and len(parents) != min(pl.per, len(pl.order) - pl.next):
            self.fail("%d nodes duplicated, --per-step asks for %d" % (len(parents), pl.per))
        if parents != want and not (self.any_drop and set(parents) <= wanted):
            self.fail("duplicated nodes %s, the next cut nodes in advance order are %s%s" % (
                parents, want, " (%d element centroids within 1e-12 of the plane)" % pl.ambiguous if pl.ambiguous else ""))
        pl.next += len(want)
        # the star of each parent: classes along the cut faces, the - side keeps the node

        def cut(key, e1, e2):
            return pl.cut_face(e1, e2) or key in pairs_before
        copies = {}
        for q, p in enumerate(d["parent"][:ncut]):
            copies.setdefault(p, []).append(nn0 + q)
        for p in want:
            star = [e for e in range(len(conn_before)) if p in conn_before[e]]
            cl = self.star_classes(x[p], cut, node_elems, at, star)
            keep = min(cl, key=lambda c: min(pl.rank(e) for e in c[0]))
            if keep[1] != p:
                self.fail("node %d: the class of element %d (the - side) does not keep it" % (p, keep[0][0]))
            if sorted(v for _, v in cl if v != p) != copies.get(p, []):
                self.fail("node %d: %d classes around it, copies %s" % (p, len(cl), copies[p]))
        cmap = {nn0 + q: p for q, p in enumerate(d["parent"])}

        def origin(v):
            while v in cmap:
                v = cmap[v]
            return v
        for e in d["elem"]:
            if tuple(origin(v) for v in conn[e]) != conn_before[e]:
                self.fail("element %d re-wired from %s to %s, not to copies of its nodes" % (e, conn_before[e], conn[e]))
        # the faces the step opens: the cut faces at the duplicated nodes, still closed before
        new_pairs = [g for g in self.pairs if g not in pairs_before]
        opened = {}
        for key, uses in fm_before.items():
            if len(uses) == 2 and pl.cut_face(uses[0][0], uses[1][0]) and any(v in copies for v in key):
                opened[conform.geo_key(x, key)] = [x[v] for v in uses[0][1]]
        if set(new_pairs) != set(opened):
            extra = sorted(set(new_pairs) - set(opened))[:1] or sorted(set(opened) - set(new_pairs))[:1]
            self.fail("opened %d faces, the cut faces at the duplicated nodes are %d (e.g. %s)"
                      % (len(new_pairs), len(opened), extra))
        edges = set()
        for f in opened.values():  # the edges of a face: its sides (every pair of a triangle)
            for i in range(len(f)):
                for j in range(i + 1, len(f)):
                    if len(f) < 4 or j == i + 1 or (i, j) == (0, 3):
                        edges.add(tuple(sorted((f[i], f[j]))))
        got = [tuple(sorted(s)) for s in seg]
        if len(set(got)) != len(got) or set(got) != edges:
            self.fail("pATH has %d segments (%d distinct), the opened faces %d edges"
                      % (len(got), len(set(got)), len(edges)))

    def path_part(self, path, s0, s1, seg):
        """the step's pATH against its part of the path (arc length s0..s1):
        every end point within one longest edge of it, and segments wherever the
        part runs more than three longest edges deep inside the mesh"""
        h = self.h
        near = path.part(s0 - h, s1 + h)
        for q in [p for sg in seg for p in sg]:
            if not near or min(math.dist(q, p) for p in near) > 1.05 * h + self.tol:
                self.fail("pATH point %s is farther than %g from the path's part %.4g..%.4g" % (q, h, s0, s1))
        if seg:
            return
        bd = [b for b in self.outer.polys]
        pts = path.part(s0, s1)[::max(1, int(h / 4 / (path.total / max(len(path.pts), 1)) + 0.5))]

        def deep(p):
            c = False
            for a, b in bd:
                if (a[1] > p[1]) != (b[1] > p[1]) and p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]:
                    c = not c
            return c and all(seg_dist(a, b, p) > h for a, b in bd)
        run = sum(math.dist(p, q) for p, q in zip(pts, pts[1:]) if math.dist(p, q) < h / 2 and deep(p) and deep(q))
        if run > 3 * h:
            self.fail("the path's part %.4g..%.4g runs %.3g deep inside the mesh, but pATH is empty" % (s0, s1, run))

    def path_step(self, d, pairs_before, seg, fm):
        def on_segment(a, b, q, tol):
            ab = [bi - ai for ai, bi in zip(a, b)]
            L2 = sum(c * c for c in ab)
            t = sum((qi - ai) * c for ai, qi, c in zip(a, q, ab)) / L2 if L2 > 0 else 0.0
            t = min(1.0, max(0.0, t))
            return math.dist(q, [ai + t * c for ai, c in zip(a, ab)]) <= tol
        """copies on the cut, inserted nodes on its segments, every node on the
        cut separated into one node per class of its star"""
        x = self.cm.x
        nn0 = len(x) - len(d["parent"])
        cutidx = self.cutidx
        stepidx = conform.FaceIndex([list(s) for s in seg], self.tol)
        keys = {conform.geo_key(x, f) for f in fm}
        for s in seg:
            if tuple(sorted(s)) not in keys:
                self.fail("pATH segment %s is no edge of the mesh" % (s,))
        node_elems, at = self.adjacency()
        for q, p in enumerate(d["parent"]):
            v = nn0 + q
            if x[v] == x[p]:
                if cutidx.find([x[v]]) < 0 and not (d["flags"] & 4 and self.drop_copy(v, p, node_elems)):
                    self.fail("node %d is duplicated (copy %d) but lies on no cut segment" % (p, v))
                continue
            if stepidx.find([x[v]]) < 0:
                self.fail("inserted node %d at %s lies on no pATH segment of the step" % (v, x[v]))
            # formats 7.1: the parent is an end (corner) of the edge (triangle)
            # the split cut; an edge the step split twice (a path crossing it
            # twice) leaves the other split node between the first and that
            # end: the walk goes on through the step's inserted nodes on the
            # segment from v to its parent
            seen, todo, near = {v}, [v], set()
            while todo:
                u0 = todo.pop()
                for u in at[x[u0]]:
                    for e in node_elems.get(u, ()):
                        for w in self.cm.conn[e]:
                            near.add(self.origin[w])
                            if w >= nn0 and w not in seen and x[w] != x[d["parent"][w - nn0]] \
                                    and on_segment(x[v], x[p], x[w], self.tol):
                                seen.add(w)
                                todo.append(w)
            if self.origin[p] not in near:
                self.fail("inserted node %d: its parent %d is no corner next to it" % (v, p))

        for g in self.pairs:
            if cutidx.find(list(g)) < 0:
                self.fail("the mesh is open at %s, which lies on no cut segment" % (g,))

        def cut(key, e1, e2):
            return key in pairs_before or cutidx.find(list(key)) >= 0
        for P in sorted(cutidx.cover(list(at))):
            cl = self.star_classes(P, cut, node_elems, at)
            if len(cl) != len(at[P]):
                self.fail("at %s %d nodes, %d of them in no element" % (P, len(at[P]), len(at[P]) - len(cl)))

    def run_step(self, rec, stage):
        cm, dim, nv = self.cm, self.dim, self.nv
        try:
            d = cutsys.mdlt(rec["MDLT"], dim, nv)
        except (cutsys.Bad, struct.error) as e:
            self.fail("MDLT: %s" % e)
        nn_before = len(cm.x)
        conn_before = list(cm.conn)
        fm_before = self.fm
        pairs_before = self.pairs
        try:
            cm.apply_mdlt(d)
            held = {v for v in range(len(cm.x)) if self.held(v)}
            if "BDLT" in rec:
                cm.apply_bdlt(cutsys.bdlt(rec["BDLT"]))
        except (cutsys.Bad, struct.error) as e:
            self.fail(str(e))
        self.newly = set()
        if d["flags"] & 4:
            self.any_drop = True
            self.newly = {v for v in range(len(cm.x)) if v not in held and self.held(v)}
        # a copy's origin is its parent's; nodes inserted at one point (on the two sides of a cut) share one
        for q, p in enumerate(d["parent"]):
            v = nn_before + q
            self.origin.append(self.origin[p] if cm.x[v] == cm.x[p] else self.inserted.setdefault(cm.x[v], v))
        p = rec["pATH"]
        pd, _, nseg = struct.unpack_from("<iiq", p, 0)
        if pd != dim or len(p) != 16 + nseg * 2 * dim * 8:
            self.fail("pATH layout")
        v, _ = cutsys.arr("d", p, 16, nseg * 2 * dim)
        seg = [(tuple(v[(2 * i) * dim:(2 * i + 1) * dim]), tuple(v[(2 * i + 1) * dim:(2 * i + 2) * dim]))
               for i in range(nseg)]
        planar = "--plane" in stage[0]
        if not planar:
            self.segs += seg
            self.cutidx = conform.FaceIndex([list(s) for s in self.segs], self.tol)
        # the mesh: positive, the volume kept, conformal
        vol = self.volume()
        if abs(vol - self.vol0) > REL * abs(self.vol0):
            self.fail("volume %.17g, was %.17g" % (vol, self.vol0))
        fm = self.fm = conform.face_map(cm.conn)
        err = conform.shared_errors(fm)
        if err:
            self.fail(err)
        self.check_dropped(fm)
        on_cut = None if planar else lambda pts: self.cutidx.find(pts) >= 0
        self.pairs, err = conform.open_faces(cm.x, fm, self.outer, self.origin, on_cut)
        if err:
            self.fail(err)
        if planar and set(pairs_before) - set(self.pairs):
            self.fail("a face opened before is closed again: %s" % (sorted(set(pairs_before) - set(self.pairs))[0],))
        # the requested nodes were duplicated
        if planar:
            # (a drop may have separated every cut node of the step already:
            # plane_step checks that each of them has one class left)
            if not d["parent"] and not self.any_drop:
                self.fail("the step duplicates nothing: no new node")
            self.plane_step(stage[1], d, conn_before, fm_before, pairs_before, seg)
        else:
            path, k, n = stage[1], stage[2], int(stage[0]["--steps"])
            self.path_part(path, path.total * (k - 1) / n, path.total * k / n, seg)
            self.path_step(d, pairs_before, seg, fm)
        return d

    def run(self, own, last_in, stages, Kacc, facc):
        i, nsteps, maxm, flags_all = 0, 0, 0, 0
        step = last_in
        si, left = -1, 0
        while i < len(own):
            step += 1
            self.step = step
            seq = []
            while i < len(own) and own[i][1] == step:
                seq.append(own[i])
                i += 1
            crit = [r[0] for r in seq if r[0] not in ("sTAt", "tIMe")]
            if crit not in (["MDLT", "UPDT", "pATH"], ["MDLT", "BDLT", "UPDT", "pATH"]):
                self.fail("records %s" % crit)
            while left == 0:
                si += 1
                if si >= len(stages):
                    self.fail("more steps than the cut stages asked for")
                o = stages[si]
                left = int(o.get("--steps", "0"))
                if "--plane" in o:
                    stage = [o, Plane(self.cm, o)]
                elif "--path" not in o:  # a blade or a surface: check_blade.py's (it crashed, KeyError)
                    self.fail("a cut stage with neither --plane nor --path (%s): use check_blade.py"
                              % " ".join(sorted(k for k in o if k.startswith("--"))))
                else:
                    try:
                        stage = [o, pathfile.Path(o["--path"]), 0]
                    except (OSError, ValueError) as e:
                        self.fail("the path file of %s: %s" % (o.get("--path"), e))
            if len(stage) == 3:
                stage[2] += 1
            left -= 1
            rec = {r[0]: r[2] for r in seq}
            d = self.run_step(rec, stage)
            flags_all |= d["flags"]
            try:
                u = cutsys.updt(rec["UPDT"])
            except (cutsys.Bad, struct.error) as e:
                self.fail("UPDT: %s" % e)
            if u[1] != self.dim * len(d["parent"]):
                self.fail("k = %d for %d new nodes" % (u[1], len(d["parent"])))
            err = cutsys.apply_updt(Kacc, facc, u)
            if err:
                self.fail(err)
            maxm = max(maxm, u[0])
            err = cutsys.check(self.cm, Kacc, facc, REL, full=nsteps == 0 or i >= len(own))
            if err:
                self.fail("the accumulated updates against an independent assembly: " + err)
            nsteps += 1
        if left or si != len(stages) - 1:
            fail("the cut stages asked for %d more steps" % (left + sum(int(o.get("--steps", "0")) for o in stages[si + 1:])))
        return nsteps, maxm, flags_all


def main():
    args = sys.argv[1:]
    if len(args) != 2:
        raise SystemExit(__doc__)
    rin = raw_records(open(args[0], "rb").read())
    rout = raw_records(open(args[1], "rb").read())
    # HEAD, then one pROv per cut stage (cut | cut ...: the last one first), then the input's records
    passed = rin[1:-1]
    j = 1
    while j < len(rout) and rout[j][0] == "pROv" and "cut" in rout[j][2].decode() and \
            [(o[0], o[3]) for o in rout[j:j + len(passed)]] != [(r[0], r[3]) for r in passed]:
        j += 1
    if rout[0][0] != "HEAD" or j == 1:
        fail("output does not start with cut's HEAD and pROv")
    stages = [stage_of(r[2].decode()) for r in reversed(rout[1:j])]
    for i, r in enumerate(passed):
        o = rout[j + i] if j + i < len(rout) else ("", 0, b"", b"")
        if (o[0], o[3]) != (r[0], r[3]):
            fail("record %d (%s) of the input is not passed byte for byte" % (i + 1, r[0]))
    own = rout[j + len(passed):]
    if own[-1][0] != "TAIL":
        fail("no TAIL")
    own = own[:-1]
    last_in = max([s for t, s, p, b in rin if s >= 0] + [0])
    total = sum(int(o.get("--steps", "0")) for o in stages)
    if not own or own[0][0] != "pLAN" or len(own[0][2]) != 8:
        fail("no pLAN of 8 bytes after the input's records")
    plan = struct.unpack("<ii", own[0][2])
    if plan != (last_in + 1, last_in + total):
        fail("pLAN plans steps %d to %d, the stages bring %d to %d" % (plan + (last_in + 1, last_in + total)))
    own = own[1:]
    if any(r[0] == "pLAN" for r in own):
        fail("a second pLAN after the first step")
    m = augstream.mesh([(t, 0, s, p) for t, s, p, b in rin])
    ck = Checker(m)
    Kacc, facc = ck.cm.assemble()
    for t, s, p, b in rin:
        if t == "KMAT":
            which, n, K0 = cutsys.kmat(p)
            if which == 0:
                Kacc = K0
        if t == "FVEC":
            facc = cutsys.fvec(p)[1]
        if t in ("MDLT", "BDLT", "UPDT"):
            fail("the input has cut steps already; this checker starts from an uncut mesh")
    err = cutsys.check(ck.cm, Kacc, facc, REL)
    if err:
        fail("K_0 of the input against an independent assembly: " + err)
    nsteps, maxm, flags_all = ck.run(own, last_in, stages, Kacc, facc)
    print("ok steps=%d nodes=%d elements=%d max_m=%d flags=%d" % (nsteps, len(ck.cm.x), len(ck.cm.conn), maxm, flags_all))


main()
