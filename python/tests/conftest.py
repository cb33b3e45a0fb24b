"""Shared helpers: the repository's OpenSubdiv regression shapes and golden data, read
without subsurf (so that the tests compare subsurf with OpenSubdiv, not with itself)."""

import gzip
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
SHAPES = REPO / "crates" / "subsurf" / "tests" / "shapes" / "osd"
GOLDEN = REPO / "crates" / "subsurf" / "tests" / "golden"

BOUNDARY = {"0": "none", "1": "edgeAndCorner", "2": "edgeOnly"}


def read_shape(name):
    """The OBJ shape `name` as the keyword arguments of `subsurf.Mesh`: points, faces and
    OpenSubdiv's tags (`t crease`, `t corner`, `t hole`, `t interpolateboundary`,
    `t creasemethod`, `t smoothtriangles`), parsed here."""
    points, counts, indices = [], [], []
    crease_indices, crease_sharpnesses = [], []
    corner_indices, corner_sharpnesses, holes = [], [], []
    kw = {}
    for line in (SHAPES / f"{name}.obj").read_text().splitlines():
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            points.append([float(x) for x in t[1:4]])
        elif t[0] == "f":
            corners = [int(c.split("/")[0]) - 1 for c in t[1:]]
            counts.append(len(corners))
            indices.extend(corners)
        elif t[0] == "t":
            tag, args = t[1], t[3:]
            if tag == "crease":
                crease_indices += [int(args[0]), int(args[1])]
                crease_sharpnesses.append(float(args[2]))
            elif tag == "corner":
                corner_indices.append(int(args[0]))
                corner_sharpnesses.append(float(args[1]))
            elif tag == "hole":
                holes += [int(a) for a in args]
            elif tag == "interpolateboundary":
                kw["interpolate_boundary"] = BOUNDARY[args[0]]
            elif tag == "creasemethod":
                kw["crease_method"] = "chaikin" if args[0] == "chaikin" else "uniform"
            elif tag == "smoothtriangles":
                kw["triangle_subdivision_rule"] = "smooth" if args[0] == "smooth" else "catmullClark"
    kw.update(
        points=np.array(points),
        face_vertex_counts=np.array(counts),
        face_vertex_indices=np.array(indices),
    )
    if crease_sharpnesses:
        kw.update(
            crease_indices=np.array(crease_indices),
            crease_lengths=np.full(len(crease_sharpnesses), 2),
            crease_sharpnesses=np.array(crease_sharpnesses),
        )
    if corner_indices:
        kw.update(corner_indices=corner_indices, corner_sharpnesses=corner_sharpnesses)
    if holes:
        kw.update(hole_indices=holes)
    return kw


def golden_refinement(name):
    """`{(level, mode): (verts, {index: xyz})}` of `golden/osd/<name>.txt.gz` (OpenSubdiv's
    `Far` refinement; `golden/osd_schemes` for Loop and bilinear shapes; the format is in
    `golden/README.md`)."""
    cases, current = {}, None
    kind = "osd" if name.startswith("catmark") else "osd_schemes"
    with gzip.open(GOLDEN / kind / f"{name}.txt.gz", "rt") as f:
        for line in f:
            t = line.split()
            if not t or t[0] in ("#", "shape"):
                continue
            if t[0] == "case":
                current = {}
                cases[(int(t[1]), t[2])] = (int(t[4]), current)
            elif t[0] != "end":
                current[int(t[0])] = np.array([float(x) for x in t[1:4]])
    return cases


def golden_limit(name, kind="limit"):
    """`(faces, u, v, p, du, dv)` arrays of `golden/<kind>/<name>.txt.gz` (OpenSubdiv's
    `Bfr` on a 5 x 5 grid of every quad face, or on Loop's triangular grid)."""
    rows = []
    with gzip.open(GOLDEN / kind / f"{name}.txt.gz", "rt") as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            rows.append([float(x) for x in line.split()])
    a = np.array(rows)
    return a[:, 0].astype(int), a[:, 1], a[:, 2], a[:, 3:6], a[:, 6:9], a[:, 9:12]
