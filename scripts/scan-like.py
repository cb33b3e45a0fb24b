#!/usr/bin/env python3
"""Writes a scan-like all-triangle mesh: a bumpy torus of N x M quads, each split into two
triangles along a random diagonal, so vertex valences range over 4-8 as in scans and CAD
tessellations (not the regular valence 6 of a grid cut the same way everywhere). Used by
BENCHMARKS.md ("Loop and bilinear") for the Loop rows.

Usage: scripts/scan-like.py OUT.obj [N M [SEED]]   (default 250 x 200: 100 000 triangles)
"""
import math
import random
import sys


def main():
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 250
    m = int(sys.argv[3]) if len(sys.argv) > 3 else 200
    rng = random.Random(int(sys.argv[4]) if len(sys.argv) > 4 else 1)
    with open(out, "w") as f:
        for i in range(n):
            for j in range(m):
                u, v = 2 * math.pi * i / n, 2 * math.pi * j / m
                r = 0.35 + 0.02 * math.sin(7 * u) * math.cos(5 * v) + 0.002 * rng.random()
                f.write("v %.17g %.17g %.17g\n" % ((1 + r * math.cos(v)) * math.cos(u),
                                                   (1 + r * math.cos(v)) * math.sin(u),
                                                   r * math.sin(v)))
        idx = lambda i, j: (i % n) * m + (j % m) + 1
        for i in range(n):
            for j in range(m):
                a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
                if rng.random() < 0.5:
                    f.write("f %d %d %d\nf %d %d %d\n" % (a, b, c, a, c, d))
                else:
                    f.write("f %d %d %d\nf %d %d %d\n" % (a, b, d, b, c, d))


if __name__ == "__main__":
    main()
