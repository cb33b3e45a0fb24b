//! [`Tessellation::evaluate_face_varying`]: face-varying data (texture coordinates) at the
//! corners of a tessellation.

use super::eval::Domain;
use super::face_varying::FaceVaryingSurface;
use super::surface::SurfacePoint;
use super::tessellate::{TessellateError, Tessellation};
use crate::mesh::{FaceVarying, PolyMesh, INVALID};

/// Points evaluated per call of [`FaceVaryingSurface::eval_many`].
const CHUNK: usize = 1 << 16;

/// Values at one output vertex within this fraction of the values' extent are one value.
const SAME_VALUE: f64 = 1e-9;

impl Tessellation {
    /// The limit of a face-varying channel (e.g. texture coordinates) at every corner of
    /// the tessellation, as a channel of its faces, named `name`: for output face `q`,
    /// corner `i` has value `indices[face_offsets[q] + i]` as in a
    /// [`PolyMesh`]'s channels, so that the tessellation can be
    /// written with texture coordinates (`write_tessellation` writes the channel named
    /// `"uv"`).
    ///
    /// `surface` is the channel's limit ([`FaceVaryingSurface`]) on `mesh`, the mesh the
    /// tessellation was sampled from by [`tessellate`](super::tessellate()). Each corner is
    /// evaluated in its own base face's parametrisation, once per output vertex and base
    /// face (within a face the channel is continuous). Across base faces a channel has
    /// seams, where faces give a vertex different values: the corners of one output vertex
    /// share a value when their values differ by at most 10⁻⁹ of the extent of all values
    /// (the larger of the components' ranges); the first corner's value is kept, so a
    /// shared value is bit-identical on both sides of an edge that is no seam. A vertex on
    /// a seam thus has one value per side, as the input has.
    ///
    /// # Errors
    /// [`TessellateError::NoCornerPoints`] for a tessellation without surface points (one
    /// sampled through refinement by [`nonuniform::tessellate`](crate::nonuniform::tessellate())),
    /// [`TessellateError::Layout`] when the tessellation does not follow `mesh`'s faces,
    /// [`TessellateError::Eval`] when `surface` cannot be evaluated at a corner (it was built
    /// from another mesh).
    pub fn evaluate_face_varying(
        &self,
        mesh: &PolyMesh,
        surface: &FaceVaryingSurface,
        name: &str,
    ) -> Result<FaceVarying, TessellateError> {
        let corners = self.corner_points(mesh, surface)?;
        // One evaluation per (output vertex, base face): `request[c]` for corner `c`.
        let mut last_face = vec![INVALID; self.num_vertices()];
        let mut last_request = vec![INVALID; self.num_vertices()];
        let mut request = Vec::with_capacity(corners.len());
        let mut points: Vec<SurfacePoint> = Vec::new();
        let mut owner: Vec<u32> = Vec::new();
        for (&v, p) in self.face_verts.iter().zip(&corners) {
            let v = v as usize;
            if last_face[v] != p.face {
                last_face[v] = p.face;
                last_request[v] = points.len() as u32;
                points.push(*p);
                owner.push(v as u32);
            }
            request.push(last_request[v]);
        }
        drop((last_face, last_request, corners));
        let dim = surface.dim();
        let mut values = Vec::with_capacity(points.len() * dim);
        for chunk in points.chunks(CHUNK) {
            let got = surface.eval_many(chunk).map_err(|source| {
                // The first point's error: find which one fails, for the message.
                let p = (chunk.iter())
                    .find(|&&p| surface.eval_point(p).is_err())
                    .unwrap_or(&chunk[0]);
                TessellateError::Eval {
                    face: p.face,
                    subface: p.subface,
                    u: p.u,
                    v: p.v,
                    source,
                }
            })?;
            values.extend_from_slice(&got.value);
        }
        let (values, merged) = merge_per_vertex(&values, dim, &owner, self.num_vertices());
        let indices = request.iter().map(|&r| merged[r as usize]).collect();
        Ok(FaceVarying::new_unchecked(
            name.to_string(),
            dim,
            values,
            indices,
        ))
    }

    /// Per face corner (in [`face_verts`](Self::face_verts) order), the point of the
    /// corner's own base face (and sub-face) it lies at, from the layout
    /// [`tessellate`](super::tessellate()) documents: faces in base face order, each
    /// sub-face's grid by rows of cells from `v = 0`, cells along `u`, a cell's quad
    /// `(a, b) (a + 1, b) (a + 1, b + 1) (a, b + 1)`, and with triangles each quad as two
    /// triangles (`0 1 2, 0 2 3` or `0 1 3, 1 2 3`, told apart by their first vertices);
    /// on a triangle domain of `surface`, the triangles of its triangular grid.
    fn corner_points(
        &self,
        mesh: &PolyMesh,
        surface: &FaceVaryingSurface,
    ) -> Result<Vec<SurfacePoint>, TessellateError> {
        if self.points.is_empty() && self.num_faces() > 0 {
            return Err(TessellateError::NoCornerPoints);
        }
        let r = self.rate;
        let mut out = Vec::with_capacity(self.face_verts.len());
        let mut q = 0;
        while q < self.num_faces() {
            let (f, j) = self.source[q];
            let n = if (f as usize) < mesh.num_faces() {
                mesh.face(f as usize).len()
            } else {
                0
            };
            let tri = surface.domain(f as usize) == Domain::Triangle;
            let s = if n == 4 || tri { r } else { r / 2 };
            let at = |a: u32, b: u32| SurfacePoint {
                face: f,
                subface: j,
                u: f64::from(a) / f64::from(s),
                v: f64::from(b) / f64::from(s),
            };
            let cells = (s as usize) * (s as usize);
            // Quads split into triangles come two per cell.
            let per_cell = if !tri && self.face(q).len() == 3 {
                2
            } else {
                1
            };
            let end = q + cells * per_cell;
            if n < 3 || end > self.num_faces() || self.source[q..end].iter().any(|&x| x != (f, j)) {
                return Err(TessellateError::Layout { face: q });
            }
            if tri {
                for b in 0..s {
                    for a in 0..s - b {
                        out.extend([at(a, b), at(a + 1, b), at(a, b + 1)]);
                        if a + 1 < s - b {
                            out.extend([at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)]);
                        }
                    }
                }
                q = end;
                continue;
            }
            let triangles = per_cell == 2;
            for c in 0..cells as u32 {
                let (a, b) = (c % s, c / s);
                let quad = [at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)];
                if triangles {
                    let k = q + 2 * c as usize;
                    let along02 = self.face(k)[0] == self.face(k + 1)[0];
                    let order = if along02 {
                        [0, 1, 2, 0, 2, 3]
                    } else {
                        [0, 1, 3, 1, 2, 3]
                    };
                    out.extend(order.map(|i| quad[i]));
                } else {
                    out.extend(quad);
                }
            }
            q = end;
        }
        if out.len() != self.face_verts.len() {
            return Err(TessellateError::Layout { face: 0 });
        }
        Ok(out)
    }
}

/// Merges the values of each vertex that lie within [`SAME_VALUE`] of the extent of all
/// values: `values` holds `dim` components per evaluation, `owner` the vertex of each.
/// Returns the distinct values and, per evaluation, its value's index.
fn merge_per_vertex(
    values: &[f64],
    dim: usize,
    owner: &[u32],
    num_vertices: usize,
) -> (Vec<f64>, Vec<u32>) {
    let extent = (0..dim)
        .map(|k| {
            let (lo, hi) = (values.iter().skip(k).step_by(dim))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                    (lo.min(x), hi.max(x))
                });
            hi - lo
        })
        .fold(0.0f64, f64::max);
    let tolerance = SAME_VALUE * extent;
    // Per vertex, the first of its distinct values, and per value the next of its vertex.
    let mut first = vec![INVALID; num_vertices];
    let mut next: Vec<u32> = Vec::new();
    let mut out = Vec::with_capacity(values.len());
    let mut index = Vec::with_capacity(owner.len());
    for (x, &v) in values.chunks_exact(dim).zip(owner) {
        let mut k = first[v as usize];
        let mut last = INVALID;
        while k != INVALID {
            let y = &out[k as usize * dim..][..dim];
            if x.iter()
                .zip(y)
                .all(|(a, b): (&f64, &f64)| (a - b).abs() <= tolerance)
            {
                break;
            }
            last = k;
            k = next[k as usize];
        }
        if k == INVALID {
            k = next.len() as u32;
            next.push(INVALID);
            out.extend_from_slice(x);
            if last == INVALID {
                first[v as usize] = k;
            } else {
                next[last as usize] = k;
            }
        }
        index.push(k);
    }
    (out, index)
}

#[cfg(test)]
mod tests {
    use super::super::tessellate::tessellate;
    use super::super::{LimitSurface, LoopSurface};
    use super::*;
    use crate::mesh::{FaceVaryingInterpolation, Options};

    /// A 3 × 3 grid of quads whose last quad is split into two triangles, not flat, with a
    /// channel of its positions: per face (`islands`) or per vertex, shifted by `+10` in
    /// `x` on the faces right of `x = 2` with `islands`.
    fn grid(islands: bool) -> PolyMesh {
        let mut p = Vec::new();
        for j in 0..4 {
            for i in 0..4 {
                p.push([i as f64, j as f64, 0.1 * ((i * j) % 3) as f64]);
            }
        }
        let v = |i: u32, j: u32| j * 4 + i;
        let mut faces: Vec<Vec<u32>> = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                faces.push(vec![v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        let last = faces.pop().unwrap_or_default();
        faces.push(vec![last[0], last[1], last[2]]);
        faces.push(vec![last[0], last[2], last[3]]);
        let mut m = PolyMesh::from_faces(p.clone(), &faces).unwrap();
        let (values, indices) = if islands {
            let mut values = Vec::new();
            for f in &faces {
                let right = f.iter().all(|&x| p[x as usize][0] >= 2.0);
                for &x in f {
                    let q = p[x as usize];
                    values.extend([q[0] + if right { 10.0 } else { 0.0 }, q[1], q[2]]);
                }
            }
            (values, (0..m.face_verts().len() as u32).collect())
        } else {
            (
                p.iter().flatten().copied().collect(),
                m.face_verts().to_vec(),
            )
        };
        m.face_varying
            .push(FaceVarying::new("data", 3, values, indices).unwrap());
        m
    }

    fn options(mode: FaceVaryingInterpolation) -> Options {
        Options {
            face_varying: mode,
            ..Options::default()
        }
    }

    /// A channel of the positions without seams in mode `none` is the limit surface
    /// itself: every corner's value is its vertex's position, and every vertex has one
    /// value. A corner evaluated at another point than its vertex would differ.
    #[test]
    fn a_channel_of_the_positions_is_the_tessellation() {
        let m = grid(false);
        let o = options(FaceVaryingInterpolation::None);
        let s = LimitSurface::new(&m, o).unwrap();
        let uv = FaceVaryingSurface::new(&m, o, 0).unwrap();
        for triangles in [false, true] {
            let t = tessellate(&s, &m, 4, triangles).unwrap();
            let ch = t.evaluate_face_varying(&m, &uv, "data").unwrap();
            assert_eq!(ch.num_values(), t.num_vertices());
            assert_eq!(ch.indices().len(), t.face_verts.len());
            for (&v, &k) in t.face_verts.iter().zip(ch.indices()) {
                let (p, x) = (t.positions[v as usize], ch.value(k as usize));
                assert!((0..3).all(|c| (p[c] - x[c]).abs() < 1e-12), "{p:?} {x:?}");
            }
        }
    }

    /// The same on triangle domains: a Loop channel of the positions is the Loop limit
    /// surface at every corner of its triangular grids.
    #[test]
    fn a_loop_channel_of_the_positions_is_the_tessellation() {
        let q = grid(false);
        let faces: Vec<[u32; 3]> = (q.faces())
            .flat_map(|f| match f.len() {
                4 => vec![[f[0], f[1], f[2]], [f[0], f[2], f[3]]],
                _ => vec![[f[0], f[1], f[2]]],
            })
            .collect();
        let mut m = PolyMesh::from_faces(q.positions().to_vec(), &faces).unwrap();
        let values = m.positions().iter().flatten().copied().collect();
        let indices = m.face_verts().to_vec();
        m.face_varying
            .push(FaceVarying::new("data", 3, values, indices).unwrap());
        let o = options(FaceVaryingInterpolation::None);
        let s = LoopSurface::new(&m, o).unwrap();
        let uv = FaceVaryingSurface::for_scheme(&m, crate::scheme::Scheme::Loop, o, 0).unwrap();
        let t = tessellate(&s, &m, 3, false).unwrap();
        let ch = t.evaluate_face_varying(&m, &uv, "data").unwrap();
        assert_eq!(ch.num_values(), t.num_vertices());
        for (&v, &k) in t.face_verts.iter().zip(ch.indices()) {
            let (p, x) = (t.positions[v as usize], ch.value(k as usize));
            assert!((0..3).all(|c| (p[c] - x[c]).abs() < 1e-12), "{p:?} {x:?}");
        }
    }

    /// A seam splits exactly the vertices on it: one value per side, the sides `10` apart.
    #[test]
    fn seams_give_a_value_per_side() {
        let m = grid(true);
        let o = options(FaceVaryingInterpolation::All);
        let s = LimitSurface::new(&m, o).unwrap();
        let uv = FaceVaryingSurface::new(&m, o, 0).unwrap();
        let rate = 4;
        let t = tessellate(&s, &m, rate, true).unwrap();
        let ch = t.evaluate_face_varying(&m, &uv, "data").unwrap();
        // The seam runs along x = 2 over three base edges: 3 × rate + 1 output vertices.
        assert_eq!(ch.num_values(), t.num_vertices() + 3 * rate as usize + 1);
        let mut per_vertex = vec![Vec::new(); t.num_vertices()];
        for (&v, &k) in t.face_verts.iter().zip(ch.indices()) {
            if !per_vertex[v as usize].contains(&k) {
                per_vertex[v as usize].push(k);
            }
        }
        for ks in per_vertex.iter().filter(|ks| ks.len() > 1) {
            assert_eq!(ks.len(), 2);
            let (a, b) = (ch.value(ks[0] as usize), ch.value(ks[1] as usize));
            assert!(((b[0] - a[0]).abs() - 10.0).abs() < 1e-12 && (b[1] - a[1]).abs() < 1e-12);
        }
    }

    #[test]
    fn foreign_tessellations_are_refused() {
        let m = grid(false);
        let o = Options::default();
        let s = LimitSurface::new(&m, o).unwrap();
        let uv = FaceVaryingSurface::new(&m, o, 0).unwrap();
        let mut t = tessellate(&s, &m, 2, false).unwrap();
        let points = std::mem::take(&mut t.points);
        let got = t.evaluate_face_varying(&m, &uv, "data");
        assert_eq!(got.unwrap_err(), TessellateError::NoCornerPoints);
        t.points = points;
        t.source.swap(0, 5);
        let got = t.evaluate_face_varying(&m, &uv, "data");
        assert!(
            matches!(got, Err(TessellateError::Layout { face: 0 })),
            "{got:?}"
        );
    }
}
