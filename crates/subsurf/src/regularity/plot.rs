//! A picture of a regularity report, like the paper's Figs. 5–7: on the left the control
//! net (its `x, y` projection) with u-edges blue and v-edges red and each face tinted by its
//! class (green certified, orange regular but not certified, red not regular — drawn on
//! top with a dark red outline — grey not applicable or not sampled); on the right the fans
//! of the global u-differences (blue) and v-differences (red) drawn from one origin, scaled
//! to the longest. As SVG (with a legend) or PNG (the same drawing, no text). Spatial nets
//! are drawn in their `x, y` projection.

#[cfg(feature = "render")]
use image::{Rgb, RgbImage};

use super::cone::Difference;
use super::report::{Class, Mode, RegularityReport};
use crate::mesh::PolyMesh;

/// Picture width in pixels (two square panels).
pub const PLOT_WIDTH: u32 = 1000;
/// Picture height in pixels.
pub const PLOT_HEIGHT: u32 = 520;
const PANEL: f64 = 500.0;
const MARGIN: f64 = 20.0;

const BLUE: [u8; 3] = [40, 80, 220];
const RED: [u8; 3] = [215, 40, 40];
const GREY: [u8; 3] = [120, 120, 120];
const DARK_RED: [u8; 3] = [150, 0, 0];

#[derive(Clone, Debug)]
enum Prim {
    Polygon(Vec<[f64; 2]>, [u8; 3]),
    Line([f64; 2], [f64; 2], [u8; 3], f64),
    Text([f64; 2], String),
}

fn fill(class: Class, certified: bool) -> [u8; 3] {
    match class {
        Class::Certified => [190, 235, 190],
        Class::RegularNotCertified => [255, 214, 140],
        Class::NotRegular | Class::Contradiction => [255, 150, 150],
        Class::Unsampled if certified => [190, 235, 190],
        Class::Unsampled => [225, 225, 225],
    }
}

/// The picture of a regularity report: the net's panel, the fans' panel, the captions.
fn scene(mesh: &PolyMesh, report: &RegularityReport, mode: Mode) -> Vec<Prim> {
    let mut out = Vec::new();
    net_panel(mesh, report, mode, &mut out);
    fans_panel(mesh, report, &mut out);
    captions(report, mode, &mut out);
    out
}

/// The left panel: the net seen along z, each face filled by its class (the faces that are
/// not regular last, outlined), the u- and v-differences of the components (every edge in
/// grey when there are none).
fn net_panel(mesh: &PolyMesh, report: &RegularityReport, mode: Mode, out: &mut Vec<Prim>) {
    let pos = mesh.positions();
    let (lo, hi) = mesh.bounding_box().unwrap_or(([0.0; 3], [1.0; 3]));
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    let s = (PANEL - 2.0 * MARGIN) / span;
    let ox = MARGIN + ((PANEL - 2.0 * MARGIN) - (hi[0] - lo[0]) * s) / 2.0;
    let oy = MARGIN + ((PANEL - 2.0 * MARGIN) - (hi[1] - lo[1]) * s) / 2.0;
    let map = |p: [f64; 3]| {
        [
            ox + (p[0] - lo[0]) * s,
            PLOT_HEIGHT as f64 - (oy + (p[1] - lo[1]) * s),
        ]
    };
    // Faces that are not regular are drawn last, outlined, so that a fold shows on top.
    let mut bad_outlines = Vec::new();
    let mut later = Vec::new();
    for (f, fv) in mesh.faces().enumerate() {
        let pts: Vec<[f64; 2]> = fv.iter().map(|&v| map(pos[v as usize])).collect();
        let certified = report
            .faces
            .get(f)
            .is_some_and(|r| report.certificate(r.face as usize, mode).is_certified());
        let class = if f < report.faces.len() {
            report.class(f, mode)
        } else {
            Class::Unsampled
        };
        if matches!(class, Class::NotRegular | Class::Contradiction) {
            for k in 0..pts.len() {
                bad_outlines.push(Prim::Line(pts[k], pts[(k + 1) % pts.len()], DARK_RED, 2.5));
            }
            later.push(Prim::Polygon(pts, fill(class, certified)));
        } else {
            out.push(Prim::Polygon(pts, fill(class, certified)));
        }
    }
    out.extend(later);
    let edge =
        |d: &Difference, c| Prim::Line(map(pos[d.from as usize]), map(pos[d.to as usize]), c, 1.2);
    if report.components.is_empty() {
        for fv in mesh.faces() {
            for k in 0..fv.len() {
                let d = Difference {
                    from: fv[k],
                    to: fv[(k + 1) % fv.len()],
                };
                out.push(edge(&d, GREY));
            }
        }
    }
    for c in &report.components {
        out.extend(c.u.iter().map(|d| edge(d, BLUE)));
        out.extend(c.v.iter().map(|d| edge(d, RED)));
    }
    out.extend(bad_outlines);
}

/// The right panel: the u- and v-differences of every component as a fan from a common
/// centre, scaled to the longest (or a note when there is no global u/v labelling).
fn fans_panel(mesh: &PolyMesh, report: &RegularityReport, out: &mut Vec<Prim>) {
    let pos = mesh.positions();
    let centre = [PANEL + PANEL / 2.0, PLOT_HEIGHT as f64 / 2.0];
    let vec = |d: &Difference| {
        let (a, b) = (pos[d.from as usize], pos[d.to as usize]);
        [b[0] - a[0], b[1] - a[1]]
    };
    let longest = report
        .components
        .iter()
        .flat_map(|c| c.u.iter().chain(&c.v))
        .map(|d| {
            let w = vec(d);
            w[0].hypot(w[1])
        })
        .fold(0.0, f64::max);
    if longest > 0.0 {
        let r = PANEL / 2.0 - MARGIN;
        for c in &report.components {
            for (ds, col) in [(&c.u, BLUE), (&c.v, RED)] {
                for d in ds {
                    let w = vec(d);
                    let end = [
                        centre[0] + w[0] / longest * r,
                        centre[1] - w[1] / longest * r,
                    ];
                    out.push(Prim::Line(centre, end, col, 1.0));
                }
            }
        }
    } else {
        out.push(Prim::Text(
            [PANEL + MARGIN, PLOT_HEIGHT as f64 / 2.0],
            "no global u/v labelling: no fans".into(),
        ));
    }
}

/// The captions: the counts of `mode`'s certificate, and the colours of the differences.
fn captions(report: &RegularityReport, mode: Mode, out: &mut Vec<Prim>) {
    let c = report.counts(mode);
    out.push(Prim::Text(
        [MARGIN, 16.0],
        format!(
            "{} certificate: {} certified, {} regular not certified, {} not regular, {} not applicable",
            match mode {
                Mode::Global => "global",
                Mode::Local => "local",
            },
            c.certified,
            c.regular_not_certified,
            c.not_regular,
            c.not_applicable
        ),
    ));
    out.push(Prim::Text(
        [PANEL + MARGIN, 16.0],
        "u-differences blue, v-differences red".into(),
    ));
}

fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The picture as an SVG document.
pub fn plot_svg(mesh: &PolyMesh, report: &RegularityReport, mode: Mode) -> String {
    use std::fmt::Write;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{PLOT_WIDTH}\" height=\"{PLOT_HEIGHT}\" viewBox=\"0 0 {PLOT_WIDTH} {PLOT_HEIGHT}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for p in scene(mesh, report, mode) {
        let _ = match p {
            Prim::Polygon(pts, c) => {
                let pts: Vec<String> = pts.iter().map(|q| format!("{:.2},{:.2}", q[0], q[1])).collect();
                writeln!(s, "<polygon points=\"{}\" fill=\"{}\"/>", pts.join(" "), hex(c))
            }
            Prim::Line(a, b, c, w) => writeln!(
                s,
                "<line x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{}\" stroke-width=\"{w}\"/>",
                a[0], a[1], b[0], b[1], hex(c)
            ),
            Prim::Text(a, t) => writeln!(
                s,
                "<text x=\"{:.1}\" y=\"{:.1}\" font-family=\"sans-serif\" font-size=\"12\">{}</text>",
                a[0], a[1], escape(&t)
            ),
        };
    }
    s.push_str("</svg>\n");
    s
}

/// The picture as an RGB image (no text).
#[cfg(feature = "render")]
pub fn plot_image(mesh: &PolyMesh, report: &RegularityReport, mode: Mode) -> RgbImage {
    let mut img = RgbImage::from_pixel(PLOT_WIDTH, PLOT_HEIGHT, Rgb([255, 255, 255]));
    let (w, h) = (PLOT_WIDTH as i64, PLOT_HEIGHT as i64);
    for p in scene(mesh, report, mode) {
        match p {
            Prim::Polygon(pts, c) => {
                let (x0, x1, y0, y1) = bounds(&pts, 0.0, w, h);
                for y in y0..y1 {
                    for x in x0..x1 {
                        if inside(&pts, [x as f64 + 0.5, y as f64 + 0.5]) {
                            img.put_pixel(x as u32, y as u32, Rgb(c));
                        }
                    }
                }
            }
            Prim::Line(a, b, c, lw) => {
                let (x0, x1, y0, y1) = bounds(&[a, b], lw + 1.0, w, h);
                for y in y0..y1 {
                    for x in x0..x1 {
                        let d = seg_dist([x as f64 + 0.5, y as f64 + 0.5], a, b);
                        let cover = (lw / 2.0 + 0.5 - d).clamp(0.0, 1.0);
                        if cover > 0.0 {
                            let px = img.get_pixel_mut(x as u32, y as u32);
                            for k in 0..3 {
                                let v = px.0[k] as f64 * (1.0 - cover) + c[k] as f64 * cover;
                                px.0[k] = v.round() as u8;
                            }
                        }
                    }
                }
            }
            Prim::Text(..) => {}
        }
    }
    img
}

#[cfg(feature = "render")]
fn bounds(pts: &[[f64; 2]], pad: f64, w: i64, h: i64) -> (i64, i64, i64, i64) {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in pts {
        x0 = x0.min(p[0]);
        x1 = x1.max(p[0]);
        y0 = y0.min(p[1]);
        y1 = y1.max(p[1]);
    }
    let c = |v: f64, hi: i64| (v as i64).clamp(0, hi);
    (
        c((x0 - pad).floor(), w),
        c((x1 + pad).ceil() + 1.0, w),
        c((y0 - pad).floor(), h),
        c((y1 + pad).ceil() + 1.0, h),
    )
}

#[cfg(feature = "render")]
fn inside(pts: &[[f64; 2]], q: [f64; 2]) -> bool {
    let mut odd = false;
    let n = pts.len();
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        if (a[1] > q[1]) != (b[1] > q[1]) {
            let x = a[0] + (q[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if q[0] < x {
                odd = !odd;
            }
        }
    }
    odd
}

#[cfg(feature = "render")]
fn seg_dist(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q[0] - a[0] - t * dx).hypot(q[1] - a[1] - t * dy)
}
