"""Subdivision surfaces exactly as OpenSubdiv computes them, with numpy arrays in and out.

The mesh speaks USD's vocabulary (``UsdGeomMesh``'s attribute names and tokens)::

    import numpy as np
    import subsurf

    cube = subsurf.Mesh(
        points=np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                         [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float),
        face_vertex_counts=[4] * 6,
        face_vertex_indices=[0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                             1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7],
        crease_indices=[0, 1], crease_lengths=[2], crease_sharpnesses=[2.0],
    )
    refined = cube.subdivide(2)             # a Mesh: refined.points is (98, 3) float64
    surface = cube.limit_surface()
    pos, du, dv = surface.evaluate([0, 1], [0.5, 0.25], [0.5, 0.75])
    tessellation = cube.tessellate(rate=8)  # watertight, with limit normals

The paper methods work on meshes (``Mesh.g2_surface``, ``Mesh.spline_surface``,
``Mesh.regularity``) and on curves and patches (``interpolate_curves``, ``blend``,
``fill``).

Every call releases the interpreter lock and runs on the library's own threads.
"""

from ._subsurf import (
    BlendResult,
    Mesh,
    Reposer,
    SubsurfError,
    Surface,
    __version__,
    blend,
    fill,
    interpolate_curves,
    read,
)

__all__ = [
    "BlendResult",
    "Mesh",
    "Reposer",
    "SubsurfError",
    "Surface",
    "__version__",
    "blend",
    "fill",
    "interpolate_curves",
    "read",
]
