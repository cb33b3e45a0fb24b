//! Control mesh lines: segments 1.5 pixels wide, drawn into the supersampled band
//! (so the box filter anti-aliases them) and depth-tested against the surface.
//!
//! A sample of a line is *visible* when no surface is there or the line is no farther than
//! the surface plus [`DEPTH_BIAS`] of its distance (so that lines lying on the surface, as
//! along boundaries and creases, show); otherwise it is *hidden*, drawn faintly, so that the
//! whole cage stays readable.

use super::camera::Projected;
use super::raster::{sample_span, Band};

/// Relative depth tolerance of the line depth test.
pub(crate) const DEPTH_BIAS: f64 = 0.005;

/// No line at a sample.
pub(crate) const NO_LINE: u8 = 0;
/// A line behind the surface.
pub(crate) const HIDDEN: u8 = 1;
/// A line in front of (or on) the surface.
pub(crate) const VISIBLE: u8 = 2;

/// Half the line width, in samples, for `ss` samples per pixel.
pub(crate) fn half_width(ss: usize) -> f64 {
    0.75 * ss as f64
}

/// Per band of `band_samples` sample rows, the lines (in order) that may touch it.
pub(crate) fn bin_lines(
    lines: &[[Projected; 2]],
    band_samples: usize,
    bands: usize,
    half_width: f64,
) -> Vec<Vec<u32>> {
    let mut bins = vec![Vec::new(); bands];
    for (i, [a, b]) in lines.iter().enumerate() {
        let ys = [
            a.y - half_width,
            a.y + half_width,
            b.y - half_width,
            b.y + half_width,
        ];
        if let Some((y0, y1)) = sample_span(&ys, bands * band_samples) {
            for bin in &mut bins[y0 / band_samples..=(y1 - 1) / band_samples] {
                bin.push(i as u32);
            }
        }
    }
    bins
}

/// Per sample of `band`, [`NO_LINE`], [`HIDDEN`] or [`VISIBLE`] (the most visible of the
/// lines `bin` of `lines` covering it).
pub(crate) fn draw(band: &Band, lines: &[[Projected; 2]], bin: &[u32], ss: usize) -> Vec<u8> {
    let mut cover = vec![NO_LINE; if bin.is_empty() { 0 } else { band.inv_w.len() }];
    let hw = half_width(ss);
    for &i in bin {
        let [a, b] = lines[i as usize];
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let len2 = dx * dx + dy * dy;
        let Some((x0, x1)) = sample_span(&[a.x - hw, a.x + hw, b.x - hw, b.x + hw], band.width)
        else {
            continue;
        };
        let Some((y0, y1)) = sample_span(
            &[a.y - hw, a.y + hw, b.y - hw, b.y + hw],
            band.y0 + band.rows,
        ) else {
            continue;
        };
        for sy in y0.max(band.y0)..y1 {
            let py = sy as f64 + 0.5;
            for sx in x0..x1 {
                let px = sx as f64 + 0.5;
                let t = if len2 > 0.0 {
                    (((px - a.x) * dx + (py - a.y) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (qx, qy) = (a.x + t * dx - px, a.y + t * dy - py);
                if qx * qx + qy * qy > hw * hw {
                    continue;
                }
                let k = (sy - band.y0) * band.width + sx;
                let iw = a.inv_w + t * (b.inv_w - a.inv_w);
                let surface = band.inv_w[k];
                let state = if surface == 0.0 || iw * (1.0 + DEPTH_BIAS) >= surface {
                    VISIBLE
                } else {
                    HIDDEN
                };
                cover[k] = cover[k].max(state);
            }
        }
    }
    cover
}
