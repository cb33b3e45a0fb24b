//! The whole check: local and global certificates for every face, and the sampled ground
//! truth, in one [`RegularityReport`].

use std::collections::BTreeSet;

use rayon::prelude::*;

use super::cone::{is_zero, test_cones, ConeTest, Difference, Dimension, Obstruction, Witness};
use super::error::RegularityError;
use super::exact::Sign;
use super::frame::{local_differences, Frames, NoFrame};
use super::neighbourhood::{block, Block, Inapplicable};
use super::sample::{sample_faces, Sampled};
use crate::limit::LimitSurface;
use crate::mesh::{Options, PolyMesh, Topology};

/// Which certificate decides.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Theorem 3: one u-cone and one v-cone per connected component of the net.
    #[default]
    Global,
    /// The cones of each face's 4×4 patch neighbourhood.
    Local,
}

/// What to check.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegularityOptions {
    /// Scheme options (boundary interpolation decides which corners are regular).
    pub scheme: Options,
    /// Planar or spatial; `None`: planar exactly when every `z` is 0.
    pub dimension: Option<Dimension>,
    /// Samples per side of each face for the ground truth (`0`: no sampling; else at least 2).
    pub samples: usize,
}

impl Default for RegularityOptions {
    fn default() -> Self {
        Self {
            scheme: Options::default(),
            dimension: None,
            samples: 9,
        }
    }
}

/// Why a face that the certificate applies to is not certified.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Refusal {
    /// An edge of the face has zero length.
    ZeroEdge(Difference),
    /// The cones meet (or are not pointed).
    Cones(Obstruction),
    /// Planar: the Jacobian has a strict sign, but the opposite of the mesh's orientation
    /// (the face is folded over relative to the rest).
    Orientation,
    /// Global only: the net has no consistent `(i, j)` labelling.
    NoFrame(NoFrame),
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::ZeroEdge(d) => write!(f, "edge {d} has zero length"),
            Self::Cones(o) => write!(f, "{o}"),
            Self::Orientation => write!(
                f,
                "the Jacobian has the sign opposite to the mesh's orientation"
            ),
            Self::NoFrame(e) => write!(f, "{e}"),
        }
    }
}

/// A face's certificate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Certificate {
    /// The limit surface is regular on the whole face.
    Certified(Witness),
    /// The certificate applies but does not hold.
    Refused(Refusal),
    /// The certificate does not apply to the face.
    NotApplicable(Inapplicable),
}

impl std::fmt::Display for Certificate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Certified(_) => write!(f, "certified"),
            Self::Refused(r) => write!(f, "refused: {r}"),
            Self::NotApplicable(i) => write!(f, "not applicable: {i}"),
        }
    }
}

impl Certificate {
    /// Whether the face is certified.
    pub fn is_certified(&self) -> bool {
        matches!(self, Self::Certified(_))
    }
}

/// The verdict on one face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceReport {
    /// The face.
    pub face: u32,
    /// Certificate from the face's own patch neighbourhood.
    pub local: Certificate,
    /// Certificate from the global cones of the face's component.
    pub global: Certificate,
    /// The sampled ground truth (`None` when not sampled, or for holes and non-quads).
    pub sampled: Option<Sampled>,
}

/// A face's class, comparing a certificate with the samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Class {
    /// Certified, and every sample regular.
    Certified,
    /// Not certified (refused or not applicable), every sample regular.
    RegularNotCertified,
    /// Not certified, and a sample is singular or folded.
    NotRegular,
    /// Not sampled; certified or not.
    Unsampled,
    /// Certified but a sample is singular: must never happen (a certificate error or a
    /// sample at the tolerance).
    Contradiction,
}

/// Numbers of faces per class (and of faces the certificate does not apply to).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Certified faces.
    pub certified: usize,
    /// Refused faces (the certificate applies).
    pub refused: usize,
    /// Faces the certificate does not apply to.
    pub not_applicable: usize,
    /// Sampled regular but not certified.
    pub regular_not_certified: usize,
    /// Sampled not regular.
    pub not_regular: usize,
    /// Certified but sampled not regular (always 0 unless something is wrong).
    pub contradictions: usize,
}

/// Everything [`check_regularity`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct RegularityReport {
    /// Planar or spatial.
    pub dimension: Dimension,
    /// Planar: the sign of the net's total signed area, which a certified Jacobian must
    /// have (`Positive` for spatial nets).
    pub orientation: Sign,
    /// Per face.
    pub faces: Vec<FaceReport>,
    /// The global labelling, or why there is none.
    pub frames: Result<Frames, NoFrame>,
    /// Per component of the labelling: its u- and v-differences and the cone test.
    pub components: Vec<ComponentCones>,
    /// Samples per side of each face (0: not sampled).
    pub samples: usize,
}

/// The global cones of one connected component.
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentCones {
    /// All u-differences (each edge once).
    pub u: Vec<Difference>,
    /// All v-differences.
    pub v: Vec<Difference>,
    /// Their cone test.
    pub test: ConeTest,
}

impl RegularityReport {
    /// The certificate of `face` in `mode`.
    pub fn certificate(&self, face: usize, mode: Mode) -> &Certificate {
        match mode {
            Mode::Global => &self.faces[face].global,
            Mode::Local => &self.faces[face].local,
        }
    }

    /// Whether every face is certified in `mode` (and there is at least one face).
    pub fn certified(&self, mode: Mode) -> bool {
        !self.faces.is_empty()
            && (0..self.faces.len()).all(|f| self.certificate(f, mode).is_certified())
    }

    /// The class of `face` in `mode`.
    pub fn class(&self, face: usize, mode: Mode) -> Class {
        let certified = self.certificate(face, mode).is_certified();
        match (certified, self.faces[face].sampled.map(|s| s.is_regular())) {
            (_, None) => Class::Unsampled,
            (true, Some(true)) => Class::Certified,
            (true, Some(false)) => Class::Contradiction,
            (false, Some(true)) => Class::RegularNotCertified,
            (false, Some(false)) => Class::NotRegular,
        }
    }

    /// Face counts in `mode`.
    pub fn counts(&self, mode: Mode) -> Counts {
        let mut c = Counts::default();
        for f in 0..self.faces.len() {
            match self.certificate(f, mode) {
                Certificate::Certified(_) => c.certified += 1,
                Certificate::Refused(_) => c.refused += 1,
                Certificate::NotApplicable(_) => c.not_applicable += 1,
            }
            match self.class(f, mode) {
                Class::RegularNotCertified => c.regular_not_certified += 1,
                Class::NotRegular => c.not_regular += 1,
                Class::Contradiction => c.contradictions += 1,
                Class::Certified | Class::Unsampled => {}
            }
        }
        c
    }

    /// Faces certified by their local cones but not by the global ones.
    pub fn local_only(&self) -> usize {
        self.faces
            .iter()
            .filter(|f| f.local.is_certified() && !f.global.is_certified())
            .count()
    }
}

/// The u- and v-differences of a patch neighbourhood: every pair of horizontally
/// (vertically) adjacent real cells, oriented along `u` (`v`).
pub(super) fn block_differences(b: &Block) -> (Vec<Difference>, Vec<Difference>) {
    let mut u = Vec::with_capacity(12);
    let mut v = Vec::with_capacity(12);
    for i in 0..4 {
        for j in 0..4 {
            if let Some(from) = b.cells[i][j] {
                if let Some(to) = b.cells.get(i + 1).and_then(|c| c[j]) {
                    u.push(Difference { from, to });
                }
                if let Some(&Some(to)) = b.cells[i].get(j + 1) {
                    v.push(Difference { from, to });
                }
            }
        }
    }
    (u, v)
}

/// The sign of the total signed area of the faces (x, y), `Positive` when zero.
fn planar_orientation(mesh: &PolyMesh) -> Sign {
    let p = mesh.positions();
    let mut area = 0.0;
    for f in mesh.faces() {
        for k in 0..f.len() {
            let (a, b) = (p[f[k] as usize], p[f[(k + 1) % f.len()] as usize]);
            area += a[0] * b[1] - a[1] * b[0];
        }
    }
    if area < 0.0 {
        Sign::Negative
    } else {
        Sign::Positive
    }
}

/// Certifies `mesh` face by face, globally and locally, and samples its limit surface
/// (see the [module docs](super)).
///
/// # Errors
/// [`RegularityError::Mesh`] for an invalid mesh; [`RegularityError::Eval`] if sampling fails.
pub fn check_regularity(
    mesh: &PolyMesh,
    options: &RegularityOptions,
) -> Result<RegularityReport, RegularityError> {
    check_regularity_with(mesh, options, None)
}

/// [`check_regularity`], sampling `surface` when given: the exact limit surface of `mesh`
/// under `options.scheme`, built by the caller (for example within a memory limit, by
/// [`LimitSurface::builder`]; faces it has no surface of are not sampled). `None`: built
/// here when `options.samples > 0`.
///
/// # Errors
/// As [`check_regularity`].
pub fn check_regularity_with(
    mesh: &PolyMesh,
    options: &RegularityOptions,
    surface: Option<&LimitSurface>,
) -> Result<RegularityReport, RegularityError> {
    mesh.validate()?;
    let (t, _) = Topology::from_mesh(mesh, &options.scheme)?;
    let pos = mesh.positions();
    let dimension = options.dimension.unwrap_or_else(|| {
        if pos.iter().all(|p| p[2] == 0.0) {
            Dimension::Planar
        } else {
            Dimension::Spatial
        }
    });
    let orientation = match dimension {
        Dimension::Planar => planar_orientation(mesh),
        Dimension::Spatial => Sign::Positive,
    };
    let prelim = local_certificates(&t, pos, dimension, orientation);
    // Global cones per component.
    let frames = Frames::new(&t);
    let components = match &frames {
        Ok(fr) => component_cones(&t, fr, pos, dimension),
        Err(_) => Vec::new(),
    };
    let sampled = sample_limit(
        mesh,
        options,
        surface,
        t.num_faces(),
        dimension,
        orientation,
    )?;
    let faces = prelim
        .into_iter()
        .enumerate()
        .map(|(f, p)| {
            let (local, global) = match p {
                Err(c) => (c, c),
                Ok(local) => {
                    let global = match &frames {
                        Err(e) => Certificate::Refused(Refusal::NoFrame(*e)),
                        Ok(fr) => verdict(components[fr.component[f] as usize].test, orientation),
                    };
                    (local, global)
                }
            };
            FaceReport {
                face: f as u32,
                local,
                global,
                sampled: sampled[f],
            }
        })
        .collect();
    Ok(RegularityReport {
        dimension,
        orientation,
        faces,
        frames,
        components,
        samples: if options.samples > 0 {
            options.samples.max(2)
        } else {
            0
        },
    })
}

/// The certificate a cone test gives ([Wang et al. 2016], Theorem 3): certified when the
/// cones are disjoint (a planar witness only with the mesh's `orientation`), refused when
/// they meet.
fn verdict(test: ConeTest, orientation: Sign) -> Certificate {
    match test {
        ConeTest::Disjoint(w @ Witness::Planar { orientation: o }) => {
            if o == orientation {
                Certificate::Certified(w)
            } else {
                Certificate::Refused(Refusal::Orientation)
            }
        }
        ConeTest::Disjoint(w) => Certificate::Certified(w),
        ConeTest::Meet(o) => Certificate::Refused(Refusal::Cones(o)),
    }
}

/// Per face, the local certificate from its patch neighbourhood's cones ([Wang et al. 2016],
/// Theorem 3 on the face's own differences; see the module documentation) (`Ok`), or the
/// certificate that settles the face locally and globally (`Err`: no applicable
/// neighbourhood, or a zero edge of the face itself).
fn local_certificates(
    t: &Topology,
    pos: &[[f64; 3]],
    dimension: Dimension,
    orientation: Sign,
) -> Vec<Result<Certificate, Certificate>> {
    (0..t.num_faces())
        .into_par_iter()
        .map(|f| {
            let b = block(t, f).map_err(Certificate::NotApplicable)?;
            let (fu, fv) = local_differences(t.face_vertices(f), 0);
            if let Some(&d) = fu.iter().chain(&fv).find(|&&d| is_zero(pos, d, dimension)) {
                return Err(Certificate::Refused(Refusal::ZeroEdge(d)));
            }
            let (u, v) = block_differences(&b);
            Ok(verdict(test_cones(pos, dimension, &u, &v), orientation))
        })
        .collect()
}

/// The global cones of every connected component (in the frames `fr`): the sets of `u` and
/// `v` differences of all its faces, and their cone test ([Wang et al. 2016], Theorem 3).
fn component_cones(
    t: &Topology,
    fr: &Frames,
    pos: &[[f64; 3]],
    dimension: Dimension,
) -> Vec<ComponentCones> {
    let mut sets = vec![(BTreeSet::new(), BTreeSet::new()); fr.num_components];
    for f in 0..t.num_faces() {
        let (u, v) = fr.face_differences(t, f);
        let c = fr.component[f] as usize;
        sets[c].0.extend(u);
        sets[c].1.extend(v);
    }
    sets.into_par_iter()
        .map(|(u, v)| {
            let (u, v): (Vec<_>, Vec<_>) = (u.into_iter().collect(), v.into_iter().collect());
            let test = test_cones(pos, dimension, &u, &v);
            ComponentCones { u, v, test }
        })
        .collect()
}

/// The sampled ground truth of every face ([`sample_faces`] on `surface`, or on the limit
/// surface of `mesh` built here), scaled by the bounding-box diagonal; all `None` when
/// `options.samples` is 0.
fn sample_limit(
    mesh: &PolyMesh,
    options: &RegularityOptions,
    surface: Option<&LimitSurface>,
    num_faces: usize,
    dimension: Dimension,
    orientation: Sign,
) -> Result<Vec<Option<Sampled>>, RegularityError> {
    if options.samples == 0 {
        return Ok(vec![None; num_faces]);
    }
    let faces_list: Vec<u32> = (0..num_faces as u32).collect();
    let built;
    let surface = match surface {
        Some(s) => s,
        None => {
            built = LimitSurface::new(mesh, options.scheme)?;
            &built
        }
    };
    let scale = mesh.bounding_box().map_or(1.0, |(lo, hi)| {
        let d = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        d[0].hypot(d[1]).hypot(d[2])
    });
    Ok(sample_faces(
        surface,
        &faces_list,
        options.samples,
        dimension,
        orientation,
        scale,
    )?)
}
