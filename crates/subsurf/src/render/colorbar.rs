//! The colour bar of curvature pictures: a vertical strip on the right with the colour map,
//! the maximum at the top, the middle value and the minimum at the bottom, and the
//! curvature's name above it.

use super::curvature::{self, CurvatureKind};
use super::font;
use image::{Rgb, RgbImage};

/// Text and frame colour.
const INK: [u8; 3] = [40, 40, 48];

/// Where the colour bar goes.
pub(crate) struct ColorBar {
    kind: CurvatureKind,
    /// The colour range.
    pub range: (f64, f64),
    /// Width of the strip it takes on the right of the picture, pixels.
    pub strip_width: usize,
    scale: usize,
    labels: [String; 3],
    x0: usize,
    y0: usize,
    bar_width: usize,
    bar_height: usize,
}

impl ColorBar {
    /// Lays the bar out in a `width × height` picture.
    pub(super) fn layout(
        kind: CurvatureKind,
        range: (f64, f64),
        width: usize,
        height: usize,
    ) -> Self {
        let scale = (height / 240).max(1);
        let labels = [range.1, 0.5 * (range.0 + range.1), range.0].map(font::label);
        let text = labels
            .iter()
            .map(|l| font::text_width(l, scale))
            .chain([font::text_width(kind.name(), scale)])
            .max()
            .unwrap_or(0);
        let margin = 6 * scale;
        let bar_width = 10 * scale;
        let gap = 4 * scale;
        let strip = (margin + bar_width + gap + text + margin).min(width / 2);
        let bar_height = (height * 3 / 5).max(2);
        Self {
            kind,
            range,
            strip_width: strip,
            scale,
            labels,
            x0: width - strip + margin,
            y0: (height - bar_height) / 2,
            bar_width,
            bar_height,
        }
    }

    /// Draws the bar into `img`.
    pub(super) fn draw(&self, img: &mut RgbImage) {
        let (w, h) = (img.width() as usize, img.height() as usize);
        let mut put = |x: usize, y: usize, c: [u8; 3]| {
            if x < w && y < h {
                img.put_pixel(x as u32, y as u32, Rgb(c));
            }
        };
        for dy in 0..self.bar_height {
            let t = 1.0 - dy as f64 / (self.bar_height - 1) as f64;
            let value = self.range.0 + t * (self.range.1 - self.range.0);
            let c = curvature::colour(self.kind, self.range, value)
                .map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8);
            for dx in 0..self.bar_width {
                put(self.x0 + dx, self.y0 + dy, c);
            }
        }
        // A one-pixel frame around the bar.
        let (x1, y1) = (self.x0 + self.bar_width, self.y0 + self.bar_height);
        for x in self.x0 - 1..=x1 {
            put(x, self.y0 - 1, INK);
            put(x, y1, INK);
        }
        for y in self.y0 - 1..=y1 {
            put(self.x0 - 1, y, INK);
            put(x1, y, INK);
        }
        let s = self.scale;
        let tx = (x1 + 4 * s) as i64;
        let half = (font::HEIGHT * s / 2) as i64;
        let ys = [
            self.y0 as i64,
            (self.y0 + self.bar_height / 2) as i64,
            y1 as i64,
        ];
        for (label, y) in self.labels.iter().zip(ys) {
            font::draw_text(img, tx, y - half, label, s, INK);
        }
        let title_y = self.y0 as i64 - half - ((font::HEIGHT + 4) * s) as i64;
        font::draw_text(img, self.x0 as i64, title_y, self.kind.name(), s, INK);
    }
}
