//! Meshes and helpers shared by the test modules (the G2-cap ones mostly), and the shared
//! scheme options (`schemes`) and interpolation curves (`curves`).
#![allow(dead_code)] // each test module uses a subset

pub mod curves;
pub mod schemes;

use std::path::{Path, PathBuf};

use subsurf::io::{parse_obj, read_obj};
use subsurf::mesh::{Options, PolyMesh};

/// A small deterministic generator (xorshift), so the tests need no extra crate.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// The directory of OpenSubdiv's regression shapes.
pub fn osd_shapes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/shapes/osd")
}

/// Every Catmull-Clark regression shape of OpenSubdiv's (`catmark_*.obj`; the Loop and
/// bilinear ones are [`osd_shapes_of`]`("loop_")`, `("bilinear_")`), sorted by name, with
/// the scheme options of its tags.
pub fn osd_shapes() -> Vec<(String, PolyMesh, Options)> {
    let shapes = osd_shapes_of("catmark_");
    assert!(shapes.len() >= 80, "expected the 87 OpenSubdiv shapes");
    shapes
}

/// The regression shapes whose names start with `prefix`, sorted by name, with the scheme
/// options of their tags.
pub fn osd_shapes_of(prefix: &str) -> Vec<(String, PolyMesh, Options)> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(osd_shapes_dir())
        .expect("shapes directory")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with(prefix))
        })
        .collect();
    paths.sort();
    assert!(!paths.is_empty(), "no shapes named {prefix}*");
    paths
        .iter()
        .map(|path| {
            let obj =
                read_obj(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            let options = obj.options.resolve(Options::default());
            (name, obj.mesh, options)
        })
        .collect()
}

pub fn cube() -> PolyMesh {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    let f = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    PolyMesh::from_faces(p, &f).unwrap()
}

pub fn example(name: &str) -> PolyMesh {
    let path = format!(
        "{}/../../examples/meshes/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read(&path).unwrap();
    parse_obj(&text[..], &path).unwrap().mesh
}

/// A closed mesh with vertices of valence 3, 5, 6, 7 and 8: a prism-like ring of quads
/// around an `n`-valent pole on both ends, with a little noise.
pub fn double_cone(n: usize, seed: u64) -> PolyMesh {
    let mut rng = Rng(seed | 1);
    let tau = std::f64::consts::TAU;
    let mut p = vec![[0.0, 0.0, 1.2], [0.0, 0.0, -1.2]];
    for ring in 0..3 {
        let z = [0.6, 0.0, -0.6][ring];
        let r = [0.8, 1.1, 0.8][ring];
        for i in 0..2 * n {
            let a = tau * i as f64 / (2 * n) as f64;
            p.push([
                r * a.cos() + 0.05 * rng.next(),
                r * a.sin() + 0.05 * rng.next(),
                z + 0.05 * rng.next(),
            ]);
        }
    }
    let at = |ring: usize, i: usize| (2 + ring * 2 * n + i % (2 * n)) as u32;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for i in 0..n {
        let k = 2 * i;
        faces.push(vec![0, at(0, k), at(0, k + 1), at(0, k + 2)]);
        faces.push(vec![1, at(2, k + 2), at(2, k + 1), at(2, k)]);
    }
    for ring in 0..2 {
        for i in 0..2 * n {
            faces.push(vec![
                at(ring, i),
                at(ring + 1, i),
                at(ring + 1, i + 1),
                at(ring, i + 1),
            ]);
        }
    }
    PolyMesh::from_faces(p, &faces).unwrap()
}

/// `crates/subsurf/tests/SUB`.
pub fn tests_dir(sub: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(sub)
}

/// The texts of the gzipped golden files (`*.txt.gz`) of `tests/SUB`, in file name order.
pub fn golden_texts(sub: &str) -> Vec<String> {
    use std::io::Read;
    let mut files: Vec<PathBuf> = std::fs::read_dir(tests_dir(sub))
        .expect("golden directory")
        .map(|e| e.expect("golden directory entry").path())
        .filter(|p| p.to_string_lossy().ends_with(".txt.gz"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|f| {
            let mut text = String::new();
            flate2::read::GzDecoder::new(std::fs::File::open(&f).expect("golden file"))
                .read_to_string(&mut text)
                .expect("gzipped text");
            text
        })
        .collect()
}
