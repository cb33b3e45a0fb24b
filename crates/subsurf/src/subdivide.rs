//! The one-call facade: [`subdivide`] a [`PolyMesh`] to a level with any [`Scheme`],
//! optionally to the limit.

use crate::limit;
use crate::mesh::{Options, PolyMesh, Topology, TopologyWarning};
use crate::refine::uniform::{
    estimate_face_varying, estimate_uniform, groups_of_refined, refine_uniform, Steps,
};
use crate::refine::Error;
use crate::refine::{interpolate_with, refine_topology};
use crate::scheme::adjustable::Mixed;
use crate::scheme::catmark::CatmullClark;
use crate::scheme::loop_::Loop;
use crate::scheme::{Bilinear, Rules, Scheme};

/// What [`subdivide`] should do.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SubdivideOptions {
    /// Number of uniform refinement steps (0 leaves the mesh as it is).
    pub levels: u32,
    /// The subdivision scheme.
    pub scheme: Scheme,
    /// The rules' options: boundary interpolation, crease method, triangle rule.
    pub options: Options,
    /// Move the last level's vertices to their limit positions and compute limit normals
    /// (NURSS: limit positions only, [`Nurss::limit_points`](crate::nonuniform::Nurss::limit_points)).
    /// Face-varying channels (texture coordinates) are moved to their limit too, as
    /// OpenSubdiv's `PrimvarRefiner::LimitFaceVarying` moves them
    /// ([`FaceVaryingRefiner::limit`](crate::refine::FaceVaryingRefiner::limit); NURSS: the
    /// limit points of each channel's value mesh, see [`Nurss::new`](crate::nonuniform::Nurss::new)).
    pub limit: bool,
    /// Keep hole faces in the output (tagged as holes) so that the result can be refined
    /// again with the same outcome; by default holes are left out, as OpenSubdiv does.
    pub keep_holes: bool,
    /// Refuse (with [`Error::TooLarge`]) when the estimated memory exceeds this many bytes.
    pub max_memory: Option<u64>,
}

/// The result of [`subdivide`].
#[derive(Clone, Debug, PartialEq)]
pub struct Subdivision {
    /// The refined mesh. Its tags carry the sharpness still left at the last level, and
    /// with [`Scheme::Nurss`] its knot intervals and weights ([`PolyMesh::knots`]); each
    /// face has its base face's object, group and material ([`PolyMesh::groups`]).
    pub mesh: PolyMesh,
    /// Unit limit normals per vertex, when [`SubdivideOptions::limit`] was set (not for
    /// NURSS).
    pub normals: Option<Vec<[f64; 3]>>,
    /// Warnings about the input (ignored tags, non-manifold elements).
    pub warnings: Vec<TopologyWarning>,
}

/// Estimated peak memory in bytes of [`subdivide`] with `opts` (the scheme, the levels,
/// and whether limit positions are computed), saturating at `u64::MAX`; face-varying
/// channels add their values and indices per output face (up to a value per face corner).
/// NURSS keeps every level complete (with its knot intervals) and refines homogeneous
/// points: twice Catmull-Clark's estimate, and twice more for each face-varying channel
/// (refined as a value mesh of its own, a level like the mesh's).
pub fn estimate_memory(mesh: &PolyMesh, opts: &SubdivideOptions) -> u64 {
    match Steps::of(opts.scheme) {
        Some(steps) => estimate_uniform(mesh, steps, opts.levels, opts.limit)
            .saturating_add(estimate_face_varying(mesh, steps, opts.levels, opts.limit)),
        None => estimate_uniform(
            mesh,
            Steps::Family(Mixed::CATMULL_CLARK),
            opts.levels,
            opts.limit,
        )
        .saturating_mul(2 * (1 + mesh.face_varying.len() as u64)),
    }
}

/// Refines `mesh` uniformly `opts.levels` times with `opts.scheme`, optionally moving the
/// result to the limit. Catmull-Clark and the adjustable scheme refine as OpenSubdiv does
/// (same rules for boundaries, creases, corners, holes, triangles and non-manifold
/// topology; same vertex and face order); so does NURSS, whose numbering is Catmull-Clark's.
/// Face-varying channels are refined with every scheme (NURSS: as [`Nurss::new`](crate::nonuniform::Nurss::new)
/// says).
///
/// With `opts.limit` the last level is moved to its limit: for the adjustable scheme, the
/// limit of the mixed scheme with `min(steps, opts.levels)` adjustable steps, which is the
/// Catmull-Clark limit of the last level (see [`MixedSurface`](crate::MixedSurface) for
/// evaluation anywhere on it).
///
/// Only the last two levels are kept in memory while refining (NURSS: the last level and
/// its knot intervals).
///
/// # Errors
/// [`Error::Mesh`] for an invalid mesh or tags; [`Error::Nurss`] for bad knot tags or a
/// semi-sharp crease with NURSS; [`Error::TooLarge`] when the estimated memory exceeds
/// `opts.max_memory` or the result would exceed 32-bit indices.
pub fn subdivide(mesh: &PolyMesh, opts: &SubdivideOptions) -> Result<Subdivision, Error> {
    subdivide_with_progress(mesh, opts, &mut |_, _| {})
}

/// [`subdivide`], calling `progress(level_done, levels)` after each level.
pub fn subdivide_with_progress(
    mesh: &PolyMesh,
    opts: &SubdivideOptions,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Subdivision, Error> {
    mesh.validate()?;
    let estimate = estimate_memory(mesh, opts);
    if let Some(limit) = opts.max_memory {
        if estimate > limit {
            return Err(Error::TooLarge {
                levels: opts.levels,
                estimate,
                limit,
            });
        }
    }
    let Some(steps) = Steps::of(opts.scheme) else {
        let s = crate::nonuniform::refined(mesh, &opts.options, opts.levels, progress)?;
        return Ok(Subdivision {
            mesh: nurss_output(mesh, &s, opts, opts.limit)?,
            normals: None,
            warnings: s.warnings().to_vec(),
        });
    };
    let mut u = refine_uniform(
        mesh,
        &opts.options,
        steps,
        opts.levels,
        opts.limit,
        progress,
    )?;
    let normals = opts.limit.then(|| {
        u.limit_face_varying(opts.scheme, &opts.options);
        match opts.scheme {
            Scheme::Loop => limit_in_place(Loop, &u.level, &opts.options, &mut u.positions),
            Scheme::Bilinear => limit_in_place(Bilinear, &u.level, &opts.options, &mut u.positions),
            _ => limit_in_place(CatmullClark, &u.level, &opts.options, &mut u.positions),
        }
    });
    let warnings = std::mem::take(&mut u.warnings);
    Ok(Subdivision {
        mesh: u.into_mesh(opts.keep_holes),
        normals,
        warnings,
    })
}

/// The mesh of a NURSS refinement `s` of `mesh` (`Nurss::output_mesh`,
/// moved to the limit with `limit`) with `mesh`'s face groups carried to the children of
/// each face (NURSS numbers faces as Catmull-Clark does).
pub(crate) fn nurss_output(
    mesh: &PolyMesh,
    s: &crate::nonuniform::Nurss,
    opts: &SubdivideOptions,
    limit: bool,
) -> Result<PolyMesh, Error> {
    let mut out = s.output_mesh(opts.keep_holes, limit);
    let cc = Steps::Family(Mixed::CATMULL_CLARK);
    out.groups = groups_of_refined(mesh, &opts.options, cc, opts.levels, opts.keep_holes)?;
    debug_assert!(out.groups.validate(out.num_faces()).is_ok());
    Ok(out)
}

/// Moves `pos` (values at the vertices of `level`) to their limit positions with the limit
/// masks of `rules` and returns unit limit normals. Catmull-Clark's limit masks need quads
/// around each vertex; where a vertex touches an n-gon (only possible at the base level)
/// the masks are applied one level further down, whose vertex `v` is the child of `v` and
/// has the same limit. Loop's need triangles only, which the triangle split keeps.
fn limit_in_place<R: Rules>(
    rules: R,
    level: &Topology,
    options: &Options,
    pos: &mut [[f64; 3]],
) -> Vec<[f64; 3]> {
    let nv = level.num_vertices();
    let all_quads = rules.splits_triangles()
        || (0..level.num_faces()).all(|f| level.face_vertices(f).len() == 4);
    let (lim, t1, t2) = if all_quads {
        let mut lim = vec![[0.0; 3]; nv];
        let (mut t1, mut t2) = (vec![[0.0; 3]; nv], vec![[0.0; 3]; nv]);
        limit::limit_points_with(rules, level, pos, &mut lim, Some((&mut t1, &mut t2)));
        (lim, t1, t2)
    } else {
        let child = refine_topology(level, options, true);
        let mut cpos = vec![[0.0; 3]; child.num_vertices()];
        interpolate_with(level, &child, options, rules, pos, &mut cpos);
        let n = child.num_vertices();
        let mut lim = vec![[0.0; 3]; n];
        let (mut t1, mut t2) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        limit::limit_points_with(rules, &child, &cpos, &mut lim, Some((&mut t1, &mut t2)));
        lim.truncate(nv);
        t1.truncate(nv);
        t2.truncate(nv);
        (lim, t1, t2)
    };
    pos.copy_from_slice(&lim);
    limit::normals(level, pos, &t1, &t2)
}
