//! The library's layers run one way: a module uses only modules of its own layer or
//! below (ARCHITECTURE.md). This test reads the sources and lists every `crate::X` path in
//! code (not in comments, not in the unit tests at the end of a file or in a file of unit
//! tests) that names a module of a higher layer.
//!
//! Upward uses that remain are listed in `KNOWN`, each to be removed; the test fails on a
//! new one, and on a listed one that is gone (so that the list only shrinks).

use std::collections::BTreeSet;
use std::fs;
use std::path::Path;

/// Layers, bottom-up; modules of one layer may use each other.
const LAYERS: &[&[&str]] = &[
    &["geom", "hash", "cpu", "json"],
    &["mesh"],
    &["scheme"],
    &["refine"],
    &["limit"],
    &[
        "mixed",
        "nonuniform",
        "nurbs",
        "curves",
        "blend",
        "g2cap",
        "spline",
        "regularity",
    ],
    &["io", "render"],
    &["subdivide", "repose", "info"],
];

/// Upward uses still to be removed: (from module, to module).
const KNOWN: &[(&str, &str)] = &[];

fn layer(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

/// The module each item re-exported at the crate root comes from (`pub use m::{a, b};` in
/// `lib.rs`), so that `crate::a` counts as a use of `m`.
fn root_exports(lib: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for item in code(lib).split(';') {
        let Some(path) = item.trim().strip_prefix("pub use ") else {
            continue;
        };
        let Some((module, rest)) = path.split_once("::") else {
            continue;
        };
        let names = match rest.rsplit_once("::") {
            _ if rest.starts_with('{') => rest.trim_matches(|c| c == '{' || c == '}').to_string(),
            Some((_, last)) => last.to_string(),
            None => rest.to_string(),
        };
        for name in names.split(',') {
            let name = name.trim();
            let name = name.rsplit("::").next().unwrap_or(name);
            if !name.is_empty() {
                out.push((name.to_string(), module.trim().to_string()));
            }
        }
    }
    out
}

/// The code of `text` before its unit tests, without comments.
fn code(text: &str) -> String {
    let end = text.find("#[cfg(test)]\nmod tests").unwrap_or(text.len());
    text[..end]
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The first names of the paths after `crate::`: one name, or each item of a group
/// `{a::b, c, d::{e, f}}`.
fn targets(after: &str) -> Vec<String> {
    let name = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let Some(group) = after.strip_prefix('{') else {
        return vec![name(after)];
    };
    let (mut depth, mut start, mut out) = (0, 0, Vec::new());
    for (k, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                out.push(name(&group[start..k]));
                break;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(name(&group[start..k]));
                start = k + 1;
            }
            _ => {}
        }
    }
    out
}

/// The files of `dir` that hold unit tests only: those its sources include as
/// `#[cfg(test)] #[path = "NAME"] mod …;` (tests may use any layer, as the unit tests at the
/// end of a file may).
fn unit_test_files(dir: &Path) -> BTreeSet<String> {
    const INCLUDE: &str = "#[cfg(test)]\n#[path = \"";
    let mut names = BTreeSet::new();
    for entry in fs::read_dir(dir).expect("source directory") {
        let path = entry.expect("directory entry").path();
        if path.extension().is_some_and(|x| x == "rs") {
            let text = fs::read_to_string(&path).expect("readable source");
            for (i, _) in text.match_indices(INCLUDE) {
                let rest = &text[i + INCLUDE.len()..];
                names.extend(rest.split('"').next().map(str::to_string));
            }
        }
    }
    names
}

fn visit(
    dir: &Path,
    src: &Path,
    exports: &[(String, String)],
    found: &mut BTreeSet<(String, String, String)>,
) {
    let tests = unit_test_files(dir);
    for entry in fs::read_dir(dir).expect("source directory") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            visit(&path, src, exports, found);
            continue;
        }
        if path.extension().and_then(|e| e.to_str()) != Some("rs") {
            continue;
        }
        let rel = path.strip_prefix(src).expect("under src");
        let from = rel
            .components()
            .next()
            .and_then(|c| c.as_os_str().to_str())
            .map(|s| s.trim_end_matches(".rs").to_string())
            .expect("a module");
        let Some(from_layer) = layer(&from) else {
            continue;
        };
        if path
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(|n| tests.contains(n))
        {
            continue;
        }
        let text = code(&fs::read_to_string(&path).expect("readable source"));
        for (i, _) in text.match_indices("crate::") {
            for name in targets(&text[i + 7..]) {
                let to = exports
                    .iter()
                    .find(|(item, _)| *item == name)
                    .map_or(name, |(_, module)| module.clone());
                if layer(&to).is_some_and(|l| l > from_layer) {
                    found.insert((from.clone(), to, rel.display().to_string()));
                }
            }
        }
    }
}

#[test]
fn layers_run_one_way() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let lib = fs::read_to_string(src.join("lib.rs")).expect("lib.rs");
    let exports = root_exports(&lib);
    assert!(
        exports
            .iter()
            .any(|(item, m)| item == "subdivide" && m == "subdivide"),
        "lib.rs's re-exports were not read: {exports:?}"
    );
    let mut found = BTreeSet::new();
    visit(&src, &src, &exports, &mut found);
    let edges: BTreeSet<(&str, &str)> = found
        .iter()
        .map(|(a, b, _)| (a.as_str(), b.as_str()))
        .collect();
    let new: Vec<_> = found
        .iter()
        .filter(|(a, b, _)| !KNOWN.contains(&(a.as_str(), b.as_str())))
        .collect();
    assert!(new.is_empty(), "upward uses (from, to, file): {new:#?}");
    let gone: Vec<_> = KNOWN.iter().filter(|e| !edges.contains(e)).collect();
    assert!(
        gone.is_empty(),
        "upward uses no longer found; remove them from KNOWN: {gone:?}"
    );
}
