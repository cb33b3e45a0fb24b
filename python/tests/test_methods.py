"""The paper methods on patches and curves (blend, fill) and the regularity certificate:
the command-line tool's output (its binary built from the same sources) reproduced exactly,
properties checked with B-splines evaluated here (de Boor), and bad input named."""

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import subsurf

REPO = Path(__file__).resolve().parents[2]
PATCHES = REPO / "examples" / "patches"
MESHES = REPO / "examples" / "meshes"


def cli_binary():
    """The `subsurf` binary: `SUBSURF_BIN`, else the debug build of this checkout (which CI's
    `cargo test --workspace` builds before the Python tests)."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    path = Path(os.environ.get("SUBSURF_BIN", target / "debug" / "subsurf"))
    if not path.exists():
        pytest.skip(f"no subsurf binary at {path} (cargo build -p subsurf-cli, or SUBSURF_BIN)")
    return path


def run_cli(*args, expect=(0,)):
    r = subprocess.run([str(cli_binary()), *map(str, args)], capture_output=True, text=True)
    assert r.returncode in expect, r.stderr
    return r.stdout


def de_boor(points, knots, x, degree=3):
    """The point at `x` of the B-spline with control points `points` (any trailing shape)."""
    points, knots = np.asarray(points, float), np.asarray(knots, float)
    k = int(np.searchsorted(knots, x, side="right")) - 1
    k = min(max(k, degree), len(points) - 1)
    d = [points[j + k - degree].copy() for j in range(degree + 1)]
    for r in range(1, degree + 1):
        for j in range(degree, r - 1, -1):
            lo, hi = knots[j + k - degree], knots[j + 1 + k - r]
            a = (x - lo) / (hi - lo)
            d[j] = (1 - a) * d[j - 1] + a * d[j]
    return d[degree]


def boundary_vertices(mesh):
    """The vertices on edges that one face uses."""
    counts, indices = mesh.face_vertex_counts, mesh.face_vertex_indices
    uses, start = {}, 0
    for c in counts:
        f = indices[start : start + c]
        start += c
        for i in range(c):
            e = tuple(sorted((int(f[i]), int(f[(i + 1) % c]))))
            uses[e] = uses.get(e, 0) + 1
    return sorted({v for e, n in uses.items() if n == 1 for v in e})


def hole_sides(n=5):
    """`n` clamped cubic curves with non-uniform knots around a wavy loop, curve `k` from
    corner `k` to corner `k + 1` (as `(points, knots)`), and the corners."""

    def corner(k):
        a = 2 * np.pi * k / n
        return np.array([2 * np.cos(a), 2 * np.sin(a), 0.4 * np.cos(3 * a)])

    sides = []
    for k in range(n):
        a, b = corner(k), corner((k + 1) % n)
        m = 5 + k % 2
        t = np.linspace(0, 1, m)[:, None]
        bump = np.sin(np.pi * t)
        out = np.concatenate([(a + b)[:2] / 2 * 0.3 * bump, 0.2 * bump], axis=1)
        knots = [0.0] * 4 + [1.0 + i * 0.7 + 0.2 * k for i in range(m - 4)]
        knots += [1.0 + (m - 4) * 0.9 + 0.3 * k] * 4
        sides.append((a + (b - a) * t + out, knots))
    return sides, [corner(k) for k in range(n)]


def obj_lines(path, skip=("#",)):
    return [l for l in Path(path).read_text().splitlines() if not l.startswith(skip)]


@pytest.mark.parametrize(
    "command, name, extra",
    [
        ("blend", "blend3", ["--levels", "3"]),
        ("blend", "blend5", ["--levels", "2", "--samples", "5"]),
        ("fill", "hole3", []),
        ("fill", "hole5", ["--bulge", "0.4", "--levels", "3", "--samples", "3"]),
        ("fill", "hole5-g1", ["--g1", "--levels", "3"]),
    ],
)
def test_blend_and_fill_write_what_the_command_writes(tmp_path, command, name, extra):
    source = PATCHES / f"{name}.json"
    run_cli(
        command, source, "-o", tmp_path / "cli.obj", "--control-mesh", tmp_path / "c.obj", *extra
    )
    kw = {"levels": 5, "samples": 8}
    for flag, value in zip(extra, extra[1:] + [None]):
        if flag == "--g1":
            kw["g1"] = True
        elif flag.startswith("--"):
            kw[flag[2:]] = float(value) if flag == "--bulge" else int(value)
    method = subsurf.blend if command == "blend" else subsurf.fill
    result = method(str(source), **kw)
    result.write(tmp_path / "py.obj")
    assert (tmp_path / "py.obj").read_bytes() == (tmp_path / "cli.obj").read_bytes()
    assert result.comment == (tmp_path / "cli.obj").read_text().splitlines()[0][2:]
    # The control mesh: the same points, faces and knot intervals (`t interval` tags).
    result.control.write(tmp_path / "py-c.obj")
    skip = ("#", "t interpolateboundary")
    assert obj_lines(tmp_path / "py-c.obj", skip) == obj_lines(tmp_path / "c.obj", skip)
    assert result.method == command and result.control.scheme == "nurss"
    # The groups of the file are the result's meshes and polylines.
    text = (tmp_path / "cli.obj").read_text()
    groups = [l[2:] for l in text.splitlines() if l.startswith("g ")]
    patches = [f"patch_{k + 1}" for k in range(len(result.patches))]
    curves = [f"curve_{k + 1}" for k in range(len(result.curves))]
    assert groups == patches + [command] + curves
    v = np.array(
        [[float(x) for x in l.split()[1:]] for l in text.splitlines() if l.startswith("v ")]
    )
    at = sum(p.num_points for p in result.patches)
    assert np.array_equal(v[at : at + result.surface.num_points], result.surface.points)


def test_arrays_blend_as_the_file_does_and_homogeneous_points_are_w_times_xyz():
    docs = json.loads((PATCHES / "blend3.json").read_text())
    arrays = [(np.array(d["points"]), d["knots_u"], d["knots_v"]) for d in docs]
    from_file = subsurf.blend(PATCHES / "blend3.json", levels=2, samples=3)
    from_arrays = subsurf.blend(arrays, levels=2, samples=3)
    assert np.array_equal(from_arrays.surface.points, from_file.surface.points)
    assert np.array_equal(
        from_arrays.surface.face_vertex_indices, from_file.surface.face_vertex_indices
    )
    # Homogeneous points (w x, w y, w z, w) with w = 2 everywhere are the same points: the
    # blend (computed in homogeneous coordinates, then projected) is the same surface.
    doubled = [
        (np.concatenate([2 * p, np.full(p.shape[:2] + (1,), 2.0)], axis=2), ku, kv)
        for p, ku, kv in arrays
    ]
    rational = subsurf.blend(doubled, levels=2, samples=3)
    assert np.abs(rational.surface.points - from_file.surface.points).max() < 1e-12
    # Unequal weights change the surface.
    varied = [
        (np.concatenate([p * w[..., None], w[..., None]], axis=2), ku, kv)
        for (p, ku, kv), w in (
            (a, 1 + 0.5 * np.random.default_rng(k).random(a[0].shape[:2]))
            for k, a in enumerate(arrays)
        )
    ]
    assert (
        np.abs(
            subsurf.blend(varied, levels=2).surface.points[:100]
            - subsurf.blend(arrays, levels=2).surface.points[:100]
        ).max()
        > 1e-6
    )


def test_the_blend_surface_runs_through_every_base_patchs_boundary():
    """C0 with each patch along its first row u = u_3 (its boundary curve, evaluated here):
    the nearest blend vertex to every point of the curve comes closer as the vertices do
    (halving per level); a blend beside the curve would stay at its distance."""
    docs = json.loads((PATCHES / "blend3.json").read_text())
    curves = []
    for d in docs:
        p, ku, kv = np.array(d["points"]), d["knots_u"], d["knots_v"]
        row = np.array([de_boor(p[:, j], ku, ku[3]) for j in range(p.shape[1])])
        curves.append(np.array([de_boor(row, kv, x) for x in np.linspace(kv[3], kv[-4], 150)]))
    curves = np.concatenate(curves)
    gaps = []
    for levels in (2, 3, 4, 5):
        points = subsurf.blend(PATCHES / "blend3.json", levels=levels).surface.points
        gaps.append(np.linalg.norm(curves[:, None] - points[None], axis=2).min(axis=1).max())
    assert all(b < 0.6 * a for a, b in zip(gaps, gaps[1:])), gaps
    assert gaps[-1] < 0.02, gaps


def test_the_fill_interpolates_its_corners_and_converges_to_its_sides():
    sides, corners = hole_sides(5)
    dense = np.concatenate(
        [np.array([de_boor(p, k, x) for x in np.linspace(k[3], k[-4], 20000)]) for p, k in sides]
    )
    gaps = []
    for levels in (1, 2, 3):
        f = subsurf.fill(sides, levels=levels, samples=4)
        points = f.surface.points
        for c in corners:
            assert np.linalg.norm(points - c, axis=1).min() < 1e-12
        rim = points[boundary_vertices(f.surface)]
        gaps.append(np.linalg.norm(rim[:, None] - dense[None], axis=2).min(axis=1).max())
    # Control points of a limit that is the curves: O(h^2), a quarter per level.
    assert all(b < 0.3 * a for a, b in zip(gaps, gaps[1:])), gaps
    # The polylines are on the curves (each point's parameter searched here), end to end.
    for (p, k), line in zip(sides, f.curves):
        assert np.abs(line[[0, -1]] - [de_boor(p, k, k[3]), de_boor(p, k, k[-4])]).max() < 1e-12
        ts = np.linspace(k[3], k[-4], 2001)
        samples = np.array([de_boor(p, k, t) for t in ts])
        for q in line:
            i = int(np.linalg.norm(samples - q, axis=1).argmin())
            lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, len(ts) - 1)]
            for _ in range(80):
                a, b = lo + (hi - lo) / 3, hi - (hi - lo) / 3
                if np.linalg.norm(de_boor(p, k, a) - q) < np.linalg.norm(de_boor(p, k, b) - q):
                    hi = b
                else:
                    lo = a
            assert np.linalg.norm(de_boor(p, k, lo) - q) < 1e-9
    assert f.patches == [] and f.method == "fill"
    # The bulge moves the inside along the boundary's normal (+z for this loop).
    heights = [
        subsurf.fill(sides, levels=2, bulge=b).surface.points[:, 2].mean() for b in (-0.4, 0, 0.4)
    ]
    assert heights[0] < heights[1] < heights[2], heights


def test_bad_patches_and_curves_are_named():
    sides, _ = hole_sides(4)
    with pytest.raises(subsurf.SubsurfError, match=r"^boundary: sides of the hole: got 2"):
        subsurf.fill(sides[:2])
    moved = [(p.copy(), k) for p, k in sides]
    moved[1][0][-1, 2] += 0.5
    with pytest.raises(
        subsurf.SubsurfError, match=r"^boundary\[1\]: curve 1 does not share a corner"
    ):
        subsurf.fill(moved)
    with pytest.raises(
        subsurf.SubsurfError, match=r"boundary\[0\]: a curve; --g1 needs the patches"
    ):
        subsurf.fill(sides, g1=True)
    with pytest.raises(
        subsurf.SubsurfError, match=r"patches\[0\]: a curve; blending takes patches"
    ):
        subsurf.blend(sides)
    with pytest.raises(subsurf.SubsurfError, match=r"vase.json\[0\]: a curve"):
        subsurf.blend(REPO / "examples" / "curves" / "vase.json")
    with pytest.raises(
        subsurf.SubsurfError,
        match=r"hole3.json\[0\]: patch 0 and patch 2 do not share a tangent plane",
    ):
        subsurf.fill(str(PATCHES / "hole3.json"), g1=True)
    with pytest.raises(subsurf.SubsurfError, match="missing.json"):
        subsurf.blend(PATCHES / "missing.json")
    p, k = sides[0]
    with pytest.raises(
        subsurf.SubsurfError, match=r"boundary\[0\]: knots has 5 knots for 5 control points"
    ):
        subsurf.fill([(p, k[:5])] + sides[1:])
    with pytest.raises(subsurf.SubsurfError, match=r"boundary\[0\]: knots: .*"):
        subsurf.fill([(p, k[::-1])] + sides[1:])
    with pytest.raises(subsurf.SubsurfError, match=r"boundary\[0\]: curve 0: degree 2"):
        subsurf.fill([(p, [0, 0, 0, 1, 1.5, 2, 2, 2])] + sides[1:])
    bad = p.copy()
    bad[2, 1] = np.nan
    with pytest.raises(
        ValueError, match=r"boundary\[0\]: points\[2\] has a value that is not finite"
    ):
        subsurf.fill([(bad, k)] + sides[1:])
    with pytest.raises(
        ValueError, match=r"boundary\[0\]: a curve \(points, knots\) has points of shape"
    ):
        subsurf.fill([(p[:, :2], k)] + sides[1:])
    weights = np.column_stack([p, -np.ones(len(p))])
    with pytest.raises(subsurf.SubsurfError, match=r"boundary\[0\]: .*weight"):
        subsurf.fill([(weights, k)] + sides[1:])
    with pytest.raises(TypeError, match=r"boundary\[0\] must be \(points, knots\)"):
        subsurf.fill([p] + sides[1:])
    with pytest.raises(TypeError, match="a path or a sequence"):
        subsurf.fill(3)
    with pytest.raises(ValueError, match="levels 9: at most 8"):
        subsurf.fill(sides, levels=9)
    with pytest.raises(ValueError, match="samples 0"):
        subsurf.blend(PATCHES / "blend3.json", samples=0)
    with pytest.raises(ValueError, match="bulge inf is not a finite number"):
        subsurf.fill(sides, bulge=float("inf"))


REGULARITY_CASES = [
    ("regularity-gear", []),
    ("regularity-gear", ["--local"]),
    ("regularity-dolphin", ["--local", "--sample", "3"]),
    ("regularity-butterfly", ["--sample", "0"]),
    ("grid", ["--planar"]),
    ("cube", ["--local"]),
    ("pentaprism", []),
]


@pytest.mark.parametrize("name, args", REGULARITY_CASES)
def test_regularity_reports_what_the_command_reports(name, args):
    path = MESHES / f"{name}.obj"
    cli = json.loads(run_cli("regularity", path, "--json", *args, expect=(0, 3)))
    kw = {"local": "--local" in args, "planar": "--planar" in args}
    if "--sample" in args:
        kw["sample"] = int(args[args.index("--sample") + 1])
    report = subsurf.read(str(path)).regularity(**kw)
    assert report.pop("file") is None
    assert cli.pop("file") == str(path)
    assert report == cli


def test_regularity_plots_are_the_commands(tmp_path):
    path = MESHES / "regularity-gear.obj"
    run_cli("regularity", path, "--local", "--plot", tmp_path / "cli.svg", expect=(0, 3))
    run_cli("regularity", path, "--plot", tmp_path / "cli.png", expect=(0, 3))
    gear = subsurf.read(str(path))
    gear.regularity(local=True, plot=tmp_path / "py.svg")
    gear.regularity(plot=str(tmp_path / "py.png"))
    assert (tmp_path / "py.svg").read_bytes() == (tmp_path / "cli.svg").read_bytes()
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cli.png").read_bytes()


def grid_net(xs, rows=2):
    """A planar quad grid with columns at `xs`, corners tagged (edge-and-corner)."""
    n = len(xs)
    points = [[x, float(j), 0.0] for j in range(rows + 1) for x in xs]
    faces = [
        [j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i]
        for j in range(rows)
        for i in range(n - 1)
    ]
    return subsurf.Mesh(
        points, [4] * len(faces), np.ravel(faces), interpolate_boundary="edgeAndCorner"
    )


def test_regularity_certifies_a_fan_free_strip_and_names_a_fold():
    report = grid_net([0.0, 1.0, 2.0, 3.0]).regularity(local=True)
    assert report["certified"] and report["counts"]["certified"] == report["counts"]["faces"] == 6
    assert report["dimension"] == "planar" and report["mode"] == "local"
    # Columns 2 and 3 swapped: the net folds over, and so does its limit surface.
    folded = grid_net([0.0, 1.0, 3.5, 2.5, 4.0, 5.0]).regularity(local=True)
    assert not folded["certified"]
    bad = [f for f in folded["faces"] if f["class"] == "not-regular"]
    assert bad and all(f["local"] == "refused" and f["worst_sample"]["value"] <= 0 for f in bad)
    assert any(f["face"] in (2, 7) for f in bad)
    # Spatial: no orientation; unsampled faces have no worst sample.
    bumped = subsurf.Mesh(
        [[0, 0, 0], [1, 0, 0.2], [1, 1, 0], [0, 1, 0.1]],
        [4],
        [0, 1, 2, 3],
        interpolate_boundary="edgeAndCorner",
    ).regularity(sample=0)
    assert bumped["dimension"] == "spatial" and bumped["orientation"] is None
    assert bumped["samples"] == 0 and bumped["faces"][0]["worst_sample"] is None


def test_regularity_refuses_what_it_cannot_certify():
    with pytest.raises(
        subsurf.SubsurfError, match='Catmull-Clark nets; the mesh\'s scheme is "loop"'
    ):
        subsurf.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [3], [0, 1, 2], scheme="loop").regularity()
    strip = grid_net([0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="sample 1: 0 .no sampling. or 2 to 1024"):
        strip.regularity(sample=1)
    with pytest.raises(ValueError, match=r"net.pdf: the plot is written as .svg or .png"):
        strip.regularity(plot="net.pdf")


def test_many_poses_at_once_equal_posing_one_by_one():
    cube = subsurf.read(str(MESHES / "cube-crease.obj"))
    rng = np.random.default_rng(11)
    frames = cube.points[None] + rng.normal(scale=0.1, size=(4,) + cube.points.shape)
    reposer = subsurf.Reposer(cube, 2, limit=True)
    together = reposer.pose(frames)
    last_normals = reposer.normals.copy()
    one = subsurf.Reposer(cube, 2, limit=True)
    single = np.stack([one.pose(f) for f in frames])
    assert together.shape == single.shape == (4, one.mesh.num_points, 3)
    assert np.array_equal(together, single)
    assert np.array_equal(last_normals, one.normals)
    assert reposer.pose(frames[:0]).shape == (0, one.mesh.num_points, 3)
    with pytest.raises(subsurf.SubsurfError, match="frame 0: the pose has 7 vertices"):
        reposer.pose(frames[:, :7])
    with pytest.raises(ValueError, match=r"shape \(n, 3\) or \(frames, n, 3\)"):
        reposer.pose(frames[..., :2])
    bad = frames.copy()
    bad[2, 5, 1] = np.inf
    with pytest.raises(ValueError, match=r"points\[2, 5\] has a value that is not finite"):
        reposer.pose(bad)
