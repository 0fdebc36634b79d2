"""The cut system of every step replayed from a stream, for the test oracles,
written from the specification only (formats/stream.md 5, 6.2, 6.3, 7.1, 7.2,
7.7): the mesh of step t rebuilt from the MDLT and BDLT records, K_t and f_t
assembled from scratch on it (linear elasticity: P1 tet4, tri3 plane stress of
thickness t, Q1 hex8 with 2x2x2 Gauss), and the same pair accumulated from K_0 and the UPDT records
(AMPS paper eq. 3.1). Matrices are dicts {(i, j): v} of the upper triangle."""
import math
import struct

import augstream


class Bad(Exception):
    """a record that does not decode or does not fit the mesh"""


def rel_option(args, default):
    """the value of --rel in the command line args (removed from it), or default"""
    if "--rel" not in args:
        return default
    i = args.index("--rel")
    rel = float(args[i + 1])
    del args[i:i + 2]
    return rel


def arr(fmt, p, pos, n):
    if n < 0 or pos + n * struct.calcsize(fmt) > len(p):
        raise Bad("payload too short")
    return augstream.arr(fmt, p, pos, n)


def mdlt(p, dim, nv):
    """MDLT (7.1) as a dict: parent, x (tuples), elem, conn, cadd, madd (tuples), flags"""
    nnew, = struct.unpack_from("<q", p, 0)
    par, pos = arr("i", p, 8, nnew)
    x, pos = arr("d", p, pos, nnew * dim)
    nmod, = struct.unpack_from("<q", p, pos)
    el, pos = arr("i", p, pos + 8, nmod)
    cn, pos = arr("i", p, pos, nmod * nv)
    nadd, = struct.unpack_from("<q", p, pos)
    ca, pos = arr("i", p, pos + 8, nadd * nv)
    ma, pos = arr("i", p, pos, nadd)
    if pos + 8 != len(p):
        raise Bad("MDLT payload size")
    fl, _ = struct.unpack_from("<ii", p, pos)
    return {"parent": par, "x": [tuple(x[i * dim:(i + 1) * dim]) for i in range(nnew)], "elem": el,
            "conn": [tuple(cn[i * nv:(i + 1) * nv]) for i in range(nmod)],
            "cadd": [tuple(ca[i * nv:(i + 1) * nv]) for i in range(nadd)], "madd": ma, "flags": fl}


def bdlt(p):
    """BDLT (7.7): (fix dofs, values, load dofs, values)"""
    nf, = struct.unpack_from("<q", p, 0)
    dof, pos = arr("i", p, 8, nf)
    val, pos = arr("d", p, pos, nf)
    nl, = struct.unpack_from("<q", p, pos)
    ldof, pos = arr("i", p, pos + 8, nl)
    lval, pos = arr("d", p, pos, nl)
    if pos != len(p):
        raise Bad("BDLT payload size")
    return dof, val, ldof, lval


def updt(p):
    """UPDT (7.2): (m, k, H, E column-major, df)"""
    m, k = struct.unpack_from("<ii", p, 0)
    H, pos = arr("i", p, 8, m)
    s = m + k
    E, pos = arr("d", p, pos, s * s)
    df, pos = arr("d", p, pos, s)
    if pos != len(p):
        raise Bad("UPDT payload size")
    return m, k, H, E, df


def kmat(p):
    """KMAT (6.2): (which, n, upper triangle dict)"""
    which, _, n, nnz = struct.unpack_from("<iiqq", p, 0)
    cp, pos = arr("q", p, 24, n + 1)
    ri, pos = arr("i", p, pos, nnz)
    va, pos = arr("d", p, pos, nnz)
    K = {}
    for j in range(n):
        for q in range(cp[j], cp[j + 1]):
            key = (min(ri[q], j), max(ri[q], j))
            K[key] = K.get(key, 0.0) + va[q]
    return which, n, K


def fvec(p):
    kind, _, n = struct.unpack_from("<iiq", p, 0)
    return kind, arr("d", p, 16, n)[0]


# hex8 corners in natural coordinates (gmsh order)
HEXC = ((-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1))


def inv3(J):
    """(det J, J^-1) of a 3 x 3 list of lists, by Cramer's rule"""
    a, b, c = J[0]
    d, e, f = J[1]
    g, h, i = J[2]
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    adj = [[e * i - f * h, c * h - b * i, b * f - c * e],
           [f * g - d * i, a * i - c * g, c * d - a * f],
           [d * h - e * g, b * g - a * h, a * e - b * d]]
    return det, [[v / det for v in row] for row in adj]


def hex_points(P):
    """[(w det J, N, G)] at the 2x2x2 Gauss points of the trilinear hex with
    corners P: N[a] shape values, G[a][k] = dN_a/dx_k (Hughes, The Finite
    Element Method, sec. 3.5-3.8)"""
    g = 1 / math.sqrt(3)
    out = []
    for xi in ((i, j, k) for k in (-g, g) for j in (-g, g) for i in (-g, g)):
        N, dN = [], []
        for c in HEXC:
            f = [1 + c[k] * xi[k] for k in range(3)]
            N.append(f[0] * f[1] * f[2] / 8)
            dN.append((c[0] * f[1] * f[2] / 8, f[0] * c[1] * f[2] / 8, f[0] * f[1] * c[2] / 8))
        # J[r][k] = dx_r / dxi_k
        J = [[sum(P[a][r] * dN[a][k] for a in range(8)) for k in range(3)] for r in range(3)]
        det, Ji = inv3(J)
        G = [[sum(dN[a][k] * Ji[k][r] for k in range(3)) for r in range(3)] for a in range(8)]
        out.append((det, N, G))
    return out


def membrane(P, mat, kf):
    """mem3 (formats 5.3, 5.9): the tri3 plane-stress matrix in the triangle's
    own axes e1 = (p1-p0)/|p1-p0|, e2 = n x e1, rotated to 3-D, K = T' K2 T
    with T = diag(E', E', E'), E = [e1 e2] (3 x 2); plus the foundation
    kf A (1 + delta_ab) / 12 n n'"""
    a = [P[1][k] - P[0][k] for k in range(3)]
    b = [P[2][k] - P[0][k] for k in range(3)]
    n = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    ln, la = math.sqrt(sum(v * v for v in n)), math.sqrt(sum(v * v for v in a))
    n = [v / ln for v in n]
    e1 = [v / la for v in a]
    e2 = [n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0]]
    q = [[sum((P[i][k] - P[0][k]) * e[k] for k in range(3)) for e in (e1, e2)] for i in range(3)]
    K2 = stiffness(q, 2, mat)
    K = [[0.0] * 9 for _ in range(9)]
    E = [e1, e2]
    area = ln / 2
    for A in range(3):
        for B in range(3):
            for i in range(3):
                for j in range(3):
                    v = sum(E[k][i] * K2[A * 2 + k][B * 2 + l] * E[l][j] for k in range(2) for l in range(2))
                    K[A * 3 + i][B * 3 + j] = v + kf * area * (2.0 if A == B else 1.0) / 12 * n[i] * n[j]
    return K


def stiffness(P, dim, mat, kf=0.0):
    """element stiffness of the simplex or trilinear hex (8 corners: 2x2x2
    Gauss) with corners P (list of lists), dof order node*dim + c; mat = (id,
    name, E, nu, rho, t); 3 corners in 3-D: the membrane triangle (kf its
    foundation modulus)"""
    if dim == 3 and len(P) == 3:
        return membrane(P, mat, kf)
    _, _, E, nu, _, t = mat
    mu = E / (2 * (1 + nu))
    if len(P) == 8:
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        K = [[0.0] * 24 for _ in range(24)]
        for w, _, G in hex_points(P):
            for a in range(8):
                for b in range(8):
                    gg = sum(G[a][k] * G[b][k] for k in range(3))
                    for i in range(3):
                        for j in range(3):
                            v = lam * G[a][i] * G[b][j] + mu * G[a][j] * G[b][i] + (mu * gg if i == j else 0.0)
                            K[a * 3 + i][b * 3 + j] += w * v
        return K
    if dim == 3:
        J = [[P[i][k] - P[0][k] for k in range(3)] for i in (1, 2, 3)]
        det = (J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0])
               + J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]))
        # inv[i][j] = (J^-1)[i][j]; the gradient of barycentric i+1 is column i of J^-1
        inv = [[(J[(j + 1) % 3][(i + 1) % 3] * J[(j + 2) % 3][(i + 2) % 3]
                 - J[(j + 1) % 3][(i + 2) % 3] * J[(j + 2) % 3][(i + 1) % 3]) / det for j in range(3)] for i in range(3)]
        g = [[inv[k][i] for k in range(3)] for i in range(3)]
        G = [[-(g[0][k] + g[1][k] + g[2][k]) for k in range(3)]] + g
        w = abs(det) / 6
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    else:
        x1, y1 = P[1][0] - P[0][0], P[1][1] - P[0][1]
        x2, y2 = P[2][0] - P[0][0], P[2][1] - P[0][1]
        det = x1 * y2 - x2 * y1
        g1, g2 = (y2 / det, -x2 / det), (-y1 / det, x1 / det)
        G = [(-(g1[0] + g2[0]), -(g1[1] + g2[1])), g1, g2]
        w = abs(det) / 2 * t
        lam = E * nu / (1 - nu * nu)  # plane stress
    nv = dim + 1
    K = [[0.0] * (nv * dim) for _ in range(nv * dim)]
    for a in range(nv):
        for b in range(nv):
            gg = sum(G[a][k] * G[b][k] for k in range(dim))
            for i in range(dim):
                for j in range(dim):
                    v = lam * G[a][i] * G[b][j] + mu * G[a][j] * G[b][i] + (mu * gg if i == j else 0.0)
                    K[a * dim + i][b * dim + j] = w * v
    return K


class CutMesh:
    """the mesh of the current step in the cut-matrix numbering of 7.2"""

    def __init__(self, m):
        self.dim, self.nv = m["dim"], m["nv"]
        self.x = list(m["x"])
        self.conn = list(m["conn"])
        self.mat = list(m["mat"])
        self.mats = m["mats"]
        self.kf = m.get("fndn", [0.0] * len(self.mats))
        self.fix = dict(m.get("fix", {}))
        self.load = dict(m.get("load", {}))
        self.grav = tuple(m.get("grav", (0.0, 0.0, 0.0)))
        self.nn0 = len(self.x)
        self.map0, k = [], 0
        for dof in range(self.nn0 * self.dim):
            self.map0.append(-1 if dof in self.fix else k)
            k += dof not in self.fix
        self.nfree0 = k
        self.cache, self.dirty = {}, set()

    def order(self):
        return self.nfree0 + (len(self.x) - self.nn0) * self.dim

    def index(self, dof):
        """matrix index of a DOF, -1 for a DOF of the original mesh constrained in FIXD"""
        if dof < self.nn0 * self.dim:
            return self.map0[dof]
        return self.nfree0 + dof - self.nn0 * self.dim

    def apply_mdlt(self, d):
        """mesh += d (7.1): new nodes inherit their parent's constraints"""
        nn, ne, nv = len(self.x), len(self.conn), self.nv
        for q, par in enumerate(d["parent"]):
            if not 0 <= par < nn + q:
                raise Bad("parent %d of new node %d" % (par, nn + q))
            self.x.append(d["x"][q])
            for c in range(self.dim):
                if par * self.dim + c in self.fix:
                    self.fix[(nn + q) * self.dim + c] = self.fix[par * self.dim + c]
                    self.dirty.add(nn + q)
        nn = len(self.x)
        for q, e in enumerate(d["elem"]):
            if not 0 <= e < ne or (q and e <= d["elem"][q - 1]):
                raise Bad("re-wired element %d (not increasing below %d)" % (e, ne))
            self.conn[e] = d["conn"][q]
        self.conn += d["cadd"]
        self.mat += d["madd"]
        for c in d["conn"] + d["cadd"]:
            if len(set(c)) != nv or not all(0 <= v < nn for v in c):
                raise Bad("element nodes %s" % (c,))
        if not all(0 <= k < len(self.mats) for k in d["madd"]):
            raise Bad("material of an added element")

    def apply_bdlt(self, b):
        dof, val, ldof, lval = b
        ndof = len(self.x) * self.dim
        for ds in (dof, ldof):
            if any(not 0 <= v < ndof for v in ds) or any(ds[i] >= ds[i + 1] for i in range(len(ds) - 1)):
                raise Bad("BDLT DOFs not increasing in 0..%d" % (ndof - 1))
        self.fix.update(zip(dof, val))
        self.load.update(zip(ldof, lval))
        self.dirty.update(v // self.dim for v in dof)

    def body(self, conn, mat):
        """the element's consistent load of the body force rho * grav (5.8): per
        DOF rho |e| t / nv * grav_c"""
        P = [self.x[v] for v in conn]
        if not any(self.grav):
            return [0.0] * (len(conn) * self.dim)
        _, _, _, _, rho, t = self.mats[mat]
        meas = abs(augstream.corners_measure(P)) * (t if self.dim == 2 or self.nv == 3 else 1.0)
        w = rho * meas / len(conn)
        return [w * self.grav[c] for _ in conn for c in range(self.dim)]

    def forces(self):
        """the nodal forces of the mesh now, {dof: value}: LOAD (and BDLT's) plus
        the body force of every element"""
        f = dict(self.load)
        if any(self.grav):
            for e, conn in enumerate(self.conn):
                be = self.body(conn, self.mat[e])
                for q, v in enumerate(conn):
                    for c in range(self.dim):
                        d = v * self.dim + c
                        f[d] = f.get(d, 0.0) + be[q * self.dim + c]
        return f

    def element_terms(self, conn, mat, dofs):
        """the element's terms of K_t ((i, j), v) and of f_t (i, v) under the
        current constraints of its DOFs (the body force included)"""
        Ke = stiffness([self.x[v] for v in conn], self.dim, self.mats[mat], self.kf[mat])
        gi = [self.index(d) for d in dofs]
        fixed = [d in self.fix for d in dofs]
        kt, ft = [], []
        be = self.body(conn, mat)
        ft += [(gi[a], be[a]) for a in range(len(dofs)) if not fixed[a] and be[a] != 0]
        for b in range(len(dofs)):
            if fixed[b]:
                vb = self.fix[dofs[b]]
                if vb != 0:
                    ft += [(gi[a], -Ke[a][b] * vb) for a in range(len(dofs)) if not fixed[a]]
                continue
            kt += [((gi[a], gi[b]), Ke[a][b]) for a in range(len(dofs)) if not fixed[a] and gi[a] <= gi[b]]
        return kt, ft

    def element_sum(self, full):
        """sumK, sumf = the sum of the element terms of every element of the
        mesh as it is now; full: summed afresh, else the terms of the elements
        whose nodes, material or constraints changed since the last call
        replaced (the nodes and material of every element are compared, and
        the constraints of the elements at the nodes whose constraints changed)"""
        dim, nv, fix, cache, dirty = self.dim, self.nv, self.fix, self.cache, self.dirty
        if full or not hasattr(self, "state"):
            self.sumK, self.sumf, self.state = {}, {}, []
        S, F, state = self.sumK, self.sumf, self.state
        for e, conn in enumerate(self.conn):
            old = state[e] if e < len(state) else None
            if old and old[0] == conn and old[1] == self.mat[e] and not (dirty and any(v in dirty for v in conn)):
                continue
            dofs = [conn[a] * dim + c for a in range(nv) for c in range(dim)]
            key = (conn, self.mat[e], tuple(map(fix.get, dofs)))
            if key == old:
                continue
            terms = cache.get(key)
            if terms is None:
                terms = cache[key] = self.element_terms(conn, self.mat[e], dofs)
            for sign, (kt, ft) in ((-1.0, cache[old]), (1.0, terms)) if old else ((1.0, terms),):
                for ij, v in kt:
                    S[ij] = S.get(ij, 0.0) + sign * v
                for i, v in ft:
                    F[i] = F.get(i, 0.0) + sign * v
            if old:
                state[e] = key
            else:
                state.append(key)
        dirty.clear()

    def residue(self, K, f, full=False):
        """(K - K_t, f - f_t) with K_t, f_t the system assembled from scratch
        on the mesh (7.2): identity rows for constrained matrix indices with
        f = the value; elsewhere stiffness over the unconstrained indices, f =
        nodal force - sum K_ij value_j over constrained j. K, f not changed."""
        self.element_sum(full)
        fix, S = self.fix, self.sumK
        get = S.get
        D = {k: v - get(k, 0.0) for k, v in K.items()}
        for k in S.keys() - K.keys():
            D[k] = -S[k]
        r = list(f) + [0.0] * max(0, self.order() - len(f))
        for dof, v in self.load.items():
            if dof not in fix and self.index(dof) >= 0:
                r[self.index(dof)] -= v
        for i, v in self.sumf.items():
            r[i] -= v
        for dof, v in fix.items():
            g = self.index(dof)
            if g >= 0:
                D[(g, g)] = D.get((g, g), 0.0) - 1.0
                r[g] = (f[g] if g < len(f) else 0.0) - v
        return D, r

    def assemble(self):
        """K_t and f_t from scratch"""
        D, r = self.residue({}, [], True)
        return {k: -v for k, v in D.items()}, [-v for v in r]


def apply_updt(K, f, u):
    """(K, f) of step t-1 -> of step t by eq. 3.1, in place:
    K_t = [K 0; 0 I_k] - Hbar (E + [0 0; 0 I_k]) Hbar', f_t = [f; 0] + Hbar df;
    the first inconsistency as a string, else None"""
    m, k, H, E, df = u
    n, s = len(f), m + k
    if any(not 0 <= H[q] < n or (q and H[q] <= H[q - 1]) for q in range(m)):
        return "H not increasing in 0..%d" % (n - 1)
    g = H + list(range(n, n + k))
    f += [0.0] * k
    for q in range(n, n + k):
        K[(q, q)] = 1.0
    get = K.get
    for b in range(s):
        f[g[b]] += df[b]
        col = E[b * s:(b + 1) * s]
        if col != E[b::s]:
            return "E not symmetric"
        if b >= m:
            col[b] += 1.0
        gb = g[b]
        for a, v in enumerate(col):
            if v != 0 and g[a] <= gb:
                key = (g[a], gb)
                K[key] = get(key, 0.0) - v
    return None


def check(cm, K, f, rel, full=True):
    """where (K, f) differs from the system assembled from scratch on cm by more
    than rel * max|K| (f: rel * max(max|f|, max|K| max|prescribed value|)), as a
    string; else None. full = False: the element sum carried from the last
    check (CutMesh.element_sum)"""
    if len(f) != cm.order():
        return "order %d, the mesh has %d matrix indices" % (len(f), cm.order())
    D, r = cm.residue(K, f, full)
    mx = max(map(abs, K.values()))
    dm = max(map(abs, D.values()))
    if not dm <= rel * mx:
        key = max(D, key=lambda k: abs(D[k]))
        return "K%s is %.17g, assembled %.17g (max|K| %g)" % (key, K.get(key, 0.0), K.get(key, 0.0) - D[key], mx)
    vmax = max([abs(v) for v in cm.fix.values()] + [0.0])
    fs = max(max(map(abs, f), default=0.0), mx * vmax, 1e-300)
    if r and not max(map(abs, r)) <= rel * fs:
        i = max(range(len(r)), key=lambda i: abs(r[i]))
        return "f[%d] is %.17g, assembled %.17g" % (i, f[i], f[i] - r[i])
    return None
