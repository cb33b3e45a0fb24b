//! [`Parameterization`]: OpenSubdiv's parameterisation of a face of any size, as its `Bfr`
//! evaluator lays it out (`Bfr::Parameterization`, OpenSubdiv 3.5, `bfr/parameterization.h`).
//!
//! A quad has one parameter domain, `[0, 1]²`. A face of any other size `n` has none of its
//! own: Catmull-Clark splits it into `n` quad *sub-faces* (the children of one step), and
//! `Bfr` (`Parameterization::QUAD_SUBFACES`) places them in one `(u, v)` plane as tiles of a
//! grid `u_dim = ⌈√n⌉` tiles wide: sub-face `j` is the tile in column `j mod u_dim` and row
//! `⌊j / u_dim⌋`, whose corner is the face's vertex `j`, and it covers the lower-left
//! quarter of its unit tile, `[c, c + ½] × [r, r + ½]` (the rest of the tile is a gap that
//! belongs to no sub-face). In the tile, `u` runs from vertex `j` toward the midpoint of edge
//! `j` (toward vertex `j + 1`), `v` toward the midpoint of edge `j − 1`, and `(c + ½, r + ½)`
//! is the face's centre. The sub-face's own *normalized* coordinates (Ptex's) are
//! `s = 2 (u − c)`, `t = 2 (v − r)` in `[0, 1]²`: those of [`SurfacePoint`]'s sub-face, the
//! quad child of the face at its vertex `j` ([`LimitSurface`]'s parametrisation). So a
//! derivative by `u` is twice the derivative by `s`.
//!
//! For example a triangle has `u_dim = 2`: its vertices are at `(0, 0)`, `(1, 0)`, `(0, 1)`,
//! its centre at `(0.5, 0.5)`, `(1.5, 0.5)` and `(0.5, 1.5)` in the three tiles; a pentagon
//! and up to a 9-gon have `u_dim = 3`, a 10- to 16-gon `u_dim = 4`.
//!
//! Checked against `Bfr::Parameterization::GetVertexCoord` for every face size from 3 to
//! 65 025 and `ConvertNormalizedSubFaceToCoord` for sizes 3 to 40 (OpenSubdiv 3.5). `Bfr`
//! keeps `u_dim` in 8 bits, so it has no parameterisation for faces of more than
//! 255² = 65 025 vertices (it divides by zero); this type continues the same formula
//! (`u_dim = 256` up to 65 536).
//!
//! [`LimitSurface`]: super::LimitSurface
//! [`SurfacePoint`]: super::SurfacePoint

/// The `(u, v)` layout of a face of `size` vertices (see the module `limit::param`).
///
/// ```
/// use subsurf::limit::Parameterization;
/// let tri = Parameterization::new(3);
/// assert!(tri.has_subfaces());
/// assert_eq!(tri.u_dim(), 2);
/// // Sub-face 2 of a triangle is the tile in row 1: its corner is vertex 2, at (0, 1),
/// // its far corner the face's centre.
/// assert_eq!(tri.to_face(2, 0.0, 0.0), (0.0, 1.0));
/// assert_eq!(tri.to_face(2, 1.0, 1.0), (0.5, 1.5));
/// assert_eq!(tri.to_subface(0.5, 1.5), Some((2, 1.0, 1.0)));
/// // A quad is its own domain.
/// let quad = Parameterization::new(4);
/// assert!(!quad.has_subfaces());
/// assert_eq!(quad.to_face(0, 0.25, 0.75), (0.25, 0.75));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parameterization {
    size: usize,
    u_dim: usize,
}

impl Parameterization {
    /// The parameterisation of a face of `size` vertices (a quad's for 4).
    pub fn new(size: usize) -> Self {
        let u_dim = if size == 4 { 1 } else { ceil_sqrt(size) };
        Self { size, u_dim }
    }

    /// The face's size.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Whether the face is split into sub-faces (every size but 4).
    pub fn has_subfaces(&self) -> bool {
        self.size != 4
    }

    /// Number of sub-faces: 1 for a quad, `size` otherwise (as
    /// [`LimitSurface::num_subfaces`](super::LimitSurface::num_subfaces)).
    pub fn num_subfaces(&self) -> usize {
        if self.has_subfaces() {
            self.size
        } else {
            1
        }
    }

    /// Tiles per row of the layout, `⌈√size⌉` (1 for a quad).
    pub fn u_dim(&self) -> usize {
        self.u_dim
    }

    /// The face's `(u, v)` of the point `(s, t)` (normalized, in `[0, 1]²`) of sub-face
    /// `sub`: `(c + s/2, r + t/2)` with `(c, r)` the sub-face's tile; `(s, t)` itself on a
    /// quad.
    pub fn to_face(&self, sub: usize, s: f64, t: f64) -> (f64, f64) {
        if !self.has_subfaces() {
            return (s, t);
        }
        let (c, r) = ((sub % self.u_dim) as f64, (sub / self.u_dim) as f64);
        (c + 0.5 * s, r + 0.5 * t)
    }

    /// The sub-face and its normalized `(s, t)` of the face's `(u, v)`, as `Bfr`'s
    /// `ConvertCoordToNormalizedSubFace` finds them: the tile of `(u, v)`, where a point
    /// more than ¾ across a tile belongs to the next tile (it lies in the gap, past the
    /// sub-face's side at ½); `(u, v)` itself on a quad. `None` if `(u, v)` is not finite
    /// or the tile is no sub-face of the face.
    pub fn to_subface(&self, u: f64, v: f64) -> Option<(usize, f64, f64)> {
        if !(u.is_finite() && v.is_finite()) {
            return None;
        }
        if !self.has_subfaces() {
            return Some((0, u, v));
        }
        let tile = |x: f64| {
            let f = x.floor();
            if x - f > 0.75 {
                f + 1.0
            } else {
                f
            }
        };
        let (c, r) = (tile(u), tile(v));
        if c < 0.0 || r < 0.0 || c >= self.u_dim as f64 {
            return None;
        }
        let sub = r as usize * self.u_dim + c as usize;
        (sub < self.size).then_some((sub, 2.0 * (u - c), 2.0 * (v - r)))
    }

    /// The factor from derivatives by the normalized `(s, t)` of a sub-face to derivatives
    /// by the face's `(u, v)`: 2 (a sub-face is half a tile wide), 1 on a quad. Second
    /// derivatives scale by its square.
    pub fn derivative_scale(&self) -> f64 {
        if self.has_subfaces() {
            2.0
        } else {
            1.0
        }
    }
}

/// `⌈√n⌉`, exactly (by integers).
fn ceil_sqrt(n: usize) -> usize {
    let mut r = (n as f64).sqrt() as usize;
    while r * r > n {
        r -= 1;
    }
    while r * r < n {
        r += 1;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tiles per row `Bfr::Parameterization` gives, as printed by OpenSubdiv 3.5 for
    /// face sizes 3 to 40 (`GetVertexCoord` of the last vertex).
    #[test]
    fn tiles_per_row_are_bfrs() {
        let bfr = [
            (3, 2),
            (5, 3),
            (9, 3),
            (10, 4),
            (16, 4),
            (17, 5),
            (25, 5),
            (26, 6),
            (36, 6),
            (37, 7),
            (65_025, 255),
            (65_026, 256),
            (65_535, 256),
        ];
        for (n, u_dim) in bfr {
            assert_eq!(Parameterization::new(n).u_dim(), u_dim, "size {n}");
        }
        assert_eq!(Parameterization::new(4).u_dim(), 1);
    }

    /// `Bfr`'s coordinates (OpenSubdiv 3.5, `ConvertNormalizedSubFaceToCoord` and
    /// `GetVertexCoord`), and the way back.
    #[test]
    fn sub_faces_map_to_bfrs_tiles_and_back() {
        // Normalized (1, 1) of sub-face 1 is the centre in tile (1, 0); (0.25, 0.75) of
        // the last sub-face of a 5-gon is in tile (1, 1), of a 7-gon in tile (0, 2).
        assert_eq!(Parameterization::new(5).to_face(1, 1.0, 1.0), (1.5, 0.5));
        assert_eq!(
            Parameterization::new(5).to_face(4, 0.25, 0.75),
            (1.125, 1.375)
        );
        assert_eq!(
            Parameterization::new(7).to_face(6, 0.25, 0.75),
            (0.125, 2.375)
        );
        assert_eq!(Parameterization::new(12).to_face(11, 0.0, 0.0), (3.0, 2.0));
        for n in [3, 5, 6, 9, 10, 17, 40] {
            let p = Parameterization::new(n);
            for sub in 0..n {
                for (s, t) in [(0.0, 0.0), (1.0, 1.0), (0.5, 0.25), (1.0, 0.0), (0.0, 1.0)] {
                    let (u, v) = p.to_face(sub, s, t);
                    assert_eq!(p.to_subface(u, v), Some((sub, s, t)), "{n} {sub} {s} {t}");
                }
            }
            // The gap past a sub-face's side, and tiles that are no sub-face.
            assert_eq!(p.to_subface(0.8, 0.0).map(|x| x.0), Some(1));
            assert_eq!(p.to_subface(-0.5, 0.0), None);
            let rows = n.div_ceil(p.u_dim());
            assert_eq!(p.to_subface(0.0, rows as f64), None);
        }
        assert_eq!(Parameterization::new(3).to_subface(1.0, 1.0), None);
        assert_eq!(Parameterization::new(3).to_subface(f64::NAN, 0.0), None);
    }
}
