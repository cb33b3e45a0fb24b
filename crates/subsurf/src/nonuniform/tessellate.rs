//! Tessellation of the NURSS limit surface through refinement.

use super::{Nurss, NurssError};
use crate::geom;
use crate::limit::Tessellation;
use crate::mesh::{FaceVarying, Options, PolyMesh};

/// Samples the NURSS limit surface of `mesh` (with its [`PolyMesh::knots`]) at `rate`
/// segments per input edge, rounded up to a power of two `2^L` (the rate used is in
/// [`Tessellation::rate`]); with `triangles` each quad is split along its shorter diagonal.
///
/// Non-uniform Catmull-Clark has no closed-form patches away from regular grids, so the
/// surface is sampled the way [JOS 2003] and [Jiang et al.] show it: refine `L` levels, then move every
/// vertex of the last level to its exact limit point ([`Nurss::limit_points`]). A quad of
/// the input becomes `2^L × 2^L` quads whose corners lie on the limit surface (an `n`-gon
/// becomes `n` quad sub-faces of `2^(L−1) × 2^(L−1)`, as in
/// [`limit::tessellate`](crate::limit::tessellate)); samples shared by neighbouring faces
/// are one vertex, so the result is watertight.
///
/// **Face-varying channels** (texture coordinates) of `mesh` are refined with it and moved
/// to their limit the same way ([`Nurss::new`] says how NURSS refines them), and written as
/// the tessellation's [`Tessellation::face_varying`] at the corners of its faces: a sample
/// on a seam has one value per side, as the input has.
///
/// **Normals** are those of the sampled mesh: at each vertex the normalised sum of the
/// Newell normals (area-weighted) of its faces. They converge to the surface normal as the
/// rate grows, but are not exact (unlike [`limit::tessellate`](crate::limit::tessellate)'s
/// for Catmull-Clark); they are meant for display. At an infinitely sharp crease or a
/// boundary the two sides' normals are averaged.
///
/// # Errors
/// The errors of [`Nurss::new`]; [`NurssError::TooLarge`] when the refinement would
/// overflow 32-bit indices.
///
/// ```
/// use subsurf::mesh::{EdgeInterval, Options, PolyMesh};
/// use subsurf::nonuniform::tessellate;
/// let mut cube = PolyMesh::from_faces(
///     vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.],
///          [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]],
///     &[[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]],
/// )?;
/// cube.knots.intervals.push(EdgeInterval { v0: 0, v1: 1, interval: 3.0 });
/// let t = tessellate(&cube, &Options::default(), 4, false)?;
/// assert_eq!((t.rate, t.num_faces()), (4, 6 * 16));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn tessellate(
    mesh: &PolyMesh,
    options: &Options,
    rate: u32,
    triangles: bool,
) -> Result<Tessellation, NurssError> {
    let rate = rate.max(1).next_power_of_two();
    let levels = rate.trailing_zeros();
    let quads = mesh.face_verts().len() as u64 * 4u64.saturating_pow(levels.saturating_sub(1));
    if levels > 15 || quads.saturating_mul(4) >= u32::MAX as u64 {
        return Err(NurssError::TooLarge {
            level: levels,
            faces: quads,
        });
    }
    let mut s = Nurss::new(mesh, options)?;
    let source = refine_with_sources(&mut s, levels);
    let positions = s.limit_points();
    let level = s.topology();
    let mut face_offsets = vec![0u32];
    let mut face_verts = Vec::with_capacity(level.face_verts().len());
    // Per output corner, the level's face-vertex slot it is (for the channels).
    let mut slots = Vec::with_capacity(level.face_verts().len());
    let mut out_source = Vec::with_capacity(level.num_faces());
    for (f, &src) in source.iter().enumerate().take(level.num_faces()) {
        if level.is_hole(f) {
            continue;
        }
        let fv = level.face_vertices(f);
        let o = level.face_offsets[f];
        let mut corners = |c: &[u32]| {
            face_verts.extend(c.iter().map(|&i| fv[i as usize]));
            slots.extend(c.iter().map(|&i| o + i));
            face_offsets.push(face_verts.len() as u32);
            out_source.push(src);
        };
        if triangles && fv.len() == 4 {
            let dist2 = |a: u32, b: u32| {
                let d = geom::sub(&positions[a as usize], &positions[b as usize]);
                geom::dot(&d, &d)
            };
            let (d02, d13) = (dist2(fv[0], fv[2]), dist2(fv[1], fv[3]));
            let tris = if d02 <= d13 {
                [[0, 1, 2], [0, 2, 3]]
            } else {
                [[0, 1, 3], [1, 2, 3]]
            };
            tris.iter().for_each(|t| corners(t));
        } else {
            corners(&(0..fv.len() as u32).collect::<Vec<_>>());
        }
    }
    let face_varying = (s.face_varying_limit(true).iter())
        .map(|ch| corner_channel(ch, &slots))
        .collect();
    // Keep only the vertices of written faces, in order of first use.
    let mut remap = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    for v in &mut face_verts {
        let r = &mut remap[*v as usize];
        if *r == u32::MAX {
            *r = kept.len() as u32;
            kept.push(positions[*v as usize]);
        }
        *v = *r;
    }
    let mut normals = vec![[0.0; 3]; kept.len()];
    for w in face_offsets.windows(2) {
        let face = &face_verts[w[0] as usize..w[1] as usize];
        let n = geom::newell_normal(&kept, face);
        for &v in face {
            for (a, b) in normals[v as usize].iter_mut().zip(n) {
                *a += b;
            }
        }
    }
    for n in &mut normals {
        *n = geom::normalize_or_zero(*n);
    }
    Ok(Tessellation {
        rate,
        positions: kept,
        normals,
        face_offsets,
        face_verts,
        source: out_source,
        points: Vec::new(),
        face_varying,
    })
}

/// Refines `s` by `levels` steps and returns, for each face of the last level, the base
/// face and sub-face (for a non-quad base face, its quad sub-face of the first level) that
/// it samples.
fn refine_with_sources(s: &mut Nurss, levels: u32) -> Vec<(u32, u32)> {
    let t0 = s.topology();
    let mut source: Vec<(u32, u32)> = (0..t0.num_faces() as u32).map(|f| (f, 0)).collect();
    for level in 0..levels {
        let parent = s.topology();
        let mut child = vec![(0u32, 0u32); parent.face_verts().len()];
        for (f, &(base, sub)) in source.iter().enumerate() {
            let o = parent.face_offsets[f] as usize;
            let n = parent.face_vertices(f).len();
            for j in 0..n {
                // A non-quad base face's first-level children are its quad sub-faces.
                let sub = if level == 0 && n != 4 { j as u32 } else { sub };
                child[o + j] = (base, sub);
            }
        }
        source = child;
        s.step();
    }
    source
}

/// The channel `ch` (of a level) at the output corners, corner `k` being the level's
/// face-vertex slot `slots[k]`: the values used, in order of first use.
fn corner_channel(ch: &FaceVarying, slots: &[u32]) -> FaceVarying {
    let dim = ch.dim();
    let mut remap = vec![u32::MAX; ch.num_values()];
    let mut values = Vec::new();
    let indices = (slots.iter())
        .map(|&s| {
            let x = ch.indices()[s as usize] as usize;
            if remap[x] == u32::MAX {
                remap[x] = (values.len() / dim) as u32;
                values.extend_from_slice(ch.value(x));
            }
            remap[x]
        })
        .collect();
    FaceVarying::new_unchecked(ch.name().to_string(), dim, values, indices)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::EdgeInterval;

    fn grid(n: u32) -> PolyMesh {
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f64, j as f64);
                pos.push([x, y, 0.1 * (x * x - y * y)]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = (n + 1) * j + i;
                faces.push([v, v + 1, v + n + 2, v + n + 1]);
            }
        }
        PolyMesh::from_faces(pos, &faces).unwrap()
    }

    #[test]
    fn samples_are_limit_points_and_shared() {
        let mut m = grid(4);
        m.knots.intervals.push(EdgeInterval {
            v0: 1,
            v1: 2,
            interval: 2.5,
        });
        let t = tessellate(&m, &Options::default(), 3, false).unwrap();
        assert_eq!(t.rate, 4);
        assert_eq!(t.num_faces(), 16 * 16);
        // Watertight: a (4·4+1)² grid of distinct samples.
        assert_eq!(t.num_vertices(), 17 * 17);
        let mut s = Nurss::new(&m, &Options::default()).unwrap();
        s.refine(2);
        let lp = s.limit_points();
        for p in &t.positions {
            assert!(lp.iter().any(|q| q == p));
        }
        // Normals are unit and point up on this gently curved sheet.
        assert!(t.normals.iter().all(|n| n[2] > 0.5));
        assert!(t.source.iter().all(|&(f, s)| f < 16 && s == 0));
    }

    #[test]
    fn ngons_become_sub_faces_and_triangles_split_quads() {
        let hexagon: Vec<[f64; 3]> = (0..6)
            .map(|k| {
                let a = k as f64 * std::f64::consts::PI / 3.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let m = PolyMesh::from_faces(hexagon, &[[0u32, 1, 2, 3, 4, 5]]).unwrap();
        let t = tessellate(&m, &Options::default(), 4, true).unwrap();
        // 6 sub-faces of 2 x 2 quads, 2 triangles each.
        assert_eq!(t.num_faces(), 6 * 4 * 2);
        let subs: std::collections::BTreeSet<u32> = t.source.iter().map(|s| s.1).collect();
        assert_eq!(subs.len(), 6);
    }
}
