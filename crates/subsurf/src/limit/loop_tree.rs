//! Configuration trees of the Loop limit surface: the refinement of an irregular
//! triangle's cut-out, computed once for every face and node with the same neighbourhood,
//! as weights on the cut-out's points.
//!
//! As for Catmull-Clark ([`super::tree`]), the limit over an irregular triangle depends
//! linearly on the points of its cut-out through a refinement decided by the cut-out's
//! topology alone. A [`LoopTree`] holds, for one cut-out (its face 0 the node's triangle),
//! the points of its one-step Loop refinement that the four children read, as sparse rows
//! on the cut-out's points ([`super::rows::NodeRows`], from the refinement's own masks,
//! [`refinement_rows`](crate::refine::refinement_rows) with Loop's rules), and each child
//! as a box-spline net on those points or as the tree of its own cut-out (shared through
//! [`LoopTrees`]). [`LoopSurface`](super::LoopSurface) evaluates a face by flowing its
//! points down the tree: no topology is refined once a configuration is built.

use std::sync::{Arc, OnceLock};

use super::box_spline::{box_net, NetPoint};
use super::configs::{Configs, Keyed};
use super::local::cut_out_unbounded;
use super::rows::{NodeRows, WeightPool};
use crate::mesh::{Options, PackedTopology, Topology};
use crate::refine::refine_tri_topology;
use crate::scheme::loop_::Loop;

/// Configurations kept per surface at most (and at most four per face of the mesh plus
/// 64, [`LoopTrees::for_faces`]); past them, new configurations are built for the face
/// evaluated and dropped with it, as a surface whose faces nearly all differ (a scan's
/// irregular triangulation) would otherwise keep one tree per face.
const MAX_TREES: usize = 8192;

/// Bytes of a kept configuration, as estimated: its cut-out packed and unpacked and its
/// children's rows (5.5 KiB on average on `catmark_bishop` split into triangles, 1,319
/// trees: peak memory 9 → 16 MiB).
pub(super) const TREE_BYTES: u64 = 8 << 10;

/// The configurations of one Loop surface and the weights their rows share.
#[derive(Debug)]
pub(super) struct LoopTrees {
    trees: Configs<LoopTree>,
    weights: WeightPool,
}

impl Default for LoopTrees {
    fn default() -> Self {
        LoopTrees::for_faces(usize::MAX)
    }
}

impl LoopTrees {
    /// The most trees a surface of `faces` faces keeps: [`MAX_TREES`], and no more than
    /// four per face plus 64.
    pub(super) fn cap(faces: usize) -> usize {
        MAX_TREES.min(faces.saturating_mul(4).saturating_add(64))
    }

    /// An empty cache for a surface of `faces` faces (keeping at most [`Self::cap`]).
    pub(super) fn for_faces(faces: usize) -> Self {
        LoopTrees {
            trees: Configs::with_cap(Self::cap(faces)),
            weights: WeightPool::default(),
        }
    }

    /// The tree of the cut-out `topo` (as [`cut_out_topology`] makes it; its face 0 the
    /// triangle).
    pub(super) fn get(&self, topo: Topology) -> Arc<LoopTree> {
        self.trees.find(topo, |t, key| LoopTree {
            key,
            topo: t.clone(),
            kids: OnceLock::new(),
        })
    }

    /// Number of configurations kept.
    pub(super) fn len(&self) -> usize {
        self.trees.len()
    }
}

/// The tree of one configuration: face 0 of cut-out `topo`, a triangle that is not one
/// box-spline patch.
#[derive(Debug)]
pub(super) struct LoopTree {
    key: PackedTopology,
    /// The cut-out: the corner analyses of the nodes read it (every point at a corner of
    /// a face that is not one patch takes one), so it is kept unpacked.
    pub topo: Topology,
    kids: OnceLock<LoopKids>,
}

impl Keyed for LoopTree {
    fn key(&self) -> &PackedTopology {
        &self.key
    }
}

/// A node's four children (OpenSubdiv's numbering: child `j < 3` at corner `j`, child 3
/// the middle one) and the refined points they read.
#[derive(Debug)]
pub(super) struct LoopKids {
    /// Row `k`: the `k`th refined point the children read, as weights on the cut-out's
    /// points.
    rows: NodeRows,
    pub kids: [LoopKid; 4],
}

/// A child of a node, on its parent's refined points ([`LoopKids::refine_into`]).
#[derive(Debug)]
pub(super) enum LoopKid {
    /// One box-spline patch: its twelve control points.
    Patch([NetPoint; 12]),
    /// Irregular: the tree of the child's cut-out, and where each of the cut-out's points
    /// is among the refined points.
    Node(Arc<LoopTree>, Box<[u32]>),
}

impl LoopKids {
    /// The refined points of a node evaluated on `pos`, into `out`.
    pub(super) fn refine_into(&self, pos: &[[f64; 3]], out: &mut Vec<[f64; 3]>) {
        self.rows.apply(pos, out);
    }
}

impl LoopTree {
    /// The children (built the first time, their own trees found in `trees`).
    pub(super) fn kids(&self, options: &Options, trees: &LoopTrees) -> &LoopKids {
        self.kids.get_or_init(|| self.build_kids(options, trees))
    }

    fn build_kids(&self, options: &Options, trees: &LoopTrees) -> LoopKids {
        let t = &self.topo;
        let child = refine_tri_topology(t, options, true);
        let chaikin = options.crease_method == crate::mesh::CreaseMethod::Chaikin;
        // Face 0's children are the first four faces of its refinement.
        let found: [Result<[NetPoint; 12], Vec<u32>>; 4] = std::array::from_fn(|j| {
            box_net(&child, j).ok_or_else(|| cut_out_unbounded(&child, j, chaikin))
        });
        let mut needed = Vec::new();
        for kid in &found {
            match kid {
                Ok(net) => net.iter().for_each(|p| match *p {
                    NetPoint::Vertex(a) => needed.push(a),
                    NetPoint::Phantom(a, b, c) => needed.extend([a, b, c]),
                }),
                Err(faces) => needed.extend(
                    (faces.iter()).flat_map(|&g| child.face_vertices(g as usize).iter().copied()),
                ),
            }
        }
        needed.sort_unstable();
        needed.dedup();
        let slot = |v: u32| match needed.binary_search(&v) {
            Ok(k) => k as u32,
            Err(_) => unreachable!("a child reads a refined vertex its node does not compute"),
        };
        let rows = NodeRows::refinement(t, &child, options, Loop, &needed, |c| c, &trees.weights);
        let kids = found.map(|kid| match kid {
            Ok(net) => LoopKid::Patch(net.map(|p| match p {
                NetPoint::Vertex(a) => NetPoint::Vertex(slot(a)),
                NetPoint::Phantom(a, b, c) => NetPoint::Phantom(slot(a), slot(b), slot(c)),
            })),
            Err(faces) => {
                let (sub, verts) = cut_out_topology(&child, &faces);
                let cols = verts.iter().map(|&v| slot(v)).collect();
                LoopKid::Node(trees.get(sub), cols)
            }
        });
        LoopKids { rows, kids }
    }
}

/// The cut-out `faces` of `level` as the key of its configuration, and the level's vertex
/// of each of its vertices: in canonical form ([`Topology::subset_canonical`]), unless a
/// vertex of it is non-manifold, where the level's own order is kept
/// ([`Topology::subset`]): around a non-manifold vertex the order of the faces is not a
/// cycle that a canonical start could stand for.
pub(super) fn cut_out_topology(level: &Topology, faces: &[u32]) -> (Topology, Vec<u32>) {
    let non_manifold = (faces.iter())
        .flat_map(|&f| level.face_vertices(f as usize))
        .any(|&v| level.vertex_tag(v as usize).non_manifold);
    if non_manifold {
        level.subset(faces)
    } else {
        level.subset_canonical(faces)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::interpolate_loop;

    /// A node's rows give the points of Loop's own refinement of its cut-out
    /// ([`interpolate_loop`]) that its children read, on the root cut-out of every
    /// irregular face of every Loop regression shape (creases, corners, boundaries,
    /// non-manifold edges and vertices).
    #[test]
    fn rows_are_loop_refinement() {
        let dir = format!("{}/tests/shapes/osd", env!("CARGO_MANIFEST_DIR"));
        let mut checked = 0;
        for entry in std::fs::read_dir(&dir).expect("shapes") {
            let path = entry.expect("entry").path();
            let name = path.display().to_string();
            if !name.contains("loop_") || !name.ends_with(".obj") {
                continue;
            }
            let obj = crate::io::obj::read_obj(&path).expect("shape");
            let options = obj.options.resolve(Options::default());
            let t = Topology::from_mesh(&obj.mesh, &options)
                .expect("topology")
                .0;
            let trees = LoopTrees::default();
            let chaikin = options.crease_method == crate::mesh::CreaseMethod::Chaikin;
            for f in 0..t.num_faces() {
                if box_net(&t, f).is_some() || t.is_hole(f) {
                    continue;
                }
                let faces = cut_out_unbounded(&t, f, chaikin);
                let (sub, verts) = cut_out_topology(&t, &faces);
                let pos: Vec<[f64; 3]> = verts
                    .iter()
                    .map(|&v| obj.mesh.positions()[v as usize])
                    .collect();
                let tree = trees.get(sub);
                check_node(
                    &tree,
                    &pos,
                    &options,
                    &trees,
                    chaikin,
                    4,
                    &mut checked,
                    &name,
                );
            }
        }
        assert!(checked > 100, "{checked} children checked");
    }

    /// Checks the children of `tree` evaluated on `pos` against [`interpolate_loop`], and
    /// theirs, `levels` deep.
    #[allow(clippy::too_many_arguments)]
    fn check_node(
        tree: &LoopTree,
        pos: &[[f64; 3]],
        options: &Options,
        trees: &LoopTrees,
        chaikin: bool,
        levels: u32,
        checked: &mut usize,
        name: &str,
    ) {
        let kids = tree.kids(options, trees);
        let mut refined = Vec::new();
        kids.refine_into(pos, &mut refined);
        let child = refine_tri_topology(&tree.topo, options, true);
        let mut want = vec![[0.0; 3]; child.num_vertices()];
        interpolate_loop(&tree.topo, &child, options, pos, &mut want);
        let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12);
        for (j, kid) in kids.kids.iter().enumerate() {
            match kid {
                LoopKid::Patch(net) => {
                    let Some(net_want) = box_net(&child, j) else {
                        panic!("{name}: child {j} is no patch");
                    };
                    for (p, q) in net.iter().zip(&net_want) {
                        assert!(close(p.at(&refined), q.at(&want)), "{name}: child {j} net");
                    }
                }
                LoopKid::Node(sub, cols) => {
                    let sub_faces = cut_out_unbounded(&child, j, chaikin);
                    let (topo, sub_verts) = cut_out_topology(&child, &sub_faces);
                    assert!(
                        PackedTopology::new(&topo) == sub.key,
                        "{name}: child {j} key"
                    );
                    let mine: Vec<[f64; 3]> = cols.iter().map(|&c| refined[c as usize]).collect();
                    for (&a, &v) in mine.iter().zip(&sub_verts) {
                        assert!(close(a, want[v as usize]), "{name}: child {j}: {a:?}");
                    }
                    *checked += 1;
                    if levels > 1 {
                        check_node(
                            sub,
                            &mine,
                            options,
                            trees,
                            chaikin,
                            levels - 1,
                            checked,
                            name,
                        );
                    }
                }
            }
        }
    }
}
