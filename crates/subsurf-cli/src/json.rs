//! A tiny JSON value with a pretty printer, enough for `subsurf info --json`.

use std::fmt::{self, Write};

/// A JSON value. Objects keep their keys in insertion order.
#[derive(Clone, Debug, PartialEq)]
pub enum Json {
    /// `null`.
    Null,
    /// `true` / `false`.
    Bool(bool),
    /// An integer.
    Int(i64),
    /// A number; non-finite values are written as `null`.
    Num(f64),
    /// A string.
    Str(String),
    /// An array.
    Arr(Vec<Json>),
    /// An object.
    Obj(Vec<(String, Json)>),
}

impl Json {
    /// An object from `(key, value)` pairs.
    pub fn obj<K: Into<String>>(pairs: impl IntoIterator<Item = (K, Json)>) -> Self {
        Self::Obj(pairs.into_iter().map(|(k, v)| (k.into(), v)).collect())
    }

    /// A count (saturating at `i64::MAX`).
    pub fn count(n: usize) -> Self {
        Self::Int(i64::try_from(n).unwrap_or(i64::MAX))
    }

    /// A string.
    pub fn str(s: impl Into<String>) -> Self {
        Self::Str(s.into())
    }

    fn write(&self, f: &mut fmt::Formatter<'_>, indent: usize) -> fmt::Result {
        match self {
            Self::Null => f.write_str("null"),
            Self::Bool(b) => write!(f, "{b}"),
            Self::Int(i) => write!(f, "{i}"),
            // `{:?}` is the shortest round-trip form, e.g. `1.0`, `0.1`, `1e-7`: valid JSON.
            Self::Num(x) if x.is_finite() => write!(f, "{x:?}"),
            Self::Num(_) => f.write_str("null"),
            Self::Str(s) => write_str(f, s),
            Self::Arr(items) if items.iter().all(Self::is_scalar) => {
                f.write_char('[')?;
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    item.write(f, indent)?;
                }
                f.write_char(']')
            }
            Self::Arr(items) => {
                f.write_char('[')?;
                for (i, item) in items.iter().enumerate() {
                    f.write_str(if i > 0 { ",\n" } else { "\n" })?;
                    write!(f, "{:1$}", "", indent + 2)?;
                    item.write(f, indent + 2)?;
                }
                write!(f, "\n{:1$}]", "", indent)
            }
            Self::Obj(pairs) if pairs.is_empty() => f.write_str("{}"),
            Self::Obj(pairs) => {
                f.write_char('{')?;
                for (i, (key, value)) in pairs.iter().enumerate() {
                    f.write_str(if i > 0 { ",\n" } else { "\n" })?;
                    write!(f, "{:1$}", "", indent + 2)?;
                    write_str(f, key)?;
                    f.write_str(": ")?;
                    value.write(f, indent + 2)?;
                }
                write!(f, "\n{:1$}}}", "", indent)
            }
        }
    }

    fn is_scalar(&self) -> bool {
        !matches!(self, Self::Arr(_) | Self::Obj(_))
    }
}

impl fmt::Display for Json {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(f, 0)
    }
}

fn write_str(f: &mut fmt::Formatter<'_>, s: &str) -> fmt::Result {
    f.write_char('"')?;
    for c in s.chars() {
        match c {
            '"' => f.write_str("\\\"")?,
            '\\' => f.write_str("\\\\")?,
            '\n' => f.write_str("\\n")?,
            '\r' => f.write_str("\\r")?,
            '\t' => f.write_str("\\t")?,
            c if u32::from(c) < 0x20 => write!(f, "\\u{:04x}", u32::from(c))?,
            c => f.write_char(c)?,
        }
    }
    f.write_char('"')
}

#[cfg(test)]
mod tests {
    use super::Json;

    #[test]
    fn writes_valid_json() {
        let v = Json::obj([
            ("name", Json::str("a \"b\"\\c\n\u{1}é")),
            ("n", Json::Int(-3)),
            ("x", Json::Num(0.1)),
            ("one", Json::Num(1.0)),
            ("tiny", Json::Num(1e-300)),
            ("nan", Json::Num(f64::NAN)),
            ("ok", Json::Bool(true)),
            ("none", Json::Null),
            ("empty", Json::Obj(vec![])),
            ("list", Json::Arr(vec![Json::Int(1), Json::Int(2)])),
            ("objs", Json::Arr(vec![Json::obj([("k", Json::Int(1))])])),
        ]);
        let text = v.to_string();
        let parsed: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(parsed["name"], "a \"b\"\\c\n\u{1}é");
        assert_eq!(parsed["x"], 0.1);
        assert_eq!(parsed["one"], 1.0);
        assert_eq!(parsed["tiny"], 1e-300);
        assert!(parsed["nan"].is_null());
        assert_eq!(parsed["list"][1], 2);
        assert_eq!(parsed["objs"][0]["k"], 1);
    }
}
