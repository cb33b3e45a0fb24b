//! End-to-end test of `subsurf demo`: the gallery page and every file it shows.

use crate::common;
use common::*;

use std::collections::BTreeSet;
use std::fs;
use std::path::Path;

/// Tags that have no end tag in HTML.
const VOID: [&str; 4] = ["img", "meta", "br", "link"];

/// A small HTML well-formedness check: every tag is closed in order (void elements
/// aside), attribute values are quoted; returns the `src` and `href` values in order.
fn check_html(page: &str) -> (Vec<String>, Vec<String>) {
    assert!(page.starts_with("<!DOCTYPE html>"), "no doctype");
    let (mut srcs, mut hrefs) = (Vec::new(), Vec::new());
    let mut stack: Vec<String> = Vec::new();
    let mut rest = &page["<!DOCTYPE html>".len()..];
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unterminated tag") + start;
        let tag = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack
                .pop()
                .unwrap_or_else(|| panic!("</{name}> closes nothing"));
            assert_eq!(open, name, "<{open}> closed by </{name}>");
            continue;
        }
        let name: String = tag
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric())
            .collect();
        assert!(!name.is_empty(), "bad tag <{tag}>");
        // Attributes: name="value" pairs, values without '"' or '<'.
        let mut attrs = tag[name.len()..].trim();
        while !attrs.is_empty() {
            let (key, value) = attrs
                .split_once("=\"")
                .unwrap_or_else(|| panic!("unquoted attribute in <{tag}>"));
            let close = value.find('"').expect("attribute value not closed");
            let v = &value[..close];
            assert!(!v.contains('<'), "unescaped '<' in <{tag}>");
            match key.trim() {
                "src" => srcs.push(v.to_owned()),
                "href" => hrefs.push(v.to_owned()),
                _ => {}
            }
            attrs = value[close + 1..].trim();
        }
        if name == "style" || name == "title" {
            // Raw text up to the end tag.
            let close = format!("</{name}>");
            let at = rest.find(&close).expect("raw text element not closed");
            rest = &rest[at + close.len()..];
            continue;
        }
        if !VOID.contains(&name.as_str()) {
            stack.push(name);
        }
    }
    assert!(stack.is_empty(), "unclosed: {stack:?}");
    (srcs, hrefs)
}

#[test]
fn demo_builds_a_gallery_whose_pictures_all_exist() {
    let dir = dir_with(&[]);
    let o = run_in(dir.path(), &["demo", "-o", "gallery"]);
    assert_code(&o, 0);
    let out = dir.path().join("gallery");
    let page = fs::read_to_string(out.join("index.html")).expect("index.html");
    let (srcs, hrefs) = check_html(&page);

    // Every picture: a relative path to a PNG that decodes, of the gallery's size, not blank
    // (or an SVG plot with lines).
    assert!(srcs.len() >= 80, "only {} pictures", srcs.len());
    for src in &srcs {
        assert!(
            !src.contains('/') && !src.contains(':'),
            "not a local relative link: {src}"
        );
        if src.ends_with(".svg") {
            // A plot: an SVG with its lines (the browser test decodes it).
            let svg = fs::read_to_string(out.join(src)).expect("the plot");
            assert!(
                svg.starts_with("<svg") && svg.contains("<polyline"),
                "{src}"
            );
            continue;
        }
        let img = image::open(out.join(src))
            .unwrap_or_else(|e| panic!("{src}: {e}"))
            .to_rgb8();
        assert!(img.width() >= 16 && img.height() >= 16, "{src}");
        let first = *img.get_pixel(0, 0);
        let differing = img.pixels().filter(|&&p| p != first).count();
        assert!(
            differing * 10 > (img.width() * img.height()) as usize,
            "{src} is (nearly) blank"
        );
    }
    // One caption per picture.
    assert_eq!(page.matches("<figcaption>").count(), srcs.len());
    assert!(!page.contains("<figcaption></figcaption>"));

    // Every link: a file of the gallery (or an anchor of the page); every written file is
    // shown or linked.
    let mut linked = BTreeSet::new();
    for href in &hrefs {
        if let Some(anchor) = href.strip_prefix('#') {
            assert!(
                page.contains(&format!("id=\"{anchor}\"")),
                "no section {anchor}"
            );
            continue;
        }
        assert!(out.join(href).is_file(), "{href} missing");
        linked.insert(href.clone());
    }
    linked.extend(srcs.iter().cloned());
    let written: BTreeSet<String> = listing(&out)
        .into_iter()
        .filter(|f| f != "index.html")
        .collect();
    assert_eq!(written, linked, "written files that the page does not show");

    // Every method of the project has a group on the page.
    for method in [
        "Catmull-Clark refinement",
        "Exact limit surface",
        "Pictures of the limit surface",
        "Shape-adjustable Catmull-Clark",
        "Non-uniform Catmull-Clark (NURSS)",
        "G2 caps at extraordinary vertices",
        "Sub-basis spline surface",
        "Regularity certificate",
        "Curve interpolation",
        "C2 blending of patches",
        "N-sided hole filling",
    ] {
        assert!(page.contains(&format!("<h3>{method}</h3>")), "{method}");
    }
    let has = |f: &str| assert!(written.contains(f), "{f} missing");

    // Each bundled surface mesh has a section with Catmull-Clark's and the adjustable
    // scheme's outputs.
    for ex in [
        "cube",
        "cube-crease",
        "grid",
        "hut",
        "torus",
        "pentaprism",
        "catmark_pawn",
    ] {
        assert!(page.contains(&format!("<section id=\"{ex}\">")), "{ex}");
        for suffix in [
            "-l3.obj",
            "-limit.glb",
            "-shaded.png",
            "-zebra.png",
            "-curvature.png",
        ] {
            has(&format!("{ex}{suffix}"));
        }
        for c in ["0", "0.25", "0.8"] {
            has(&format!("{ex}-c{c}-l2.obj"));
            has(&format!("{ex}-c{c}-zebra.png"));
        }
    }
    // G2 caps beside Catmull-Clark at valence 3 (cube) and 5 (pentaprism); the pictures
    // differ, and the patches are a subsurf-g2 JSON document.
    for ex in ["cube", "pentaprism"] {
        for suffix in [
            "cc-zebra.png",
            "g2-zebra.png",
            "cc-curvature.png",
            "g2-curvature.png",
        ] {
            has(&format!("{ex}-{suffix}"));
        }
        let pixels = |f: &str| image::open(out.join(f)).expect(f).to_rgb8();
        assert_ne!(
            pixels(&format!("{ex}-cc-zebra.png")),
            pixels(&format!("{ex}-g2-zebra.png")),
            "{ex}: the G2 caps change nothing"
        );
        let json = fs::read_to_string(out.join(format!("{ex}-g2.json"))).expect("g2 json");
        assert!(
            json.trim_start().starts_with('{') && json.contains("subsurf-g2"),
            "{ex}"
        );
    }
    // The sub-basis spline on the closed quad meshes without tags.
    for ex in ["cube", "torus", "pentaprism"] {
        for suffix in ["spline.obj", "spline-patches.png", "spline-zebra.png"] {
            has(&format!("{ex}-{suffix}"));
        }
    }
    assert!(
        !written.contains("grid-spline.obj"),
        "a mesh with a boundary has no spline"
    );
    // NURSS beside uniform Catmull-Clark of the same cage; the refined mesh keeps its knots.
    for f in [
        "nurss-grid-l3.obj",
        "nurss-grid-shaded.png",
        "nurss-grid-nurss-l3.obj",
        "nurss-grid-nurss-limit.obj",
        "nurss-grid-nurss-shaded.png",
        "nurss-grid-nurss-zebra.png",
    ] {
        has(f);
    }
    let refined = fs::read_to_string(out.join("nurss-grid-nurss-l3.obj")).expect("nurss");
    assert!(
        refined.contains("\nt interval "),
        "no knot intervals in the NURSS output"
    );
    // The regularity certificate of the planar nets, with the verdict in the caption.
    for ex in ["gear", "dolphin", "butterfly"] {
        for mode in ["local", "global"] {
            has(&format!("regularity-{ex}-regularity-{mode}.png"));
        }
    }
    assert!(page.contains("local certificate (per-face cones): certified regular; 144 of 144"));
    // Curve interpolation: control mesh with knot intervals, limit mesh, pictures.
    for ex in ["vase", "dolphin"] {
        for suffix in ["control.obj", "limit.obj", "shaded.png", "zebra.png"] {
            has(&format!("{ex}-{suffix}"));
        }
    }
    // The vase's curves have non-uniform knots: the control mesh carries them.
    let vase = fs::read_to_string(out.join("vase-control.obj")).expect("obj");
    assert!(vase.contains("\nt interval "), "vase: no knot intervals");
    // Blending and hole filling: the patches and the new surface as OBJ groups, pictures.
    for (ex, group) in [
        ("blend3", "blend"),
        ("blend5", "blend"),
        ("hole3", "fill"),
        ("hole5", "fill"),
        ("hole3-g1", "fill"),
        ("hole5-g1", "fill"),
    ] {
        let obj = fs::read_to_string(out.join(format!("{ex}-{group}.obj"))).expect("obj");
        assert!(
            obj.contains("\ng patch_1") && obj.contains(&format!("\ng {group}")),
            "{ex}"
        );
        has(&format!("{ex}-shaded.png"));
        has(&format!("{ex}-zebra.png"));
    }
    has("nurss-grid-nurss-l2-edges.png");
    check_captions(&page, &out);
    let glb = fs::read(out.join("torus-limit.glb")).expect("glb");
    assert_eq!(&glb[..4], b"glTF");
    assert!(Path::new(&out.join("cube.obj")).is_file());
    assert!(Path::new(&out.join("vase.json")).is_file());
}

/// The caption of the picture `file` in `page`.
fn caption<'a>(page: &'a str, file: &str) -> &'a str {
    let at = page
        .find(&format!("<img src=\"{file}\""))
        .unwrap_or_else(|| panic!("{file} not shown"));
    let rest = &page[at..];
    let start = rest.find("<figcaption>").expect("caption") + "<figcaption>".len();
    &rest[start..start + rest[start..].find("</figcaption>").expect("caption end")]
}

/// The numbers written in `text` (decimal or with an exponent).
fn numbers(text: &str) -> Vec<f64> {
    text.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
        .filter_map(|w| {
            w.trim_matches(|c| c == '.' || c == '-' || c == 'e')
                .parse()
                .ok()
        })
        .collect()
}

/// Captions state what was measured, and the pictures show what the captions say.
fn check_captions(page: &str, out: &Path) {
    // G2 caps: the measured jumps of the normal curvature are at rounding level for the
    // caps and large for Catmull-Clark at the vertex; both pictures on one colour range.
    for ex in ["cube", "pentaprism", "hut"] {
        let g2 = caption(page, &format!("{ex}-g2-curvature.png"));
        let jumps: Vec<f64> = numbers(g2.split("(relative)").nth(1).expect(g2))
            .into_iter()
            .take(3)
            .collect();
        assert_eq!(jumps.len(), 3, "{g2}");
        assert!(jumps.iter().all(|&j| (0.0..1e-9).contains(&j)), "{g2}");
        let cc = caption(page, &format!("{ex}-cc-curvature.png"));
        let cc_jump = numbers(cc.split("up to").nth(1).expect(cc))[0];
        assert!(cc_jump > 0.1, "{cc}");
        // The zebra caption gives the share of pixels that differ, as measured.
        let zebra = caption(page, &format!("{ex}-cc-zebra.png"));
        let share = numbers(zebra.split("zebra stripes:").nth(1).expect(zebra))[0];
        let a = image::open(out.join(format!("{ex}-cc-zebra.png")))
            .unwrap()
            .to_rgb8();
        let b = image::open(out.join(format!("{ex}-g2-zebra.png")))
            .unwrap()
            .to_rgb8();
        let differ = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
        let measured = 100.0 * differ as f64 / f64::from(a.width() * a.height());
        assert!(
            (share - measured).abs() <= 0.05 + 1e-9,
            "{zebra}: {measured}"
        );
    }
    // The pawn's mean curvature is coloured, not washed out to white by the few samples
    // on its creases: most of the surface's pixels are clearly red or blue.
    let img = image::open(out.join("catmark_pawn-curvature.png"))
        .unwrap()
        .to_rgb8();
    let background = *img.get_pixel(0, 0);
    let surface: Vec<_> = img.pixels().filter(|&&p| p != background).collect();
    let coloured = surface
        .iter()
        .filter(|p| (i32::from(p.0[0]) - i32::from(p.0[2])).abs() > 40)
        .count();
    assert!(
        coloured * 3 > surface.len(),
        "pawn: {coloured} of {} pixels coloured",
        surface.len()
    );
    // Blends: the measured match with the patches is at rounding level.
    for ex in ["blend3", "blend5"] {
        let c = caption(page, &format!("{ex}-zebra.png"));
        let gap = numbers(c.split("at most").nth(1).expect(c))[0];
        assert!(gap < 1e-9, "{c}");
    }
    // The captions of fills say what their zebra stripes show: no "smooth" claim.
    for ex in ["hole3", "hole5", "hole3-g1", "hole5-g1"] {
        let c = caption(page, &format!("{ex}-zebra.png"));
        assert!(!c.contains("curvature continuous"), "{c}");
    }
    // A click enlarges a picture.
    assert!(page.contains("id=\"lightbox\""));
}

#[test]
fn the_html_check_catches_broken_pages() {
    let ok = "<!DOCTYPE html><html><body><img src=\"a.png\"><a href=\"b.obj\">b</a></body></html>";
    assert_eq!(check_html(ok), (vec!["a.png".into()], vec!["b.obj".into()]));
    for bad in [
        "<html><body></body></html>",
        "<!DOCTYPE html><html><body></html>",
        "<!DOCTYPE html><html><body><a href=x>y</a></body></html>",
        "<!DOCTYPE html><html><div></span></html>",
    ] {
        assert!(
            std::panic::catch_unwind(|| check_html(bad)).is_err(),
            "accepted: {bad}"
        );
    }
}
