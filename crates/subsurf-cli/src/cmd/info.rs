//! `subsurf info`: a summary of a mesh, as text or JSON.

use std::fmt::Write as _;
use std::io::Write as _;

use anyhow::{Context, Result};
use subsurf::io::FileOptions;
use subsurf::mesh::Options;
use subsurf::{mesh_info, MeshInfo};

use crate::input::Input;
use crate::json::Json;
use crate::InfoArgs;

/// Runs `subsurf info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let input = Input::read(&args.input, args.max_memory)?;
    if args.strict {
        input.check_strict()?;
    }
    for w in input.warnings() {
        crate::output::eprint_line(&format!("warning: {w}"));
    }
    let file = input.obj.options;
    let chosen = FileOptions {
        boundary: args.boundary.or(file.boundary),
        ..file
    };
    let options = chosen.resolve(Options::default());
    let info = mesh_info(&input.obj.mesh, &options).with_context(|| input.name.clone())?;
    let sources = Sources {
        file,
        flag_boundary: args.boundary.is_some(),
    };
    let text = if args.json {
        to_json(&input, &info, &options, &sources).to_string() + "\n"
    } else {
        to_text(&input, &info, &options, &sources)
    };
    std::io::stdout()
        .lock()
        .write_all(text.as_bytes())
        .context("cannot write to standard output")
}

/// Where each scheme option came from.
struct Sources {
    file: FileOptions,
    flag_boundary: bool,
}

impl Sources {
    fn boundary(&self) -> &'static str {
        if self.flag_boundary {
            "--boundary"
        } else {
            from_file(self.file.boundary.is_some())
        }
    }
}

fn from_file(set: bool) -> &'static str {
    if set {
        "file"
    } else {
        "default"
    }
}

fn manifold(info: &MeshInfo) -> bool {
    info.non_manifold_edges == 0 && info.non_manifold_vertices == 0
}

fn diagonal(lo: [f64; 3], hi: [f64; 3]) -> f64 {
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// `x` with at most 6 decimals, without trailing zeros.
fn short(x: f64) -> String {
    let s = format!("{x:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

fn point(p: [f64; 3]) -> String {
    format!("({}, {}, {})", short(p[0]), short(p[1]), short(p[2]))
}

/// `"3: 4, 4: 6"` for `(key, count)` pairs.
fn histogram(pairs: &[(usize, usize)]) -> String {
    if pairs.is_empty() {
        return "none".to_owned();
    }
    let parts: Vec<String> = pairs.iter().map(|(k, n)| format!("{k}: {n}")).collect();
    parts.join(", ")
}

/// The first lines of `subsurf info`'s text report, label and value: the file, counts, valences,
/// boundaries, manifoldness, tags, the scheme's options and where they come from.
fn mesh_lines(
    input: &Input,
    info: &MeshInfo,
    options: &Options,
    src: &Sources,
) -> Vec<(&'static str, String)> {
    vec![
        ("file", input.name.clone()),
        ("vertices", info.vertices.to_string()),
        ("edges", info.edges.to_string()),
        ("faces", info.faces.to_string()),
        ("face sizes (size: count)", histogram(&info.face_sizes)),
        ("valences (valence: count)", histogram(&info.valences)),
        (
            "extraordinary vertices",
            info.extraordinary_vertices.to_string(),
        ),
        ("isolated vertices", info.isolated_vertices.to_string()),
        ("boundary loops", info.boundary_loops.to_string()),
        ("boundary edges", info.boundary_edges.to_string()),
        (
            "manifold",
            if manifold(info) { "yes" } else { "no" }.to_owned(),
        ),
        ("non-manifold edges", info.non_manifold_edges.to_string()),
        (
            "non-manifold vertices",
            info.non_manifold_vertices.to_string(),
        ),
        (
            "euler characteristic",
            info.euler_characteristic.to_string(),
        ),
        ("creases", info.creases.to_string()),
        ("corners", info.corners.to_string()),
        ("holes", info.holes.to_string()),
        (
            "boundary interpolation",
            format!("{} ({})", options.boundary, src.boundary()),
        ),
        (
            "crease method",
            format!(
                "{} ({})",
                options.crease_method,
                from_file(src.file.crease_method.is_some())
            ),
        ),
        (
            "triangle subdivision",
            format!(
                "{} ({})",
                options.triangles,
                from_file(src.file.triangles.is_some())
            ),
        ),
        ("suggested scheme", suggestion(info)),
    ]
}

/// The suggested scheme and why ([`MeshInfo::suggested_scheme`]).
fn suggestion(info: &MeshInfo) -> String {
    match info.suggested_scheme() {
        subsurf::Scheme::Loop => {
            "loop (every face is a triangle: --scheme loop; Catmull-Clark would split each \
             into three quads around an extraordinary vertex)"
                .to_owned()
        }
        s => s.to_string(),
    }
}

/// The lines of `subsurf info`'s text report after the counts: the bounding box, the knot
/// intervals and weights (when the file has any), the ignored tags.
fn extent_and_tag_lines(input: &Input, info: &MeshInfo, lines: &mut Vec<(&'static str, String)>) {
    match info.bounding_box {
        Some((lo, hi)) => {
            lines.push(("bounding box min", point(lo)));
            lines.push(("bounding box max", point(hi)));
            lines.push(("diagonal", short(diagonal(lo, hi))));
        }
        None => lines.push(("bounding box", "none (no vertices)".to_owned())),
    }
    let knots = subsurf::nonuniform::knot_summary(&input.obj.mesh);
    if !input.obj.mesh.knots.is_empty() {
        let range = |r: Option<(f64, f64)>| {
            r.map_or(String::new(), |(a, b)| {
                format!(", from {} to {}", short(a), short(b))
            })
        };
        lines.push((
            "knot intervals",
            format!(
                "{} tagged edges{}, {} zero (untagged edges: 1)",
                knots.tagged_edges,
                range(knots.interval_range),
                knots.zero_interval_edges
            ),
        ));
        lines.push(("side intervals", knots.side_intervals.to_string()));
        lines.push((
            "rational weights",
            format!(
                "{} weighted vertices{}",
                knots.weighted_vertices,
                range(knots.weight_range)
            ),
        ));
    }
    if !input.obj.unsupported_tags.is_empty() {
        let names: Vec<&str> = input
            .obj
            .unsupported_tags
            .iter()
            .map(|t| t.name.as_str())
            .collect();
        lines.push(("ignored tags", names.join(", ")));
    }
}

/// `subsurf info`'s text report: one `label: value` line per item, values aligned.
fn to_text(input: &Input, info: &MeshInfo, options: &Options, src: &Sources) -> String {
    let mut lines = mesh_lines(input, info, options, src);
    extent_and_tag_lines(input, info, &mut lines);
    let width = lines
        .iter()
        .map(|(label, _)| label.len())
        .max()
        .unwrap_or(0)
        + 2;
    let mut text = String::new();
    for (label, value) in lines {
        let _ = writeln!(text, "{:width$}{value}", format!("{label}:"));
    }
    text
}

fn histogram_json(pairs: &[(usize, usize)], key: &str) -> Json {
    Json::Arr(
        pairs
            .iter()
            .map(|&(k, n)| Json::obj([(key, Json::count(k)), ("count", Json::count(n))]))
            .collect(),
    )
}

/// The knot tag statistics as JSON (`min`/`max` null when there are none).
fn knots_json(mesh: &subsurf::mesh::PolyMesh) -> Json {
    let k = subsurf::nonuniform::knot_summary(mesh);
    let range = |r: Option<(f64, f64)>, a: &'static str, b: &'static str| {
        let (lo, hi) = r.map_or((Json::Null, Json::Null), |(x, y)| {
            (Json::Num(x), Json::Num(y))
        });
        [(a, lo), (b, hi)]
    };
    let [imin, imax] = range(k.interval_range, "min_interval", "max_interval");
    let [wmin, wmax] = range(k.weight_range, "min_weight", "max_weight");
    Json::obj([
        ("tagged_edges", Json::count(k.tagged_edges)),
        imin,
        imax,
        ("zero_interval_edges", Json::count(k.zero_interval_edges)),
        ("side_intervals", Json::count(k.side_intervals)),
        ("weighted_vertices", Json::count(k.weighted_vertices)),
        wmin,
        wmax,
    ])
}

fn option_json<T: ToString>(value: Option<T>) -> Json {
    value.map_or(Json::Null, |v| Json::str(v.to_string()))
}

fn to_json(input: &Input, info: &MeshInfo, options: &Options, src: &Sources) -> Json {
    let coords = |p: [f64; 3]| Json::Arr(p.iter().map(|&x| Json::Num(x)).collect());
    let bounding_box = info.bounding_box.map_or(Json::Null, |(lo, hi)| {
        Json::obj([
            ("min", coords(lo)),
            ("max", coords(hi)),
            ("diagonal", Json::Num(diagonal(lo, hi))),
        ])
    });
    let file = &src.file;
    Json::obj([
        ("file", Json::str(&input.name)),
        ("vertices", Json::count(info.vertices)),
        ("edges", Json::count(info.edges)),
        ("faces", Json::count(info.faces)),
        ("face_sizes", histogram_json(&info.face_sizes, "size")),
        ("valences", histogram_json(&info.valences, "valence")),
        (
            "extraordinary_vertices",
            Json::count(info.extraordinary_vertices),
        ),
        ("isolated_vertices", Json::count(info.isolated_vertices)),
        ("boundary_loops", Json::count(info.boundary_loops)),
        ("boundary_edges", Json::count(info.boundary_edges)),
        ("manifold", Json::Bool(manifold(info))),
        ("non_manifold_edges", Json::count(info.non_manifold_edges)),
        (
            "non_manifold_vertices",
            Json::count(info.non_manifold_vertices),
        ),
        ("euler_characteristic", Json::Int(info.euler_characteristic)),
        (
            "tags",
            Json::obj([
                ("creases", Json::count(info.creases)),
                ("corners", Json::count(info.corners)),
                ("holes", Json::count(info.holes)),
            ]),
        ),
        (
            "scheme",
            Json::obj([
                ("boundary", Json::str(options.boundary.to_string())),
                (
                    "crease_method",
                    Json::str(options.crease_method.to_string()),
                ),
                ("triangles", Json::str(options.triangles.to_string())),
            ]),
        ),
        (
            "suggested_scheme",
            Json::str(info.suggested_scheme().to_string()),
        ),
        (
            "file_scheme",
            Json::obj([
                ("boundary", option_json(file.boundary)),
                ("crease_method", option_json(file.crease_method)),
                ("triangles", option_json(file.triangles)),
            ]),
        ),
        ("bounding_box", bounding_box),
        ("knots", knots_json(&input.obj.mesh)),
        (
            "unsupported_tags",
            Json::Arr(
                input
                    .obj
                    .unsupported_tags
                    .iter()
                    .map(|t| {
                        Json::obj([("line", Json::count(t.line)), ("name", Json::str(&t.name))])
                    })
                    .collect(),
            ),
        ),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_numbers() {
        assert_eq!(short(1.0), "1");
        assert_eq!(short(-0.0000001), "0");
        assert_eq!(short(1.7477806), "1.747781");
        assert_eq!(short(-2.5), "-2.5");
        assert_eq!(short(3.0f64.sqrt() * 2.0), "3.464102");
    }

    #[test]
    fn histograms() {
        assert_eq!(histogram(&[]), "none");
        assert_eq!(histogram(&[(3, 4), (4, 6)]), "3: 4, 4: 6");
    }
}
