//! C2 blending of N bicubic B-spline patches with NURSS and skirt removal ([Jiang et al.] §3.1).
//!
//! # Input
//! N ≥ 2 open bicubic patches `P_k` (control nets `b^k_{i,j}`, `i = 0..=m_k` along `u`,
//! `j = 0..=n_k` along `v`, at least 4×4, any non-uniform knots `U_k`, `V_k`), listed in
//! order around the region to be blended. Each patch is blended along its first-row
//! boundary `u = u_3` (the row `i = 0` side); going around the region, the end `j = n_k` of
//! patch `k` faces the start `j = 0` of patch `k + 1` (and the last patch's end faces the
//! first patch's start), so all patches run the same way around the region.
//!
//! # The blend control mesh
//! A *band* of quads around the region: for each patch a strip of five rows
//! `r = −1..=3` over its columns — rows 0, 1, 2 are the patch's first three rows (shared),
//! row 3 its fourth row (the extension layer, only its intervals matter) and row −1 new
//! points `2 b_{0,j} − b_{1,j}` — followed by one *gap* column of new points (the mean of
//! the two facing end columns) joining it to the next strip. The band's inner row −1 bounds
//! the middle, which is filled by a fan of quads around a centre point (the mean of row
//! −1), or by one polygon when the fan does not fit (an odd count, or four points).
//!
//! Knot intervals, with knots indexed from 0 (`u_0 … u_{m+4}`): the control-polygon edge
//! `b_i b_{i+1}` carries the span `[u_{i+2}, u_{i+3}]`. So the strip's edges between rows
//! `r` and `r + 1` carry `u_{r+3} − u_{r+2}` (row −1 to 0: `u_2 − u_1`, the paper's `e_0`;
//! row 2 to 3: `u_5 − u_4`, the extension interval), the edges between columns `j` and
//! `j + 1` carry `v_{j+3} − v_{j+2}`, and the gap edges carry the intervals beyond the
//! patch's end columns: `v_{n+3} − v_{n+2}` next to column `n` of patch `k`, `v_2 − v_1`
//! next to column 0 of patch `k + 1` (the paper's `d_s` and `d_0`). The gap's own cross
//! edges take the mean of the two strips' intervals; the fan's spokes the mean ring
//! interval.
//!
//! # Why the result is C2
//! Position, first and second `u`-derivatives of `P_k` on `u = u_3` depend only on rows
//! 0, 1, 2 and the knots `u_1 … u_5` (the basis functions `N_0 … N_2` at `u_3`; `N_3`
//! vanishes there to second order), and along `v ∈ [v_3, v_{n+1}]` on the knots
//! `v_1 … v_{n+3}`. The blend mesh holds exactly those rows and intervals on a regular grid,
//! where NURSS is knot insertion, and skirt removal makes the real part's limit end on
//! `u = u_3` (the last span whose four rows are real is `[u_2, u_3]`). The limit next to
//! `P_k` is therefore the B-spline with `P_k`'s knots on rows `−1 … 2`, which joins `P_k`
//! C2. [`Blend::boundary_spline`] evaluates it exactly from the refined mesh (see
//! [`super::grid`]); the tests compare position, first and second derivatives with `P_k`.

use std::borrow::Cow;

use super::grid::{push_interval, VertexGrid};
use super::homogeneous::{cart, mean, weighted_mesh, Patch};
use super::patch::check_bicubic;
use super::skirt::{merge_degenerate, nurss_refine_once, real_part, refine_with_skirt};
use super::BlendError;
use crate::mesh::PolyMesh;
use crate::nurbs::{BSplineSurface, Surface};

/// Most patches [`blend_control_mesh`] takes.
pub(crate) const MAX_PATCHES: usize = 64;

/// The blend control mesh with the vertex grids next to each patch.
#[derive(Clone, Debug, PartialEq)]
pub struct BlendMesh {
    /// The control mesh with knot intervals; its outer ring (the strips' rows 2–3) is the
    /// extension layer.
    pub mesh: PolyMesh,
    /// Per patch: its strip as a grid, rows `−1..=3` (5 rows) and columns: the gap before
    /// it, its columns `0..=n`, the gap after it; origin `(u_1, v_1)`.
    pub strips: Vec<VertexGrid>,
}

/// The vertex layout of the band: strip `k`, row `r + 1`, column `j` and gap columns.
struct Layout {
    strip_start: Vec<u32>,
    gap_start: Vec<u32>,
    cols: Vec<usize>,
}

impl Layout {
    fn strip(&self, k: usize, r: usize, j: usize) -> u32 {
        self.strip_start[k] + (r * self.cols[k] + j) as u32
    }
    fn gap(&self, k: usize, r: usize) -> u32 {
        self.gap_start[k] + r as u32
    }
}

/// Builds the blend control mesh of `patches` (see the module documentation):
/// polynomial patches, or rational ones refined in homogeneous coordinates (see
/// `super::homogeneous`: rows 0 to 3 keep the patch's points and weights, the phantom row
/// and the gap columns get the mean weight of the points they are made from).
///
/// # Errors
/// [`BlendError::Count`] for fewer than 2 (or more than `MAX_PATCHES`) patches;
/// [`BlendError::Degree`], [`BlendError::Unsupported`], [`BlendError::TooSmall`] naming the
/// patch; [`BlendError::Mesh`] for non-finite points.
pub fn blend_control_mesh<P: Patch>(patches: &[P]) -> Result<BlendMesh, BlendError> {
    let n = patches.len();
    if !(2..=MAX_PATCHES).contains(&n) {
        return Err(BlendError::Count {
            what: "patches to blend",
            found: n,
            min: 2,
            max: MAX_PATCHES,
        });
    }
    let patches: Vec<Cow<'_, BSplineSurface<4>>> = patches.iter().map(Patch::homogeneous).collect();
    for (k, s) in patches.iter().enumerate() {
        check_bicubic(s, k)?;
        let (rows, columns) = s.size();
        if rows < 4 || columns < 4 {
            return Err(BlendError::TooSmall {
                index: k,
                rows,
                columns,
            });
        }
    }
    let (mut pos, mut weight, lay) = band_points(&patches);
    let band = Band::new(&patches, &lay);
    let m = band.columns.len();
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for c in 0..m {
        let (a, b) = (&band.columns[c], &band.columns[(c + 1) % m]);
        for r in 0..4 {
            faces.push(vec![a[r], a[r + 1], b[r + 1], b[r]]);
        }
    }
    let spoke = fill_middle(&band, &mut pos, &mut weight, &mut faces);
    let mut mesh = weighted_mesh(pos, &weight, &faces)?;
    band.set_intervals(&mut mesh, spoke);
    let strips = strip_grids(&patches, &lay);
    Ok(BlendMesh { mesh, strips })
}

/// The band's points and weights ([Jiang et al.] §3.1; see the module documentation): per
/// patch its strip, rows
/// `−1..=3` (row −1 `2 b_{0,j} − b_{1,j}` with the mean weight of the two), then one gap
/// column per patch (the mean of the two facing end columns); with their layout.
fn band_points(patches: &[Cow<'_, BSplineSurface<4>>]) -> (Vec<[f64; 3]>, Vec<f64>, Layout) {
    let n = patches.len();
    let mut pos: Vec<[f64; 3]> = Vec::new();
    let mut weight: Vec<f64> = Vec::new();
    let mut strip_start = Vec::with_capacity(n);
    let mut cols = Vec::with_capacity(n);
    for s in patches {
        let (_, nv) = s.size();
        strip_start.push(pos.len() as u32);
        cols.push(nv);
        let p = |i: usize, j: usize| s.points()[i * nv + j];
        for r in 0..5 {
            for j in 0..nv {
                if r == 0 {
                    let (a, b) = (p(0, j), p(1, j));
                    let (ca, cb) = (cart(&a), cart(&b));
                    pos.push([
                        2.0 * ca[0] - cb[0],
                        2.0 * ca[1] - cb[1],
                        2.0 * ca[2] - cb[2],
                    ]);
                    weight.push(mean([a[3], b[3]]));
                } else {
                    pos.push(cart(&p(r - 1, j)));
                    weight.push(p(r - 1, j)[3]);
                }
            }
        }
    }
    let mut gap_start = Vec::with_capacity(n);
    for k in 0..n {
        gap_start.push(pos.len() as u32);
        let next = (k + 1) % n;
        for r in 0..5 {
            let ia = (strip_start[k] as usize) + r * cols[k] + cols[k] - 1;
            let ib = (strip_start[next] as usize) + r * cols[next];
            let (a, b) = (pos[ia], pos[ib]);
            pos.push([
                0.5 * (a[0] + b[0]),
                0.5 * (a[1] + b[1]),
                0.5 * (a[2] + b[2]),
            ]);
            weight.push(mean([weight[ia], weight[ib]]));
        }
    }
    let lay = Layout {
        strip_start,
        gap_start,
        cols,
    };
    (pos, weight, lay)
}

/// The band's columns in order around the region, with their knot intervals.
struct Band {
    /// Vertices of each column, rows `−1..=3`.
    columns: Vec<[u32; 5]>,
    /// Per column: the interval of the edges to the next column.
    next_interval: Vec<f64>,
    /// Per column: the intervals of its four cross edges (rows r → r + 1).
    cross: Vec<[f64; 4]>,
}

impl Band {
    /// The columns of every strip and gap, with the intervals of the module documentation
    /// ([Jiang et al.] §3.1, the paper's `e_0`, `d_s`, `d_0`):
    /// `v_{j+3} − v_{j+2}` along a strip, `v_{n+3} − v_{n+2}` and `v_2 − v_1` on the edges
    /// to and from a gap, `u_{r+3} − u_{r+2}` across a strip and the mean of the two strips'
    /// across a gap.
    fn new(patches: &[Cow<'_, BSplineSurface<4>>], lay: &Layout) -> Self {
        let n = patches.len();
        let mut band: Vec<[u32; 5]> = Vec::new();
        let mut next_interval: Vec<f64> = Vec::new();
        let mut cross: Vec<[f64; 4]> = Vec::new();
        let u_spans = |s: &BSplineSurface<4>| {
            let t = s.knots_u().as_slice();
            [t[2] - t[1], t[3] - t[2], t[4] - t[3], t[5] - t[4]]
        };
        for k in 0..n {
            let s = &patches[k];
            let nxt = &patches[(k + 1) % n];
            let v = s.knots_v().as_slice();
            let nv = lay.cols[k];
            for j in 0..nv {
                band.push(std::array::from_fn(|r| lay.strip(k, r, j)));
                next_interval.push(if j + 1 < nv {
                    v[j + 3] - v[j + 2]
                } else {
                    v[nv + 2] - v[nv + 1]
                });
                cross.push(u_spans(s));
            }
            band.push(std::array::from_fn(|r| lay.gap(k, r)));
            let vn = nxt.knots_v().as_slice();
            next_interval.push(vn[2] - vn[1]);
            let (a, b) = (u_spans(s), u_spans(nxt));
            cross.push(std::array::from_fn(|r| 0.5 * (a[r] + b[r])));
        }
        Self {
            columns: band,
            next_interval,
            cross,
        }
    }

    /// Tags the band's intervals on `mesh`, and on the fan's `spoke` edges the mean positive
    /// interval along the band (1 when there is none).
    fn set_intervals(&self, mesh: &mut PolyMesh, spoke: Vec<(u32, u32)>) {
        let (band, m) = (&self.columns, self.columns.len());
        for c in 0..m {
            let (a, b) = (&band[c], &band[(c + 1) % m]);
            for r in 0..5 {
                push_interval(mesh, a[r], b[r], self.next_interval[c]);
            }
            for r in 0..4 {
                push_interval(mesh, a[r], a[r + 1], self.cross[c][r]);
            }
        }
        let positive: Vec<f64> = self
            .next_interval
            .iter()
            .copied()
            .filter(|&d| d > 0.0)
            .collect();
        let spoke_interval = if positive.is_empty() {
            1.0
        } else {
            positive.iter().sum::<f64>() / positive.len() as f64
        };
        for (a, b) in spoke {
            push_interval(mesh, a, b, spoke_interval);
        }
    }
}

/// Fills the middle bounded by the band's row −1: a fan of quads around the mean of the row
/// (an even count of more than 4 columns; its spokes are returned), else one polygon.
fn fill_middle(
    band: &Band,
    pos: &mut Vec<[f64; 3]>,
    weight: &mut Vec<f64>,
    faces: &mut Vec<Vec<u32>>,
) -> Vec<(u32, u32)> {
    let m = band.columns.len();
    let ring: Vec<u32> = band.columns.iter().map(|col| col[0]).collect();
    let mut spoke = Vec::new();
    if m.is_multiple_of(2) && m > 4 {
        let c = pos.len() as u32;
        let mut centre = [0.0; 3];
        for &w in &ring {
            for k in 0..3 {
                centre[k] += pos[w as usize][k] / m as f64;
            }
        }
        pos.push(centre);
        weight.push(mean(ring.iter().map(|&w| weight[w as usize])));
        for i in (0..m).step_by(2) {
            faces.push(vec![c, ring[i], ring[i + 1], ring[(i + 2) % m]]);
            spoke.push((c, ring[i]));
        }
    } else {
        faces.push(ring.clone());
    }
    spoke
}

/// Per patch: its strip as a grid (rows `−1..=3`; columns the gap before, its own, the gap
/// after), with origin `(u_1, v_1)`.
fn strip_grids(patches: &[Cow<'_, BSplineSurface<4>>], lay: &Layout) -> Vec<VertexGrid> {
    let n = patches.len();
    (0..n)
        .map(|k| {
            let nv = lay.cols[k];
            let before = lay.gap((k + n - 1) % n, 0);
            let cols = nv + 2;
            let mut ids = Vec::with_capacity(5 * cols);
            for r in 0..5 {
                ids.push(before + r as u32);
                for j in 0..nv {
                    ids.push(lay.strip(k, r, j));
                }
                ids.push(lay.gap(k, r));
            }
            VertexGrid {
                rows: 5,
                cols,
                ids,
                origin: (
                    patches[k].knots_u().as_slice()[1],
                    patches[k].knots_v().as_slice()[1],
                ),
            }
        })
        .collect()
}

/// A refined blend.
#[derive(Clone, Debug, PartialEq)]
pub struct Blend {
    /// The initial blend control mesh.
    pub control: BlendMesh,
    /// Number of skirt-removal steps taken.
    pub levels: u32,
    /// The refined mesh, extension layer included.
    pub refined: PolyMesh,
    /// The strips' grids in the refined mesh (rows from the child of row −1 to the
    /// extension row, columns from the gap before to the gap after).
    pub strips: Vec<VertexGrid>,
}

impl Blend {
    /// The blend surface: the real part of the refined mesh (its control points), with
    /// the vertices that zero knot intervals make coincide merged
    /// (`super::skirt::merge_degenerate`: no face of zero area).
    ///
    /// # Errors
    /// None in practice ([`BlendError::Holes`]).
    pub fn surface(&self) -> Result<PolyMesh, BlendError> {
        merge_degenerate(&real_part(&self.refined)?)
    }

    /// The exact limit of the blend next to patch `k`, as a bicubic B-spline in the patch's
    /// own parameters: its domain ends at `u = u_3` (the shared boundary) and covers
    /// `v ∈ [v_3, v_{n+1}]`. It is the B-spline of the refined strip's real rows and the
    /// columns from the child of column 0 to the child of column `n`, with the refined
    /// intervals (see `super::grid`); position, `∂/∂u` and `∂²/∂u²` on `u = u_3` equal the
    /// patch's (C2). For rational patches this is the Cartesian part of the homogeneous
    /// limit; use [`boundary_surface`](Self::boundary_surface).
    ///
    /// # Errors
    /// [`BlendError::Grid`] if `k` is out of range or the grid is not a tensor product.
    pub fn boundary_spline(&self, k: usize) -> Result<BSplineSurface<3>, BlendError> {
        let (g, rows, cols) = self.strip_range(k)?;
        g.bspline(&self.refined, rows, cols)
    }

    /// [`boundary_spline`](Self::boundary_spline) for polynomial or rational patches: the
    /// exact limit next to patch `k` as the projection of the homogeneous B-spline of the
    /// refined strip (a [`Surface::Nurbs`] when some weight is not 1), which joins a NURBS
    /// patch C2 (see `super::homogeneous`).
    ///
    /// # Errors
    /// As [`boundary_spline`](Self::boundary_spline).
    pub fn boundary_surface(&self, k: usize) -> Result<Surface, BlendError> {
        let (g, rows, cols) = self.strip_range(k)?;
        super::homogeneous::surface_of(g.homogeneous_bspline(&self.refined, rows, cols)?)
    }

    /// Strip `k`'s grid and the rows and columns of its limit next to the patch.
    fn strip_range(
        &self,
        k: usize,
    ) -> Result<(&VertexGrid, std::ops::Range<usize>, std::ops::Range<usize>), BlendError> {
        let g = self
            .strips
            .get(k)
            .ok_or_else(|| BlendError::Grid(format!("no patch {k}")))?;
        let step = 1usize << self.levels;
        Ok((g, 0..g.rows - 1, step..g.cols - step))
    }
}

/// Blends `patches` C2 (polynomial [`BSplineSurface<3>`], rational [`crate::nurbs::NurbsSurface`] or
/// either, [`Surface`]): builds [`blend_control_mesh`] and refines it `levels` times with
/// NURSS and skirt removal (the paper shows 6 levels).
///
/// # Errors
/// As [`blend_control_mesh`]; NURSS errors.
pub fn blend<P: Patch>(patches: &[P], levels: u32) -> Result<Blend, BlendError> {
    let control = blend_control_mesh(patches)?;
    let mut strips = control.strips.clone();
    let refined = refine_with_skirt(&control.mesh, levels, &mut strips, nurss_refine_once)?;
    Ok(Blend {
        control,
        levels,
        refined,
        strips,
    })
}
