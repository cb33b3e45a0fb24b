//! Blending and hole filling as `subsurf blend` and `subsurf fill` run them, on the curves
//! and patches of a file (or any list of [`SourcedGeometry`]): the input's patches and
//! curves gathered and checked (errors name the item by its file position), the method
//! run, and its output assembled with the tessellated base patches and the boundary
//! polylines ([`MethodOutput`]).
//!
//! A job is prepared first ([`BlendJob::new`], [`FillJob::new`]: the input checked and the
//! control mesh built, which is cheap), so that its memory can be estimated
//! ([`BlendJob::estimate_memory`]) before it runs ([`BlendJob::run`]).

use super::fill::{fill, surface_boundary, FillOptions};
use super::g1::fill_g1;
use super::join::{blend, blend_control_mesh, BlendMesh};
use super::BlendError;
use crate::mesh::PolyMesh;
use crate::nurbs::{
    sample_parameters, Curve, Geometry, KnotVector, NurbsError, SourcedGeometry, Surface,
};

/// Most skirt-removal levels of a job (each multiplies the faces by 4).
pub const MAX_LEVELS: u32 = 8;

/// Most tessellation segments per knot span of a job.
pub const MAX_SAMPLES: u32 = 256;

/// Peak bytes per face of the last refined level's bound, output included (measured on
/// the bundled examples at levels 5–7, peak RSS of a release build of the `subsurf`
/// binary: 144–189; see RELIABILITY.md).
const BYTES_PER_REFINED_FACE: u64 = 256;

/// Peak bytes per sample of the tessellated base patches and curves, output included
/// (measured: 52 between `--samples 128` and `256`).
const BYTES_PER_SAMPLE: u64 = 96;

/// The process's own memory besides the job (code, threads, allocator), charged once.
const BASE_BYTES: u64 = 8 << 20;

/// Options of a [`BlendJob`] (the defaults are `subsurf blend`'s).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlendJobOptions {
    /// Skirt-removal refinement steps (at most [`MAX_LEVELS`]).
    pub levels: u32,
    /// Segments per knot span of the tessellated base patches (1 to [`MAX_SAMPLES`]).
    pub samples: u32,
}

impl Default for BlendJobOptions {
    fn default() -> Self {
        Self {
            levels: 5,
            samples: 8,
        }
    }
}

/// Options of a [`FillJob`] (the defaults are `subsurf fill`'s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FillJobOptions {
    /// Skirt-removal refinement steps (at most [`MAX_LEVELS`]).
    pub levels: u32,
    /// Segments per knot span of the tessellated base patches and the boundary polylines
    /// (1 to [`MAX_SAMPLES`]).
    pub samples: u32,
    /// The fill's options (its bulge).
    pub fill: FillOptions,
    /// Meet the base patches G1 ([`fill_g1`], [Jiang et al.] Algorithm 2; needs patches,
    /// not curves).
    pub g1: bool,
}

impl Default for FillJobOptions {
    fn default() -> Self {
        Self {
            levels: 5,
            samples: 8,
            fill: FillOptions::default(),
            g1: false,
        }
    }
}

/// Why a blend or fill job refuses its input or fails. Each message starts with what it is
/// about: the input item's label ([`SourcedGeometry::label`], e.g. `hole3.json[0]`) when
/// the error is about one item, else the input's name.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum JobError {
    /// A curve among the patches to blend.
    #[error("{item}: a curve; blending takes patches")]
    CurveToBlend {
        /// The curve's label.
        item: String,
    },
    /// A curve given to the G1 fill, which needs the patches' normals.
    #[error("{item}: a curve; --g1 needs the patches around the hole (their normals)")]
    CurveToG1 {
        /// The curve's label.
        item: String,
    },
    /// The method refused the input or failed.
    #[error("{at}: {error}")]
    Method {
        /// The label of the item the error is about, else the input's name.
        at: String,
        /// The method's error.
        error: BlendError,
    },
    /// A base patch or boundary curve could not be tessellated.
    #[error("{at}: {error}")]
    Tessellation {
        /// The input's name.
        at: String,
        /// The evaluation error.
        error: NurbsError,
    },
    /// Levels or samples out of range.
    #[error("{0}")]
    Option(String),
}

/// The output of a [`BlendJob`] or [`FillJob`]: the surface, the tessellated base patches
/// and boundary curves around it, and the control mesh, as `subsurf blend` and `subsurf
/// fill` write them.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodOutput {
    /// `"blend"` or `"fill"`: the method, and the name of the surface's group.
    pub method: &'static str,
    /// The base patches tessellated at the job's samples per knot span (groups `patch_1`,
    /// `patch_2`, …; none when a hole was given by curves).
    pub patches: Vec<PolyMesh>,
    /// The blend or fill surface: the control mesh refined with skirt removal.
    pub surface: PolyMesh,
    /// Fill: the boundary curves (after chaining and, for G1, as fitted) as polylines at
    /// the job's samples per knot span (groups `curve_1`, …); blend: none.
    pub curves: Vec<Vec<[f64; 3]>>,
    /// The control mesh, with its knot intervals (its outer ring is the extension layer).
    pub control: PolyMesh,
    /// A one-line description of the job, for the output file's comment.
    pub comment: String,
}

impl MethodOutput {
    /// The comment of the control mesh's file.
    pub fn control_comment(&self) -> String {
        format!(
            "subsurf {}: control mesh (outer ring: extension layer)",
            self.method
        )
    }

    /// The named groups of faces: `patch_1`, … and the surface (`blend` or `fill`).
    pub fn groups(&self) -> Vec<(String, &PolyMesh)> {
        let mut groups: Vec<(String, &PolyMesh)> = self
            .patches
            .iter()
            .enumerate()
            .map(|(k, m)| (format!("patch_{}", k + 1), m))
            .collect();
        groups.push((self.method.to_owned(), &self.surface));
        groups
    }

    /// The named polylines: `curve_1`, ….
    pub fn polylines(&self) -> Vec<(String, Vec<[f64; 3]>)> {
        self.curves
            .iter()
            .enumerate()
            .map(|(k, c)| (format!("curve_{}", k + 1), c.clone()))
            .collect()
    }
}

/// The checks common to both jobs: levels and samples in range.
fn check_range(levels: u32, samples: u32) -> Result<(), JobError> {
    if levels > MAX_LEVELS {
        return Err(JobError::Option(format!(
            "levels {levels}: at most {MAX_LEVELS} (each level multiplies the faces by 4)"
        )));
    }
    if !(1..=MAX_SAMPLES).contains(&samples) {
        return Err(JobError::Option(format!(
            "samples {samples}: 1 to {MAX_SAMPLES} segments per knot span"
        )));
    }
    Ok(())
}

/// A method error, labelled with the input item it is about (the library numbers items
/// from 0, as the JSON `[i]` positions do) or else with the input's `name`.
fn at(error: BlendError, items: &[SourcedGeometry], name: &str) -> JobError {
    let at = match error.input_index().and_then(|i| items.get(i)) {
        Some(item) => item.label(),
        None => name.to_owned(),
    };
    JobError::Method { at, error }
}

/// The samples of the tessellated `patches` at `per_span` segments per knot span:
/// `(s_u N + 1)(s_v N + 1)` per patch, `s` its spans.
fn sample_points(patches: &[Surface], per_span: u32) -> u64 {
    let n = u64::from(per_span);
    let along = |k: &KnotVector| {
        let (a, b) = k.domain();
        let spans = k
            .as_slice()
            .windows(2)
            .filter(|w| w[0] < w[1] && w[0] >= a && w[1] <= b)
            .count() as u64;
        spans.max(1).saturating_mul(n).saturating_add(1)
    };
    patches
        .iter()
        .map(|s| {
            let (ku, kv) = match s {
                Surface::BSpline(s) => (s.knots_u(), s.knots_v()),
                Surface::Nurbs(s) => (s.knots_u(), s.knots_v()),
            };
            along(ku).saturating_mul(along(kv))
        })
        .fold(0, u64::saturating_add)
}

/// The memory estimate of refining `control` `levels` times with skirt removal and
/// tessellating `samples` samples: the last level has at most `S · 4^(L−1)` faces (`S` the
/// control mesh's face corners, one quad each after a step; skirt removal only drops
/// faces), charged at [`BYTES_PER_REFINED_FACE`] each, every sample at
/// [`BYTES_PER_SAMPLE`], plus [`BASE_BYTES`].
fn estimate(control: &PolyMesh, levels: u32, samples: u64) -> u64 {
    let corners = control.face_verts().len() as u64;
    let faces = if levels == 0 {
        control.num_faces() as u64
    } else {
        corners.saturating_mul(4u64.saturating_pow(levels - 1))
    };
    faces
        .saturating_mul(BYTES_PER_REFINED_FACE)
        .saturating_add(samples.saturating_mul(BYTES_PER_SAMPLE))
        .saturating_add(BASE_BYTES)
}

/// The base patches tessellated at `samples` segments per knot span.
fn tessellate(patches: &[Surface], samples: u32, name: &str) -> Result<Vec<PolyMesh>, JobError> {
    patches
        .iter()
        .map(|s| s.grid(samples as usize))
        .collect::<Result<_, _>>()
        .map_err(|error| JobError::Tessellation {
            at: name.to_owned(),
            error,
        })
}

/// A C2 blend of the patches of a file ([`blend`], [Jiang et al.] §3.1), prepared: the
/// patches gathered and the blend control mesh built.
#[derive(Clone, Debug)]
pub struct BlendJob {
    items: Vec<SourcedGeometry>,
    name: String,
    patches: Vec<Surface>,
    control: BlendMesh,
    options: BlendJobOptions,
}

impl BlendJob {
    /// Prepares the blend of `items` (the patches of the input `name`, in order around the
    /// region to blend): every item must be a patch; the blend control mesh is built.
    ///
    /// # Errors
    /// [`JobError::CurveToBlend`] naming the first curve; [`JobError::Method`] with the
    /// errors of [`blend_control_mesh`], naming the patch; [`JobError::Option`] for levels
    /// or samples out of range.
    pub fn new(
        items: &[SourcedGeometry],
        name: &str,
        options: &BlendJobOptions,
    ) -> Result<Self, JobError> {
        check_range(options.levels, options.samples)?;
        let patches = items
            .iter()
            .map(|g| match &g.geometry {
                Geometry::Surface(s) => Ok(s.clone()),
                Geometry::Curve(_) => Err(JobError::CurveToBlend { item: g.label() }),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let control = blend_control_mesh(&patches).map_err(|e| at(e, items, name))?;
        Ok(Self {
            items: items.to_vec(),
            name: name.to_owned(),
            patches,
            control,
            options: *options,
        })
    }

    /// The blend control mesh (before refinement).
    pub fn control(&self) -> &PolyMesh {
        &self.control.mesh
    }

    /// An upper bound of the job's peak memory in bytes (constants measured on
    /// the `subsurf` binary, RELIABILITY.md), for a caller to refuse a job too large.
    pub fn estimate_memory(&self) -> u64 {
        estimate(
            &self.control.mesh,
            self.options.levels,
            sample_points(&self.patches, self.options.samples),
        )
    }

    /// Runs the blend: refines the control mesh `levels` times with skirt removal and
    /// tessellates the base patches.
    ///
    /// # Errors
    /// [`JobError::Method`] with the errors of [`blend`]; [`JobError::Tessellation`].
    pub fn run(&self) -> Result<MethodOutput, JobError> {
        let (items, name) = (&self.items, self.name.as_str());
        let b = blend(&self.patches, self.options.levels).map_err(|e| at(e, items, name))?;
        let surface = b.surface().map_err(|e| at(e, items, name))?;
        let patches = tessellate(&self.patches, self.options.samples, name)?;
        Ok(MethodOutput {
            method: "blend",
            patches,
            surface,
            curves: Vec::new(),
            control: b.control.mesh,
            comment: format!(
                "subsurf blend: {} patches, {} skirt-removal levels",
                self.patches.len(),
                self.options.levels
            ),
        })
    }
}

/// An N-sided hole fill of the curves or patches of a file ([`fill`], [Jiang et al.]
/// Algorithm 1, or G1: [`fill_g1`], Algorithm 2), prepared: the boundary curves gathered
/// and the fill's control mesh built.
#[derive(Clone, Debug)]
pub struct FillJob {
    items: Vec<SourcedGeometry>,
    name: String,
    curves: Vec<Curve>,
    surfaces: Vec<Surface>,
    control: PolyMesh,
    options: FillJobOptions,
}

impl FillJob {
    /// Prepares the fill of the hole bounded by `items` (the curves, or patches whose
    /// first-row boundary is used, of the input `name`, meeting end to end around the
    /// hole): the boundary curves are gathered and the control mesh built.
    ///
    /// # Errors
    /// [`JobError::CurveToG1`] for a curve when `options.g1`; [`JobError::Method`] with the
    /// errors of [`surface_boundary`], [`fill`] or [`fill_g1`] (at level 0), naming the
    /// item; [`JobError::Option`] for levels or samples out of range.
    pub fn new(
        items: &[SourcedGeometry],
        name: &str,
        options: &FillJobOptions,
    ) -> Result<Self, JobError> {
        check_range(options.levels, options.samples)?;
        let mut curves: Vec<Curve> = Vec::with_capacity(items.len());
        let mut surfaces: Vec<Surface> = Vec::new();
        for (k, g) in items.iter().enumerate() {
            match &g.geometry {
                Geometry::Curve(_) if options.g1 => {
                    return Err(JobError::CurveToG1 { item: g.label() })
                }
                Geometry::Curve(c) => curves.push(c.clone()),
                Geometry::Surface(s) => {
                    curves.push(surface_boundary(s, k).map_err(|e| at(e, items, name))?);
                    surfaces.push(s.clone());
                }
            }
        }
        let fail = |e| at(e, items, name);
        let control = if options.g1 {
            fill_g1(&surfaces, 0, &options.fill).map_err(fail)?.control
        } else {
            fill(&curves, 0, &options.fill).map_err(fail)?.control
        };
        Ok(Self {
            items: items.to_vec(),
            name: name.to_owned(),
            curves,
            surfaces,
            control,
            options: *options,
        })
    }

    /// The fill's control mesh (before refinement).
    pub fn control(&self) -> &PolyMesh {
        &self.control
    }

    /// The number of sides of the hole.
    pub fn sides(&self) -> usize {
        self.curves.len()
    }

    /// An upper bound of the job's peak memory in bytes (as [`BlendJob::estimate_memory`],
    /// the boundary polylines' samples included).
    pub fn estimate_memory(&self) -> u64 {
        let samples = self.options.samples;
        let polylines: u64 = self
            .curves
            .iter()
            .map(|c| sample_parameters(c.knots(), samples as usize).len() as u64)
            .sum();
        estimate(
            &self.control,
            self.options.levels,
            sample_points(&self.surfaces, samples).saturating_add(polylines),
        )
    }

    /// Runs the fill: refines the control mesh `levels` times with skirt removal,
    /// tessellates the base patches and samples the boundary curves.
    ///
    /// # Errors
    /// [`JobError::Method`] with the errors of [`fill`] or [`fill_g1`];
    /// [`JobError::Tessellation`].
    pub fn run(&self) -> Result<MethodOutput, JobError> {
        let (items, name) = (&self.items, self.name.as_str());
        let opts = &self.options;
        let fail = |e| at(e, items, name);
        let (surface, boundary, control) = if opts.g1 {
            let f = fill_g1(&self.surfaces, opts.levels, &opts.fill).map_err(fail)?;
            let curves = f.curves.iter().cloned().map(Curve::BSpline).collect();
            (f.surface().map_err(fail)?, curves, f.control)
        } else {
            let f = fill(&self.curves, opts.levels, &opts.fill).map_err(fail)?;
            (f.surface().map_err(fail)?, f.curves, f.control)
        };
        let patches = tessellate(&self.surfaces, opts.samples, name)?;
        let curves = boundary
            .iter()
            .map(|c: &Curve| c.polyline(opts.samples as usize))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|error| JobError::Tessellation {
                at: name.to_owned(),
                error,
            })?;
        Ok(MethodOutput {
            method: "fill",
            patches,
            surface,
            curves,
            control,
            comment: format!(
                "subsurf fill: {}-sided hole{}, {} skirt-removal levels, bulge {}",
                self.curves.len(),
                if opts.g1 { " (G1)" } else { "" },
                opts.levels,
                opts.fill.bulge
            ),
        })
    }
}
