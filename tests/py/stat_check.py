#!/usr/bin/env python3
"""Assertions on the rows of `stats --csv`, read with Python's csv module.

usage: stat_check.py CSV METHOD ROWS EXPR...

Every row of METHOD (there must be exactly ROWS of them; ROWS may be "+"
for at least one) must make every EXPR true: a Python expression over the
row's columns by name (step, relres, refine, ...), each a float, or None when
the cell is empty or NaN (so `relres <= 1e-12` fails on an empty cell with a
message, and `relres is None` tests for one). Also `rows`, the list of all
rows of METHOD as such dicts, e.g. for `max(r["rebuilt"] for r in rows) > 0`
(with ROWS, EXPRs that use only rows are evaluated once). Prints the first
failing row and expression; exit 1."""
import csv
import math
import sys


def val(s):
    try:
        v = float(s)
    except ValueError:
        return None
    return None if math.isnan(v) else v


def main():
    path, method, want, exprs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    rows = [{k: val(v) for k, v in r.items()} for r in csv.DictReader(open(path)) if r["method"] == method]
    if (want == "+" and not rows) or (want != "+" and len(rows) != int(want)):
        sys.exit("%s: %d rows of %s, want %s" % (path, len(rows), method, want))
    for e in exprs:
        code = compile(e, e, "eval")
        per_row = any(n != "rows" and n not in ("max", "min", "sum", "len", "all", "any", "r", "abs")
                      for n in code.co_names)
        for r in rows if per_row else [{}]:
            env = dict(r, rows=rows)
            try:
                ok = eval(code, {"__builtins__": {"max": max, "min": min, "sum": sum, "len": len, "all": all,
                                                  "any": any, "abs": abs}}, env)
            except (TypeError, NameError):
                ok = False
            if not ok:
                shown = {k: r.get(k) for k in code.co_names if k in r}
                sys.exit("%s: %s step %s: %s is false (%s)" % (path, method, r.get("step", "-"), e, shown))


main()
