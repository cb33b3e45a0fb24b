//! The patches of a [`G2Surface`] as Bézier control points ([`patches_json`]); its
//! tessellation is [`limit::tessellate`](crate::limit::tessellate)'s, as for every
//! [`Surface`](crate::limit::Surface).

use super::bezier::BezierPatch;
use super::surface::{G2Surface, PatchRef};
use super::G2Error;
use crate::json::{object, ToJson};
use crate::limit::SurfacePoint;
use crate::mesh::PolyMesh;
use rayon::prelude::*;

/// One patch of [`patches_json`].
#[derive(Clone, Debug)]
pub struct PatchJson {
    /// Base face.
    pub face: u32,
    /// Sub-face (0 for quads).
    pub subface: u32,
    /// The patch's square of the (sub-)face's parameter domain: `[u0, v0, u1, v1]`.
    pub domain: [f64; 4],
    /// For cap patches: the corner of the (sub-)face at the extraordinary vertex (the
    /// patch's `(0, 0)`), else `null`: then the patch's `(0, 0)` is `(u0, v0)` and `u`
    /// runs along the face's `u`.
    pub corner: Option<u8>,
    /// Degree in `u` and `v` (7 for caps, 3 for bicubic patches).
    pub degree: usize,
    /// `(degree + 1)²` control points `[x, y, z]`, row-major with the first index along
    /// the patch's `u`.
    pub points: Vec<[f64; 3]>,
}

/// One cap of [`patches_json`].
#[derive(Clone, Debug)]
pub struct CapJson {
    /// The extraordinary vertex, or `null` for the centre of a face.
    pub vertex: Option<usize>,
    /// The face, for a face centre.
    pub face_centre: Option<usize>,
    /// Valence `n`.
    pub valence: usize,
    /// The `n` bi-septic patches in order around the vertex.
    pub patches: Vec<PatchJson>,
}

/// The mixed-subdivision parameters of a [`SurfaceJson`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MixedJson {
    /// Shape parameter `c` of the adjustable scheme.
    pub c: f64,
    /// Number of adjustable steps `k` before Catmull-Clark.
    pub adjust_steps: u32,
}

/// The document of [`patches_json`].
#[derive(Clone, Debug)]
pub struct SurfaceJson {
    /// `"subsurf-g2"`.
    pub format: &'static str,
    /// Schema version (1).
    pub version: u32,
    /// Isolation levels `L`: bicubic squares have side `2⁻ᴸ` (`2¹⁻ᴸ` on sub-faces).
    pub levels: u32,
    /// For the G2 surface of a mixed surface ([`G2Surface::new`] with [`Scheme::Adjustable`](crate::Scheme::Adjustable)): its parameters
    /// (absent for Catmull-Clark).
    pub mixed: Option<MixedJson>,
    /// The caps.
    pub caps: Vec<CapJson>,
    /// The bicubic patches of the rest of the surface.
    pub bicubic: Vec<PatchJson>,
    /// Squares of the rest whose surface is not a single bicubic (next to boundaries,
    /// creases or uncapped vertices): `[face, subface, i, j]` with the square
    /// `[i, i+1] × [j, j+1]` in units of the square side.
    pub not_polynomial: Vec<[u32; 4]>,
    /// Extraordinary vertices (or face centres) without a cap: `[vertex or -1, face or -1,
    /// valence]` with the reason in `uncapped_reasons`.
    pub uncapped: Vec<[i64; 3]>,
    /// Why each entry of `uncapped` has no cap.
    pub uncapped_reasons: Vec<&'static str>,
}

impl SurfaceJson {
    /// All patches in file order: the caps' (degree 7) first, then the bicubic ones.
    pub fn patches(&self) -> impl Iterator<Item = &PatchJson> {
        self.caps
            .iter()
            .flat_map(|c| c.patches.iter())
            .chain(self.bicubic.iter())
    }
}

impl SurfaceJson {
    /// The document as compact JSON text (shortest round-trip `f64` digits; absent
    /// `mixed` omitted, other absent values `null`).
    pub fn to_json(&self) -> String {
        crate::json::to_string(self)
    }
}

impl ToJson for PatchJson {
    fn write_json(&self, out: &mut String) {
        object(out, |o| {
            o.field("face", &self.face);
            o.field("subface", &self.subface);
            o.field("domain", &self.domain);
            o.field("corner", &self.corner);
            o.field("degree", &self.degree);
            o.field("points", &self.points);
        });
    }
}

impl ToJson for CapJson {
    fn write_json(&self, out: &mut String) {
        object(out, |o| {
            o.field("vertex", &self.vertex);
            o.field("face_centre", &self.face_centre);
            o.field("valence", &self.valence);
            o.field("patches", &self.patches);
        });
    }
}

impl ToJson for MixedJson {
    fn write_json(&self, out: &mut String) {
        object(out, |o| {
            o.field("c", &self.c);
            o.field("adjust_steps", &self.adjust_steps);
        });
    }
}

impl ToJson for SurfaceJson {
    fn write_json(&self, out: &mut String) {
        object(out, |o| {
            o.field("format", self.format);
            o.field("version", &self.version);
            o.field("levels", &self.levels);
            o.field_if_some("mixed", &self.mixed);
            o.field("caps", &self.caps);
            o.field("bicubic", &self.bicubic);
            o.field("not_polynomial", &self.not_polynomial);
            o.field("uncapped", &self.uncapped);
            o.field("uncapped_reasons", &self.uncapped_reasons);
        });
    }
}

fn cap_patch(slot: &PatchRef, patch: &BezierPatch) -> PatchJson {
    let (u0, v0) = slot.to_face(0.0, 0.0);
    let (u1, v1) = slot.to_face(1.0, 1.0);
    PatchJson {
        face: slot.face,
        subface: slot.subface,
        domain: [u0.min(u1), v0.min(v1), u0.max(u1), v0.max(v1)],
        corner: Some(slot.corner),
        degree: patch.degree(),
        points: patch.points().to_vec(),
    }
}

/// The whole G2 surface as Bézier patches: the caps (degree 7) and, on the squares of
/// side `2⁻ᴸ` of every (sub-)face outside the caps, the bicubic patches (degree 3,
/// recovered exactly from the Catmull-Clark surface by interpolation and checked; squares
/// that are not bicubic are listed in `not_polynomial`). Schema in `docs/adjustable-g2.md`.
///
/// # Errors
/// [`G2Error::Eval`] if the Catmull-Clark surface cannot be evaluated (not expected).
pub fn patches_json(surface: &G2Surface, mesh: &PolyMesh) -> Result<SurfaceJson, G2Error> {
    let caps = surface
        .caps()
        .iter()
        .map(|c| CapJson {
            vertex: c.vertex,
            face_centre: c.face_centre,
            valence: c.slots.len(),
            patches: c
                .slots
                .iter()
                .zip(c.cap.patches())
                .map(|(s, p)| cap_patch(s, p))
                .collect(),
        })
        .collect();
    let squares = squares_outside_caps(surface, mesh);
    let fitted: Vec<Option<PatchJson>> = squares
        .par_iter()
        .map(|sq| bicubic_patch(surface, sq))
        .collect();
    let mut bicubic = Vec::new();
    let mut not_polynomial = Vec::new();
    for (sq, p) in squares.iter().zip(fitted) {
        match p {
            Some(p) => bicubic.push(p),
            None => not_polynomial.push([sq.face, sq.subface, sq.i, sq.j]),
        }
    }
    let uncapped = surface
        .uncapped()
        .iter()
        .map(|u| {
            [
                u.vertex.map_or(-1, |v| v as i64),
                u.face.map_or(-1, |f| f as i64),
                u.valence as i64,
            ]
        })
        .collect();
    Ok(SurfaceJson {
        format: "subsurf-g2",
        version: 1,
        levels: surface.levels(),
        mixed: surface.mixed().map(|m| MixedJson {
            c: m.mixed().scheme.c(),
            adjust_steps: m.mixed().steps,
        }),
        caps,
        bicubic,
        not_polynomial,
        uncapped,
        uncapped_reasons: surface.uncapped().iter().map(|u| u.reason).collect(),
    })
}

/// A square of side `h` of a (sub-)face: `[i h, (i + 1) h] × [j h, (j + 1) h]`.
struct Square {
    face: u32,
    subface: u32,
    i: u32,
    j: u32,
    h: f64,
}

/// The squares of side `2⁻ᴸ` (`L` the surface's isolation level; one level less on the
/// sub-faces of an `n`-gon) of every (sub-)face with a surface whose centre no cap covers.
fn squares_outside_caps(surface: &G2Surface, mesh: &PolyMesh) -> Vec<Square> {
    let limit = surface.limit();
    let levels = surface.levels();
    let mut squares = Vec::new();
    for f in (0..mesh.num_faces()).filter(|&f| limit.has_surface(f)) {
        let quad = mesh.face(f).len() == 4;
        let k = 1u32 << if quad { levels } else { levels - 1 };
        let h = 1.0 / k as f64;
        for subface in 0..limit.num_subfaces(f) as u32 {
            for j in 0..k {
                for i in 0..k {
                    let centre = SurfacePoint {
                        face: f as u32,
                        subface,
                        u: (i as f64 + 0.5) * h,
                        v: (j as f64 + 0.5) * h,
                    };
                    if surface.locate(centre).is_none() {
                        squares.push(Square {
                            face: f as u32,
                            subface,
                            i,
                            j,
                            h,
                        });
                    }
                }
            }
        }
    }
    squares
}

/// The bicubic Bézier patch that interpolates the Catmull-Clark surface over `sq`, if the
/// surface is that patch there: checked at four more points, within `1e-9` of the mesh's
/// size. `None` where the surface is not one bicubic polynomial on the square.
fn bicubic_patch(surface: &G2Surface, sq: &Square) -> Option<PatchJson> {
    let &Square {
        face,
        subface,
        i,
        j,
        h,
    } = sq;
    let size = surface.size();
    let at = |s: f64, t: f64| SurfacePoint {
        face,
        subface,
        u: ((i as f64 + s) * h).clamp(0.0, 1.0),
        v: ((j as f64 + t) * h).clamp(0.0, 1.0),
    };
    let mut ok = true;
    let patch = BezierPatch::interpolate(3, |s, t| match surface.eval_uncapped(at(s, t)) {
        Ok(d) => d.p,
        Err(_) => {
            ok = false;
            [0.0; 3]
        }
    })?;
    for &(s, t) in &[(0.13, 0.71), (0.91, 0.07), (0.0, 1.0), (0.5, 0.5)] {
        let q = surface.eval_uncapped(at(s, t)).ok()?.p;
        let p = patch.derivative(s, t, 0, 0);
        if (0..3).any(|a| (p[a] - q[a]).abs() > 1e-9 * size) {
            ok = false;
        }
    }
    ok.then(|| PatchJson {
        face,
        subface,
        domain: [
            i as f64 * h,
            j as f64 * h,
            (i + 1) as f64 * h,
            (j + 1) as f64 * h,
        ],
        corner: None,
        degree: 3,
        points: patch.points().to_vec(),
    })
}
