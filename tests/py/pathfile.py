"""The path file of cut(1) (PATH FILE), read from the manual only, for the
test oracles: line, polyline, Bezier of degree n (2(n+1) numbers; the
Bernstein sum), rational Bezier rbezier (n+1 triples x y w), rational
quadratic arc (weights 1, w, 1) and circle (four quarter arcs, w = cos 45 deg, counter-clockwise from
(cx + r, cy)); '#' comments; numbers separated by blanks or commas. The path
is advanced by arc length over all its items (gaps between strokes do not
count)."""
import math

COUNT = {"line": 4, "bezier": 8, "arc": 7, "circle": 3}


def bernstein(P, W, t):
    """sum w_i P_i C(n,i) t^i (1-t)^(n-i) / sum w_i C(n,i) t^i (1-t)^(n-i)"""
    n = len(P) - 1
    b = [W[i] * math.comb(n, i) * t ** i * (1 - t) ** (n - i) for i in range(n + 1)]
    return tuple(sum(b[i] * P[i][k] for i in range(n + 1)) / sum(b) for k in (0, 1))


def item(kind, v):
    """the point function [0, 1] -> (x, y) of one item"""
    if kind in ("bezier", "rbezier"):
        st = 3 if kind == "rbezier" else 2
        P = [(v[i], v[i + 1]) for i in range(0, len(v), st)]
        W = [v[i + 2] for i in range(0, len(v), 3)] if st == 3 else [1.0] * len(P)
        return lambda t: bernstein(P, W, t)
    if kind == "line":
        return lambda t: (v[0] + t * (v[2] - v[0]), v[1] + t * (v[3] - v[1]))
    w = v[6]

    def arc(t):
        b = ((1 - t) ** 2, 2 * w * t * (1 - t), t * t)
        return tuple(sum(b[i] * v[2 * i + k] for i in range(3)) / sum(b) for k in (0, 1))
    return arc


def read(name):
    """the items of the path file, in order"""
    out = []
    for line in open(name):
        words = line.split("#", 1)[0].replace(",", " ").split()
        if not words:
            continue
        v = [float(s) for s in words[1:]]
        if words[0] == "polyline":
            out += [item("line", v[i:i + 4]) for i in range(0, len(v) - 2, 2)]
        elif words[0] == "circle":
            cx, cy, r = v
            w = math.cos(math.pi / 4)
            for q in range(4):
                a = [(cx + r * math.cos(math.pi / 2 * k), cy + r * math.sin(math.pi / 2 * k)) for k in (q, q + 1)]
                c = (a[0][0] + a[1][0] - cx, a[0][1] + a[1][1] - cy)  # the corner between them
                out.append(item("arc", [a[0][0], a[0][1], c[0], c[1], a[1][0], a[1][1], w]))
        elif words[0] == "bezier" and len(v) % 2 == 0 and len(v) >= 4:
            out.append(item("bezier", v))
        elif words[0] == "rbezier" and len(v) % 3 == 0 and len(v) >= 6:
            out.append(item("rbezier", v))
        elif words[0] in COUNT and len(v) == COUNT[words[0]]:
            out.append(item(words[0], v))
        else:
            raise ValueError("%s: cannot read '%s'" % (name, line.strip()))
    return out


def samples(f, chords):
    """parameters of f: chords uniform ones, then every chord longer than
    1/chords of the item's length halved until none is (a rational arc of
    weight 50 puts most uniform parameters near its middle control point and
    left its legs in chords of a tenth of their length: the oracle then saw
    the cut's nodes far from the path)"""
    ts = [i / chords for i in range(chords + 1)]
    for _ in range(40):
        ps = [f(t) for t in ts]
        lim = sum(math.dist(p, q) for p, q in zip(ps, ps[1:])) / chords
        out = [ts[0]]
        for a, b, p, q in zip(ts, ts[1:], ps, ps[1:]):
            if math.dist(p, q) > lim and b - a > 1e-15:
                out.append((a + b) / 2)
            out.append(b)
        if len(out) == len(ts):
            return ts
        ts = out
    return ts


class Path:
    """the items sampled by fine chords (adaptive: samples): arc length s -> point"""

    def __init__(self, name, chords=1024):
        self.pts, self.s = [], []
        total = 0.0
        for f in read(name):
            prev = f(0.0)
            for t in samples(f, chords):
                p = f(t)
                total += math.dist(prev, p)
                self.pts.append(p)
                self.s.append(total)
                prev = p
        self.total = total

    def part(self, s0, s1):
        """the sample points with arc length in [s0, s1]"""
        return [p for p, s in zip(self.pts, self.s) if s0 <= s <= s1]
