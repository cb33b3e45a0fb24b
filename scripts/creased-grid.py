#!/usr/bin/env python3
"""A wavy N x N grid of quads with creases on a random fraction of its edges, as OBJ
with OpenSubdiv's `t crease` tags, for benchmarks of meshes whose faces nearly all have
irregular neighbourhoods (darts, crease corners and bends, semi-sharp edges meeting).

    scripts/creased-grid.py N FRACTION SEED SHARPNESS > grid.obj

SHARPNESS is `inf` (every crease 10, infinitely sharp), `steps` (1, 2 or 3 at random) or
`random` (uniform in 0.5..4.5, two decimals). The same arguments give the same file.
BENCHMARKS.md ("Meshes with many creases") uses N = 100, FRACTION = 0.1, SEED = 1.
"""
import math
import random
import sys


def main():
    if len(sys.argv) != 5 or sys.argv[4] not in ("inf", "steps", "random"):
        sys.exit(__doc__)
    n, fraction, seed, kind = int(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    rng = random.Random(seed)
    out = []
    for j in range(n + 1):
        for i in range(n + 1):
            z = 0.1 * math.sin(7 * i / n) * math.cos(5 * j / n)
            out.append(f"v {i / n:.6f} {j / n:.6f} {z:.6f}")

    def vid(i, j):
        return j * (n + 1) + i + 1

    for j in range(n):
        for i in range(n):
            out.append(f"f {vid(i, j)} {vid(i + 1, j)} {vid(i + 1, j + 1)} {vid(i, j + 1)}")
    for j in range(n + 1):
        for i in range(n + 1):
            for a, b in (((i, j), (i + 1, j)), ((i, j), (i, j + 1))):
                if b[0] > n or b[1] > n or rng.random() >= fraction:
                    continue
                s = {
                    "inf": lambda: 10,
                    "steps": lambda: rng.choice([1, 2, 3]),
                    "random": lambda: round(rng.uniform(0.5, 4.5), 2),
                }[kind]()
                out.append(f"t crease 2/1/0 {vid(*a) - 1} {vid(*b) - 1} {s}")
    print("\n".join(out))


if __name__ == "__main__":
    main()
