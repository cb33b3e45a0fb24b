"""subsurf from Python against OpenSubdiv: meshes built from numpy arrays (the shapes parsed
here, not by subsurf), refined and evaluated, compared with the golden data that
OpenSubdiv 3.5 computed (`crates/subsurf/tests/golden/`, how it was made is in its
README): refinement vertex for vertex (`Far`), the limit at Bfr's sample points."""

import numpy as np
import pytest

import subsurf
from conftest import SHAPES, golden_limit, golden_refinement, read_shape

REFINED = [
    "catmark_cube", "catmark_cube_creases0", "catmark_cube_creases1", "catmark_cube_corner0",
    "catmark_cube_corner4", "catmark_chaikin0", "catmark_chaikin1", "catmark_hole_test1",
    "catmark_hole_test2", "catmark_edgeonly", "catmark_edgecorner", "catmark_edgenone",
    "catmark_nonquads", "catmark_smoothtris0", "catmark_smoothtris1", "catmark_fan",
    "catmark_tent_creases0", "catmark_nonman_edges", "catmark_pole8", "catmark_torus",
    "loop_cube", "loop_cube_creases0", "loop_chaikin0", "loop_pole8", "loop_nonman_edges",
    "bilinear_cube", "bilinear_nonquads0",
]

# Shapes without points where Bfr itself approximates (darts, Chaikin creases; see
# crates/subsurf/tests/integration/limit_golden.rs).
LIMIT = [
    "catmark_cube", "catmark_cube_creases0", "catmark_cube_corner0", "catmark_edgeonly",
    "catmark_edgecorner", "catmark_hole_test1", "catmark_nonquads", "catmark_pole8",
    "catmark_torus", "catmark_fan", "catmark_nonman_edges",
]
LOOP_LIMIT = ["loop_cube", "loop_cube_creases0", "loop_pole8", "loop_xord_boundary"]


def scheme_of(name):
    return {"catmark": "catmullClark", "loop": "loop", "bilinear": "bilinear"}[name.split("_")[0]]


def diagonal(points):
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


@pytest.mark.parametrize("name", REFINED)
def test_refinement_matches_opensubdiv_far(name):
    kw = read_shape(name)
    mesh = subsurf.Mesh(scheme=scheme_of(name), **kw)
    d = diagonal(kw["points"])
    for (level, mode), (verts, samples) in golden_refinement(name).items():
        if level > 3:
            continue
        refined = mesh.subdivide(level, limit=(mode == "limit"))
        points = refined.points
        assert points.shape == (verts, 3), (level, mode)
        idx = np.array(sorted(samples))
        expected = np.array([samples[i] for i in idx])
        err = np.abs(points[idx] - expected).max()
        assert err <= 1e-12 * d, f"{name} level {level} {mode}: {err:.3e}"


@pytest.mark.parametrize("name", LIMIT)
def test_limit_matches_opensubdiv_bfr(name):
    kw = read_shape(name)
    surface = subsurf.Mesh(**kw).limit_surface()
    faces, u, v, p, du, dv = golden_limit(name)
    pos, su, sv = surface.evaluate(faces, u, v)
    d = diagonal(kw["points"])
    assert np.abs(pos - p).max() <= 1e-12 * d
    # Derivatives off the face corners (at an extraordinary corner they are tangents).
    inner = ~(np.isin(u, [0.0, 1.0]) & np.isin(v, [0.0, 1.0]))
    for ours, theirs in ((su, du), (sv, dv)):
        scale = np.maximum(np.linalg.norm(theirs, axis=1), 1e-3 * d)[inner]
        err = np.linalg.norm(ours - theirs, axis=1)[inner]
        assert (err <= 1e-9 * scale).all(), f"{name}: {(err / scale).max():.3e}"


@pytest.mark.parametrize("name", LOOP_LIMIT)
def test_loop_limit_matches_opensubdiv_bfr(name):
    kw = read_shape(name)
    surface = subsurf.Mesh(scheme="loop", **kw).limit_surface()
    faces, u, v, p, du, dv = golden_limit(name, "loop_bfr")
    pos, su, sv = surface.evaluate(faces, u, v)
    d = diagonal(kw["points"])
    assert np.abs(pos - p).max() <= 1e-12 * d
    corner = ((u == 0) & (v == 0)) | ((u == 1) & (v == 0)) | ((u == 0) & (v == 1))
    for ours, theirs in ((su, du), (sv, dv)):
        scale = np.maximum(np.linalg.norm(theirs, axis=1), 1e-3 * d)[~corner]
        err = np.linalg.norm(ours - theirs, axis=1)[~corner]
        assert (err <= 1e-9 * scale).all(), f"{name}: {(err / scale).max():.3e}"


def test_read_gives_the_same_mesh_as_the_arrays():
    kw = read_shape("catmark_cube_creases1")
    from_arrays = subsurf.Mesh(**kw).subdivide(2)
    with pytest.warns(UserWarning, match="normals"):
        from_file = subsurf.read(str(SHAPES / "catmark_cube_creases1.obj")).subdivide(2)
    assert np.array_equal(from_file.points, from_arrays.points)
    assert np.array_equal(from_file.face_vertex_indices, from_arrays.face_vertex_indices)
