//! Spatial cones: a plane through the origin that has a set of vectors strictly on one
//! side, found numerically and then **verified exactly**.
//!
//! By Gordan's theorem, non-zero vectors `g₁ … g_N` admit `n` with `n · gᵢ > 0` for all `i`
//! exactly when the origin is not in their convex hull, i.e. when the cone they span is
//! pointed (holds no line). With the vectors normalised, the point `x*` of
//! `conv{ĝᵢ}` nearest the origin is then such an `n` (it maximises the smallest margin
//! `n · ĝᵢ / |n|`), because the nearest point satisfies `x* · ĝᵢ ≥ |x*|² > 0`.
//!
//! The search: Gilbert's algorithm (repeated projection of the origin onto the segment
//! between the current point and the vector of smallest margin) until every margin is
//! positive; when it stalls and there are at most [`EXHAUSTIVE_MAX`] vectors, every vertex,
//! edge and triangle of the hull is tried (the nearest point lies on one of them). Every
//! candidate `n` (an `f64` vector) is accepted only if the **exact** sign of `n · gᵢ`
//! ([`super::exact::dot3_sign`], on the exact differences of the input points) is positive
//! for every `i`. So a returned plane always separates; a set whose separating planes are
//! all thinner than the rounding of the search is refused (conservative), never certified.

use super::exact::{dot3_sign, Sign};

/// Up to this many vectors, a stalled search falls back to trying every vertex, edge and
/// triangle of the hull (`O(N⁴)`).
pub(crate) const EXHAUSTIVE_MAX: usize = 40;

/// At most this many steps of Gilbert's algorithm (each `O(N)`).
pub(crate) const MAX_ITERATIONS: usize = 4000;

/// A space vector given by its end points: `to − from`, negated when `negate`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ray {
    /// Start point.
    pub from: [f64; 3],
    /// End point.
    pub to: [f64; 3],
    /// Use `from − to` instead.
    pub negate: bool,
}

type V = [f64; 3];

fn dot(a: &V, b: &V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn lerp(a: &V, b: &V, t: f64) -> V {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
    ]
}

fn unit(r: &Ray) -> Option<V> {
    let s = if r.negate { -1.0 } else { 1.0 };
    let d = [
        s * (r.to[0] - r.from[0]),
        s * (r.to[1] - r.from[1]),
        s * (r.to[2] - r.from[2]),
    ];
    let m = d[0].abs().max(d[1].abs()).max(d[2].abs());
    if m == 0.0 || !m.is_finite() {
        return None;
    }
    let d = [d[0] / m, d[1] / m, d[2] / m];
    let n = dot(&d, &d).sqrt();
    Some([d[0] / n, d[1] / n, d[2] / n])
}

/// Whether `n · r > 0` exactly for every ray.
pub(crate) fn separates(n: &V, rays: &[Ray]) -> bool {
    rays.iter().all(|r| {
        let want = if r.negate {
            Sign::Negative
        } else {
            Sign::Positive
        };
        dot3_sign(*n, r.from, r.to) == Some(want)
    })
}

/// A vector `n` with `n · r > 0` (exactly) for every ray, or `None` when none was found
/// (see the module docs: `None` for every set that has no such plane, and possibly for
/// sets whose planes are thinner than rounding). Every ray must be non-zero; a zero ray
/// makes the answer `None`.
pub(crate) fn separating_direction(rays: &[Ray]) -> Option<V> {
    let g: Vec<V> = rays.iter().map(unit).collect::<Option<_>>()?;
    if g.is_empty() {
        return Some([1.0, 0.0, 0.0]);
    }
    let margin = |x: &V| g.iter().map(|gi| dot(x, gi)).fold(f64::INFINITY, f64::min);
    let try_candidate = |x: &V| margin(x) > 0.0 && separates(x, rays);
    // Gilbert's algorithm.
    let mut x = g[0];
    for _ in 0..(200 + 20 * g.len()).min(MAX_ITERATIONS) {
        let (j, m) = g
            .iter()
            .enumerate()
            .map(|(i, gi)| (i, dot(&x, gi)))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        if m > 0.0 {
            if separates(&x, rays) {
                return Some(x);
            }
            break;
        }
        let xx = dot(&x, &x);
        if xx - m <= 1e-15 * xx.max(1e-300) || xx < 1e-28 {
            break; // converged (nearest point found) or at the origin
        }
        let d = [g[j][0] - x[0], g[j][1] - x[1], g[j][2] - x[2]];
        let dd = dot(&d, &d);
        if dd == 0.0 {
            break;
        }
        let t = (-dot(&x, &d) / dd).clamp(0.0, 1.0);
        x = lerp(&x, &g[j], t);
    }
    if g.len() > EXHAUSTIVE_MAX {
        return None;
    }
    // Exhaustive: the nearest point of every vertex, edge and triangle.
    let n = g.len();
    for i in 0..n {
        if try_candidate(&g[i]) {
            return Some(g[i]);
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            let x = closest_on_segment(&g[i], &g[j]);
            if try_candidate(&x) {
                return Some(x);
            }
        }
    }
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let x = closest_on_triangle(&g[i], &g[j], &g[k]);
                if try_candidate(&x) {
                    return Some(x);
                }
            }
        }
    }
    None
}

/// The point of segment `[a, b]` nearest the origin.
fn closest_on_segment(a: &V, b: &V) -> V {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let dd = dot(&d, &d);
    if dd == 0.0 {
        return *a;
    }
    lerp(a, b, (-dot(a, &d) / dd).clamp(0.0, 1.0))
}

/// The point of triangle `abc` nearest the origin (Ericson, *Real-Time Collision
/// Detection*, §5.1.5, with the query point at the origin).
fn closest_on_triangle(a: &V, b: &V, c: &V) -> V {
    let sub = |p: &V, q: &V| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let neg = |p: &V| [-p[0], -p[1], -p[2]];
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = neg(a);
    let (d1, d2) = (dot(&ab, &ap), dot(&ac, &ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = neg(b);
    let (d3, d4) = (dot(&ab, &bp), dot(&ac, &bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return lerp(a, b, d1 / (d1 - d3));
    }
    let cp = neg(c);
    let (d5, d6) = (dot(&ab, &cp), dot(&ac, &cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return lerp(a, c, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return lerp(b, c, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    [
        a[0] + ab[0] * v + ac[0] * w,
        a[1] + ab[1] * v + ac[1] * w,
        a[2] + ab[2] * v + ac[2] * w,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(d: V) -> Ray {
        Ray {
            from: [0.5, -0.25, 2.0],
            to: [0.5 + d[0], -0.25 + d[1], 2.0 + d[2]],
            negate: false,
        }
    }

    #[test]
    fn vectors_in_an_open_half_space_are_separated() {
        let rays = [
            ray([1.0, 0.0, 0.1]),
            ray([0.0, 1.0, 0.1]),
            ray([-0.9, -0.9, 0.1]),
        ];
        let n = separating_direction(&rays).expect("pointed cone");
        assert!(separates(&n, &rays));
        assert!(n[2] > 0.0);
    }

    #[test]
    fn a_cone_that_holds_a_line_or_a_plane_is_refused() {
        // Opposite vectors.
        assert_eq!(
            separating_direction(&[ray([1.0, 2.0, 3.0]), ray([-2.0, -4.0, -6.0])]),
            None
        );
        // Three vectors in a plane summing to zero (the origin inside the triangle).
        assert_eq!(
            separating_direction(&[
                ray([1.0, 0.0, 0.0]),
                ray([-0.5, 1.0, 0.0]),
                ray([-0.5, -1.0, 0.0])
            ]),
            None
        );
        // Exactly on the boundary: the origin on the hull's edge (a half-plane cone).
        assert_eq!(
            separating_direction(&[
                ray([1.0, 0.0, 0.0]),
                ray([-1.0, 0.0, 0.0]),
                ray([0.0, 0.0, 1.0])
            ]),
            None
        );
        // A negated ray is the opposite vector.
        let mut r = ray([1.0, 1.0, 0.0]);
        r.negate = true;
        assert_eq!(separating_direction(&[ray([1.0, 1.0, 0.0]), r]), None);
    }

    #[test]
    fn random_sets_agree_with_a_dense_direction_search() {
        let mut state = 0x1234_5678_9abc_def1u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        // Candidate directions on a fine sphere grid.
        let mut dirs = Vec::new();
        for i in 0..120 {
            for j in 0..240 {
                let th = std::f64::consts::PI * (i as f64 + 0.5) / 120.0;
                let ph = std::f64::consts::TAU * j as f64 / 240.0;
                dirs.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
            }
        }
        let mut found = 0;
        for _ in 0..300 {
            let n = 2 + ((next() + 1.0) * 6.0) as usize;
            let axis = [next(), next(), next()];
            let rays: Vec<Ray> = (0..n)
                .map(|_| ray([axis[0] + next(), axis[1] + next(), axis[2] + next()]))
                .collect();
            let got = separating_direction(&rays);
            let g: Vec<V> = rays.iter().map(|r| unit(r).unwrap()).collect();
            // A grid direction with a clear margin proves separability.
            let clear = dirs.iter().any(|d| g.iter().all(|gi| dot(d, gi) > 0.02));
            if let Some(x) = got {
                assert!(separates(&x, &rays));
                found += 1;
            } else {
                assert!(!clear, "missed a separable set: {g:?}");
            }
        }
        assert!(found > 50, "only {found} separable sets");
    }
}
