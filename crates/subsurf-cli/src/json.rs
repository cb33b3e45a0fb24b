//! A tiny JSON value with a pretty printer, enough for `subsurf info --json`, and a reader
//! of the library's compact documents ([`Json::parse`]) to print them the same way.

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

    /// Reads the JSON text `text` (RFC 8259): objects keep their members' order, numbers
    /// without a fraction or exponent that fit an `i64` are [`Json::Int`], the others
    /// [`Json::Num`] (parsed exactly, so they print as the digits that wrote them did).
    ///
    /// # Errors
    /// What is wrong, and at which byte.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut r = Reader { text, at: 0 };
        let value = r.value(0)?;
        r.skip_space();
        if r.at < text.len() {
            return Err(r.error("text after the value"));
        }
        Ok(value)
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

/// The deepest nesting [`Json::parse`] reads (it recurses once per level).
const MAX_DEPTH: usize = 128;

/// [`Json::parse`]'s position in its text.
struct Reader<'a> {
    text: &'a str,
    at: usize,
}

impl Reader<'_> {
    fn error(&self, what: &str) -> String {
        format!("{what} at byte {}", self.at)
    }

    fn skip_space(&mut self) {
        let rest = &self.text[self.at..];
        self.at += rest.len() - rest.trim_start_matches([' ', '\t', '\n', '\r']).len();
    }

    fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.at).copied()
    }

    /// Consumes `c` (after white space) if it comes next.
    fn eat(&mut self, c: u8) -> bool {
        self.skip_space();
        let found = self.peek() == Some(c);
        if found {
            self.at += 1;
        }
        found
    }

    fn value(&mut self, depth: usize) -> Result<Json, String> {
        if depth > MAX_DEPTH {
            return Err(self.error("nesting too deep"));
        }
        self.skip_space();
        match self.peek() {
            Some(b'{') => {
                self.at += 1;
                let mut pairs = Vec::new();
                if self.eat(b'}') {
                    return Ok(Json::Obj(pairs));
                }
                loop {
                    self.skip_space();
                    let key = self.string()?;
                    if !self.eat(b':') {
                        return Err(self.error("expected ':'"));
                    }
                    pairs.push((key, self.value(depth + 1)?));
                    if self.eat(b'}') {
                        return Ok(Json::Obj(pairs));
                    }
                    if !self.eat(b',') {
                        return Err(self.error("expected ',' or '}'"));
                    }
                }
            }
            Some(b'[') => {
                self.at += 1;
                let mut items = Vec::new();
                if self.eat(b']') {
                    return Ok(Json::Arr(items));
                }
                loop {
                    items.push(self.value(depth + 1)?);
                    if self.eat(b']') {
                        return Ok(Json::Arr(items));
                    }
                    if !self.eat(b',') {
                        return Err(self.error("expected ',' or ']'"));
                    }
                }
            }
            Some(b'"') => self.string().map(Json::Str),
            Some(b't') => self.word("true", Json::Bool(true)),
            Some(b'f') => self.word("false", Json::Bool(false)),
            Some(b'n') => self.word("null", Json::Null),
            Some(b'-' | b'0'..=b'9') => self.number(),
            _ => Err(self.error("expected a value")),
        }
    }

    fn word(&mut self, word: &str, value: Json) -> Result<Json, String> {
        if self.text[self.at..].starts_with(word) {
            self.at += word.len();
            Ok(value)
        } else {
            Err(self.error("expected a value"))
        }
    }

    fn number(&mut self) -> Result<Json, String> {
        let rest = &self.text[self.at..];
        let len = rest
            .find(|c: char| !matches!(c, '0'..='9' | '-' | '+' | '.' | 'e' | 'E'))
            .unwrap_or(rest.len());
        let token = &rest[..len];
        let integer = !token.contains(['.', 'e', 'E']);
        let value = match token.parse::<i64>() {
            Ok(i) if integer => Json::Int(i),
            _ => Json::Num(
                token
                    .parse::<f64>()
                    .map_err(|_| self.error("not a number"))?,
            ),
        };
        self.at += len;
        Ok(value)
    }

    /// A string at the position (its opening quote).
    fn string(&mut self) -> Result<String, String> {
        if self.peek() != Some(b'"') {
            return Err(self.error("expected a string"));
        }
        self.at += 1;
        let mut out = String::new();
        loop {
            let rest = &self.text[self.at..];
            let plain = rest
                .find(['"', '\\'])
                .ok_or_else(|| self.error("unterminated string"))?;
            out.push_str(&rest[..plain]);
            self.at += plain;
            if self.peek() == Some(b'"') {
                self.at += 1;
                return Ok(out);
            }
            let escape = self.text.as_bytes().get(self.at + 1).copied();
            self.at += 2;
            let c = match escape {
                Some(b'"') => '"',
                Some(b'\\') => '\\',
                Some(b'/') => '/',
                Some(b'b') => '\u{8}',
                Some(b'f') => '\u{c}',
                Some(b'n') => '\n',
                Some(b'r') => '\r',
                Some(b't') => '\t',
                Some(b'u') => {
                    let high = self.hex4()?;
                    let code = if (0xD800..0xDC00).contains(&high)
                        && self.text[self.at..].starts_with("\\u")
                    {
                        self.at += 2;
                        let low = self.hex4()?;
                        0x10000 + ((high - 0xD800) << 10) + (low.wrapping_sub(0xDC00) & 0x3FF)
                    } else {
                        high
                    };
                    char::from_u32(code).ok_or_else(|| self.error("not a character"))?
                }
                _ => return Err(self.error("bad escape")),
            };
            out.push(c);
        }
    }

    fn hex4(&mut self) -> Result<u32, String> {
        let digits = self
            .text
            .get(self.at..self.at + 4)
            .ok_or_else(|| self.error("short \\u escape"))?;
        let code = u32::from_str_radix(digits, 16).map_err(|_| self.error("bad \\u escape"))?;
        self.at += 4;
        Ok(code)
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
    fn reads_back_what_it_prints_and_compact_text() {
        let v = Json::obj([
            ("name", Json::str("a \"b\"\\c\n\u{1}é→")),
            ("n", Json::Int(-3)),
            ("x", Json::Num(0.1)),
            ("one", Json::Num(1.0)),
            ("tiny", Json::Num(-1e-300)),
            ("ok", Json::Bool(false)),
            ("none", Json::Null),
            ("empty", Json::Obj(vec![])),
            ("list", Json::Arr(vec![Json::Int(1), Json::Num(2.5)])),
            (
                "objs",
                Json::Arr(vec![Json::obj([("k", Json::Arr(vec![]))])]),
            ),
        ]);
        assert_eq!(Json::parse(&v.to_string()), Ok(v.clone()));
        let compact = r#"{"name":"a \"b\"\\c\n\u0001é→","n":-3,"x":0.1,"one":1.0,"tiny":-1e-300,"ok":false,"none":null,"empty":{},"list":[1,2.5],"objs":[{"k":[]}]}"#;
        assert_eq!(Json::parse(compact), Ok(v));
        assert_eq!(
            Json::parse(r#"["\ud83d\ude00", "\/"]"#),
            Ok(Json::Arr(vec![Json::str("😀"), Json::str("/")]))
        );
        for bad in [
            "",
            "[1,",
            "{\"a\" 1}",
            "[1] 2",
            "\"abc",
            "nul",
            "[1e]",
            "\"\\x\"",
        ] {
            assert!(Json::parse(bad).is_err(), "{bad}");
        }
    }

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
