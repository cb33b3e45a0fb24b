//! `subsurf limit`: sample the exact limit surface on an N×N grid per quad face, in the
//! column layout and order of `osd-oracle limit`, and per sub-face of every other face, in
//! OpenSubdiv `Bfr`'s parameterisation of the face ([`Parameterization`]); with
//! `--scheme loop`, the Loop limit ([`LoopSurface`]) on a triangular grid per triangle,
//! `(u, v) = (i/(N−1), j/(N−1))`, `i + j ≤ N − 1`, as `osd-oracle limit --scheme loop`;
//! with `--scheme bilinear`, the bilinear limit ([`BilinearSurface`]) on the grids of
//! Catmull-Clark's layout (quads, then the sub-faces of other faces).
//! When the mesh has texture coordinates, each row ends with their limit `s t`
//! ([`FaceVaryingSurface`]; with NURSS [`FaceVaryingSurface::nurss`]).

use anyhow::{Context, Result};
use subsurf::limit::{
    BilinearSurface, ChannelValues, Derivatives, Domain, FaceVaryingSurface, LimitSurface,
    LoopSurface, Order, Parameterization, Surface, SurfacePoint,
};
use subsurf::mesh::{Options, PolyMesh};
use subsurf::nonuniform::NurssSurface;
use subsurf::{MixedSurface, Scheme};

use crate::input::Input;
use crate::output::Output;
use crate::{LimitArgs, SchemeKind};

/// Bytes per output row held until its block is written (measured: 214 at 6 million rows).
const BYTES_PER_ROW: u64 = 256;

/// Bytes of the shortest output row (`0 0 0 0 0 0 0 0 0 0 0 0`): a file of fewer bytes per
/// row than this cannot be, so a job whose rows times this exceed the free space is refused.
const MIN_BYTES_PER_ROW: u64 = 24;

/// Grid points per block of sub-faces evaluated together (in parallel) and then written:
/// only one block's rows are held as text (about 1 MiB), where holding all of them made
/// `catmark_pawn` with `--grid 5` peak at 9.9 MiB (`osd-oracle limit`: 6.6).
const POINTS_PER_BLOCK: usize = 4096;

/// The faces a grid is sampled on, in order: every quad (every triangle of a surface on
/// triangles, [`Domain::Triangle`]) with a surface (not a hole), as `osd-oracle limit` and
/// `benchlimit` sample (`bench --limit-grid`, which times against them).
pub fn grid_faces(surface: &impl Surface) -> Vec<u32> {
    (0..surface.num_faces())
        .filter(|&f| surface.num_subfaces(f) == 1 && surface.has_surface(f))
        .map(|f| f as u32)
        .collect()
}

/// The grid of `n` samples per side on `face` of a surface whose faces have domain
/// `domain`: the `n`×`n` grid on a quad, the triangular grid on a triangle, in `osd-oracle
/// limit`'s order ([`subface_grid`], [`triangle_grid`]).
pub fn grid(face: u32, n: usize, domain: Domain) -> impl Iterator<Item = SurfacePoint> {
    let quad = (domain == Domain::Quad).then(|| subface_grid(face, 0, n));
    let triangle = (domain == Domain::Triangle).then(|| triangle_grid(face, n));
    quad.into_iter()
        .flatten()
        .chain(triangle.into_iter().flatten())
}

/// The `n`×`n` grid on sub-face `subface` of `face` (the face itself for a quad), in its own
/// `(s, t)`: `s = i / (n − 1)` outer, `t = j / (n − 1)` inner (the centre for `n = 1`).
fn subface_grid(face: u32, subface: u32, n: usize) -> impl Iterator<Item = SurfacePoint> {
    let param = move |i: usize| {
        if n == 1 {
            0.5
        } else {
            i as f64 / (n - 1) as f64
        }
    };
    (0..n * n).map(move |k| SurfacePoint {
        face,
        subface,
        u: param(k / n),
        v: param(k % n),
    })
}

/// The triangular grid of `n` samples per side on triangle `face`, in `osd-oracle limit
/// --scheme loop`'s order: `u = i / (n − 1)` outer, `v = j / (n − 1)` inner, `i + j ≤ n − 1`
/// (the centroid for `n = 1`).
fn triangle_grid(face: u32, n: usize) -> impl Iterator<Item = SurfacePoint> {
    let third = 1.0 / 3.0;
    let at = move |i: usize| i as f64 / (n.max(2) - 1) as f64;
    (0..n).flat_map(move |i| {
        (0..n - i).map(move |j| SurfacePoint {
            face,
            subface: 0,
            u: if n == 1 { third } else { at(i) },
            v: if n == 1 { third } else { at(j) },
        })
    })
}

/// The surface sampled.
enum Sampler {
    /// Catmull-Clark.
    Limit(LimitSurface),
    /// Shape-adjustable steps, then Catmull-Clark (`--c`).
    Mixed(Box<MixedSurface>),
    /// Non-uniform Catmull-Clark (knot tags or `--scheme nurss`).
    Nurss(NurssSurface),
    /// Loop, on triangles.
    Loop(Box<LoopSurface>),
    /// Bilinear.
    Bilinear(BilinearSurface),
}

impl Sampler {
    /// Sub-faces of input face `f` of `size` vertices (0 if it has no surface).
    fn subfaces(&self, f: usize, size: usize) -> usize {
        let has = match self {
            Sampler::Limit(s) => s.has_surface(f),
            Sampler::Mixed(s) => {
                // An input face has a surface if its first refined face does (holes stay
                // holes).
                let first = SurfacePoint {
                    face: f as u32,
                    subface: 0,
                    u: 0.0,
                    v: 0.0,
                };
                (s.refined_point(first))
                    .is_ok_and(|(q, _)| s.limit_surface().has_surface(q.face as usize))
            }
            Sampler::Nurss(s) => s.has_surface(f),
            Sampler::Loop(s) => return usize::from(s.has_surface(f)),
            Sampler::Bilinear(s) => s.has_surface(f),
        };
        if has {
            Parameterization::new(size).num_subfaces()
        } else {
            0
        }
    }

    /// The texture coordinates' limit at `points` (of one sub-face), `uv` the channel's
    /// surface (of the refined mesh for the adjustable scheme, whose points are mapped
    /// there).
    fn eval_uv(&self, uv: &FaceVaryingSurface, points: &[SurfacePoint]) -> Result<ChannelValues> {
        Ok(match self {
            Sampler::Mixed(s) => {
                let refined = (points.iter())
                    .map(|&p| s.refined_point(p).map(|(q, _)| q))
                    .collect::<Result<Vec<_>, _>>()?;
                uv.eval_many(&refined)?
            }
            _ => uv.eval_many(points)?,
        })
    }

    /// The derivatives at `points` (of one sub-face), into `out`; an error names `face`.
    fn eval(
        &self,
        points: &[SurfacePoint],
        out: &mut Vec<Result<Derivatives, subsurf::limit::EvalError>>,
    ) -> Result<()> {
        match self {
            Sampler::Limit(s) => s.eval_many_into(points, Order::First, out),
            Sampler::Mixed(s) => s.eval_many_into(points, Order::First, out),
            Sampler::Loop(s) => eval_surface(&**s, points, out),
            Sampler::Bilinear(s) => eval_surface(s, points, out),
            Sampler::Nurss(s) => {
                out.clear();
                for &p in points {
                    match s.eval_point_order(p, Order::First) {
                        Ok(d) => out.push(Ok(d)),
                        Err(subsurf::nonuniform::NurssEvalError::Eval(e)) => out.push(Err(e)),
                        Err(e) => return Err(e.into()),
                    }
                }
            }
        }
        Ok(())
    }
}

/// `s`'s derivatives at `points` into `out` (resized to them).
fn eval_surface(
    s: &impl Surface,
    points: &[SurfacePoint],
    out: &mut Vec<Result<Derivatives, subsurf::limit::EvalError>>,
) {
    out.clear();
    out.resize(points.len(), Ok(Derivatives::default()));
    s.evaluate_many(points, Order::First, out);
}

/// One input face's sub-face to sample: the face, its size and the sub-face.
#[derive(Clone, Copy)]
struct Unit {
    face: u32,
    size: usize,
    subface: u32,
}

/// Runs `subsurf limit`.
pub fn run(args: &LimitArgs) -> Result<()> {
    super::adjustable::check_surface_flags(args.scheme_kind, &args.adjust);
    // Every block is evaluated in parallel: this thread is the first of rayon's global
    // pool, one thread fewer than a pool beside it (`catmark_pawn --grid 5` 7.0 -> 6.4
    // MiB). Commands that may not use the pool at all leave it to start on first use.
    // If it cannot be built so, rayon builds its default one then.
    let _ = rayon::ThreadPoolBuilder::new()
        .use_current_thread()
        .build_global();
    let out = Output::new(&args.output);
    out.check()?;
    let input = Input::read_surface(&args.input, args.max_memory)?;
    if !args.quiet {
        for w in input.warnings() {
            crate::output::eprint_line(&format!("warning: {w}"));
        }
    }
    let mut options = args
        .scheme
        .over(input.obj.options)
        .resolve(Options::default());
    if let Some(mode) = args.fvar {
        options.face_varying = mode;
    }
    let uv_channel = (input.obj.mesh.face_varying.iter()).position(|c| c.name() == "uv");
    let uv_surface = |m: &PolyMesh, scheme: Scheme| {
        (uv_channel.map(|c| FaceVaryingSurface::for_scheme(m, scheme, options, c)))
            .transpose()
            .with_context(|| format!("{}: texture coordinates", input.name))
    };
    let kind = super::adjustable::surface_kind(args.scheme_kind, &args.adjust, &input, args.quiet);
    let n = args.grid as usize;
    let what = format!("sampling a {0}×{0} grid per face", args.grid);
    let hint = "use a smaller --grid";
    // The rows are streamed: neither memory nor the whole output bounds them, the disk does.
    let samples = crate::memory::grid_samples(&input.obj.mesh, args.grid);
    out.check_space(
        &input.name,
        &what,
        samples.saturating_mul(MIN_BYTES_PER_ROW),
        hint,
    )?;
    // Memory: the surface, then one block's rows as text, and the texture coordinates'
    // surface (a limit surface of the channel's value mesh, which has the mesh's faces and
    // at least its vertices: estimated as the mesh's own; with NURSS its patches too).
    let uv_bytes = match uv_channel {
        Some(_) if kind == SchemeKind::Nurss => {
            LimitSurface::estimate_build_memory(&input.obj.mesh)
                .saturating_add(NurssSurface::estimate_patch_memory(&input.obj.mesh))
        }
        Some(_) => LimitSurface::estimate_build_memory(&input.obj.mesh),
        None => 0,
    };
    let held = samples
        .min(POINTS_PER_BLOCK.max(n * n) as u64)
        .saturating_mul(BYTES_PER_ROW)
        .saturating_add(uv_bytes);
    let guard = crate::memory::SurfaceGuard {
        name: &input.name,
        what,
        max: args.max_memory,
        hint,
        quads_only: false,
    };
    let mesh = &input.obj.mesh;
    let (sampler, uv) = match (kind, super::adjustable::for_surface(&args.adjust)) {
        (SchemeKind::Nurss, _) => (
            nurss_sampler(args, &input, &options, &guard, held)?,
            nurss_uv(&input, &options, uv_channel)?,
        ),
        (_, Some(m)) => {
            let refined = super::adjustable::refined_mesh(&input, options, m)?;
            let surface = guard.limit_surface(&refined, options, args.grid, held)?;
            let uv = uv_surface(&refined, Scheme::CatmullClark)?;
            let mixed = MixedSurface::from_refined(mesh, refined, surface, m)
                .with_context(|| input.name.clone())?;
            (Sampler::Mixed(Box::new(mixed)), uv)
        }
        (SchemeKind::Loop, _) => {
            let s = guard.local_surface(LoopSurface::estimate_memory(mesh), held, || {
                LoopSurface::new(mesh, options)
            })?;
            (Sampler::Loop(Box::new(s)), uv_surface(mesh, Scheme::Loop)?)
        }
        (SchemeKind::Bilinear, _) => {
            let s = guard.local_surface(LimitSurface::estimate_build_memory(mesh), held, || {
                BilinearSurface::new(mesh)
            })?;
            (Sampler::Bilinear(s), uv_surface(mesh, Scheme::Bilinear)?)
        }
        (_, None) => (
            Sampler::Limit(guard.limit_surface(mesh, options, args.grid, held)?),
            uv_surface(mesh, Scheme::CatmullClark)?,
        ),
    };
    let units = units(mesh, &sampler);
    write_rows(&out, &input, (&sampler, uv.as_ref()), &units, n)
}

/// The sub-faces `sampler` samples, face by face in order.
fn units(mesh: &PolyMesh, sampler: &Sampler) -> Vec<Unit> {
    (0..mesh.num_faces())
        .flat_map(|f| {
            let size = mesh.face(f).len();
            let subs = sampler.subfaces(f, size);
            (0..subs as u32).map(move |subface| Unit {
                face: f as u32,
                size,
                subface,
            })
        })
        .collect()
}

/// The NURSS surface of `input`'s mesh within the memory guard (its exact patches and the
/// Catmull-Clark surface of its faces with equal intervals), every face with a surface
/// checked to have an exact evaluation before anything is written; `held` bytes are
/// taken already.
fn nurss_sampler(
    args: &LimitArgs,
    input: &Input,
    options: &Options,
    guard: &crate::memory::SurfaceGuard,
    held: u64,
) -> Result<Sampler> {
    let mesh = &input.obj.mesh;
    let hint = guard.hint;
    let patches = NurssSurface::estimate_patch_memory(mesh);
    let build = LimitSurface::estimate_build_memory(mesh);
    crate::memory::check(
        &input.name,
        &guard.what,
        patches.saturating_add(build).saturating_add(held),
        args.max_memory,
        hint,
    )?;
    let cc = |m: &PolyMesh| {
        let held = held.saturating_add(patches);
        guard
            .limit_surface(m, *options, args.grid, held)
            .map_err(NurssBuild::Guard)
    };
    let s = NurssSurface::build(mesh, options, cc).map_err(|e| match e {
        NurssBuild::Guard(e) => e,
        NurssBuild::Nurss(e) => anyhow::Error::new(e).context(input.name.clone()),
    })?;
    // A face without an exact evaluation is refused before anything is written.
    for f in (0..mesh.num_faces()).filter(|&f| s.has_surface(f)) {
        s.check_face(f).with_context(|| input.name.clone())?;
    }
    Ok(Sampler::Nurss(s))
}

/// The NURSS limit of `input`'s texture coordinates (channel `channel`, if any), every face
/// with a surface checked to have an exact evaluation (at the centre of each sub-face)
/// before anything is written.
fn nurss_uv(
    input: &Input,
    options: &Options,
    channel: Option<usize>,
) -> Result<Option<FaceVaryingSurface>> {
    let Some(c) = channel else {
        return Ok(None);
    };
    let mesh = &input.obj.mesh;
    let context = || format!("{}: texture coordinates", input.name);
    let uv = FaceVaryingSurface::nurss(mesh, *options, c).with_context(context)?;
    let holes: std::collections::HashSet<u32> = mesh.tags.holes.iter().copied().collect();
    for f in (0..mesh.num_faces() as u32).filter(|f| !holes.contains(f)) {
        let subs = Parameterization::new(mesh.face(f as usize).len()).num_subfaces();
        for subface in 0..subs as u32 {
            let p = SurfacePoint {
                face: f,
                subface,
                u: 0.5,
                v: 0.5,
            };
            if let Err(e) = uv.eval_point(p) {
                anyhow::bail!(
                    "{}: texture coordinates: {e}; their NURSS limit is exact at the vertices \
                     of refined levels (subdivide --scheme nurss --limit; tessellate --scheme \
                     nurss samples it so)",
                    input.name
                );
            }
        }
    }
    Ok(Some(uv))
}

/// Errors of building a NURSS surface within the memory guard.
enum NurssBuild {
    Guard(anyhow::Error),
    Nurss(subsurf::nonuniform::NurssError),
}

impl From<subsurf::nonuniform::NurssError> for NurssBuild {
    fn from(e: subsurf::nonuniform::NurssError) -> Self {
        NurssBuild::Nurss(e)
    }
}

/// Writes the rows of `units` to `out`, block by block: one sub-face's rows at a time, in
/// parallel over the sub-faces of a block, written in order, each point's position and
/// first derivatives, and the limit of the texture coordinates when `uv` is given. An error
/// stops the output at its block: a file is then not written at all, standard output has
/// the blocks before it.
fn write_rows(
    out: &Output,
    input: &Input,
    (sampler, uv): (&Sampler, Option<&FaceVaryingSurface>),
    units: &[Unit],
    n: usize,
) -> Result<()> {
    let units_per_block = (POINTS_PER_BLOCK / (n * n)).max(1);
    let triangles = matches!(sampler, Sampler::Loop(_));
    let unit_rows = |points: &mut Vec<SurfacePoint>, results: &mut Vec<_>, u: Unit| {
        points.clear();
        if triangles {
            points.extend(triangle_grid(u.face, n));
        } else {
            points.extend(subface_grid(u.face, u.subface, n));
        }
        let face = || format!("{}: face {}", input.name, u.face);
        sampler.eval(points, results).with_context(face)?;
        let uvs = (uv.map(|uv| sampler.eval_uv(uv, points)))
            .transpose()
            .with_context(face)?;
        // Rows give the face's (u, v) in Bfr's parameterisation, derivatives by them.
        let param = Parameterization::new(u.size);
        let scale = if triangles {
            1.0
        } else {
            param.derivative_scale()
        };
        let mut s = Vec::new();
        for (i, (p, d)) in points.iter().zip(results.iter()).enumerate() {
            let d = d.as_ref().map_err(Clone::clone).with_context(face)?;
            let (fu, fv) = if triangles {
                (p.u, p.v)
            } else {
                param.to_face(u.subface as usize, p.u, p.v)
            };
            let (du, dv) = (d.du.map(|x| scale * x), d.dv.map(|x| scale * x));
            use std::io::Write as _;
            let _ = write!(s, "{}", u.face);
            let st = uvs.as_ref().map_or(&[][..], |c| c.value_at(i));
            for x in [fu, fv].iter().chain(&d.p).chain(&du).chain(&dv).chain(st) {
                s.push(b' ');
                subsurf::io::push_decimal(&mut s, *x);
            }
            s.push(b'\n');
        }
        Ok::<_, anyhow::Error>(s)
    };
    // An evaluation error is the input's, not the output's: it is kept here and returned
    // as it is, not as a failure to write.
    let mut failed = None;
    let written = out.write(|w| {
        use rayon::prelude::*;
        let mut rows = Vec::new();
        for block in units.chunks(units_per_block) {
            block
                .par_iter()
                .map_init(
                    || (Vec::new(), Vec::new()),
                    |(points, results), &u| unit_rows(points, results, u),
                )
                .collect_into_vec(&mut rows);
            for r in rows.drain(..) {
                match r {
                    Ok(s) => w.write_all(&s)?,
                    Err(e) => {
                        failed = Some(e);
                        return Err(std::io::Error::other("evaluation failed"));
                    }
                }
            }
        }
        Ok(())
    });
    match failed {
        Some(e) => Err(e),
        None => written,
    }
}
