//! # Properties of Catmull-Clark refinement, as specifications
//!
//! The golden tests (`osd_golden.rs`) pin subsurf to OpenSubdiv on fixed shapes. The
//! properties here hold for *every* mesh, and are checked on random ones (proptest):
//!
//! 1. **Affine invariance** — refinement and limit evaluation are linear in the control
//!    points with weights that sum to one, so they commute with affine maps; limit normals
//!    transform with the cofactor matrix.
//! 2. **Regular torus = uniform bicubic B-spline** — on a closed regular quad grid, the limit
//!    positions and normals at the refined vertices are those of the periodic B-spline at the
//!    dyadic parameters, found through the documented child numbering.
//! 3. **Topology** — Euler characteristic preserved, closed stays closed, boundary edges
//!    double per level, only quads after one level, face counts `S · 4^(L-1)`.
//! 4. **Refining `a` then `b` (through an OBJ file) equals refining `a + b`** — the same
//!    surface, faces and tags, vertex for vertex up to the numbering of edge-vertices.
//! 5. **Symmetry** — a mirror-symmetric mesh refines to a mirror-symmetric result.
//! 6. **Partition of unity** — constants stay constant, at every level and in the limit.
//! 7. **Bad input** — every error names the element at fault.
//! 8. **Listing a face from another corner** changes nothing but its parameter domain:
//!    the limit surface is the same, and faces whose 1-rings differ only by that share
//!    one configuration.
//!
//! Random meshes are quad grids (open, 2..6 × 2..6 cells) or tori (closed, 3..6 × 3..6)
//! with jittered vertices; some cells are split into two triangles or merged into hexagons
//! and pentagons, and random creases (fractional, integral and infinite sharpness), corners
//! and holes are tagged; the scheme options (boundary mode, crease method, triangle rule)
//! are random too. `PROPTEST_CASES=20000 cargo test -p subsurf --test integration properties::`
//! searches deeper (about a minute).
//!
// Geometry helpers walk parallel arrays with one index.
#![allow(clippy::needless_range_loop)]

use std::collections::{HashMap, HashSet};

use proptest::prelude::*;

use subsurf::io::{parse_obj, write_obj, WriteOptions};
use subsurf::limit::{LimitSurface, SurfacePoint};
use subsurf::mesh::{
    BoundaryInterpolation, Corner, Crease, CreaseMethod, MeshError, Options, PolyMesh, Rule, Tags,
    Topology, TriangleSubdivision, VertexTag,
};
use subsurf::refine::TopologyRefiner;
use subsurf::{subdivide, Error, SubdivideOptions, Subdivision};

use crate::common::schemes;
use crate::common::schemes::SplitMix64 as Rng;
use schemes::{config, fail, mat_vec, options_strategy, scale_of, Mat3, P3};

// =======================================================================================
// Small deterministic random source for the details of a generated mesh
// =======================================================================================

/// This module's draw of a sharpness value.
trait DrawTags {
    fn sharpness(&mut self) -> f32;
}

impl DrawTags for Rng {
    /// A sharpness value: fractional, integral, infinite (10 and above) or arbitrary.
    fn sharpness(&mut self) -> f32 {
        const CHOICES: [f32; 10] = [0.3, 0.7, 1.0, 1.3, 2.0, 2.5, 3.2, 10.0, 12.0, 0.0];
        if self.below(4) == 0 {
            (self.unit() * 4.0) as f32
        } else {
            CHOICES[self.below(CHOICES.len())]
        }
    }
}

// =======================================================================================
// Random meshes
// =======================================================================================

/// A random quad-dominant mesh: an open `nx × ny` grid or a closed `nx × ny` torus.
#[derive(Clone, Debug)]
struct MeshSpec {
    nx: usize,
    ny: usize,
    closed: bool,
    /// Vertex jitter, relative to the cell size.
    jitter: f64,
    /// Split some cells into triangles and merge some pairs into hexagons and pentagons.
    face_edits: bool,
    creases: usize,
    corners: usize,
    holes: usize,
    options: Options,
    seed: u64,
}

/// Random meshes with up to `max_holes` holes.
fn mesh_spec(max_holes: usize) -> impl Strategy<Value = MeshSpec> {
    (
        (2usize..=6, 2usize..=6, any::<bool>()),
        0.0..0.3f64,
        any::<bool>(),
        (0usize..=6, 0usize..=3, 0usize..=max_holes),
        options_strategy(),
        any::<u64>(),
    )
        .prop_map(
            |((nx, ny, closed), jitter, face_edits, (creases, corners, holes), options, seed)| {
                // A torus needs three cells around each way, or two faces would share a
                // vertex pair twice (a non-manifold edge).
                let (nx, ny) = if closed {
                    (nx.max(3), ny.max(3))
                } else {
                    (nx, ny)
                };
                MeshSpec {
                    nx,
                    ny,
                    closed,
                    jitter,
                    face_edits,
                    creases,
                    corners,
                    holes,
                    options,
                    seed,
                }
            },
        )
}

/// Vertex index of grid point `(i, j)` (wrapping on a torus).
fn grid_vertex(nx: usize, ny: usize, closed: bool, i: usize, j: usize) -> u32 {
    let (cols, rows) = if closed { (nx, ny) } else { (nx + 1, ny + 1) };
    ((j % rows) * cols + (i % cols)) as u32
}

/// Positions of an open grid in the plane z = 0 (unit cells) or of a torus (radii 2.5, 1).
fn grid_positions(nx: usize, ny: usize, closed: bool) -> Vec<P3> {
    let (cols, rows) = if closed { (nx, ny) } else { (nx + 1, ny + 1) };
    let mut p = Vec::with_capacity(cols * rows);
    for j in 0..rows {
        for i in 0..cols {
            if closed {
                let th = 2.0 * std::f64::consts::PI * i as f64 / nx as f64;
                let ph = 2.0 * std::f64::consts::PI * j as f64 / ny as f64;
                let rr = 2.5 + ph.cos();
                p.push([rr * th.cos(), rr * th.sin(), ph.sin()]);
            } else {
                p.push([i as f64, j as f64, 0.0]);
            }
        }
    }
    p
}

/// The faces of the grid (or torus), cell by cell and row by row, with random edits when
/// `rng` is given: a cell is kept, split
/// into two triangles along a random diagonal, merged with its right neighbour into a
/// hexagon, or merged with the left triangle of its split right neighbour into a pentagon.
/// All faces are counter-clockwise in (i, j).
fn grid_faces(nx: usize, ny: usize, closed: bool, mut rng: Option<&mut Rng>) -> Vec<Vec<u32>> {
    let v = |i: usize, j: usize| grid_vertex(nx, ny, closed, i, j);
    let mut faces = Vec::new();
    for j in 0..ny {
        let mut i = 0;
        while i < nx {
            let kind = rng.as_mut().map_or(0, |r| r.below(8));
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            let can_merge = i + 1 < nx;
            match kind {
                5 => {
                    if rng.as_mut().is_some_and(|r| r.below(2) == 0) {
                        faces.push(vec![a, b, c]);
                        faces.push(vec![a, c, d]);
                    } else {
                        faces.push(vec![a, b, d]);
                        faces.push(vec![b, c, d]);
                    }
                    i += 1;
                }
                6 if can_merge => {
                    let (e, g) = (v(i + 2, j), v(i + 2, j + 1));
                    faces.push(vec![a, b, e, g, c, d]);
                    i += 2;
                }
                7 if can_merge => {
                    let (e, g) = (v(i + 2, j), v(i + 2, j + 1));
                    faces.push(vec![a, b, g, c, d]);
                    faces.push(vec![b, e, g]);
                    i += 2;
                }
                _ => {
                    faces.push(vec![a, b, c, d]);
                    i += 1;
                }
            }
        }
    }
    faces
}

impl MeshSpec {
    fn build(&self) -> PolyMesh {
        let mut rng = Rng(self.seed);
        let mut pos = grid_positions(self.nx, self.ny, self.closed);
        for p in &mut pos {
            for c in p.iter_mut() {
                *c += self.jitter * rng.signed();
            }
        }
        let faces = grid_faces(
            self.nx,
            self.ny,
            self.closed,
            if self.face_edits {
                Some(&mut rng)
            } else {
                None
            },
        );
        let nv = pos.len();
        let mut tags = Tags::default();
        for _ in 0..self.creases {
            let f = &faces[rng.below(faces.len())];
            let k = rng.below(f.len());
            tags.creases.push(Crease {
                v0: f[k],
                v1: f[(k + 1) % f.len()],
                sharpness: rng.sharpness(),
            });
        }
        for _ in 0..self.corners {
            tags.corners.push(Corner {
                vertex: rng.below(nv) as u32,
                sharpness: rng.sharpness(),
            });
        }
        for _ in 0..self.holes {
            tags.holes.push(rng.below(faces.len()) as u32);
        }
        let mut mesh = PolyMesh::from_faces(pos, &faces).expect("generated meshes are valid");
        mesh.tags = tags;
        mesh.validate().expect("generated tags are valid");
        mesh
    }
}

// =======================================================================================
// Geometry helpers
// =======================================================================================

fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for r in 0..3 {
        for k in 0..3 {
            c[r][k] = a[r][0] * b[0][k] + a[r][1] * b[1][k] + a[r][2] * b[2][k];
        }
    }
    c
}

fn cross(a: &P3, b: &P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: &P3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn normalize(a: &P3) -> P3 {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

fn dist(a: &P3, b: &P3) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)
}

/// The cofactor matrix `det(A) A^{-T}`: `(A u) × (A v) = cof(A) (u × v)`. Its rows are
/// the cross products of A's rows.
fn cofactor(a: &Mat3) -> Mat3 {
    [
        cross(&a[1], &a[2]),
        cross(&a[2], &a[0]),
        cross(&a[0], &a[1]),
    ]
}

/// Rotation from three Euler angles (z, y, z).
fn rotation(a: f64, b: f64, c: f64) -> Mat3 {
    let rz = |t: f64| {
        [
            [t.cos(), -t.sin(), 0.0],
            [t.sin(), t.cos(), 0.0],
            [0.0, 0.0, 1.0],
        ]
    };
    let ry = |t: f64| {
        [
            [t.cos(), 0.0, t.sin()],
            [0.0, 1.0, 0.0],
            [-t.sin(), 0.0, t.cos()],
        ]
    };
    mat_mul(&rz(a), &mat_mul(&ry(b), &rz(c)))
}

/// `got[i]` and `want[i]` agree to `tol` for every `i` (and the lengths agree).
fn compare_points(what: &str, got: &[P3], want: &[P3], tol: f64) -> Result<(), String> {
    if got.len() != want.len() {
        return Err(format!(
            "{what}: {} values, expected {}",
            got.len(),
            want.len()
        ));
    }
    let (mut worst, mut at) = (0.0, 0);
    for i in 0..got.len() {
        let d = dist(&got[i], &want[i]);
        if d > worst || d.is_nan() {
            worst = d;
            at = i;
        }
    }
    if worst <= tol {
        Ok(())
    } else {
        Err(format!(
            "{what}: vertex {at} is off by {worst:e} (tolerance {tol:e}): got {:?}, expected {:?}",
            got[at], want[at]
        ))
    }
}

fn run(mesh: &PolyMesh, opts: &SubdivideOptions) -> Subdivision {
    subdivide(mesh, opts).expect("generated meshes subdivide")
}

fn faces_of(mesh: &PolyMesh) -> Vec<Vec<u32>> {
    mesh.faces().map(<[u32]>::to_vec).collect()
}

// =======================================================================================
// 1. Affine invariance
// =======================================================================================

/// A well-conditioned affine map `x ↦ A x + b`: `A = R₁ · diag(s) · R₂` with singular
/// values in [0.5, 2] (all equal for a similarity), optionally a reflection.
#[derive(Clone, Debug)]
struct Affine {
    a: Mat3,
    b: P3,
}

fn affine_strategy() -> impl Strategy<Value = Affine> {
    let angle = || 0.0..std::f64::consts::TAU;
    (
        (angle(), angle(), angle(), angle(), angle(), angle()),
        (0.5..2.0f64, 0.5..2.0f64, 0.5..2.0f64),
        any::<bool>(),
        any::<bool>(),
        (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64),
    )
        .prop_map(|(r, (s0, s1, s2), similarity, reflect, (b0, b1, b2))| {
            let s = if similarity {
                [s0, s0, s0]
            } else {
                [s0, s1, s2]
            };
            let sign = if reflect { -1.0 } else { 1.0 };
            let d = [[sign * s[0], 0.0, 0.0], [0.0, s[1], 0.0], [0.0, 0.0, s[2]]];
            let a = mat_mul(
                &rotation(r.0, r.1, r.2),
                &mat_mul(&d, &rotation(r.3, r.4, r.5)),
            );
            Affine { a, b: [b0, b1, b2] }
        })
}

impl Affine {
    fn apply(&self, p: &P3) -> P3 {
        let y = mat_vec(&self.a, p);
        [y[0] + self.b[0], y[1] + self.b[1], y[2] + self.b[2]]
    }
}

proptest! {
    #![proptest_config(config(64))]

    /// **Affine invariance.** Every refined position (and every limit position) is an affine
    /// combination of control points — the weights of each mask sum to one — and the
    /// weights depend only on topology and sharpness, never on the positions. Hence, for
    /// any affine map `x ↦ A x + b`, `refine(A·P + b) = A·refine(P) + b`, at every level,
    /// with or without the limit. Limit tangents are linear combinations with weights
    /// summing to zero, so they transform by `A`, and normals `t₁ × t₂` by the cofactor
    /// matrix `det(A) A^{-T}` (for a rotation with uniform scale: the rotation itself;
    /// a reflection flips the orientation, and the normal with it).
    #[test]
    fn refinement_commutes_with_affine_maps(
        spec in mesh_spec(1),
        map in affine_strategy(),
        levels in 1u32..=3,
        limit in any::<bool>(),
    ) {
        let mesh = spec.build();
        let mut moved = mesh.clone();
        for p in moved.positions_mut() {
            *p = map.apply(p);
        }
        let opts = SubdivideOptions {
            levels,
            scheme: subsurf::Scheme::CatmullClark,
            options: spec.options,
            limit,
            keep_holes: true,
            max_memory: None,
        };
        let plain = run(&mesh, &opts);
        let of_moved = run(&moved, &opts);
        let moved_result: Vec<P3> = plain.mesh.positions().iter().map(|p| map.apply(p)).collect();
        let tol = 1e-12 * scale_of(&moved_result);
        compare_points("refine(A P + b) vs A refine(P) + b", of_moved.mesh.positions(), &moved_result, tol)
            .map_err(fail)?;
        prop_assert_eq!(faces_of(&of_moved.mesh), faces_of(&plain.mesh));

        if limit {
            let (n0, n1) = match (&plain.normals, &of_moved.normals) {
                (Some(a), Some(b)) => (a, b),
                _ => return Err(fail("limit: true gave no normals".into())),
            };
            let cof = cofactor(&map.a);
            let want: Vec<P3> = n0.iter().map(|n| normalize(&mat_vec(&cof, n))).collect();
            compare_points("normals of refine(A P + b) vs cof(A) normals", n1, &want, 1e-9)
                .map_err(fail)?;
        }
    }
}

// =======================================================================================
// 2. Regular torus = periodic uniform bicubic B-spline
// =======================================================================================

/// Uniform cubic B-spline basis on a knot span, `t ∈ [0, 1)`, for the control points
/// `k-1, k, k+1, k+2` of span `[k, k+1)`.
fn bspline_basis(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        s * s * s / 6.0,
        (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
        (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
        t * t * t / 6.0,
    ]
}

/// Derivative of [`bspline_basis`] with respect to `t`.
fn bspline_basis_derivative(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -0.5 * s * s,
        1.5 * t * t - 2.0 * t,
        -1.5 * t * t + t + 0.5,
        0.5 * t * t,
    ]
}

/// The periodic bicubic B-spline with control net `ctrl[i + n j]` (`n × m`, periodic in
/// both directions) at `(u, v) = (iu / den, iv / den)` in knot-span units: position,
/// `∂/∂u` and `∂/∂v`.
fn bspline_eval(ctrl: &[P3], n: usize, m: usize, iu: usize, iv: usize, den: usize) -> [P3; 3] {
    let (ku, kv) = (iu / den, iv / den);
    let (tu, tv) = (
        (iu % den) as f64 / den as f64,
        (iv % den) as f64 / den as f64,
    );
    let (bu, bv) = (bspline_basis(tu), bspline_basis(tv));
    let (du, dv) = (bspline_basis_derivative(tu), bspline_basis_derivative(tv));
    let mut out = [[0.0; 3]; 3];
    for a in 0..4 {
        let i = (ku + n + a - 1) % n;
        for b in 0..4 {
            let j = (kv + m + b - 1) % m;
            let p = &ctrl[i + n * j];
            let w = [bu[a] * bv[b], du[a] * bv[b], bu[a] * dv[b]];
            for (o, w) in out.iter_mut().zip(w) {
                for k in 0..3 {
                    o[k] += w * p[k];
                }
            }
        }
    }
    out
}

/// The difference `b - a` of two grid coordinates modulo `size`, which must be -1, 0 or 1.
fn wrapped_step(a: usize, b: usize, size: usize) -> Result<isize, String> {
    match (b + size - a) % size {
        0 => Ok(0),
        1 => Ok(1),
        d if d == size - 1 => Ok(-1),
        d => Err(format!(
            "grid coordinates {a} and {b} are {d} apart (mod {size})"
        )),
    }
}

fn wrap(x: isize, size: usize) -> usize {
    x.rem_euclid(size as isize) as usize
}

/// The grid coordinates `(I, J)` of every vertex of refined level `l`, on the
/// `n·2^l × m·2^l` grid, from the child numbering of `refine/topology.rs`: the child of
/// vertex `v` is `v` (coordinates doubled), of face `f` is `V + f` (the face's centre),
/// of edge `e` is `V + F + e` (the edge's midpoint).
fn grid_coordinates(
    r: &TopologyRefiner,
    n: usize,
    m: usize,
) -> Result<Vec<(usize, usize)>, String> {
    let mut coords: Vec<(usize, usize)> = (0..n * m).map(|v| (v % n, v / n)).collect();
    let (mut sn, mut sm) = (n, m);
    for l in 0..r.max_level() {
        let p: &Topology = r.level(l);
        let (nv, nf, ne) = (p.num_vertices(), p.num_faces(), p.num_edges());
        let step = |a: usize, b: usize| -> Result<(isize, isize), String> {
            Ok((
                wrapped_step(coords[a].0, coords[b].0, sn)?,
                wrapped_step(coords[a].1, coords[b].1, sm)?,
            ))
        };
        let (cn, cm) = (2 * sn, 2 * sm);
        let mut next = vec![(usize::MAX, usize::MAX); nv + nf + ne];
        for v in 0..nv {
            next[v] = (2 * coords[v].0, 2 * coords[v].1);
        }
        for f in 0..nf {
            let fv = p.face_vertices(f);
            if fv.len() != 4 {
                return Err(format!("level {l}: face {f} is not a quad"));
            }
            let (v0, v1, v3) = (fv[0] as usize, fv[1] as usize, fv[3] as usize);
            let (d1, d3) = (step(v0, v1)?, step(v0, v3)?);
            let (i, j) = (2 * coords[v0].0 as isize, 2 * coords[v0].1 as isize);
            next[nv + f] = (wrap(i + d1.0 + d3.0, cn), wrap(j + d1.1 + d3.1, cm));
        }
        for e in 0..ne {
            let [a, b] = p.edge_vertices(e);
            let d = step(a as usize, b as usize)?;
            let (i, j) = (
                2 * coords[a as usize].0 as isize,
                2 * coords[a as usize].1 as isize,
            );
            next[nv + nf + e] = (wrap(i + d.0, cn), wrap(j + d.1, cm));
        }
        coords = next;
        sn = cn;
        sm = cm;
    }
    // A bijection onto the grid.
    let mut seen = vec![false; sn * sm];
    for &(i, j) in &coords {
        if i >= sn || j >= sm || std::mem::replace(&mut seen[i + sn * j], true) {
            return Err(format!(
                "grid point ({i}, {j}) is hit twice or is out of range"
            ));
        }
    }
    if coords.len() != sn * sm {
        return Err(format!("{} vertices for a {sn} × {sm} grid", coords.len()));
    }
    Ok(coords)
}

/// Control points of a jittered `n × m` torus, vertex `(i, j)` at index `i + n j`.
fn torus_control_points(n: usize, m: usize, jitter: f64, seed: u64) -> Vec<P3> {
    let mut rng = Rng(seed);
    let mut p = grid_positions(n, m, true);
    for q in &mut p {
        for c in q.iter_mut() {
            *c += jitter * rng.signed();
        }
    }
    p
}

proptest! {
    #![proptest_config(config(32))]

    /// **A closed regular quad grid is a uniform bicubic B-spline surface.** Catmull-Clark
    /// generalises bicubic B-spline refinement; where every vertex has valence 4 and there
    /// are no tags, the limit surface is exactly the periodic B-spline with the control
    /// net as control points. Refining `L` levels and moving to the limit must therefore
    /// give the B-spline at the dyadic parameters: refined vertex `(I, J)` (found through
    /// the child numbering) is the surface point at `(I / 2^L, J / 2^L)` knot spans, and
    /// its limit normal is `∂u × ∂v / |∂u × ∂v|`, since the faces `(i,j) (i+1,j) (i+1,j+1)
    /// (i,j+1)` run counter-clockwise in (u, v). An independent evaluation of the basis
    /// checks masks, tangent masks, their orientation and the child numbering at once.
    #[test]
    fn regular_torus_limit_is_the_bicubic_bspline(
        n in 3usize..=6,
        m in 3usize..=6,
        levels in 1u32..=4,
        jitter in 0.0..0.4f64,
        seed in any::<u64>(),
    ) {
        let ctrl = torus_control_points(n, m, jitter, seed);
        let faces = grid_faces(n, m, true, None);
        let mesh = PolyMesh::from_faces(ctrl.clone(), &faces).expect("torus is valid");
        let out = run(&mesh, &SubdivideOptions { levels, limit: true, ..Default::default() });

        let mut r = TopologyRefiner::new(&mesh, subsurf::Scheme::CatmullClark, Options::default()).expect("torus is valid");
        r.refine_uniform(levels);
        let coords = grid_coordinates(&r, n, m).map_err(fail)?;
        let den = 1usize << levels;
        let (sn, sm) = (n * den, m * den);
        prop_assert_eq!(out.mesh.num_vertices(), sn * sm);

        // The output faces keep the (u, v) orientation of the base faces.
        for (f, fv) in out.mesh.faces().enumerate() {
            prop_assert_eq!(fv.len(), 4);
            let c: Vec<(usize, usize)> = fv.iter().map(|&v| coords[v as usize]).collect();
            let d1 = (
                wrapped_step(c[0].0, c[1].0, sn).map_err(fail)?,
                wrapped_step(c[0].1, c[1].1, sm).map_err(fail)?,
            );
            let d3 = (
                wrapped_step(c[0].0, c[3].0, sn).map_err(fail)?,
                wrapped_step(c[0].1, c[3].1, sm).map_err(fail)?,
            );
            prop_assert_eq!(d1.0 * d3.1 - d1.1 * d3.0, 1, "face {} runs clockwise in (u, v)", f);
        }

        let normals = out.normals.as_ref().ok_or_else(|| fail("no normals".into()))?;
        let mut want_p = Vec::with_capacity(coords.len());
        let mut want_n = Vec::with_capacity(coords.len());
        for &(i, j) in &coords {
            let [p, su, sv] = bspline_eval(&ctrl, n, m, i, j, den);
            want_p.push(p);
            want_n.push(normalize(&cross(&su, &sv)));
        }
        let tol = 1e-12 * scale_of(&ctrl);
        compare_points("limit positions vs B-spline", out.mesh.positions(), &want_p, tol)
            .map_err(fail)?;
        compare_points("limit normals vs B-spline ∂u × ∂v", normals, &want_n, 1e-10)
            .map_err(fail)?;
    }
}

// =======================================================================================
// 3. Euler characteristic, closedness, counts
// =======================================================================================

/// Faces per undirected edge.
fn edge_face_counts(mesh: &PolyMesh) -> HashMap<(u32, u32), usize> {
    let mut m = HashMap::new();
    for f in mesh.faces() {
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            *m.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    m
}

fn euler_characteristic(mesh: &PolyMesh) -> i64 {
    mesh.num_vertices() as i64 - edge_face_counts(mesh).len() as i64 + mesh.num_faces() as i64
}

proptest! {
    #![proptest_config(config(64))]

    /// **Refinement is a subdivision of the same topological surface.** Every face of size
    /// `n` is cut into `n` quads around a new face point, every edge into two at a new edge
    /// point; this is a cell subdivision, so the Euler characteristic `V − E + F` cannot
    /// change, a closed mesh stays closed (every edge has exactly two faces), each boundary
    /// edge becomes two boundary edges, every face after the first level is a quad, and the
    /// face count is the number of face corners `S` after one level and ×4 per level after.
    /// Holes are kept (`keep_holes`) so that the whole cell complex is counted.
    #[test]
    fn refinement_preserves_topology(spec in mesh_spec(1), levels in 1u32..=3) {
        let mesh = spec.build();
        let base_edges = edge_face_counts(&mesh);
        let base_boundary = base_edges.values().filter(|&&c| c == 1).count();
        prop_assert_eq!(base_boundary == 0, spec.closed);
        prop_assert!(base_edges.values().all(|&c| c <= 2));
        let s = mesh.face_verts().len();
        let chi = euler_characteristic(&mesh);
        let out = run(&mesh, &SubdivideOptions {
            levels,
            scheme: subsurf::Scheme::CatmullClark,
            options: spec.options,
            keep_holes: true,
            ..Default::default()
        });
        let m = &out.mesh;
        let edges = edge_face_counts(m);
        prop_assert_eq!(euler_characteristic(m), chi, "Euler characteristic changed");
        prop_assert_eq!(m.num_faces(), s << (2 * (levels - 1)), "face count");
        prop_assert!(m.faces().all(|f| f.len() == 4), "a face is not a quad");
        prop_assert!(edges.values().all(|&c| c == 1 || c == 2), "an edge has 0 or >2 faces");
        let boundary = edges.values().filter(|&&c| c == 1).count();
        prop_assert_eq!(boundary, base_boundary << levels, "boundary edges do not double");
        // Every vertex is used by some face.
        let used: HashSet<u32> = m.face_verts().iter().copied().collect();
        prop_assert_eq!(used.len(), m.num_vertices());
    }
}

// =======================================================================================
// 4. Refining a then b (through an OBJ file) equals refining a + b
// =======================================================================================

/// Whether the limit normal of a vertex with tag `tag` is a property of the surface alone:
/// at smooth and dart vertices, and on a boundary crease (faces on one side only). At an
/// interior crease or a corner the limit surface has a kink; the normal of the tangent
/// masks there is one-sided — it looks into the faces after the first sharp edge, or
/// spans the first two edges, in the vertex's rotational order (as in OpenSubdiv) — and
/// so depends on where that order starts, which numbering and orientation decide.
fn normal_is_well_defined(tag: VertexTag) -> bool {
    match tag.rule {
        Rule::Smooth | Rule::Dart => true,
        Rule::Crease => tag.boundary,
        Rule::Corner => false,
    }
}

/// The correspondence between two refinements of the same level-`a` mesh: `direct`, refined
/// from the base mesh (at least `a + b` levels), and `staged`, refined `b` levels from the
/// level-`a` mesh as read back from a file. Returns `π` with direct vertex `i` ↔ staged
/// vertex `π(i)` at level `a + b`.
///
/// Both follow the child numbering of `refine/topology.rs`, so the children of vertices
/// (`v`) and of faces (`V + f`) correspond index for index; only the children of edges
/// (`V + F + e`) may be permuted, because a level read from a file numbers its edges in
/// order of first appearance in its faces, while a refined level numbers them from its
/// parent (face-interior edges first, then the halves of parent edges).
fn staged_correspondence(
    direct: &TopologyRefiner,
    a: usize,
    staged: &TopologyRefiner,
) -> Result<Vec<u32>, String> {
    let (d0, s0) = (direct.level(a), staged.level(0));
    if d0.num_vertices() != s0.num_vertices() || d0.num_faces() != s0.num_faces() {
        return Err(format!(
            "level {a}: {} vertices and {} faces refined, {} and {} read back",
            d0.num_vertices(),
            d0.num_faces(),
            s0.num_vertices(),
            s0.num_faces()
        ));
    }
    let mut pi: Vec<u32> = (0..d0.num_vertices() as u32).collect();
    for l in 0..staged.max_level() {
        let (d, s) = (direct.level(a + l), staged.level(l));
        let (nv, nf, ne) = (d.num_vertices(), d.num_faces(), d.num_edges());
        if (nv, nf, ne) != (s.num_vertices(), s.num_faces(), s.num_edges()) {
            return Err(format!("level {}: different element counts", a + l));
        }
        for f in 0..nf {
            let mapped: Vec<u32> = d.face_vertices(f).iter().map(|&v| pi[v as usize]).collect();
            if mapped != s.face_vertices(f) {
                return Err(format!("level {}: face {f} differs", a + l));
            }
        }
        let mut next = pi.clone();
        next.extend((nv..nv + nf).map(|x| x as u32));
        for e in 0..ne {
            let [x, y] = d.edge_vertices(e);
            let g = s
                .find_edge(pi[x as usize], pi[y as usize])
                .ok_or_else(|| format!("level {}: edge {e} is missing", a + l))?;
            next.push((nv + nf) as u32 + g);
        }
        pi = next;
    }
    let distinct: HashSet<u32> = pi.iter().copied().collect();
    if distinct.len() != pi.len() {
        return Err("the correspondence is not a bijection".into());
    }
    Ok(pi)
}

/// Refines `mesh` `a` levels, writes the result as OBJ (with its scheme options), reads it
/// back, refines that `b` more levels with the options from the file, and compares with
/// refining `a + b` levels directly, through the vertex correspondence of
/// [`staged_correspondence`]: vertex count, positions (to 1e-12 relative), faces (in the
/// same order), holes, the sharpness left on creases and corners, and limit normals.
/// Returns how many vertices the staged refinement numbers differently.
fn check_two_step(
    mesh: &PolyMesh,
    options: Options,
    a: u32,
    b: u32,
    keep_holes: bool,
    limit: bool,
) -> Result<usize, String> {
    let opts = |levels, limit| SubdivideOptions {
        levels,
        scheme: subsurf::Scheme::CatmullClark,
        options,
        limit,
        keep_holes,
        max_memory: None,
    };
    let ctx = format!("levels {a} + {b}, {options:?}, keep_holes {keep_holes}, limit {limit}");
    let first = subdivide(mesh, &opts(a, false)).map_err(|e| format!("level {a}: {e}"))?;
    let mut buf = Vec::new();
    write_obj(
        &mut buf,
        &first.mesh,
        &WriteOptions {
            scheme: Some(options),
            ..Default::default()
        },
    )
    .map_err(|e| format!("write_obj: {e}"))?;
    let obj = parse_obj(&buf, "level_a.obj").map_err(|e| format!("parse_obj: {e}"))?;
    let read_options = obj.options.resolve(Options::default());
    if read_options != options {
        return Err(format!(
            "options do not round-trip: wrote {options:?}, read {read_options:?}"
        ));
    }
    if obj.mesh != first.mesh {
        return Err(format!(
            "{ctx}: the OBJ file does not round-trip the level-{a} mesh"
        ));
    }
    let staged = subdivide(
        &obj.mesh,
        &SubdivideOptions {
            options: read_options,
            ..opts(b, limit)
        },
    )
    .map_err(|e| format!("levels {a} then {b}: {e}"))?;
    let direct =
        subdivide(mesh, &opts(a + b, limit)).map_err(|e| format!("level {}: {e}", a + b))?;

    let mut rd = TopologyRefiner::new(mesh, subsurf::Scheme::CatmullClark, options)
        .map_err(|e| e.to_string())?;
    rd.refine_uniform(a + b);
    let mut rs = TopologyRefiner::new(&obj.mesh, subsurf::Scheme::CatmullClark, read_options)
        .map_err(|e| e.to_string())?;
    rs.refine_uniform(b);
    let pi = staged_correspondence(&rd, a as usize, &rs).map_err(|e| format!("{ctx}: {e}"))?;
    let (sm, dm) = (&staged.mesh, &direct.mesh);
    if sm.num_vertices() != dm.num_vertices() || pi.len() != dm.num_vertices() {
        return Err(format!(
            "{ctx}: {} vertices in two steps, {} directly",
            sm.num_vertices(),
            dm.num_vertices()
        ));
    }
    let permute = |values: &[P3]| -> Vec<P3> { pi.iter().map(|&j| values[j as usize]).collect() };
    let tol = 1e-12 * scale_of(dm.positions());
    compare_points(
        &format!("{ctx}: positions, two steps vs direct"),
        &permute(sm.positions()),
        dm.positions(),
        tol,
    )?;
    let mapped_faces: Vec<Vec<u32>> = dm
        .faces()
        .map(|f| f.iter().map(|&v| pi[v as usize]).collect())
        .collect();
    if faces_of(sm) != mapped_faces {
        return Err(format!("{ctx}: the faces differ"));
    }
    let sorted_holes = |m: &PolyMesh| sorted(&m.tags.holes);
    if sorted_holes(sm) != sorted_holes(dm) {
        return Err(format!(
            "{ctx}: hole faces differ: two steps {:?}, direct {:?}",
            sorted_holes(sm),
            sorted_holes(dm)
        ));
    }
    let creases = |m: &PolyMesh, map: &dyn Fn(u32) -> u32| {
        let mut c: Vec<(u32, u32, u32)> = m
            .tags
            .creases
            .iter()
            .map(|c| {
                let (x, y) = (map(c.v0), map(c.v1));
                (x.min(y), x.max(y), c.sharpness.to_bits())
            })
            .collect();
        c.sort_unstable();
        c
    };
    if creases(sm, &|v| v) != creases(dm, &|v| pi[v as usize]) {
        return Err(format!("{ctx}: the sharpness left on creases differs"));
    }
    let corners = |m: &PolyMesh, map: &dyn Fn(u32) -> u32| {
        let mut c: Vec<(u32, u32)> = m
            .tags
            .corners
            .iter()
            .map(|c| (map(c.vertex), c.sharpness.to_bits()))
            .collect();
        c.sort_unstable();
        c
    };
    if corners(sm, &|v| v) != corners(dm, &|v| pi[v as usize]) {
        return Err(format!("{ctx}: the sharpness left on corners differs"));
    }
    if limit {
        let (ns, nd) = match (&staged.normals, &direct.normals) {
            (Some(ns), Some(nd)) => (ns, nd),
            _ => return Err(format!("{ctx}: missing normals")),
        };
        let top = rd.level((a + b) as usize);
        for i in 0..nd.len() {
            let tag = top.vertex_tag(i);
            let got = &ns[pi[i] as usize];
            if normal_is_well_defined(tag) && dist(got, &nd[i]) > 1e-10 {
                return Err(format!(
                    "{ctx}: limit normal of vertex {i} ({:?}, boundary {}) is {got:?} in two steps, {:?} directly",
                    tag.rule, tag.boundary, nd[i]
                ));
            }
        }
    }
    Ok(pi
        .iter()
        .enumerate()
        .filter(|&(i, &j)| i != j as usize)
        .count())
}

/// Whether refinement must keep hole faces for a second run to see the same mesh: with
/// hole tags, or when `BoundaryInterpolation::None` turns boundary faces into holes.
fn needs_holes(mesh: &PolyMesh, options: &Options) -> bool {
    let open = edge_face_counts(mesh).values().any(|&c| c == 1);
    !mesh.tags.holes.is_empty() || (open && options.boundary == BoundaryInterpolation::None)
}

proptest! {
    #![proptest_config(config(64))]

    /// **Refinement composes: `a` levels then `b` levels equals `a + b` levels**, even when
    /// the intermediate mesh goes through an OBJ file. The written level carries
    /// everything the next levels depend on: exact positions, the sharpness still left on
    /// creases and corners (decayed, `f32`), the holes (with `keep_holes`), and the scheme
    /// options as tags; what a run derives by itself (boundary sharpness, sharpened
    /// corners) it derives again. This is what lets a user refine in stages.
    ///
    /// "Equals" means the same surface, faces and tags vertex for vertex, under the
    /// correspondence of [`staged_correspondence`]: the edge-vertices of the later levels
    /// are numbered differently (as OpenSubdiv numbers them when it is given the level-`a`
    /// mesh as a new base), so positions are *not* equal index for index.
    #[test]
    fn refining_in_two_steps_equals_refining_at_once(
        spec in mesh_spec(1),
        a in 0u32..=2,
        b in 1u32..=2,
        keep_holes_anyway in any::<bool>(),
        limit in any::<bool>(),
    ) {
        let mesh = spec.build();
        let keep_holes = keep_holes_anyway || needs_holes(&mesh, &spec.options);
        check_two_step(&mesh, spec.options, a, b, keep_holes, limit).map_err(fail)?;
    }
}

/// A fixed mesh with every feature: a 4 × 3 grid (open) or torus (closed) with a cell
/// split into triangles, a pentagon, semi-sharp creases of sharpness 2.5, 0.7 and 1.3
/// (a chain, so Chaikin averages them), an infinitely sharp crease, corners of
/// sharpness 2.5 and 10, and a hole.
fn feature_mesh(closed: bool) -> PolyMesh {
    let (nx, ny) = (4, 3);
    let v = |i, j| grid_vertex(nx, ny, closed, i, j);
    let mut rng = Rng(7);
    let mut pos = grid_positions(nx, ny, closed);
    for p in &mut pos {
        for c in p.iter_mut() {
            *c += 0.15 * rng.signed();
        }
    }
    let mut faces = Vec::new();
    for j in 0..ny {
        let mut i = 0;
        while i < nx {
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            if (i, j) == (0, 0) {
                faces.push(vec![a, b, c]);
                faces.push(vec![a, c, d]);
                i += 1;
            } else if (i, j) == (2, 2) {
                let (e, g) = (v(i + 2, j), v(i + 2, j + 1));
                faces.push(vec![a, b, g, c, d]);
                faces.push(vec![b, e, g]);
                i += 2;
            } else {
                faces.push(vec![a, b, c, d]);
                i += 1;
            }
        }
    }
    let mut mesh = PolyMesh::from_faces(pos, &faces).expect("feature mesh is valid");
    let crease = |v0, v1, sharpness| Crease { v0, v1, sharpness };
    mesh.tags = Tags {
        creases: vec![
            crease(v(1, 1), v(2, 1), 2.5),
            crease(v(2, 1), v(3, 1), 0.7),
            crease(v(3, 1), v(3, 2), 1.3),
            crease(v(1, 1), v(1, 2), 10.0),
        ],
        corners: vec![
            Corner {
                vertex: v(2, 2),
                sharpness: 2.5,
            },
            Corner {
                vertex: v(1, 0),
                sharpness: 10.0,
            },
        ],
        holes: vec![5],
    };
    mesh.validate().expect("feature tags are valid");
    mesh
}

fn all_options() -> Vec<Options> {
    let mut out = Vec::new();
    for boundary in [
        BoundaryInterpolation::None,
        BoundaryInterpolation::EdgeAndCorner,
        BoundaryInterpolation::EdgeOnly,
    ] {
        for crease_method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            for triangles in [TriangleSubdivision::Catmark, TriangleSubdivision::Smooth] {
                out.push(Options {
                    boundary,
                    crease_method,
                    triangles,
                    ..Options::default()
                });
            }
        }
    }
    out
}

/// **Two-step refinement, exhaustively on a mesh with every feature**: fractional creases
/// (2.5, 0.7, 1.3) decaying across the split point, corners, a hole (`keep_holes`), all
/// three boundary modes, both crease methods, both triangle rules, open and closed, split
/// after 0, 1 or 2 levels, then 1 or 2 more, with and without the limit.
#[test]
fn two_step_refinement_on_every_feature() {
    let mut failures = Vec::new();
    for closed in [false, true] {
        let mesh = feature_mesh(closed);
        for options in all_options() {
            for a in 0..=2 {
                for b in 1..=2 {
                    for limit in [false, true] {
                        if let Err(e) = check_two_step(&mesh, options, a, b, true, limit) {
                            failures.push(format!("closed {closed}: {e}"));
                        }
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// **Two-step refinement when a boundary is creased in `BoundaryInterpolation::None`.**
/// With boundary mode "none", the faces at a boundary vertex become holes unless every
/// boundary edge there is infinitely sharp — so a user can keep a boundary by creasing it
/// at 10. The refined boundary edges stay infinitely sharp, and a second run must keep
/// that boundary too, or refining in two steps would hide faces that refining at once
/// shows.
///
/// The output therefore keeps the sharpness of boundary edges in this mode (the holes
/// themselves are tagged): here a 3 × 2 grid with all 10 boundary edges creased at 10,
/// levels 1 + 1, `keep_holes`, has no hole either way.
#[test]
fn two_step_refinement_keeps_a_creased_boundary_in_boundary_none() {
    let (nx, ny) = (3, 2);
    let v = |i, j| grid_vertex(nx, ny, false, i, j);
    let mut mesh = PolyMesh::from_faces(
        grid_positions(nx, ny, false),
        &grid_faces(nx, ny, false, None),
    )
    .expect("grid is valid");
    // Crease the whole boundary.
    let mut ring = Vec::new();
    ring.extend((0..nx).map(|i| (v(i, 0), v(i + 1, 0))));
    ring.extend((0..ny).map(|j| (v(nx, j), v(nx, j + 1))));
    ring.extend((0..nx).map(|i| (v(i + 1, ny), v(i, ny))));
    ring.extend((0..ny).map(|j| (v(0, j + 1), v(0, j))));
    mesh.tags.creases = ring
        .into_iter()
        .map(|(v0, v1)| Crease {
            v0,
            v1,
            sharpness: 10.0,
        })
        .collect();
    let options = Options {
        boundary: BoundaryInterpolation::None,
        ..Options::default()
    };
    let direct = run(
        &mesh,
        &SubdivideOptions {
            levels: 2,
            scheme: subsurf::Scheme::CatmullClark,
            options,
            ..Default::default()
        },
    );
    assert_eq!(
        direct.mesh.num_faces(),
        nx * ny * 16,
        "a boundary creased at 10 keeps its faces in boundary mode none"
    );
    check_two_step(&mesh, options, 1, 1, true, false).expect("two steps equal one");
}

// =======================================================================================
// 5. Symmetry
// =======================================================================================

/// A mirror-symmetric mesh (under x ↦ −x): a cube or an open grid, with symmetric jitter,
/// symmetric triangle splits, creases, corners and holes.
#[derive(Clone, Debug)]
struct SymmetricSpec {
    /// `None`: a cube [-1, 1]³; `Some((nx, ny))`: an open grid of `nx × ny` cells centred on
    /// x = 0.
    grid: Option<(usize, usize)>,
    jitter: f64,
    splits: usize,
    creases: usize,
    corners: usize,
    holes: usize,
    /// Sharpness values whose `f32` sums are exact (multiples of 1/4), so that the
    /// order-dependent `f32` sharpness arithmetic (see the property) is exact.
    dyadic: bool,
    options: Options,
    seed: u64,
}

fn symmetric_spec() -> impl Strategy<Value = SymmetricSpec> {
    (
        prop_oneof![Just(None), (1usize..=5, 1usize..=4).prop_map(Some)],
        0.0..0.3f64,
        (0usize..=2, 0usize..=4, 0usize..=2, 0usize..=1),
        any::<bool>(),
        options_strategy(),
        any::<u64>(),
    )
        .prop_map(
            |(grid, jitter, (splits, creases, corners, holes), dyadic, options, seed)| {
                SymmetricSpec {
                    grid,
                    jitter,
                    splits,
                    creases,
                    corners,
                    holes,
                    dyadic,
                    options,
                    seed,
                }
            },
        )
}

const MIRROR: Mat3 = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn sorted(f: &[u32]) -> Vec<u32> {
    let mut s = f.to_vec();
    s.sort_unstable();
    s
}

impl SymmetricSpec {
    fn sharpness(&self, rng: &mut Rng) -> f32 {
        const DYADIC: [f32; 8] = [0.25, 0.5, 1.0, 1.5, 2.25, 2.5, 3.75, 10.0];
        if self.dyadic {
            DYADIC[rng.below(DYADIC.len())]
        } else {
            rng.sharpness()
        }
    }

    /// The mesh and the mirror permutation of its vertices.
    fn build(&self) -> (PolyMesh, Vec<u32>) {
        let mut rng = Rng(self.seed);
        let (mut pos, mut faces): (Vec<P3>, Vec<Vec<u32>>) = match self.grid {
            None => (
                [
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [0.0, 0.0, 1.0],
                    [1.0, 0.0, 1.0],
                    [1.0, 1.0, 1.0],
                    [0.0, 1.0, 1.0],
                ]
                .iter()
                .map(|p| [2.0 * p[0] - 1.0, 2.0 * p[1] - 1.0, 2.0 * p[2] - 1.0])
                .collect(),
                [
                    [0, 3, 2, 1],
                    [4, 5, 6, 7],
                    [0, 1, 5, 4],
                    [1, 2, 6, 5],
                    [2, 3, 7, 6],
                    [3, 0, 4, 7],
                ]
                .iter()
                .map(|f| f.to_vec())
                .collect(),
            ),
            Some((nx, ny)) => {
                let mut p = grid_positions(nx, ny, false);
                for q in &mut p {
                    q[0] -= nx as f64 / 2.0;
                }
                (p, grid_faces(nx, ny, false, None))
            }
        };
        // The mirror permutation, from the exact (unjittered) positions.
        let sigma: Vec<u32> = pos
            .iter()
            .map(|p| {
                let q = mat_vec(&MIRROR, p);
                pos.iter()
                    .position(|x| x == &q)
                    .expect("the base mesh is mirror-symmetric") as u32
            })
            .collect();
        // Symmetric jitter.
        for v in 0..pos.len() {
            let w = sigma[v] as usize;
            if w < v {
                continue;
            }
            let mut d = [0.0; 3];
            for c in d.iter_mut() {
                *c = self.jitter * rng.signed();
            }
            if w == v {
                d[0] = 0.0;
            }
            pos[v] = [pos[v][0] + d[0], pos[v][1] + d[1], pos[v][2] + d[2]];
            pos[w] = mat_vec(&MIRROR, &pos[v]);
        }
        let mirror_face = |faces: &[Vec<u32>], f: usize| -> usize {
            let want = sorted(
                &faces[f]
                    .iter()
                    .map(|&v| sigma[v as usize])
                    .collect::<Vec<_>>(),
            );
            faces
                .iter()
                .position(|g| sorted(g) == want)
                .expect("faces are mirror-symmetric")
        };
        // Symmetric splits of quads not fixed by the mirror.
        for _ in 0..self.splits {
            let f = rng.below(faces.len());
            let g = mirror_face(&faces, f);
            if g == f || faces[f].len() != 4 {
                continue;
            }
            let k = rng.below(2);
            let split = |face: &[u32], a: u32, c: u32| -> [Vec<u32>; 2] {
                let i = face.iter().position(|&x| x == a).expect("corner in face");
                debug_assert_eq!(face[(i + 2) % 4], c);
                let r = |o: usize| face[(i + o) % 4];
                [vec![r(0), r(1), r(2)], vec![r(0), r(2), r(3)]]
            };
            let (fa, fc) = (faces[f][k], faces[f][k + 2]);
            let [f0, f1] = split(&faces[f], fa, fc);
            let [g0, g1] = split(&faces[g], sigma[fa as usize], sigma[fc as usize]);
            let (hi, lo) = (f.max(g), f.min(g));
            faces.remove(hi);
            faces.remove(lo);
            faces.extend([f0, f1, g0, g1]);
        }
        let nv = pos.len();
        let mut tags = Tags::default();
        for _ in 0..self.creases {
            let f = &faces[rng.below(faces.len())];
            let k = rng.below(f.len());
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            let sharpness = self.sharpness(&mut rng);
            for (v0, v1) in [(a, b), (sigma[a as usize], sigma[b as usize])] {
                tags.creases.push(Crease { v0, v1, sharpness });
            }
        }
        for _ in 0..self.corners {
            let v = rng.below(nv);
            let sharpness = self.sharpness(&mut rng);
            for vertex in [v as u32, sigma[v]] {
                tags.corners.push(Corner { vertex, sharpness });
            }
        }
        for _ in 0..self.holes {
            let f = rng.below(faces.len());
            tags.holes.push(f as u32);
            tags.holes.push(mirror_face(&faces, f) as u32);
        }
        let mut mesh = PolyMesh::from_faces(pos, &faces).expect("symmetric mesh is valid");
        mesh.tags = tags;
        (mesh, sigma)
    }
}

/// The mirror permutation of the vertices of the deepest level of `r`, from that of the
/// base: the child of vertex `v` mirrors to the child of `σ(v)`, the child of face `f` to
/// that of the face with the mirrored vertex set, the child of edge `(a, b)` to that of
/// edge `(σa, σb)`.
fn refined_permutation(r: &TopologyRefiner, base: &[u32]) -> Result<Vec<u32>, String> {
    let mut sigma = base.to_vec();
    for l in 0..r.max_level() {
        let p = r.level(l);
        let (nv, nf) = (p.num_vertices(), p.num_faces());
        let by_verts: HashMap<Vec<u32>, usize> =
            (0..nf).map(|f| (sorted(p.face_vertices(f)), f)).collect();
        let mut next: Vec<u32> = sigma.clone();
        for f in 0..nf {
            let m: Vec<u32> = p
                .face_vertices(f)
                .iter()
                .map(|&v| sigma[v as usize])
                .collect();
            let g = by_verts
                .get(&sorted(&m))
                .ok_or_else(|| format!("level {l}: face {f} has no mirror image"))?;
            next.push((nv + g) as u32);
        }
        for e in 0..p.num_edges() {
            let [a, b] = p.edge_vertices(e);
            let g = p
                .find_edge(sigma[a as usize], sigma[b as usize])
                .ok_or_else(|| format!("level {l}: edge {e} has no mirror image"))?;
            next.push((nv + nf) as u32 + g);
        }
        sigma = next;
    }
    let distinct: HashSet<u32> = sigma.iter().copied().collect();
    if distinct.len() != sigma.len() {
        return Err("the mirror map of refined vertices is not a permutation".into());
    }
    Ok(sigma)
}

proptest! {
    #![proptest_config(config(48))]

    /// **Symmetry in, symmetry out.** The masks depend on topology and sharpness only, not
    /// on the orientation of faces or the numbering of vertices, so a mesh that a mirror
    /// maps onto itself (positions, faces, tags) refines to a point set that the mirror
    /// maps onto itself: `refined[σ(i)] = M · refined[i]`, with the permutation σ of the
    /// refined vertices induced from that of the base (a bijection, hence the two point
    /// sets are equal as sets). The oriented surface is symmetric too, so limit normals
    /// satisfy `n[σ(i)] = M · n[i]` wherever the normal is a property of the surface.
    ///
    /// To 1e-12 when the sharpness values are dyadic. With arbitrary fractional sharpness
    /// the symmetry holds only to `f32` precision: like OpenSubdiv, the weight of a
    /// decaying corner or crease sums the sharpness of its edges in `f32`, in the vertex's
    /// rotational order, which the mirror reverses (e.g. a cube corner with vertex
    /// sharpness 0.3 and edges 1.0 and 0.3: `0.3 + 1.0 + 0.3 ≠ 0.3 + 0.3 + 1.0` in `f32`,
    /// and the mirrored corners end up 2.6e-8 apart).
    #[test]
    fn mirror_symmetric_meshes_refine_symmetrically(
        spec in symmetric_spec(),
        levels in 1u32..=3,
        limit in any::<bool>(),
        keep_holes in any::<bool>(),
    ) {
        let (mesh, base_sigma) = spec.build();
        let out = run(&mesh, &SubdivideOptions {
            levels,
            scheme: subsurf::Scheme::CatmullClark,
            options: spec.options,
            limit,
            keep_holes,
            max_memory: None,
        });
        let mut r = TopologyRefiner::new(&mesh, subsurf::Scheme::CatmullClark, spec.options).expect("valid mesh");
        r.refine_uniform(levels);
        let sigma = refined_permutation(&r, &base_sigma).map_err(fail)?;
        let pos = out.mesh.positions();
        prop_assert_eq!(sigma.len(), pos.len());
        let mirrored: Vec<P3> = (0..pos.len())
            .map(|i| {
                // The point that lands on vertex i is the mirror of σ⁻¹(i); σ is an involution.
                mat_vec(&MIRROR, &pos[sigma[i] as usize])
            })
            .collect();
        let (tol, normal_tol) = if spec.dyadic { (1e-12, 1e-9) } else { (1e-6, 1e-5) };
        let tol = tol * scale_of(pos);
        compare_points("refined[σ(i)] vs M refined[i]", pos, &mirrored, tol).map_err(fail)?;
        if let Some(n) = &out.normals {
            // Only where the limit normal is a property of the surface (see
            // `normal_is_well_defined`): a mirror reverses rotational order.
            let top = r.level(levels as usize);
            for i in 0..n.len() {
                let tag = top.vertex_tag(i);
                if !normal_is_well_defined(tag) {
                    continue;
                }
                let want = mat_vec(&MIRROR, &n[sigma[i] as usize]);
                prop_assert!(
                    dist(&n[i], &want) <= normal_tol,
                    "normal {} ({:?}) is {:?}, the mirror of normal {} is {:?}",
                    i, tag.rule, n[i], sigma[i], want
                );
            }
        }
    }
}

// =======================================================================================
// 6. Partition of unity
// =======================================================================================

proptest! {
    #![proptest_config(config(48))]

    /// **Partition of unity.** The weights of every refinement mask (smooth, crease,
    /// corner, and the fractional blends of decaying creases) sum to one, so a constant
    /// field is reproduced exactly at every level; the limit position masks sum to one too,
    /// and the limit tangent masks to zero, so the limit of a constant is that constant with
    /// zero tangents. (Linear fields are *not* reproduced in general — Catmull-Clark only
    /// has affine invariance, which property 1 checks.)
    #[test]
    fn constants_stay_constant(spec in mesh_spec(1), levels in 1u32..=3, c in -100.0..100.0f64) {
        let mesh = spec.build();
        let mut r = TopologyRefiner::new(&mesh, subsurf::Scheme::CatmullClark, spec.options).expect("valid mesh");
        r.refine_uniform(levels);
        let field = vec![[c]; mesh.num_vertices()];
        let refined = r.interpolate_all(&field);
        let tol = 1e-12 * c.abs().max(1.0);
        prop_assert_eq!(refined.len(), r.level(levels as usize).num_vertices());
        for (i, x) in refined.iter().enumerate() {
            prop_assert!((x[0] - c).abs() <= tol, "vertex {}: {} instead of {}", i, x[0], c);
        }
        let top = r.level(levels as usize);
        let n = top.num_vertices();
        let (mut lim, mut t1, mut t2) = (vec![[0.0]; n], vec![[0.0]; n], vec![[0.0]; n]);
        subsurf::limit::limit_points(top, &refined, &mut lim, Some((&mut t1, &mut t2)));
        for i in 0..n {
            prop_assert!((lim[i][0] - c).abs() <= tol, "limit at {}: {} instead of {}", i, lim[i][0], c);
            prop_assert!(t1[i][0].abs() <= 10.0 * tol && t2[i][0].abs() <= 10.0 * tol,
                "tangents at {}: {}, {} instead of 0", i, t1[i][0], t2[i][0]);
        }
    }
}

// =======================================================================================
// 8. Listing faces from other corners
// =======================================================================================

/// Point `(u, v)` of a quad listed from its corner `r` (corner `k` at `(0,0), (1,0),
/// (1,1), (0,1)` for `k = 0..4`), in the domain of the quad listed from corner 0: each
/// step from corner `k + 1` back to corner `k` maps `(u, v)` to `(1 − v, u)`.
fn unrotate(r: usize, (mut u, mut v): (f64, f64)) -> (f64, f64) {
    for _ in 0..r % 4 {
        (u, v) = (1.0 - v, u);
    }
    (u, v)
}

/// `mesh` with face `f` listed from its corner `rotations[f]`.
fn rotated(mesh: &PolyMesh, rotations: &[usize]) -> PolyMesh {
    let faces: Vec<Vec<u32>> = (faces_of(mesh).into_iter().zip(rotations))
        .map(|(mut f, &r)| {
            let k = r % f.len();
            f.rotate_left(k);
            f
        })
        .collect();
    let mut out = PolyMesh::from_faces(mesh.positions().to_vec(), &faces).expect("same mesh");
    out.tags = mesh.tags.clone();
    out
}

proptest! {
    #![proptest_config(config(48))]

    /// **Listing faces from other corners.** The Catmull-Clark rules do not depend on
    /// which corner a face is listed from; only the face's own parameter domain turns
    /// with it (a quad's by a quarter per corner, an `n`-gon's sub-faces by one each). So
    /// the limit surface of a mesh whose every face is listed from a random corner is the
    /// same, point for point, as that of the mesh as given. (The limit surface shares the
    /// local refinement of faces whose 1-rings are alike, listed canonically whatever the
    /// corners their neighbours start from: this checks that the canonical listing keeps
    /// the surface.)
    #[test]
    fn limit_surface_does_not_depend_on_face_listing(spec in mesh_spec(1), seed in any::<u64>()) {
        let mesh = spec.build();
        let mut rng = Rng(seed);
        let rotations: Vec<usize> = (0..mesh.num_faces()).map(|_| rng.below(12)).collect();
        let turned = rotated(&mesh, &rotations);
        let a = LimitSurface::new(&mesh, spec.options).expect("valid mesh");
        let b = LimitSurface::new(&turned, spec.options).expect("valid mesh");
        let tol = 1e-12 * scale_of(mesh.positions());
        let params = [0.0, 0.3, 0.5, 0.75, 1.0];
        for f in 0..mesh.num_faces() {
            let n = a.num_subfaces(f);
            let r = rotations[f] % mesh.face(f).len();
            for j in 0..n {
                for (&u, &v) in params.iter().flat_map(|u| params.iter().map(move |v| (u, v))) {
                    let at = |face_sub: u32, (u, v): (f64, f64)| SurfacePoint { face: f as u32, subface: face_sub, u, v };
                    let (want, got) = if n == 1 {
                        (a.eval_point(at(0, unrotate(r, (u, v)))), b.eval_point(at(0, (u, v))))
                    } else {
                        (a.eval_point(at(((j + r) % n) as u32, (u, v))), b.eval_point(at(j as u32, (u, v))))
                    };
                    match (want, got) {
                        (Ok(w), Ok(g)) => prop_assert!(
                            dist(&w.p, &g.p) <= tol,
                            "face {} (from corner {}), sub-face {}, ({}, {}): {:?} instead of {:?}", f, r, j, u, v, g.p, w.p
                        ),
                        (w, g) => prop_assert_eq!(w.is_ok(), g.is_ok(), "face {} sub-face {}", f, j),
                    }
                }
            }
        }
    }
}

/// A triangulated torus (every vertex of valence 6) whose triangles are listed from
/// random corners, as in scanned meshes: every triangle's 1-ring has the same shape, and
/// the surface has one configuration (one per face when the listing was not made
/// canonical: 1,151 of 1,152).
#[test]
fn a_regular_triangulation_listed_anyhow_has_one_configuration() {
    let n = 24;
    let positions = grid_positions(n, n, true);
    let mut rng = Rng(7);
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let at = |di, dj| grid_vertex(n, n, true, i + di, j + dj);
            for mut t in [
                [at(0, 0), at(1, 0), at(1, 1)],
                [at(0, 0), at(1, 1), at(0, 1)],
            ] {
                t.rotate_left(rng.below(3));
                faces.push(t);
            }
        }
    }
    let mesh = PolyMesh::from_faces(positions, &faces).expect("torus");
    let surface = LimitSurface::new(&mesh, Options::default()).expect("valid mesh");
    assert_eq!(surface.num_configurations(), 1);
}

// =======================================================================================
// 7. Bad input
// =======================================================================================

fn square() -> Vec<P3> {
    vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]
}

/// `err`'s message contains every one of `phrases`.
#[track_caller]
fn assert_names(err: &dyn std::fmt::Display, phrases: &[&str]) {
    let shown = err.to_string();
    for p in phrases {
        assert!(shown.contains(p), "{shown:?} does not name {p:?}");
    }
}

/// A face needs three vertices; the error names the face and its count.
#[test]
fn face_with_fewer_than_three_vertices_is_rejected() {
    let faces: [&[u32]; 2] = [&[0, 1, 2], &[2, 3]];
    let e = PolyMesh::from_faces(square(), &faces).expect_err("a 2-gon is invalid");
    assert_eq!(e, MeshError::FaceTooSmall { face: 1, count: 2 });
    assert_names(&e, &["face 1", "2 vertices"]);
}

/// A face may only use existing vertices; the error names the face, the index and the count.
#[test]
fn out_of_range_vertex_is_rejected() {
    let e = PolyMesh::from_faces(square(), &[[0u32, 1, 2, 3], [0, 2, 9, 1]])
        .expect_err("vertex 9 does not exist");
    assert_eq!(
        e,
        MeshError::VertexOutOfRange {
            face: 1,
            index: 9,
            count: 4
        }
    );
    assert_names(&e, &["face 1", "vertex 9", "4 vertices"]);
}

/// Coordinates must be finite; the error names the vertex.
#[test]
fn non_finite_coordinate_is_rejected() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let mut p = square();
        p[2][1] = bad;
        let e = PolyMesh::from_faces(p, &[[0u32, 1, 2, 3]]).expect_err("non-finite coordinate");
        assert!(
            matches!(e, MeshError::NonFiniteCoordinate { vertex: 2, .. }),
            "{e:?}"
        );
        assert_names(&e, &["vertex 2"]);
    }
}

/// CSR offsets must never decrease and must end at the number of face-vertices; a
/// decreasing offset is reported with its face.
#[test]
fn malformed_csr_offsets_are_rejected() {
    let verts = vec![0u32, 1, 2, 3];
    let cases: [(Vec<u32>, &str); 3] = [
        (vec![0, 3], "last offset"),
        (vec![0, 4, 5], "last offset"),
        (vec![0, 4, 3, 4], "face 1"),
    ];
    for (offsets, phrase) in cases {
        let e =
            PolyMesh::new(square(), offsets.clone(), verts.clone()).expect_err("malformed offsets");
        assert!(
            matches!(e, MeshError::BadFaceOffsets(_)),
            "{offsets:?}: {e:?}"
        );
        assert_names(&e, &[phrase]);
    }
}

/// CSR offsets must start at 0 (and so cannot be empty): `PolyMesh::new` returns
/// `BadFaceOffsets` — documented under "# Errors".
///
#[test]
fn csr_offsets_not_starting_at_zero_are_rejected() {
    for offsets in [vec![], vec![1, 4]] {
        let e = PolyMesh::new(square(), offsets.clone(), vec![0, 1, 2, 3])
            .expect_err("offsets must start at 0");
        assert!(
            matches!(e, MeshError::BadFaceOffsets(_)),
            "{offsets:?}: {e:?}"
        );
        assert_names(&e, &["first offset"]);
    }
}

fn quad_with_tags(tags: Tags) -> PolyMesh {
    let mut m = PolyMesh::from_faces(square(), &[[0u32, 1, 2, 3]]).expect("a quad is valid");
    m.tags = tags;
    m
}

/// Tags are validated like the rest of the mesh, by [`PolyMesh::validate`] and by
/// [`subdivide`]: negative or NaN sharpness, a corner on a vertex that does not exist,
/// a hole on a face that does not exist. Each error names the tagged element.
#[test]
fn bad_tags_are_rejected() {
    let crease = |sharpness| Crease {
        v0: 0,
        v1: 1,
        sharpness,
    };
    let cases: Vec<(Tags, Vec<&str>)> = vec![
        (
            Tags {
                creases: vec![crease(-1.0)],
                ..Tags::default()
            },
            vec!["crease on edge (0, 1)", "-1"],
        ),
        (
            Tags {
                creases: vec![crease(f32::NAN)],
                ..Tags::default()
            },
            vec!["crease on edge (0, 1)", "NaN"],
        ),
        (
            Tags {
                corners: vec![Corner {
                    vertex: 2,
                    sharpness: f32::NAN,
                }],
                ..Tags::default()
            },
            vec!["corner at vertex 2", "NaN"],
        ),
        (
            Tags {
                corners: vec![Corner {
                    vertex: 3,
                    sharpness: -0.5,
                }],
                ..Tags::default()
            },
            vec!["corner at vertex 3", "-0.5"],
        ),
        (
            Tags {
                corners: vec![Corner {
                    vertex: 9,
                    sharpness: 1.0,
                }],
                ..Tags::default()
            },
            vec!["corner", "vertex 9", "4"],
        ),
        (
            Tags {
                creases: vec![Crease {
                    v0: 0,
                    v1: 7,
                    sharpness: 1.0,
                }],
                ..Tags::default()
            },
            vec!["crease", "vertex 7"],
        ),
        (
            Tags {
                holes: vec![3],
                ..Tags::default()
            },
            vec!["hole", "face 3", "1"],
        ),
    ];
    for (tags, phrases) in cases {
        let m = quad_with_tags(tags.clone());
        let e = m.validate().expect_err("bad tags");
        assert!(
            matches!(
                e,
                MeshError::BadSharpness { .. } | MeshError::TagOutOfRange { .. }
            ),
            "{tags:?}: {e:?}"
        );
        assert_names(&e, &phrases);
        let s = subdivide(
            &m,
            &SubdivideOptions {
                levels: 1,
                scheme: subsurf::Scheme::CatmullClark,
                ..Default::default()
            },
        )
        .expect_err("subdivide validates tags");
        assert!(
            matches!(&s, Error::Mesh(inner) if inner.to_string() == e.to_string()),
            "{s:?}"
        );
        assert_names(&s, &phrases);
    }
}

/// `check_strict` rejects an edge shared by three faces, naming the edge and two faces.
#[test]
fn strict_check_rejects_non_manifold_edge() {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [0.5, -1.0, 0.0],
        [0.5, 0.0, 1.0],
    ];
    let m = PolyMesh::from_faces(p, &[[0u32, 1, 2], [1, 0, 3], [0, 1, 4]])
        .expect("non-manifold meshes are accepted by from_faces");
    let e = m.check_strict().expect_err("edge (0, 1) has three faces");
    assert!(
        matches!(
            e,
            MeshError::NonManifoldEdge {
                v0: 0,
                v1: 1,
                faces: 3,
                ..
            }
        ),
        "{e:?}"
    );
    assert_names(&e, &["edge (0, 1)", "3 faces"]);
}

/// `check_strict` rejects two faces that run their common edge the same way, naming both.
#[test]
fn strict_check_rejects_inconsistent_orientation() {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, 1.0, 0.0],
        [0.5, -1.0, 0.0],
    ];
    let m = PolyMesh::from_faces(p, &[[0u32, 1, 2], [0, 1, 3]]).expect("accepted");
    let e = m.check_strict().expect_err("both faces run 0 → 1");
    assert_eq!(
        e,
        MeshError::InconsistentOrientation {
            f0: 0,
            f1: 1,
            v0: 0,
            v1: 1
        }
    );
    assert_names(&e, &["faces 0 and 1", "(0, 1)"]);
}

/// `check_strict` rejects a bowtie: a vertex whose faces form two fans.
#[test]
fn strict_check_rejects_bowtie_vertex() {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0],
        [-1.0, -1.0, 0.0],
    ];
    let m = PolyMesh::from_faces(p, &[[0u32, 1, 2], [0, 3, 4]]).expect("accepted");
    let e = m.check_strict().expect_err("vertex 0 has two fans");
    assert_eq!(
        e,
        MeshError::NonManifoldVertex {
            vertex: 0,
            faces: 2
        }
    );
    assert_names(&e, &["vertex 0", "2 faces"]);
}

/// A face that lists a vertex twice is accepted (as OpenSubdiv does) but rejected by
/// `check_strict`, which names the face and the vertex.
#[test]
fn strict_check_rejects_repeated_vertex() {
    let mut p = square();
    p.push([2.0, 0.5, 0.0]);
    let m = PolyMesh::from_faces(p, &[[0u32, 1, 2, 3], [1, 4, 2, 4]])
        .expect("degenerate faces are accepted");
    let e = m.check_strict().expect_err("face 1 repeats vertex 4");
    assert_eq!(e, MeshError::RepeatedVertex { face: 1, vertex: 4 });
    assert_names(&e, &["face 1", "vertex 4"]);
}

/// A memory limit refuses a refinement that would exceed it, before doing any work, and
/// says which level was asked for.
#[test]
fn memory_limit_refuses_deep_refinement() {
    let (mesh, _) = SymmetricSpec {
        grid: None,
        jitter: 0.0,
        splits: 0,
        creases: 0,
        corners: 0,
        holes: 0,
        dyadic: true,
        options: Options::default(),
        seed: 0,
    }
    .build();
    let e = subdivide(
        &mesh,
        &SubdivideOptions {
            levels: 6,
            scheme: subsurf::Scheme::CatmullClark,
            max_memory: Some(1000),
            ..Default::default()
        },
    )
    .expect_err("level 6 needs far more than 1000 bytes");
    assert!(
        matches!(
            e,
            Error::TooLarge {
                levels: 6,
                limit: 1000,
                ..
            }
        ),
        "{e:?}"
    );
    assert_names(&e, &["level 6"]);
}

/// Every relation of a topology is consistent both ways: each edge is among its faces'
/// edges and its ends' edges, each face among its vertices' faces. Also for faces that
/// repeat a vertex (the `topology` fuzz target's finding: `f 1 2 3 4`, `f 1 4 5 1 6 2`).
fn assert_adjacency_consistent(mesh: &PolyMesh, options: &Options) {
    let (t, _) = Topology::from_mesh(mesh, options).expect("topology");
    for e in 0..t.num_edges() {
        for &f in t.edge_face_list(e) {
            assert!(
                t.face_edge_list(f as usize).contains(&(e as u32)),
                "edge {e} face {f}"
            );
        }
        let [a, b] = t.edge_vertices(e);
        assert!(
            t.vertex_edges(a as usize).contains(&(e as u32)),
            "edge {e} at {a}"
        );
        assert!(
            t.vertex_edges(b as usize).contains(&(e as u32)),
            "edge {e} at {b}"
        );
    }
    for v in 0..t.num_vertices() {
        for &f in t.vertex_faces(v) {
            assert!(
                t.face_vertices(f as usize).contains(&(v as u32)),
                "vertex {v} face {f}"
            );
        }
    }
}

#[test]
fn adjacency_of_faces_that_repeat_a_vertex() {
    let p: Vec<[f64; 3]> = (0..6).map(|i| [i as f64, (i * i) as f64, 0.0]).collect();
    for faces in [
        vec![vec![0u32, 1, 2, 3], vec![0, 3, 4, 0, 5, 1]],
        vec![vec![0u32, 1, 2, 3], vec![3, 4, 0, 5, 1, 0]],
    ] {
        let mesh = PolyMesh::from_faces(p.clone(), &faces).expect("mesh");
        for boundary in [
            BoundaryInterpolation::EdgeOnly,
            BoundaryInterpolation::EdgeAndCorner,
            BoundaryInterpolation::None,
        ] {
            let options = Options {
                boundary,
                ..Options::default()
            };
            assert_adjacency_consistent(&mesh, &options);
        }
    }
}

/// A face that holds a vertex twice (`f 1 4 5 1 6 2`) makes that vertex non-manifold, so
/// the surface does not depend on the corner the face is listed from (OpenSubdiv's walk
/// around the vertex listed an edge twice and missed another, and the two listings refined
/// 8 % of the diagonal apart; it aborts on the second).
#[test]
fn faces_that_repeat_a_vertex_refine_alike_from_any_corner() {
    let p: Vec<[f64; 3]> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
    ];
    let refined = |second: Vec<u32>| {
        let mesh = PolyMesh::from_faces(p.clone(), &[vec![0, 1, 2, 3], second]).expect("mesh");
        let opts = SubdivideOptions {
            levels: 2,
            scheme: subsurf::Scheme::CatmullClark,
            ..SubdivideOptions::default()
        };
        let mut points: Vec<[u64; 3]> = subdivide(&mesh, &opts)
            .expect("refinement")
            .mesh
            .positions()
            .iter()
            .map(|q| q.map(|x| (x * 1e9).round() as i64 as u64))
            .collect();
        points.sort_unstable();
        points
    };
    let first = vec![0, 3, 4, 0, 5, 1];
    for k in 1..first.len() {
        let mut turned = first.clone();
        turned.rotate_left(k);
        assert_eq!(
            refined(first.clone()),
            refined(turned),
            "started at corner {k}"
        );
    }
}
