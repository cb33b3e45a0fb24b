//! The cone test of Theorem 3 (with the correction explained in [`super`]): do the cone
//! of the u-differences and the cone of the v-differences meet only at the origin, and
//! can a non-negative combination of u-differences never be parallel to one of
//! v-differences?
//!
//! With `U`, `V` the sets of **non-zero** differences (zero differences add nothing to a
//! non-negative combination and are left out), the test passes when
//! - **planar**: every `a × b` (`a ∈ U`, `b ∈ V`) has the same strict sign `σ` — then
//!   `det(S_u, S_v) = Σ wₐ w_b (a × b)` has sign `σ` whenever some `wₐ w_b > 0`. Decided
//!   exactly from the two angular sectors ([`super::sector`]): both cones must be pointed
//!   and the four products of their extreme vectors must share a strict sign (by
//!   bilinearity the extremes decide every pair). This is equivalent to
//!   `cone(U) ∩ cone(V) = {0}` *and* `cone(U) ∩ −cone(V) = {0}`, with both pointed.
//! - **spatial**: there are planes `n`, `m` with `n · a > 0 > n · b` and `m · a > 0, m · b > 0`
//!   for all `a ∈ U`, `b ∈ V` ([`super::separation`], verified exactly). Then for
//!   non-trivial non-negative combinations `S_u`, `S_v`: `n · S_u > 0` and `m · S_u > 0`, so
//!   `S_u ≠ 0`; `S_v ≠ 0` likewise; `S_u = λ S_v` with `λ > 0` contradicts `n`, with `λ < 0`
//!   contradicts `m`. So `S_u × S_v ≠ 0`. By Gordan's theorem such `n` exists exactly when
//!   `cone(U)`, `cone(V)` are pointed and meet only at the origin, and `m` exactly when
//!   `cone(U)` and `−cone(V)` are pointed and meet only at the origin: the spatial test is
//!   the same condition as the planar one.

use super::exact::Sign;
use super::sector::{sector, Arrow, SectorError};
use super::separation::{separating_direction, Ray};

/// A difference vector of the control net: `position[to] − position[from]` (an edge,
/// oriented along `u` or `v`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Difference {
    /// Start vertex.
    pub from: u32,
    /// End vertex.
    pub to: u32,
}

/// Planar (`x, y`; the Jacobian determinant) or spatial (`x, y, z`; the normal).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dimension {
    /// Coordinates `x, y`; regular means `det(S_u, S_v) ≠ 0` with one sign.
    Planar,
    /// Coordinates `x, y, z`; regular means `S_u × S_v ≠ 0`.
    Spatial,
}

/// A parametric direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    /// Along `u`.
    U,
    /// Along `v`.
    V,
}

/// Proof that the cones are disjoint (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Witness {
    /// Every `a × b` has this sign: the sign of the Jacobian determinant.
    Planar {
        /// `Positive` or `Negative`.
        orientation: Sign,
    },
    /// `n · a > 0 > n · b` and `m · a > 0`, `m · b > 0` for all u-differences `a` and
    /// v-differences `b`.
    Spatial {
        /// Separates the u-cone from the v-cone.
        n: [f64; 3],
        /// Separates the u-cone from the opposite of the v-cone.
        m: [f64; 3],
    },
}

/// Why the cone test failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Obstruction {
    /// Planar: the differences of one direction span a half-plane or more (e.g. two
    /// opposite ones), so their combinations can vanish.
    NotPointed {
        /// Which cone.
        direction: Direction,
        /// Two of its differences that are opposite or span an angle ≥ π with the
        /// sector's other vectors.
        a: Difference,
        /// See `a`.
        b: Difference,
    },
    /// Planar: the u-difference `u` and v-difference `v` are parallel, or their cross
    /// product has the other sign than another pair's: the cones (or a cone and the other's
    /// opposite) meet.
    Meet {
        /// A u-difference.
        u: Difference,
        /// A v-difference.
        v: Difference,
    },
    /// Spatial: no plane separates the u-cone from the v-cone (`opposite == false`) or
    /// from the opposite of the v-cone (`opposite == true`).
    NoSeparatingPlane {
        /// Which of the two planes is missing.
        opposite: bool,
    },
    /// Every difference of this direction is zero: the tangent can vanish.
    Empty {
        /// Which cone.
        direction: Direction,
    },
    /// A sign could not be decided exactly (coordinates of magnitude near `1e-135` or
    /// below, see `super::exact`).
    Undecided,
}

impl std::fmt::Display for Difference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}→{}", self.from, self.to)
    }
}

impl std::fmt::Display for Obstruction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::NotPointed { direction, a, b } => write!(
                f,
                "the {}-differences span a half-plane or more ({a} and {b})",
                match direction {
                    Direction::U => "u",
                    Direction::V => "v",
                }
            ),
            Self::Meet { u, v } => write!(
                f,
                "the cones meet: u-difference {u} and v-difference {v} are parallel or on the wrong side"
            ),
            Self::NoSeparatingPlane { opposite: false } => {
                write!(f, "no plane separates the u-cone from the v-cone")
            }
            Self::NoSeparatingPlane { opposite: true } => {
                write!(f, "no plane separates the u-cone from the opposite of the v-cone")
            }
            Self::Empty { direction } => write!(
                f,
                "every {}-difference is zero",
                match direction {
                    Direction::U => "u",
                    Direction::V => "v",
                }
            ),
            Self::Undecided => write!(f, "undecided (coordinates below the exact range)"),
        }
    }
}

/// Outcome of the cone test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConeTest {
    /// The cones meet only at the origin, and not along opposite rays either.
    Disjoint(Witness),
    /// They do (or it could not be decided).
    Meet(Obstruction),
}

/// Whether `d` is exactly the zero vector in `dim`.
pub(crate) fn is_zero(pos: &[[f64; 3]], d: Difference, dim: Dimension) -> bool {
    let (a, b) = (pos[d.from as usize], pos[d.to as usize]);
    a[0] == b[0] && a[1] == b[1] && (dim == Dimension::Planar || a[2] == b[2])
}

/// The cone test on the differences `u` and `v` of `pos` (zero differences are skipped).
pub(crate) fn test_cones(
    pos: &[[f64; 3]],
    dim: Dimension,
    u: &[Difference],
    v: &[Difference],
) -> ConeTest {
    let keep = |ds: &[Difference]| -> Vec<Difference> {
        ds.iter()
            .copied()
            .filter(|&d| !is_zero(pos, d, dim))
            .collect()
    };
    let (u, v) = (keep(u), keep(v));
    for (ds, direction) in [(&u, Direction::U), (&v, Direction::V)] {
        if ds.is_empty() {
            return ConeTest::Meet(Obstruction::Empty { direction });
        }
    }
    match dim {
        Dimension::Planar => planar(pos, &u, &v),
        Dimension::Spatial => spatial(pos, &u, &v),
    }
}

fn arrow(pos: &[[f64; 3]], d: Difference) -> Arrow {
    let (a, b) = (pos[d.from as usize], pos[d.to as usize]);
    Arrow {
        from: [a[0], a[1]],
        to: [b[0], b[1]],
    }
}

fn planar(pos: &[[f64; 3]], u: &[Difference], v: &[Difference]) -> ConeTest {
    let extremes = |ds: &[Difference], direction| {
        let arrows: Vec<Arrow> = ds.iter().map(|&d| arrow(pos, d)).collect();
        match sector(&arrows) {
            Ok(Some((lo, hi))) => Ok(Some((ds[lo], ds[hi]))),
            Ok(None) => Ok(None),
            Err(SectorError::NotPointed { added, extreme }) => Err(Obstruction::NotPointed {
                direction,
                a: ds[extreme],
                b: ds[added],
            }),
            Err(SectorError::Undecided) => Err(Obstruction::Undecided),
        }
    };
    let su = match extremes(u, Direction::U) {
        Ok(s) => s,
        Err(o) => return ConeTest::Meet(o),
    };
    let sv = match extremes(v, Direction::V) {
        Ok(s) => s,
        Err(o) => return ConeTest::Meet(o),
    };
    let (Some((ul, uh)), Some((vl, vh))) = (su, sv) else {
        // An empty cone: its combinations are zero, nothing is certified.
        return ConeTest::Meet(Obstruction::Undecided);
    };
    let mut orientation = None;
    for a in [ul, uh] {
        for b in [vl, vh] {
            let Some(s) = arrow(pos, a).cross(&arrow(pos, b)) else {
                return ConeTest::Meet(Obstruction::Undecided);
            };
            if s == Sign::Zero || orientation.is_some_and(|o| o != s) {
                return ConeTest::Meet(Obstruction::Meet { u: a, v: b });
            }
            orientation = Some(s);
        }
    }
    match orientation {
        Some(orientation) => ConeTest::Disjoint(Witness::Planar { orientation }),
        None => ConeTest::Meet(Obstruction::Undecided),
    }
}

fn spatial(pos: &[[f64; 3]], u: &[Difference], v: &[Difference]) -> ConeTest {
    if u.is_empty() || v.is_empty() {
        return ConeTest::Meet(Obstruction::Undecided);
    }
    let rays = |negate_v: bool| -> Vec<Ray> {
        let ray = |d: Difference, negate| Ray {
            from: pos[d.from as usize],
            to: pos[d.to as usize],
            negate,
        };
        u.iter()
            .map(|&d| ray(d, false))
            .chain(v.iter().map(|&d| ray(d, negate_v)))
            .collect()
    };
    let Some(n) = separating_direction(&rays(true)) else {
        return ConeTest::Meet(Obstruction::NoSeparatingPlane { opposite: false });
    };
    let Some(m) = separating_direction(&rays(false)) else {
        return ConeTest::Meet(Obstruction::NoSeparatingPlane { opposite: true });
    };
    ConeTest::Disjoint(Witness::Spatial { n, m })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points: the origin, then the given vectors' end points; differences from 0.
    fn setup(
        us: &[[f64; 3]],
        vs: &[[f64; 3]],
    ) -> (Vec<[f64; 3]>, Vec<Difference>, Vec<Difference>) {
        let mut pos = vec![[0.0; 3]];
        let mut diff = |p: &[f64; 3]| {
            pos.push(*p);
            Difference {
                from: 0,
                to: pos.len() as u32 - 1,
            }
        };
        let u: Vec<_> = us.iter().map(&mut diff).collect();
        let v: Vec<_> = vs.iter().map(&mut diff).collect();
        (pos, u, v)
    }

    fn both(us: &[[f64; 3]], vs: &[[f64; 3]]) -> (ConeTest, ConeTest) {
        let (pos, u, v) = setup(us, vs);
        (
            test_cones(&pos, Dimension::Planar, &u, &v),
            test_cones(&pos, Dimension::Spatial, &u, &v),
        )
    }

    fn disjoint(t: ConeTest) -> bool {
        matches!(t, ConeTest::Disjoint(_))
    }

    #[test]
    fn separated_sectors_pass_with_the_jacobian_sign() {
        let (p, s) = both(
            &[[1.0, 0.0, 0.0], [1.0, 0.5, 0.0]],
            &[[0.0, 1.0, 0.0], [-0.5, 1.0, 0.0]],
        );
        assert_eq!(
            p,
            ConeTest::Disjoint(Witness::Planar {
                orientation: Sign::Positive
            })
        );
        assert!(disjoint(s));
        // Swapping u and v flips the Jacobian's sign.
        let (p, _) = both(&[[0.0, 1.0, 0.0]], &[[1.0, 0.0, 0.0]]);
        assert_eq!(
            p,
            ConeTest::Disjoint(Witness::Planar {
                orientation: Sign::Negative
            })
        );
    }

    #[test]
    fn sectors_that_just_touch_fail() {
        // A u-difference and a v-difference along the same ray.
        let (p, s) = both(
            &[[1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            &[[1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        );
        assert!(matches!(p, ConeTest::Meet(Obstruction::Meet { .. })));
        assert!(!disjoint(s));
        // Along opposite rays: the cones meet only at the origin (the paper's condition
        // holds) but S_u and S_v can be antiparallel, so the normal can vanish.
        let (p, s) = both(
            &[[1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            &[[-1.0, -1.0, 0.0], [-1.0, -2.0, 0.0]],
        );
        assert!(matches!(p, ConeTest::Meet(Obstruction::Meet { .. })));
        assert_eq!(
            s,
            ConeTest::Meet(Obstruction::NoSeparatingPlane { opposite: true })
        );
    }

    #[test]
    fn overlapping_sectors_fail() {
        let (p, s) = both(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[[1.0, 1.0, 0.0]]);
        assert!(matches!(p, ConeTest::Meet(Obstruction::Meet { .. })));
        assert_eq!(
            s,
            ConeTest::Meet(Obstruction::NoSeparatingPlane { opposite: false })
        );
    }

    #[test]
    fn a_cone_containing_the_origin_in_its_hull_fails() {
        // u-differences in opposite directions: their sum can be zero.
        let (p, s) = both(&[[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]], &[[0.0, 1.0, 0.0]]);
        assert!(matches!(
            p,
            ConeTest::Meet(Obstruction::NotPointed {
                direction: Direction::U,
                ..
            })
        ));
        assert!(!disjoint(s));
        // Three v-differences at 120°.
        let (p, _) = both(
            &[[1.0, 0.0, 0.0]],
            &[[0.0, 1.0, 0.0], [-0.866, -0.5, 0.0], [0.866, -0.5, 0.0]],
        );
        assert!(matches!(
            p,
            ConeTest::Meet(Obstruction::NotPointed {
                direction: Direction::V,
                ..
            })
        ));
    }

    #[test]
    fn zero_differences_are_left_out() {
        let (p, s) = both(
            &[[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
            &[[0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
        );
        assert!(disjoint(p) && disjoint(s));
        // Only zero differences: nothing spans the cone, nothing is certified.
        let (p, s) = both(&[[0.0, 0.0, 0.0]], &[[0.0, 1.0, 0.0]]);
        let empty = ConeTest::Meet(Obstruction::Empty {
            direction: Direction::U,
        });
        assert_eq!((p, s), (empty, empty));
    }

    #[test]
    fn spatial_cones_out_of_plane() {
        // u around +x, v around +y, both tilted up: separable by n = x − y, m = x + y.
        let (_, s) = both(
            &[[1.0, 0.1, 0.5], [1.0, -0.1, -0.5]],
            &[[0.1, 1.0, 0.5], [-0.1, 1.0, -0.5]],
        );
        let ConeTest::Disjoint(Witness::Spatial { n, m }) = s else {
            panic!("{s:?}")
        };
        assert!(n[0] > 0.0 && n[1] < 0.0 && m[0] > 0.0 && m[1] > 0.0);
        // A v-difference that is a positive combination of u-differences: the cones meet.
        let (_, s) = both(
            &[[1.0, 0.0, 1.0], [1.0, 0.0, -1.0]],
            &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        );
        assert_eq!(
            s,
            ConeTest::Meet(Obstruction::NoSeparatingPlane { opposite: false })
        );
    }
}
