//! A [`RegularityReport`] read in one [`Mode`]: the verdict, the faces that fail, and the
//! report as `subsurf regularity` prints it, as text ([`RegularityReport::summary`]) or as
//! a JSON object ([`RegularityReport::to_json`]; fields in `docs/regularity.md`).

use std::fmt::Write as _;

use super::cone::{ConeTest, Dimension};
use super::exact::Sign;
use super::report::{Certificate, Class, Mode, RegularityReport};
use crate::json::{object, to_string, ToJson};

/// How many failing faces the text summary lists.
const SHOWN: usize = 20;

impl Mode {
    /// `"global"` or `"local"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Global => "global",
            Self::Local => "local",
        }
    }
}

impl Dimension {
    /// `"planar"` or `"spatial"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Planar => "planar",
            Self::Spatial => "spatial",
        }
    }
}

impl Class {
    /// `"certified"`, `"regular-not-certified"`, `"not-regular"`, `"unsampled"` or
    /// `"contradiction"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Certified => "certified",
            Self::RegularNotCertified => "regular-not-certified",
            Self::NotRegular => "not-regular",
            Self::Unsampled => "unsampled",
            Self::Contradiction => "contradiction",
        }
    }
}

impl Certificate {
    /// `"certified"`, `"refused"` or `"not-applicable"`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Certified(_) => "certified",
            Self::Refused(_) => "refused",
            Self::NotApplicable(_) => "not-applicable",
        }
    }

    /// Why the face is not certified (`None` when it is).
    pub fn reason(&self) -> Option<String> {
        match self {
            Self::Certified(_) => None,
            Self::Refused(r) => Some(r.to_string()),
            Self::NotApplicable(i) => Some(i.to_string()),
        }
    }
}

impl RegularityReport {
    /// The verdict of `mode`'s certificate: every face certified, and no sample
    /// contradicting a certificate (`subsurf regularity` exits with 0 exactly then).
    pub fn regular(&self, mode: Mode) -> bool {
        self.certified(mode) && self.counts(mode).contradictions == 0
    }

    /// The faces that `mode`'s certificate does not certify or that a sample contradicts,
    /// ascending.
    pub fn failing_faces(&self, mode: Mode) -> Vec<usize> {
        (0..self.faces.len())
            .filter(|&f| {
                !self.certificate(f, mode).is_certified()
                    || matches!(self.class(f, mode), Class::Contradiction)
            })
            .collect()
    }

    /// The text report of the net `name` read in `mode`: the net, both certificates'
    /// verdicts, the global cones, the counts of `mode`'s certificate and of the samples,
    /// the first 20 faces that fail (each with its certificate and its worst sample), and
    /// the verdict ([`regular`](Self::regular)); one line each, every line ending in `\n`.
    pub fn summary(&self, name: &str, mode: Mode) -> String {
        let mut s = String::new();
        let c = self.counts(mode);
        let orient = match (self.dimension, self.orientation) {
            (Dimension::Planar, Sign::Negative) => ", clockwise",
            (Dimension::Planar, _) => ", counter-clockwise",
            _ => "",
        };
        let _ = writeln!(
            s,
            "{name}: {} net{orient}, {} faces",
            self.dimension.name(),
            self.faces.len()
        );
        let yes = |b: bool| if b { "certified" } else { "not certified" };
        let _ = writeln!(
            s,
            "global certificate (one cone pair per component): {}; local certificate (per face): {}",
            yes(self.certified(Mode::Global)),
            yes(self.certified(Mode::Local))
        );
        self.global_cones(&mut s);
        let _ = writeln!(
            s,
            "{} certificate: {} certified, {} refused, {} not applicable",
            mode.name(),
            c.certified,
            c.refused,
            c.not_applicable
        );
        if self.samples > 0 {
            let _ = writeln!(
                s,
                "limit surface sampled {n}x{n} per face: {} certified, {} regular but not certified, {} not regular",
                c.certified - c.contradictions,
                c.regular_not_certified,
                c.not_regular,
                n = self.samples
            );
            if c.contradictions > 0 {
                let _ = writeln!(
                    s,
                    "WARNING: {} certified faces have a sample at the singularity tolerance",
                    c.contradictions
                );
            }
        }
        let _ = writeln!(
            s,
            "local certificate succeeds where the global one fails: {} faces",
            self.local_only()
        );
        self.failing_lines(&mut s, mode);
        let _ = writeln!(
            s,
            "verdict ({} certificate): {}",
            mode.name(),
            if self.regular(mode) {
                "the limit surface is regular"
            } else {
                "not certified"
            }
        );
        s
    }

    /// The summary's lines on the global cones: one per component with its difference
    /// counts and whether its cones are disjoint (or why there are none).
    fn global_cones(&self, s: &mut String) {
        match &self.frames {
            Err(e) => {
                let _ = writeln!(s, "global cones: none ({e})");
            }
            Ok(_) => {
                for (i, comp) in self.components.iter().enumerate() {
                    let verdict = match comp.test {
                        ConeTest::Disjoint(_) => "disjoint".to_owned(),
                        ConeTest::Meet(o) => o.to_string(),
                    };
                    let _ = writeln!(
                        s,
                        "global cones, component {i}: {} u-differences, {} v-differences: {verdict}",
                        comp.u.len(),
                        comp.v.len()
                    );
                }
            }
        }
    }

    /// The summary's lines on the faces that fail ([`failing_faces`](Self::failing_faces)):
    /// the first [`SHOWN`], each with its certificate and its worst sample.
    fn failing_lines(&self, s: &mut String, mode: Mode) {
        let bad = self.failing_faces(mode);
        for &f in bad.iter().take(SHOWN) {
            let mut line = format!("  face {f}: {}", self.certificate(f, mode));
            if let Some(sm) = self.faces[f].sampled {
                let w = sm.worst();
                let what = if sm.is_regular() {
                    "sampled regular, least"
                } else {
                    "sampled NOT regular"
                };
                let _ = write!(
                    line,
                    "; {what}: sine {:.3e} at (u, v) = ({}, {})",
                    w.value, w.u, w.v
                );
            }
            let _ = writeln!(s, "{line}");
        }
        if bad.len() > SHOWN {
            let _ = writeln!(s, "  … and {} more faces", bad.len() - SHOWN);
        }
    }

    /// The report of the net `name` (`null` when `None`) read in `mode` as one compact JSON
    /// object (the library's JSON writer: shortest round-trip numbers). Its members, in
    /// order: `file`, `dimension`, `orientation` (planar: 1 counter-clockwise, −1
    /// clockwise; spatial: `null`), `mode`, `certified` ([`regular`](Self::regular)),
    /// `global_certified`, `local_certified`, `local_only_faces`, `samples`, `counts`
    /// (`faces`, `certified`, `refused`, `not_applicable`, `regular_not_certified`,
    /// `not_regular`, `contradictions`), `labelling` (why there is no global labelling, or
    /// `null`), `components` (per component: `u_differences`, `v_differences`, `disjoint`,
    /// `reason`) and `faces` (per face: `face`, `local`, `local_reason`, `global`,
    /// `global_reason`, `class`, `worst_sample` with `u`, `v`, `value`, or `null`).
    pub fn to_json(&self, name: Option<&str>, mode: Mode) -> String {
        to_string(&ReportJson {
            name,
            report: self,
            mode,
        })
    }
}

/// [`RegularityReport::to_json`]'s document.
struct ReportJson<'a> {
    name: Option<&'a str>,
    report: &'a RegularityReport,
    mode: Mode,
}

impl ToJson for ReportJson<'_> {
    fn write_json(&self, out: &mut String) {
        let (r, mode) = (self.report, self.mode);
        let c = r.counts(mode);
        object(out, |o| {
            o.field("file", &self.name);
            o.field("dimension", r.dimension.name());
            let orientation: Option<i64> = match r.dimension {
                Dimension::Planar if r.orientation == Sign::Negative => Some(-1),
                Dimension::Planar => Some(1),
                Dimension::Spatial => None,
            };
            o.field("orientation", &orientation);
            o.field("mode", mode.name());
            o.field("certified", &r.regular(mode));
            o.field("global_certified", &r.certified(Mode::Global));
            o.field("local_certified", &r.certified(Mode::Local));
            o.field("local_only_faces", &r.local_only());
            o.field("samples", &r.samples);
            o.field("counts", &CountsJson(r.faces.len(), c));
            o.field("labelling", &r.frames.as_ref().err().map(|e| e.to_string()));
            o.field("components", &ComponentsJson(r));
            o.field("faces", &FacesJson(r, mode));
        });
    }
}

/// The `counts` member: the number of faces and [`RegularityReport::counts`].
struct CountsJson(usize, super::report::Counts);

impl ToJson for CountsJson {
    fn write_json(&self, out: &mut String) {
        let c = &self.1;
        object(out, |o| {
            o.field("faces", &self.0);
            o.field("certified", &c.certified);
            o.field("refused", &c.refused);
            o.field("not_applicable", &c.not_applicable);
            o.field("regular_not_certified", &c.regular_not_certified);
            o.field("not_regular", &c.not_regular);
            o.field("contradictions", &c.contradictions);
        });
    }
}

/// The `components` member: each component's global cones.
struct ComponentsJson<'a>(&'a RegularityReport);

impl ToJson for ComponentsJson<'_> {
    fn write_json(&self, out: &mut String) {
        out.push('[');
        for (i, comp) in self.0.components.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            let reason = match comp.test {
                ConeTest::Disjoint(_) => None,
                ConeTest::Meet(o) => Some(o.to_string()),
            };
            object(out, |o| {
                o.field("u_differences", &comp.u.len());
                o.field("v_differences", &comp.v.len());
                o.field("disjoint", &matches!(comp.test, ConeTest::Disjoint(_)));
                o.field("reason", &reason);
            });
        }
        out.push(']');
    }
}

/// The `faces` member: each face's certificates, class and worst sample.
struct FacesJson<'a>(&'a RegularityReport, Mode);

impl ToJson for FacesJson<'_> {
    fn write_json(&self, out: &mut String) {
        let (r, mode) = (self.0, self.1);
        out.push('[');
        for (f, fr) in r.faces.iter().enumerate() {
            if f > 0 {
                out.push(',');
            }
            object(out, |o| {
                o.field("face", &f);
                o.field("local", fr.local.name());
                o.field("local_reason", &fr.local.reason());
                o.field("global", fr.global.name());
                o.field("global_reason", &fr.global.reason());
                o.field("class", r.class(f, mode).name());
                o.field("worst_sample", &fr.sampled.map(|s| WorstJson(s.worst())));
            });
        }
        out.push(']');
    }
}

/// A face's `worst_sample`: `u`, `v` and the sine measure `value`.
struct WorstJson(super::sample::Sample);

impl ToJson for WorstJson {
    fn write_json(&self, out: &mut String) {
        object(out, |o| {
            o.field("u", &self.0.u);
            o.field("v", &self.0.v);
            o.field("value", &self.0.value);
        });
    }
}
