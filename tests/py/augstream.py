"""Independent reader of the augcut stream (formats/stream.md), for tests.

Written from the specification only: signature, records
u64 length | type[4] | body (u32 flags, i32 step, u64 rawlen, payload) | u32 crc,
crc = zlib crc32 over type and body; TAIL counts the records before it.
decode() returns the list of records; mesh() decodes the mesh records."""
import struct
import sys
import zlib

SIG = b"\x89AUG\r\n\x1a\n"


class StreamError(Exception):
    pass


def records(data):
    """[(type, flags, step, payload)] of a whole stream; raises StreamError."""
    if data[:8] != SIG:
        raise StreamError("bad signature")
    pos, out = 8, []
    while True:
        if pos + 12 > len(data):
            raise StreamError("truncated before TAIL")
        length, = struct.unpack_from("<Q", data, pos)
        typ = data[pos + 8:pos + 12].decode("ascii")
        body = data[pos + 12:pos + 12 + length]
        if len(body) != length or length < 16 or pos + 16 + length > len(data):
            raise StreamError("truncated record %d" % len(out))
        crc, = struct.unpack_from("<I", data, pos + 12 + length)
        if crc != zlib.crc32(data[pos + 8:pos + 12 + length]) & 0xffffffff:
            raise StreamError("CRC of record %d (%s)" % (len(out), typ))
        flags, step, rawlen = struct.unpack_from("<IiQ", body, 0)
        payload = body[16:]
        if flags & 1:
            payload = zlib.decompress(payload)
        elif flags:
            raise StreamError("bad flags")
        if len(payload) != rawlen:
            raise StreamError("rawlen of record %d" % len(out))
        out.append((typ, flags, step, payload))
        pos += 16 + length
        if typ == "TAIL":
            n, = struct.unpack("<Q", payload)
            if n != len(out) - 1:
                raise StreamError("TAIL count %d, records %d" % (n, len(out) - 1))
            if pos != len(data):
                raise StreamError("bytes after TAIL")
            return out


def name(b):
    return b.split(b"\0", 1)[0].decode("utf-8")


def arr(fmt, payload, pos, n):
    size = struct.calcsize(fmt)
    return list(struct.unpack_from("<%d%s" % (n, fmt), payload, pos)), pos + n * size


def mesh(recs):
    """dict with dim, x (list of tuples), etype, nv, conn (list of tuples), mat,
    mats [(id, name, E, nu, rho, t)], sets {name: nodes} (in record order in
    set_order), fix {dof: value}, load {dof: value}, out (kind, name, nodes),
    types (record types in order)."""
    m = {"types": [r[0] for r in recs], "sets": {}, "set_order": []}
    for typ, flags, step, p in recs:
        if typ == "NODE":
            dim, _, nn = struct.unpack_from("<iiq", p, 0)
            x, end = arr("d", p, 16, nn * dim)
            assert end == len(p)
            m["dim"] = dim
            m["x"] = [tuple(x[i * dim:(i + 1) * dim]) for i in range(nn)]
        elif typ == "MATL":
            n, = struct.unpack_from("<i", p, 0)
            assert len(p) == 4 + 104 * n
            mats = []
            for i in range(n):
                o = 4 + 104 * i
                mid, = struct.unpack_from("<i", p, o)
                E, nu, rho, t = struct.unpack_from("<4d", p, o + 72)
                mats.append((mid, name(p[o + 8:o + 72]), E, nu, rho, t))
            m["mats"] = mats
        elif typ == "ELEM":
            et, nv, ne = struct.unpack_from("<iiq", p, 0)
            c, pos = arr("i", p, 16, ne * nv)
            mat, pos = arr("i", p, pos, ne)
            assert pos == len(p)
            m.update(etype=et, nv=nv, conn=[tuple(c[i * nv:(i + 1) * nv]) for i in range(ne)], mat=mat)
        elif typ == "nSEt":
            nm = name(p[:64])
            n, = struct.unpack_from("<q", p, 64)
            nodes, pos = arr("i", p, 72, n)
            assert pos == len(p)
            m["sets"][nm] = nodes
            m["set_order"].append(nm)
        elif typ in ("FIXD", "LOAD"):
            n, = struct.unpack_from("<q", p, 0)
            dof, pos = arr("i", p, 8, n)
            val, pos = arr("d", p, pos, n)
            assert pos == len(p)
            assert all(dof[i] < dof[i + 1] for i in range(n - 1))
            m["fix" if typ == "FIXD" else "load"] = dict(zip(dof, val))
        elif typ == "GRAV":
            m["grav"] = struct.unpack_from("<3d", p, 0)
        elif typ == "FNDN":
            n, = struct.unpack_from("<i", p, 0)
            assert len(p) == 8 + 8 * n
            m["fndn"] = list(struct.unpack_from("<%dd" % n, p, 8))
        elif typ == "oUTs":
            kind, = struct.unpack_from("<i", p, 0)
            nm = name(p[8:72])
            n, = struct.unpack_from("<q", p, 72)
            nodes, pos = arr("i", p, 80, n)
            assert pos == len(p)
            m["out"] = (kind, nm, nodes)
        elif typ == "HEAD":
            m["head"] = struct.unpack_from("<II", p, 0) + (p[8:].decode(),)
        elif typ == "pROv":
            m.setdefault("prov", []).append(p.decode())
    return m


def frame(p):
    """fRAM (7.9): (frame, time, dim, nodes or None, u, v); StreamError when
    the payload size disagrees with its header"""
    fr, dim, count, time, indexed = struct.unpack_from("<iiqdi", p, 0)
    pos = 32
    nodes = None
    if indexed:
        nodes, pos = arr("i", p, pos, count)
    u, pos = arr("d", p, pos, count * dim)
    v, pos = arr("d", p, pos, count * dim)
    if pos != len(p):
        raise StreamError("fRAM payload size")
    return fr, time, dim, nodes, u, v


def kv(p):
    """a named-value record (sTAt, tIMe, qUAl, cOND): (tag, {key: value})"""
    tag = name(p[:16])
    n, = struct.unpack_from("<i", p, 16)
    vals = {}
    for i in range(n):
        o = 24 + 24 * i
        vals[name(p[o:o + 16])] = struct.unpack_from("<d", p, o + 16)[0]
    return tag, vals
def hex_volume(P):
    """volume of the trilinear hex with corners P (gmsh order): the integral
    of det(dx/dxi) over [-1,1]^3 by the 2x2x2 Gauss rule (exact)"""
    g = 1 / 3 ** 0.5
    C = ((-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1))
    v = 0.0
    for xi in ((i, j, k) for i in (-g, g) for j in (-g, g) for k in (-g, g)):
        J = [[0.0] * 3 for _ in range(3)]
        for a, c in enumerate(C):
            f = [1 + c[k] * xi[k] for k in range(3)]
            d = (c[0] * f[1] * f[2] / 8, f[0] * c[1] * f[2] / 8, f[0] * f[1] * c[2] / 8)
            for r in range(3):
                for k in range(3):
                    J[r][k] += P[a][r] * d[k]
        v += (J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0])
              + J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]))
    return v


def measure(m, e):
    """signed volume (tet4, hex8) or area (tri3) of element e"""
    return corners_measure([m["x"][i] for i in m["conn"][e]])


def corners_measure(P):
    """signed volume (8 corners: hex8, 4: tet4) or area (3: tri3) of the element
    with corners P"""
    if len(P) == 8:
        return hex_volume(P)
    if len(P) == 4:
        a = [P[1][k] - P[0][k] for k in range(3)]
        b = [P[2][k] - P[0][k] for k in range(3)]
        c = [P[3][k] - P[0][k] for k in range(3)]
        return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6
    if len(P[0]) == 3:  # mem3: |(p1-p0) x (p2-p0)| / 2 (formats 5.3)
        a = [P[1][k] - P[0][k] for k in range(3)]
        b = [P[2][k] - P[0][k] for k in range(3)]
        n = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
        return 0.5 * (n[0] ** 2 + n[1] ** 2 + n[2] ** 2) ** 0.5
    return 0.5 * ((P[1][0] - P[0][0]) * (P[2][1] - P[0][1]) - (P[2][0] - P[0][0]) * (P[1][1] - P[0][1]))


if __name__ == "__main__":
    data = open(sys.argv[1], "rb").read() if len(sys.argv) > 1 else sys.stdin.buffer.read()
    m = mesh(records(data))
    print("records", " ".join(m["types"]))
    print("nodes", len(m.get("x", [])), "elements", len(m.get("conn", [])),
          "materials", len(m.get("mats", [])), "sets", len(m["sets"]))
    for s in m["set_order"]:
        print("set", s, len(m["sets"][s]))


def mode(p):
    """a MODE payload (formats 7.5) as a dict; phi[j][k] = the dim values of
    mode j at node nodes[k]"""
    domain, frame, dim, kind, count, r, _ = struct.unpack_from("<iiiiqii", p, 0)
    nodes, o = arr("i", p, 32, count)
    sigma, o = arr("d", p, o, r)
    flat, o = arr("d", p, o, r * count * dim)
    if o != len(p):
        raise StreamError("MODE length")
    phi = [[flat[(j * count + k) * dim:(j * count + k + 1) * dim] for k in range(count)] for j in range(r)]
    return {"domain": domain, "frame": frame, "dim": dim, "kind": kind, "count": count, "r": r,
            "nodes": nodes, "sigma": sigma, "phi": phi}
