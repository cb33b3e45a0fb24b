//! The quartic box spline: the Loop limit surface over a *regular* triangle, in closed form.
//!
//! Loop's subdivision on the regular triangular lattice (every vertex of valence 6, the masks
//! `⅜ ⅜ ⅛ ⅛` and `⅝ + 6 · 1/16`) converges to the three-direction quartic box spline with
//! each of the directions `(1, 0)`, `(0, 1)`, `(1, 1)` taken twice (C. Loop, "Smooth
//! subdivision surfaces based on triangles", M.S. thesis, University of Utah, 1987, §3;
//! J. Stam, "Evaluation of Loop subdivision surfaces", SIGGRAPH 1998 course notes, §2 and
//! appendix, where the twelve basis functions are given in barycentric coordinates).
//!
//! # Control points and parameterisation
//! The triangle `(c₀, c₁, c₂)` has `(u, v) = (0, 0)` at `c₀`, `u` toward `c₁`, `v` toward
//! `c₂` (OpenSubdiv's triangle parameterisation, `Far::PatchParam`, `Bfr::Parameterization`).
//! In lattice coordinates `c₀ = (0, 0)`, `c₁ = (1, 0)`, `c₂ = (0, 1)`, and the twelve control
//! points whose basis functions do not vanish on the triangle are, in the order used here
//! (the order of Stam's figure and of OpenSubdiv's `Far::PatchDescriptor::LOOP`):
//!
//! ```text
//!        10 --- 11                      (-1,2)  (0,2)
//!       /  \   /  \
//!      7 --- 8 --- 9             (-1,1)  (0,1)  (1,1)
//!     / \   / \   / \
//!    3 --- 4 --- 5 --- 6     (-1,0)  (0,0)  (1,0)  (2,0)
//!     \   / \   / \   /
//!      0 --- 1 --- 2             (0,-1)  (1,-1) (2,-1)
//! ```
//!
//! so the triangle is `(4, 5, 8)`, and the six neighbours of a lattice point `p` are
//! `p + dᵢ` with `d = (1,0), (0,1), (-1,1), (-1,0), (0,-1), (1,-1)` ([`DIRECTIONS`], in
//! counter-clockwise order).
//!
//! # The basis
//! `S(u, v) = Σᵢ Bᵢ(u, v) Pᵢ` with `Bᵢ = (1/12) Σₖ C[i][k] Mₖ(u, v)` and the monomials
//! `M = (1, u, v, u², uv, v², u³, u²v, uv², v³, u⁴, u³v, u²v², uv³, v⁴)`. The integer
//! matrix [`COEFFICIENTS`] was derived from Loop's rules alone (`scripts/derive-loop-box-spline.py`):
//! a patch is the unique polynomial family with `Σ Bᵢ = 1` such that, for each of the four
//! children `k` of the triangle (the corner ones and the middle one, whose parameterisation
//! is turned by half a turn: `(u, v) = ((1, 1) − (s, t)) / 2`), `B(φₖ(s, t)) = Sₖᵀ B(s, t)`
//! with `Sₖ` the 12 × 12 matrix of Loop's masks that gives the child's twelve points from the
//! parent's. It equals Stam's basis expanded into monomials (and the table in OpenSubdiv's
//! `Far::internal::EvalBasisBoxSplineTri`). Derivatives are those of the monomials.
//!
//! # Boundaries, creases and corners: phantom points
//! Along a boundary, or an infinitely sharp edge (where Loop's crease rules are its boundary
//! rules: `¾ v + ⅛ (a + b)` and midpoints), the limit over a triangle whose corners are
//! regular *in their sector* (the faces around the corner reached without crossing an
//! infinitely sharp edge) is the same box spline of twelve points, some of them *phantom*
//! points extrapolated from the sector's own (OpenSubdiv's `Far` boundary masks for the box
//! spline, `adjustBoxSplineTriBoundaryWeights`, and `Bfr::FaceSurface::isRegular`):
//! - a crease or boundary corner `c` (crease rule) whose sector has 3 faces has 4 real
//!   neighbours `c + d_s … c + d_{s+3}` (`xₖ` the point at `d_k`); the missing two are
//!   `c + d_{s+4} = c + x_{s+3} − x_{s+2}` and `c + d_{s+5} = c + x_s − x_{s+1}`;
//! - an infinitely sharp corner (corner rule) whose sector is the triangle alone has the
//!   two real neighbours `x_s, x_{s+1}`, and `c + d_{s+2} = c + x_{s+1} − x_s`,
//!   `c + d_{s+3} = 2c − x_s`, `c + d_{s+4} = 2c − x_{s+1}`, `c + d_{s+5} = c + x_s − x_{s+1}`;
//!
//! each the lattice translate `c + (x_a − c) − (x_b − c)` of points the sector has, so the
//! extrapolation is exact for every affine function. The tests check the result against the
//! limit of Loop refinement.

use super::Derivatives;
use crate::mesh::{Rule, Topology};
use crate::scheme::crease::is_infinite;

/// The six neighbour directions of a lattice point, counter-clockwise (module docs).
pub(super) const DIRECTIONS: [(i32, i32); 6] = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)];

/// Lattice coordinates of the twelve control points (module docs).
pub(super) const POINTS: [(i32, i32); 12] = [
    (0, -1),
    (1, -1),
    (2, -1),
    (-1, 0),
    (0, 0),
    (1, 0),
    (2, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
    (-1, 2),
    (0, 2),
];

/// The control points at the triangle's corners `c₀, c₁, c₂`.
pub(super) const CORNERS: [usize; 3] = [4, 5, 8];

/// `12 Bᵢ` as integer coefficients of the monomials
/// `(1, u, v, u², uv, v², u³, u²v, uv², v³, u⁴, u³v, u²v², uv³, v⁴)` (module docs).
pub(super) const COEFFICIENTS: [[i8; 15]; 12] = [
    [1, -2, -4, 0, 6, 6, 2, 0, -6, -4, -1, -2, 0, 2, 1],
    [1, 2, -2, 0, -6, 0, -4, 0, 6, 2, 2, 4, 0, -2, -1],
    [0, 0, 0, 0, 0, 0, 2, 0, 0, 0, -1, -2, 0, 0, 0],
    [1, -4, -2, 6, 6, 0, -4, -6, 0, 2, 1, 2, 0, -2, -1],
    [6, 0, 0, -12, -12, -12, 8, 12, 12, 8, -1, -2, 0, -2, -1],
    [1, 4, 2, 6, 6, 0, -4, -6, -12, -4, -1, -2, 0, 4, 2],
    [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 0, 0, 0],
    [1, -2, 2, 0, -6, 0, 2, 6, 0, -4, -1, -2, 0, 4, 2],
    [1, 2, 4, 0, 6, 6, -4, -12, -6, -4, 2, 4, 0, -2, -1],
    [0, 0, 0, 0, 0, 0, 2, 6, 6, 2, -1, -2, 0, -2, -1],
    [0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, -2, -1],
    [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1],
];

/// Exponents `(a, b)` of the monomials `uᵃ vᵇ`, in the order of [`COEFFICIENTS`].
const EXPONENTS: [(i32, i32); 15] = [
    (0, 0),
    (1, 0),
    (0, 1),
    (2, 0),
    (1, 1),
    (0, 2),
    (3, 0),
    (2, 1),
    (1, 2),
    (0, 3),
    (4, 0),
    (3, 1),
    (2, 2),
    (1, 3),
    (0, 4),
];

/// The twelve basis functions at `(u, v)` and their partial derivatives:
/// `[B, B_u, B_v, B_uu, B_uv, B_vv]` (the tests' reference for [`BoxPoly`]).
#[cfg(test)]
pub(super) fn basis(u: f64, v: f64) -> [[f64; 12]; 6] {
    // Powers 0..=4 of u and v.
    let mut pu = [1.0; 5];
    let mut pv = [1.0; 5];
    for k in 1..5 {
        pu[k] = pu[k - 1] * u;
        pv[k] = pv[k - 1] * v;
    }
    // `d^i/du^i d^j/dv^j` of `u^a v^b` = falling factorials times lower powers.
    let term = |a: i32, b: i32, i: i32, j: i32| -> f64 {
        if a < i || b < j {
            return 0.0;
        }
        let fall = |n: i32, k: i32| (0..k).map(|m| f64::from(n - m)).product::<f64>();
        fall(a, i) * fall(b, j) * pu[(a - i) as usize] * pv[(b - j) as usize]
    };
    const ORDERS: [(i32, i32); 6] = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];
    let mut out = [[0.0; 12]; 6];
    for (o, &(i, j)) in ORDERS.iter().enumerate() {
        let m: [f64; 15] = std::array::from_fn(|k| term(EXPONENTS[k].0, EXPONENTS[k].1, i, j));
        for (p, row) in COEFFICIENTS.iter().enumerate() {
            let s: f64 = row.iter().zip(&m).map(|(&c, &x)| f64::from(c) * x).sum();
            out[o][p] = s / 12.0;
        }
    }
    out
}

/// A box-spline patch as its polynomial: `S(u, v) = Σₖ aₖ Mₖ(u, v)` over the fifteen
/// monomials of [`EXPONENTS`], `aₖ = (1/12) Σᵢ C[i][k] Pᵢ` (module docs). Evaluating it
/// costs the monomials and their derivatives once per point, where computing the twelve
/// basis functions first and combining the points with them takes about five times the
/// arithmetic: a patch evaluated at many points is converted once.
#[derive(Clone, Copy, Debug)]
pub(super) struct BoxPoly([[f64; 3]; 15]);

impl BoxPoly {
    /// The polynomial of the patch with control points `cp`.
    pub(super) fn new(cp: &[[f64; 3]; 12]) -> Self {
        let mut a = [[0.0; 3]; 15];
        for (row, p) in COEFFICIENTS.iter().zip(cp) {
            for (ak, &c) in a.iter_mut().zip(row) {
                if c != 0 {
                    let c = f64::from(c);
                    (0..3).for_each(|d| ak[d] += c * p[d]);
                }
            }
        }
        a.iter_mut()
            .for_each(|ak| ak.iter_mut().for_each(|x| *x /= 12.0));
        BoxPoly(a)
    }

    /// Position and first and second derivatives at `(u, v)`.
    pub(super) fn eval(&self, u: f64, v: f64) -> Derivatives {
        // Powers 0..=4 of u and v.
        let mut pu = [1.0; 5];
        let mut pv = [1.0; 5];
        for k in 1..5 {
            pu[k] = pu[k - 1] * u;
            pv[k] = pv[k - 1] * v;
        }
        let mut out = [[0.0; 3]; 6];
        for (ak, &(a, b)) in self.0.iter().zip(&EXPONENTS) {
            let (a, b) = (a as usize, b as usize);
            // `∂ᵢ/∂uⁱ ∂ʲ/∂vʲ uᵃ vᵇ` for the six orders, falling factorials times lower
            // powers (zero where an exponent would go below zero).
            let d = |n: usize, k: usize, p: &[f64; 5]| -> f64 {
                match k {
                    0 => p[n],
                    1 if n >= 1 => n as f64 * p[n - 1],
                    2 if n >= 2 => (n * (n - 1)) as f64 * p[n - 2],
                    _ => 0.0,
                }
            };
            let m = [
                d(a, 0, &pu) * d(b, 0, &pv),
                d(a, 1, &pu) * d(b, 0, &pv),
                d(a, 0, &pu) * d(b, 1, &pv),
                d(a, 2, &pu) * d(b, 0, &pv),
                d(a, 1, &pu) * d(b, 1, &pv),
                d(a, 0, &pu) * d(b, 2, &pv),
            ];
            for (o, &w) in out.iter_mut().zip(&m) {
                (0..3).for_each(|i| o[i] += w * ak[i]);
            }
        }
        let [p, du, dv, duu, duv, dvv] = out;
        Derivatives {
            p,
            du,
            dv,
            duu,
            duv,
            dvv,
        }
    }
}

/// One control point of a box-spline net: a point of the level, or a phantom point
/// `a + b − c` of three of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum NetPoint {
    /// A vertex of the level.
    Vertex(u32),
    /// The phantom point `a + b − c`.
    Phantom(u32, u32, u32),
}

impl NetPoint {
    /// The point's position among `pos`.
    pub(super) fn at(self, pos: &[[f64; 3]]) -> [f64; 3] {
        match self {
            NetPoint::Vertex(a) => pos[a as usize],
            NetPoint::Phantom(a, b, c) => {
                let (a, b, c) = (pos[a as usize], pos[b as usize], pos[c as usize]);
                std::array::from_fn(|k| a[k] + b[k] - c[k])
            }
        }
    }
}

/// The twelve control points of triangle `f` of the triangle level `t` when its limit is one
/// box-spline patch (module docs): every corner smooth of valence 6 with no sharp edge, or a
/// crease (boundary) corner whose sector has 3 faces, or an infinitely sharp corner whose
/// sector is `f` alone; no semi-sharp vertex or edge at a corner; not a hole. `None`
/// otherwise (the face is refined further).
pub(super) fn box_net(t: &Topology, f: usize) -> Option<[NetPoint; 12]> {
    if t.is_hole(f) || t.face_vertices(f).len() != 3 {
        return None;
    }
    let mut net: [Option<NetPoint>; 12] = [None; 12];
    for k in 0..3 {
        let fan = corner_fan(t, f, k)?;
        // Corner `k` is at lattice point CORNERS[k]; face `f` lies between its directions
        // `2k` (toward the next corner) and `2k + 1` (toward the previous one).
        let c = fan.centre;
        let origin = POINTS[CORNERS[k]];
        // `after` runs clockwise from direction `2k`, `before` counter-clockwise from
        // `2k + 1`: the arc of real neighbours starts at `2k − (after.len() − 1)`.
        let m = fan.before.len() + fan.after.len();
        let s = (2 * k + 6 - (fan.after.len() - 1)) % 6;
        let mut real = [None; 6];
        let ring = fan.after.iter().rev().chain(&fan.before);
        for (i, &x) in ring.enumerate() {
            real[(s + i) % 6] = Some(x);
        }
        let x = |i: usize| real[(s + i) % 6].unwrap_or(c);
        for (i, slot) in real.iter().enumerate() {
            let d = DIRECTIONS[i];
            let lattice = (origin.0 + d.0, origin.1 + d.1);
            let Some(p) = POINTS.iter().position(|&q| q == lattice) else {
                continue;
            };
            if net[p].is_some() {
                continue;
            }
            net[p] = Some(match slot {
                Some(v) => NetPoint::Vertex(*v),
                None => {
                    let j = (i + 6 - s) % 6;
                    match (m, j) {
                        (4, 4) => NetPoint::Phantom(c, x(3), x(2)),
                        (4, 5) => NetPoint::Phantom(c, x(0), x(1)),
                        (2, 2) => NetPoint::Phantom(c, x(1), x(0)),
                        (2, 3) => NetPoint::Phantom(c, c, x(0)),
                        (2, 4) => NetPoint::Phantom(c, c, x(1)),
                        (2, 5) => NetPoint::Phantom(c, x(0), x(1)),
                        _ => return None,
                    }
                }
            });
        }
        net[CORNERS[k]] = Some(NetPoint::Vertex(c));
    }
    let mut out = [NetPoint::Vertex(0); 12];
    for (o, n) in out.iter_mut().zip(net) {
        *o = n?;
    }
    Some(out)
}

/// The neighbours of corner `k` of triangle `f` in its sector: `after` the far ends of the
/// edges met turning from `f`'s edge toward its next corner away from `f` (that corner
/// first), `before` those met turning the other way (its previous corner first).
struct Fan {
    centre: u32,
    before: Vec<u32>,
    after: Vec<u32>,
}

/// The fan of corner `k` of `f` when the corner is regular for a box-spline patch (see
/// [`box_net`]), else `None`.
fn corner_fan(t: &Topology, f: usize, k: usize) -> Option<Fan> {
    let fv = t.face_vertices(f);
    let c = fv[k];
    let tag = t.vertex_tag(c as usize);
    if tag.non_manifold || tag.semi_sharp || tag.semi_sharp_edges {
        return None;
    }
    let edges = t.vertex_edges(c as usize);
    let sharp = edges
        .iter()
        .filter(|&&e| t.edge_sharpness(e as usize) > 0.0);
    if sharp
        .clone()
        .any(|&e| !is_infinite(t.edge_sharpness(e as usize)))
    {
        return None;
    }
    let num_sharp = sharp.count();
    // Face edge `k` joins corner `k` and the next corner; edge `k + 2` the previous one.
    let fe = t.face_edge_list(f);
    let next = walk(t, f, c, fe[k], fv[(k + 1) % 3])?;
    let prev = walk(t, f, c, fe[(k + 2) % 3], fv[(k + 2) % 3])?;
    debug_assert!(next.1 == prev.1);
    let (after, closed) = next;
    // Around a closed fan the walk toward the next corner met every neighbour but the
    // previous corner.
    let before = if closed {
        vec![fv[(k + 2) % 3]]
    } else {
        prev.0
    };
    let fan = Fan {
        centre: c,
        before,
        after,
    };
    let m = fan.before.len() + fan.after.len();
    let faces = if closed { m } else { m - 1 };
    let ok = match tag.rule {
        Rule::Smooth => closed && num_sharp == 0 && faces == 6 && edges.len() == 6,
        Rule::Crease => !closed && num_sharp == 2 && faces == 3,
        Rule::Corner => !closed && faces == 1,
        Rule::Dart => false,
    };
    ok.then_some(fan)
}

/// The far ends of the edges at `c` met from face `f` across its edge `e` (whose far end is
/// `x`, listed first) and on around `c` while the edges crossed are smooth with two faces:
/// `(ends, closed)`, `closed` when the walk came back to `f` (then the ends are all of
/// `c`'s neighbours, `x` not repeated). `None` when the walk meets something it cannot follow
/// (a face that is not a triangle, more than six steps).
fn walk(t: &Topology, f: usize, c: u32, e: u32, x: u32) -> Option<(Vec<u32>, bool)> {
    let mut ends = vec![x];
    let (mut g, mut e, mut x) = (f, e, x);
    for _ in 0..7 {
        let faces = t.edge_face_list(e as usize);
        if faces.len() != 2 || t.edge_sharpness(e as usize) > 0.0 {
            return Some((ends, false));
        }
        let h = if faces[0] as usize == g {
            faces[1]
        } else {
            faces[0]
        } as usize;
        if h == f {
            ends.pop();
            return Some((ends, true));
        }
        let hv = t.face_vertices(h);
        if hv.len() != 3 {
            return None;
        }
        let he = t.face_edge_list(h);
        // The edge of `h` at `c` other than `e`, and its far end.
        let j = (0..3).find(|&j| {
            let [a, b] = t.edge_vertices(he[j] as usize);
            he[j] != e && (a == c || b == c)
        })?;
        let [a, b] = t.edge_vertices(he[j] as usize);
        let y = if a == c { b } else { a };
        if y == x || y == c {
            return None;
        }
        ends.push(y);
        (g, e, x) = (h, he[j], y);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial form of a patch gives the position and derivatives of its basis
    /// functions combined with its control points, to rounding, across the triangle.
    #[test]
    fn polynomial_form_equals_the_basis() {
        let cp: [[f64; 3]; 12] = std::array::from_fn(|i| {
            let x = i as f64;
            [x.sin() * 3.0 + 1.0, (0.7 * x).cos() - 2.0, 0.1 * x * x]
        });
        let poly = BoxPoly::new(&cp);
        for i in 0..=10 {
            for j in 0..=(10 - i) {
                let (u, v) = (f64::from(i) / 10.0, f64::from(j) / 10.0);
                let b = basis(u, v);
                let d = poly.eval(u, v);
                let got = [d.p, d.du, d.dv, d.duu, d.duv, d.dvv];
                for (o, g) in got.iter().enumerate() {
                    for k in 0..3 {
                        let want: f64 = (0..12).map(|p| b[o][p] * cp[p][k]).sum();
                        assert!((g[k] - want).abs() < 1e-12, "({u}, {v}) order {o}: {g:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn partition_of_unity_and_linear_precision() {
        for &(u, v) in &[
            (0.0, 0.0),
            (0.3, 0.2),
            (1.0, 0.0),
            (0.0, 1.0),
            (0.25, 0.75),
            (0.1, 0.6),
        ] {
            let b = basis(u, v);
            let sum: f64 = b[0].iter().sum();
            assert!((sum - 1.0).abs() < 1e-14);
            for d in 1..6 {
                assert!(b[d].iter().sum::<f64>().abs() < 1e-13);
            }
            // Linear functions of the lattice are reproduced: x(p) = p → S(u, v) = (u, v).
            let lin = |o: usize, axis: usize| -> f64 {
                (0..12)
                    .map(|i| b[o][i] * f64::from(if axis == 0 { POINTS[i].0 } else { POINTS[i].1 }))
                    .sum()
            };
            assert!((lin(0, 0) - u).abs() < 1e-14 && (lin(0, 1) - v).abs() < 1e-14);
            assert!((lin(1, 0) - 1.0).abs() < 1e-13 && lin(1, 1).abs() < 1e-13);
            assert!(lin(2, 0).abs() < 1e-13 && (lin(2, 1) - 1.0).abs() < 1e-13);
            for d in 3..6 {
                assert!(lin(d, 0).abs() < 1e-13 && lin(d, 1).abs() < 1e-13);
            }
        }
    }

    /// At a corner the patch is Loop's limit position mask `½ c + 1/12 Σ neighbours`.
    #[test]
    fn corners_take_the_limit_mask() {
        for (k, &(u, v)) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].iter().enumerate() {
            let b = basis(u, v)[0];
            let c = POINTS[CORNERS[k]];
            for (i, &p) in POINTS.iter().enumerate() {
                let d = (p.0 - c.0, p.1 - c.1);
                let want = if d == (0, 0) {
                    0.5
                } else if DIRECTIONS.contains(&d) {
                    1.0 / 12.0
                } else {
                    0.0
                };
                assert!((b[i] - want).abs() < 1e-15, "corner {k} point {i}");
            }
        }
    }

    /// The derivatives are those of the basis: central differences agree.
    #[test]
    fn derivatives_match_differences() {
        let (u, v, h) = (0.31, 0.27, 1e-5);
        let b = basis(u, v);
        let at = |u, v| basis(u, v)[0];
        let atd = |u, v, o: usize| basis(u, v)[o];
        for i in 0..12 {
            let du = (at(u + h, v)[i] - at(u - h, v)[i]) / (2.0 * h);
            let dv = (at(u, v + h)[i] - at(u, v - h)[i]) / (2.0 * h);
            assert!((du - b[1][i]).abs() < 1e-9 && (dv - b[2][i]).abs() < 1e-9);
            let duu = (atd(u + h, v, 1)[i] - atd(u - h, v, 1)[i]) / (2.0 * h);
            let duv = (atd(u, v + h, 1)[i] - atd(u, v - h, 1)[i]) / (2.0 * h);
            let dvv = (atd(u, v + h, 2)[i] - atd(u, v - h, 2)[i]) / (2.0 * h);
            assert!((duu - b[3][i]).abs() < 1e-8);
            assert!((duv - b[4][i]).abs() < 1e-8);
            assert!((dvv - b[5][i]).abs() < 1e-8);
        }
    }
}
