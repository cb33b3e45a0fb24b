//! Reflection lines ("zebra stripes"): the surface as a mirror in an environment of
//! parallel light planes.
//!
//! The view ray `d` (eye to surface point) is reflected by the unit normal,
//! `r = d − 2 (d·n) n`, and the stripe is a function of the component of `r` along a fixed
//! axis `A` (fixed relative to the camera, tilted from the picture's vertical):
//! `cos(k π (r·A))`, white where positive and black where negative, with a short smooth
//! transition (the supersampling anti-aliases the rest). That is an environment of `k`
//! pairs of black and white bands, parallel planes seen in every direction: the stripes
//! never converge to a point (where `r` is along `±A` they close into rings around a solid
//! spot).
//!
//! Evaluated per sample from the interpolated normal, the stripes depend on the normal
//! only: where the normal jumps (a G0 kink, as along an infinitely sharp crease) the stripes
//! break; where the curvature jumps (G1 but not G2) they kink; on a G2 surface they bend
//! smoothly.

use crate::geom::{self, V3};

/// Stripe pairs across the range of `r·A`.
pub(crate) const STRIPES: f64 = 10.0;
/// Half-width of the black–white transition, in units of `cos(k π r·A)`.
const EDGE: f64 = 0.25;

/// The stripes' axis `A` in view space (x right, y up, z toward the viewer).
fn axis() -> V3 {
    geom::normalize_or_zero([0.45, 1.0, 0.25])
}

/// The stripe brightness in `[0, 1]` (0 black, 1 white) of a view-space surface point
/// seen along the unit direction `d` (from the eye) with unit normal `n`.
pub(crate) fn stripe(d: &V3, n: &V3) -> f64 {
    let dn = geom::dot(d, n);
    let r = [0, 1, 2].map(|k| d[k] - 2.0 * dn * n[k]);
    let x = geom::dot(&r, &axis()).clamp(-1.0, 1.0);
    smoothstep(-EDGE, EDGE, (STRIPES * std::f64::consts::PI * x).cos())
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stripes_alternate_as_the_normal_turns() {
        let d = [0.0, 0.0, -1.0];
        let values: Vec<f64> = (0..200)
            .map(|i| {
                let a = (i as f64 / 200.0 - 0.5) * 1.2;
                stripe(&d, &[a.sin(), 0.0, a.cos()])
            })
            .collect();
        assert!(values.contains(&0.0));
        assert!(values.contains(&1.0));
        assert!(values.iter().all(|v| (0.0..=1.0).contains(v)));
    }
}
