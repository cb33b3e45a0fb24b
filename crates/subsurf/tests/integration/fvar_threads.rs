//! # Face-varying refinement on one thread and on two
//!
//! Large levels of face-varying data (texture coordinates) are refined in parallel: their
//! value topology and their values over ranges of faces, edges and vertices, each range
//! writing its own part of every array. The result may not depend on the schedule: a
//! channel refined in a rayon pool of one thread (the serial paths) and of two (the
//! parallel ones, which passes over 16 384 elements or more take) is the same bit for bit,
//! in every face-varying mode and with every scheme that refines face-varying data.

use subsurf::mesh::{
    BoundaryInterpolation, Corner, Crease, CreaseMethod, FaceVarying, FaceVaryingInterpolation,
    Options, PolyMesh,
};
use subsurf::scheme::Adjustable;
use subsurf::{subdivide, Mixed, Scheme, SubdivideOptions};

/// A small deterministic generator (64-bit LCG, top bits).
struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) % n as u64) as usize
    }
}

/// An `n × n` grid of quads (with `triangles`, each quad cut along a diagonal) with a
/// `"uv"` channel full of seams: faces share values within blocks of 7 × 9 faces (5 wide
/// on every 13th column), one face in 50 is an island of its own; and 300 creases and 80
/// corners, semi-sharp and infinitely sharp, on pseudo-random edges and vertices.
fn textured_grid(n: usize, triangles: bool, rng: &mut Lcg) -> PolyMesh {
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            pos.push([i as f64, j as f64, rng.below(1000) as f64 * 1e-3]);
        }
    }
    let mut values = Vec::new();
    let mut index = std::collections::HashMap::new();
    let (mut faces, mut indices) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            let mut block = (if i % 13 == 0 { i / 5 } else { i / 7 }, j / 9);
            if rng.below(50) == 0 {
                block = (1000 + i, 1000 + j);
            }
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let polys: Vec<Vec<(usize, usize)>> = if triangles {
                vec![
                    vec![corners[0], corners[1], corners[2]],
                    vec![corners[0], corners[2], corners[3]],
                ]
            } else {
                vec![corners.to_vec()]
            };
            for poly in polys {
                faces.push(poly.iter().map(|&(a, b)| at(a, b)).collect::<Vec<_>>());
                for (a, b) in poly {
                    let id = *index.entry((a, b, block)).or_insert_with(|| {
                        let k = block.0 * 31 + block.1;
                        values.extend([a as f64 / n as f64 + 1e-3 * k as f64, b as f64]);
                        (values.len() / 2 - 1) as u32
                    });
                    indices.push(id);
                }
            }
        }
    }
    let mut mesh = PolyMesh::from_faces(pos, &faces).expect("a grid is valid");
    mesh.face_varying
        .push(FaceVarying::new("uv", 2, values, indices).expect("finite values"));
    let sharpness = [0.5, 1.0, 1.7, 2.5, 3.0, 10.0];
    for _ in 0..300 {
        let (i, j) = (rng.below(n), rng.below(n + 1));
        mesh.tags.creases.push(Crease {
            v0: at(i, j),
            v1: at(i + 1, j),
            sharpness: sharpness[rng.below(sharpness.len())],
        });
    }
    for _ in 0..80 {
        let v = at(rng.below(n + 1), rng.below(n + 1));
        let sharpness = [0.7, 2.2, 10.0][rng.below(3)];
        mesh.tags.corners.push(Corner {
            vertex: v,
            sharpness,
        });
    }
    mesh
}

/// The `"uv"` channel of `mesh` refined with `opts`, as bits and indices.
fn refined_uv(mesh: &PolyMesh, opts: &SubdivideOptions) -> (Vec<u64>, Vec<u32>) {
    let out = subdivide(mesh, opts).expect("the grid refines").mesh;
    let uv = &out.face_varying[0];
    let bits = uv.values().iter().map(|x| x.to_bits()).collect();
    (bits, uv.indices().to_vec())
}

#[test]
fn face_varying_refinement_gives_the_same_bits_with_one_or_two_threads(
) -> Result<(), Box<dyn std::error::Error>> {
    let mut rng = Lcg(29);
    // 16 900 quads, 17 161 vertices, 34 060 edges: every pass is parallel from level 0.
    let quads = textured_grid(130, false, &mut rng);
    let tris = textured_grid(100, true, &mut rng);
    assert!(quads.num_faces() >= 16_384 && quads.num_vertices() >= 16_384);
    let adjustable = Scheme::Adjustable(Mixed {
        scheme: Adjustable::new(0.3)?,
        steps: 1,
    });
    let chaikin = Options {
        crease_method: CreaseMethod::Chaikin,
        boundary: BoundaryInterpolation::EdgeAndCorner,
        ..Options::default()
    };
    // (scheme, mesh, options, limit)
    let cases = [
        (Scheme::CatmullClark, &quads, Options::default(), false),
        (Scheme::CatmullClark, &quads, Options::default(), true),
        (Scheme::CatmullClark, &quads, chaikin, false),
        (adjustable, &quads, Options::default(), false),
        (Scheme::Bilinear, &quads, Options::default(), false),
        (Scheme::Loop, &tris, Options::default(), false),
    ];
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build()?;
    for (scheme, mesh, options, limit) in cases {
        for mode in FaceVaryingInterpolation::ALL_MODES {
            let opts = SubdivideOptions {
                levels: 2,
                scheme,
                options: Options {
                    face_varying: mode,
                    ..options
                },
                limit,
                ..SubdivideOptions::default()
            };
            let serial = one.install(|| refined_uv(mesh, &opts));
            let parallel = two.install(|| refined_uv(mesh, &opts));
            let what = format!("{scheme:?} {mode} (limit: {limit})");
            assert_eq!(serial.1, parallel.1, "{what}: value indices differ");
            assert_eq!(
                serial.0.len(),
                parallel.0.len(),
                "{what}: value counts differ"
            );
            if let Some(i) = (0..serial.0.len()).find(|&i| serial.0[i] != parallel.0[i]) {
                panic!("{what}: number {i} of the values differs");
            }
        }
    }
    Ok(())
}

/// `estimate_memory` counts the face-varying channels: the estimate with a channel exceeds
/// the one without by more than the refined channel's own arrays (its values and their
/// indices), for the layout with the most values, a UV island per face.
#[test]
fn memory_estimate_counts_the_face_varying_channels() {
    let mut rng = Lcg(7);
    for (scheme, triangles) in [(Scheme::CatmullClark, false), (Scheme::Loop, true)] {
        let textured = textured_grid(12, triangles, &mut rng);
        // Every face corner its own value.
        let corners = textured.face_verts().len();
        let islands = FaceVarying::new(
            "uv",
            2,
            (0..2 * corners).map(|i| i as f64).collect(),
            (0..corners as u32).collect(),
        )
        .expect("finite values");
        let mut mesh = textured.clone();
        mesh.face_varying = vec![islands];
        let mut plain = textured;
        plain.face_varying.clear();
        for limit in [false, true] {
            let opts = SubdivideOptions {
                levels: 3,
                scheme,
                limit,
                ..SubdivideOptions::default()
            };
            let out = subdivide(&mesh, &opts).expect("the grid refines").mesh;
            let uv = &out.face_varying[0];
            let arrays = 8 * uv.values().len() + 4 * uv.indices().len();
            let extra =
                subsurf::estimate_memory(&mesh, &opts) - subsurf::estimate_memory(&plain, &opts);
            assert!(
                extra > arrays as u64,
                "{scheme:?}, limit {limit}: {extra} <= {arrays}"
            );
        }
    }
}
