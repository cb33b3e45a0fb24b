//! Files of curves and surfaces: JSON documents or OBJ free-form elements, one reader and
//! one writer for both, chosen by the file's contents and the output's extension.
//!
//! Commands that take NURBS input (curve interpolation, patch blending, hole filling,
//! format conversion) read it through [`read_geometry`], so every one of them accepts:
//!
//! - JSON ([`nurbs::json`](crate::nurbs::json) schema): one document or an array of them;
//!   recognised by its first non-blank character, `{` or `[`;
//! - OBJ free-form geometry ([`obj::parse_obj_freeform`](super::obj::parse_obj_freeform)):
//!   anything else.

use super::obj::{parse_obj_freeform, write_obj_freeform, ObjError};
use crate::nurbs::{from_json_str_all, to_json_string_all, Geometry, NurbsError, SourcedGeometry};
use std::path::Path;

/// An error reading a file of curves and surfaces.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GeometryFileError {
    /// The file could not be read.
    #[error("cannot read {source_name}: {message}")]
    Io {
        /// File name as given.
        source_name: String,
        /// The operating system's message.
        message: String,
    },
    /// A malformed OBJ file or free-form element (names the line).
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// A malformed JSON document (names the field, line and column).
    #[error("{source_name}: {error}")]
    Json {
        /// File name as given.
        source_name: String,
        /// What is wrong.
        error: NurbsError,
    },
    /// The file holds no curve or surface.
    #[error("{source_name}: no curves or surfaces found (expected JSON documents or OBJ `curv`/`surf` elements)")]
    Empty {
        /// File name as given.
        source_name: String,
    },
}

/// Reads the curves and surfaces of a JSON or OBJ file (see the module
/// documentation of `io::geometry`); `-` reads standard input.
///
/// # Errors
/// `GeometryFileError`: unreadable file, malformed content (naming line or field), or no
/// curve or surface at all.
pub fn read_geometry(path: &Path) -> Result<Vec<SourcedGeometry>, GeometryFileError> {
    let name = if path.as_os_str() == "-" {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    };
    let io_error = |e: std::io::Error| GeometryFileError::Io {
        source_name: name.clone(),
        message: e.to_string(),
    };
    let bytes = if path.as_os_str() == "-" {
        let mut v = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin(), &mut v).map_err(io_error)?;
        v
    } else {
        std::fs::read(path).map_err(io_error)?
    };
    parse_geometry(&bytes, &name)
}

/// Parses the curves and surfaces of JSON or OBJ bytes; `source_name` is used in errors and
/// origins.
///
/// # Errors
/// As [`read_geometry`].
pub fn parse_geometry(
    bytes: &[u8],
    source_name: &str,
) -> Result<Vec<SourcedGeometry>, GeometryFileError> {
    let first = bytes.iter().find(|b| !b.is_ascii_whitespace());
    let items = if matches!(first, Some(b'{' | b'[')) {
        let text = std::str::from_utf8(bytes).map_err(|e| GeometryFileError::Json {
            source_name: source_name.into(),
            error: NurbsError::JsonSyntax {
                line: 1,
                column: 1,
                message: format!("not UTF-8 text ({e})"),
            },
        })?;
        from_json_str_all(text)
            .map_err(|error| GeometryFileError::Json {
                source_name: source_name.into(),
                error,
            })?
            .into_iter()
            .enumerate()
            .map(|(i, geometry)| SourcedGeometry {
                geometry,
                name: None,
                origin: format!("{source_name}[{i}]"),
            })
            .collect::<Vec<_>>()
    } else {
        parse_obj_freeform(bytes, source_name)?
            .into_iter()
            .map(|e| SourcedGeometry {
                geometry: e.geometry,
                name: e.name,
                origin: format!("{source_name}:{}", e.line),
            })
            .collect()
    };
    if items.is_empty() {
        return Err(GeometryFileError::Empty {
            source_name: source_name.into(),
        });
    }
    Ok(items)
}

/// The output format of [`geometry_to_string`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeometryFormat {
    /// A JSON array of documents ([`to_json_string_all`]).
    Json,
    /// OBJ free-form elements ([`write_obj_freeform`]).
    Obj,
}

impl GeometryFormat {
    /// The format for a file name's extension (`.json` or `.obj`, any case).
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "json" => Some(Self::Json),
            "obj" => Some(Self::Obj),
            _ => None,
        }
    }
}

/// Curves and surfaces as the text of a JSON or OBJ file; both read back exactly.
pub fn geometry_to_string(items: &[Geometry], format: GeometryFormat) -> String {
    match format {
        GeometryFormat::Json => to_json_string_all(items),
        GeometryFormat::Obj => write_obj_freeform(items),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nurbs::{BSplineCurve, Curve, NurbsCurve};

    fn items() -> Vec<Geometry> {
        vec![
            Geometry::Curve(Curve::Nurbs(
                NurbsCurve::circle([0.0, 0.0, 1.0], 3.0).unwrap(),
            )),
            Geometry::Curve(Curve::BSpline(
                BSplineCurve::clamped_uniform(
                    3,
                    vec![
                        [0.0, 0.0, 0.0],
                        [1.0, 1.0, 0.0],
                        [2.0, 0.5, 0.0],
                        [3.0, 0.0, 1.0],
                    ],
                )
                .unwrap(),
            )),
        ]
    }

    #[test]
    fn json_and_obj_round_trip_and_name_their_origin() {
        for (format, origin) in [
            (GeometryFormat::Json, "c.json[1]"),
            (GeometryFormat::Obj, "c.json:24"),
        ] {
            let text = geometry_to_string(&items(), format);
            let back = parse_geometry(text.as_bytes(), "c.json").unwrap();
            let got: Vec<Geometry> = back.iter().map(|g| g.geometry.clone()).collect();
            assert_eq!(got, items());
            assert_eq!(back[1].origin, origin, "{text}");
        }
    }

    #[test]
    fn errors_name_the_file_and_place() {
        let e = parse_geometry(b"[{\"type\": \"bspline-curve\"}]", "x.json").unwrap_err();
        assert!(e.to_string().starts_with("x.json: JSON field `[0]"), "{e}");
        let e = parse_geometry(b"v 1 2 3\nf 1 1 1\n", "y.obj").unwrap_err();
        assert!(
            e.to_string().contains("y.obj: no curves or surfaces"),
            "{e}"
        );
        let e = parse_geometry(b"cstype taylor\n", "z.obj").unwrap_err();
        assert_eq!(
            e.to_string(),
            "z.obj:1: cstype taylor is not supported (bspline and bezier are)"
        );
    }
}
