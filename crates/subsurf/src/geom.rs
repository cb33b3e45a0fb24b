//! Small 3-vector helpers shared by the geometry layers (one definition of each, so that
//! normals are computed the same way everywhere).

/// A point or vector in 3D.
pub(crate) type V3 = [f64; 3];

/// `a - b`.
#[inline]
pub(crate) fn sub(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a + b`.
#[inline]
pub(crate) fn add(a: &V3, b: &V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `s a`.
#[inline]
pub(crate) fn scale(a: &V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a · b`.
#[inline]
pub(crate) fn dot(a: &V3, b: &V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
#[inline]
pub(crate) fn cross(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `|a|`, without overflow or underflow for any finite `a` (scaled by its largest
/// component first).
#[inline]
pub(crate) fn norm(a: &V3) -> f64 {
    let m = a[0].abs().max(a[1].abs()).max(a[2].abs());
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let s = [a[0] / m, a[1] / m, a[2] / m];
    m * dot(&s, &s).sqrt()
}

/// `a / |a|`, or zero when `a` is zero or not finite; exact in direction for any finite
/// magnitude (tiny and huge vectors alike).
#[inline]
pub(crate) fn normalize_or_zero(a: V3) -> V3 {
    let m = a[0].abs().max(a[1].abs()).max(a[2].abs());
    if m == 0.0 || !m.is_finite() {
        return [0.0; 3];
    }
    let s = [a[0] / m, a[1] / m, a[2] / m];
    let n = dot(&s, &s).sqrt();
    [s[0] / n, s[1] / n, s[2] / n]
}

/// The unit vector along `a × b`, or zero when they are parallel (or zero, or not finite),
/// for any finite magnitudes: each factor is scaled by its largest component first, so
/// neither tiny nor huge vectors underflow or overflow.
pub(crate) fn unit_cross(a: &V3, b: &V3) -> V3 {
    let scaled = |v: &V3| {
        let m = v[0].abs().max(v[1].abs()).max(v[2].abs());
        if m > 0.0 && m.is_finite() {
            Some([v[0] / m, v[1] / m, v[2] / m])
        } else {
            None
        }
    };
    match (scaled(a), scaled(b)) {
        (Some(a), Some(b)) => normalize_or_zero(cross(&a, &b)),
        _ => [0.0; 3],
    }
}

/// Newell's normal of polygon `face` (not normalised; twice the vector area):
/// `n = Σ (yᵢ − yᵢ₊₁)(zᵢ + zᵢ₊₁), Σ (zᵢ − zᵢ₊₁)(xᵢ + xᵢ₊₁), Σ (xᵢ − xᵢ₊₁)(yᵢ + yᵢ₊₁)`,
/// with coordinates taken relative to the first vertex (the formula is
/// translation-invariant; this keeps the products small). Works for non-planar and
/// non-convex polygons.
pub(crate) fn newell_normal(positions: &[V3], face: &[u32]) -> V3 {
    let Some(&first) = face.first() else {
        return [0.0; 3];
    };
    let origin = positions[first as usize];
    let mut n = [0.0; 3];
    for (i, &v) in face.iter().enumerate() {
        let a = sub(&positions[v as usize], &origin);
        let b = sub(&positions[face[(i + 1) % face.len()] as usize], &origin);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newell_normal_of_a_unit_square_is_twice_its_area_along_z() {
        let p = [
            [0.0, 0.0, 5.0],
            [1.0, 0.0, 5.0],
            [1.0, 1.0, 5.0],
            [0.0, 1.0, 5.0],
        ];
        assert_eq!(newell_normal(&p, &[0, 1, 2, 3]), [0.0, 0.0, 2.0]);
        assert_eq!(newell_normal(&p, &[0, 3, 2, 1]), [0.0, 0.0, -2.0]);
    }

    #[test]
    fn cross_and_normalize() {
        assert_eq!(cross(&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(normalize_or_zero([0.0, 3.0, 4.0]), [0.0, 0.6, 0.8]);
        assert_eq!(normalize_or_zero([0.0; 3]), [0.0; 3]);
        assert_eq!(normalize_or_zero([f64::NAN, 0.0, 0.0]), [0.0; 3]);
        let n = normalize_or_zero([0.0, 3e-200, 4e-200]);
        assert!((n[1] - 0.6).abs() < 1e-15 && (n[2] - 0.8).abs() < 1e-15);
        let n = normalize_or_zero([0.0, 3e200, 4e200]);
        assert!((n[1] - 0.6).abs() < 1e-15 && (n[2] - 0.8).abs() < 1e-15);
        assert!((norm(&[0.0, 3e200, 4e200]) / 5e200 - 1.0).abs() < 1e-15);
    }
}
