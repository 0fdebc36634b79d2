"""Compare two `stats --dump` texts with numeric tolerances (tests/golden.test).

    python3 dumpcmp.py GOLDEN NEW        exit 0 when they match, else 1 with
                                         the first differences on stdout

Records (lines starting with "#") must agree in number and header. In pROv
records the directory of the program that wrote them is left out (the
command line "/x/bin/cut --plane ..." reads "cut --plane ..."), and with it
their len=, so that the tools may be called by any path. Within a
record, lines are split into whitespace tokens; a token that is a number in
both texts compares numerically, every other token exactly. Numbers a
(golden) and b (new) match when
  |a - b| <= RTOL * max(|a|, |b|)                     (relative 1e-9), or
  |a - b| <= RTOL * S, S = the largest magnitude in the same field: an entry
      at rounding level against its array (a matrix entry that cancels to
      1e-17, a displacement component of 1e-19) is noise, not drift, or
  the key is a residual (relres*, berr_*, err_*) and |a - b| <= RES_ATOL: these
      measure rounding error itself (1e-15), whose digits are not
      reproducible across BLAS or compiler versions.
A field is a line indented by two spaces with its continuation lines (four
spaces, starting with "N:" or a number); a four-space line "key value" of a
named-value record is a field of its own."""
import re
import sys

RTOL = 1e-9
RES_ATOL = 1e-10
RESIDUAL = re.compile(r"^(relres\w*|berr_\w+|err_\w+)$")
INDEX = re.compile(r"^\d+:$")
PROG_DIR = re.compile(r'^(\s*")/[^" ]*/')


def num(tok):
    try:
        return float(tok)
    except ValueError:
        return None


def records(path):
    recs, cur = [], None
    for line in open(path):
        line = line.rstrip("\n")
        if line.startswith("#"):
            if " pROv " in line:
                line = line.split(" len=")[0]
            cur = [line, []]
            recs.append(cur)
        elif cur is None:
            raise SystemExit("%s: text before the first record header" % path)
        else:
            if " pROv " in cur[0]:
                line = PROG_DIR.sub(r"\1", line)
                if line.lstrip().startswith("text["):
                    line = "  text"
            cur[1].append(line)
    return recs


def fields(lines):
    """[[line, ...]] grouped as described above"""
    out = []
    for line in lines:
        toks = line.split()
        cont = line.startswith("    ") and toks and (INDEX.match(toks[0]) or num(toks[0]) is not None)
        if cont and out:
            out[-1].append(line)
        else:
            out.append([line])
    return out


def compare_field(ga, gb, where, bad):
    ta = [t for l in ga for t in l.split()]
    tb = [t for l in gb for t in l.split()]
    if len(ta) != len(tb):
        bad.append("%s: %d tokens, golden has %d: %r" % (where, len(tb), len(ta), gb[0].strip()))
        return
    key = ta[0] if ta else ""
    vals = [abs(v) for v in map(num, ta) if v is not None]
    scale = max(vals) if vals else 0.0
    for x, y in zip(ta, tb):
        a, b = num(x), num(y)
        if a is None or b is None:
            if x != y:
                bad.append("%s: %r, golden %r" % (where, y, x))
            continue
        d = abs(a - b)
        if d <= RTOL * max(abs(a), abs(b)) or d <= RTOL * scale:
            continue
        if RESIDUAL.match(key) and d <= RES_ATOL:
            continue
        bad.append("%s: %s = %r, golden %r (relative %.3g)" % (where, key, b, a, d / max(abs(a), abs(b))))


def main(golden, new):
    ra, rb = records(golden), records(new)
    bad = []
    if len(ra) != len(rb):
        bad.append("%d records, golden has %d" % (len(rb), len(ra)))
    for (ha, la), (hb, lb) in zip(ra, rb):
        if ha != hb:
            bad.append("header %r, golden %r" % (hb, ha))
            continue
        fa, fb = fields(la), fields(lb)
        if len(fa) != len(fb):
            bad.append("%s: %d fields, golden has %d" % (ha, len(fb), len(fa)))
            continue
        for ga, gb in zip(fa, fb):
            compare_field(ga, gb, ha.split(" step")[0], bad)
    for b in bad[:20]:
        print("%s: %s" % (new, b))
    if len(bad) > 20:
        print("%s: ... %d differences in all" % (new, len(bad)))
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit("usage: dumpcmp.py GOLDEN NEW")
    sys.exit(main(sys.argv[1], sys.argv[2]))
