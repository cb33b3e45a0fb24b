//! Shading: Lambert diffuse and Blinn-Phong highlights from a key and a fill light fixed
//! to the camera, two-sided (a back face is lit as if seen from its front, so it is never
//! black), computed per sample and box-filtered down to pixels.
//!
//! Lighting is computed in linear light and encoded with gamma 2.2; colours given in sRGB
//! (base colours, colour maps) are decoded first.

use super::curvature::{self, CurvatureKind};
use super::lines::{HIDDEN, VISIBLE};
use super::raster::{Band, NONE};
use super::scene::{Frame, Scene};
use super::{zebra, Paint, Render, Shading};
use crate::geom::{self, V3};
use rayon::prelude::*;

/// A light: unit direction toward it (view space) and intensity.
struct Light {
    dir: V3,
    intensity: f64,
}

/// Key light from the upper left, in front; fill from the right, slightly below.
fn lights() -> [Light; 2] {
    [
        Light {
            dir: geom::normalize_or_zero([-0.5, 0.65, 0.55]),
            intensity: 0.95,
        },
        Light {
            dir: geom::normalize_or_zero([0.7, -0.2, 0.45]),
            intensity: 0.2,
        },
    ]
}

const AMBIENT: f64 = 0.05;
const SPECULAR: f64 = 0.22;
const SHININESS: f64 = 48.0;

/// Clay-like base colour (sRGB).
const CLAY: [f64; 3] = [0.78, 0.76, 0.72];
/// The colours of [`Paint::Faces`] (sRGB), in the order the greedy colouring uses them.
const FACE_COLOURS: [[f64; 3]; super::scene::FACE_PALETTE] = [
    [0.55, 0.68, 0.86],
    [0.93, 0.80, 0.55],
    [0.62, 0.82, 0.62],
    [0.88, 0.60, 0.60],
    [0.75, 0.65, 0.88],
    [0.60, 0.84, 0.84],
];
/// The squares of [`Paint::Checker`] (sRGB), inside the unit square of texture
/// coordinates and (tinted red) outside it.
const CHECKER_LIGHT: [f64; 3] = [0.92, 0.90, 0.84];
const CHECKER_DARK: [f64; 3] = [0.22, 0.30, 0.42];
const CHECKER_OUT_LIGHT: [f64; 3] = [0.95, 0.72, 0.70];
const CHECKER_OUT_DARK: [f64; 3] = [0.55, 0.18, 0.18];
/// Control mesh line colour (sRGB) and opacity when visible or hidden.
const LINE: [f64; 3] = [0.08, 0.1, 0.16];
const LINE_VISIBLE: f64 = 1.0;
const LINE_HIDDEN: f64 = 0.25;

fn to_linear(c: [f64; 3]) -> [f64; 3] {
    c.map(|x| x.max(0.0).powf(2.2))
}

fn to_srgb(c: [f64; 3]) -> [f64; 3] {
    c.map(|x| x.clamp(0.0, 1.0).powf(1.0 / 2.2))
}

/// Entries of the curvature colour table.
const LUT_SIZE: usize = 1024;

/// Everything per triangle and per scene that shading needs.
pub(crate) struct Shader<'a> {
    scene: &'a Scene,
    frame: &'a Frame,
    paint: Paint,
    shading: Shading,
    /// The curvature range and its colours (linear), evenly spaced over it.
    range: (f64, f64),
    lut: Vec<[f64; 3]>,
    background: [u8; 3],
    background_linear: [f64; 3],
    albedo: [f64; 3],
    face_albedo: Vec<[f64; 3]>,
    line: [f64; 3],
    /// Per triangle, its view-space geometric normal (from its vertices' winding).
    geometric: Vec<V3>,
    lights: [Light; 2],
}

impl<'a> Shader<'a> {
    /// Prepares shading of `scene` as seen in `frame`; `range` is the curvature colour
    /// range (with [`Paint::Curvature`]).
    pub(super) fn new(
        opts: &Render,
        scene: &'a Scene,
        frame: &'a Frame,
        range: Option<(f64, f64)>,
    ) -> Self {
        let geometric = scene
            .triangles
            .par_iter()
            .map(|t| {
                let p = t.map(|v| frame.view_pos[v as usize]);
                geom::normalize_or_zero(geom::cross(
                    &geom::sub(&p[1], &p[0]),
                    &geom::sub(&p[2], &p[0]),
                ))
            })
            .collect();
        let range = range.unwrap_or((-1.0, 1.0));
        let lut = match opts.paint {
            Paint::Curvature(kind) => (0..LUT_SIZE)
                .map(|i| {
                    let t = i as f64 / (LUT_SIZE - 1) as f64;
                    to_linear(curvature::colour(
                        kind,
                        range,
                        range.0 + t * (range.1 - range.0),
                    ))
                })
                .collect(),
            _ => Vec::new(),
        };
        Self {
            scene,
            frame,
            paint: opts.paint,
            shading: opts.shading,
            range,
            lut,
            background: opts.background,
            background_linear: to_linear(opts.background.map(|c| f64::from(c) / 255.0)),
            albedo: to_linear(CLAY),
            face_albedo: FACE_COLOURS.iter().map(|&c| to_linear(c)).collect(),
            line: to_linear(LINE),
            geometric,
            lights: lights(),
        }
    }

    /// The pixels of `band` (`rows` output rows of `width` pixels, RGB bytes), from its
    /// samples and line coverage: samples are averaged in linear light.
    pub(super) fn resolve(
        &self,
        band: &Band,
        cover: &[u8],
        ss: usize,
        width: usize,
        rows: usize,
    ) -> Vec<u8> {
        let mut out = Vec::with_capacity(width * rows * 3);
        let norm = 1.0 / (ss * ss) as f64;
        for y in 0..rows {
            for x in 0..width {
                let mut acc = [0.0; 3];
                let mut empty = true;
                for sy in 0..ss {
                    let row = (y * ss + sy) * band.width;
                    for sx in 0..ss {
                        let k = row + x * ss + sx;
                        let alpha = match cover.get(k) {
                            Some(&VISIBLE) => LINE_VISIBLE,
                            Some(&HIDDEN) => LINE_HIDDEN,
                            _ => 0.0,
                        };
                        let mut c = match band.tri[k] {
                            NONE => self.background_linear,
                            _ => {
                                empty = false;
                                self.sample(band, k)
                            }
                        };
                        if alpha > 0.0 {
                            empty = false;
                            c = [0, 1, 2].map(|i| c[i] + (self.line[i] - c[i]) * alpha);
                        }
                        (0..3).for_each(|i| acc[i] += c[i]);
                    }
                }
                if empty {
                    out.extend(self.background);
                } else {
                    let c = to_srgb(acc.map(|v| v * norm));
                    out.extend(c.map(|v| (v * 255.0).round().clamp(0.0, 255.0) as u8));
                }
            }
        }
        out
    }

    /// The linear colour of covered sample `k`.
    fn sample(&self, band: &Band, k: usize) -> [f64; 3] {
        let t = band.tri[k];
        let tri = &self.scene.triangles[t as usize];
        let [b1, b2] = band.bary[k].map(f64::from);
        let w = [1.0 - b1 - b2, b1, b2];
        let mix = |attr: &[V3]| -> V3 {
            let mut acc = [0.0; 3];
            for (i, &v) in tri.iter().enumerate() {
                (0..3).for_each(|c| acc[c] += w[i] * attr[v as usize][c]);
            }
            acc
        };
        let pos = mix(&self.frame.view_pos);
        let to_eye = geom::normalize_or_zero(pos.map(|x| -x));
        let g = self.geometric[t as usize];
        let mut n = match self.shading {
            Shading::Smooth => geom::normalize_or_zero(mix(&self.frame.view_normal)),
            Shading::Flat => self.frame.view_flat[t as usize],
        };
        if n == [0.0; 3] {
            n = g;
        }
        // Two-sided: orient the normal like the triangle's winding, then toward the eye
        // when the triangle is seen from behind.
        if geom::dot(&n, &g) < 0.0 {
            n = n.map(|x| -x);
        }
        if geom::dot(&g, &to_eye) < 0.0 {
            n = n.map(|x| -x);
        }
        match self.paint {
            Paint::Plain => self.lit(self.albedo, &n, &to_eye),
            Paint::Faces => {
                let f = self.scene.face[t as usize] as usize;
                let c = self.scene.face_colour.get(f).map_or(0, |&c| c as usize);
                self.lit(self.face_albedo[c % self.face_albedo.len()], &n, &to_eye)
            }
            Paint::Zebra => {
                let d = to_eye.map(|x| -x);
                let s = zebra::stripe(&d, &n);
                let albedo = 0.002 + 0.9 * s;
                let key = geom::dot(&n, &self.lights[0].dir).max(0.0);
                [albedo * (0.75 + 0.25 * key); 3]
            }
            Paint::Checker { squares } => {
                let uv = match &self.scene.uv {
                    Some(uv) => [0, 1].map(|c| {
                        (tri.iter().zip(&w))
                            .map(|(&i, &wi)| wi * uv[i as usize][c])
                            .sum()
                    }),
                    None => [f64::NAN; 2],
                };
                self.lit(self.checker(uv, squares), &n, &to_eye)
            }
            Paint::Curvature(_) => {
                let value = match &self.scene.values {
                    Some(v) => tri.iter().zip(&w).map(|(&i, &wi)| wi * v[i as usize]).sum(),
                    None => f64::NAN,
                };
                let albedo = if value.is_nan() {
                    to_linear(curvature::colour(CurvatureKind::Gauss, self.range, value))
                } else {
                    let t = (value - self.range.0) / (self.range.1 - self.range.0);
                    let i = (t.clamp(0.0, 1.0) * (LUT_SIZE - 1) as f64).round() as usize;
                    self.lut[i.min(LUT_SIZE - 1)]
                };
                // Softly lit, so that the shape still reads but the colours stay true.
                let key = geom::dot(&n, &self.lights[0].dir).max(0.0);
                let fill = geom::dot(&n, &self.lights[1].dir).max(0.0);
                let light = 0.45 + 0.45 * key + 0.12 * fill;
                albedo.map(|a| a * light)
            }
        }
    }

    /// The linear albedo of [`Paint::Checker`] at texture coordinate `uv`: light and dark
    /// squares, tinted red outside the unit square (and grey where `uv` is unknown).
    fn checker(&self, [s, t]: [f64; 2], squares: u32) -> [f64; 3] {
        if !(s.is_finite() && t.is_finite()) {
            return self.albedo;
        }
        let n = f64::from(squares);
        let odd = ((s * n).floor() + (t * n).floor()).rem_euclid(2.0) == 1.0;
        let inside = (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t);
        let colour = match (inside, odd) {
            (true, false) => CHECKER_LIGHT,
            (true, true) => CHECKER_DARK,
            (false, false) => CHECKER_OUT_LIGHT,
            (false, true) => CHECKER_OUT_DARK,
        };
        to_linear(colour)
    }

    /// Lambert + Blinn-Phong of `albedo`, linear.
    fn lit(&self, albedo: [f64; 3], n: &V3, to_eye: &V3) -> [f64; 3] {
        let mut diffuse = AMBIENT;
        let mut spec = 0.0;
        for l in &self.lights {
            let nl = geom::dot(n, &l.dir);
            if nl > 0.0 {
                diffuse += l.intensity * nl;
                let h = geom::normalize_or_zero([0, 1, 2].map(|i| l.dir[i] + to_eye[i]));
                spec += l.intensity * geom::dot(n, &h).max(0.0).powf(SHININESS);
            }
        }
        albedo.map(|a| a * diffuse + SPECULAR * spec)
    }
}
