"""A notebook-style tour: build a mesh from arrays, refine it, evaluate its exact limit
surface and plot the mean curvature along a line across a crease.

    python python/examples/refine_evaluate_plot.py   # writes limit-curvature.png

Each block below is one notebook cell. Needs matplotlib for the plot.
"""

import numpy as np

import subsurf

# %% A cube with a semi-sharp crease along three of its edges (USD's crease encoding).
cube = subsurf.Mesh(
    points=np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                     [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float),
    face_vertex_counts=[4] * 6,
    face_vertex_indices=[0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                         1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7],
    crease_indices=[0, 1, 2, 3], crease_lengths=[4], crease_sharpnesses=[2.0],
)

# %% Refinement, exactly as OpenSubdiv numbers and computes it.
refined = cube.subdivide(3)
print(refined, "sharpness left:", refined.crease_sharpnesses[:4])

# %% The exact limit surface along face 2 (the side x-z face, crossing the crease at v = 0):
# position, first and second derivatives, then the mean curvature from the fundamental forms.
v = np.linspace(0.0, 1.0, 201)
u = np.full_like(v, 0.5)
p, du, dv, duu, duv, dvv = cube.limit_surface().evaluate(np.full(v.size, 2), u, v, second=True)
n = np.cross(du, dv)
n /= np.linalg.norm(n, axis=1, keepdims=True)
E, F, G = (du * du).sum(1), (du * dv).sum(1), (dv * dv).sum(1)
L, M, N = (duu * n).sum(1), (duv * n).sum(1), (dvv * n).sum(1)
mean_curvature = (E * N - 2 * F * M + G * L) / (2 * (E * G - F * F))

# %% Plot: |H| is largest at the semi-sharp crease (v = 0); at v = 1/4 the curvature jumps,
# where the rule of the sharpness-2 crease (two levels, 2⁻² of the face) ends.
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed: no plot")
else:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(v, mean_curvature)
    ax.set_xlabel("v on face 2 (u = 0.5)")
    ax.set_ylabel("mean curvature H")
    ax.set_title("Exact limit surface of a creased cube")
    fig.tight_layout()
    fig.savefig("limit-curvature.png", dpi=120)
    print("wrote limit-curvature.png")
