//! Criterion bench: building the G2 cap solver of one valence ([Tang et al. 2017]) — the production
//! per-Fourier-frequency solve ([`CapSolver`]: `⌊n/2⌋ + 1` systems of at most 50
//! unknowns) against the reference all-sectors solve ([`DenseCapSolver`]: one system of
//! `25n` unknowns and `72n` rows) — and completing one cap with each (applying the
//! precomputed matrices).
//!
//! Run with `cargo bench -p subsurf --bench g2cap`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use subsurf::g2cap::{CapSolver, DenseCapSolver};

const VALENCES: [usize; 4] = [3, 5, 8, 16];

/// `64n` control points with every point set (the solvers read only the outer rows).
fn net(n: usize) -> Vec<[f64; 3]> {
    (0..64 * n)
        .map(|g| {
            let x = g as f64;
            [(0.37 * x).sin(), (0.11 * x).cos(), 0.01 * x]
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("g2cap_solver_build");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(3));
    for n in VALENCES {
        g.bench_with_input(BenchmarkId::new("per_frequency", n), &n, |b, &n| {
            b.iter(|| CapSolver::new(black_box(n)).expect("valence"))
        });
        g.bench_with_input(BenchmarkId::new("all_sectors", n), &n, |b, &n| {
            b.iter(|| DenseCapSolver::new(black_box(n)).expect("valence"))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("g2cap_complete");
    g.sample_size(20);
    g.measurement_time(Duration::from_secs(2));
    for n in VALENCES {
        let (fast, dense) = (
            CapSolver::new(n).expect("valence"),
            DenseCapSolver::new(n).expect("valence"),
        );
        let points = net(n);
        g.bench_with_input(BenchmarkId::new("per_frequency", n), &n, |b, _| {
            b.iter(|| {
                let mut p = points.clone();
                // The residual check may refuse this arbitrary net; the work is done.
                let _ = fast.complete(black_box(&mut p));
                p
            })
        });
        g.bench_with_input(BenchmarkId::new("all_sectors", n), &n, |b, _| {
            b.iter(|| {
                let mut p = points.clone();
                let _ = dense.complete(black_box(&mut p));
                p
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
