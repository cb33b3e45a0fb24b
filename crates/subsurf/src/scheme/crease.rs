//! Sharpness rules (OpenSubdiv's `Sdc::Crease`), computed in `f32` exactly as OpenSubdiv
//! does so that decisions and transitional weights agree bit for bit.
//!
//! Sharpness `s`: `s <= 0` smooth, `0 < s < 10` semi-sharp, `s >= 10` infinitely sharp.
//! A semi-sharp feature uses the sharp rule for `⌊s⌋` levels and, in the step where `s`
//! falls to 0, a blend of the sharp and smooth rules weighted by the fraction of `s`
//! (DeRose, Kass, Truong, "Subdivision Surfaces in Character Animation", SIGGRAPH 1998,
//! §3; OpenSubdiv's `ComputeFractionalWeightAtVertex`).

use crate::mesh::CreaseMethod;
// The classification of sharpness values, which the mesh layer's topology needs too, is
// the mesh layer's; this is its public path.
pub(crate) use crate::mesh::sharpness::{
    is_infinite, is_semi_sharp, is_sharp, is_smooth, vertex_rule, SHARPNESS_INFINITE,
};

/// Sharpness one level down: `s - 1`, kept infinite at ≥ 10 and clamped at 0.
#[inline]
pub(crate) fn decrement(s: f32) -> f32 {
    if is_smooth(s) {
        0.0
    } else if is_infinite(s) {
        SHARPNESS_INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

/// Sharpness of the child of an edge with sharpness `s` at a parent vertex whose incident
/// edges have sharpness `incident` (which includes `s` itself).
///
/// Uniform: `decrement(s)`. Chaikin: with `k > 1` semi-sharp edges at the vertex, the child
/// takes `0.75 s + 0.25 avg(other semi-sharp) - 1` (OpenSubdiv's
/// `SubdivideEdgeSharpnessAtVertex`).
pub(crate) fn subdivide_edge_sharpness(method: CreaseMethod, s: f32, incident: &[f32]) -> f32 {
    if method == CreaseMethod::Uniform || incident.len() < 2 {
        return decrement(s);
    }
    if is_smooth(s) {
        return 0.0;
    }
    if is_infinite(s) {
        return SHARPNESS_INFINITE;
    }
    let (mut sum, mut count) = (0.0f32, 0u32);
    for &x in incident {
        if is_semi_sharp(x) {
            count += 1;
            sum += x;
        }
    }
    let mut c = s;
    if count > 1 {
        let avg = (sum - s) / (count - 1) as f32;
        c = 0.75 * s + 0.25 * avg;
    }
    c -= 1.0;
    if is_sharp(c) {
        c
    } else {
        0.0
    }
}

/// Weight of the sharp (parent-rule) mask when a vertex changes rule during a step:
/// the average sharpness of the features that become smooth, clamped to 1
/// (OpenSubdiv's `ComputeFractionalWeightAtVertex`).
///
/// `parent_edges` and `child_edges` are the sharpness of the vertex's edges before and
/// after the step, in the same order.
pub(crate) fn fractional_weight(
    method: CreaseMethod,
    parent_vertex: f32,
    child_vertex: f32,
    parent_edges: &[f32],
    child_edges: &[f32],
) -> f32 {
    let (mut count, mut sum) = (0u32, 0.0f32);
    if is_sharp(parent_vertex) && is_smooth(child_vertex) {
        count = 1;
        sum = parent_vertex;
    }
    if method == CreaseMethod::Uniform {
        for &p in parent_edges {
            if is_sharp(p) && p <= 1.0 {
                sum += p;
                count += 1;
            }
        }
    } else {
        for (&p, &c) in parent_edges.iter().zip(child_edges) {
            if is_sharp(p) && is_smooth(c) {
                sum += p;
                count += 1;
            }
        }
    }
    if count == 0 {
        return 0.0;
    }
    let w = sum / count as f32;
    if w > 1.0 {
        1.0
    } else {
        w
    }
}

/// Indices of the first and the last sharp edge of a crease vertex (exactly two are
/// expected; OpenSubdiv's `GetSharpEdgePairOfCrease`).
pub(crate) fn crease_ends(edge_sharpness: &[f32]) -> (usize, usize) {
    let first = edge_sharpness
        .iter()
        .position(|&s| is_sharp(s))
        .unwrap_or(0);
    let last = edge_sharpness
        .iter()
        .rposition(|&s| is_sharp(s))
        .unwrap_or(0);
    (first, last)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Rule;

    #[test]
    fn rules_follow_sharp_edge_count() {
        assert_eq!(vertex_rule(0.0, 0), Rule::Smooth);
        assert_eq!(vertex_rule(0.0, 1), Rule::Dart);
        assert_eq!(vertex_rule(0.0, 2), Rule::Crease);
        assert_eq!(vertex_rule(0.0, 3), Rule::Corner);
        assert_eq!(vertex_rule(0.5, 0), Rule::Corner);
    }

    #[test]
    fn decrement_keeps_infinite_and_clamps() {
        assert_eq!(decrement(10.0), 10.0);
        assert_eq!(decrement(12.0), 10.0);
        assert_eq!(decrement(2.5), 1.5);
        assert_eq!(decrement(1.0), 0.0);
        assert_eq!(decrement(0.3), 0.0);
        assert_eq!(decrement(-1.0), 0.0);
    }

    #[test]
    fn chaikin_averages_semi_sharp_neighbours_only() {
        // 3 and 1 semi-sharp, 10 infinite (ignored), 0 smooth (ignored).
        let inc = [3.0, 1.0, 10.0, 0.0];
        let c = subdivide_edge_sharpness(CreaseMethod::Chaikin, 3.0, &inc);
        assert_eq!(c, 0.75 * 3.0 + 0.25 * 1.0 - 1.0);
        // A lone semi-sharp edge just decrements.
        assert_eq!(
            subdivide_edge_sharpness(CreaseMethod::Chaikin, 2.5, &[2.5, 0.0]),
            1.5
        );
        assert_eq!(
            subdivide_edge_sharpness(CreaseMethod::Uniform, 3.0, &inc),
            2.0
        );
    }

    #[test]
    fn fractional_weight_is_average_of_decaying_features() {
        let w = fractional_weight(CreaseMethod::Uniform, 0.0, 0.0, &[0.5, 0.25, 3.0, 0.0], &[]);
        assert_eq!(w, 0.375);
        assert_eq!(
            fractional_weight(CreaseMethod::Uniform, 0.0, 0.0, &[2.0, 3.0], &[]),
            0.0
        );
        // Parent vertex sharpness that decays counts too, and the result is clamped to 1.
        assert_eq!(
            fractional_weight(CreaseMethod::Uniform, 0.75, 0.0, &[1.0], &[]),
            0.875
        );
        assert_eq!(
            fractional_weight(CreaseMethod::Chaikin, 0.0, 0.0, &[1.5, 2.0], &[0.0, 1.0]),
            1.0
        );
    }

    #[test]
    fn crease_ends_are_first_and_last_sharp() {
        assert_eq!(crease_ends(&[0.0, 2.0, 0.0, 10.0]), (1, 3));
    }
}
