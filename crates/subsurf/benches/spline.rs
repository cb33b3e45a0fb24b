//! Criterion bench: cost per evaluated point of the sub-basis spline surface ([Sub-basis splines])
//! against the polynomial uniform bicubic B-spline patch (`limit::bspline::eval`), both with
//! position and first and second derivatives, and position only. The paper claims that,
//! once the sub-basis functions are tabulated, a point costs about as much as a B-spline
//! point.
//!
//! Run with `cargo bench -p subsurf --bench spline`. Numbers are in `BENCHMARKS.md`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use subsurf::io::parse_obj;
use subsurf::limit::bspline;
use subsurf::spline::SubBasisSurface;

/// Points per face per iteration (a 8 × 8 grid).
const GRID: usize = 8;

fn params() -> Vec<(f64, f64)> {
    (0..GRID)
        .flat_map(|a| {
            (0..GRID).map(move |b| {
                (
                    (a as f64 + 0.5) / GRID as f64,
                    (b as f64 + 0.5) / GRID as f64,
                )
            })
        })
        .collect()
}

/// One 4 × 4 B-spline control net per face: the same number of patches, the same memory
/// traffic pattern (the positions `pos` of the pawn's control points, cycled).
fn nets(pos: &[[f64; 3]], faces: usize) -> Vec<[[[f64; 3]; 4]; 4]> {
    (0..faces)
        .map(|f| {
            let mut net = [[[0.0; 3]; 4]; 4];
            for (i, row) in net.iter_mut().enumerate() {
                for (j, p) in row.iter_mut().enumerate() {
                    *p = pos[(f * 7 + i * 4 + j) % pos.len()];
                }
            }
            net
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let pawn = parse_obj(
        include_bytes!("../../../examples/meshes/catmark_pawn.obj"),
        "catmark_pawn.obj",
    )
    .expect("pawn")
    .mesh;
    let surface = SubBasisSurface::new(&pawn).expect("quad mesh");
    let faces: Vec<u32> = (0..pawn.num_faces() as u32)
        .filter(|&f| surface.has_surface(f as usize))
        .collect();
    let nets = nets(pawn.positions(), faces.len());
    let uv = params();
    let points = (faces.len() * uv.len()) as u64;

    let mut g = c.benchmark_group("spline_vs_bspline_per_point");
    g.throughput(Throughput::Elements(points));
    g.measurement_time(Duration::from_secs(4));
    g.sample_size(20);
    g.bench_function("bspline_derivatives", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for net in &nets {
                for &(u, v) in &uv {
                    acc += bspline::eval(black_box(net), u, v).duv[0];
                }
            }
            acc
        })
    });
    g.bench_function("spline_derivatives", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &f in &faces {
                let patch = surface.patch(f as usize).expect("surface");
                for &(u, v) in &uv {
                    acc += black_box(patch).eval(u, v).duv[0];
                }
            }
            acc
        })
    });
    g.bench_function("spline_derivatives_checked", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &f in &faces {
                for &(u, v) in &uv {
                    acc += black_box(&surface).eval(f, u, v).expect("surface").duv[0];
                }
            }
            acc
        })
    });
    g.bench_function("bspline_position", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for net in &nets {
                for &(u, v) in &uv {
                    let (bu, _, _) = bspline::basis(u);
                    let (bv, _, _) = bspline::basis(v);
                    let mut p = [0.0; 3];
                    let net = black_box(net);
                    for i in 0..4 {
                        for j in 0..4 {
                            let w = bu[i] * bv[j];
                            for k in 0..3 {
                                p[k] += w * net[i][j][k];
                            }
                        }
                    }
                    acc += p[0];
                }
            }
            acc
        })
    });
    g.bench_function("spline_position", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &f in &faces {
                let patch = surface.patch(f as usize).expect("surface");
                for &(u, v) in &uv {
                    acc += black_box(patch).position(u, v)[0];
                }
            }
            acc
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
