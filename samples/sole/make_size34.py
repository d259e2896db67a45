#!/usr/bin/env python3
"""Makes size34.csv: a plausible digitised size-34 insole contour (seed 001, §2.1, §7).

No real pattern was available. The outline is drawn from 29 hand-placed key points
(heel at y = 0, toe at y = 228, 79 mm wide at the ball, a concave waist on the arch side:
the extents of the seed's example file, about 82 × 228 mm), joined by a periodic
Catmull-Rom spline, sampled at 80 points evenly by length counter-clockwise from the heel
(so p1–p3 lie on the heel arc, as in the seed's prototype), given σ = 0.05 mm of tracing
noise (seeded, reproducible) and rounded to 0.1 mm as read off millimetre paper.
"""
import math
import random

KEY = [
    (41, 0), (56, 4), (66, 14), (70, 30), (69, 50), (67, 75), (66, 100), (70, 125),
    (78, 150), (82, 165), (81, 185), (76, 203), (66, 218), (52, 226), (38, 228), (24, 224),
    (13, 214), (6, 198), (3, 178), (4, 158), (8, 138), (14, 118), (17, 100), (16, 80),
    (13, 60), (12, 40), (14, 22), (22, 8), (31, 2),
]


def catmull(p0, p1, p2, p3, t):
    return tuple(
        0.5 * (2 * b + (-a + c) * t + (2 * a - 5 * b + 4 * c - d) * t * t
               + (-a + 3 * b - 3 * c + d) * t ** 3)
        for a, b, c, d in zip(p0, p1, p2, p3)
    )


def main():
    n = len(KEY)
    dense = []
    for i in range(n):
        for k in range(50):
            dense.append(catmull(KEY[i - 1], KEY[i], KEY[(i + 1) % n], KEY[(i + 2) % n], k / 50))
    seg = [math.dist(dense[i], dense[(i + 1) % len(dense)]) for i in range(len(dense))]
    total = sum(seg)
    rng = random.Random(34)
    out, acc, i = [], 0.0, 0
    for k in range(80):
        s = total * k / 80
        while acc + seg[i] < s:
            acc += seg[i]
            i += 1
        t = (s - acc) / seg[i]
        a, b = dense[i], dense[(i + 1) % len(dense)]
        x = a[0] + (b[0] - a[0]) * t + rng.gauss(0, 0.05)
        y = a[1] + (b[1] - a[1]) * t + rng.gauss(0, 0.05)
        out.append((round(x, 1), round(y, 1)))
    with open("size34.csv", "w") as f:
        f.write("# size-34 left insole, digitised (synthetic: see make_size34.py), mm\n")
        f.write("x,y\n")
        for x, y in out:
            f.write(f"{x + 0.0:.1f},{y + 0.0:.1f}\n")


if __name__ == "__main__":
    main()
