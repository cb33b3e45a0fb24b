//! Creases from geometry: [`crease_by_angle`] tags every edge whose dihedral angle exceeds
//! a threshold (a long-standing request to OpenSubdiv, which only takes explicit tags).

use super::{Crease, MeshError, Options, PolyMesh, Topology};
use crate::geom;

/// Relative size below which a face normal counts as zero: a face is degenerate when
/// `|n| ≤ DEGENERATE_RELATIVE · Σ |p_{i+1} − p_i|²`, i.e. its area is zero up to rounding.
const DEGENERATE_RELATIVE: f64 = 1e-12;

/// Invalid arguments to [`crease_by_angle`], or a mesh whose topology cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CreaseAngleError {
    /// The threshold angle is NaN, infinite or outside [0, 180] degrees.
    #[error("crease angle {0} is invalid: it must be a number of degrees in [0, 180]")]
    BadAngle(f64),
    /// The sharpness is NaN, infinite or negative.
    #[error(
        "crease sharpness {0} is invalid: it must be a finite number ≥ 0 (≥ 10 is infinitely sharp)"
    )]
    BadSharpness(f32),
    /// The mesh's topology could not be built.
    #[error(transparent)]
    Mesh(#[from] MeshError),
}

/// Creases of sharpness `sharpness` on every edge whose crease angle exceeds `angle_deg`
/// degrees, one per edge, in edge order (first appearance while walking the faces).
///
/// # What is measured
/// For every manifold interior edge (exactly two faces, which run it in opposite
/// directions), the angle between the normals `n0`, `n1` of its two faces:
///
/// `angle = atan2(|n0 × n1|, n0 · n1)`, in degrees,
///
/// which is 0 where the surface continues flat, 90 on the edges of a cube and 180 for a
/// sheet folded back onto itself. An edge gets a crease when `angle > angle_deg`, so
/// `angle_deg = 180` creases nothing and `angle_deg = 0` every edge that is not exactly
/// flat.
///
/// A face's normal is Newell's normal over the whole polygon (computed relative to the
/// face's first vertex, for accuracy far from the origin), so n-gons and non-planar faces
/// get the area-weighted average plane:
///
/// `n_x = Σ (y_i − y_{i+1})(z_i + z_{i+1})`, `n_y = Σ (z_i − z_{i+1})(x_i + x_{i+1})`,
/// `n_z = Σ (x_i − x_{i+1})(y_i + y_{i+1})` (indices modulo the face size).
///
/// For a counter-clockwise face it points outwards and its length is twice the area of a
/// planar face; for a quad it equals the cross product of the diagonals.
///
/// # What is skipped
/// - Boundary edges (one face) and non-manifold edges (more than two faces, or two faces
///   running the edge in the same direction): refinement already makes them infinitely
///   sharp.
/// - Edges next to a degenerate face, one whose Newell normal is zero up to rounding
///   (`|n| ≤ 1e-12 · Σ |edge|²`: zero area, e.g. all its vertices on one line): it has no
///   direction to compare with.
///
/// Hole faces are measured like any other face (they still shape their neighbours).
///
/// # Combining with the mesh's own tags
/// The result is meant to go *before* the mesh's explicit creases:
/// `tags.creases = [auto..., file...]`. Since an edge listed twice takes the last value
/// (as in OpenSubdiv), a crease written in the file overrides the automatic one on the
/// same edge. `subsurf subdivide --crease-angle` does exactly this.
///
/// `options` only matter for building the [`Topology`] (they do not change which edges
/// are measured).
///
/// # Errors
/// [`CreaseAngleError::BadAngle`] unless `angle_deg` is finite and in [0, 180];
/// [`CreaseAngleError::BadSharpness`] unless `sharpness` is finite and ≥ 0;
/// [`CreaseAngleError::Mesh`] when the topology cannot be built (index range exceeded).
///
/// # Example
/// ```
/// use subsurf::mesh::{crease_by_angle, Options, PolyMesh, SHARPNESS_INFINITE};
///
/// let p = vec![
///     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
///     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
/// ];
/// let faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
/// let mut cube = PolyMesh::from_faces(p, &faces).unwrap();
///
/// // The cube's edges are at 90°: all 12 exceed 60°, none exceeds 100°.
/// let creases = crease_by_angle(&cube, &Options::default(), 60.0, SHARPNESS_INFINITE).unwrap();
/// assert_eq!(creases.len(), 12);
/// assert!(crease_by_angle(&cube, &Options::default(), 100.0, 10.0).unwrap().is_empty());
///
/// // Automatic creases first, so that the mesh's own tags win on the same edge.
/// let explicit = std::mem::take(&mut cube.tags.creases);
/// cube.tags.creases = creases;
/// cube.tags.creases.extend(explicit);
///
/// assert!(crease_by_angle(&cube, &Options::default(), 200.0, 10.0).is_err());
/// ```
pub fn crease_by_angle(
    mesh: &PolyMesh,
    options: &Options,
    angle_deg: f64,
    sharpness: f32,
) -> Result<Vec<Crease>, CreaseAngleError> {
    if !(angle_deg.is_finite() && (0.0..=180.0).contains(&angle_deg)) {
        return Err(CreaseAngleError::BadAngle(angle_deg));
    }
    if !(sharpness.is_finite() && sharpness >= 0.0) {
        return Err(CreaseAngleError::BadSharpness(sharpness));
    }
    let (topo, _warnings) = Topology::from_mesh(mesh, options)?;
    let positions = mesh.positions();
    let normals: Vec<Option<[f64; 3]>> = (0..topo.num_faces())
        .map(|f| newell_normal(positions, topo.face_vertices(f)))
        .collect();
    let mut creases = Vec::new();
    for e in 0..topo.num_edges() {
        let tag = topo.edge_tag(e);
        let faces = topo.edge_face_list(e);
        if tag.boundary || tag.non_manifold || faces.len() != 2 || faces[0] == faces[1] {
            continue;
        }
        let (Some(n0), Some(n1)) = (normals[faces[0] as usize], normals[faces[1] as usize]) else {
            continue;
        };
        if angle_between_deg(n0, n1) > angle_deg {
            let [v0, v1] = topo.edge_vertices(e);
            creases.push(Crease { v0, v1, sharpness });
        }
    }
    Ok(creases)
}

/// Newell's normal of the polygon `face` (not normalised), or `None` when it is zero up to
/// rounding. Coordinates are taken relative to the first vertex (the formula is
/// translation-invariant; this keeps the products small).
fn newell_normal(positions: &[[f64; 3]], face: &[u32]) -> Option<[f64; 3]> {
    let n = geom::newell_normal(positions, face);
    let scale: f64 = (0..face.len())
        .map(|i| {
            let a = &positions[face[i] as usize];
            let d = geom::sub(&positions[face[(i + 1) % face.len()] as usize], a);
            geom::dot(&d, &d)
        })
        .sum();
    // False for NaN too (coordinates so large that the products overflow).
    (geom::norm(&n) > DEGENERATE_RELATIVE * scale).then_some(n)
}

/// The angle between two non-zero vectors, in degrees, in [0, 180] (accurate near 0 and
/// 180, unlike `acos` of the normalised dot product).
fn angle_between_deg(a: [f64; 3], b: [f64; 3]) -> f64 {
    geom::norm(&geom::cross(&a, &b))
        .atan2(geom::dot(&a, &b))
        .to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::SHARPNESS_INFINITE;

    use crate::mesh::test_cube as cube;
    use crate::mesh::test_grid as grid;

    /// Edges of `creases` as sorted vertex pairs, sorted.
    fn edges(creases: &[Crease]) -> Vec<(u32, u32)> {
        let mut e: Vec<_> = creases
            .iter()
            .map(|c| (c.v0.min(c.v1), c.v0.max(c.v1)))
            .collect();
        e.sort_unstable();
        e
    }

    fn run(mesh: &PolyMesh, angle: f64) -> Vec<Crease> {
        crease_by_angle(mesh, &Options::default(), angle, SHARPNESS_INFINITE).unwrap()
    }

    #[test]
    fn cube_edges_are_at_ninety_degrees() {
        let m = cube();
        let c = run(&m, 89.0);
        assert_eq!(c.len(), 12);
        assert!(c.iter().all(|c| c.sharpness == SHARPNESS_INFINITE));
        let (t, _) = Topology::from_mesh(&m, &Options::default()).unwrap();
        let mut all: Vec<_> = (0..t.num_edges())
            .map(|e| {
                let [a, b] = t.edge_vertices(e);
                (a.min(b), a.max(b))
            })
            .collect();
        all.sort_unstable();
        assert_eq!(edges(&c), all);
        assert!(run(&m, 91.0).is_empty());
        assert!(run(&m, 180.0).is_empty());
        assert_eq!(run(&m, 0.0).len(), 12);
    }

    #[test]
    fn sharpness_is_passed_through() {
        let c = crease_by_angle(&cube(), &Options::default(), 45.0, 2.5).unwrap();
        assert_eq!(c.len(), 12);
        assert!(c.iter().all(|c| c.sharpness == 2.5));
        let c = crease_by_angle(&cube(), &Options::default(), 45.0, 0.0).unwrap();
        assert!(c.iter().all(|c| c.sharpness == 0.0));
    }

    #[test]
    fn flat_grid_has_no_creases() {
        let m = grid(4, 3, |x, y| [x, y, 0.0]);
        assert!(run(&m, 0.0).is_empty());
        // Tilted and far from the origin: still flat up to rounding.
        let m = grid(4, 3, |x, y| [1e6 + x, 2e6 + 0.6 * y, -3e6 + 0.8 * y]);
        assert!(run(&m, 1e-6).is_empty());
    }

    #[test]
    fn folded_grid_creases_exactly_the_fold() {
        // 3 × 4 quads; rows j ≥ 1 are turned 30° about the line y = 1.
        let (s, c) = 30f64.to_radians().sin_cos();
        let m = grid(3, 4, |x, y| {
            if y <= 1.0 {
                [x, y, 0.0]
            } else {
                [x, 1.0 + (y - 1.0) * c, (y - 1.0) * s]
            }
        });
        let got = run(&m, 20.0);
        // The interior edges on the fold line y = 1: (i, 1)–(i + 1, 1), i = 0..3.
        let want: Vec<(u32, u32)> = (0..3).map(|i| (4 + i, 4 + i + 1)).collect();
        assert_eq!(edges(&got), want);
        assert!(run(&m, 29.9).len() == 3);
        assert!(run(&m, 30.1).is_empty());
    }

    #[test]
    fn n_gons_use_the_whole_polygon() {
        // A hexagonal prism: side faces meet at 60°, caps meet the sides at 90°.
        let mut p = Vec::new();
        for z in [0.0, 1.0] {
            for k in 0..6 {
                let a = (k as f64 * 60.0).to_radians();
                p.push([a.cos(), a.sin(), z]);
            }
        }
        let mut faces: Vec<Vec<u32>> = vec![(0..6).rev().collect(), (6..12).collect()];
        for k in 0..6 {
            let k1 = (k + 1) % 6;
            faces.push(vec![k, k1, k1 + 6, k + 6]);
        }
        let m = PolyMesh::from_faces(p, &faces).unwrap();
        assert_eq!(run(&m, 50.0).len(), 18);
        assert_eq!(run(&m, 70.0).len(), 12);
        assert!(run(&m, 95.0).is_empty());
    }

    #[test]
    fn non_planar_quads_use_the_newell_normal() {
        // Two twisted quads sharing the edge 1–4.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.2],
            [2.0, 0.0, -0.3],
            [0.0, 1.0, 0.4],
            [1.0, 1.0, -0.1],
            [2.0, 1.0, 0.5],
        ];
        let faces = [[0, 1, 4, 3], [1, 2, 5, 4]];
        let m = PolyMesh::from_faces(p.clone(), &faces).unwrap();
        // Newell's normal of a quad is the cross product of its diagonals.
        let diag = |f: [u32; 4]| {
            let d = |a: u32, b: u32| {
                let (a, b) = (p[a as usize], p[b as usize]);
                [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
            };
            let (u, v) = (d(f[0], f[2]), d(f[1], f[3]));
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        for f in faces {
            let n = newell_normal(&p, &f).unwrap();
            let want = diag(f);
            for k in 0..3 {
                assert!((n[k] - want[k]).abs() < 1e-14, "{n:?} vs {want:?}");
            }
        }
        let angle = angle_between_deg(diag(faces[0]), diag(faces[1]));
        assert!(angle > 1.0 && angle < 179.0, "{angle}");
        assert_eq!(edges(&run(&m, angle - 1e-9)), vec![(1, 4)]);
        assert!(run(&m, angle + 1e-9).is_empty());
    }

    #[test]
    fn boundary_and_non_manifold_edges_are_skipped() {
        // An open box (a cube without its top face): the 4 rim edges are boundaries.
        let mut m = cube();
        let faces: Vec<Vec<u32>> = m
            .faces()
            .filter(|f| f[0] != 4)
            .map(<[u32]>::to_vec)
            .collect();
        m = PolyMesh::from_faces(m.positions().to_vec(), &faces).unwrap();
        assert_eq!(m.num_faces(), 5);
        let c = run(&m, 45.0);
        assert_eq!(c.len(), 8);
        assert!(c.iter().all(|c| c.v0 < 4 || c.v1 < 4));
        // Three quads on one edge (0–1) at 90° from each other: non-manifold, skipped.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
            [1.0, -1.0, 0.0],
            [0.0, -1.0, 0.0],
        ];
        let m = PolyMesh::from_faces(p, &[[0, 1, 2, 3], [1, 0, 5, 4], [0, 1, 6, 7]]).unwrap();
        assert!(run(&m, 0.0).is_empty());
    }

    #[test]
    fn degenerate_faces_are_skipped() {
        // A unit square and a second quad on its edge 1–2.
        let square = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let faces = [[0, 1, 2, 3], [2, 1, 4, 5]];
        // The second quad has zero area: all its vertices lie on the line x = 1, z = 0.
        let mut p = square.to_vec();
        p.extend([[1.0, -1.0, 0.0], [1.0, 2.0, 0.0]]);
        let m = PolyMesh::from_faces(p, &faces).unwrap();
        assert!(newell_normal(m.positions(), m.face(1)).is_none());
        assert!(run(&m, 0.0).is_empty());
        // The same topology with a proper second quad, standing at 90°, is creased.
        let mut p = square.to_vec();
        p.extend([[1.0, 0.0, 1.0], [1.0, 1.0, 1.0]]);
        let m = PolyMesh::from_faces(p, &faces).unwrap();
        assert!(newell_normal(m.positions(), m.face(1)).is_some());
        assert_eq!(edges(&run(&m, 45.0)), vec![(1, 2)]);
    }

    #[test]
    fn invalid_arguments_are_rejected() {
        let m = cube();
        let o = Options::default();
        for a in [-1.0, 180.5, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            match crease_by_angle(&m, &o, a, 10.0) {
                Err(CreaseAngleError::BadAngle(x)) => assert!(x.is_nan() || x == a),
                other => panic!("angle {a}: {other:?}"),
            }
        }
        for s in [-0.5, f32::NAN, f32::INFINITY] {
            match crease_by_angle(&m, &o, 30.0, s) {
                Err(CreaseAngleError::BadSharpness(x)) => assert!(x.is_nan() || x == s),
                other => panic!("sharpness {s}: {other:?}"),
            }
        }
        let msg = crease_by_angle(&m, &o, 200.0, 10.0)
            .unwrap_err()
            .to_string();
        assert!(msg.contains("200") && msg.contains("[0, 180]"), "{msg}");
        assert!(crease_by_angle(&m, &o, 0.0, 0.0).is_ok());
        assert!(crease_by_angle(&m, &o, 180.0, 10.0).is_ok());
    }

    #[test]
    fn explicit_tags_after_auto_creases_win() {
        let mut m = cube();
        m.tags.creases.push(Crease {
            v0: 1,
            v1: 0,
            sharpness: 0.0,
        });
        let mut creases = run(&m, 60.0);
        creases.append(&mut m.tags.creases);
        m.tags.creases = creases;
        let (t, _) = Topology::from_mesh(&m, &Options::default()).unwrap();
        for e in 0..t.num_edges() {
            let [a, b] = t.edge_vertices(e);
            let want = if (a.min(b), a.max(b)) == (0, 1) {
                0.0
            } else {
                SHARPNESS_INFINITE
            };
            assert_eq!(t.edge_sharpness(e), want, "edge {a}-{b}");
        }
    }
}
