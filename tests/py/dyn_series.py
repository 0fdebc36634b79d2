#!/usr/bin/env python3
"""Time series of a dynamic stream's frames (formats/stream.md 7.9): per fRAM
'frame time mean' with mean the average of component C of u over the frame's
nodes; with --period: the mean period of the oscillation of that average
about its mean, from the up-crossings (linear interpolation) after --skip
frames, printed as 'period T crossings N'.

usage: dyn_series.py C [--period] [--skip N] STREAM"""
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402


def main():
    args = sys.argv[1:]
    period = "--period" in args
    if period:
        args.remove("--period")
    skip = 0
    if "--skip" in args:
        i = args.index("--skip")
        skip = int(args[i + 1])
        del args[i:i + 2]
    if len(args) != 2:
        raise SystemExit(__doc__)
    comp = int(args[0])
    ts, ys = [], []
    for t, fl, s, p in augstream.records(open(args[1], "rb").read()):
        if t != "fRAM":
            continue
        fr, dim, count, time, indexed = struct.unpack_from("<iiqdi", p, 0)
        pos = 32 + (4 * count if indexed else 0)
        u, _ = augstream.arr("d", p, pos, count * dim)
        y = sum(u[q * dim + comp] for q in range(count)) / count
        ts.append(time)
        ys.append(y)
        if not period:
            print(fr, repr(time), repr(y))
    if period:
        t2, y2 = ts[skip:], ys[skip:]
        mean = sum(y2) / len(y2)
        up = []
        for k in range(1, len(y2)):
            a, b = y2[k - 1] - mean, y2[k] - mean
            if a < 0 <= b:
                up.append(t2[k - 1] + (t2[k] - t2[k - 1]) * (-a) / (b - a))
        if len(up) < 2:
            raise SystemExit("fewer than two up-crossings")
        print("period %.17g crossings %d" % ((up[-1] - up[0]) / (len(up) - 1), len(up)))


main()
