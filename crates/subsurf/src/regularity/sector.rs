//! Planar cones as angular sectors: the smallest sector (of opening below π) that holds a
//! set of non-zero plane vectors, found in one pass with exact predicates.
//!
//! A set of non-zero vectors spans a *pointed* cone (one that holds no line) exactly when
//! it fits in an open half-plane; the cone is then the sector between its two extreme
//! vectors `lo` and `hi` (`lo × hi ≥ 0`, counter-clockwise from `lo` to `hi`, opening
//! `< π`). A vector `g` is added to the sector `[lo, hi]` by these exact cases:
//! - inside: `lo × g ≥ 0`, `g × hi ≥ 0`, and (`lo × hi > 0` or `lo · g > 0`): unchanged;
//! - clockwise of it: `g × lo > 0` and `g × hi > 0`: the sector becomes `[g, hi]`;
//! - counter-clockwise of it: `lo × g > 0` and `hi × g > 0`: it becomes `[lo, g]`;
//! - otherwise the vectors span a half-plane or more (opposite vectors, or an opening of
//!   π or more): the set is not pointed.
//!
//! Greedy insertion is exact: the sector of a prefix is the smallest one holding it, so if
//! the whole set fits in an open half-plane, one of the first three cases applies at every
//! step.

use super::exact::{cross2_sign, dot2_sign, Sign};

/// A plane vector given by its two end points (the exact difference `to − from`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Arrow {
    /// Start point.
    pub from: [f64; 2],
    /// End point.
    pub to: [f64; 2],
}

impl Arrow {
    /// `self × other`, exactly.
    pub(crate) fn cross(&self, other: &Arrow) -> Option<Sign> {
        cross2_sign(self.from, self.to, other.from, other.to)
    }

    /// `self · other`, exactly.
    pub(crate) fn dot(&self, other: &Arrow) -> Option<Sign> {
        dot2_sign(self.from, self.to, other.from, other.to)
    }
}

/// Why a set of vectors has no sector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SectorError {
    /// The vectors with these indices (and the sector built so far) span a half-plane or
    /// more: the cone is not pointed.
    NotPointed {
        /// The vector that did not fit.
        added: usize,
        /// One extreme of the sector it did not fit in.
        extreme: usize,
    },
    /// A sign could not be decided exactly (see [`super::exact`]).
    Undecided,
}

/// The sector of `arrows` (all non-zero): indices of its clockwise and counter-clockwise
/// extremes `(lo, hi)`; `None` for an empty set.
pub(crate) fn sector(arrows: &[Arrow]) -> Result<Option<(usize, usize)>, SectorError> {
    if arrows.is_empty() {
        return Ok(None);
    }
    let (mut lo, mut hi) = (0usize, 0usize);
    let s = |x: Option<Sign>| x.ok_or(SectorError::Undecided);
    for (g, ga) in arrows.iter().enumerate().skip(1) {
        let (l, h) = (&arrows[lo], &arrows[hi]);
        let lo_g = s(l.cross(ga))?;
        let g_hi = s(ga.cross(h))?;
        let lo_hi = s(l.cross(h))?;
        let inside = lo_g != Sign::Negative
            && g_hi != Sign::Negative
            && (lo_hi == Sign::Positive || s(l.dot(ga))? == Sign::Positive);
        if inside {
            continue;
        }
        if lo_g == Sign::Negative && g_hi == Sign::Positive {
            lo = g;
        } else if lo_g == Sign::Positive && g_hi == Sign::Negative {
            hi = g;
        } else {
            let extreme = if lo_g == Sign::Negative { hi } else { lo };
            return Err(SectorError::NotPointed { added: g, extreme });
        }
    }
    Ok(Some((lo, hi)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arrow(x: f64, y: f64) -> Arrow {
        Arrow {
            from: [0.0, 0.0],
            to: [x, y],
        }
    }

    fn angle(a: &Arrow) -> f64 {
        (a.to[1] - a.from[1]).atan2(a.to[0] - a.from[0])
    }

    #[test]
    fn sector_of_a_fan_is_its_extreme_vectors() {
        let a = [
            arrow(1.0, 0.2),
            arrow(1.0, -0.5),
            arrow(0.3, 1.0),
            arrow(1.0, 0.0),
        ];
        assert_eq!(sector(&a), Ok(Some((1, 2))));
        assert_eq!(sector(&[]), Ok(None));
        assert_eq!(sector(&a[..1]), Ok(Some((0, 0))));
    }

    #[test]
    fn opposite_vectors_are_not_pointed() {
        let a = [arrow(1.0, 1.0), arrow(-2.0, -2.0)];
        assert!(matches!(sector(&a), Err(SectorError::NotPointed { .. })));
        // Parallel, same direction: a sector of opening 0.
        let b = [arrow(1.0, 1.0), arrow(3.0, 3.0)];
        assert_eq!(sector(&b), Ok(Some((0, 0))));
    }

    #[test]
    fn an_opening_of_exactly_pi_is_not_pointed() {
        let a = [arrow(1.0, 0.0), arrow(0.0, 1.0), arrow(-1.0, 0.0)];
        assert!(matches!(sector(&a), Err(SectorError::NotPointed { .. })));
        let b = [arrow(1.0, 0.0), arrow(-1.0, 1e-200), arrow(0.0, 1.0)];
        assert_eq!(sector(&b), Ok(Some((0, 1))), "just below π is pointed");
        // Below the exact range the sign is undecided, not guessed.
        let c = [arrow(1.0, 0.0), arrow(-1.0, 1e-300)];
        assert_eq!(sector(&c), Err(SectorError::Undecided));
    }

    #[test]
    fn greedy_sector_agrees_with_an_angular_brute_force() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..3000 {
            let n = 1 + (next() * 8.0) as usize;
            let centre = next() * std::f64::consts::TAU;
            let spread = next() * 4.0;
            let arrows: Vec<Arrow> = (0..n)
                .map(|_| {
                    let t = centre + (next() - 0.5) * spread;
                    let r = 0.1 + next();
                    Arrow {
                        from: [next(), next()],
                        to: [0.0, 0.0],
                    }
                    .with_direction(t, r)
                })
                .collect();
            // Brute force: pointed iff some vector's half-plane test leaves all others
            // strictly within π counter-clockwise of the clockwise extreme.
            let ang: Vec<f64> = arrows.iter().map(angle).collect();
            let pointed = (0..n).any(|i| {
                ang.iter().all(|&b| {
                    let d = (b - ang[i]).rem_euclid(std::f64::consts::TAU);
                    d < std::f64::consts::PI - 1e-9 || d.abs() < 1e-12
                })
            });
            let clear = (0..n).all(|i| {
                ang.iter().all(|&b| {
                    let d = (b - ang[i]).rem_euclid(std::f64::consts::TAU);
                    (d - std::f64::consts::PI).abs() > 1e-6
                })
            });
            if !clear {
                continue;
            }
            match sector(&arrows) {
                Ok(Some((lo, hi))) => {
                    assert!(pointed, "{ang:?}");
                    // Every vector lies counter-clockwise of lo and clockwise of hi.
                    for a in &arrows {
                        assert_ne!(arrows[lo].cross(a), Some(Sign::Negative));
                        assert_ne!(a.cross(&arrows[hi]), Some(Sign::Negative));
                    }
                }
                Ok(None) => unreachable!(),
                Err(_) => assert!(!pointed, "{ang:?}"),
            }
        }
    }

    impl Arrow {
        fn with_direction(self, t: f64, r: f64) -> Arrow {
            Arrow {
                from: self.from,
                to: [self.from[0] + r * t.cos(), self.from[1] + r * t.sin()],
            }
        }
    }
}
