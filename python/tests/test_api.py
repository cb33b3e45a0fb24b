"""The Python API: arrays in and out, USD's crease encoding, texture coordinates, errors
that name what is at fault, files, and the interpreter lock released during long calls."""

import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import subsurf

REPO = Path(__file__).resolve().parents[2]

CUBE_POINTS = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
    float,
)
CUBE_COUNTS = [4] * 6
CUBE_INDICES = [0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7]


def cube(**kw):
    return subsurf.Mesh(CUBE_POINTS, CUBE_COUNTS, CUBE_INDICES, **kw)


def test_arrays_round_trip_with_numpy_dtypes():
    m = subsurf.Mesh(
        CUBE_POINTS.astype(np.float32),
        np.array(CUBE_COUNTS, np.uint8),
        np.array(CUBE_INDICES, np.int64),
        corner_indices=[0],
        corner_sharpnesses=[3.0],
        hole_indices=[5],
    )
    assert m.points.dtype == np.float64 and m.points.shape == (8, 3)
    assert np.array_equal(m.points, CUBE_POINTS)
    assert m.face_vertex_counts.tolist() == CUBE_COUNTS
    assert m.face_vertex_indices.tolist() == CUBE_INDICES
    assert m.corner_indices.tolist() == [0] and m.corner_sharpnesses.tolist() == [3.0]
    assert m.hole_indices.tolist() == [5]
    assert (m.num_points, m.num_faces) == (8, 6)
    assert m.interpolate_boundary == "edgeOnly" and m.scheme == "catmullClark"
    # The hole is left out of the refined mesh, as OpenSubdiv does.
    assert m.subdivide(1).num_faces == 20


def test_crease_chains_per_crease_and_per_edge_are_the_same_edges():
    chain = cube(crease_indices=[0, 1, 2, 3], crease_lengths=[4], crease_sharpnesses=[2.5])
    edges = cube(
        crease_indices=[0, 1, 2, 3], crease_lengths=[4], crease_sharpnesses=[2.5, 2.5, 2.5]
    )
    pairs = cube(
        crease_indices=[0, 1, 1, 2, 2, 3], crease_lengths=[2, 2, 2], crease_sharpnesses=[2.5] * 3
    )
    assert chain.crease_indices.tolist() == [0, 1, 1, 2, 2, 3]
    assert chain.crease_lengths.tolist() == [2, 2, 2]
    a, b, c = (m.subdivide(3).points for m in (chain, edges, pairs))
    assert np.array_equal(a, b) and np.array_equal(a, c)
    assert not np.array_equal(a, cube().subdivide(3).points)


def test_refined_sharpness_is_what_is_left():
    r = cube(crease_indices=[0, 1], crease_lengths=[2], crease_sharpnesses=[2.5]).subdivide(1)
    assert r.crease_sharpnesses.tolist() == [1.5, 1.5]
    # Refining 1 then 2 levels gives the points of refining 3 (numbered otherwise: the
    # second refinement numbers from the written mesh's edges).
    once = cube(crease_indices=[0, 1], crease_lengths=[2], crease_sharpnesses=[2.5])
    a, b = (set(map(tuple, np.round(x.points, 12))) for x in (r.subdivide(2), once.subdivide(3)))
    assert len(a) == 386 and a == b


def test_limit_evaluation_agrees_with_limit_refinement_at_the_corners():
    m = cube(crease_indices=[0, 1, 2], crease_lengths=[3], crease_sharpnesses=[1.5])
    refined = m.subdivide(2, limit=True)
    surface = m.limit_surface()
    assert surface.num_faces == 6
    # Vertex 0 of the mesh stays vertex 0; its limit is corner (0, 0) of face 0.
    pos, du, dv = surface.evaluate([0], [0.0], [0.0])
    assert np.allclose(pos[0], refined.points[0], atol=1e-12)
    n = np.cross(du[0], dv[0])
    n /= np.linalg.norm(n)
    assert np.allclose(n, refined.normals[0], atol=1e-9)
    p2 = surface.evaluate(np.arange(6), np.full(6, 0.3), np.full(6, 0.6), second=True)
    assert len(p2) == 6 and all(a.shape == (6, 3) for a in p2)


def test_texture_coordinates_are_refined_and_evaluated():
    # One (u, v) per face corner: each face gets the unit square.
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    m = cube(uvs=np.tile(square, (6, 1)), face_varying_linear_interpolation="none")
    assert m.uvs.shape == (24, 2) and m.uv_indices.tolist() == list(range(24))
    r = m.subdivide(2)
    assert r.uvs is not None and len(r.uv_indices) == 4 * r.num_faces
    assert r.face_varying_linear_interpolation == "none"
    # Smooth within each face ("none"): not the square's own parameter off the centre.
    uv = m.limit_surface().evaluate_uv([0, 3], [0.5, 0.25], [0.5, 0.75])
    assert np.allclose(uv[0], [0.5, 0.5], atol=1e-12)
    assert not np.allclose(uv[1], [0.25, 0.75], atol=1e-3)
    # Linear everywhere ("all"): the bilinear map of each face's square.
    linear = cube(uvs=np.tile(square, (6, 1)), face_varying_linear_interpolation="all")
    uv = linear.limit_surface().evaluate_uv([0, 3], [0.5, 0.25], [0.5, 0.75])
    assert np.allclose(uv, [[0.5, 0.5], [0.25, 0.75]], atol=1e-12)
    t = m.tessellate(4)
    assert t.uvs is not None and t.normals.shape == (t.num_points, 3)
    with pytest.raises(subsurf.SubsurfError, match="no texture coordinates"):
        cube().limit_surface().evaluate_uv([0], [0.5], [0.5])


def test_tessellation_is_watertight_and_closed():
    t = cube(crease_indices=[0, 1], crease_lengths=[2], crease_sharpnesses=[10.0]).tessellate(
        rate=5, triangles=True
    )
    counts, idx = t.face_vertex_counts, t.face_vertex_indices
    assert (counts == 3).all() and t.num_faces == 6 * 25 * 2
    directed = {}
    for f in idx.reshape(-1, 3):
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            directed[(a, b)] = directed.get((a, b), 0) + 1
    # Closed and consistently oriented: every directed edge once, and its reverse once.
    assert all(n == 1 and directed.get((b, a)) == 1 for (a, b), n in directed.items())
    assert t.num_points - len(directed) // 2 + t.num_faces == 2  # Euler characteristic


def test_loop_needs_triangles_and_bad_input_names_the_culprit():
    with pytest.raises(subsurf.SubsurfError, match="face 0"):
        cube(scheme="loop").subdivide(1)
    with pytest.raises(subsurf.SubsurfError, match="vertex 9"):
        subsurf.Mesh(CUBE_POINTS, [3], [0, 1, 9])
    with pytest.raises(ValueError, match="sum to 4"):
        subsurf.Mesh(CUBE_POINTS, [4], [0, 1, 2])
    with pytest.raises(ValueError, match=r"shape \(n, 3\)"):
        subsurf.Mesh(CUBE_POINTS[:, :2], CUBE_COUNTS, CUBE_INDICES)
    with pytest.raises(TypeError, match="integers"):
        subsurf.Mesh(CUBE_POINTS, CUBE_COUNTS, np.array(CUBE_INDICES, float))
    with pytest.raises(ValueError, match=r"points\[2\]"):
        bad = CUBE_POINTS.copy()
        bad[2, 1] = np.nan
        subsurf.Mesh(bad, CUBE_COUNTS, CUBE_INDICES)
    with pytest.raises(ValueError, match=r"face_vertex_indices\[0\] = -1"):
        subsurf.Mesh(CUBE_POINTS, [3], [-1, 1, 2])
    with pytest.raises(ValueError, match="interpolate_boundary"):
        cube(interpolate_boundary="edgeAndCorners")
    with pytest.raises(ValueError, match="scheme"):
        cube(scheme="catmark")
    with pytest.raises(ValueError, match="crease_sharpnesses has 2 values"):
        cube(crease_indices=[0, 1, 2, 3], crease_lengths=[4], crease_sharpnesses=[1.0, 2.0])
    with pytest.raises(subsurf.SubsurfError, match=r"point 1 \(face 2, subface 0, u 1.5"):
        cube().limit_surface().evaluate([0, 2], [0.5, 1.5], [0.5, 0.5])
    with pytest.raises(ValueError, match="one entry per point"):
        cube().limit_surface().evaluate([0, 1], [0.5], [0.5])
    assert issubclass(subsurf.SubsurfError, ValueError)


def test_files_are_written_whole_and_read_back(tmp_path):
    m = cube(crease_indices=[0, 1], crease_lengths=[2], crease_sharpnesses=[3.0])
    r = m.subdivide(1)
    r.write(tmp_path / "r.obj")
    back = subsurf.read(str(tmp_path / "r.obj"))
    assert np.array_equal(back.points, r.points)
    assert np.array_equal(back.face_vertex_indices, r.face_vertex_indices)
    assert back.crease_sharpnesses.tolist() == r.crease_sharpnesses.tolist()
    t = m.tessellate(2)
    t.write(tmp_path / "t.ply")
    with pytest.warns(UserWarning, match="nx, ny, nz"):
        assert subsurf.read(str(tmp_path / "t.ply")).num_faces == t.num_faces
    with pytest.raises(subsurf.SubsurfError, match="PLY would drop"):
        r.write(tmp_path / "r.ply")
    assert not (tmp_path / "r.ply").exists()
    with pytest.raises(ValueError, match="write .obj or .ply"):
        r.write(tmp_path / "r.stl")
    with pytest.raises(subsurf.SubsurfError, match="missing.obj"):
        subsurf.read(str(tmp_path / "missing.obj"))


def test_reposing_equals_refining_the_moved_mesh():
    m = cube(crease_indices=[0, 1, 2], crease_lengths=[3], crease_sharpnesses=[1.5])
    reposer = subsurf.Reposer(m, 3, limit=True)
    rng = np.random.default_rng(7)
    for _ in range(3):
        moved = CUBE_POINTS + rng.normal(scale=0.2, size=CUBE_POINTS.shape)
        posed = reposer.pose(moved)
        full = subsurf.Mesh(
            moved, CUBE_COUNTS, CUBE_INDICES,
            crease_indices=[0, 1, 2], crease_lengths=[3], crease_sharpnesses=[1.5],
        ).subdivide(3, limit=True)
        assert np.abs(posed - full.points).max() < 1e-13
        assert np.abs(reposer.normals - full.normals).max() < 1e-12
        assert np.array_equal(reposer.mesh.face_vertex_indices, full.face_vertex_indices)
    with pytest.raises(subsurf.SubsurfError, match="the pose has 7 vertices, the base mesh 8"):
        reposer.pose(CUBE_POINTS[:7])


def test_the_adjustable_scheme_is_catmull_clark_at_c_one_half():
    cc = cube().subdivide(2).points
    assert np.abs(cube(scheme="adjustable", c=0.5).subdivide(2).points - cc).max() < 1e-15
    tight = cube(scheme="adjustable", c=0.3, adjust_steps=2)
    assert (tight.c, tight.adjust_steps, tight.scheme) == (0.3, 2, "adjustable")
    r = tight.subdivide(3)
    assert np.abs(r.points - cube().subdivide(3).points).max() > 1e-3
    # Re-posing and the limit surface take the scheme too.
    assert np.abs(subsurf.Reposer(tight, 3).pose(CUBE_POINTS) - r.points).max() < 1e-14
    pos, _, _ = tight.limit_surface().evaluate([0], [0.0], [0.0])
    limit = tight.subdivide(3, limit=True).points[0]
    assert np.abs(pos[0] - limit).max() < 1e-12
    t = tight.tessellate(4)
    assert t.num_faces == 6 * 16
    with pytest.raises(subsurf.SubsurfError, match="c"):
        cube(scheme="adjustable", c=1.5)


def test_nurss_takes_knot_intervals():
    x_edges = [[0, 1], [3, 2], [4, 5], [7, 6]]
    uniform = cube(scheme="nurss").subdivide(2).points
    assert np.abs(uniform - cube().subdivide(2).points).max() < 1e-12
    stretched = cube(
        scheme="nurss", knot_interval_indices=x_edges, knot_intervals=[3.0] * 4
    )
    r = stretched.subdivide(2)
    assert np.abs(r.points - uniform).max() > 1e-3
    assert np.abs(subsurf.Reposer(stretched, 2).pose(CUBE_POINTS) - r.points).max() < 1e-14
    t = stretched.tessellate(4)
    assert t.num_faces == 6 * 16
    with pytest.raises(ValueError, match="nurss"):
        cube(knot_interval_indices=x_edges, knot_intervals=[3.0] * 4)
    with pytest.raises(ValueError, match="two per edge"):
        cube(scheme="nurss", knot_interval_indices=x_edges, knot_intervals=[3.0] * 3)


def test_g2_and_spline_surfaces():
    limit = cube().limit_surface()
    g2 = cube().g2_surface()
    assert (limit.kind, g2.kind) == ("limit", "g2")
    # Outside the caps (corner squares of side 2^-2 at the eight valence-3 vertices) the
    # G2 surface is the limit surface.
    f, u, v = np.arange(6), np.full(6, 0.5), np.full(6, 0.5)
    assert np.abs(g2.evaluate(f, u, v)[0] - limit.evaluate(f, u, v)[0]).max() < 1e-12
    inside = g2.evaluate([0], [0.05], [0.05])[0] - limit.evaluate([0], [0.05], [0.05])[0]
    assert np.abs(inside).max() > 1e-6
    t = g2.tessellate(4, triangles=True)
    assert t.num_faces == 6 * 16 * 2 and t.normals.shape == (t.num_points, 3)
    with pytest.raises(subsurf.SubsurfError, match="limit surface only"):
        g2.evaluate_uv([0], [0.5], [0.5])
    # On a torus every vertex is regular: the sub-basis spline is the uniform bicubic
    # B-spline, which is the Catmull-Clark limit.
    torus = subsurf.read(str(Path(__file__).resolve().parents[2] / "examples/meshes/torus.obj"))
    spline = torus.spline_surface()
    assert spline.kind == "spline" and spline.mesh.num_faces == torus.num_faces
    rng = np.random.default_rng(3)
    f = rng.integers(0, torus.num_faces, 50)
    u, v = rng.random(50), rng.random(50)
    a = spline.evaluate(f, u, v)
    b = torus.limit_surface().evaluate(f, u, v)
    assert all(np.abs(x - y).max() < 1e-12 for x, y in zip(a, b))
    # A mesh with a triangle gets one Catmull-Clark step first.
    pyramid = subsurf.Mesh(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 1]],
        [4, 3, 3, 3, 3],
        [0, 3, 2, 1, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4],
    )
    assert pyramid.spline_surface().mesh.num_faces == 16


def test_interpolated_curves_lie_on_the_limit_surface(tmp_path):
    # A closed planar cubic B-spline with uniform knots: its point at knot i is
    # (P[i-1] + 4 P[i] + P[i+1]) / 6 (de Boor), computed here independently of subsurf.
    angle = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    radius = 1.0 + 0.3 * np.cos(3 * angle)
    points = np.stack([radius * np.cos(angle), radius * np.sin(angle), np.zeros(8)], axis=1)
    doc = {"type": "bspline-curve", "degree": 3, "knots": list(range(9)),
           "points": points.tolist(), "closed": True}
    (tmp_path / "curve.json").write_text(__import__("json").dumps(doc))
    mesh = subsurf.interpolate_curves(tmp_path / "curve.json", width=0.2)
    assert mesh.scheme == "nurss"
    limit = mesh.subdivide(4, limit=True).points
    on_curve = (np.roll(points, 1, 0) + 4 * points + np.roll(points, -1, 0)) / 6
    distance = np.linalg.norm(limit[:, None, :] - on_curve[None, :, :], axis=2).min(axis=0)
    assert (distance < 1e-9).all(), distance
    with pytest.raises(subsurf.SubsurfError, match="width"):
        subsurf.interpolate_curves(tmp_path / "curve.json", width=-1.0)


def test_trimesh_interop():
    trimesh = pytest.importorskip("trimesh")
    tri = cube().tessellate(2, triangles=True).to_trimesh()
    assert isinstance(tri, trimesh.Trimesh) and tri.is_watertight
    back = subsurf.Mesh.from_trimesh(tri)
    assert back.scheme == "loop" and back.num_faces == len(tri.faces)


def long_subdivide():
    big = cube()
    return lambda: big.subdivide(7)


def long_pose():
    reposer = subsurf.Reposer(cube(), 5)
    frames = np.tile(CUBE_POINTS, (200, 1, 1))
    return lambda: reposer.pose(frames)


def patch_arrays(name):
    """The patches of a bundled example as arrays (so that no file is read in the call)."""
    docs = __import__("json").loads((REPO / "examples/patches" / name).read_text())
    return [(np.array(d["points"]), d["knots_u"], d["knots_v"]) for d in docs]


def long_blend():
    patches = patch_arrays("blend5.json")
    return lambda: subsurf.blend(patches, levels=6)


def long_fill():
    patches = patch_arrays("hole5.json")
    return lambda: subsurf.fill(patches, levels=7)


def long_regularity():
    net = subsurf.read(str(REPO / "examples/meshes/regularity-gear.obj")).subdivide(2)
    return lambda: net.regularity(sample=17)


# Each prepares its arguments and returns the call to watch.
LONG_CALLS = {
    "subdivide": long_subdivide,
    "blend": long_blend,
    "fill": long_fill,
    "pose": long_pose,
    "regularity": long_regularity,
}


@pytest.mark.parametrize("name", sorted(LONG_CALLS))
def test_long_calls_release_the_interpreter_lock(name):
    """While one thread computes, another runs Python code. With the thread switch interval
    at an hour, the lock changes hands only when a thread gives it up: the counter can move
    during the call only if the call released it."""
    call = LONG_CALLS[name]()
    in_call, done, seen = threading.Event(), threading.Event(), []

    def work():
        in_call.set()
        call()
        in_call.clear()
        done.set()

    def count():
        while not done.is_set():
            if in_call.is_set():
                seen.append(1)
                return
            done.wait(0.0005)

    old = sys.getswitchinterval()
    sys.setswitchinterval(3600)
    try:
        counter = threading.Thread(target=count)
        counter.start()
        worker = threading.Thread(target=work)
        worker.start()
        worker.join()
        counter.join()
    finally:
        sys.setswitchinterval(old)
    assert seen, f"no Python code ran while {name} ran"
