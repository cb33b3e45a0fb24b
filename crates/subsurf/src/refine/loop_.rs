//! Loop subdivision of triangle meshes ([`scheme::loop_`](crate::scheme::loop_)) and
//! bilinear subdivision ([`scheme::bilinear`](crate::scheme::bilinear)), as OpenSubdiv
//! refines them: the topology once ([`TopologyRefiner`](super::TopologyRefiner) with
//! [`Scheme::Loop`](crate::Scheme::Loop) or `Bilinear`), then any primvar through it
//! ([`interpolate_loop`], or [`interpolate_with`](super::interpolate_with) and
//! [`Bilinear`](crate::scheme::bilinear::Bilinear)). [`subdivide`](fn@crate::subdivide)
//! refines a mesh with either through `refine::uniform`, its face-varying channels (texture
//! coordinates) with them through [`FaceVaryingRefiner`](super::FaceVaryingRefiner), which
//! follows Loop's triangle split.

use super::primvar::{axpy, run_chunks, vertex_points};
use crate::mesh::{MeshError, Options, PolyMesh, Topology};
use crate::scheme::loop_::Loop;
use crate::scheme::Rules;

/// [`MeshError::NotTriangle`] for the first face of `mesh` that is not a triangle.
pub(crate) fn check_triangles(mesh: &PolyMesh) -> Result<(), MeshError> {
    match mesh.faces().position(|f| f.len() != 3) {
        Some(face) => Err(MeshError::NotTriangle {
            face,
            count: mesh.faces().nth(face).map_or(0, <[u32]>::len),
        }),
        None => Ok(()),
    }
}

/// Interpolates `src` (values at the vertices of the triangle mesh `parent`) to `dst`
/// (values at the vertices of `child`, its triangle split) with Loop's
/// masks (`Loop`, with the rules of [`Rules`]): the edge points first
/// (`⅜(v₀ + v₁) + ⅛(o₀ + o₁)` when smooth), then the vertex points
/// (`(1 − nβₙ) v + βₙ Σ eᵢ` when smooth), as OpenSubdiv's `PrimvarRefiner::Interpolate`.
///
/// # Panics
/// If `src.len() != parent.num_vertices()` or `dst.len() != child.num_vertices()`.
pub fn interpolate_loop<const D: usize>(
    parent: &Topology,
    child: &Topology,
    options: &Options,
    src: &[[f64; D]],
    dst: &mut [[f64; D]],
) {
    let nv = parent.num_vertices();
    assert_eq!(src.len(), nv, "source has the wrong number of values");
    assert_eq!(
        dst.len(),
        child.num_vertices(),
        "destination has the wrong number of values"
    );
    let (vert_pts, edge_pts) = dst.split_at_mut(nv);
    // The vertex of face `f` opposite its edge `i`.
    let opposite =
        |f: u32, i: u16| &src[parent.face_vertices(f as usize)[(i as usize + 2) % 3] as usize];
    let edge_pass = |(start, out): (usize, &mut [[f64; D]])| {
        for (i, o) in out.iter_mut().enumerate() {
            let e = start + i;
            let [a, b] = parent.edge_verts[e];
            let faces = parent.edge_face_list(e);
            let local = &parent.edge_face_local[parent.edge_face_offsets[e] as usize..];
            let sharp = parent.edge_sharpness[e];
            let (pa, pb) = (&src[a as usize], &src[b as usize]);
            if sharp <= 0.0 && faces.len() == 2 {
                let opp = [opposite(faces[0], local[0]), opposite(faces[1], local[1])];
                *o = Loop.smooth_edge_point([pa, pb], opp);
                continue;
            }
            let child_rule = child.vert_tags[nv + e].get().rule;
            let m = Loop.edge_mask(options, sharp, child_rule, faces.len(), [false; 2]);
            let mut acc: [f64; D] = std::array::from_fn(|k| m.vertex * (pa[k] + pb[k]));
            if !m.is_crease() {
                for (j, (&f, &l)) in faces.iter().zip(local).enumerate() {
                    let w = if j < 2 { m.faces[j] } else { m.other_faces };
                    axpy(&mut acc, w, opposite(f, l));
                }
            }
            *o = acc;
        }
    };
    let vertex_pass = |chunk: (usize, &mut [[f64; D]])| {
        vertex_points(parent, child, options, Loop, src, None, chunk)
    };
    rayon::join(
        || run_chunks(edge_pts, edge_pass),
        || run_chunks(vert_pts, vertex_pass),
    );
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::mesh::{BoundaryInterpolation, Corner, Crease, Tags, TopologyWarning};
    use crate::refine::uniform::{refine_uniform, Steps};
    use crate::scheme::Scheme;

    /// `mesh` refined `levels` times with `steps`, as `subdivide` refines it.
    fn refine(
        mesh: &PolyMesh,
        options: &Options,
        steps: Steps,
        levels: u32,
        keep_holes: bool,
    ) -> Result<(PolyMesh, Vec<TopologyWarning>), MeshError> {
        mesh.validate()?;
        let mut u = refine_uniform(mesh, options, steps, levels, false, &mut |_, _| {})?;
        let warnings = std::mem::take(&mut u.warnings);
        Ok((u.into_mesh(keep_holes), warnings))
    }

    fn subdivide_loop(
        mesh: &PolyMesh,
        options: &Options,
        levels: u32,
        keep_holes: bool,
    ) -> Result<(PolyMesh, Vec<TopologyWarning>), MeshError> {
        refine(mesh, options, Steps::Loop, levels, keep_holes)
    }

    fn subdivide_bilinear(
        mesh: &PolyMesh,
        options: &Options,
        levels: u32,
        keep_holes: bool,
    ) -> Result<(PolyMesh, Vec<TopologyWarning>), MeshError> {
        refine(mesh, options, Steps::Bilinear, levels, keep_holes)
    }
    use crate::mesh::CreaseMethod;

    /// An `n × n` grid of squares, each cut into two triangles along alternating
    /// diagonals, with heights `z(i, j)`.
    pub(in crate::refine) fn tri_grid(n: u32, z: impl Fn(u32, u32) -> f64) -> PolyMesh {
        let id = |i: u32, j: u32| i * (n + 1) + j;
        let mut pos = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                pos.push([j as f64, i as f64, z(i, j)]);
            }
        }
        let mut faces = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j));
                if (i + j) % 2 == 0 {
                    faces.extend([[a, b, c], [a, c, d]]);
                } else {
                    faces.extend([[a, b, d], [b, c, d]]);
                }
            }
        }
        PolyMesh::from_faces(pos, &faces).unwrap()
    }

    /// A grid with semi-sharp creases (decaying at different levels, meeting at a vertex
    /// with three sharp edges), an infinitely sharp one and a semi-sharp corner.
    fn creased_grid() -> PolyMesh {
        let mut m = tri_grid(4, |i, j| ((i * 7 + j * 3) % 5) as f64 * 0.3);
        let crease = |v0, v1, sharpness| Crease { v0, v1, sharpness };
        m.tags.creases = vec![
            crease(6, 7, 2.5),
            crease(7, 8, 1.25),
            crease(7, 12, 0.5),
            crease(16, 17, 10.0),
            crease(17, 18, 10.0),
        ];
        m.tags.corners = vec![Corner {
            vertex: 13,
            sharpness: 1.5,
        }];
        m
    }

    fn run_loop(m: &PolyMesh, o: &Options, levels: u32) -> PolyMesh {
        subdivide_loop(m, o, levels, true).unwrap().0
    }

    #[test]
    fn a_face_that_is_not_a_triangle_is_named() {
        let m = PolyMesh::from_faces(
            vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            &[vec![0u32, 1, 2], vec![0, 2, 3, 1]],
        )
        .unwrap();
        let want = MeshError::NotTriangle { face: 1, count: 4 };
        let got = subdivide_loop(&m, &Options::default(), 1, false);
        assert_eq!(got.unwrap_err(), want);
        let refiner = super::super::TopologyRefiner::new(&m, Scheme::Loop, Options::default());
        assert_eq!(
            refiner.unwrap_err(),
            super::super::Error::Mesh(want.clone())
        );
        assert!(want.to_string().contains("face 1 has 4 vertices"));
    }

    /// Refining the output of `a` levels (whose tags carry the remaining sharpness and
    /// the holes) `b` more levels gives the result of `a + b` levels. The two number edges
    /// differently (the output's edges are numbered afresh when it is read), so new
    /// vertices come in another order; the children of the output's vertices keep their
    /// indices in both, and their positions, which depend on everything around them, are
    /// compared.
    #[test]
    fn refining_the_output_again_continues_the_refinement() {
        let m = creased_grid();
        for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            for boundary in [
                BoundaryInterpolation::EdgeOnly,
                BoundaryInterpolation::EdgeAndCorner,
                BoundaryInterpolation::None,
            ] {
                let o = Options {
                    crease_method: method,
                    boundary,
                    ..Options::default()
                };
                let all = run_loop(&m, &o, 3);
                let first = run_loop(&m, &o, 1);
                let again = run_loop(&first, &o, 2);
                assert_eq!(all.num_vertices(), again.num_vertices());
                assert_eq!(all.num_faces(), again.num_faces());
                assert_eq!(all.tags.holes.len(), again.tags.holes.len());
                let n = first.num_vertices();
                for (p, q) in all.positions()[..n].iter().zip(&again.positions()[..n]) {
                    for k in 0..3 {
                        assert!((p[k] - q[k]).abs() < 1e-13, "{method:?} {boundary:?}");
                    }
                }
            }
        }
    }

    /// Loop's masks are affine combinations: refining an affinely mapped mesh is mapping
    /// the refined mesh; a flat mesh stays flat (creases, corners and all).
    #[test]
    fn loop_is_affine_invariant_and_keeps_a_flat_mesh_flat() {
        let m = creased_grid();
        let o = Options::default();
        let map = |p: &[f64; 3]| {
            [
                2.0 * p[0] - 0.5 * p[1] + 0.25 * p[2] + 3.0,
                0.3 * p[0] + 1.5 * p[1] - p[2] - 1.0,
                -0.7 * p[0] + 0.2 * p[1] + 0.9 * p[2] + 0.5,
            ]
        };
        let mut moved = m.clone();
        let pos: Vec<[f64; 3]> = m.positions().iter().map(map).collect();
        moved.positions_mut().copy_from_slice(&pos);
        let a = run_loop(&m, &o, 3);
        let b = run_loop(&moved, &o, 3);
        for (p, q) in a.positions().iter().zip(b.positions()) {
            let p = map(p);
            for k in 0..3 {
                assert!((p[k] - q[k]).abs() < 1e-12);
            }
        }
        let mut flat = m.clone();
        for p in flat.positions_mut() {
            p[2] = 0.25 * p[0] - 0.5 * p[1] + 1.0;
        }
        let r = run_loop(&flat, &o, 3);
        assert!(r
            .positions()
            .iter()
            .all(|p| (p[2] - (0.25 * p[0] - 0.5 * p[1] + 1.0)).abs() < 1e-12));
    }

    /// `mesh` with a face-varying channel `"p"` holding its positions, one value per
    /// vertex indexed as the faces index the vertices: the channel's topology is the
    /// vertex topology.
    fn with_position_channel(mesh: &PolyMesh) -> PolyMesh {
        let mut m = mesh.clone();
        let values = m.positions().iter().flatten().copied().collect();
        let ch = crate::mesh::FaceVarying::new("p", 3, values, m.face_verts().to_vec()).unwrap();
        m.face_varying = vec![ch];
        m
    }

    /// A face-varying channel laid out as the vertices, in mode `None` (no face-varying
    /// boundary is made linear or sharp), takes exactly the vertex masks: Loop's
    /// face-varying path (`FaceVaryingRefiner` with the triangle split) gives every face
    /// corner the position that the vertex path (`interpolate_loop`) gives the corner's
    /// vertex — with semi-sharp and infinitely sharp creases, a semi-sharp corner,
    /// boundaries in every mode, both crease methods, a non-manifold edge and a
    /// degenerate triangle.
    #[test]
    fn face_varying_on_the_vertex_topology_refines_as_the_vertices() {
        use crate::mesh::FaceVaryingInterpolation;
        let grid = creased_grid();
        // Two more triangles on the grid's edge 6-7 (a non-manifold fin), one degenerate.
        let mut pos = grid.positions().to_vec();
        pos.push([1.5, 1.0, 2.0]);
        let top = pos.len() as u32 - 1;
        let mut faces: Vec<Vec<u32>> = grid.faces().map(<[u32]>::to_vec).collect();
        faces.extend([vec![6, 7, top], vec![7, top, 7]]);
        let mut fin = PolyMesh::from_faces(pos, &faces).unwrap();
        fin.tags = grid.tags.clone();
        for mesh in [grid, fin] {
            let m = with_position_channel(&mesh);
            for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
                for boundary in [
                    BoundaryInterpolation::EdgeOnly,
                    BoundaryInterpolation::EdgeAndCorner,
                    BoundaryInterpolation::None,
                ] {
                    let o = Options {
                        crease_method: method,
                        boundary,
                        face_varying: FaceVaryingInterpolation::None,
                        ..Options::default()
                    };
                    let out = subdivide_loop(&m, &o, 3, true).unwrap().0;
                    let ch = &out.face_varying[0];
                    assert_eq!(ch.indices().len(), out.face_verts().len());
                    for (&v, &x) in out.face_verts().iter().zip(ch.indices()) {
                        let (p, q) = (out.positions()[v as usize], ch.value(x as usize));
                        for k in 0..3 {
                            let e = (p[k] - q[k]).abs();
                            assert!(e < 1e-13, "{method:?} {boundary:?}: vertex {v} {e:e}");
                        }
                    }
                }
            }
        }
    }

    /// Loop's face-varying refinement of random triangle soups (repeated and degenerate
    /// triangles, non-manifold edges and vertices, isolated vertices, random seams,
    /// creases and corners) in every mode never panics and gives a well-formed channel:
    /// one value index per face corner, all in range, all values finite; a constant
    /// channel stays constant (the masks are affine combinations).
    #[test]
    fn face_varying_refines_random_triangle_soups() {
        use crate::mesh::{FaceVarying, FaceVaryingInterpolation as F};
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        let modes = [
            F::None,
            F::CornersOnly,
            F::CornersPlus1,
            F::CornersPlus2,
            F::Boundaries,
            F::All,
        ];
        let mut refined = 0;
        for case in 0..120 {
            let nv = 3 + next(6) as u32;
            let nf = 1 + next(8) as usize;
            let faces: Vec<[u32; 3]> = (0..nf)
                .map(|_| [0; 3].map(|_| next(nv as u64) as u32))
                .collect();
            let pos = (0..nv)
                .map(|i| [i as f64, (i * i % 7) as f64, next(5) as f64])
                .collect();
            let Ok(mut m) = PolyMesh::from_faces(pos, &faces) else {
                continue;
            };
            let nvals = 1 + next(2 * nv as u64) as u32;
            let indices = (0..3 * nf).map(|_| next(nvals as u64) as u32).collect();
            let values = (0..2 * nvals).map(|i| f64::from(i % 5) * 0.25).collect();
            let constant = vec![0.5; nv as usize];
            let by_vertex = m.face_verts().to_vec();
            m.face_varying = vec![
                FaceVarying::new("uv", 2, values, indices).unwrap(),
                FaceVarying::new("c", 1, constant, by_vertex).unwrap(),
            ];
            let edges: Vec<(u32, u32)> = faces.iter().map(|f| (f[0], f[1])).collect();
            m.tags.creases = edges
                .iter()
                .take(next(3) as usize)
                .map(|&(v0, v1)| Crease {
                    v0,
                    v1,
                    sharpness: [0.5, 1.7, 10.0][next(3) as usize],
                })
                .collect();
            m.tags.corners = vec![Corner {
                vertex: next(nv as u64) as u32,
                sharpness: 1.5,
            }];
            for mode in modes {
                let o = Options {
                    face_varying: mode,
                    crease_method: [CreaseMethod::Uniform, CreaseMethod::Chaikin][case % 2],
                    ..Options::default()
                };
                let Ok((out, _)) = subdivide_loop(&m, &o, 2, false) else {
                    continue;
                };
                refined += 1;
                for ch in &out.face_varying {
                    assert_eq!(ch.indices().len(), out.face_verts().len(), "case {case}");
                    assert!(ch.indices().iter().all(|&i| (i as usize) < ch.num_values()));
                    assert!(ch.values().iter().all(|x| x.is_finite()), "case {case}");
                }
                let c = &out.face_varying[1];
                assert!(
                    c.values().iter().all(|&x| (x - 0.5).abs() < 1e-15),
                    "case {case} {mode:?}: a constant channel changed"
                );
            }
        }
        assert!(refined > 300, "only {refined} refinements");
    }

    /// Bilinear: vertices stay, new points lie on the input's faces, sharpness changes
    /// nothing, and boundary mode `None` makes no holes (OpenSubdiv's rule for schemes
    /// without a neighbourhood).
    #[test]
    fn bilinear_refines_on_the_faces_and_ignores_sharpness() {
        let m = creased_grid();
        let plain = {
            let mut p = m.clone();
            p.tags = Tags::default();
            p
        };
        let none = Options {
            boundary: BoundaryInterpolation::None,
            ..Options::default()
        };
        let (a, _) = subdivide_bilinear(&m, &none, 2, false).unwrap();
        let (b, _) = subdivide_bilinear(&plain, &Options::default(), 2, false).unwrap();
        assert_eq!(a.positions(), b.positions());
        assert_eq!(a.num_faces(), 4 * m.face_verts().len());
        assert_eq!(&a.positions()[..m.num_vertices()], m.positions());
        // On a flat mesh every point stays on the plane.
        let mut flat = plain.clone();
        for p in flat.positions_mut() {
            p[2] = 2.0 * p[0] + p[1];
        }
        let (f, _) = subdivide_bilinear(&flat, &none, 3, false).unwrap();
        assert!(f
            .positions()
            .iter()
            .all(|p| (p[2] - 2.0 * p[0] - p[1]).abs() < 1e-12));
    }
}
