//! A compact JSON writer (RFC 8259) for the library's documents: NURBS curves and surfaces
//! ([`nurbs`](crate::nurbs)), the Bézier patches of a G2 surface
//! ([`g2cap::patches_json`](crate::g2cap::patches_json)) and the regularity report
//! ([`RegularityReport::to_json`](crate::regularity::RegularityReport::to_json)).
//!
//! The text is what `serde_json::to_string` writes for the same document, byte for byte:
//! no whitespace; numbers as the shortest decimal that reads back as the same `f64`, by the
//! [`zmij`] crate (`1.0`, `0.1`, `1e-7`, `1.5e+20`), non-finite ones as `null`; strings with
//! `"`, `\` and the control characters escaped (`\n`, `\u001f`, …). So documents keep their
//! form without the `serde` dependency, and reading one back with the crate's exact reader
//! (`nurbs/json_reader.rs`) gives every `f64` bit for bit.
//!
//! A document is written by implementing [`ToJson`]: numbers, strings, `bool`, slices,
//! arrays and `Option` (`null`) already do, and a struct writes its fields in order with
//! [`object`].

use std::fmt::Write;

/// A value that writes itself as JSON text.
pub(crate) trait ToJson {
    /// Appends the value's JSON text to `out`.
    fn write_json(&self, out: &mut String);
}

/// The JSON text of `value`.
pub(crate) fn to_string<T: ToJson + ?Sized>(value: &T) -> String {
    let mut out = String::new();
    value.write_json(&mut out);
    out
}

/// Appends an object whose members `members` writes with [`Object::field`], in order.
pub(crate) fn object(out: &mut String, members: impl FnOnce(&mut Object<'_>)) {
    out.push('{');
    members(&mut Object { out, first: true });
    out.push('}');
}

/// The members of an object being written ([`object`]).
pub(crate) struct Object<'a> {
    out: &'a mut String,
    first: bool,
}

impl Object<'_> {
    /// Appends the member `key: value`.
    pub(crate) fn field<T: ToJson + ?Sized>(&mut self, key: &str, value: &T) {
        if !self.first {
            self.out.push(',');
        }
        self.first = false;
        key.write_json(self.out);
        self.out.push(':');
        value.write_json(self.out);
    }

    /// Appends the member `key: value` if `value` is `Some`, nothing if it is `None`.
    pub(crate) fn field_if_some<T: ToJson>(&mut self, key: &str, value: &Option<T>) {
        if let Some(value) = value {
            self.field(key, value);
        }
    }
}

impl ToJson for f64 {
    fn write_json(&self, out: &mut String) {
        if self.is_finite() {
            out.push_str(zmij::Buffer::new().format_finite(*self));
        } else {
            out.push_str("null");
        }
    }
}

macro_rules! integer_to_json {
    ($($t:ty),*) => {$(
        impl ToJson for $t {
            fn write_json(&self, out: &mut String) {
                // Writing to a `String` cannot fail.
                let _ = write!(out, "{self}");
            }
        }
    )*};
}
integer_to_json!(u8, u32, u64, usize, i64);

impl ToJson for bool {
    fn write_json(&self, out: &mut String) {
        out.push_str(if *self { "true" } else { "false" });
    }
}

impl ToJson for str {
    fn write_json(&self, out: &mut String) {
        out.push('"');
        for c in self.chars() {
            match c {
                '"' => out.push_str("\\\""),
                '\\' => out.push_str("\\\\"),
                '\n' => out.push_str("\\n"),
                '\r' => out.push_str("\\r"),
                '\t' => out.push_str("\\t"),
                '\u{8}' => out.push_str("\\b"),
                '\u{c}' => out.push_str("\\f"),
                c if u32::from(c) < 0x20 => {
                    let _ = write!(out, "\\u{:04x}", u32::from(c));
                }
                c => out.push(c),
            }
        }
        out.push('"');
    }
}

impl ToJson for String {
    fn write_json(&self, out: &mut String) {
        self.as_str().write_json(out);
    }
}

impl<T: ToJson + ?Sized> ToJson for &T {
    fn write_json(&self, out: &mut String) {
        (**self).write_json(out);
    }
}

impl<T: ToJson> ToJson for Option<T> {
    fn write_json(&self, out: &mut String) {
        match self {
            Some(value) => value.write_json(out),
            None => out.push_str("null"),
        }
    }
}

impl<T: ToJson> ToJson for [T] {
    fn write_json(&self, out: &mut String) {
        out.push('[');
        for (i, item) in self.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            item.write_json(out);
        }
        out.push(']');
    }
}

impl<T: ToJson, const N: usize> ToJson for [T; N] {
    fn write_json(&self, out: &mut String) {
        self.as_slice().write_json(out);
    }
}

impl<T: ToJson> ToJson for Vec<T> {
    fn write_json(&self, out: &mut String) {
        self.as_slice().write_json(out);
    }
}

#[cfg(test)]
mod tests {
    use super::{object, to_string, ToJson};

    struct Doc {
        name: &'static str,
        x: Vec<[f64; 2]>,
        w: Option<Vec<f64>>,
        corner: Option<u8>,
        flags: [bool; 2],
    }

    impl ToJson for Doc {
        fn write_json(&self, out: &mut String) {
            object(out, |o| {
                o.field("name", self.name);
                o.field("x", &self.x);
                o.field_if_some("w", &self.w);
                o.field("corner", &self.corner);
                o.field("flags", &self.flags);
            });
        }
    }

    #[test]
    fn writes_compact_json_with_shortest_round_trip_numbers() {
        let doc = Doc {
            name: "a\"b\\c\nd\u{1}\u{8}é",
            x: vec![
                [1.0, 0.1],
                [-1e-7, 1.5e20],
                [f64::NAN, f64::INFINITY],
                [-0.0, 3.0],
            ],
            w: None,
            corner: None,
            flags: [true, false],
        };
        assert_eq!(
            to_string(&doc),
            r#"{"name":"a\"b\\c\nd\u0001\bé","x":[[1.0,0.1],[-1e-7,1.5e+20],[null,null],[-0.0,3.0]],"corner":null,"flags":[true,false]}"#
        );
        let doc = Doc {
            w: Some(vec![0.5]),
            corner: Some(3),
            ..doc
        };
        assert!(to_string(&doc).contains(r#""w":[0.5],"corner":3,"#));
        assert_eq!(to_string(&Vec::<u32>::new()), "[]");
        assert_eq!(to_string(&[-1_i64, i64::MIN]), "[-1,-9223372036854775808]");
        assert_eq!(to_string(&u64::MAX), "18446744073709551615");
    }

    #[test]
    fn numbers_and_strings_are_written_as_serde_json_writes_them() {
        let mut x = 0.123_456_789_f64;
        for i in 0..2000 {
            x = (x * 7919.0 + f64::from(i)).fract() * 10f64.powi(i % 61 - 30);
            let y = if i % 3 == 0 { -x } else { x };
            assert_eq!(to_string(&y), serde_json::to_string(&y).unwrap(), "{y:e}");
        }
        let s: String = (0u8..128).map(char::from).chain("é∑😀".chars()).collect();
        assert_eq!(to_string(&s), serde_json::to_string(&s).unwrap());
    }
}
