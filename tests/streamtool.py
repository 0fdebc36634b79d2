#!/usr/bin/env python3
"""Independent implementation of the augcut stream framing (formats/stream.md),
used by the shell tests to inspect streams and to damage them on purpose.

usage: streamtool.py list FILE                 one line per record: index type step len flags
       streamtool.py damage KIND FILE > OUT    KIND: truncate-mid, truncate-tail, flip, signature,
                                               textmode, version, length, notail, critical,
                                               ancillary, badtail
"""
import struct, sys, zlib

SIG = b"\x89AUG\r\n\x1a\n"

def records(data):
    if data[:8] != SIG:
        raise SystemExit("bad signature")
    pos, out = 8, []
    while pos < len(data):
        (blen,) = struct.unpack_from("<Q", data, pos)
        typ = data[pos + 8:pos + 12]
        body = data[pos + 12:pos + 12 + blen]
        (crc,) = struct.unpack_from("<I", data, pos + 12 + blen)
        if zlib.crc32(typ + body) != crc:
            raise SystemExit("crc mismatch at %d" % pos)
        flags, step, rawlen = struct.unpack_from("<IiQ", body, 0)
        payload = body[16:]
        if flags & 1:
            payload = zlib.decompress(payload)
        assert len(payload) == rawlen
        out.append(dict(start=pos, end=pos + 16 + blen, type=typ.decode(), step=step,
                        flags=flags, payload=payload, body=body))
        pos += 16 + blen
    return out

def record(typ, payload, step=-1):
    body = struct.pack("<IiQ", 0, step, len(payload)) + payload
    return struct.pack("<Q", len(body)) + typ + body + struct.pack("<I", zlib.crc32(typ + body))

def damage(kind, data):
    recs = records(data)
    tail = recs[-1]
    assert tail["type"] == "TAIL"
    before_tail = data[:tail["start"]]
    ntail = len(recs)  # records before TAIL, counting HEAD, once one is added
    if kind == "truncate-mid":
        r = recs[len(recs) // 2]
        return data[:(r["start"] + r["end"]) // 2]
    if kind == "truncate-tail":
        return data[:-3]
    if kind == "flip":
        r = recs[len(recs) // 2]
        b = bytearray(data)
        b[r["start"] + 12 + 16 + len(r["body"]) // 2 - 8] ^= 0x10
        return bytes(b)
    if kind == "signature":
        return b"AUGCUT\n\n" + data[8:]
    if kind == "textmode":
        return data[:4] + b"\n" + data[6:]       # CR LF -> LF
    if kind == "version":
        h = recs[0]
        payload = struct.pack("<II", 2, 0) + h["payload"][8:]
        return SIG + record(b"HEAD", payload) + data[h["end"]:]
    if kind == "length":
        r = recs[len(recs) // 2]
        b = bytearray(data)
        struct.pack_into("<Q", b, r["start"], (1 << 62))
        return bytes(b)
    if kind == "notail":
        return before_tail
    if kind == "badtail":
        return before_tail + record(b"TAIL", struct.pack("<Q", ntail + 5))
    if kind in ("critical", "ancillary"):
        typ = b"XQZW" if kind == "critical" else b"xQZw"
        extra = record(typ, b"opaque payload \x00\x01\x02")
        return before_tail + extra + record(b"TAIL", struct.pack("<Q", ntail))
    raise SystemExit("unknown damage " + kind)

def main():
    if len(sys.argv) == 3 and sys.argv[1] == "list":
        for i, r in enumerate(records(open(sys.argv[2], "rb").read())):
            print(i, r["type"], r["step"], len(r["payload"]), r["flags"])
    elif len(sys.argv) == 4 and sys.argv[1] == "damage":
        sys.stdout.buffer.write(damage(sys.argv[2], open(sys.argv[3], "rb").read()))
    else:
        raise SystemExit(__doc__)

if __name__ == "__main__":
    main()
