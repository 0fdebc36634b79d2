#!/usr/bin/env python3
"""Print the named-value records (cOND sTAt tIMe qUAl) of an augcut stream as
lines "TYPE step tag key value", and the node count as "NODE -1 - nn N",
seeking over every other payload (fast on streams holding a large FACT).
--records: one line per record instead, "TYPE step tag key=value ...".
usage: aug_kv.py [--records] FILE"""
import struct, sys, zlib

per_rec = "--records" in sys.argv
with open(sys.argv[-1], "rb") as f:
    if f.read(8) != b"\x89AUG\r\n\x1a\n":
        sys.exit("aug_kv.py: not an augcut stream")
    while True:
        h = f.read(12)
        if len(h) < 12:
            break
        (blen,) = struct.unpack_from("<Q", h, 0)
        typ = h[8:12].decode("ascii", "replace")
        if typ in ("cOND", "sTAt", "tIMe", "qUAl", "NODE"):
            body = f.read(blen)
            f.seek(4, 1)
            flags, step = struct.unpack_from("<Ii", body, 0)
            p = zlib.decompress(body[16:]) if flags & 1 else body[16:]
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
                print("%s %d %s %s" % (typ, step, tag, " ".join("%s=%.17g" % kv_ for kv_ in kv)))
            else:
                for key, v in kv:
                    print("%s %d %s %s %.17g" % (typ, step, tag, key, v))
        else:
            f.seek(blen + 4, 1)
