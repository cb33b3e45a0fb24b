//! The classification of sharpness values (OpenSubdiv's `Sdc::Crease`), in `f32` as
//! OpenSubdiv computes it: `s <= 0` smooth, `0 < s < 10` semi-sharp, `s >= 10`
//! infinitely sharp; and the rule of a vertex from its sharpness and its sharp edges.
//! Public as `scheme::crease`, with the rules of refining sharpness.

use super::Rule;

pub(crate) use super::SHARPNESS_INFINITE;

/// `s > 0`.
#[inline]
pub(crate) fn is_sharp(s: f32) -> bool {
    s > 0.0
}

/// `s <= 0`.
#[inline]
pub(crate) fn is_smooth(s: f32) -> bool {
    s <= 0.0
}

/// `s >= 10`.
#[inline]
pub(crate) fn is_infinite(s: f32) -> bool {
    s >= SHARPNESS_INFINITE
}

/// `0 < s < 10`.
#[inline]
pub(crate) fn is_semi_sharp(s: f32) -> bool {
    s > 0.0 && s < SHARPNESS_INFINITE
}

/// Rule of a vertex with sharpness `vertex_sharpness` and `sharp_edges` incident sharp
/// edges: sharp vertex or more than two sharp edges → corner; else smooth, dart, crease
/// for 0, 1, 2 sharp edges.
#[inline]
pub(crate) fn vertex_rule(vertex_sharpness: f32, sharp_edges: usize) -> Rule {
    if is_sharp(vertex_sharpness) {
        return Rule::Corner;
    }
    match sharp_edges {
        0 => Rule::Smooth,
        1 => Rule::Dart,
        2 => Rule::Crease,
        _ => Rule::Corner,
    }
}
