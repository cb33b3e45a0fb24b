//! # Loop and bilinear refinement against OpenSubdiv, shape by shape
//!
//! OpenSubdiv's 25 Loop regression shapes (`tests/shapes/osd/loop_*.obj`) and 3 bilinear ones
//! (`bilinear_*.obj`), copied verbatim from OpenSubdiv 3.6.0, are refined to levels 1–4 with
//! [`subdivide`] and [`Scheme::Loop`] or [`Scheme::Bilinear`], and compared with what OpenSubdiv 3.5
//! computed for the same file with `SCHEME_LOOP` / `SCHEME_BILINEAR`
//! (`tests/golden/osd_schemes/<shape>.txt.gz`, written by `scripts/make-golden-schemes.sh`
//! through `osd-oracle refine --scheme loop|bilinear`; format and provenance in
//! `tests/golden/README.md`). The checks are those of `osd_golden.rs` (see its top comment):
//! vertex count (hole-only vertices included), faces written (holes left out) with their
//! sizes and their list in order (FNV-1a hash), sampled positions index for index within
//! `1e-12 ×` the input's bounding-box diagonal, and sums over all vertices; each level both
//! refined and with its vertices moved to their limit positions (`--limit`, OpenSubdiv's
//! `PrimvarRefiner::Limit` with the scheme's limit masks). Limit evaluation at any
//! `(face, u, v)` for these schemes is not compared here. The lower-level path,
//! [`TopologyRefiner`] (and [`interpolate_with`]`(.., Bilinear, ..)`), gives the same bits
//! (`refiners_equal_subdivide`).

use std::fmt::Write as _;

use super::osd_golden::{
    boundary_tag, compare_case, crate_dir, diagonal, load_golden_from, quiet_catch, sample_indices,
    shape_names_with_prefix, shapes_dir, Expect,
};
use subsurf::io::read_obj;
use subsurf::mesh::{Options, PolyMesh, Topology};
use subsurf::refine::{interpolate_with, TopologyRefiner};
use subsurf::scheme::Bilinear;
use subsurf::{subdivide, Scheme, SubdivideOptions};

const REL_TOL: f64 = 1e-12;
const LEVELS: [u32; 4] = [1, 2, 3, 4];

fn golden_dir() -> std::path::PathBuf {
    crate_dir().join("tests/golden/osd_schemes")
}

/// The written mesh of a refined level: every vertex, the faces that are not holes.
fn written(level: &Topology, pos: Vec<[f64; 3]>) -> PolyMesh {
    let faces: Vec<Vec<u32>> = (0..level.num_faces())
        .filter(|&f| !level.is_hole(f))
        .map(|f| level.face_vertices(f).to_vec())
        .collect();
    PolyMesh::from_faces(pos, &faces).expect("a refined level is a valid mesh")
}

/// `mesh` refined `levels` times with `scheme` by the facade, hole faces left out; with
/// `limit`, the last level moved to its limit positions.
fn refine_with(
    mesh: &PolyMesh,
    scheme: Scheme,
    options: Options,
    levels: u32,
    limit: bool,
) -> Result<PolyMesh, subsurf::Error> {
    let opts = SubdivideOptions {
        levels,
        scheme,
        options,
        limit,
        ..Default::default()
    };
    Ok(subdivide(mesh, &opts)?.mesh)
}

/// `mesh` refined `levels` times with Loop on a [`TopologyRefiner`].
fn refine_loop(mesh: &PolyMesh, options: Options, levels: u32) -> Result<PolyMesh, subsurf::Error> {
    let mut r = TopologyRefiner::new(mesh, Scheme::Loop, options)?;
    r.refine_uniform(levels);
    let pos = r.interpolate_all(mesh.positions());
    Ok(written(r.level(levels as usize), pos))
}

/// `mesh` refined `levels` times with the bilinear scheme, its masks applied level by level
/// with [`interpolate_with`] on a [`TopologyRefiner`]'s levels.
fn refine_bilinear(
    mesh: &PolyMesh,
    options: Options,
    levels: u32,
) -> Result<PolyMesh, subsurf::Error> {
    let mut r = TopologyRefiner::new(mesh, Scheme::Bilinear, options)?;
    r.refine_uniform(levels);
    let mut pos = mesh.positions().to_vec();
    for l in 1..=levels as usize {
        let mut next = vec![[0.0; 3]; r.level(l).num_vertices()];
        interpolate_with(
            r.level(l - 1),
            r.level(l),
            r.options(),
            Bilinear,
            &pos,
            &mut next,
        );
        pos = next;
    }
    assert_eq!(pos, r.interpolate_all(mesh.positions()));
    Ok(written(r.level(levels as usize), pos))
}

/// Compares every shape named `prefix*` with its golden data; returns the table of largest
/// relative errors and the failures.
fn check(prefix: &str) -> (String, Vec<String>) {
    let mut table = String::new();
    let mut failures = Vec::new();
    for name in shape_names_with_prefix(prefix) {
        let golden = match load_golden_from(&golden_dir(), &name) {
            Ok(g) => g,
            Err(e) => {
                failures.push(e);
                continue;
            }
        };
        let obj = match read_obj(&shapes_dir().join(format!("{name}.obj"))) {
            Ok(o) => o,
            Err(e) => {
                failures.push(format!("{name}: {e}"));
                continue;
            }
        };
        let mut options = obj.options.resolve(Options::default());
        options.boundary = golden.boundary;
        let diag = diagonal(&obj.mesh);
        let _ = write!(table, "{name:<28} {:<16}", golden.boundary.to_string());
        for case in &golden.cases {
            let mode = if case.limit { "limit" } else { "refine" };
            let what = format!("{name} level {} {mode}", case.level);
            let Expect::Data(want) = &case.expect else {
                failures.push(format!("{what}: the oracle failed on it"));
                continue;
            };
            let scheme = match prefix {
                "loop_" => Scheme::Loop,
                _ => Scheme::Bilinear,
            };
            let run = || refine_with(&obj.mesh, scheme, options, case.level, case.limit);
            let mesh = match quiet_catch(run) {
                Ok(Ok(m)) => m,
                Ok(Err(e)) => {
                    failures.push(format!("{what}: {e}"));
                    continue;
                }
                Err(p) => {
                    failures.push(format!("{what}: panicked: {p}"));
                    continue;
                }
            };
            let mut err = f64::NAN;
            compare_case(
                &what,
                &mesh,
                want,
                REL_TOL * diag,
                diag,
                &mut failures,
                |e| err = e,
            );
            let _ = write!(table, " {err:>8.1e}");
        }
        table.push('\n');
    }
    (table, failures)
}

fn run_and_report(prefix: &str) {
    let (table, failures) = check(prefix);
    println!(
        "largest sampled error / input diagonal, levels 1-4 refined and at the limit \
         (check: <= {REL_TOL:e})\n{table}"
    );
    assert!(
        failures.is_empty(),
        "subsurf differs from OpenSubdiv:\n  {}",
        failures.join("\n  ")
    );
}

/// Every Loop shape, levels 1–4.
#[test]
fn osd_golden_loop_shapes() {
    run_and_report("loop_");
}

/// Every bilinear shape, levels 1–4.
#[test]
fn osd_golden_bilinear_shapes() {
    run_and_report("bilinear_");
}

/// The golden data itself: one file per shape and no strays, the shape's boundary tag,
/// levels 1–4 refined and at the limit, samples at the documented indices.
#[test]
fn osd_golden_schemes_data_is_complete() {
    let mut names = shape_names_with_prefix("loop_");
    names.extend(shape_names_with_prefix("bilinear_"));
    assert_eq!(names.len(), 28, "25 Loop and 3 bilinear shapes");
    let mut problems = Vec::new();
    let files: Vec<String> = std::fs::read_dir(golden_dir())
        .expect("tests/golden/osd_schemes is missing")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    for f in &files {
        let stem = f.strip_suffix(".txt.gz").unwrap_or(f);
        if !names.iter().any(|n| n == stem) {
            problems.push(format!("stray golden file {f}"));
        }
    }
    for name in &names {
        let g = match load_golden_from(&golden_dir(), name) {
            Ok(g) => g,
            Err(e) => {
                problems.push(e);
                continue;
            }
        };
        let text = std::fs::read_to_string(shapes_dir().join(format!("{name}.obj"))).unwrap();
        if g.name != *name || g.boundary != boundary_tag(&text) {
            problems.push(format!("{name}: name or boundary differs from the shape's"));
        }
        let cases: Vec<(u32, bool)> = g.cases.iter().map(|c| (c.level, c.limit)).collect();
        let want: Vec<(u32, bool)> = LEVELS
            .iter()
            .flat_map(|&l| [(l, false), (l, true)])
            .collect();
        if cases != want {
            problems.push(format!("{name}: cases {cases:?}"));
        }
        for c in &g.cases {
            if let Expect::Data(d) = &c.expect {
                let idx: Vec<usize> = d.samples.iter().map(|s| s.0).collect();
                if idx != sample_indices(d.verts) {
                    problems.push(format!("{name} level {}: sample indices", c.level));
                }
                let want_size = if name.starts_with("loop_") { 3 } else { 4 };
                if d.sizes.keys().any(|&k| k != want_size) {
                    problems.push(format!(
                        "{name} level {}: face sizes {:?}",
                        c.level, d.sizes
                    ));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The refiners give `subdivide`'s bits: positions, faces and written faces, every shape at
/// levels 1–3.
#[test]
fn refiners_equal_subdivide() {
    let mut cases = 0;
    for (prefix, scheme) in [("loop_", Scheme::Loop), ("bilinear_", Scheme::Bilinear)] {
        for name in shape_names_with_prefix(prefix) {
            let obj = read_obj(&shapes_dir().join(format!("{name}.obj"))).expect("shape");
            let options = obj.options.resolve(Options::default());
            for levels in 1..=3 {
                let facade =
                    refine_with(&obj.mesh, scheme, options, levels, false).expect("subdivide");
                let refiner = match scheme {
                    Scheme::Loop => refine_loop(&obj.mesh, options, levels),
                    _ => refine_bilinear(&obj.mesh, options, levels),
                }
                .expect("refiner");
                assert_eq!(
                    facade.positions(),
                    refiner.positions(),
                    "{name} level {levels}"
                );
                assert_eq!(
                    facade.face_verts(),
                    refiner.face_verts(),
                    "{name} level {levels}"
                );
                cases += 1;
            }
        }
    }
    assert_eq!(cases, 3 * 28);
}

/// Loop's limit with texture coordinates against OpenSubdiv (`tests/golden/loop_limit/`,
/// written by `scripts/loop-limit-golden.py` through `osd-oracle refine --scheme loop
/// --limit --fvar MODE`): three shapes with seams, creases and an extraordinary boundary,
/// levels 1–2, the six face-varying modes; every limit position within `1e-12 ×` the
/// diagonal and every limit `vt` within `1e-12`, index for index.
#[test]
fn loop_limit_with_texture_coordinates_matches_opensubdiv() {
    use subsurf::mesh::FaceVaryingInterpolation;
    let texts = crate::common::golden_texts("golden/loop_limit");
    assert_eq!(texts.len(), 3, "three shapes");
    let mut cases = 0;
    for text in &texts {
        let name = (text.lines().next())
            .and_then(|l| l.split(" for ").nth(1))
            .and_then(|l| l.split(".obj").next())
            .expect("a header naming the shape");
        let obj = read_obj(&shapes_dir().join(format!("{name}.obj"))).expect("shape");
        let diag = diagonal(&obj.mesh);
        let mut lines = text.lines().skip(1);
        while let Some(head) = lines.next() {
            let t: Vec<&str> = head.split_whitespace().collect();
            let (level, mode): (u32, FaceVaryingInterpolation) =
                (t[1].parse().expect("level"), t[2].parse().expect("mode"));
            let mut want_v = Vec::new();
            let mut want_vt = Vec::new();
            for l in lines.by_ref().take_while(|l| *l != "end") {
                let x: Vec<f64> = l
                    .split_whitespace()
                    .skip(1)
                    .map(|x| x.parse().unwrap())
                    .collect();
                if l.starts_with("vt ") {
                    want_vt.push([x[0], x[1]]);
                } else {
                    want_v.push([x[0], x[1], x[2]]);
                }
            }
            let options = Options {
                face_varying: mode,
                ..obj.options.resolve(Options::default())
            };
            let m = refine_with(&obj.mesh, Scheme::Loop, options, level, true).expect("subdivide");
            let what = format!("{name} level {level} {mode}");
            assert_eq!(m.num_vertices(), want_v.len(), "{what}");
            for (i, (p, q)) in m.positions().iter().zip(&want_v).enumerate() {
                let e = (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f64::max);
                assert!(e <= REL_TOL * diag, "{what}: vertex {i}: {p:?} vs {q:?}");
            }
            let uv = m.face_varying.first().expect("texture coordinates");
            assert_eq!(uv.num_values(), want_vt.len(), "{what}");
            for (i, q) in want_vt.iter().enumerate() {
                let p = uv.value(i);
                assert!(
                    (p[0] - q[0]).abs() <= 1e-12 && (p[1] - q[1]).abs() <= 1e-12,
                    "{what}: vt {i}: {p:?} vs {q:?}"
                );
            }
            cases += 1;
        }
    }
    assert_eq!(cases, 3 * 2 * 6);
}
