//! The NURBS JSON reader (`subsurf::nurbs::from_json_str`) on arbitrary text, then
//! evaluation at the ends and the middle of the domain, and a write/read round trip.
//!
//! Checks: no panic, no hang (degrees and knot counts come from the input); an accepted
//! document writes back and reads back equal.
#![no_main]

use libfuzzer_sys::fuzz_target;
use subsurf::nurbs::{from_json_str, Curve, Geometry, Surface};

fn samples((a, b): (f64, f64)) -> [f64; 3] {
    [a, 0.5 * a + 0.5 * b, b]
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(g) = from_json_str(text) else {
        return;
    };
    match g {
        Geometry::Curve(c) => {
            match &c {
                Curve::BSpline(b) => {
                    for t in samples(b.domain()) {
                        let _ = b.eval(t);
                    }
                }
                Curve::Nurbs(n) => {
                    for t in samples(n.domain()) {
                        let _ = n.eval(t);
                    }
                }
            }
            let again =
                Curve::from_json_str(&c.to_json_string()).expect("written curve reads back");
            assert_eq!(again, c);
        }
        Geometry::Surface(s) => {
            match &s {
                Surface::BSpline(b) => {
                    let (du, dv) = b.domain();
                    for u in samples(du) {
                        for v in samples(dv) {
                            let _ = b.eval(u, v);
                        }
                    }
                }
                Surface::Nurbs(n) => {
                    let (du, dv) = n.domain();
                    for u in samples(du) {
                        for v in samples(dv) {
                            let _ = n.eval(u, v);
                        }
                    }
                }
            }
            let again =
                Surface::from_json_str(&s.to_json_string()).expect("written surface reads back");
            assert_eq!(again, s);
        }
    }
});
