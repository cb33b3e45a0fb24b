//! Shortest round-trip decimals for text output (OBJ coordinates, `subsurf limit` rows).

/// Appends `x` as the shortest decimal that reads back as the same `f64`, never in
/// exponent form, as Rust's `Display` writes it: `1`, `-0`, `0.1`, `0.0000001`,
/// `123400000000000000000`; `NaN`, `inf` and `-inf` as `Display` does.
///
/// The digits are those of the [`zmij`] crate (a port of Zverovich's Żmij algorithm: the
/// shortest correctly rounded digits), several times faster than the standard library's
/// formatting, which was most of the time of writing a refined mesh. zmij writes `1.0`,
/// `1e-7` and `1.234e+20`; this places the decimal point as `Display` does. Where two
/// shortest decimals are equally near `x` (an exact tie, about one number in 1 500 of
/// random bit patterns and scaled integers, a handful of the 57 M coordinates of a scan
/// refined to 4.8 M quads), zmij takes the one with the even last digit and `Display` the
/// larger, as `19.046524047851562` against `…563` for `19.0465240478515625`. Both read
/// back as `x`.
///
/// ```
/// let mut text = Vec::new();
/// for x in [1.0, 0.1, -1e-7, 1.5e20] {
///     subsurf::io::push_decimal(&mut text, x);
///     text.push(b' ');
/// }
/// assert_eq!(text, b"1 0.1 -0.0000001 150000000000000000000 ");
/// assert_eq!("-0.0000001".parse::<f64>(), Ok(-1e-7));
/// ```
pub fn push_decimal(buf: &mut Vec<u8>, x: f64) {
    let mut digits = zmij::Buffer::new();
    let s = digits.format(x).as_bytes();
    let Some(e) = s.iter().position(|&c| c == b'e') else {
        // `I.F`: as `Display` writes it, but for the `.0` of whole numbers.
        buf.extend_from_slice(s.strip_suffix(b".0").unwrap_or(s));
        return;
    };
    // `[-]D[.F]e±X`: one digit before the point, none of the digits zero at the ends but
    // for a lone `0`.
    let (mantissa, exponent) = (&s[..e], &s[e + 1..]);
    let (negative, mantissa) = match mantissa.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, mantissa),
    };
    let (sign, magnitude) = match exponent.split_first() {
        Some((b'-', rest)) => (-1, rest),
        Some((b'+', rest)) => (1, rest),
        _ => (1, exponent),
    };
    let exponent = sign
        * magnitude
            .iter()
            .fold(0i32, |a, &d| 10 * a + i32::from(d - b'0'));
    let mut d = [0u8; 24];
    let mut n = 0;
    for &c in mantissa.iter().filter(|&&c| c != b'.') {
        d[n] = c;
        n += 1;
    }
    let d = &d[..n];
    if negative {
        buf.push(b'-');
    }
    // The point goes after digit `1 + exponent`.
    let point = 1 + exponent;
    if point <= 0 {
        buf.extend_from_slice(b"0.");
        buf.resize(buf.len() + (-point) as usize, b'0');
        buf.extend_from_slice(d);
    } else if point as usize >= d.len() {
        buf.extend_from_slice(d);
        buf.resize(buf.len() + point as usize - d.len(), b'0');
    } else {
        let (whole, fraction) = d.split_at(point as usize);
        buf.extend_from_slice(whole);
        buf.push(b'.');
        buf.extend_from_slice(fraction);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shortest(x: f64) -> String {
        let mut buf = Vec::new();
        push_decimal(&mut buf, x);
        String::from_utf8(buf).unwrap()
    }

    /// Coordinates are written as `Display` writes them, never in exponent form, and read
    /// back bit for bit; where the text differs from `Display`'s (an exact tie between two
    /// shortest decimals), only in the last digit, by one.
    #[test]
    fn shortest_decimals_read_back_bit_for_bit() {
        for (x, text) in [
            (1.0, "1"),
            (-0.0, "-0"),
            (0.0, "0"),
            (0.1, "0.1"),
            (-2.5, "-2.5"),
            (1e-7, "0.0000001"),
            (-1.5e-5, "-0.000015"),
            (1e15, "1000000000000000"),
            (1.234e20, "123400000000000000000"),
            // Exact ties: 133182662272291.125 and 19.0465240478515625.
            (133_182_662_272_291.0 + 0.125, "133182662272291.12"),
            (1_248_233.0 / 65_536.0, "19.046524047851562"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(shortest(x), text, "{x:e}");
        }
        assert_eq!(shortest(f64::MAX), format!("{}", f64::MAX));
        assert_eq!(shortest(-5e-324), format!("{}", -5e-324));
        // Random bit patterns, and random integers scaled by powers of two.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let (mut ties, mut tried) = (0, 0);
        for i in 0..200_000u64 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = if i % 2 == 0 {
                f64::from_bits(state)
            } else {
                (state >> 11) as f64 * 2f64.powi((state % 160) as i32 - 100)
            };
            if !x.is_finite() {
                continue;
            }
            tried += 1;
            let (ours, std) = (shortest(x), format!("{x}"));
            assert!(!ours.contains('e'), "{ours}");
            assert_eq!(
                ours.parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{ours}"
            );
            if ours != std {
                ties += 1;
                let (a, b) = (ours.as_bytes(), std.as_bytes());
                let n = a.len();
                assert!(n == b.len() && a[..n - 1] == b[..n - 1], "{ours} {std}");
                assert_eq!(a[n - 1] + 1, b[n - 1], "{ours} {std}");
            }
        }
        // Ties are rare (about one number in 1 500 here).
        assert!(ties * 500 < tried, "{ties} of {tried}");
    }
}
