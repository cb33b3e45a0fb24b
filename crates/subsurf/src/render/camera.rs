//! The orbit camera: looks at a centre from azimuth/elevation, perspective, fitted to a
//! bounding sphere.

use crate::geom::{self, V3};
use crate::io::Up;

/// Field of view across the narrower side of the viewport, in degrees.
pub(crate) const FOV_DEGREES: f64 = 30.0;
/// Extra distance so that the bounding sphere does not touch the picture's edges.
const MARGIN: f64 = 1.12;

/// The area of the picture the surface is framed in (from its top-left corner), in pixels.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Viewport {
    pub width: f64,
    pub height: f64,
}

/// A point projected to the picture: `x` right and `y` down in pixels (times the
/// supersampling factor), and `inv_w` the reciprocal of its distance along the view axis
/// (affine in screen space, so it interpolates linearly; larger is nearer).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Projected {
    pub x: f64,
    pub y: f64,
    pub inv_w: f64,
}

/// A perspective camera. View space: `x` right, `y` up, `z` toward the viewer (the camera
/// looks along `−z`), eye at the origin.
#[derive(Clone, Debug)]
pub(crate) struct Camera {
    eye: V3,
    right: V3,
    up: V3,
    back: V3,
    /// Pixels per unit of `x / depth`.
    focal: f64,
    /// Picture position of the view axis, pixels.
    cx: f64,
    cy: f64,
}

impl Camera {
    /// Looks at `centre` from `view = (azimuth, elevation)` degrees, far enough away that
    /// the sphere of `radius` around `centre` fits the viewport, magnified `zoom` times.
    ///
    /// With `Up::Z`, azimuth 0 and elevation 0 put the eye on the `−Y` side looking along
    /// `+Y` (`X` to the right, `Z` up), the usual "front" view; azimuth 90 puts it on `+X`.
    /// With `Up::Y` the eye is on `+Z` looking along `−Z` (`X` right, `Y` up).
    pub(super) fn orbit(
        centre: V3,
        radius: f64,
        view: (f64, f64),
        up: Up,
        vp: Viewport,
        zoom: f64,
    ) -> Self {
        let (x, back, top) = match up {
            Up::Z => ([1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
            Up::Y => ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        };
        let (az, el) = (view.0.to_radians(), view.1.to_radians());
        let comb = |a: f64, u: &V3, b: f64, v: &V3, c: f64, w: &V3| {
            [0, 1, 2].map(|i| a * u[i] + b * v[i] + c * w[i])
        };
        // Unit vector from the centre to the eye.
        let dir = comb(
            az.sin() * el.cos(),
            &x,
            az.cos() * el.cos(),
            &back,
            el.sin(),
            &top,
        );
        // Horizontal, never degenerate (also looking straight down).
        let right = comb(az.cos(), &x, -az.sin(), &back, 0.0, &top);
        let forward = dir.map(|c| -c);
        let up = geom::cross(&right, &forward);
        let half = (FOV_DEGREES / 2.0).to_radians();
        let radius = if radius > 0.0 && radius.is_finite() {
            radius
        } else {
            1.0
        };
        let distance = MARGIN * radius / half.sin();
        let eye = [0, 1, 2].map(|i| centre[i] + distance * dir[i]);
        let focal = zoom * 0.5 * vp.width.min(vp.height) / half.tan();
        Self {
            eye,
            right,
            up,
            back: dir,
            focal,
            cx: 0.5 * vp.width,
            cy: 0.5 * vp.height,
        }
    }

    /// `p` in view space.
    pub(super) fn to_view(&self, p: &V3) -> V3 {
        let d = geom::sub(p, &self.eye);
        [
            geom::dot(&d, &self.right),
            geom::dot(&d, &self.up),
            geom::dot(&d, &self.back),
        ]
    }

    /// A view-space direction.
    pub(super) fn dir_to_view(&self, n: &V3) -> V3 {
        [
            geom::dot(n, &self.right),
            geom::dot(n, &self.up),
            geom::dot(n, &self.back),
        ]
    }

    /// Projects a view-space point, in pixels times `scale`; `None` behind (or too near)
    /// the eye.
    pub(super) fn project_view(&self, v: &V3, scale: f64) -> Option<Projected> {
        let depth = -v[2];
        if !(depth > 0.0 && depth.is_finite()) {
            return None;
        }
        let inv_w = 1.0 / depth;
        Some(Projected {
            x: scale * (self.cx + self.focal * v[0] * inv_w),
            y: scale * (self.cy - self.focal * v[1] * inv_w),
            inv_w,
        })
    }

    /// Projects a world point (see [`Camera::project_view`]).
    pub(super) fn project(&self, p: &V3, scale: f64) -> Option<Projected> {
        self.project_view(&self.to_view(p), scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_view_z_up() {
        let vp = Viewport {
            width: 200.0,
            height: 100.0,
        };
        let c = Camera::orbit([0.0; 3], 1.0, (0.0, 0.0), Up::Z, vp, 1.0);
        // The centre lands in the middle; +X to the right, +Z up (y down in pixels).
        let o = c.project(&[0.0; 3], 1.0).unwrap();
        assert!((o.x - 100.0).abs() < 1e-9 && (o.y - 50.0).abs() < 1e-9);
        let px = c.project(&[0.5, 0.0, 0.0], 1.0).unwrap();
        let pz = c.project(&[0.0, 0.0, 0.5], 1.0).unwrap();
        assert!(px.x > o.x && (px.y - o.y).abs() < 1e-9);
        assert!(pz.y < o.y && (pz.x - o.x).abs() < 1e-9);
        // -Y is nearer than +Y.
        let near = c.project(&[0.0, -0.5, 0.0], 1.0).unwrap();
        let far = c.project(&[0.0, 0.5, 0.0], 1.0).unwrap();
        assert!(near.inv_w > far.inv_w);
        // The unit sphere fits: its top is inside the picture.
        assert!(pz.y > 0.0 && c.project(&[0.0, 0.0, 1.0], 1.0).unwrap().y > 0.0);
    }

    #[test]
    fn looking_straight_down_is_not_degenerate() {
        let vp = Viewport {
            width: 100.0,
            height: 100.0,
        };
        for up in [Up::Z, Up::Y] {
            let c = Camera::orbit([0.0; 3], 1.0, (30.0, 90.0), up, vp, 1.0);
            let p = c.project(&[0.2, 0.3, 0.1], 1.0).unwrap();
            assert!(p.x.is_finite() && p.y.is_finite());
        }
    }
}
