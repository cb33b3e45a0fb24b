//! A [`Topology`] packed into one byte string: every field, each array in the fewest
//! bytes per entry that hold its largest entry.
//!
//! # Why
//! The limit surface keeps one cut-out per configuration of an irregular face (the root
//! of its configuration tree, `limit::tree`), both to tell configurations apart and to
//! refine it when a point first needs a level below. A cut-out has a few dozen vertices,
//! edges and faces, so every index in it fits in a byte, yet as a [`Topology`] it is
//! twenty 32-bit arrays (about 2.6 KiB with the allocations' headers): on a mesh whose
//! faces nearly all have configurations of their own (a grid with creases on a tenth of
//! its edges, 6,800 configurations for 10,000 faces) they were 30 % of the surface.
//! Packed, a cut-out takes about a fifth of that, and two packed cut-outs are equal
//! exactly when their topologies are ([`Topology::structure_key`]: the same fields).
//!
//! # Format
//! Variable-length integers (LEB128: seven bits per byte, the high bit set on all but the
//! last): `num_vertices`, `max_valence`, a byte of flags (`has_holes`, `complete`), then
//! each array in [`Topology`]'s order: its length times four plus its width code (0: every
//! entry zero, nothing follows; 1, 2, 3: one, two, four bytes per entry), then the
//! entries, little-endian. `edge_verts` is one array of both ends of each edge;
//! sharpness is stored as the bits of each `f32`, tags as their packed bits. The width of
//! an array depends only on its entries, so equal topologies pack to equal bytes.

use super::topology::{PackedEdgeTag, PackedVertexTag, Topology};

/// A [`Topology`] in a compact form (module docs): [`unpack`](Self::unpack) gives it back
/// exactly; equal bytes, equal topologies.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PackedTopology(Box<[u8]>);

impl PackedTopology {
    /// `t` packed.
    pub(crate) fn new(t: &Topology) -> Self {
        let mut w = Vec::with_capacity(256);
        varint(&mut w, t.num_vertices);
        varint(&mut w, t.max_valence);
        w.push(u8::from(t.has_holes) | u8::from(t.complete) << 1);
        array(&mut w, t.face_offsets.iter().copied());
        array(&mut w, t.face_verts.iter().copied());
        array(&mut w, t.face_edges.iter().copied());
        array(&mut w, t.face_holes.iter().map(|&h| u32::from(h)));
        array(&mut w, t.edge_verts.as_flattened().iter().copied());
        array(&mut w, t.edge_face_offsets.iter().copied());
        array(&mut w, t.edge_faces.iter().copied());
        array(&mut w, t.edge_face_local.iter().map(|&x| u32::from(x)));
        array(&mut w, t.vert_face_offsets.iter().copied());
        array(&mut w, t.vert_faces.iter().copied());
        array(&mut w, t.vert_face_local.iter().map(|&x| u32::from(x)));
        array(&mut w, t.vert_edge_offsets.iter().copied());
        array(&mut w, t.vert_edges.iter().copied());
        array(&mut w, t.vert_edge_local.iter().map(|&x| u32::from(x)));
        array(&mut w, t.edge_sharpness.iter().map(|x| x.to_bits()));
        array(&mut w, t.vert_sharpness.iter().map(|x| x.to_bits()));
        array(&mut w, t.edge_tags.iter().map(|t| t.bits()));
        array(&mut w, t.vert_tags.iter().map(|t| t.bits()));
        PackedTopology(w.into())
    }

    /// The topology packed.
    pub(crate) fn unpack(&self) -> Topology {
        let mut r = Reader(&self.0);
        let num_vertices = r.varint();
        let max_valence = r.varint();
        let flags = r.byte();
        // Entries narrower than `u32` were stored from values of their own type, so the
        // conversions below give them back unchanged.
        let narrow = |v: Vec<u32>| v.into_iter().map(|x| x as u16).collect();
        Topology {
            num_vertices,
            max_valence,
            has_holes: flags & 1 != 0,
            complete: flags & 2 != 0,
            face_offsets: r.array(),
            face_verts: r.array(),
            face_edges: r.array(),
            face_holes: r.array().into_iter().map(|h| h != 0).collect(),
            edge_verts: (r.array().chunks_exact(2)).map(|e| [e[0], e[1]]).collect(),
            edge_face_offsets: r.array(),
            edge_faces: r.array(),
            edge_face_local: narrow(r.array()),
            vert_face_offsets: r.array(),
            vert_faces: r.array(),
            vert_face_local: narrow(r.array()),
            vert_edge_offsets: r.array(),
            vert_edges: r.array(),
            vert_edge_local: r.array().into_iter().map(|x| x as u8).collect(),
            edge_sharpness: r.array().into_iter().map(f32::from_bits).collect(),
            vert_sharpness: r.array().into_iter().map(f32::from_bits).collect(),
            edge_tags: r
                .array()
                .into_iter()
                .map(PackedEdgeTag::from_bits)
                .collect(),
            vert_tags: (r.array().into_iter())
                .map(PackedVertexTag::from_bits)
                .collect(),
        }
    }

    /// The packed bytes.
    pub(crate) fn as_bytes(&self) -> &[u8] {
        &self.0
    }
}

/// Appends `x` as a variable-length integer (module docs).
fn varint(w: &mut Vec<u8>, mut x: u32) {
    while x >= 0x80 {
        w.push(x as u8 | 0x80);
        x >>= 7;
    }
    w.push(x as u8);
}

/// Appends an array (module docs).
fn array(w: &mut Vec<u8>, xs: impl Iterator<Item = u32> + Clone) {
    let (len, max) = xs.clone().fold((0u32, 0u32), |(n, m), x| (n + 1, m.max(x)));
    let (code, bytes) = match max {
        0 => (0, 0),
        1..=0xff => (1, 1),
        0x100..=0xffff => (2, 2),
        _ => (3, 4),
    };
    varint(w, len * 4 + code);
    w.reserve(len as usize * bytes);
    // One arm per width, so that each entry is a store of known size.
    match bytes {
        0 => {}
        1 => xs.for_each(|x| w.push(x as u8)),
        2 => xs.for_each(|x| w.extend_from_slice(&(x as u16).to_le_bytes())),
        _ => xs.for_each(|x| w.extend_from_slice(&x.to_le_bytes())),
    }
}

/// Reads what [`PackedTopology::new`] wrote, in order.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn byte(&mut self) -> u8 {
        let (&b, rest) = self.0.split_first().unwrap_or((&0, &[]));
        self.0 = rest;
        b
    }

    fn varint(&mut self) -> u32 {
        let mut x = 0;
        for shift in (0..35).step_by(7) {
            let b = self.byte();
            x |= u32::from(b & 0x7f) << shift;
            if b < 0x80 {
                break;
            }
        }
        x
    }

    fn array(&mut self) -> Vec<u32> {
        let head = self.varint();
        let (len, bytes) = (head / 4, [0, 1, 2, 4][head as usize % 4]);
        if bytes == 0 {
            return vec![0; len as usize];
        }
        let (data, rest) = self.0.split_at(len as usize * bytes);
        self.0 = rest;
        // One loop per width: the roots of trees are unpacked often, and a loop copying
        // each entry's bytes one by one would not be vectorised.
        match bytes {
            1 => data.iter().map(|&b| u32::from(b)).collect(),
            2 => (data.chunks_exact(2))
                .map(|c| u32::from(u16::from_le_bytes([c[0], c[1]])))
                .collect(),
            _ => (data.chunks_exact(4))
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{test_cube, test_grid, Corner, Crease, Options, PolyMesh};

    fn key(t: &Topology) -> Vec<u32> {
        let mut k = Vec::new();
        t.structure_key(&mut k);
        k
    }

    /// Cut-outs of every face of a creased, holed grid and of a cube, and the whole
    /// meshes: unpacking gives every field back, and the bytes are equal exactly when
    /// the structure keys are.
    #[test]
    fn packing_round_trips_and_tells_topologies_apart() {
        let mut grid = test_grid(6, 5, |x, y| [x, y, 0.0]);
        let tags = &mut grid.tags;
        tags.creases.push(Crease {
            v0: 8,
            v1: 9,
            sharpness: 2.5,
        });
        tags.creases.push(Crease {
            v0: 9,
            v1: 16,
            sharpness: 10.0,
        });
        tags.corners.push(Corner {
            vertex: 20,
            sharpness: 1.25,
        });
        tags.holes.push(12);
        let meshes: Vec<PolyMesh> = vec![grid, test_cube()];
        let mut seen: Vec<(Vec<u32>, PackedTopology)> = Vec::new();
        for mesh in &meshes {
            let (t, _) = Topology::from_mesh(mesh, &Options::default()).unwrap();
            let mut tops = vec![t.clone()];
            for f in 0..t.num_faces() as u32 {
                let ring: Vec<u32> = (t.face_vertices(f as usize).iter())
                    .flat_map(|&v| t.vertex_faces(v as usize).iter().copied())
                    .fold(vec![f], |mut acc, g| {
                        if !acc.contains(&g) {
                            acc.push(g);
                        }
                        acc
                    });
                tops.push(t.subset_canonical(&ring).0);
            }
            for top in tops {
                let packed = PackedTopology::new(&top);
                assert_eq!(key(&packed.unpack()), key(&top));
                assert!(packed.as_bytes().len() < 4 * key(&top).len());
                for (k, p) in &seen {
                    assert_eq!(*k == key(&top), *p == packed);
                }
                seen.push((key(&top), packed));
            }
        }
        // Some faces share a configuration (the pairs above compared equal ones too).
        let distinct: std::collections::HashSet<&PackedTopology> =
            seen.iter().map(|(_, p)| p).collect();
        assert!(
            distinct.len() < seen.len(),
            "{} of {}",
            distinct.len(),
            seen.len()
        );
    }

    #[test]
    fn varints_and_widths() {
        for x in [0, 1, 127, 128, 300, 0xffff, 0x1_0000, u32::MAX] {
            let mut w = Vec::new();
            varint(&mut w, x);
            assert_eq!(Reader(&w).varint(), x);
        }
        for xs in [
            vec![],
            vec![0, 0],
            vec![3, 255],
            vec![256, 1],
            vec![u32::MAX, 7],
        ] {
            let mut w = Vec::new();
            array(&mut w, xs.iter().copied());
            let mut r = Reader(&w);
            assert_eq!(r.array(), xs);
            assert!(r.0.is_empty());
        }
    }
}
