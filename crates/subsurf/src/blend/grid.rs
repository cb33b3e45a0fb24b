//! [`VertexGrid`]: a rectangular grid of mesh vertices (a regular part of a quad mesh),
//! carried through refinement, and the exact limit surface over it.
//!
//! # The limit on a regular part
//! Where every vertex of a quad grid is regular (valence 4, its four faces in the grid or
//! continuing it), one NURSS step is exactly midpoint knot insertion into the
//! tensor-product cubic B-spline whose control net is the grid and whose knot intervals are
//! the grid's edge intervals (Sederberg et al. 1998, §3; [JOS 2003]). So the limit
//! surface over such a grid *is* that B-spline — with the convention that the control
//! polygon edge `c_i c_{i+1}` carries the knot span `[t_{i+2}, t_{i+3}]` — and
//! [`VertexGrid::bspline`] evaluates it exactly by de Boor, including derivatives. Only the
//! spans whose 4×4 control blocks lie in the grid are meaningful; the knots outside the
//! grid are read from the grid's extra rows/columns beyond the requested range (or repeated
//! when there are none: those knots influence only spans that should not be evaluated).

use std::collections::HashMap;
use std::ops::Range;

use super::BlendError;
use crate::mesh::{PolyMesh, Topology};
use crate::nurbs::{BSplineSurface, KnotVector};

/// A `rows × cols` grid of vertex indices (`ids[r * cols + c]`), consecutive entries joined
/// by mesh edges and consecutive 2×2 blocks forming quads.
#[derive(Clone, Debug, PartialEq)]
pub struct VertexGrid {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Vertex indices, row by row.
    pub ids: Vec<u32>,
    /// The knots at the start of the first row edge and the first column edge (the knot
    /// `t_2` of [`bspline`](Self::bspline) over the whole grid): `(u, v)`.
    pub origin: (f64, f64),
}

fn grid_err(msg: String) -> BlendError {
    BlendError::Grid(msg)
}

impl VertexGrid {
    /// The vertex at row `r`, column `c`.
    pub fn at(&self, r: usize, c: usize) -> u32 {
        self.ids[r * self.cols + c]
    }

    /// The grid of child vertices after one Catmull-Clark-topology step of the mesh with
    /// `topology` (OpenSubdiv numbering: vertex `v` → `v`, face `f` → `V + f`, edge `e` →
    /// `V + F + e`): `(2 rows − 1) × (2 cols − 1)`.
    ///
    /// # Errors
    /// [`BlendError::Grid`] if two neighbours are not joined by an edge or a 2×2 block is not
    /// a face.
    pub fn refine(&self, topology: &Topology) -> Result<Self, BlendError> {
        let (nv, nf) = (topology.num_vertices() as u32, topology.num_faces() as u32);
        let edge = |a: u32, b: u32| -> Result<u32, BlendError> {
            topology
                .find_edge(a, b)
                .map(|e| nv + nf + e)
                .ok_or_else(|| grid_err(format!("vertices {a} and {b} are not joined by an edge")))
        };
        let face = |q: [u32; 4]| -> Result<u32, BlendError> {
            for &f in topology.vertex_faces(q[0] as usize) {
                let fv = topology.face_vertices(f as usize);
                if fv.len() == 4 && q.iter().all(|v| fv.contains(v)) {
                    return Ok(nv + f);
                }
            }
            Err(grid_err(format!("vertices {q:?} are not a quad face")))
        };
        let (rows, cols) = (2 * self.rows - 1, 2 * self.cols - 1);
        let mut ids = vec![0u32; rows * cols];
        for r in 0..rows {
            for c in 0..cols {
                let (i, j) = (r / 2, c / 2);
                ids[r * cols + c] = match (r % 2, c % 2) {
                    (0, 0) => self.at(i, j),
                    (0, _) => edge(self.at(i, j), self.at(i, j + 1))?,
                    (_, 0) => edge(self.at(i, j), self.at(i + 1, j))?,
                    _ => face([
                        self.at(i, j),
                        self.at(i, j + 1),
                        self.at(i + 1, j + 1),
                        self.at(i + 1, j),
                    ])?,
                };
            }
        }
        Ok(Self {
            rows,
            cols,
            ids,
            origin: self.origin,
        })
    }

    /// Maps the grid through a renumbering (`u32::MAX`: dropped) and trims leading and
    /// trailing rows and columns that were dropped entirely; `mesh` is the mesh the grid
    /// indexes before renumbering, whose intervals move the [`origin`](Self::origin) past
    /// the trimmed leading rows and columns.
    ///
    /// # Errors
    /// [`BlendError::Grid`] if a dropped vertex remains inside, or nothing remains.
    pub fn renumber(&self, new_index: &[u32], mesh: &PolyMesh) -> Result<Self, BlendError> {
        let map: Vec<u32> = self
            .ids
            .iter()
            .map(|&v| new_index.get(v as usize).copied().unwrap_or(u32::MAX))
            .collect();
        let dead_row =
            |r: usize, c0: usize, c1: usize| (c0..c1).all(|c| map[r * self.cols + c] == u32::MAX);
        let dead_col =
            |c: usize, r0: usize, r1: usize| (r0..r1).all(|r| map[r * self.cols + c] == u32::MAX);
        let (mut r0, mut r1, mut c0, mut c1) = (0, self.rows, 0, self.cols);
        loop {
            let before = (r0, r1, c0, c1);
            while r0 < r1 && dead_row(r0, c0, c1) {
                r0 += 1;
            }
            while r1 > r0 && dead_row(r1 - 1, c0, c1) {
                r1 -= 1;
            }
            while c0 < c1 && dead_col(c0, r0, r1) {
                c0 += 1;
            }
            while c1 > c0 && dead_col(c1 - 1, r0, r1) {
                c1 -= 1;
            }
            if before == (r0, r1, c0, c1) {
                break;
            }
        }
        if r1 - r0 < 2 || c1 - c0 < 2 {
            return Err(grid_err("the grid was dropped by skirt removal".into()));
        }
        let mut ids = Vec::with_capacity((r1 - r0) * (c1 - c0));
        for r in r0..r1 {
            for c in c0..c1 {
                let v = map[r * self.cols + c];
                if v == u32::MAX {
                    return Err(grid_err(format!(
                        "row {r}, column {c} was dropped inside the grid"
                    )));
                }
                ids.push(v);
            }
        }
        let iv = intervals(mesh);
        let d = |a: u32, b: u32| iv.get(&(a.min(b), a.max(b))).copied().unwrap_or(1.0);
        let du: f64 = (0..r0).map(|r| d(self.at(r, c0), self.at(r + 1, c0))).sum();
        let dv: f64 = (0..c0).map(|c| d(self.at(r0, c), self.at(r0, c + 1))).sum();
        Ok(Self {
            rows: r1 - r0,
            cols: c1 - c0,
            ids,
            origin: (self.origin.0 + du, self.origin.1 + dv),
        })
    }

    /// The tensor-product cubic B-spline over rows `rows` and columns `cols` of the grid,
    /// with positions from `mesh` and knots from its edge intervals (untagged edges: 1),
    /// placed by the grid's [`origin`](Self::origin).
    /// See the [module documentation](self) for when this is the exact limit surface.
    ///
    /// # Errors
    /// [`BlendError::Grid`] if the intervals along a direction differ between rows (or
    /// columns) by more than `1e-12` relative (not a tensor product), or the range has fewer
    /// than 4 rows or columns; [`BlendError::Nurbs`].
    pub fn bspline(
        &self,
        mesh: &PolyMesh,
        rows: Range<usize>,
        cols: Range<usize>,
    ) -> Result<BSplineSurface<3>, BlendError> {
        self.spline_of(mesh, rows, cols, |v| mesh.positions()[v as usize])
    }

    /// [`bspline`](Self::bspline) of the homogeneous points `(w x, w y, w z, w)`, with the
    /// weights of the mesh's [`crate::mesh::VertexWeight`] tags (untagged: 1): the exact
    /// limit of a rational mesh over the grid is its projection (see
    /// [`super::homogeneous`]).
    ///
    /// # Errors
    /// As [`bspline`](Self::bspline).
    pub fn homogeneous_bspline(
        &self,
        mesh: &PolyMesh,
        rows: Range<usize>,
        cols: Range<usize>,
    ) -> Result<BSplineSurface<4>, BlendError> {
        let w = super::homogeneous::mesh_weights(mesh);
        self.spline_of(mesh, rows, cols, |v| {
            super::homogeneous::weighted(mesh.positions()[v as usize], w[v as usize])
        })
    }

    /// The B-spline over `rows` × `cols` with knots from `mesh`'s intervals and the control
    /// point `point(v)` of each grid vertex `v`.
    fn spline_of<const D: usize>(
        &self,
        mesh: &PolyMesh,
        rows: Range<usize>,
        cols: Range<usize>,
        point: impl Fn(u32) -> [f64; D],
    ) -> Result<BSplineSurface<D>, BlendError> {
        if rows.len() < 4 || cols.len() < 4 || rows.end > self.rows || cols.end > self.cols {
            return Err(grid_err(format!(
                "a B-spline needs a range of at least 4×4 inside the {}×{} grid",
                self.rows, self.cols
            )));
        }
        let lookup = intervals(mesh);
        let iv = |a: u32, b: u32| lookup.get(&(a.min(b), a.max(b))).copied().unwrap_or(1.0);
        // Intervals between consecutive rows (read along every column of the range).
        let along = |n: usize, range: &Range<usize>, other: &Range<usize>, by_row: bool| {
            let mut out = Vec::new();
            let lo = range.start.saturating_sub(2);
            let hi = (range.end + 2).min(n);
            for k in lo..hi - 1 {
                let mut first = None;
                for o in other.clone() {
                    let (a, b) = if by_row {
                        (self.at(k, o), self.at(k + 1, o))
                    } else {
                        (self.at(o, k), self.at(o, k + 1))
                    };
                    let d = iv(a, b);
                    match first {
                        None => first = Some(d),
                        Some(f) if (f - d).abs() > 1e-12 * f.abs().max(d.abs()).max(1e-300) => {
                            return Err(grid_err(format!(
                                "intervals {f} and {d} across the same grid line differ: not a tensor product"
                            )))
                        }
                        _ => {}
                    }
                }
                out.push((k, first.unwrap_or(1.0)));
            }
            // Knot intervals: two before the range, the range's edges, two after.
            let get = |k: isize| -> Option<f64> {
                out.iter()
                    .find(|(kk, _)| *kk as isize == k)
                    .map(|&(_, d)| d)
            };
            let (s, e) = (range.start as isize, range.end as isize);
            let mut d = Vec::new();
            let first_in = get(s).unwrap_or(1.0);
            let before1 = get(s - 1).unwrap_or(first_in);
            let before2 = get(s - 2).unwrap_or(before1);
            let last_in = get(e - 2).unwrap_or(1.0);
            let after1 = get(e - 1).unwrap_or(last_in);
            let after2 = get(e).unwrap_or(after1);
            d.push(before2);
            d.push(before1);
            for k in s..e - 1 {
                d.push(get(k).unwrap_or(1.0));
            }
            d.push(after1);
            d.push(after2);
            Ok(d)
        };
        let du = along(self.rows, &rows, &cols, true)?;
        let dv = along(self.cols, &cols, &rows, false)?;
        let knots = |d: &[f64], anchor: f64| -> Result<KnotVector, BlendError> {
            let mut t = vec![anchor - d[1] - d[0], anchor - d[1], anchor];
            for &x in &d[2..] {
                let last = t[t.len() - 1];
                t.push(last + x);
            }
            Ok(KnotVector::new(3, t)?)
        };
        let before_u: f64 = (0..rows.start)
            .map(|r| iv(self.at(r, cols.start), self.at(r + 1, cols.start)))
            .sum();
        let before_v: f64 = (0..cols.start)
            .map(|c| iv(self.at(rows.start, c), self.at(rows.start, c + 1)))
            .sum();
        let ku = knots(&du, self.origin.0 + before_u)?;
        let kv = knots(&dv, self.origin.1 + before_v)?;
        let mut points = Vec::with_capacity(rows.len() * cols.len());
        for r in rows.clone() {
            for c in cols.clone() {
                points.push(point(self.at(r, c)));
            }
        }
        Ok(BSplineSurface::new(ku, kv, points)?)
    }
}

/// Edge intervals of `mesh` by sorted vertex pair.
pub(crate) fn intervals(mesh: &PolyMesh) -> HashMap<(u32, u32), f64> {
    mesh.knots
        .intervals
        .iter()
        .map(|t| ((t.v0.min(t.v1), t.v0.max(t.v1)), t.interval))
        .collect()
}

/// A quad grid mesh: `rows × cols` points (`points[r * cols + c]`), the interval of the
/// edges between rows `r` and `r + 1` is `du[r]`, between columns `c` and `c + 1` is
/// `dv[c]`, and the grid's origin is `(0, 0)`. Faces are oriented `(r, c) → (r + 1, c) → (r + 1, c + 1) → (r, c + 1)` (normal
/// `∂/∂u × ∂/∂v` when rows run along `u`). Returns the mesh and its `VertexGrid`.
///
/// # Errors
/// [`BlendError::Mesh`] for non-finite points; [`BlendError::Grid`] for wrong lengths.
pub fn grid_mesh(
    rows: usize,
    cols: usize,
    points: Vec<[f64; 3]>,
    du: &[f64],
    dv: &[f64],
) -> Result<(PolyMesh, VertexGrid), BlendError> {
    if rows < 2
        || cols < 2
        || points.len() != rows * cols
        || du.len() + 1 != rows
        || dv.len() + 1 != cols
    {
        return Err(grid_err("grid sizes do not match".into()));
    }
    let id = |r: usize, c: usize| (r * cols + c) as u32;
    let mut faces = Vec::new();
    for r in 0..rows - 1 {
        for c in 0..cols - 1 {
            faces.push([id(r, c), id(r + 1, c), id(r + 1, c + 1), id(r, c + 1)]);
        }
    }
    let mut mesh = PolyMesh::from_faces(points, &faces)?;
    for r in 0..rows {
        for c in 0..cols {
            if r + 1 < rows {
                push_interval(&mut mesh, id(r, c), id(r + 1, c), du[r]);
            }
            if c + 1 < cols {
                push_interval(&mut mesh, id(r, c), id(r, c + 1), dv[c]);
            }
        }
    }
    let grid = VertexGrid {
        rows,
        cols,
        ids: (0..(rows * cols) as u32).collect(),
        origin: (0.0, 0.0),
    };
    Ok((mesh, grid))
}

/// Tags edge `a`–`b` with `interval` unless it is the default 1.
pub(crate) fn push_interval(mesh: &mut PolyMesh, a: u32, b: u32, interval: f64) {
    if interval != 1.0 {
        mesh.knots.intervals.push(crate::mesh::EdgeInterval {
            v0: a,
            v1: b,
            interval,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blend::skirt::{nurss_refine_once, refine_with_skirt};

    #[test]
    fn nurss_on_a_regular_grid_is_the_b_spline_of_the_refined_grid() {
        // A 7×7 grid with non-uniform intervals: after two skirt steps the B-spline of the
        // tracked real grid equals the B-spline of the initial real grid (knot insertion).
        let du = [0.5, 1.0, 2.0, 0.7, 1.3, 0.4];
        let dv = [1.0, 0.3, 1.1, 2.0, 0.6, 0.9];
        let mut pts = Vec::new();
        for r in 0..7 {
            for c in 0..7 {
                let (x, y) = (r as f64, c as f64);
                pts.push([x, y, (0.3 * x).sin() * (0.5 * y).cos() + 0.1 * x * y]);
            }
        }
        let (mesh, grid) = grid_mesh(7, 7, pts, &du, &dv).unwrap();
        let before = grid.bspline(&mesh, 0..7, 0..7).unwrap();
        let mut grids = [grid];
        let out = refine_with_skirt(&mesh, 2, &mut grids, nurss_refine_once).unwrap();
        let g = &grids[0];
        // Each step drops the outer ring; the grid's origin follows the trimmed rows.
        assert_eq!((g.rows, g.cols), (13, 13));
        assert_eq!(g.origin, (du[0] + du[1] / 2.0, dv[0] + dv[1] / 2.0));
        let after = g.bspline(&out, 0..g.rows, 0..g.cols).unwrap();
        let cum = |d: &[f64], k: usize| d[..k].iter().sum::<f64>();
        let (u0, u1, v0, v1) = (cum(&du, 2), cum(&du, 4), cum(&dv, 2), cum(&dv, 4));
        for i in 0..=8 {
            for j in 0..=8 {
                let u = u0 + (u1 - u0) * i as f64 / 8.0;
                let v = v0 + (v1 - v0) * j as f64 / 8.0;
                let (a, b) = (
                    before.eval_second(u, v).unwrap(),
                    after.eval_second(u, v).unwrap(),
                );
                for (x, y) in [
                    (a.p, b.p),
                    (a.du, b.du),
                    (a.dv, b.dv),
                    (a.duu, b.duu),
                    (a.duv, b.duv),
                ] {
                    for k in 0..3 {
                        assert!((x[k] - y[k]).abs() < 1e-10, "{u} {v}: {x:?} vs {y:?}");
                    }
                }
            }
        }
    }
}
