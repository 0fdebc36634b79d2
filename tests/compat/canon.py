#!/usr/bin/env python3
"""Canonical digest of one tool run for the before/after comparison of a
refactor (tests/compat/snapshot.sh): a stream minus its timing (tIMe) and
provenance (pROv) records, re-framed, hashed; other output hashed as text
when it is deterministic (stats --dump --no-times), else only its size class.
usage: canon.py OUTFILE RC TOOL ARGS..."""
import hashlib, os, re, struct, sys, zlib

SIG = b"\x89AUG\r\n\x1a\n"


def canon_stream(data):
    pos, parts = 8, [SIG]
    while pos + 12 <= len(data):
        (blen,) = struct.unpack_from("<Q", data, pos)
        typ = data[pos + 8:pos + 12]
        end = pos + 16 + blen
        if end > len(data):
            parts.append(b"TRUNC" + data[pos:])
            break
        if typ not in (b"tIMe", b"pROv"):
            body = data[pos + 12:pos + 12 + blen]
            flags, step, rawlen = struct.unpack_from("<IiQ", body, 0) if blen >= 16 else (0, 0, 0)
            payload = body[16:]
            if flags & 1:
                try:
                    payload = zlib.decompress(payload)
                except zlib.error:
                    pass
            parts.append(typ + struct.pack("<iQ", step, len(payload)) + payload)
        pos = end
    if pos < len(data):
        parts.append(b"REST" + data[pos:])
    return b"".join(parts)


out, rc, tool = sys.argv[1], sys.argv[2], sys.argv[3]
args = " ".join(sys.argv[4:])
root = os.environ.get("AUG_ROOT")
if root:
    args = args.replace(root, "ROOT")
args = re.sub(r"/tmp/[A-Za-z0-9._-]*", "TMP", args)
data = open(out, "rb").read()
if data[:8] == SIG:
    kind, digest = "stream", hashlib.sha256(canon_stream(data)).hexdigest()[:16]
elif tool == "stats" and "--dump" in args and "--no-times" in args:
    # pROv records name the tools' paths and temporary files: left out
    text = re.sub(rb"(?m)^#\d+ pROv .*\n(?:[^#].*\n)*", b"", data)
    kind, digest = "dump", hashlib.sha256(text).hexdigest()[:16]
else:
    kind, digest = "text", "-"
test = os.environ.get("AUG_SNAP_TEST", "?")
print("%s\t%s %s\trc=%s\t%s\t%s" % (test, tool, args, rc, kind, digest))
