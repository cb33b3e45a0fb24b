//! [`to_iges`]: the Bézier patches of a G2 surface ([`SurfaceJson`]: the bi-septic caps
//! and the bicubic patches of the rest) as an IGES 5.3 file of Rational B-Spline Surface
//! entities (type 128), the exchange format CAD systems read.
//!
//! # Layout (IGES 5.3, ch. 2; entity 128 in §4.24)
//! Fixed 80-column records: columns 1-72 data, 73 the section letter, 74-80 the sequence
//! number. Sections: Start (`S`, free text), Global (`G`, parameters of the file:
//! delimiters, precision, units = millimetres, IGES version 11 = 5.3), Directory Entry
//! (`D`, two records of nine 8-column fields per entity: type, pointer to its parameter
//! data, …, parameter line count, form 0), Parameter Data (`P`, columns 1-64 free-format
//! parameters separated by `,` and ended by `;`, 66-72 the pointer back to the directory
//! entry), Terminate (`T`, the record count of each section).
//!
//! A Bézier patch of degree `d` is the B-spline surface with `K1 = K2 = M1 = M2 = d`,
//! clamped knots `0` (`d + 1` times) and `1` (`d + 1` times) in `u` and `v`, all weights 1
//! (`PROP3 = 1`: polynomial), control points `p(i, j)` with the `u` index `i` varying
//! fastest, and the parameter range `[0, 1]²` (the patch's own parameters; its place in
//! the input face is in the JSON output). Reals are written with the shortest digits that
//! read back to the same `f64`, always with a decimal point. The file is deterministic:
//! the Global section's dates are fixed (`20000101.000000`), not the time of writing.

use super::export::{PatchJson, SurfaceJson};

/// Columns of Parameter Data available for parameters.
const P_WIDTH: usize = 64;

/// A real in IGES form: shortest round-trip digits, with a decimal point, exponent `E`.
fn real(x: f64) -> String {
    let s = format!("{x:?}");
    let s = if s.contains('.') || !x.is_finite() {
        s
    } else if let Some((m, e)) = s.split_once('e') {
        format!("{m}.0e{e}")
    } else {
        format!("{s}.0")
    };
    s.replace('e', "E")
}

/// A Hollerith string `nHtext`.
fn hollerith(s: &str) -> String {
    format!("{}H{s}", s.len())
}

/// One 80-column record: `data` (≤ 72 columns) padded, the section letter, the number.
fn record(data: &str, section: char, seq: usize) -> String {
    debug_assert!(data.len() <= 72, "an IGES record holds 72 columns: {data}");
    format!("{data:<72}{section}{seq:>7}\n")
}

/// Free-format parameters packed into lines of at most `width` columns (a parameter is
/// never split), each with its delimiter; the last ends with `;`.
fn pack(params: &[String], width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for (k, p) in params.iter().enumerate() {
        let token = format!("{p}{}", if k + 1 == params.len() { ';' } else { ',' });
        if !line.is_empty() && line.len() + token.len() > width {
            lines.push(std::mem::take(&mut line));
        }
        line.push_str(&token);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// The parameters of entity 128 for one Bézier patch.
fn surface_parameters(patch: &PatchJson) -> Vec<String> {
    let d = patch.degree;
    let mut p: Vec<String> = [128, d, d, d, d, 0, 0, 1, 0, 0]
        .iter()
        .map(|x| x.to_string())
        .collect();
    for _ in 0..2 {
        p.extend((0..=d).map(|_| real(0.0)));
        p.extend((0..=d).map(|_| real(1.0)));
    }
    p.extend((0..(d + 1) * (d + 1)).map(|_| real(1.0)));
    for j in 0..=d {
        for i in 0..=d {
            let q = patch.points[i * (d + 1) + j];
            p.extend(q.iter().map(|&x| real(x)));
        }
    }
    p.extend([0.0, 1.0, 0.0, 1.0].map(real));
    p
}

/// The patches of `doc` (every cap patch, then every bicubic patch) as an IGES file, one
/// entity 128 each; `name` goes into the Global section as the file name (its printable
/// ASCII characters other than the delimiters, at most 60).
pub fn to_iges(doc: &SurfaceJson, name: &str) -> String {
    let name: String = name
        .chars()
        .filter(|c| c.is_ascii_graphic() && *c != ',' && *c != ';' || *c == ' ')
        .take(60)
        .collect();
    let patches: Vec<&PatchJson> = doc.patches().collect();
    let mut out = String::new();
    let start = [
        "subsurf: G2 surface (Tang et al. 2017) as Bezier patches, entity 128.",
        "Cap patches (degree 7) first, then the bicubic patches.",
    ];
    for (k, s) in start.iter().enumerate() {
        out.push_str(&record(s, 'S', k + 1));
    }
    let global = [
        "1H,".to_string(),
        "1H;".to_string(),
        hollerith("subsurf"),
        hollerith(&name),
        hollerith("subsurf"),
        hollerith(env!("CARGO_PKG_VERSION")),
        "32".into(),
        "38".into(),
        "6".into(),
        "308".into(),
        "15".into(),
        hollerith("subsurf"),
        real(1.0),
        "2".into(),
        hollerith("MM"),
        "1".into(),
        real(0.0),
        hollerith("20000101.000000"),
        real(1e-10),
        real(0.0),
        hollerith("subsurf"),
        hollerith("subsurf"),
        "11".into(),
        "0".into(),
        hollerith("20000101.000000"),
    ];
    let g_lines = pack(&global, 72);
    for (k, l) in g_lines.iter().enumerate() {
        out.push_str(&record(l, 'G', k + 1));
    }
    let mut d_records = String::new();
    let mut p_records = String::new();
    let mut p_seq = 1;
    for (e, patch) in patches.iter().enumerate() {
        let de = 2 * e + 1;
        let lines = pack(&surface_parameters(patch), P_WIDTH);
        let line1 = format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            128, p_seq, 0, 0, 0, 0, 0, 0, "00000000"
        );
        let line2 = format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            128,
            0,
            0,
            lines.len(),
            0,
            "",
            "",
            "BEZIER",
            e + 1
        );
        d_records.push_str(&record(&line1, 'D', de));
        d_records.push_str(&record(&line2, 'D', de + 1));
        for l in &lines {
            p_records.push_str(&record(&format!("{l:<64} {de:>7}"), 'P', p_seq));
            p_seq += 1;
        }
    }
    out.push_str(&d_records);
    out.push_str(&p_records);
    let t = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        start.len(),
        g_lines.len(),
        2 * patches.len(),
        p_seq - 1
    );
    out.push_str(&record(&t, 'T', 1));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reals read back exactly and always carry a decimal point.
    #[test]
    fn reals_round_trip_with_a_decimal_point() {
        for x in [
            0.0,
            1.0,
            -2.5,
            1e-7,
            1.5e-300,
            123456789.0,
            0.1 + 0.2,
            -3e22,
        ] {
            let s = real(x);
            assert!(s.contains('.'), "{s}");
            assert_eq!(s.parse::<f64>().unwrap(), x, "{s}");
        }
    }

    /// A hostile file name cannot break the fixed columns.
    #[test]
    fn file_names_are_sanitised() {
        let doc = SurfaceJson {
            format: "subsurf-g2",
            version: 1,
            levels: 2,
            mixed: None,
            caps: Vec::new(),
            bicubic: Vec::new(),
            not_polynomial: Vec::new(),
            uncapped: Vec::new(),
            uncapped_reasons: Vec::new(),
        };
        let text = to_iges(&doc, &format!("a,b;c\u{e9}{}", "x".repeat(200)));
        assert!(text.lines().all(|l| l.len() == 80));
        assert!(text.contains("60Habcxxx"));
    }

    /// Packing never splits a parameter and respects the width.
    #[test]
    fn packing_respects_the_columns() {
        let params: Vec<String> = (0..100).map(|k| real(k as f64 * 0.123456789)).collect();
        let lines = pack(&params, P_WIDTH);
        assert!(lines.iter().all(|l| l.len() <= P_WIDTH));
        let joined: String = lines.concat();
        let back: Vec<&str> = joined.trim_end_matches(';').split(',').collect();
        assert_eq!(back.len(), params.len());
        assert!(back.iter().zip(&params).all(|(a, b)| a == b));
    }
}
