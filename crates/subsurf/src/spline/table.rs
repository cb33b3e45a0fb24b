//! [`ValenceTable`]: the three sub-basis functions of one valence, tabulated once.
//!
//! Valences 3 to [`EAGER_MAX_VALENCE`] are computed together the first time any of them is
//! asked for and kept for the life of the process; larger valences are computed on request
//! (O(n) work) and cached per surface by [`super::SubBasisSurface`].

use super::subbasis::{Class, SubBasis};
use std::sync::{Arc, OnceLock};

/// The largest valence tabulated eagerly (process-wide, once).
pub const EAGER_MAX_VALENCE: usize = 16;

/// The class-1, class-2 and class-3 sub-basis functions of one valence.
#[derive(Clone, Debug, PartialEq)]
pub struct ValenceTable {
    /// Valence `n ≥ 3`.
    pub valence: usize,
    /// Class 1 ([`Class::Centre`]).
    pub centre: SubBasis,
    /// Class 2 ([`Class::Edge`]).
    pub edge: SubBasis,
    /// Class 3 ([`Class::Corner`]).
    pub corner: SubBasis,
}

impl ValenceTable {
    /// Computes the table of valence `n` (see [`SubBasis::new`]).
    ///
    /// # Panics
    /// If `n < 3`.
    pub fn compute(n: usize) -> Self {
        Self {
            valence: n,
            centre: SubBasis::new(n, Class::Centre),
            edge: SubBasis::new(n, Class::Edge),
            corner: SubBasis::new(n, Class::Corner),
        }
    }

    /// The function of `class`.
    pub fn get(&self, class: Class) -> &SubBasis {
        match class {
            Class::Centre => &self.centre,
            Class::Edge => &self.edge,
            Class::Corner => &self.corner,
        }
    }
}

static EAGER: OnceLock<Vec<Arc<ValenceTable>>> = OnceLock::new();

/// The table of valence `n` (`None` for `n < 3`): shared from the process-wide tabulation
/// for `3 ≤ n ≤ EAGER_MAX_VALENCE`, computed afresh otherwise.
pub fn valence_table(n: usize) -> Option<Arc<ValenceTable>> {
    if n < 3 {
        return None;
    }
    if n <= EAGER_MAX_VALENCE {
        let all = EAGER.get_or_init(|| {
            (3..=EAGER_MAX_VALENCE)
                .map(|n| Arc::new(ValenceTable::compute(n)))
                .collect()
        });
        return Some(all[n - 3].clone());
    }
    Some(Arc::new(ValenceTable::compute(n)))
}
