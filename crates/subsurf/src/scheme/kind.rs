//! Which subdivision scheme refines a mesh: OpenSubdiv's `Sdc::SchemeType` and this
//! library's own schemes, as one parameter of every operation.

use std::fmt;

use super::adjustable::Mixed;

/// A subdivision scheme, the parameter that every operation takes
/// ([`subdivide`](fn@crate::subdivide), [`RefinePlan::new`](crate::refine::RefinePlan::new),
/// [`Reposer::new`](crate::Reposer::new), [`estimate_memory`](fn@crate::estimate_memory)).
/// The options that shape a scheme's rules (boundaries, creases, triangles) are
/// [`Options`](crate::mesh::Options), given beside it.
///
/// ```
/// use subsurf::scheme::Adjustable;
/// use subsurf::{Mixed, Scheme};
///
/// let cc = Scheme::default();
/// assert_eq!(cc, Scheme::CatmullClark);
/// // The shape-adjustable masks with c = 0.3 on the first two steps, Catmull-Clark after.
/// let adjusted = Scheme::Adjustable(Mixed { scheme: Adjustable::new(0.3)?, steps: 2 });
/// assert_eq!(adjusted.to_string(), "adjustable");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[non_exhaustive]
pub enum Scheme {
    /// Catmull-Clark (E. Catmull & J. Clark, "Recursively generated B-spline surfaces on
    /// arbitrary topological meshes", Computer-Aided Design 10(6), 1978) with OpenSubdiv's
    /// rules for boundaries, semi-sharp creases, corners, triangles and non-manifold
    /// topology (`Sdc::SCHEME_CATMARK`); masks in `catmark`.
    #[default]
    CatmullClark,
    /// The shape-adjustable scheme ([Tang et al. 2017], `adjustable`):
    /// its masks with parameter `c` on the first `steps` refinement steps, Catmull-Clark
    /// after ([`Mixed`]). Topology, numbering and sharpness are Catmull-Clark's; with
    /// `c = ½` the result is Catmull-Clark's.
    Adjustable(Mixed),
    /// Non-uniform Catmull-Clark (NURSS: T. W. Sederberg, J. Zheng, D. Sewell & M. Sabin,
    /// "Non-uniform recursive subdivision surfaces", SIGGRAPH 1998), with the mesh's knot
    /// intervals and weights ([`PolyMesh::knots`](crate::mesh::PolyMesh::knots); untagged
    /// edges have interval 1, when it is Catmull-Clark). Semi-sharp creases are refused
    /// ([`NurssError::SemiSharp`](crate::nonuniform::NurssError::SemiSharp)); masks in
    /// `nurss`.
    Nurss,
    /// Loop subdivision of triangle meshes (C. Loop, "Smooth subdivision surfaces based on
    /// triangles", M.S. thesis, University of Utah, 1987) with OpenSubdiv's rules for
    /// boundaries, creases, corners, non-manifold topology and face-varying data
    /// (`Sdc::SCHEME_LOOP`); masks in `loop_`. A face that is not a triangle is an error
    /// naming it.
    Loop,
    /// Bilinear subdivision (`Sdc::SCHEME_BILINEAR`): the Catmull-Clark split of any
    /// polygons with face centroids, edge midpoints and the vertices themselves, so the
    /// surface is the control mesh; masks in `bilinear`.
    Bilinear,
}

impl Scheme {
    /// The scheme's name as the command line spells it: `catmull-clark`, `adjustable`,
    /// `nurss`, `loop`, `bilinear`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::CatmullClark => "catmull-clark",
            Self::Adjustable(_) => "adjustable",
            Self::Nurss => "nurss",
            Self::Loop => "loop",
            Self::Bilinear => "bilinear",
        }
    }
}

impl fmt::Display for Scheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Any number of steps of the adjustable scheme: [`Scheme::Adjustable`].
impl From<Mixed> for Scheme {
    fn from(m: Mixed) -> Self {
        Self::Adjustable(m)
    }
}
