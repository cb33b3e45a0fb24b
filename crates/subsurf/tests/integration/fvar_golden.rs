//! # Face-varying data (texture coordinates) against OpenSubdiv
//!
//! Each shape of `tests/golden/fvar/` (OpenSubdiv's Catmull-Clark regression shapes with
//! `vt` from `tests/shapes/osd/`, and `tests/golden/fvar/textured_cube.obj`) is refined with
//! Catmull-Clark, and each shape of `tests/golden/fvar_loop/` (the 23 Loop regression
//! shapes with `vt`, and the two `textured_tri_cube*.obj` there) with Loop, to levels 1–3 in each of the six face-varying modes, and
//! the `"uv"` channel is compared with what OpenSubdiv 3.5 computed (`osd-oracle refine
//! SHAPE L --fvar MODE [--scheme loop]`, written by `scripts/fvar-golden.py`; format in
//! `tests/golden/README.md`): the number of values, the face-corner value indices of every
//! written face exactly (an FNV-1a hash over each face's size and 0-based `vt` indices, as
//! for the vertex golden data), up to 256 values index for index (all when there are at
//! most 256) within 1e-12 (the shapes' values are at most 3 in size, most at most 1), and
//! the sums of `s` and `t` over all values within 1e-12 per value. Values compare by index
//! because subsurf numbers child values as OpenSubdiv does.

use subsurf::io::read_obj;
use subsurf::mesh::{FaceVaryingInterpolation, Options};
use subsurf::{subdivide, Scheme, SubdivideOptions};

use crate::common::tests_dir as dir;

fn fnv(offsets: &[u32], indices: &[u32]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    let mut eat = |x: u32| {
        for b in x.to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x100000001b3);
        }
    };
    for w in offsets.windows(2) {
        eat(w[1] - w[0]);
        for &i in &indices[w[0] as usize..w[1] as usize] {
            eat(i);
        }
    }
    h
}

/// One case of a golden file.
struct Case {
    level: u32,
    mode: FaceVaryingInterpolation,
    values: usize,
    faces: usize,
    hash: u64,
    sum: [f64; 2],
    samples: Vec<(usize, [f64; 2])>,
}

fn parse(text: &str) -> (String, Vec<Case>) {
    let mut shape = String::new();
    let mut cases = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let t: Vec<&str> = line.split_whitespace().collect();
        match t.first().copied() {
            Some("shape") => shape = t[1].to_string(),
            Some("case") => cases.push(Case {
                level: t[1].parse().unwrap(),
                mode: t[2].parse().unwrap(),
                values: t[4].parse().unwrap(),
                faces: t[6].parse().unwrap(),
                hash: u64::from_str_radix(t[8], 16).unwrap(),
                sum: [t[10].parse().unwrap(), t[11].parse().unwrap()],
                samples: Vec::new(),
            }),
            Some("end") | None => {}
            Some(i) => {
                let c = cases.last_mut().expect("a sample belongs to a case");
                c.samples.push((
                    i.parse().unwrap(),
                    [t[1].parse().unwrap(), t[2].parse().unwrap()],
                ));
            }
        }
    }
    (shape, cases)
}

/// The differences of one case of the golden directory `tests/<sub>` refined with
/// `scheme`, if any, and its largest sampled error. The shape is the OBJ file beside the
/// golden file if there is one, else the regression shape of `tests/shapes/osd/`. A shape
/// that does not load or refine is a difference naming the reason.
fn check(sub: &str, shape: &str, scheme: Scheme, c: &Case) -> (Vec<String>, f64) {
    let own = dir(sub).join(format!("{shape}.obj"));
    let path = if own.exists() {
        own
    } else {
        dir("shapes/osd").join(format!("{shape}.obj"))
    };
    let at = format!("{shape} ({scheme}) level {} {}", c.level, c.mode);
    let obj = match read_obj(&path) {
        Ok(obj) => obj,
        Err(e) => {
            return (
                vec![format!("{at}: cannot read {path:?}: {e}")],
                f64::INFINITY,
            )
        }
    };
    let options = Options {
        face_varying: c.mode,
        ..obj.options.resolve(Options::default())
    };
    let opts = SubdivideOptions {
        levels: c.level,
        scheme,
        options,
        ..Default::default()
    };
    let out = match subdivide(&obj.mesh, &opts) {
        Ok(s) => s.mesh,
        Err(e) => return (vec![format!("{at}: not refined: {e}")], f64::INFINITY),
    };
    let Some(uv) = out.face_varying.iter().find(|f| f.name() == "uv") else {
        return (vec![format!("{at}: no uv channel")], f64::INFINITY);
    };
    let mut problems = Vec::new();
    if uv.num_values() != c.values {
        problems.push(format!(
            "{at}: {} values, expected {}",
            uv.num_values(),
            c.values
        ));
        return (problems, f64::INFINITY);
    }
    if out.num_faces() != c.faces || fnv(out.face_offsets(), uv.indices()) != c.hash {
        problems.push(format!("{at}: face value indices differ"));
    }
    let mut worst = 0.0f64;
    for &(i, st) in &c.samples {
        let v = uv.value(i);
        let e = (v[0] - st[0]).abs().max((v[1] - st[1]).abs());
        if e > 1e-12 {
            problems.push(format!(
                "{at}: value {i} is {v:?}, expected {st:?} (error {e:e})"
            ));
        }
        worst = worst.max(e);
    }
    for k in 0..2 {
        let s: f64 = uv.values().iter().skip(k).step_by(uv.dim()).sum();
        if (s - c.sum[k]).abs() > 1e-12 * c.values as f64 {
            problems.push(format!(
                "{at}: sum of component {k} is {s}, expected {}",
                c.sum[k]
            ));
        }
    }
    (problems, worst)
}

/// Checks every golden file of `tests/<sub>` (at least `min_files`) refined with `scheme`.
fn check_all(sub: &str, scheme: Scheme, min_files: usize) {
    let files = crate::common::golden_texts(sub);
    assert!(
        files.len() >= min_files,
        "golden files missing: {}",
        files.len()
    );
    let mut problems = Vec::new();
    for text in files {
        let (shape, cases) = parse(&text);
        assert_eq!(cases.len(), 18, "{shape}: 3 levels × 6 modes");
        let mut worst = 0.0f64;
        for c in &cases {
            let (p, w) = check(sub, &shape, scheme, c);
            problems.extend(p);
            worst = worst.max(w);
        }
        println!("{shape:28} largest sampled uv error {worst:.1e}");
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn fvar_golden_all_shapes() {
    check_all("golden/fvar", Scheme::CatmullClark, 14);
}

/// Loop's face-varying refinement (the triangle split) against OpenSubdiv on its 23 Loop
/// regression shapes with texture coordinates and two triangulated textured cubes: seams,
/// the six modes, semi-sharp and infinitely sharp creases and corners, both crease
/// methods, non-manifold edges and vertices, the three boundary modes.
#[test]
fn fvar_golden_loop_shapes() {
    check_all("golden/fvar_loop", Scheme::Loop, 25);
}
