//! What is drawn: triangles with per-vertex positions, normals and values, from the exact
//! limit surface or a refined mesh, and the control mesh's edges.

use super::camera::{Camera, Projected};
use super::curvature::{Curvature, CurvatureKind};
use super::{Geometry, Paint, Render, RenderError};
use crate::geom::{self, V3};
use crate::limit::{
    tessellate, BilinearSurface, Derivatives, Domain, EvalError, FaceVaryingSurface, LimitSurface,
    LoopSurface, Order, Surface, SurfacePoint, Tessellation,
};
use crate::mesh::{FaceVarying, Options, PolyMesh};
use crate::refine::uniform::{refine_mesh, Steps};
use crate::scheme::Scheme;
use rayon::prelude::*;

/// Points evaluated per call of [`Surface::evaluate_many`] (bounds the memory of the
/// derivatives held at once).
const CHUNK: usize = 1 << 16;

/// Triangles to draw.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scene {
    /// Vertex positions.
    pub positions: Vec<V3>,
    /// Unit vertex normals (zero where none exists).
    pub normals: Vec<V3>,
    /// Per-vertex curvature of the requested kind (NaN where unknown), with
    /// [`Paint::Curvature`].
    pub values: Option<Vec<f64>>,
    /// Per-vertex texture coordinates, with [`Paint::Checker`].
    pub uv: Option<Vec<[f64; 2]>>,
    /// Triangles (counter-clockwise seen from the side the normals point to).
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle, the unit normal of the polygon it comes from (flat shading).
    pub flat: Vec<V3>,
    /// Per triangle, its base face.
    pub face: Vec<u32>,
    /// Per base face, its colour index with [`Paint::Faces`] (see [`face_colours`]).
    pub face_colour: Vec<u8>,
    /// The control mesh's edges.
    pub edges: Vec<[V3; 2]>,
}

/// The scene seen by a camera.
pub(crate) struct Frame {
    /// Per vertex, its projection (samples), `None` behind the eye.
    pub screen: Vec<Option<Projected>>,
    /// Per vertex, its view-space position.
    pub view_pos: Vec<V3>,
    /// Per vertex, its view-space normal.
    pub view_normal: Vec<V3>,
    /// Per triangle, its view-space flat normal.
    pub view_flat: Vec<V3>,
}

impl Scene {
    /// Builds the scene of `mesh` as `opts` asks.
    pub(super) fn build(
        mesh: &PolyMesh,
        options: &Options,
        opts: &Render,
    ) -> Result<Self, RenderError> {
        Self::build_with(mesh, options, opts, None)
    }

    /// [`build`](Self::build), sampling `surface` instead of the mesh's limit surface when
    /// given (for [`Geometry::Limit`]; the grid is the limit surface's tessellation grid).
    pub(super) fn build_with(
        mesh: &PolyMesh,
        options: &Options,
        opts: &Render,
        surface: Option<&dyn Surface>,
    ) -> Result<Self, RenderError> {
        if matches!(opts.paint, Paint::Checker { .. }) && uv_channel(mesh).is_none() {
            return Err(RenderError::NoTextureCoordinates);
        }
        let faces = drawn_faces(mesh, opts.geometry, opts.scheme);
        if faces > MAX_DRAWN_FACES as u128 {
            return Err(RenderError::TooLarge {
                faces,
                limit: MAX_DRAWN_FACES,
            });
        }
        let mut scene = match opts.geometry {
            Geometry::Limit { rate } => {
                let kind = match opts.paint {
                    Paint::Curvature(k) => Some(k),
                    _ => None,
                };
                let grid = LimitGrid::sample_with(
                    mesh,
                    options,
                    opts.scheme,
                    rate,
                    kind.is_some(),
                    surface,
                    opts.surface_memory,
                )?;
                let uv = match opts.paint {
                    Paint::Checker { .. } => {
                        Some(grid_uvs(mesh, options, opts.scheme, &grid.points)?)
                    }
                    _ => None,
                };
                Self {
                    uv,
                    ..Self::from_grid(grid, kind)
                }
            }
            Geometry::Level(levels) => {
                let textured = matches!(opts.paint, Paint::Checker { .. });
                Self::from_level(mesh, options, opts.scheme, levels, textured)?
            }
        };
        if opts.control_mesh {
            scene.edges = control_edges(mesh);
        }
        if opts.paint == Paint::Faces {
            scene.face_colour = face_colours(mesh, FACE_PALETTE);
        }
        Ok(scene)
    }

    fn from_grid(grid: LimitGrid, kind: Option<CurvatureKind>) -> Self {
        let mut triangles = Vec::with_capacity(2 * grid.cells.len());
        let mut flat = Vec::with_capacity(2 * grid.cells.len());
        let mut face = Vec::with_capacity(2 * grid.cells.len());
        for (&cell, &f) in grid.cells.iter().zip(&grid.cell_face) {
            let n = geom::normalize_or_zero(geom::newell_normal(&grid.positions, cell.verts()));
            let (split, count) = match cell {
                Cell::Quad(q) => (split_quad(&grid.positions, q), 2),
                Cell::Tri(t) => ([t, t], 1),
            };
            for &t in &split[..count] {
                triangles.push(t);
                flat.push(n);
                face.push(f);
            }
        }
        let values = kind.zip(grid.curvature.as_ref()).map(|(k, cs)| {
            let mut v: Vec<f64> = cs
                .iter()
                .map(|c| c.map_or(f64::NAN, |c| c.get(k)))
                .collect();
            fill_missing(&mut v, &grid.cells);
            v
        });
        Self {
            positions: grid.positions,
            normals: grid.normals,
            values,
            triangles,
            flat,
            face,
            face_colour: Vec::new(),
            edges: Vec::new(),
            uv: None,
        }
    }

    /// The mesh refined `levels` times with `scheme` (holes left out), normals averaged
    /// from its faces; with `textured`, its refined texture coordinates, each vertex copied
    /// per texture coordinate its corners take (see [`Scene::unweld`]).
    fn from_level(
        mesh: &PolyMesh,
        options: &Options,
        scheme: Scheme,
        levels: u32,
        textured: bool,
    ) -> Result<Self, RenderError> {
        let steps = Steps::of(scheme).ok_or(RenderError::Scheme {
            scheme: scheme.name(),
            what: "a refined level",
        })?;
        let m = &refine_mesh(mesh, options, steps, levels, true)?;
        let channel = match textured {
            true => Some(uv_channel(m).ok_or(RenderError::NoTextureCoordinates)?),
            false => None,
        };
        // Per triangle, the texture coordinates of its corners.
        let mut uv_values: Vec<[f64; 2]> = channel.map_or_else(Vec::new, |c| {
            c.values()
                .chunks_exact(c.dim())
                .map(|x| [x[0], x.get(1).copied().unwrap_or(0.0)])
                .collect()
        });
        let mut corner_uv: Vec<[u32; 3]> = Vec::new();
        let mut hole = vec![false; m.num_faces()];
        for &h in &m.tags.holes {
            if let Some(x) = hole.get_mut(h as usize) {
                *x = true;
            }
        }
        let base_face = base_faces(mesh, steps, levels, m.num_faces());
        let mut positions = m.positions().to_vec();
        let (mut normals, polygon_normal) = normals_of(m, &hole);
        let (mut triangles, mut flat, mut face) = (Vec::new(), Vec::new(), Vec::new());
        for (f, fv) in m.faces().enumerate() {
            if hole[f] {
                continue;
            }
            let start = m.face_offsets()[f] as usize;
            // The corner of `fv` that vertex `v` is (the face's centre: `n`).
            let uv_of = |v: u32, centre: u32| -> u32 {
                let c = channel.map_or(&[][..], |c| c.indices());
                match fv.iter().position(|&x| x == v) {
                    Some(i) if !c.is_empty() => c[start + i],
                    _ => centre,
                }
            };
            let centre_uv = match channel {
                Some(c) if fv.len() > 4 => {
                    let k = &c.indices()[start..start + fv.len()];
                    let mean = |i: usize| {
                        k.iter().map(|&x| uv_values[x as usize][i]).sum::<f64>() / k.len() as f64
                    };
                    let centre = [mean(0), mean(1)];
                    uv_values.push(centre);
                    (uv_values.len() - 1) as u32
                }
                _ => 0,
            };
            let mut push = |t: [u32; 3]| {
                triangles.push(t);
                flat.push(polygon_normal[f]);
                face.push(base_face[f]);
                if channel.is_some() {
                    corner_uv.push(t.map(|v| uv_of(v, centre_uv)));
                }
            };
            match fv.len() {
                3 => push([fv[0], fv[1], fv[2]]),
                4 => split_quad(&positions, [fv[0], fv[1], fv[2], fv[3]])
                    .into_iter()
                    .for_each(&mut push),
                n => {
                    // A fan around the centroid (also fine for non-convex n-gons that are
                    // star-shaped from it).
                    let c = push_centroid(&mut positions, &mut normals, fv);
                    for i in 0..n {
                        push([fv[i], fv[(i + 1) % n], c]);
                    }
                }
            }
        }
        let mut scene = Self {
            positions,
            normals,
            values: None,
            triangles,
            flat,
            face,
            face_colour: Vec::new(),
            edges: Vec::new(),
            uv: None,
        };
        if channel.is_some() {
            scene.unweld(&corner_uv, &uv_values);
        }
        Ok(scene)
    }

    /// Gives every vertex one texture coordinate: `corner_uv` holds, per triangle, the
    /// indices into `values` of its corners' coordinates; a vertex whose corners take
    /// several (on a seam) is copied once per coordinate, with its position and normal.
    fn unweld(&mut self, corner_uv: &[[u32; 3]], values: &[[f64; 2]]) {
        let mut copies: std::collections::HashMap<(u32, u32), u32> = Default::default();
        let (mut positions, mut normals, mut uv) = (Vec::new(), Vec::new(), Vec::new());
        for (t, ks) in self.triangles.iter_mut().zip(corner_uv) {
            for (v, &k) in t.iter_mut().zip(ks) {
                *v = *copies.entry((*v, k)).or_insert_with(|| {
                    positions.push(self.positions[*v as usize]);
                    normals.push(self.normals[*v as usize]);
                    uv.push(values[k as usize]);
                    (uv.len() - 1) as u32
                });
            }
        }
        self.positions = positions;
        self.normals = normals;
        self.uv = Some(uv);
    }

    /// Centre of the bounding box of the drawn vertices (and of the control mesh when
    /// `with_edges`) and the radius of the smallest sphere around it holding them all.
    pub(super) fn bounding_sphere(&self, with_edges: bool) -> (V3, f64) {
        let mut used = vec![false; self.positions.len()];
        for t in &self.triangles {
            t.iter().for_each(|&v| used[v as usize] = true);
        }
        let points = || {
            self.positions
                .iter()
                .zip(&used)
                .filter(|(_, &u)| u)
                .map(|(p, _)| p)
                .chain(
                    self.edges
                        .iter()
                        .filter(move |_| with_edges)
                        .flat_map(|e| e.iter()),
                )
        };
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in points() {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if !lo[0].is_finite() {
            return ([0.0; 3], 1.0);
        }
        let c = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        let r = points().fold(0.0f64, |r, p| r.max(geom::norm(&geom::sub(p, &c))));
        (c, r)
    }

    /// Projects every vertex.
    pub(super) fn project(&self, camera: &Camera, scale: f64) -> Frame {
        let view_pos: Vec<V3> = self
            .positions
            .par_iter()
            .map(|p| camera.to_view(p))
            .collect();
        let screen = view_pos
            .par_iter()
            .map(|v| camera.project_view(v, scale))
            .collect();
        let view_normal = self
            .normals
            .par_iter()
            .map(|n| camera.dir_to_view(n))
            .collect();
        let view_flat = self
            .flat
            .par_iter()
            .map(|n| camera.dir_to_view(n))
            .collect();
        Frame {
            screen,
            view_pos,
            view_normal,
            view_flat,
        }
    }
}

/// The most polygons [`Scene::build`] draws (2²⁴; the scene takes about 200 bytes per
/// vertex).
pub(crate) const MAX_DRAWN_FACES: u64 = 1 << 24;

/// How many polygons drawing `mesh` as `geometry` with `scheme` makes (an upper bound:
/// holes counted).
fn drawn_faces(mesh: &PolyMesh, geometry: Geometry, scheme: Scheme) -> u128 {
    let triangles = scheme == Scheme::Loop;
    match geometry {
        Geometry::Limit { rate } => {
            let r = u128::from(rate) + 1;
            mesh.faces()
                .map(|f| match f.len() {
                    4 => r * r,
                    _ if triangles => r * r,
                    n => n as u128 * (r / 2 + 1) * (r / 2 + 1),
                })
                .sum()
        }
        Geometry::Level(0) => mesh.num_faces() as u128,
        Geometry::Level(l) => {
            // The first level has a quad per face corner, or four triangles per triangle.
            let shift = 2 * u128::from(l - 1);
            let s = match triangles {
                true => 4 * mesh.num_faces() as u128,
                false => mesh.face_verts().len() as u128,
            };
            if shift >= 100 {
                u128::MAX
            } else {
                s.saturating_mul(1u128 << shift)
            }
        }
    }
}

/// Quad `a b c d` as two triangles, split along its shorter diagonal in space (`a c` when
/// both are equally long).
fn split_quad(p: &[V3], [a, b, c, d]: [u32; 4]) -> [[u32; 3]; 2] {
    let len = |x: u32, y: u32| {
        let e = geom::sub(&p[x as usize], &p[y as usize]);
        geom::dot(&e, &e)
    };
    if len(b, d) < len(a, c) {
        [[a, b, d], [b, c, d]]
    } else {
        [[a, b, c], [a, c, d]]
    }
}

/// The distinct edges of the control mesh (of every face, holes included).
fn control_edges(mesh: &PolyMesh) -> Vec<[V3; 2]> {
    let mut pairs: Vec<(u32, u32)> = mesh
        .faces()
        .flat_map(|fv| {
            (0..fv.len()).map(move |i| {
                let (a, b) = (fv[i], fv[(i + 1) % fv.len()]);
                (a.min(b), a.max(b))
            })
        })
        .filter(|(a, b)| a != b)
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    let p = mesh.positions();
    pairs
        .into_iter()
        .map(|(a, b)| [p[a as usize], p[b as usize]])
        .collect()
}

/// Colours of [`Paint::Faces`].
pub(crate) const FACE_PALETTE: usize = 6;

/// A colour index per base face such that faces sharing an edge differ when possible:
/// greedy colouring in face order, each face taking the lowest index its already coloured
/// neighbours do not use (on a quad grid numbered by rows this is a checkerboard; on a
/// cube, three colours). Faces with `palette` or more coloured neighbours cycle.
pub(crate) fn face_colours(mesh: &PolyMesh, palette: usize) -> Vec<u8> {
    let mut edges: Vec<(u32, u32, u32)> = mesh
        .faces()
        .enumerate()
        .flat_map(|(f, fv)| {
            (0..fv.len()).map(move |i| {
                let (a, b) = (fv[i], fv[(i + 1) % fv.len()]);
                (a.min(b), a.max(b), f as u32)
            })
        })
        .collect();
    edges.sort_unstable();
    let mut neighbours = vec![Vec::new(); mesh.num_faces()];
    for run in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        for x in run {
            for y in run {
                if x.2 != y.2 {
                    neighbours[x.2 as usize].push(y.2);
                }
            }
        }
    }
    let mut colour = vec![u8::MAX; mesh.num_faces()];
    for f in 0..mesh.num_faces() {
        let mut used = vec![false; palette];
        for &g in &neighbours[f] {
            if let Some(u) = used.get_mut(colour[g as usize] as usize) {
                *u = true;
            }
        }
        let c = used.iter().position(|&u| !u).unwrap_or(f % palette.max(1));
        colour[f] = c as u8;
    }
    colour
}

/// Replaces NaN values by the mean of the known values of the vertices sharing a cell
/// with them (twice, so that a missing value next to a missing value is filled too).
fn fill_missing(values: &mut [f64], cells: &[Cell]) {
    for _ in 0..2 {
        if !values.iter().any(|v| v.is_nan()) {
            return;
        }
        let mut sum = vec![(0.0, 0u32); values.len()];
        for q in cells.iter().map(Cell::verts) {
            for &a in q {
                if !values[a as usize].is_nan() {
                    continue;
                }
                for &b in q {
                    let x = values[b as usize];
                    if !x.is_nan() {
                        sum[a as usize].0 += x;
                        sum[a as usize].1 += 1;
                    }
                }
            }
        }
        for (v, (s, n)) in values.iter_mut().zip(sum) {
            if v.is_nan() && n > 0 {
                *v = s / f64::from(n);
            }
        }
    }
}

/// A cell of a [`LimitGrid`]: a quad of a quad domain's grid, or a triangle of a
/// triangle domain's (see [`tessellate`]), counter-clockwise like its base face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cell {
    Quad([u32; 4]),
    Tri([u32; 3]),
}

impl Cell {
    fn verts(&self) -> &[u32] {
        match self {
            Cell::Quad(q) => q,
            Cell::Tri(t) => t,
        }
    }
}

/// The limit surface sampled on a grid per (sub-)face, each grid with its own vertices
/// evaluated from its own face; positions from the watertight tessellation (so that
/// neighbouring grids meet exactly).
pub(crate) struct LimitGrid {
    /// Positions (shared samples bit-identical across grids).
    pub positions: Vec<V3>,
    /// Unit normals from the exact limit derivatives of the grid's own face (the
    /// tessellation's normal where those are degenerate).
    pub normals: Vec<V3>,
    /// Where each vertex was evaluated.
    pub points: Vec<SurfacePoint>,
    /// Exact curvature per vertex (`None` where the second derivatives are degenerate:
    /// at irregular corners), when asked for.
    pub curvature: Option<Vec<Option<Curvature>>>,
    /// Grid cells.
    pub cells: Vec<Cell>,
    /// Per cell, its base face.
    pub cell_face: Vec<u32>,
}

impl LimitGrid {
    /// Samples the limit surface of `mesh` under `scheme` at `rate`, evaluating `other`
    /// (positions, normals and curvature) on the same grid instead when given, with the
    /// limit surface within `max_bytes` (see [`Render::surface_memory`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn sample_with(
        mesh: &PolyMesh,
        options: &Options,
        scheme: Scheme,
        rate: u32,
        with_curvature: bool,
        other: Option<&dyn Surface>,
        max_bytes: Option<u64>,
    ) -> Result<Self, RenderError> {
        let surface = limit_surface(mesh, options, scheme, rate, max_bytes)?;
        let t = tessellate(&*surface, mesh, rate, false)?;
        let (mut g, layout) = Self::layout(&*surface, &t);
        g.evaluate(
            other.unwrap_or(&*surface),
            other.is_some(),
            &layout,
            with_curvature,
        )?;
        Ok(g)
    }

    /// The grids of the tessellation `t` of `surface`, one per (sub-)face, positions from
    /// `t` and normals not yet evaluated; and per grid vertex the tessellation's normal
    /// (the fallback where the derivatives are degenerate) and whether it is a grid corner.
    fn layout(surface: &dyn Surface, t: &Tessellation) -> (Self, GridLayout) {
        let mut g = LimitGrid {
            positions: Vec::new(),
            normals: Vec::new(),
            points: Vec::new(),
            curvature: None,
            cells: Vec::with_capacity(t.num_faces()),
            cell_face: Vec::with_capacity(t.num_faces()),
        };
        let mut fallback = Vec::new();
        let mut corner = Vec::new();
        // Output faces come per (sub-)face, each a row-major grid of cells from
        // (u, v) = (0, 0) (see `tessellate`).
        let mut q = 0;
        while q < t.num_faces() {
            let (face, sub) = t.source[q];
            let run = t.source[q..]
                .iter()
                .take_while(|&&s| s == (face, sub))
                .count();
            let tri = surface.domain(face as usize) == Domain::Triangle;
            let s = if tri || surface.num_subfaces(face as usize) == 1 {
                t.rate
            } else {
                t.rate / 2
            }
            .max(1) as usize;
            let side = s + 1;
            let base = g.positions.len() as u32;
            // Per grid point `(a, b)` at `b * side + a`, its tessellation vertex.
            let mut grid = vec![u32::MAX; side * side];
            // The cells in grid points, in `tessellate`'s order.
            let at = |a: usize, b: usize| (b * side + a) as u32;
            let mut cells = Vec::with_capacity(run);
            if tri {
                for b in 0..s {
                    for a in 0..s - b {
                        cells.push(Cell::Tri([at(a, b), at(a + 1, b), at(a, b + 1)]));
                        if a + 1 < s - b {
                            cells.push(Cell::Tri([at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)]));
                        }
                    }
                }
            } else {
                for c in 0..s * s {
                    let (a, b) = (c % s, c / s);
                    let quad = [at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)];
                    cells.push(Cell::Quad(quad));
                }
            }
            // The grid's vertices, row by row (on a triangle only those with a + b ≤ s).
            let inside = |i: usize| !tri || i % side + i / side <= s;
            let mut local = vec![u32::MAX; side * side];
            let kept = (0..side * side).filter(|&i| inside(i));
            for (i, v) in kept.zip(base..) {
                local[i] = v;
            }
            for (c, cell) in cells.iter().take(run).enumerate() {
                for (&i, &v) in cell.verts().iter().zip(t.face(q + c)) {
                    grid[i as usize] = v;
                }
                g.cells.push(match *cell {
                    Cell::Quad(q) => Cell::Quad(q.map(|i| local[i as usize])),
                    Cell::Tri(t) => Cell::Tri(t.map(|i| local[i as usize])),
                });
                g.cell_face.push(face);
            }
            for (i, &v) in grid.iter().enumerate().filter(|&(i, _)| inside(i)) {
                let (a, b) = (i % side, i / side);
                // Unused only if the run were short (never, per `tessellate`'s layout).
                let v = if v == u32::MAX { 0 } else { v as usize };
                g.positions.push(t.positions[v]);
                fallback.push(t.normals[v]);
                let end = |x: usize| x == 0 || x == s;
                corner.push(end(a) && end(b) && (!tri || a + b <= s));
                g.points.push(SurfacePoint {
                    face,
                    subface: sub,
                    u: a as f64 / s as f64,
                    v: b as f64 / s as f64,
                });
            }
            q += run;
        }
        (g, GridLayout { fallback, corner })
    }
    /// Evaluates `surface` (whose positions replace the tessellation's when `moved`: another
    /// surface than the tessellated one) at every grid point: the unit normals (`layout`'s fallback where degenerate) and,
    /// `with_curvature`, the curvature (none at irregular corners, where the evaluator
    /// returns tangents and zero second derivatives).
    fn evaluate(
        &mut self,
        surface: &dyn Surface,
        moved: bool,
        layout: &GridLayout,
        with_curvature: bool,
    ) -> Result<(), RenderError> {
        let order = if with_curvature {
            Order::Second
        } else {
            Order::First
        };
        let mut curv = Vec::new();
        let mut evaluated: Vec<Result<Derivatives, EvalError>> = Vec::new();
        for (i, chunk) in self.points.chunks(CHUNK).enumerate() {
            evaluated.clear();
            evaluated.resize(chunk.len(), Ok(Derivatives::default()));
            surface.evaluate_many(chunk, order, &mut evaluated);
            for (j, d) in evaluated.drain(..).enumerate() {
                let d = d?;
                let k = i * CHUNK + j;
                if moved {
                    self.positions[k] = d.p;
                }
                let n = d.normal();
                self.normals
                    .push(if n == [0.0; 3] { layout.fallback[k] } else { n });
                if with_curvature {
                    let flat = d.duu == [0.0; 3] && d.duv == [0.0; 3] && d.dvv == [0.0; 3];
                    curv.push(if layout.corner[k] && flat {
                        None
                    } else {
                        Curvature::from_derivatives(&d)
                    });
                }
            }
        }
        if with_curvature {
            self.curvature = Some(curv);
        }
        Ok(())
    }
}

/// Per vertex of a [`LimitGrid`] being sampled: the tessellation's normal, used where the
/// limit normal is degenerate, and whether it is a corner of its grid.
struct GridLayout {
    fallback: Vec<V3>,
    corner: Vec<bool>,
}

/// `mesh`'s texture coordinates: its face-varying channel named `"uv"`.
fn uv_channel(mesh: &PolyMesh) -> Option<&FaceVarying> {
    mesh.face_varying.iter().find(|c| c.name() == "uv")
}

/// The limit of `mesh`'s texture coordinates (the first two components) at `points`.
fn grid_uvs(
    mesh: &PolyMesh,
    options: &Options,
    scheme: Scheme,
    points: &[SurfacePoint],
) -> Result<Vec<[f64; 2]>, RenderError> {
    let c = (mesh.face_varying.iter())
        .position(|c| c.name() == "uv")
        .ok_or(RenderError::NoTextureCoordinates)?;
    let surface = FaceVaryingSurface::for_scheme(mesh, scheme, *options, c)?;
    let mut out = Vec::with_capacity(points.len());
    for chunk in points.chunks(CHUNK) {
        let got = surface.eval_many(chunk)?;
        out.extend((0..got.len()).map(|i| {
            let x = got.value_at(i);
            [x[0], x.get(1).copied().unwrap_or(0.0)]
        }));
    }
    Ok(out)
}

/// The base face of each of the `num_faces` faces of `mesh` refined `levels` times with
/// `steps`. Refined face `i` comes from level-1 face `i >> 2(levels - 1)`, which is the
/// child of the base face owning that face-vertex slot (OpenSubdiv's numbering, see
/// ARCHITECTURE.md); with Loop, from base face `i >> 2 levels` (four children per
/// triangle).
fn base_faces(mesh: &PolyMesh, steps: Steps, levels: u32, num_faces: usize) -> Vec<u32> {
    if levels == 0 {
        return (0..num_faces as u32).collect();
    }
    if steps == Steps::Loop {
        return (0..num_faces)
            .map(|i| i.checked_shr(2 * levels).unwrap_or(0) as u32)
            .collect();
    }
    let mut slot_face = vec![0u32; mesh.face_verts().len()];
    let o = mesh.face_offsets();
    for f in 0..mesh.num_faces() {
        slot_face[o[f] as usize..o[f + 1] as usize].fill(f as u32);
    }
    (0..num_faces)
        .map(|i| {
            let slot = i.checked_shr(2 * (levels - 1)).unwrap_or(0);
            slot_face.get(slot).copied().unwrap_or(0)
        })
        .collect()
}

/// Appends the centroid of the polygon `fv` to `positions`, with the normalised sum of its
/// corners' normals to `normals`, and returns its index.
fn push_centroid(positions: &mut Vec<V3>, normals: &mut Vec<V3>, fv: &[u32]) -> u32 {
    let c = positions.len() as u32;
    let n = fv.len() as f64;
    let mut centre = [0.0; 3];
    let mut nrm = [0.0; 3];
    for &v in fv {
        (0..3).for_each(|k| {
            centre[k] += positions[v as usize][k] / n;
            nrm[k] += normals[v as usize][k];
        });
    }
    positions.push(centre);
    normals.push(geom::normalize_or_zero(nrm));
    c
}

/// The normals of a polygon mesh `m`, faces marked in `hole` left out: per vertex the
/// normalised sum of the Newell normals of its faces, and per face its unit Newell normal
/// (zero for holes and degenerate faces).
fn normals_of(m: &PolyMesh, hole: &[bool]) -> (Vec<V3>, Vec<V3>) {
    let positions = m.positions();
    let mut acc = vec![[0.0; 3]; positions.len()];
    let mut polygon_normal = vec![[0.0; 3]; m.num_faces()];
    for (f, fv) in m.faces().enumerate() {
        if hole[f] {
            continue;
        }
        let n = geom::newell_normal(positions, fv);
        for &v in fv {
            (0..3).for_each(|k| acc[v as usize][k] += n[k]);
        }
        polygon_normal[f] = geom::normalize_or_zero(n);
    }
    let normals = acc.into_iter().map(geom::normalize_or_zero).collect();
    (normals, polygon_normal)
}

/// The limit surface of `mesh` under `scheme` (Catmull-Clark's [`LimitSurface`], Loop's
/// [`LoopSurface`], the bilinear [`BilinearSurface`]), built within `max_bytes` when given, which its evaluation at `rate` must
/// fit too.
fn limit_surface(
    mesh: &PolyMesh,
    options: &Options,
    scheme: Scheme,
    rate: u32,
    max_bytes: Option<u64>,
) -> Result<Box<dyn Surface>, RenderError> {
    match scheme {
        Scheme::CatmullClark => Ok(Box::new(surface_within(mesh, options, rate, max_bytes)?)),
        Scheme::Loop | Scheme::Bilinear => {
            // The surface keeps the topology and the points (as much as the Catmull-Clark
            // surface's build); Loop's refinement of a face lives only while it is
            // evaluated.
            let estimate = LimitSurface::estimate_build_memory(mesh);
            if let Some(limit) = max_bytes.filter(|&limit| estimate > limit) {
                return Err(RenderError::SurfaceMemory {
                    rate,
                    estimate,
                    limit,
                });
            }
            Ok(match scheme {
                Scheme::Loop => Box::new(LoopSurface::new(mesh, *options)?),
                _ => Box::new(BilinearSurface::new(mesh)?),
            })
        }
        _ => Err(RenderError::Scheme {
            scheme: scheme.name(),
            what: "a limit surface",
        }),
    }
}

/// The Catmull-Clark limit surface of `mesh`, built within `max_bytes` when given, which its
/// evaluation at `rate` must fit too.
fn surface_within(
    mesh: &PolyMesh,
    options: &Options,
    rate: u32,
    max_bytes: Option<u64>,
) -> Result<LimitSurface, RenderError> {
    let Some(limit) = max_bytes else {
        return Ok(LimitSurface::new(mesh, *options)?);
    };
    let surface = LimitSurface::new_within(mesh, *options, limit)?;
    let estimate = surface.estimate_memory(rate);
    if estimate > limit {
        return Err(RenderError::SurfaceMemory {
            rate,
            estimate,
            limit,
        });
    }
    Ok(surface)
}
