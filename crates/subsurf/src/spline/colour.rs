//! Colours for pictures of the sub-basis spline in the spirit of the paper's Fig. 7: a
//! palette and a colouring of the faces in which neighbours differ ([`face_colours`]), and
//! a colour ramp for a scalar such as one control point's basis function
//! ([`scalar_colours`]).

use super::error::SplineError;
use crate::mesh::{Options, PolyMesh, Topology};

/// Colours of [`face_colours`] indices, in the spirit of the paper's Fig. 7.
pub const PALETTE: [[u8; 3]; 6] = [
    [230, 159, 0],
    [86, 180, 233],
    [0, 158, 115],
    [240, 228, 66],
    [204, 121, 167],
    [213, 94, 0],
];

/// A blue (0) to red (`max`) colour ramp of `values` (`max` = the largest value, or 1 if
/// none is positive).
pub fn scalar_colours(values: &[f64]) -> Vec<[u8; 3]> {
    let max = values.iter().cloned().fold(0.0f64, f64::max);
    let max = if max > 0.0 { max } else { 1.0 };
    values
        .iter()
        .map(|&x| {
            let t = (x / max).clamp(0.0, 1.0);
            let r = (255.0 * t).round() as u8;
            let g = (255.0 * (1.0 - (2.0 * t - 1.0).abs()) * 0.8).round() as u8;
            let b = (255.0 * (1.0 - t)).round() as u8;
            [r, g, b]
        })
        .collect()
}

/// A colour index per face such that faces sharing an edge get different indices (greedy
/// colouring in face order; at most `1 +` the largest number of edge neighbours, 5 for
/// quads), for pictures like the paper's Fig. 7 where neighbouring patches differ in colour.
///
/// # Errors
/// [`SplineError::Mesh`] for an invalid mesh.
pub fn face_colours(mesh: &PolyMesh) -> Result<Vec<u8>, SplineError> {
    let (topo, _) = Topology::from_mesh(mesh, &Options::default())?;
    let mut colour = vec![u8::MAX; topo.num_faces()];
    for f in 0..topo.num_faces() {
        let mut used = 0u64;
        for &e in topo.face_edge_list(f) {
            for &g in topo.edge_face_list(e as usize) {
                let c = colour[g as usize];
                if c < 64 {
                    used |= 1 << c;
                }
            }
        }
        colour[f] = (!used).trailing_zeros().min(63) as u8;
    }
    Ok(colour)
}
