//! Subdivision surfaces that interpolate cubic B-spline and NURBS curves ([JOS 2003]: "symmetric
//! zonal meshes"; non-uniform Catmull-Clark, [`crate::nonuniform`], does the refinement).
//!
//! Around the control polygon of each curve (the *middle polygon*) a strip of quads is built,
//! two per polygon edge, whose side points are placed symmetrically about the polygon
//! (`P_i ± o_i`) and whose edges carry the knot intervals of Theorem 1 (see `zone`). NURSS
//! then refines the middle polygon exactly as midpoint knot insertion refines the curve, so the
//! limit surface passes through the curve: for any knot vector (non-uniform, multiple knots
//! for C1 and C0 points, clamped or not, closed), and for rational curves (weights on the
//! middle polygon, side points weighted like their middle point — a circle stays a circle).
//! Up to four curves may share a control point, passing through it or ending there (joint
//! polygon groups, `crossing`): opposite branches join `G2`, adjacent ones `G0`
//! (Corollary 1); two ends meeting nearly opposite share one zone. The zones may also be inserted into a host mesh whose edges contain the
//! control polygons (`host`, the paper's Fig. 11).
//!
//! | module | concept |
//! |---|---|
//! | `curve` | the curve's middle polygon: which interval on which edge, phantom end points |
//! | `frame` | side directions: rotation-minimising frame or a given side vector |
//! | `crossing` | shared control points, the checks a joint polygon group needs |
//! | `zone` | the symmetric zonal mesh, its intervals and weights; why the boundary needs no skirt removal |
//! | `host` | zones cut into a host mesh along its edges; the auxiliary intervals of Fig. 11 |
//! | `track` | the middle polygon at any refinement level |
//!
//! Source: [JOS 2003] (docs/references.md), "Subdivision surfaces interpolating cubic NURBS
//! curves" (Chinese, with English abstract), §2–3, Lemma 1, Theorem 1, Corollary 1.
//!
//! ```
//! use subsurf::curves::{interpolate_curves, CubicCurve, InterpolateOptions};
//! use subsurf::nurbs::{BSplineCurve, Curve};
//! use subsurf::nonuniform::Nurss;
//!
//! let pts = vec![[0.0, 0.0, 0.0], [1.0, 2.0, 0.0], [3.0, 2.0, 1.0], [4.0, 0.0, 0.0], [6.0, 1.0, 0.0]];
//! let spline = BSplineCurve::clamped_uniform(3, pts)?;
//! let curve = CubicCurve::new(&Curve::BSpline(spline.clone()), "profile")?;
//! let zones = interpolate_curves(&[curve], &InterpolateOptions::default())?;
//! // Control point P_2 sits at the knot t_4; the limit surface passes through C(t_4) there.
//! let zone = &zones.zones[0];
//! let limit = Nurss::new(&zones.mesh, &Default::default())?.limit_points();
//! let on_surface = limit[zone.middle[zone.first + 2] as usize];
//! let on_curve = spline.eval(spline.knots().as_slice()[4])?;
//! assert!((0..3).all(|k| (on_surface[k] - on_curve[k]).abs() < 1e-12));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub(crate) mod crossing;
pub(crate) mod curve;
mod error;
pub(crate) mod frame;
mod grid;
pub(crate) mod host;
pub(crate) mod track;
pub(crate) mod zone;

pub use curve::{CubicCurve, MiddlePolygon};
pub use error::InterpolateError;
pub use frame::{side_directions, tangents};
pub use host::{embed_curves, HostOptions, DEFAULT_HOST_WIDTH};
pub use track::refine_polyline;

use crate::mesh::{Options, PolyMesh};
use crate::nonuniform::NurssError;
use crate::nurbs::{Geometry, SourcedGeometry};

/// Default zone width, relative to the size (bounding-box diagonal of the control points)
/// of each curve.
pub const DEFAULT_WIDTH: f64 = 0.05;

/// How the zones are built.
#[derive(Clone, Debug, PartialEq)]
pub struct InterpolateOptions {
    /// Distance of the side points from the middle polygon, relative to the curve's size
    /// (the diagonal of its control points' bounding box); at crossings the other curve
    /// decides. Must be finite and > 0. Default [`DEFAULT_WIDTH`].
    pub width: f64,
    /// Side direction: `None` for a rotation-minimising frame started from the polygon's
    /// plane normal (a planar curve's zone stands perpendicular to its plane), or a vector
    /// projected perpendicular to the curve at every control point (see `frame`).
    pub side: Option<[f64; 3]>,
}

impl Default for InterpolateOptions {
    fn default() -> Self {
        Self {
            width: DEFAULT_WIDTH,
            side: None,
        }
    }
}

/// One curve's zone in the control mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Zone {
    /// The curve's name.
    pub label: String,
    /// Mesh vertices of the middle polygon (phantom end points included).
    pub middle: Vec<u32>,
    /// Closed middle polygon.
    pub closed: bool,
    /// Knot at `middle[0]` (see [`MiddlePolygon::start_knot`]).
    pub start_knot: f64,
    /// Index in `middle` of the curve's control point 0.
    pub first: usize,
    /// Number of the curve's control points.
    pub count: usize,
    /// The zone's intervals are the curve's knot intervals times this (1 for a standalone
    /// zone; in a host, see `host`): the knot at `middle[j]` is `start_knot` plus the
    /// intervals of the middle edges before it divided by `knot_scale`.
    pub knot_scale: f64,
}

/// The interpolating control mesh and where each curve's zone is in it.
#[derive(Clone, Debug, PartialEq)]
pub struct Interpolation {
    /// Quads with knot intervals and (rational curves) weights in [`PolyMesh::knots`]: refine
    /// with [`crate::nonuniform`].
    pub mesh: PolyMesh,
    /// One zone per curve, in input order.
    pub zones: Vec<Zone>,
}

/// Builds the control mesh whose NURSS limit surface interpolates `curves` (see the [module
/// documentation](self)).
///
/// # Errors
/// [`InterpolateError`]: no curves, a bad option, a curve the method cannot take, or a
/// crossing that is not a joint polygon group (naming the curve and the point).
pub fn interpolate_curves(
    curves: &[CubicCurve],
    opts: &InterpolateOptions,
) -> Result<Interpolation, InterpolateError> {
    interpolate_curves_counted(curves, opts, &mut 0)
}

/// [`interpolate_curves`], adding to `work` the elementary steps taken (candidate pairs of
/// points and edges compared, columns and anchors visited): a measure of the running time
/// that tests compare across input sizes.
pub(crate) fn interpolate_curves_counted(
    curves: &[CubicCurve],
    opts: &InterpolateOptions,
    work: &mut u64,
) -> Result<Interpolation, InterpolateError> {
    if curves.is_empty() {
        return Err(InterpolateError::NoCurves);
    }
    if !(opts.width.is_finite() && opts.width > 0.0) {
        return Err(InterpolateError::BadOption(format!(
            "the zone width must be a finite number > 0, got {}",
            opts.width
        )));
    }
    if let Some(s) = opts.side {
        if !s.iter().all(|c| c.is_finite()) || s == [0.0; 3] {
            return Err(InterpolateError::BadOption(format!(
                "the side vector must be finite and non-zero, got ({}, {}, {})",
                s[0], s[1], s[2]
            )));
        }
    }
    let all: Vec<[f64; 3]> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .collect();
    let tol = 1e-9 * zone::curve_size(&all);
    let crossings = crossing::find_crossings_counted(curves, tol, work)?;
    let (mesh, zones) = zone::build(curves, &crossings, opts.width, opts.side, work)?;
    Ok(Interpolation { mesh, zones })
}

/// [`interpolate_curves`] for the curves of a file (as `io::read_geometry` reads them);
/// each is named by its [`SourcedGeometry::label`].
///
/// # Errors
/// As [`interpolate_curves`]; a surface in the file is a [`InterpolateError::BadCurve`].
pub fn interpolate_geometry(
    items: &[SourcedGeometry],
    opts: &InterpolateOptions,
) -> Result<Interpolation, InterpolateError> {
    interpolate_curves(&curves_of(items)?, opts)
}

/// [`embed_curves`] for the curves of a file (as `io::read_geometry` reads them),
/// embedded in `host`; each curve is named by its [`SourcedGeometry::label`].
///
/// # Errors
/// As [`embed_curves`]; a surface in the file is a [`InterpolateError::BadCurve`].
pub fn embed_geometry(
    host: &PolyMesh,
    items: &[SourcedGeometry],
    opts: &HostOptions,
) -> Result<Interpolation, InterpolateError> {
    embed_curves(host, &curves_of(items)?, opts)
}

/// The checked cubic curves of a file.
fn curves_of(items: &[SourcedGeometry]) -> Result<Vec<CubicCurve>, InterpolateError> {
    items
        .iter()
        .map(|g| match &g.geometry {
            Geometry::Curve(c) => CubicCurve::new(c, &g.label()),
            Geometry::Surface(_) => Err(InterpolateError::BadCurve {
                curve: g.label(),
                reason: "is a surface; curve interpolation takes curves only".into(),
            }),
        })
        .collect()
}

impl Interpolation {
    /// The control mesh refined `levels` times with NURSS (default scheme options), with its
    /// knot intervals and weights; with `limit` the last level's vertices are moved to their
    /// limit positions ([`crate::nonuniform::Nurss::limit_points`]), which sample the limit surface
    /// (along each middle polygon: the curve at the knots of the refined polygon's points).
    ///
    /// # Errors
    /// [`NurssError`] (too many levels for the index range).
    pub fn refined_mesh(&self, levels: u32, limit: bool) -> Result<PolyMesh, NurssError> {
        Ok(
            crate::nonuniform::refined(&self.mesh, &Options::default(), levels, &mut |_, _| {})?
                .output_mesh(false, limit),
        )
    }

    /// The limit surface sampled by refining `levels` times and moving to the limit:
    /// [`refined_mesh`](Self::refined_mesh)`(levels, true)`.
    ///
    /// # Errors
    /// As [`refined_mesh`](Self::refined_mesh).
    pub fn limit_mesh(&self, levels: u32) -> Result<PolyMesh, NurssError> {
        self.refined_mesh(levels, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::{BSplineCurve, Curve, KnotVector};

    /// A long wavy curve of `n` points along `x` and a short curve crossing it at every
    /// tenth point (`n / 10` joint polygon groups), all with uniform knots.
    fn network(n: usize) -> Vec<CubicCurve> {
        let uniform = |m: usize| KnotVector::new(3, (0..m + 4).map(|i| i as f64).collect());
        let long: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let t = i as f64;
                [t, 0.0, 0.3 * (std::f64::consts::TAU * t / 20.0).sin()]
            })
            .collect();
        let mut curves = vec![CubicCurve::new(
            &Curve::BSpline(BSplineCurve::new(uniform(n).unwrap(), long).unwrap()),
            "long",
        )
        .unwrap()];
        for m in 1..n / 10 {
            let x = 10.0 * m as f64;
            let pts = (-3i32..=3)
                .map(|j| {
                    let y = j as f64;
                    [x, y, 0.02 * y * y * y]
                })
                .collect();
            let c = Curve::BSpline(BSplineCurve::new(uniform(7).unwrap(), pts).unwrap());
            curves.push(CubicCurve::new(&c, &format!("cross {m}")).unwrap());
        }
        curves
    }

    #[test]
    fn work_is_linear_in_the_control_points() {
        // The work (points and edges compared, columns and anchors visited) per control point
        // stays the same when the input doubles; comparing every pair, as before, doubled it.
        let work = |n: usize| {
            let curves = network(n);
            let points: usize = curves.iter().map(CubicCurve::len).sum();
            let mut w = 0;
            let out = interpolate_curves_counted(&curves, &InterpolateOptions::default(), &mut w)
                .unwrap();
            assert_eq!(out.zones.len(), curves.len());
            w as f64 / points as f64
        };
        let (small, large) = (work(2000), work(4000));
        assert!(
            large < 1.1 * small,
            "work per point {small} at 2000 points, {large} at 4000"
        );
    }
}
