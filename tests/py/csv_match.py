#!/usr/bin/env python3
"""stats --csv against the sTAt and tIMe records of its stream, read by the
independent reader (augstream.py) and parsed with Python's csv module
(RFC 4180: a quoted cell holds commas, doubled quotes, line breaks).

usage: csv_match.py STREAM CSV
The header is step,method,time_ms,relres,m,k then every other sTAt/tIMe key
sorted by its bytes; one row per sTAt record in stream order, (step, tag) of
the record; every cell the record's value (sTAt over tIMe), empty where the
records have none. Prints the failures; exit 1 on any."""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import augstream  # noqa: E402


def main():
    stat, time = {}, {}
    for t, f, s, p in augstream.records(open(sys.argv[1], "rb").read()):
        if t in ("sTAt", "tIMe"):
            tag, d = augstream.kv(p)
            (stat if t == "sTAt" else time)[(s, tag)] = d
    rows = list(csv.reader(open(sys.argv[2], newline="")))
    head, body = rows[0], rows[1:]
    fail = []
    lead = ["step", "method", "time_ms", "relres", "m", "k"]
    others = sorted({k for d in list(stat.values()) + list(time.values()) for k in d} - set(lead),
                    key=lambda k: k.encode())
    if head != lead + others:
        fail.append("header %s, want %s" % (head, lead + others))
    if len(body) != len(stat):
        fail.append("%d rows for %d sTAt records" % (len(body), len(stat)))
    for r in body:
        if len(r) != len(head):
            fail.append("row %s has %d cells" % (r, len(r)))
            continue
        key = (int(r[0]), r[1])
        d = dict(time.get(key, {}))
        d.update(stat.get(key, {}))
        for name, cell in zip(head[2:], r[2:]):
            if name in d:
                if cell == "" or float(cell) != d[name]:
                    fail.append("%s %s: %r, want %r" % (key, name, cell, d[name]))
            elif cell != "":
                fail.append("%s %s: %r where the records have nothing" % (key, name, cell))
    if [(int(r[0]), r[1]) for r in body] != list(stat.keys()):
        fail.append("row order %s, want %s" % ([(r[0], r[1]) for r in body], list(stat.keys())))
    for f in fail:
        print("FAIL:", f)
    sys.exit(1 if fail else 0)


main()
