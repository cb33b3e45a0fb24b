#!/usr/bin/env python3
"""Writes OBJ meshes that stress refinement where ordinary models do not (BENCHMARKS.md,
"Quad meshes, extreme valences, Chaikin creases and low levels of large scans"):

  cyl1000.obj   a cylinder of 10 x 1000 quads closed by two 1000-gons
  cone1000.obj  a double cone: two apexes of valence 1000, 2000 triangles
  strip.obj     a strip of 20 000 quads, one wide (all of it boundary)
  uvsphere.obj  a UV sphere of 64 x 32: quads, and triangle fans of valence 64 at the poles

Usage: scripts/stress-meshes.py OUTDIR
"""
import math
import os
import sys


def write(path, verts, faces):
    with open(path, "w") as out:
        for p in verts:
            out.write("v %.17g %.17g %.17g\n" % p)
        for f in faces:
            out.write("f " + " ".join(str(i + 1) for i in f) + "\n")


def cylinder(n, rows):
    verts = [
        (math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), 2 * r / rows)
        for r in range(rows + 1)
        for i in range(n)
    ]
    faces = [
        (r * n + i, r * n + (i + 1) % n, (r + 1) * n + (i + 1) % n, (r + 1) * n + i)
        for r in range(rows)
        for i in range(n)
    ]
    faces.append(tuple(reversed(range(n))))
    faces.append(tuple(rows * n + i for i in range(n)))
    return verts, faces


def cone(n):
    verts = [(0.0, 0.0, 1.0), (0.0, 0.0, 0.0)]
    verts += [
        (math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), 0.3) for i in range(n)
    ]
    faces = []
    for i in range(n):
        j = (i + 1) % n
        faces += [(0, 2 + i, 2 + j), (1, 2 + j, 2 + i)]
    return verts, faces


def strip(n):
    verts = []
    for i in range(n + 1):
        verts += [(float(i), 0.0, 0.0), (float(i), 1.0, 0.1 * math.sin(i))]
    faces = [(2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1) for i in range(n)]
    return verts, faces


def uv_sphere(nu, nv):
    verts = [(0.0, 0.0, 1.0)]
    for j in range(1, nv):
        t = math.pi * j / nv
        for i in range(nu):
            p = 2 * math.pi * i / nu
            verts.append((math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)))
    verts.append((0.0, 0.0, -1.0))
    south = len(verts) - 1
    faces = [(0, 1 + i, 1 + (i + 1) % nu) for i in range(nu)]
    for j in range(nv - 2):
        for i in range(nu):
            a, b = 1 + j * nu + i, 1 + j * nu + (i + 1) % nu
            faces.append((a, a + nu, b + nu, b))
    last = 1 + (nv - 2) * nu
    faces += [(south, last + (i + 1) % nu, last + i) for i in range(nu)]
    return verts, faces


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        sys.stderr.write(__doc__)
        return 2
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name, (verts, faces) in [
        ("cyl1000", cylinder(1000, 10)),
        ("cone1000", cone(1000)),
        ("strip", strip(20000)),
        ("uvsphere", uv_sphere(64, 32)),
    ]:
        write(os.path.join(out, name + ".obj"), verts, faces)
    return 0


if __name__ == "__main__":
    sys.exit(main())
