//! The curve and surface file reader (`subsurf::io::parse_geometry`: JSON
//! documents or arrays, and OBJ free-form `cstype`/`deg`/`curv`/`surf`/`parm`/`end`) on
//! arbitrary bytes, then sampling of everything it accepts and a round trip through both
//! writers.
//!
//! Checks: no panic, no hang (degrees, counts and indices come from the input); what is
//! accepted samples without error, writes as JSON and reads back equal, and writes as OBJ
//! free-form and reads back.
#![no_main]

use libfuzzer_sys::fuzz_target;
use subsurf::io::{geometry_to_string, parse_geometry, GeometryFormat};
use subsurf::nurbs::Geometry;

fuzz_target!(|data: &[u8]| {
    let Ok(items) = parse_geometry(data, "fuzz") else {
        return;
    };
    let geometry: Vec<Geometry> = items.into_iter().map(|g| g.geometry).collect();
    for g in &geometry {
        match g {
            Geometry::Curve(c) => {
                c.polyline(2).expect("an accepted curve samples");
            }
            Geometry::Surface(s) => {
                // Keep the grid small whatever the number of knot spans.
                let _ = s.grid(1);
            }
        }
    }
    let json = geometry_to_string(&geometry, GeometryFormat::Json);
    let back = parse_geometry(json.as_bytes(), "json").expect("written JSON reads back");
    let again: Vec<Geometry> = back.into_iter().map(|g| g.geometry).collect();
    assert_eq!(again, geometry);
    let obj = geometry_to_string(&geometry, GeometryFormat::Obj);
    let back = parse_geometry(obj.as_bytes(), "obj").expect("written OBJ reads back");
    assert_eq!(back.len(), geometry.len());
});
