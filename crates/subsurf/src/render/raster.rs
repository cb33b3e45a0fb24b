//! The triangle rasteriser: a band of sample rows with a z-buffer that keeps, per sample,
//! the nearest triangle and its perspective-correct barycentric coordinates (shading is
//! deferred, so that it runs once per visible sample).
//!
//! Samples are at the centres of a grid of `supersampling²` per pixel. A sample belongs to
//! a triangle when it is inside or on its edges; the edge functions are evaluated in one
//! canonical direction per edge, so two triangles sharing an edge (with bit-identical end
//! points) see exactly opposite values: no sample falls between them. Depth is `1/w`
//! (affine in screen space, interpolated exactly); ties keep the earlier triangle, so the
//! result does not depend on anything but the triangle order.

use super::camera::Projected;
use super::scene::Frame;

/// No triangle at a sample.
pub(crate) const NONE: u32 = u32::MAX;

/// A band of sample rows.
pub(crate) struct Band {
    /// Samples per row.
    pub width: usize,
    /// First sample row.
    pub y0: usize,
    /// Sample rows.
    pub rows: usize,
    /// Per sample, `1/depth` of the nearest surface (0: none).
    pub inv_w: Vec<f64>,
    /// Per sample, the nearest triangle ([`NONE`] if none).
    pub tri: Vec<u32>,
    /// Per sample, the perspective-correct barycentric coordinates of vertices 1 and 2.
    pub bary: Vec<[f32; 2]>,
}

impl Band {
    /// An empty band.
    pub(super) fn new(width: usize, y0: usize, rows: usize) -> Self {
        Self {
            width,
            y0,
            rows,
            inv_w: vec![0.0; width * rows],
            tri: vec![NONE; width * rows],
            bary: vec![[0.0; 2]; width * rows],
        }
    }

    /// Rasterises triangle `id` with vertices `t` (indices into `screen`).
    pub(super) fn triangle(&mut self, id: u32, screen: &[Option<Projected>], t: &[u32; 3]) {
        let (Some(a), Some(b), Some(c)) = (
            screen[t[0] as usize],
            screen[t[1] as usize],
            screen[t[2] as usize],
        ) else {
            return;
        };
        let area = edge(&a, &b, c.x, c.y);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        let (xs, ys) = ([a.x, b.x, c.x], [a.y, b.y, c.y]);
        let Some((x0, x1)) = sample_span(&xs, self.width) else {
            return;
        };
        let Some((y0, y1)) = sample_span(&ys, self.y0 + self.rows) else {
            return;
        };
        let y0 = y0.max(self.y0);
        let inv_area = 1.0 / area;
        for sy in y0..y1 {
            let py = sy as f64 + 0.5;
            let row = (sy - self.y0) * self.width;
            let Some((x0, x1)) = row_span(&a, &b, &c, area, py, (x0, x1)) else {
                continue;
            };
            for sx in x0..x1 {
                let px = sx as f64 + 0.5;
                let l0 = edge(&b, &c, px, py) * inv_area;
                let l1 = edge(&c, &a, px, py) * inv_area;
                let l2 = edge(&a, &b, px, py) * inv_area;
                if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
                    continue;
                }
                let iw = l0 * a.inv_w + l1 * b.inv_w + l2 * c.inv_w;
                let i = row + sx;
                if iw > self.inv_w[i] {
                    self.inv_w[i] = iw;
                    self.tri[i] = id;
                    self.bary[i] = [(l1 * b.inv_w / iw) as f32, (l2 * c.inv_w / iw) as f32];
                }
            }
        }
    }
}

/// The samples of row `py` within `x0..x1` that may lie in the triangle `a b c` (of twice
/// the signed area `area`): where each edge's function, linear along the row, has the
/// triangle's sign, computed in real arithmetic and widened by a margin far beyond its
/// rounding (the exact test of each sample decides). A thin slanted triangle, like the
/// wedges around the centre of an `n`-gon of thousands of vertices, covers a few samples
/// of each row of its bounding box: testing the whole box cost `O(n)` rows of `O(width)`
/// samples per triangle.
fn row_span(
    a: &Projected,
    b: &Projected,
    c: &Projected,
    area: f64,
    py: f64,
    (x0, x1): (usize, usize),
) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = (x0 as f64, x1 as f64);
    for (p, q) in [(b, c), (c, a), (a, b)] {
        // The edge function is (q.x − p.x)(py − p.y) − (q.y − p.y)(px − p.x): zero at
        // px = p.x + t, increasing with px when −(q.y − p.y) has the sign of the area.
        let dy = q.y - p.y;
        let t = (q.x - p.x) * (py - p.y) / dy;
        let root = p.x + t;
        if dy == 0.0 || !root.is_finite() {
            continue;
        }
        let margin = 2.0 + 1e-9 * (p.x.abs() + t.abs());
        // Sample `k` is at `k + 0.5`.
        if (-dy > 0.0) == (area > 0.0) {
            lo = lo.max((root - margin - 0.5).floor());
        } else {
            hi = hi.min((root + margin - 0.5).ceil() + 1.0);
        }
    }
    let (lo, hi) = (lo.max(x0 as f64), hi.min(x1 as f64));
    (lo < hi).then_some((lo as usize, hi as usize))
}

/// Twice the signed area of `a b p` (positive when counter-clockwise in a y-up frame),
/// evaluated from the lexicographically smaller end point, so that `edge(b, a, p)` is
/// exactly `−edge(a, b, p)`.
#[inline]
fn edge(a: &Projected, b: &Projected, px: f64, py: f64) -> f64 {
    if (a.x, a.y) <= (b.x, b.y) {
        (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)
    } else {
        -((a.x - b.x) * (py - b.y) - (a.y - b.y) * (px - b.x))
    }
}

/// The samples `k` (centres `k + 0.5`) within `[min, max]` of `v`, clipped to `0..limit`,
/// as a half-open range; `None` when empty.
pub(crate) fn sample_span(v: &[f64], limit: usize) -> Option<(usize, usize)> {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let first = (lo - 0.5).ceil().max(0.0);
    let last = (hi - 0.5).floor().min(limit as f64 - 1.0);
    (first <= last).then(|| (first as usize, last as usize + 1))
}

/// Per band of `band_samples` sample rows, the triangles (in order) that may cover it.
pub(crate) fn bin_triangles(
    frame: &Frame,
    triangles: &[[u32; 3]],
    band_samples: usize,
    bands: usize,
) -> Vec<Vec<u32>> {
    let mut bins = vec![Vec::new(); bands];
    let limit = bands * band_samples;
    for (i, t) in triangles.iter().enumerate() {
        let ys: Option<Vec<f64>> = t
            .iter()
            .map(|&v| frame.screen[v as usize].map(|p| p.y))
            .collect();
        let Some(ys) = ys else {
            continue;
        };
        if let Some((y0, y1)) = sample_span(&ys, limit) {
            for bin in &mut bins[y0 / band_samples..=(y1 - 1) / band_samples] {
                bin.push(i as u32);
            }
        }
    }
    bins
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Option<Projected> {
        Some(Projected { x, y, inv_w: 1.0 })
    }

    /// Each row's span holds every sample the exact test accepts (so the picture is the
    /// one of testing the whole bounding box), on triangles of every shape, orientation
    /// and size, degenerate rows and far-off vertices included; and a thin slanted
    /// triangle's spans hold a few samples per row, not its bounding box's width.
    #[test]
    fn row_spans_hold_every_covered_sample_and_little_else() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = |scale: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * scale
        };
        let (w, h) = (64usize, 64usize);
        for case in 0..400 {
            let scale = [70.0, 5.0, 1e4, 64.0][case % 4];
            let mut v: Vec<Projected> = (0..3)
                .map(|_| Projected {
                    x: rnd(scale) - 0.1 * scale,
                    y: rnd(scale) - 0.1 * scale,
                    inv_w: 1.0,
                })
                .collect();
            if case % 5 == 0 {
                v[1].y = v[0].y; // a horizontal edge
            }
            let (a, b, c) = (v[0], v[1], v[2]);
            let area = edge(&a, &b, c.x, c.y);
            if area == 0.0 {
                continue;
            }
            for sy in 0..h {
                let py = sy as f64 + 0.5;
                let span = row_span(&a, &b, &c, area, py, (0, w));
                for sx in 0..w {
                    let px = sx as f64 + 0.5;
                    let inside = [(b, c), (c, a), (a, b)]
                        .iter()
                        .all(|(p, q)| edge(p, q, px, py) / area >= 0.0);
                    if inside {
                        let held = span.is_some_and(|(x0, x1)| (x0..x1).contains(&sx));
                        assert!(held, "case {case}: sample {sx},{sy} outside {span:?}");
                    }
                }
            }
        }
        // A sliver from one corner of a 1000-sample square to the other, one sample wide.
        let (a, b, c) = (
            Projected {
                x: 0.0,
                y: 0.0,
                inv_w: 1.0,
            },
            Projected {
                x: 1000.0,
                y: 999.0,
                inv_w: 1.0,
            },
            Projected {
                x: 1000.0,
                y: 1000.0,
                inv_w: 1.0,
            },
        );
        let area = edge(&a, &b, c.x, c.y);
        let tested: usize = (0..1000)
            .filter_map(|sy| row_span(&a, &b, &c, area, sy as f64 + 0.5, (0, 1000)))
            .map(|(x0, x1)| x1 - x0)
            .sum();
        assert!(tested < 8 * 1000, "{tested} samples tested");
    }

    /// Two triangles sharing a diagonal at odd angles cover every sample of their square
    /// exactly once or twice, never zero times.
    #[test]
    fn shared_edges_leave_no_gaps() {
        let screen = [p(0.3, 0.1), p(30.7, 2.3), p(29.1, 31.9), p(1.7, 28.4)];
        let mut band = Band::new(32, 0, 32);
        band.triangle(0, &screen, &[0, 1, 2]);
        band.triangle(1, &screen, &[0, 2, 3]);
        // Every sample strictly inside the quad is covered.
        let mut covered = 0;
        for y in 4..26 {
            for x in 4..26 {
                assert_ne!(band.tri[y * 32 + x], NONE, "gap at {x},{y}");
                covered += 1;
            }
        }
        assert!(covered > 0);
    }

    #[test]
    fn nearer_wins_and_barycentrics_sum_below_one() {
        let mut screen = vec![p(0.0, 0.0), p(16.0, 0.0), p(0.0, 16.0)];
        screen.extend([p(0.0, 0.0), p(16.0, 0.0), p(0.0, 16.0)].map(|q| {
            q.map(|mut q| {
                q.inv_w = 2.0;
                q
            })
        }));
        let mut band = Band::new(16, 0, 16);
        band.triangle(0, &screen, &[0, 1, 2]);
        band.triangle(1, &screen, &[3, 5, 4]); // clockwise: drawn as well
        assert_eq!(band.tri[3 * 16 + 3], 1);
        let [b1, b2] = band.bary[3 * 16 + 3];
        assert!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0);
        assert_eq!(band.tri[15 * 16 + 15], NONE);
    }
}
