//! IGES export of the G2 surface (entity 128): the file is read back by an independent
//! parser of the fixed-column records written here from the IGES 5.3 layout, and every
//! patch — degrees, clamped knots, unit weights, control points (bit for bit), parameter
//! range — is the one of the JSON export.

use subsurf::g2cap::{patches_json, to_iges, G2Surface, G2SurfaceOptions, PatchJson};

use crate::common;
use common::cube;

/// One parsed entity: its directory fields and free-format parameters.
struct Entity {
    kind: u32,
    form: u32,
    params: Vec<String>,
}

/// Parses the records: checks columns, section order and numbering, the Terminate
/// counts and the pointers between Directory Entry and Parameter Data.
fn parse(text: &str) -> Vec<Entity> {
    let mut sections: Vec<(char, Vec<String>)> = Vec::new();
    for line in text.lines() {
        assert_eq!(line.len(), 80, "record of {} columns: {line:?}", line.len());
        let letter = line.as_bytes()[72] as char;
        let seq: usize = line[73..].trim().parse().unwrap();
        if sections.last().map(|s| s.0) != Some(letter) {
            sections.push((letter, Vec::new()));
        }
        let records = &mut sections.last_mut().unwrap().1;
        records.push(line[..72].to_string());
        assert_eq!(seq, records.len(), "section {letter} numbering");
    }
    let order: String = sections.iter().map(|s| s.0).collect();
    assert_eq!(order, "SGDPT");
    let count = |c: char| sections.iter().find(|s| s.0 == c).unwrap().1.len();
    let t = &sections[4].1[0];
    for (k, c) in "SGDP".chars().enumerate() {
        let field = &t[8 * k..8 * k + 8];
        assert_eq!(field.chars().next(), Some(c));
        assert_eq!(field[1..].trim().parse::<usize>().unwrap(), count(c));
    }
    let global = &sections[1].1.concat();
    assert!(global.starts_with("1H,,1H;,"), "{global}");
    let d = &sections[2].1;
    let p = &sections[3].1;
    let field = |s: &str, k: usize| s[8 * k..8 * k + 8].trim().to_string();
    let mut out = Vec::new();
    for e in 0..d.len() / 2 {
        let (l1, l2) = (&d[2 * e], &d[2 * e + 1]);
        let kind: u32 = field(l1, 0).parse().unwrap();
        assert_eq!(field(l2, 0), field(l1, 0));
        let start: usize = field(l1, 1).parse().unwrap();
        let lines: usize = field(l2, 3).parse().unwrap();
        let form: u32 = field(l2, 4).parse().unwrap();
        let mut data = String::new();
        for r in &p[start - 1..start - 1 + lines] {
            assert_eq!(r[65..72].trim().parse::<usize>().unwrap(), 2 * e + 1);
            data.push_str(r[..64].trim_end());
        }
        assert!(data.ends_with(';'), "entity {e}");
        let params = data
            .trim_end_matches(';')
            .split(',')
            .map(str::to_string)
            .collect();
        out.push(Entity { kind, form, params });
    }
    out
}

/// Checks one entity 128 against its patch.
fn check(entity: &Entity, patch: &PatchJson) {
    assert_eq!((entity.kind, entity.form), (128, 0));
    let p = &entity.params;
    let int = |k: usize| p[k].parse::<usize>().unwrap();
    let real = |k: usize| p[k].parse::<f64>().unwrap();
    assert_eq!(int(0), 128);
    let d = patch.degree;
    assert_eq!([int(1), int(2), int(3), int(4)], [d, d, d, d]);
    assert_eq!([int(5), int(6), int(7), int(8), int(9)], [0, 0, 1, 0, 0]);
    let mut k = 10;
    for _ in 0..2 {
        for j in 0..2 * (d + 1) {
            assert!(p[k].contains('.'), "reals carry a decimal point: {}", p[k]);
            assert_eq!(real(k), if j <= d { 0.0 } else { 1.0 });
            k += 1;
        }
    }
    for _ in 0..(d + 1) * (d + 1) {
        assert_eq!(real(k), 1.0);
        k += 1;
    }
    for j in 0..=d {
        for i in 0..=d {
            let q = patch.points[i * (d + 1) + j];
            for c in q {
                assert_eq!(real(k).to_bits(), c.to_bits());
                k += 1;
            }
        }
    }
    assert_eq!(
        [real(k), real(k + 1), real(k + 2), real(k + 3)],
        [0.0, 1.0, 0.0, 1.0]
    );
    assert_eq!(k + 4, p.len());
}

#[test]
fn iges_entities_read_back_as_the_json_patches() {
    let mesh = cube();
    let surface = G2Surface::new(&mesh, &G2SurfaceOptions::default()).unwrap();
    let doc = patches_json(&surface, &mesh).unwrap();
    let text = to_iges(&doc, "cube-g2.igs");
    let entities = parse(&text);
    let patches: Vec<&PatchJson> = doc.patches().collect();
    assert_eq!(entities.len(), patches.len());
    assert_eq!(patches.iter().filter(|p| p.degree == 7).count(), 24);
    for (e, p) in entities.iter().zip(&patches) {
        check(e, p);
    }
    // Deterministic: the same surface gives the same file.
    assert_eq!(text, to_iges(&doc, "cube-g2.igs"));
}

#[test]
fn json_text_reads_back_with_an_independent_parser() {
    let mesh = cube();
    let surface = G2Surface::new(&mesh, &G2SurfaceOptions::default()).unwrap();
    let doc = patches_json(&surface, &mesh).unwrap();
    let v: serde_json::Value = serde_json::from_str(&doc.to_json()).unwrap();
    assert_eq!(v["format"], "subsurf-g2");
    assert_eq!(v["levels"].as_u64(), Some(u64::from(doc.levels)));
    assert!(v.get("mixed").is_none(), "absent `mixed` is omitted");
    let caps = v["caps"].as_array().unwrap();
    assert_eq!(caps.len(), doc.caps.len());
    let patches: Vec<&serde_json::Value> = caps
        .iter()
        .flat_map(|c| c["patches"].as_array().unwrap())
        .chain(v["bicubic"].as_array().unwrap())
        .collect();
    let expected: Vec<&PatchJson> = doc.patches().collect();
    assert_eq!(patches.len(), expected.len());
    for (p, e) in patches.iter().zip(&expected) {
        assert_eq!(p["face"].as_u64(), Some(u64::from(e.face)));
        assert_eq!(p["corner"].as_u64(), e.corner.map(u64::from));
        assert_eq!(p["degree"].as_u64(), Some(e.degree as u64));
        let points = p["points"].as_array().unwrap();
        assert_eq!(points.len(), e.points.len());
        for (q, x) in points.iter().zip(&e.points) {
            for (a, b) in q.as_array().unwrap().iter().zip(x) {
                assert_eq!(a.as_f64().unwrap().to_bits(), b.to_bits());
            }
        }
    }
}
