#!/usr/bin/env python3
"""Independent check of the reaction forces (rEAC, formats/stream.md 7.10) from
the specification only. For every rEAC of a stream, read from its `stats
--dump` text (so the dump is checked too), with the fELD of the same step
(every node: solve with --output all), on the mesh of that step replayed from
the stream's own records (tests/py/cutsys.py: MDLT, BDLT, constraints
inherited by copies; set membership inherited by copies):

  - the DOFs are exactly the constrained DOFs of the mesh, increasing;
  - every reaction equals (K u - f) at its DOF to --rel relative (of the
    largest |K u - f|), K u summed here over the elements (cutsys.stiffness)
    that hold the DOF's node, f the nodal loads and the body force (GRAV);
  - the reactions balance the loads and the foundation's forces (FNDN, the
    Winkler foundation under membrane triangles: -Kf u summed over all DOFs):
    |sum r_c + sum f_c - sum (Kf u)_c| <= --rel (sum |r_c| + sum |f_c| +
    |sum (Kf u)_c|) for every component c;
  - total is the sum of the reactions per component, and the sets are the
    stream's named sets that hold a constrained DOF, in stream order, each with
    the sum of the reactions at its constrained DOFs (1e-12 relative of sum |r|).

usage: check_reaction.py [--rel R] STREAM DUMP   (default R = 1e-10)
Prints 'ok STREAM reactions=N max_rel=... max_balance=...' or the first
failure; exit 1 on a failure."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402
import cutsys  # noqa: E402


def unescape(s):
    """a quoted name of the dump (aug_txt_esc) back to its text"""
    s, out, i = s[1:-1], [], 0
    while i < len(s):
        if s[i] == "\\" and s[i + 1] == "x":
            out.append(chr(int(s[i + 2:i + 4], 16)))
            i += 4
        elif s[i] == "\\":
            out.append(s[i + 1])
            i += 2
        else:
            out.append(s[i])
            i += 1
    return "".join(out)


def dump_records(path):
    """{index: (type, step, fields)} of the records a dump text decodes:
    fields[key] = scalar text, or the list of numbers of an array; the sets of
    an rEAC as fields['sets'] = [(name, resultant)]"""
    recs, cur, arr = {}, None, None
    for line in open(path):
        line = line.rstrip("\n")
        if line.startswith("#"):
            head = line.split()
            cur = {"sets": []}
            recs[int(head[0][1:])] = (head[1], int(head[2].split("=")[1]), cur)
            arr = None
        elif line.startswith("    ") and arr is not None and line.split()[0].endswith(":"):
            arr.extend(float(t) for t in line.split(":", 1)[1].split())
        elif line.startswith("  set "):
            cur["sets"].append([unescape(line[6:]), None])
        elif line.startswith("  "):
            key, _, rest = line.strip().partition(" ")
            if "[" in key:
                arr = []
                name = key.split("[")[0]
                if name == "resultant":
                    cur["sets"][-1][1] = arr
                else:
                    cur[name] = arr
            else:
                cur[key], arr = rest, None
    return recs


class Scene(cutsys.CutMesh):
    """the mesh of the current step with the named sets (copies inherit)"""

    def __init__(self, m):
        super().__init__(m)
        self.sets = [(s, set(m["sets"][s])) for s in m["set_order"]]

    def apply_mdlt(self, d):
        nn = len(self.x)
        super().apply_mdlt(d)
        for q, par in enumerate(d["parent"]):
            for _, nodes in self.sets:
                if par in nodes:
                    nodes.add(nn + q)

    def ku_minus_f(self, u):
        """{dof: (K u - f)_dof} over the constrained DOFs"""
        forces = self.forces()
        dim, r = self.dim, {d: -forces.get(d, 0.0) for d in self.fix}
        for e, conn in enumerate(self.conn):
            dofs = [v * dim + c for v in conn for c in range(dim)]
            if not any(d in self.fix for d in dofs):
                continue
            Ke = cutsys.stiffness([self.x[v] for v in conn], dim, self.mats[self.mat[e]], self.kf[self.mat[e]])
            ue = [u[d] for d in dofs]
            for a, d in enumerate(dofs):
                if d in self.fix:
                    r[d] += sum(k * w for k, w in zip(Ke[a], ue))
        return r

    def foundation_force(self, u):
        """per component, the total force the foundation (FNDN, formats 5.9)
        exerts on the sheet, sum over the elements of Kf_e u_e, Kf_e the
        element's foundation term alone (zero without a foundation)"""
        dim, tot = self.dim, [0.0] * self.dim
        for e, conn in enumerate(self.conn):
            kf = self.kf[self.mat[e]]
            if not kf:
                continue
            P = [self.x[v] for v in conn]
            mat = self.mats[self.mat[e]]
            K1, K0 = cutsys.stiffness(P, dim, mat, kf), cutsys.stiffness(P, dim, mat)
            ue = [u[v * dim + c] for v in conn for c in range(dim)]
            for a in range(len(ue)):
                tot[a % dim] += sum((k1 - k0) * w for k1, k0, w in zip(K1[a], K0[a], ue))
        return tot


def check(sc, f, u, rel):
    """the failures of one rEAC (fields f) against the field u, and (rel error, balance)"""
    dim = sc.dim
    dofs = [int(v) for v in f["dof"]]
    r = f["r"]
    if int(f["dim"]) != dim or int(f["n"]) != len(dofs) or len(r) != len(dofs):
        return "dim %s, n %s: %d DOFs" % (f["dim"], f["n"], len(dofs)), 0, 0
    if dofs != sorted(sc.fix):
        return "DOFs %s... are not the %d constrained DOFs of the mesh" % (dofs[:6], len(sc.fix)), 0, 0
    ref = sc.ku_minus_f(u)
    scale = max([abs(v) for v in ref.values()] + [1e-300])
    err = max([abs(a - ref[d]) for a, d in zip(r, dofs)] + [0.0]) / scale
    if not err <= rel:
        k = max(range(len(dofs)), key=lambda k: abs(r[k] - ref[dofs[k]]))
        return "DOF %d: reaction %.17g, K u - f = %.17g (%.3g relative)" % (dofs[k], r[k], ref[dofs[k]], err), err, 0
    bal = 0.0
    fk = sc.foundation_force(u)
    for c in range(dim):
        rc = [a for a, d in zip(r, dofs) if d % dim == c]
        fc = [v for d, v in sc.forces().items() if d % dim == c] + [-fk[c]]
        b = abs(sum(rc) + sum(fc)) / max(sum(map(abs, rc)) + sum(map(abs, fc)), 1e-300)
        bal = max(bal, b)
        if not b <= rel:
            return "component %d: sum of reactions %.17g + sum of loads and foundation forces %.17g (%.3g)" \
                % (c, sum(rc), sum(fc), b), err, bal
        if not abs(f["total"][c] - sum(rc)) <= 1e-12 * max(sum(map(abs, rc)), 1e-300):
            return "total[%d] %.17g, sum of the reactions %.17g" % (c, f["total"][c], sum(rc)), err, bal
    want = [s for s, nodes in sc.sets if any(d // dim in nodes for d in dofs)]
    got = [s for s, _ in f["sets"]]
    if got != want or int(f["nset"]) != len(got):
        return "sets %s, the sets that hold a constrained DOF are %s" % (got, want), err, bal
    tot = max(sum(map(abs, r)), 1e-300)
    for (s, res), (_, nodes) in zip(f["sets"], [x for x in sc.sets if x[0] in want]):
        for c in range(dim):
            v = sum(a for a, d in zip(r, dofs) if d % dim == c and d // dim in nodes)
            if not abs(res[c] - v) <= 1e-12 * tot:
                return "set %s: resultant[%d] %.17g, sum over its DOFs %.17g" % (s, c, res[c], v), err, bal
    return None, err, bal


def main():
    args = sys.argv[1:]
    rel = cutsys.rel_option(args, 1e-10)
    if len(args) != 2:
        raise SystemExit(__doc__)
    recs = augstream.records(open(args[0], "rb").read())
    text = dump_records(args[1])
    sc = Scene(augstream.mesh(recs))
    dim, fields, n, worst, wbal, msg = sc.dim, {}, 0, 0.0, 0.0, None
    for i, (t, fl, s, p) in enumerate(recs):
        if t == "MDLT":
            sc.apply_mdlt(cutsys.mdlt(p, dim, sc.nv))
        elif t == "BDLT":
            sc.apply_bdlt(cutsys.bdlt(p))
        if t not in ("fELD", "rEAC"):
            continue
        if i not in text or text[i][0] != t or text[i][1] != s:
            msg = "record %d (%s, step %d) is not in the dump" % (i, t, s)
            break
        f = text[i][2]
        if t == "fELD":
            if "node" not in f and int(f["count"]) == len(sc.x):
                fields[s] = f["u"]
            continue
        if s not in fields:
            msg = "step %d: no fELD of every node before its rEAC" % s
            break
        m, err, bal = check(sc, f, fields[s], rel)
        if m:
            msg = "step %d: %s" % (s, m)
            break
        n += 1
        worst, wbal = max(worst, err), max(wbal, bal)
    if msg:
        print("FAIL %s: %s" % (args[0], msg))
        sys.exit(1)
    print("ok %s reactions=%d max_rel=%.3g max_balance=%.3g" % (args[0], n, worst, wbal))


main()
