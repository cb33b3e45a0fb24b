"""Type stubs of the extension module `subsurf._subsurf` (see `subsurf/__init__.py`)."""

from os import PathLike
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

Scheme = Literal["catmullClark", "loop", "bilinear", "adjustable", "nurss"]
Boundary = Literal["none", "edgeOnly", "edgeAndCorner"]
FaceVaryingMode = Literal["none", "cornersOnly", "cornersPlus1", "cornersPlus2", "boundaries", "all"]
Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int32]
ArrayLike = npt.ArrayLike
Path = Union[str, PathLike]
# A curve (points (n, 3) or homogeneous (n, 4), knots) or a patch (points (m, n, 3) or
# homogeneous (m, n, 4), knots_u, knots_v); homogeneous points are (w x, w y, w z, w).
CurveArrays = Tuple[ArrayLike, ArrayLike]
PatchArrays = Tuple[ArrayLike, ArrayLike, ArrayLike]

class SubsurfError(ValueError):
    """A mesh, its tags or an evaluation request that subsurf refuses; the message names the
    face, vertex or point at fault."""

class Mesh:
    """A polygon mesh with its subdivision options, in USD's vocabulary (`UsdGeomMesh`)."""

    def __init__(
        self,
        points: ArrayLike,
        face_vertex_counts: ArrayLike,
        face_vertex_indices: ArrayLike,
        *,
        crease_indices: Optional[ArrayLike] = None,
        crease_lengths: Optional[ArrayLike] = None,
        crease_sharpnesses: Optional[ArrayLike] = None,
        corner_indices: Optional[ArrayLike] = None,
        corner_sharpnesses: Optional[ArrayLike] = None,
        hole_indices: Optional[ArrayLike] = None,
        interpolate_boundary: Boundary = "edgeOnly",
        scheme: Scheme = "catmullClark",
        uvs: Optional[ArrayLike] = None,
        uv_indices: Optional[ArrayLike] = None,
        face_varying_linear_interpolation: FaceVaryingMode = "all",
        crease_method: Literal["uniform", "chaikin"] = "uniform",
        triangle_subdivision_rule: Literal["catmullClark", "smooth"] = "catmullClark",
        c: float = 0.5,
        adjust_steps: int = 1,
        knot_interval_indices: Optional[ArrayLike] = None,
        knot_intervals: Optional[ArrayLike] = None,
        weights: Optional[ArrayLike] = None,
    ) -> None: ...
    @property
    def c(self) -> Optional[float]:
        """The adjustable scheme's shape parameter, or None."""
    @property
    def adjust_steps(self) -> Optional[int]:
        """The levels the adjustable scheme refines before Catmull-Clark, or None."""
    @property
    def points(self) -> Floats:
        """`(n, 3)` positions."""
    @property
    def face_vertex_counts(self) -> Ints: ...
    @property
    def face_vertex_indices(self) -> Ints: ...
    @property
    def crease_indices(self) -> Ints:
        """Two vertices per sharp edge."""
    @property
    def crease_lengths(self) -> Ints:
        """2 per sharp edge."""
    @property
    def crease_sharpnesses(self) -> Floats: ...
    @property
    def corner_indices(self) -> Ints: ...
    @property
    def corner_sharpnesses(self) -> Floats: ...
    @property
    def hole_indices(self) -> Ints: ...
    @property
    def uvs(self) -> Optional[Floats]:
        """`(m, 2)` texture coordinates, or None."""
    @property
    def uv_indices(self) -> Optional[Ints]:
        """One index into `uvs` per face corner, or None."""
    @property
    def normals(self) -> Optional[Floats]:
        """`(n, 3)` unit limit normals (`subdivide(limit=True)`, `tessellate`), or None."""
    @property
    def scheme(self) -> Scheme: ...
    @property
    def interpolate_boundary(self) -> Boundary: ...
    @property
    def face_varying_linear_interpolation(self) -> FaceVaryingMode: ...
    @property
    def crease_method(self) -> Literal["uniform", "chaikin"]: ...
    @property
    def triangle_subdivision_rule(self) -> Literal["catmullClark", "smooth"]: ...
    @property
    def num_points(self) -> int: ...
    @property
    def num_faces(self) -> int: ...
    def subdivide(self, levels: int, *, limit: bool = False) -> Mesh:
        """Refine `levels` times, as OpenSubdiv's `Far` numbers and computes it; with
        `limit`, move the last level to its limit and set `normals`.

        >>> import subsurf
        >>> tri = subsurf.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [3], [0, 1, 2], scheme="loop")
        >>> tri.subdivide(2).num_faces
        16
        """
    def limit_surface(self) -> Surface:
        """The exact limit surface (and the limit of the texture coordinates)."""
    def g2_surface(self, levels: Optional[int] = None) -> Surface:
        """The surface with curvature-continuous (G2) bi-septic caps at the extraordinary
        vertices (Tang, Li, Liu and Gu 2017), after `levels` isolation levels."""
    def spline_surface(self) -> Surface:
        """The rational bicubic sub-basis spline surface (over the first Catmull-Clark level
        when the mesh has non-quad faces: see `Surface.mesh`)."""
    def tessellate(self, rate: int = 8, *, triangles: bool = False) -> Mesh:
        """A watertight tessellation of the limit surface, with limit normals and texture
        coordinates; its scheme is "bilinear"."""
    def regularity(
        self,
        *,
        local: bool = False,
        sample: int = 9,
        planar: bool = False,
        plot: Optional[Path] = None,
    ) -> Dict[str, Any]:
        """The regularity certificate of the Catmull-Clark limit surface (Wang, Lin, Wang
        and Lu 2016) as `subsurf regularity --json` reports it (`file` is None):
        `certified`, `counts`, the global cones per component and each face's verdict.
        `local`: per face's patch neighbourhood instead of one cone pair per component;
        `sample`: `sample x sample` limit samples per face (0: none, else 2 to 1024);
        `planar`: treat the net as planar (x, y); `plot`: draw the net and its difference
        fans to an .svg or .png file.

        >>> import subsurf
        >>> strip = subsurf.Mesh([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]],
        ...                      [4, 4], [0, 1, 4, 3, 1, 2, 5, 4],
        ...                      interpolate_boundary="edgeAndCorner")
        >>> report = strip.regularity()
        >>> report["certified"], report["counts"]["certified"]
        (True, 2)
        """
    def write(self, path: Path) -> None:
        """Write OBJ (`.obj`) or PLY (`.ply`); the file appears only once complete."""
    @staticmethod
    def from_trimesh(mesh: object, *, scheme: Scheme = "loop") -> Mesh:
        """A mesh from a `trimesh.Trimesh` (its `vertices` and `faces`)."""
    def to_trimesh(self) -> object:
        """The mesh as a `trimesh.Trimesh` (polygons as triangle fans). Needs trimesh."""

class Surface:
    """A smooth surface over a mesh's faces: the exact limit surface (as OpenSubdiv's
    `Bfr::Surface` evaluates it), the G2-capped surface or the sub-basis spline surface."""

    @property
    def num_faces(self) -> int: ...
    @property
    def kind(self) -> Literal["limit", "g2", "spline"]: ...
    @property
    def mesh(self) -> Mesh:
        """The mesh whose faces `evaluate` takes."""
    def tessellate(self, rate: int = 8, *, triangles: bool = False) -> Mesh:
        """A watertight tessellation with normals (and, on a limit surface, the limit of the
        texture coordinates)."""
    def evaluate(
        self,
        face_ids: ArrayLike,
        u: ArrayLike,
        v: ArrayLike,
        *,
        subfaces: Optional[ArrayLike] = None,
        second: bool = False,
    ) -> Tuple[Floats, ...]:
        """`(pos, du, dv)` at every `(face_ids[i], u[i], v[i])`, each `(n, 3)`; with
        `second`, also `(duu, duv, dvv)`. Loop triangles take `u, v >= 0, u + v <= 1`; an
        n-gon's quad sub-face is chosen by `subfaces`."""
    def evaluate_uv(
        self,
        face_ids: ArrayLike,
        u: ArrayLike,
        v: ArrayLike,
        *,
        subfaces: Optional[ArrayLike] = None,
    ) -> Floats:
        """The limit of the texture coordinates, `(n, 2)`."""

class Reposer:
    """Refinement of one mesh in many poses: topology and masks computed once, each pose
    only interpolated (animation)."""

    def __init__(self, mesh: Mesh, levels: int, *, limit: bool = False) -> None: ...
    def pose(self, points: ArrayLike) -> Floats:
        """The refined points `(m, 3)` of the base mesh's points moved to `points` `(n, 3)`;
        equal to `Mesh.subdivide` of the moved mesh. Many frames at once: `(frames, n, 3)`
        gives `(frames, m, 3)`, each frame as if posed alone (`mesh` and `normals` are then
        the last frame's)."""
    @property
    def mesh(self) -> Mesh:
        """The refined mesh in the last pose."""
    @property
    def normals(self) -> Optional[Floats]:
        """The limit normals of the last pose (`limit=True`), or None."""

class BlendResult:
    """A blend or fill (`blend`, `fill`): the surface, the base patches and boundary
    curves around it, and the control mesh."""

    @property
    def method(self) -> Literal["blend", "fill"]: ...
    @property
    def surface(self) -> Mesh:
        """The blend or fill surface (scheme "bilinear")."""
    @property
    def control(self) -> Mesh:
        """The control mesh (scheme "nurss", with its knot intervals; the outer ring is the
        extension layer)."""
    @property
    def patches(self) -> List[Mesh]:
        """The base patches tessellated at `samples` segments per knot span."""
    @property
    def curves(self) -> List[Floats]:
        """Fill: the boundary curves as `(k, 3)` polylines; blend: empty."""
    @property
    def comment(self) -> str:
        """A one-line description of the job."""
    def write(self, path: Path) -> None:
        """Write the OBJ file of `subsurf blend` / `subsurf fill`: groups `patch_1`, ...,
        `blend` or `fill`, and the polylines `curve_1`, ...."""

def blend(
    patches: Union[Path, Sequence[PatchArrays]],
    *,
    levels: int = 5,
    samples: int = 8,
) -> BlendResult:
    """Join N >= 2 bicubic B-spline or NURBS patches C2 with a non-uniform Catmull-Clark
    surface refined `levels` times with skirt removal (Jiang et al.), as `subsurf blend`
    does. `patches`: a JSON or OBJ free-form file, or `(points, knots_u, knots_v)` tuples
    in order around the region (each blended along its first row); `samples`: segments per
    knot span of the tessellated base patches.

    >>> import subsurf
    >>> b = subsurf.blend("examples/patches/blend3.json", levels=3)  # doctest: +SKIP
    >>> b.surface.num_faces, [p.num_faces for p in b.patches]  # doctest: +SKIP
    (3024, [128, 128, 128])
    """

def fill(
    boundary: Union[Path, Sequence[Union[CurveArrays, PatchArrays]]],
    *,
    levels: int = 5,
    bulge: float = 0.0,
    g1: bool = False,
    samples: int = 8,
) -> BlendResult:
    """Fill the hole bounded by 3 to 8 cubic curves or bicubic patches (their first-row
    boundary) with a corner-interpolating non-uniform Catmull-Clark surface (Jiang et al.,
    Algorithm 1), as `subsurf fill` does; `bulge` moves the inner points along the normal by
    `bulge` times the hole's radius; `g1` (patches only, Algorithm 2) meets the patches with
    a continuous normal.

    >>> import numpy as np, subsurf
    >>> corners = [np.array([np.cos(a), np.sin(a), 0.0]) for a in np.arange(3) * 2 * np.pi / 3]
    >>> sides = [(np.linspace(corners[k], corners[(k + 1) % 3], 4), [0, 0, 0, 0, 1, 1, 1, 1])
    ...          for k in range(3)]
    >>> f = subsurf.fill(sides, levels=2)
    >>> f.method, len(f.curves), f.patches
    ('fill', 3, [])
    """

def read(
    path: Path, *, scheme: Scheme = "catmullClark", c: float = 0.5, adjust_steps: int = 1
) -> Mesh:
    """Read an OBJ, PLY or glTF mesh with its tags and texture coordinates; what the file
    holds and the mesh cannot keep is reported as a warning."""

def interpolate_curves(
    path: Path,
    *,
    width: Optional[float] = None,
    side: Optional[Tuple[float, float, float]] = None,
    host: Optional[Mesh] = None,
) -> Mesh:
    """The control mesh (scheme "nurss", with knot intervals) whose limit surface
    interpolates the cubic B-spline and NURBS curves of a JSON or OBJ file; with `host`,
    the curves are embedded in that mesh."""
