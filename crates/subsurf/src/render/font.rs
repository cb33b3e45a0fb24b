//! A tiny 5 × 7 bitmap font: digits, `- + . e` and the few letters of the colour bar's
//! titles, drawn at an integer scale.

use image::{Rgb, RgbImage};

/// Glyph width and height in font pixels; glyphs advance by `WIDTH + 1`.
pub(crate) const WIDTH: usize = 5;
/// See [`WIDTH`].
pub(crate) const HEIGHT: usize = 7;

/// Rows of a glyph, top first, bit 4 the leftmost column; unknown characters are blank.
fn glyph(c: char) -> [u8; HEIGHT] {
    match c {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '-' => [0x00, 0x00, 0x00, 0x0E, 0x00, 0x00, 0x00],
        '+' => [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C],
        'e' => [0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E],
        'a' => [0x00, 0x00, 0x0E, 0x01, 0x0F, 0x11, 0x0F],
        'g' => [0x00, 0x0F, 0x11, 0x0F, 0x01, 0x11, 0x0E],
        'm' => [0x00, 0x00, 0x1A, 0x15, 0x15, 0x11, 0x11],
        'n' => [0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11],
        's' => [0x00, 0x00, 0x0E, 0x10, 0x0E, 0x01, 0x1E],
        'u' => [0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0D],
        'x' => [0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11],
        _ => [0; HEIGHT],
    }
}

/// Width in pixels of `text` at `scale`.
pub(crate) fn text_width(text: &str, scale: usize) -> usize {
    let n = text.chars().count();
    if n == 0 {
        0
    } else {
        (n * (WIDTH + 1) - 1) * scale
    }
}

/// Draws `text` with its top-left corner at `(x, y)` (pixels outside the image are
/// skipped).
pub(crate) fn draw_text(
    img: &mut RgbImage,
    x: i64,
    y: i64,
    text: &str,
    scale: usize,
    colour: [u8; 3],
) {
    let s = scale as i64;
    for (i, c) in text.chars().enumerate() {
        let gx = x + i as i64 * (WIDTH as i64 + 1) * s;
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..WIDTH {
                if bits & (1 << (WIDTH - 1 - col)) == 0 {
                    continue;
                }
                for dy in 0..s {
                    for dx in 0..s {
                        let px = gx + col as i64 * s + dx;
                        let py = y + row as i64 * s + dy;
                        if px >= 0
                            && py >= 0
                            && (px as u64) < u64::from(img.width())
                            && (py as u64) < u64::from(img.height())
                        {
                            img.put_pixel(px as u32, py as u32, Rgb(colour));
                        }
                    }
                }
            }
        }
    }
}

/// A short label for `x`: three significant digits, fixed-point for magnitudes in
/// `[0.01, 10000)`, else scientific (`1.5e-5`); trailing zeros dropped.
pub(crate) fn label(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return "0".to_owned();
    }
    let a = x.abs();
    if (0.01..10000.0).contains(&a) {
        let decimals = (2 - a.log10().floor() as i64).max(0) as usize;
        trim(&format!("{x:.decimals$}"))
    } else {
        let s = format!("{x:.2e}");
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m)),
            None => s,
        }
    }
}

fn trim(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels() {
        assert_eq!(label(0.0), "0");
        assert_eq!(label(1.0), "1");
        assert_eq!(label(-0.5), "-0.5");
        assert_eq!(label(2.345), "2.35");
        assert_eq!(label(123.4), "123");
        assert_eq!(label(0.01234), "0.0123");
        assert_eq!(label(1.5e-5), "1.5e-5");
        assert_eq!(label(-2.0e6), "-2e6");
        // Every character of a label has a glyph.
        for l in ["-1.5e-5", "0.0123", "2e6", "gauss", "mean", "max"] {
            assert!(l.chars().all(|c| glyph(c) != [0; HEIGHT]), "{l}");
        }
    }
}
