//! Corner (end) interpolation with zero intervals ([Jiang et al.] §3.2): a clamped bicubic
//! B-spline patch as a NURSS control mesh whose skirt-removal limit is the patch itself,
//! boundary curves and corners included.
//!
//! The control net `b_{i,j}` (`i = 0..=m` along `u`, `j = 0..=n` along `v`) of a patch with
//! clamped knots `u_0 = … = u_3`, `u_{m+1} = … = u_{m+4}` gets the intervals of its knot
//! spans: the edge `b_{i,j} b_{i+1,j}` carries `u_{i+3} − u_{i+2}` (so the first and last
//! intervals of every column are 0), likewise along `v`. One extension layer (phantom
//! points `2 b_0 − b_1`) carries the intervals beyond the net, `u_2 − u_1 = 0`. Then each
//! skirt-removal step is midpoint knot insertion into the clamped spline: the new outer
//! real row is the refined control polygon of the boundary curve (its cross edges keep
//! interval 0 and its extension edges too), so the limit interpolates the boundary curves
//! and the corners. The degenerate NURSS rules (all-zero weights) only ever make points of
//! the extension layer, which skirt removal drops.

use super::grid::{grid_mesh, VertexGrid};
use super::homogeneous::{cart, mean, Patch};
use super::BlendError;
use crate::mesh::{PolyMesh, VertexWeight};
use crate::nurbs::{BSplineSurface, KnotVector};

/// A control mesh with an extension layer and the grid of its vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct GridControlMesh {
    /// The mesh with knot intervals; its outer ring is the extension layer.
    pub mesh: PolyMesh,
    /// All vertices as a grid, extension layer included (`(m + 3) × (n + 3)`), with origin
    /// `(u_1, v_1)` (the knots at the start of its first edges).
    pub grid: VertexGrid,
}

/// Whether `k` (cubic) has end knots of multiplicity 4.
pub(crate) fn is_clamped(k: &KnotVector) -> bool {
    let t = k.as_slice();
    t.len() >= 8 && t[0] == t[3] && t[t.len() - 1] == t[t.len() - 4]
}

/// Checks that `s` is an open, bicubic patch; `index` names it in errors.
pub(crate) fn check_bicubic<const D: usize>(
    s: &BSplineSurface<D>,
    index: usize,
) -> Result<(), BlendError> {
    let (p, q) = s.degrees();
    if p != 3 || q != 3 {
        return Err(BlendError::Degree {
            what: "patch",
            index,
            degree: p.max(q),
        });
    }
    let (cu, cv) = s.is_closed();
    if cu || cv {
        return Err(BlendError::Unsupported {
            what: "patch",
            index,
            kind: "closed",
        });
    }
    Ok(())
}

/// The corner-interpolating control mesh of a clamped bicubic patch (see the
/// module documentation), polynomial or rational: a NURBS patch's net keeps its
/// weights (the phantom points get the mean weight of the two points they reflect), and
/// NURSS refines it in homogeneous coordinates, so the limit is the NURBS patch (see
/// `super::homogeneous`).
///
/// # Errors
/// [`BlendError::Degree`], [`BlendError::Unsupported`] (closed), [`BlendError::NotClamped`].
pub fn corner_interpolating_mesh<P: Patch>(patch: &P) -> Result<GridControlMesh, BlendError> {
    let s = patch.homogeneous();
    check_bicubic(&s, 0)?;
    for (k, direction) in [(s.knots_u(), "u"), (s.knots_v(), "v")] {
        if !is_clamped(k) {
            return Err(BlendError::NotClamped {
                index: 0,
                direction,
            });
        }
    }
    let (nu, nv) = s.size();
    let at = |i: isize, j: isize| -> ([f64; 3], f64) {
        // Phantom points by reflection: 2 b_0 − b_1 beyond each end.
        let fold = |k: isize, n: usize| -> (usize, usize, bool) {
            if k < 0 {
                (0, 1, true)
            } else if k >= n as isize {
                (n - 1, n - 2, true)
            } else {
                (k as usize, k as usize, false)
            }
        };
        let (i0, i1, ri) = fold(i, nu);
        let (j0, j1, rj) = fold(j, nv);
        let p = |a: usize, b: usize| cart(&s.points()[a * nv + b]);
        let w = |a: usize, b: usize| s.points()[a * nv + b][3];
        let mut out = [0.0; 3];
        for k in 0..3 {
            let row = |jj: usize| {
                if ri {
                    2.0 * p(i0, jj)[k] - p(i1, jj)[k]
                } else {
                    p(i0, jj)[k]
                }
            };
            out[k] = if rj { 2.0 * row(j0) - row(j1) } else { row(j0) };
        }
        let weight = if ri || rj {
            mean([w(i0, j0), w(i1, j0), w(i0, j1), w(i1, j1)])
        } else {
            w(i0, j0)
        };
        (out, weight)
    };
    let (rows, cols) = (nu + 2, nv + 2);
    let mut points = Vec::with_capacity(rows * cols);
    let mut weights = Vec::with_capacity(rows * cols);
    for r in 0..rows as isize {
        for c in 0..cols as isize {
            let (p, w) = at(r - 1, c - 1);
            points.push(p);
            weights.push(w);
        }
    }
    // Grid edge k joins net indices k − 1 and k: the knot span [t_{k+1}, t_{k+2}].
    let spans =
        |t: &[f64], n: usize| -> Vec<f64> { (0..n + 1).map(|k| t[k + 2] - t[k + 1]).collect() };
    let du = spans(s.knots_u().as_slice(), nu);
    let dv = spans(s.knots_v().as_slice(), nv);
    let (mut mesh, mut grid) = grid_mesh(rows, cols, points, &du, &dv)?;
    mesh.knots.weights = VertexWeight::tags(&weights);
    grid.origin = (s.knots_u().as_slice()[1], s.knots_v().as_slice()[1]);
    Ok(GridControlMesh { mesh, grid })
}
