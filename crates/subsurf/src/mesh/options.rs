//! Scheme options that apply to a whole mesh (OpenSubdiv's `Sdc::Options`).

use std::fmt;
use std::str::FromStr;

/// How boundary vertices are interpolated (OpenSubdiv's `VtxBoundaryInterpolation`).
///
/// In all modes boundary *edges* are infinitely sharp (the boundary curve is a cubic
/// B-spline of the boundary polygon), exactly as in OpenSubdiv.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BoundaryInterpolation {
    /// `VTX_BOUNDARY_NONE`: faces at a boundary vertex whose boundary edges are not all
    /// explicitly infinitely sharp are holes: they shape their neighbours but are not part
    /// of the surface and are not written. OBJ tag `t interpolateboundary 1/0/0 0`.
    None,
    /// `VTX_BOUNDARY_EDGE_AND_CORNER`: like [`EdgeOnly`](Self::EdgeOnly), and boundary
    /// vertices with a single incident face (corners) are infinitely sharp: they stay put.
    /// OBJ tag value 1.
    EdgeAndCorner,
    /// `VTX_BOUNDARY_EDGE_ONLY` (the default): boundary edges are sharp creases, corners
    /// are smooth crease vertices. OBJ tag value 2.
    #[default]
    EdgeOnly,
}

impl BoundaryInterpolation {
    /// The value of OpenSubdiv's `t interpolateboundary` tag: 0 none, 1 edge-and-corner,
    /// 2 edge-only.
    pub fn from_tag_value(v: i64) -> Option<Self> {
        match v {
            0 => Some(Self::None),
            1 => Some(Self::EdgeAndCorner),
            2 => Some(Self::EdgeOnly),
            _ => None,
        }
    }

    /// Inverse of [`from_tag_value`](Self::from_tag_value).
    pub fn tag_value(self) -> i64 {
        match self {
            Self::None => 0,
            Self::EdgeAndCorner => 1,
            Self::EdgeOnly => 2,
        }
    }
}

impl FromStr for BoundaryInterpolation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(Self::None),
            "edge-and-corner" | "corner" => Ok(Self::EdgeAndCorner),
            "edge-only" | "edge" => Ok(Self::EdgeOnly),
            _ => Err(format!(
                "unknown boundary mode '{s}' (expected edge-only, edge-and-corner or none)"
            )),
        }
    }
}

impl fmt::Display for BoundaryInterpolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::None => "none",
            Self::EdgeAndCorner => "edge-and-corner",
            Self::EdgeOnly => "edge-only",
        })
    }
}

/// How semi-sharp edge sharpness decays from one level to the next
/// (OpenSubdiv's `CreasingMethod`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CreaseMethod {
    /// `CREASE_UNIFORM`: every sharpness decreases by 1 per level.
    #[default]
    Uniform,
    /// `CREASE_CHAIKIN`: at a vertex with several semi-sharp edges, each child edge takes
    /// `0.75 s + 0.25 avg(other semi-sharp s) - 1` (infinitely sharp and smooth
    /// neighbours do not enter the average). OBJ tag `t creasemethod 0/0/1 chaikin`.
    Chaikin,
}

impl FromStr for CreaseMethod {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "uniform" | "normal" => Ok(Self::Uniform),
            "chaikin" => Ok(Self::Chaikin),
            _ => Err(format!(
                "unknown crease method '{s}' (expected uniform or chaikin)"
            )),
        }
    }
}

impl fmt::Display for CreaseMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Uniform => "uniform",
            Self::Chaikin => "chaikin",
        })
    }
}

/// The rule for edges next to triangles (OpenSubdiv's `TriangleSubdivision`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TriangleSubdivision {
    /// `TRI_SUB_CATMARK`: triangles are ordinary 3-sided faces.
    #[default]
    Catmark,
    /// `TRI_SUB_SMOOTH`: the edge-point face weight of a triangle is 0.47 instead of 0.25,
    /// which rounds triangle-heavy regions. OBJ tag `t smoothtriangles 0/0/1 smooth`.
    Smooth,
}

impl FromStr for TriangleSubdivision {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "catmark" => Ok(Self::Catmark),
            "smooth" => Ok(Self::Smooth),
            _ => Err(format!(
                "unknown triangle rule '{s}' (expected catmark or smooth)"
            )),
        }
    }
}

impl fmt::Display for TriangleSubdivision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Catmark => "catmark",
            Self::Smooth => "smooth",
        })
    }
}

/// Where face-varying data (texture coordinates) is interpolated linearly instead of
/// smoothly: OpenSubdiv's `Sdc::Options::FVarLinearInterpolation`, in its order, from
/// completely smooth to completely linear. "Corners" are face-varying boundary values
/// with a single face; "boundaries" are all face-varying boundaries (seams and mesh
/// boundaries). Where face-varying data is continuous and away from boundaries, every mode
/// but [`All`](Self::All) uses the vertex rules. OBJ tag
/// `t facevaryinginterpolateboundary 1/0/0 K`, `K` = 0..5 in the order below.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FaceVaryingInterpolation {
    /// `FVAR_LINEAR_NONE`: smooth everywhere; boundaries are cubic B-spline creases and
    /// corners are smooth (Hbr's "edge only").
    None,
    /// `FVAR_LINEAR_CORNERS_ONLY`: sharpen corners only.
    CornersOnly,
    /// `FVAR_LINEAR_CORNERS_PLUS1`: sharpen corners, junctions of three or more regions,
    /// and the two values of a vertex when either has an infinitely sharp or
    /// discontinuous edge inside its span (Hbr's "edge and corner").
    CornersPlus1,
    /// `FVAR_LINEAR_CORNERS_PLUS2`: like [`CornersPlus1`](Self::CornersPlus1), and both
    /// values of a vertex when one of them is a corner, and darts (Hbr's "edge and corner"
    /// with "propagate corners").
    CornersPlus2,
    /// `FVAR_LINEAR_BOUNDARIES`: linear along every face-varying boundary (Hbr's
    /// "always sharp").
    Boundaries,
    /// `FVAR_LINEAR_ALL` (the default): linear everywhere (bilinear refinement of the
    /// values).
    #[default]
    All,
}

impl FaceVaryingInterpolation {
    /// Every mode, in the order of the OBJ tag's value.
    pub const ALL_MODES: [Self; 6] = [
        Self::None,
        Self::CornersOnly,
        Self::CornersPlus1,
        Self::CornersPlus2,
        Self::Boundaries,
        Self::All,
    ];

    /// The mode of OpenSubdiv's `t facevaryinginterpolateboundary` tag value (0 none ..
    /// 5 all).
    pub fn from_tag_value(v: i64) -> Option<Self> {
        usize::try_from(v)
            .ok()
            .and_then(|i| Self::ALL_MODES.get(i).copied())
    }

    /// Inverse of [`from_tag_value`](Self::from_tag_value).
    pub fn tag_value(self) -> i64 {
        Self::ALL_MODES.iter().position(|&m| m == self).unwrap_or(5) as i64
    }
}

impl FromStr for FaceVaryingInterpolation {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL_MODES
            .iter()
            .copied()
            .find(|m| m.to_string() == s)
            .ok_or_else(|| {
                format!(
                    "unknown face-varying mode '{s}' (expected none, corners-only, corners-plus1, corners-plus2, boundaries or all)"
                )
            })
    }
}

impl fmt::Display for FaceVaryingInterpolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::None => "none",
            Self::CornersOnly => "corners-only",
            Self::CornersPlus1 => "corners-plus1",
            Self::CornersPlus2 => "corners-plus2",
            Self::Boundaries => "boundaries",
            Self::All => "all",
        })
    }
}

/// Scheme options of a mesh (OpenSubdiv's `Sdc::Options`, Catmull-Clark scheme).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Options {
    /// Boundary vertex interpolation.
    pub boundary: BoundaryInterpolation,
    /// Decay of semi-sharp creases.
    pub crease_method: CreaseMethod,
    /// Edge rule next to triangles.
    pub triangles: TriangleSubdivision,
    /// Linear interpolation of face-varying data ([`crate::mesh::FaceVarying`]).
    pub face_varying: FaceVaryingInterpolation,
}
