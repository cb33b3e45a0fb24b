//! One uniform Catmull-Clark topology step: the child [`Topology`] derived directly from
//! the parent's indices (no hashing), with tags and sharpness propagated as OpenSubdiv's
//! `Vtr::internal::Refinement` does.
//!
//! # Child numbering (OpenSubdiv's default order)
//! With `V`, `F`, `E` the parent's vertex, face and edge counts and `S` the total number
//! of face-vertices:
//! - vertices: the child of vertex `v` is `v`; of face `f` is `V + f`; of edge `e` is
//!   `V + F + e`;
//! - faces: the child of face `f` at its corner `j` is `face_offsets[f] + j`, a quad
//!   `[child of vertex j, child of edge j, child of f, child of edge j-1]`, rotated for
//!   parent quads so that its corner `j` is the vertex child (the parent's parametric
//!   orientation is kept);
//! - edges: `face_offsets[f] + j` joins the children of `f` and of its edge `j`;
//!   `S + 2e + k` joins the children of edge `e` and of its end `k`.

use crate::mesh::{CreaseMethod, EdgeTag, Options, Rule, Topology, VertexTag};
use crate::scheme::crease;

/// Rotation of the child quad at `corner` of a parent face of size `n`: child quads of
/// quads are rotated so that their corner `corner` is the parent vertex's child.
#[inline]
fn rot(n: usize, corner: usize) -> usize {
    if n == 4 {
        corner
    } else {
        0
    }
}

/// Child edge of parent edge `e` at its end vertex `v`; `leaving` says whether a face
/// runs the edge away from `v` (which picks the child of a degenerate edge, whose two ends
/// are both `v`: the first child when leaving, the second when entering).
#[inline]
fn edge_child_at(p: &Topology, s: u32, e: u32, v: u32, leaving: bool) -> u32 {
    let [a, b] = p.edge_verts[e as usize];
    let k = if a == b { !leaving } else { a != v };
    s + 2 * e + k as u32
}

/// Refines `p` one level: the child's topology, tags and sharpness. With `full == false`
/// only what is needed to interpolate into the child and to write it out is built (faces,
/// edges' vertices, tags and sharpness), not the relations needed to refine it further or
/// to evaluate limit masks on it (face → edges, edge → faces, vertex → faces and edges);
/// OpenSubdiv skips the same work for the last level.
pub(crate) fn refine_topology(p: &Topology, options: &Options, full: bool) -> Topology {
    let nv = p.num_vertices();
    let nf = p.num_faces();
    let ne = p.num_edges();
    let s = p.face_verts.len() as u32;
    let (fc0, ec0) = (nv as u32, (nv + nf) as u32);
    let cnv = nv + nf + ne;
    let cnf = s as usize;
    let cne = s as usize + 2 * ne;

    // Faces: every child is a quad.
    let face_offsets: Vec<u32> = (0..=cnf as u32).map(|i| 4 * i).collect();
    let mut face_verts = vec![0u32; 4 * cnf];
    let mut face_edges = if full {
        vec![0u32; 4 * cnf]
    } else {
        Vec::new()
    };
    let mut face_holes = vec![false; cnf];
    for f in 0..nf {
        let o = p.face_offsets[f] as usize;
        let fv = p.face_vertices(f);
        let fe = p.face_edge_list(f);
        let n = fv.len();
        let hole = p.face_holes[f];
        for j in 0..n {
            let jp = if j == 0 { n - 1 } else { j - 1 };
            let v = fv[j];
            let verts = [v, ec0 + fe[j], fc0 + f as u32, ec0 + fe[jp]];
            let edges = [
                edge_child_at(p, s, fe[j], v, true),
                (o + j) as u32,
                (o + jp) as u32,
                edge_child_at(p, s, fe[jp], v, false),
            ];
            let cf = o + j;
            let r = rot(n, j);
            for k in 0..4 {
                face_verts[4 * cf + (k + r) % 4] = verts[k];
            }
            if full {
                for k in 0..4 {
                    face_edges[4 * cf + (k + r) % 4] = edges[k];
                }
            }
            face_holes[cf] = hole;
        }
    }

    // Edges: vertices.
    let mut edge_verts = vec![[0u32; 2]; cne];
    for f in 0..nf {
        let o = p.face_offsets[f] as usize;
        for (j, &e) in p.face_edge_list(f).iter().enumerate() {
            edge_verts[o + j] = [fc0 + f as u32, ec0 + e];
        }
    }
    for e in 0..ne {
        for k in 0..2 {
            edge_verts[s as usize + 2 * e + k] = [ec0 + e as u32, p.edge_verts[e][k]];
        }
    }

    let mut child = Topology {
        num_vertices: cnv as u32,
        face_offsets,
        face_verts,
        face_edges,
        face_holes,
        edge_verts,
        edge_sharpness: vec![0.0; cne],
        vert_sharpness: vec![0.0; cnv],
        edge_tags: vec![EdgeTag::default(); cne],
        vert_tags: vec![VertexTag::default(); cnv],
        has_holes: p.has_holes,
        complete: full,
        ..Topology::default()
    };
    propagate_tags_and_sharpness(p, &mut child, options.crease_method);
    if full {
        build_relations(p, &mut child);
    }
    child
}

/// The child's edge → faces and vertex → faces/edges relations, in rotational order.
fn build_relations(p: &Topology, c: &mut Topology) {
    let nv = p.num_vertices();
    let nf = p.num_faces();
    let ne = p.num_edges();
    let s = p.face_verts.len() as u32;
    let cnv = nv + nf + ne;
    let cnf = s as usize;
    let cne = s as usize + 2 * ne;

    // Edges: faces.
    let mut edge_face_offsets = vec![0u32; cne + 1];
    for i in 0..cnf {
        edge_face_offsets[i + 1] = edge_face_offsets[i] + 2;
    }
    for e in 0..ne {
        let m = p.edge_face_list(e).len() as u32;
        let i = cnf + 2 * e;
        edge_face_offsets[i + 1] = edge_face_offsets[i] + m;
        edge_face_offsets[i + 2] = edge_face_offsets[i + 1] + m;
    }
    let nef = edge_face_offsets[cne] as usize;
    let mut edge_faces = vec![0u32; nef];
    let mut edge_face_local = vec![0u16; nef];
    for f in 0..nf {
        let o = p.face_offsets[f] as usize;
        let fe = p.face_edge_list(f);
        let n = fe.len();
        for j in 0..n {
            let ce = o + j;
            let jn = if j + 1 == n { 0 } else { j + 1 };
            let at = edge_face_offsets[ce] as usize;
            edge_faces[at] = ce as u32;
            edge_face_local[at] = ((1 + rot(n, j)) % 4) as u16;
            edge_faces[at + 1] = (o + jn) as u32;
            edge_face_local[at + 1] = ((2 + rot(n, jn)) % 4) as u16;
        }
    }
    for e in 0..ne {
        let ev = p.edge_verts[e];
        let pfaces = p.edge_face_list(e);
        let plocal = &p.edge_face_local[p.edge_face_offsets[e] as usize..];
        for k in 0..2 {
            let ce = s as usize + 2 * e + k;
            let first = edge_face_offsets[ce] as usize;
            for (at, (pf, &i)) in (first..).zip(pfaces.iter().zip(plocal)) {
                let pf = *pf as usize;
                let fv = p.face_vertices(pf);
                let n = fv.len();
                let i = i as usize;
                let at_start = if ev[0] == ev[1] {
                    k == 0
                } else {
                    fv[i] == ev[k]
                };
                let (corner, pos) = if at_start { (i, 0) } else { ((i + 1) % n, 3) };
                edge_faces[at] = p.face_offsets[pf] + corner as u32;
                edge_face_local[at] = ((pos + rot(n, corner)) % 4) as u16;
            }
        }
    }

    // Vertices: faces and edges around each child vertex, in rotational order.
    let mut vert_face_offsets = vec![0u32; cnv + 1];
    let mut vert_edge_offsets = vec![0u32; cnv + 1];
    for v in 0..nv {
        vert_face_offsets[v + 1] = vert_face_offsets[v] + p.vertex_faces(v).len() as u32;
        vert_edge_offsets[v + 1] = vert_edge_offsets[v] + p.vertex_edges(v).len() as u32;
    }
    for f in 0..nf {
        let n = p.face_vertices(f).len() as u32;
        let i = nv + f;
        vert_face_offsets[i + 1] = vert_face_offsets[i] + n;
        vert_edge_offsets[i + 1] = vert_edge_offsets[i] + n;
    }
    for e in 0..ne {
        let m = p.edge_face_list(e).len() as u32;
        let i = nv + nf + e;
        vert_face_offsets[i + 1] = vert_face_offsets[i] + 2 * m;
        vert_edge_offsets[i + 1] = vert_edge_offsets[i] + m + 2;
    }
    let mut vert_faces = vec![0u32; vert_face_offsets[cnv] as usize];
    let mut vert_face_local = vec![0u16; vert_faces.len()];
    let mut vert_edges = vec![0u32; vert_edge_offsets[cnv] as usize];
    let mut vert_edge_local = vec![0u8; vert_edges.len()];
    for v in 0..nv {
        let fo = vert_face_offsets[v] as usize;
        for (k, (&pf, &j)) in p
            .vertex_faces(v)
            .iter()
            .zip(p.vertex_face_locals(v))
            .enumerate()
        {
            let n = p.face_vertices(pf as usize).len();
            vert_faces[fo + k] = p.face_offsets[pf as usize] + j as u32;
            vert_face_local[fo + k] = rot(n, j as usize) as u16;
        }
        let eo = vert_edge_offsets[v] as usize;
        for (k, (&pe, &l)) in p
            .vertex_edges(v)
            .iter()
            .zip(p.vertex_edge_locals(v))
            .enumerate()
        {
            vert_edges[eo + k] = s + 2 * pe + l as u32;
            vert_edge_local[eo + k] = 1;
        }
    }
    for f in 0..nf {
        let cv = nv + f;
        let o = p.face_offsets[f] as usize;
        let n = p.face_vertices(f).len();
        let fo = vert_face_offsets[cv] as usize;
        let eo = vert_edge_offsets[cv] as usize;
        for i in 0..n {
            vert_faces[fo + i] = (o + i) as u32;
            vert_face_local[fo + i] = ((2 + rot(n, i)) % 4) as u16;
            vert_edges[eo + i] = (o + (i + n - 1) % n) as u32;
            vert_edge_local[eo + i] = 0;
        }
    }
    for e in 0..ne {
        let cv = nv + nf + e;
        let pfaces = p.edge_face_list(e);
        let plocal = &p.edge_face_local[p.edge_face_offsets[e] as usize..];
        let mut fo = vert_face_offsets[cv] as usize;
        let eo = vert_edge_offsets[cv] as usize;
        let manifold = !p.edge_tags[e].non_manifold && pfaces.len() <= 2;
        // The two child faces in each parent face: the one at the edge's second vertex
        // in that face first, then the one at its first vertex.
        for (&pf, &i) in pfaces.iter().zip(plocal) {
            let pfu = pf as usize;
            let n = p.face_vertices(pfu).len();
            let (c0, c1) = (i as usize, (i as usize + 1) % n);
            let base = p.face_offsets[pfu];
            vert_faces[fo] = base + c1 as u32;
            vert_face_local[fo] = ((3 + rot(n, c1)) % 4) as u16;
            vert_faces[fo + 1] = base + c0 as u32;
            vert_face_local[fo + 1] = ((1 + rot(n, c0)) % 4) as u16;
            fo += 2;
        }
        if manifold {
            // Counter-clockwise: [edge child toward the first face's second vertex,
            // interior edge of face 0, edge child toward its first vertex, interior edge
            // of face 1].
            let pf0 = pfaces[0] as usize;
            let i0 = plocal[0] as usize;
            let fv = p.face_vertices(pf0);
            let (a, b) = (fv[i0], fv[(i0 + 1) % fv.len()]);
            vert_edges[eo] = edge_child_at(p, s, e as u32, b, false);
            vert_edges[eo + 1] = p.face_offsets[pf0] + i0 as u32;
            vert_edges[eo + 2] = edge_child_at(p, s, e as u32, a, true);
            vert_edge_local[eo] = 0;
            vert_edge_local[eo + 1] = 1;
            vert_edge_local[eo + 2] = 0;
            if pfaces.len() == 2 {
                vert_edges[eo + 3] = p.face_offsets[pfaces[1] as usize] + plocal[1] as u32;
                vert_edge_local[eo + 3] = 1;
            }
        } else {
            vert_edges[eo] = s + 2 * e as u32;
            vert_edges[eo + 1] = s + 2 * e as u32 + 1;
            vert_edge_local[eo] = 0;
            vert_edge_local[eo + 1] = 0;
            for (k, (&pf, &i)) in pfaces.iter().zip(plocal).enumerate() {
                vert_edges[eo + 2 + k] = p.face_offsets[pf as usize] + i as u32;
                vert_edge_local[eo + 2 + k] = 1;
            }
        }
    }

    c.edge_face_offsets = edge_face_offsets;
    c.edge_faces = edge_faces;
    c.edge_face_local = edge_face_local;
    c.vert_face_offsets = vert_face_offsets;
    c.vert_faces = vert_faces;
    c.vert_face_local = vert_face_local;
    c.vert_edge_offsets = vert_edge_offsets;
    c.vert_edges = vert_edges;
    c.vert_edge_local = vert_edge_local;
    // Valence never shrinks: vertex children keep theirs, face children have the face
    // size, edge children 2 + the edge's face count.
    let max_face = (0..nf).map(|f| p.face_vertices(f).len()).max().unwrap_or(0);
    let max_edge_faces = (0..ne)
        .map(|e| p.edge_face_list(e).len())
        .max()
        .unwrap_or(0);
    let max_edge_valence = max_edge_faces + max_edge_faces.max(2);
    c.max_valence = p
        .max_valence
        .max(max_face as u32)
        .max(max_edge_valence as u32);
}

/// Tags and sharpness of the child level (OpenSubdiv's `propagateComponentTags`,
/// `subdivideEdgeSharpness`, `subdivideVertexSharpness`, `reclassifySemisharpVertices`).
fn propagate_tags_and_sharpness(p: &Topology, c: &mut Topology, method: CreaseMethod) {
    let nv = p.num_vertices();
    let nf = p.num_faces();
    let ne = p.num_edges();
    let s = p.face_verts.len();

    // Edges from faces stay smooth (default); edges from edges inherit and decay.
    let mut incident = Vec::new();
    for e in 0..ne {
        let tag = p.edge_tags[e];
        let ps = p.edge_sharpness[e];
        for k in 0..2 {
            let ce = s + 2 * e + k;
            let mut ctag = tag;
            let cs = if tag.inf_sharp {
                crease::SHARPNESS_INFINITE
            } else if tag.semi_sharp {
                let cs = if method == CreaseMethod::Uniform {
                    crease::decrement(ps)
                } else {
                    let v = p.edge_verts[e][k] as usize;
                    incident.clear();
                    incident.extend(
                        p.vertex_edges(v)
                            .iter()
                            .map(|&x| p.edge_sharpness[x as usize]),
                    );
                    crease::subdivide_edge_sharpness(method, ps, &incident)
                };
                if !crease::is_sharp(cs) {
                    ctag.semi_sharp = false;
                }
                cs
            } else {
                0.0
            };
            c.edge_tags[ce] = ctag;
            c.edge_sharpness[ce] = cs;
        }
    }

    // Vertices from vertices inherit and decay.
    for v in 0..nv {
        let mut tag = p.vert_tags[v];
        let cs = if tag.inf_sharp {
            crease::SHARPNESS_INFINITE
        } else if tag.semi_sharp {
            let cs = crease::decrement(p.vert_sharpness[v]);
            if !crease::is_sharp(cs) {
                tag.semi_sharp = false;
            }
            cs
        } else {
            0.0
        };
        c.vert_tags[v] = tag;
        c.vert_sharpness[v] = cs;
    }
    // Vertices from faces: smooth (default tag).
    // Vertices from edges: crease if the edge was sharp.
    for e in 0..ne {
        let et = p.edge_tags[e];
        let cv = nv + nf + e;
        let mut tag = VertexTag {
            non_manifold: et.non_manifold,
            boundary: et.boundary,
            semi_sharp_edges: et.semi_sharp,
            inf_sharp_edges: et.inf_sharp,
            rule: if et.semi_sharp || et.inf_sharp {
                Rule::Crease
            } else {
                Rule::Smooth
            },
            ..VertexTag::default()
        };
        if tag.semi_sharp_edges {
            let count = c.edge_tags[s + 2 * e].semi_sharp as usize
                + c.edge_tags[s + 2 * e + 1].semi_sharp as usize;
            tag.semi_sharp_edges = count > 0;
            tag.rule = crease::vertex_rule(0.0, count);
        }
        c.vert_tags[cv] = tag;
    }
    // Re-classify vertex children whose sharp features decayed.
    for v in 0..nv {
        let pt = p.vert_tags[v];
        if !pt.semi_sharp && !pt.semi_sharp_edges {
            continue;
        }
        let ct = c.vert_tags[v];
        let decayed = pt.semi_sharp && !ct.semi_sharp;
        if pt.semi_sharp_edges || decayed {
            let (mut inf, mut semi) = (0, 0);
            for (&pe, &l) in p.vertex_edges(v).iter().zip(p.vertex_edge_locals(v)) {
                let t = c.edge_tags[s + 2 * pe as usize + l as usize];
                inf += t.inf_sharp as usize;
                semi += t.semi_sharp as usize;
            }
            let ct = &mut c.vert_tags[v];
            ct.semi_sharp_edges = semi > 0;
            if !ct.semi_sharp && !ct.inf_sharp {
                ct.rule = crease::vertex_rule(0.0, inf + semi);
            }
        }
    }
}
