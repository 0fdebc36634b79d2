#!/usr/bin/env python3
"""Print the named-value records (cOND sTAt tIMe qUAl) of an augcut stream as
lines "TYPE step tag key value", and the node count as "NODE -1 - nn N",
seeking over every other payload (fast on streams holding a large FACT).
--records: one line per record instead, "TYPE step tag key=value ...".
usage: aug_kv.py [--records] FILE
As a module: payloads(path, types) yields (type, step, payload) of the
records of those types, inflated, seeking over the others."""
import struct, sys, zlib


def payloads(path, types):
    with open(path, "rb") as f:
        if f.read(8) != b"\x89AUG\r\n\x1a\n":
            sys.exit("%s: %s: not an augcut stream" % (sys.argv[0], path))
        while True:
            h = f.read(12)
            if len(h) < 12:
                return
            (blen,) = struct.unpack_from("<Q", h, 0)
            typ = h[8:12].decode("ascii", "replace")
            if typ not in types:
                f.seek(blen + 4, 1)
                continue
            body = f.read(blen)
            f.seek(4, 1)
            flags, step = struct.unpack_from("<Ii", body, 0)
            yield typ, step, zlib.decompress(body[16:]) if flags & 1 else body[16:]


if __name__ == "__main__":
    per_rec = "--records" in sys.argv
    for typ, step, p in payloads(sys.argv[-1], ("cOND", "sTAt", "tIMe", "qUAl", "NODE")):
        if typ == "NODE":
            print("NODE -1 - nn %d" % struct.unpack_from("<q", p, 8)[0])
            continue
        tag = p[:16].split(b"\0")[0].decode()
        (n,) = struct.unpack_from("<i", p, 16)
        kv = []
        for q in range(n):
            key = p[24 + 24 * q:40 + 24 * q].split(b"\0")[0].decode()
            (v,) = struct.unpack_from("<d", p, 40 + 24 * q)
            kv.append((key, v))
        if per_rec:
            print("%s %d %s %s" % (typ, step, tag, " ".join("%s=%.17g" % x for x in kv)))
        else:
            for key, v in kv:
                print("%s %d %s %s %.17g" % (typ, step, tag, key, v))
