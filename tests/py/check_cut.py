#!/usr/bin/env python3
"""Independent check of a cut stream (formats/stream.md 7.1, 7.2, 7.6, 7.7),
written from the specification only.

usage: check_cut.py IN.aug OUT.aug [--k-every N]

IN: an uncut stream (meshload, perhaps factor); OUT: IN through one or more cuts.
- every record of IN but HEAD and TAIL is in OUT byte for byte, in order,
  right after HEAD and the cut stages' pROv; then per step MDLT [BDLT] UPDT pATH
  (ancillary sTAt/tIMe allowed), steps consecutive;
- the mesh rebuilt from MDLT/BDLT keeps its volume (area), has no element of
  measure <= 0, and every face is shared by at most two elements;
- K_t and f_t accumulated from K_0 (KMAT of IN, or assembled here when IN has
  none) and the UPDT records equal the cut system assembled here from scratch
  (own linear elasticity: tet4, tri3 plane stress) at every N-th step and the
  last, entry by entry within 1e-11 * max|K|. K_0 of IN is checked the same.
Prints one line 'ok steps=S ...' or the first failure, exit 1."""
import struct
import sys
import zlib

sys.path.insert(0, __import__("os").path.dirname(__file__))
import augstream  # noqa: E402

SIG = b"\x89AUG\r\n\x1a\n"


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


def arr(fmt, p, pos, n):
    size = struct.calcsize(fmt)
    return list(struct.unpack_from("<%d%s" % (n, fmt), p, pos)), pos + n * size


def stiffness(m, conn, mat):
    """element stiffness (list of lists), dof order node*dim+c"""
    dim = m["dim"]
    _, _, E, nu, _, t = m["mats"][mat]
    P = [m["x"][i] for i in conn]
    if dim == 3:
        a = [[P[i][k] - P[0][k] for k in range(3)] for i in (1, 2, 3)]
        # J rows: edge vectors; gradients of barycentrics 1..3 = rows of J^-T
        J = a
        det = (J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0])
               + J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]))
        inv = [[(J[(j + 1) % 3][(i + 1) % 3] * J[(j + 2) % 3][(i + 2) % 3] - J[(j + 1) % 3][(i + 2) % 3] * J[(j + 2) % 3][(i + 1) % 3]) / det
                for j in range(3)] for i in range(3)]  # inv[i][j] = (J^-1)[i][j]
        g = [[inv[k][i] for k in range(3)] for i in range(3)]  # grad of lambda_{i+1}
        g0 = [-(g[0][k] + g[1][k] + g[2][k]) for k in range(3)]
        G = [g0] + g
        vol = abs(det) / 6
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        mu = E / (2 * (1 + nu))
        nd = 12
        K = [[0.0] * nd for _ in range(nd)]
        for a_ in range(4):
            for b in range(4):
                for i in range(3):
                    for j in range(3):
                        v = lam * G[a_][i] * G[b][j] + mu * G[a_][j] * G[b][i]
                        if i == j:
                            v += mu * sum(G[a_][k] * G[b][k] for k in range(3))
                        K[a_ * 3 + i][b * 3 + j] = vol * v
        return K
    x1, y1 = P[1][0] - P[0][0], P[1][1] - P[0][1]
    x2, y2 = P[2][0] - P[0][0], P[2][1] - P[0][1]
    det = x1 * y2 - x2 * y1
    g1 = (y2 / det, -x2 / det)
    g2 = (-y1 / det, x1 / det)
    G = [(-(g1[0] + g2[0]), -(g1[1] + g2[1])), g1, g2]
    area = abs(det) / 2
    # plane stress: lambda* = E nu / (1 - nu^2), mu = E / (2 (1 + nu))
    lam = E * nu / (1 - nu * nu)
    mu = E / (2 * (1 + nu))
    K = [[0.0] * 6 for _ in range(6)]
    for a_ in range(3):
        for b in range(3):
            for i in range(2):
                for j in range(2):
                    v = lam * G[a_][i] * G[b][j] + mu * G[a_][j] * G[b][i]
                    if i == j:
                        v += mu * (G[a_][0] * G[b][0] + G[a_][1] * G[b][1])
                    K[a_ * 2 + i][b * 2 + j] = area * t * v
    return K


def cut_index(m, nn0, map0, nfree0, node, c):
    dim = m["dim"]
    if node < nn0:
        return map0[node * dim + c]
    return nfree0 + (node - nn0) * dim + c


def assemble(m, nn0, map0, nfree0):
    """K_t (dict (i, j) -> v, i <= j) and f_t (list) from scratch (7.2)"""
    dim, nv = m["dim"], m["nv"]
    n = nfree0 + (len(m["x"]) - nn0) * dim
    K, f = {}, [0.0] * n
    fix, load = m["fix"], m["load"]
    for dof, v in load.items():
        g = cut_index(m, nn0, map0, nfree0, dof // dim, dof % dim)
        if g >= 0 and dof not in fix:
            f[g] += v
    for e, conn in enumerate(m["conn"]):
        Ke = stiffness(m, conn, m["mat"][e])
        dofs = [conn[a] * dim + c for a in range(nv) for c in range(dim)]
        gi = [cut_index(m, nn0, map0, nfree0, d // dim, d % dim) for d in dofs]
        for b in range(nv * dim):
            if dofs[b] in fix:
                vb = fix[dofs[b]]
                if vb != 0:
                    for a in range(nv * dim):
                        if gi[a] >= 0 and dofs[a] not in fix:
                            f[gi[a]] -= Ke[a][b] * vb
                continue
            if gi[b] < 0:
                continue
            for a in range(nv * dim):
                if gi[a] < 0 or dofs[a] in fix or gi[a] > gi[b]:
                    continue
                K[(gi[a], gi[b])] = K.get((gi[a], gi[b]), 0.0) + Ke[a][b]
    for dof, v in fix.items():
        g = cut_index(m, nn0, map0, nfree0, dof // dim, dof % dim)
        if g >= 0:
            K[(g, g)] = 1.0
            f[g] = v
    return K, f


def compare(Ka, fa, Kb, fb, what):
    mx = max(abs(v) for v in Ka.values())
    for key in set(Ka) | set(Kb):
        a, b = Ka.get(key, 0.0), Kb.get(key, 0.0)
        if abs(a - b) > 1e-11 * mx:
            fail("%s: K%s is %.17g, want %.17g (max|K| %g)" % (what, key, b, a, mx))
    if len(fa) != len(fb):
        fail("%s: f has %d entries, want %d" % (what, len(fb), len(fa)))
    fm = max([abs(v) for v in fa] + [1.0])
    for i in range(len(fa)):
        if abs(fa[i] - fb[i]) > 1e-11 * (fm + mx):
            fail("%s: f[%d] is %.17g, want %.17g" % (what, i, fb[i], fa[i]))


def faces_ok(m):
    count = {}
    nv = m["nv"]
    for c in m["conn"]:
        for f in range(nv):
            key = tuple(sorted(c[:f] + c[f + 1:]))
            count[key] = count.get(key, 0) + 1
    return max(count.values()) <= 2


def main():
    args = sys.argv[1:]
    every = 1
    if "--k-every" in args:
        i = args.index("--k-every")
        every = int(args[i + 1])
        del args[i:i + 2]
    rin = raw_records(open(args[0], "rb").read())
    rout = raw_records(open(args[1], "rb").read())
    # HEAD, then one pROv per cut stage (cut | cut ...), then the input's records
    passed = rin[1:-1]
    j = 1
    while j < len(rout) and rout[j][0] == "pROv" and "cut" in rout[j][2].decode() and \
            [(o[0], o[3]) for o in rout[j:j + len(passed)]] != [(r[0], r[3]) for r in passed]:
        j += 1
    if rout[0][0] != "HEAD" or j == 1:
        fail("output does not start with cut's HEAD and pROv")
    for i, r in enumerate(passed):
        o = rout[j + i] if j + i < len(rout) else ("", 0, b"", b"")
        if (o[0], o[3]) != (r[0], r[3]):
            fail("record %d (%s) of the input is not passed byte for byte" % (i + 1, r[0]))
    own = rout[j + len(passed):]
    if own[-1][0] != "TAIL":
        fail("no TAIL")
    own = own[:-1]
    recs = [(t, 0, s, p) for t, s, p, b in rin]
    m = augstream.mesh(recs)
    m.setdefault("fix", {})
    m.setdefault("load", {})
    dim = m["dim"]
    nn0 = len(m["x"])
    map0, k = [], 0
    for dof in range(nn0 * dim):
        if dof in m["fix"]:
            map0.append(-1)
        else:
            map0.append(k)
            k += 1
    nfree0 = k
    Kacc, facc = assemble(m, nn0, map0, nfree0)
    last_in = max([s for t, s, p, b in rin if s >= 0] + [0])
    for t, s, p, b in rin:
        if t == "KMAT":
            which, stype, n, nnz = struct.unpack_from("<iiqq", p, 0)
            if which != 0:
                continue
            cp, pos = arr("q", p, 24, n + 1)
            ri, pos = arr("i", p, pos, nnz)
            va, pos = arr("d", p, pos, nnz)
            K0 = {}
            for j in range(n):
                for q in range(cp[j], cp[j + 1]):
                    a, c = min(ri[q], j), max(ri[q], j)
                    K0[(a, c)] = K0.get((a, c), 0.0) + va[q]
            Kacc = K0
        if t == "FVEC":
            kind, _, n = struct.unpack_from("<iiq", p, 0)
            v, _ = arr("d", p, 16, n)
            facc = v
        if t in ("MDLT", "BDLT", "UPDT"):
            fail("the input has cut steps already; this checker starts from an uncut mesh")
    Kscr, fscr = assemble(m, nn0, map0, nfree0)
    compare(Kscr, fscr, Kacc, facc, "K_0 of the input against an independent assembly")
    vol0 = sum(augstream.measure(m, e) for e in range(len(m["conn"])))
    step = last_in
    i = 0
    nsteps, maxm, flags_all = 0, 0, 0
    while i < len(own):
        step += 1
        seq = []
        while i < len(own) and own[i][1] == step:
            seq.append(own[i])
            i += 1
        crit = [r[0] for r in seq if r[0] not in ("sTAt", "tIMe")]
        if crit not in (["MDLT", "UPDT", "pATH"], ["MDLT", "BDLT", "UPDT", "pATH"]):
            fail("step %d: records %s" % (step, crit))
        rec = {r[0]: r[2] for r in seq}
        # MDLT
        p = rec["MDLT"]
        nv = m["nv"]
        nnew, = struct.unpack_from("<q", p, 0)
        par, pos = arr("i", p, 8, nnew)
        x, pos = arr("d", p, pos, nnew * dim)
        nmod, = struct.unpack_from("<q", p, pos)
        el, pos = arr("i", p, pos + 8, nmod)
        cn, pos = arr("i", p, pos, nmod * nv)
        nadd, = struct.unpack_from("<q", p, pos)
        ca, pos = arr("i", p, pos + 8, nadd * nv)
        ma, pos = arr("i", p, pos, nadd)
        fl, _ = struct.unpack_from("<ii", p, pos)
        flags_all |= fl
        nn_before = len(m["x"])
        for q in range(nnew):
            m["x"].append(tuple(x[q * dim:(q + 1) * dim]))
            for c in range(dim):
                d = par[q] * dim + c
                if d in m["fix"]:
                    m["fix"][(nn_before + q) * dim + c] = m["fix"][d]
        for q in range(nmod):
            m["conn"][el[q]] = tuple(cn[q * nv:(q + 1) * nv])
        for q in range(nadd):
            m["conn"].append(tuple(ca[q * nv:(q + 1) * nv]))
            m["mat"].append(ma[q])
        if "BDLT" in rec:
            p = rec["BDLT"]
            nf, = struct.unpack_from("<q", p, 0)
            dof, pos = arr("i", p, 8, nf)
            val, pos = arr("d", p, pos, nf)
            nl, = struct.unpack_from("<q", p, pos)
            ldof, pos = arr("i", p, pos + 8, nl)
            lval, pos = arr("d", p, pos, nl)
            m["fix"].update(zip(dof, val))
            m["load"].update(zip(ldof, lval))
        # UPDT
        p = rec["UPDT"]
        mm, kk = struct.unpack_from("<ii", p, 0)
        H, pos = arr("i", p, 8, mm)
        s = mm + kk
        E, pos = arr("d", p, pos, s * s)
        df, pos = arr("d", p, pos, s)
        if pos != len(p):
            fail("step %d: UPDT size" % step)
        if kk != dim * nnew:
            fail("step %d: k = %d for %d new nodes" % (step, kk, nnew))
        n_prev = len(facc)
        if any(H[q] >= n_prev or (q and H[q] <= H[q - 1]) for q in range(mm)):
            fail("step %d: H not increasing below %d" % (step, n_prev))
        g = H + list(range(n_prev, n_prev + kk))
        facc = facc + [0.0] * kk
        for q in range(n_prev, n_prev + kk):
            Kacc[(q, q)] = 1.0
        for b in range(s):
            facc[g[b]] += df[b]
            for a in range(s):
                if E[a + b * s] != E[b + a * s]:
                    fail("step %d: E not symmetric" % step)
                if g[a] <= g[b]:
                    key = (g[a], g[b])
                    Kacc[key] = Kacc.get(key, 0.0) - E[a + b * s] - (1.0 if a == b and a >= mm else 0.0)
        maxm = max(maxm, mm)
        # pATH
        p = rec["pATH"]
        pd, _, nseg = struct.unpack_from("<iiq", p, 0)
        if pd != dim or len(p) != 16 + nseg * 2 * dim * 8:
            fail("step %d: pATH layout" % step)
        nsteps += 1
        if nsteps % every == 0 or i >= len(own):
            Kscr, fscr = assemble(m, nn0, map0, nfree0)
            compare(Kscr, fscr, Kacc, facc, "step %d" % step)
    vol = sum(augstream.measure(m, e) for e in range(len(m["conn"])))
    if abs(vol - vol0) > 1e-12 * abs(vol0):
        fail("volume %.17g, was %.17g" % (vol, vol0))
    mn = min(augstream.measure(m, e) for e in range(len(m["conn"])))
    if not mn > 0:
        fail("an element of measure %g" % mn)
    if not faces_ok(m):
        fail("a face shared by three or more elements")
    print("ok steps=%d nodes=%d elements=%d max_m=%d flags=%d" % (nsteps, len(m["x"]), len(m["conn"]), maxm, flags_all))


main()
