//! Configurations by their cut-out: the map in which the limit surfaces find the tree of
//! an irregular face's neighbourhood (and of every node below it) built once for every
//! face and node with the same.
//!
//! A configuration's key is its cut-out in canonical form
//! ([`Topology::subset_canonical`](crate::mesh::Topology)), packed ([`PackedTopology`]):
//! two cut-outs have the same surface, as a function of their points, exactly when their
//! packed forms are equal.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use super::lock;
use crate::hash::FxHasher;
use crate::mesh::{PackedTopology, Topology};

/// A configuration's tree, found by its packed cut-out.
pub(super) trait Keyed {
    /// The packed cut-out.
    fn key(&self) -> &PackedTopology;
}

/// Trees by a hash of their packed cut-out, each bucket compared cut-out by cut-out.
type Map<T> = HashMap<u64, Vec<Arc<T>>, BuildHasherDefault<FxHasher>>;

/// The configurations of one surface (module docs), at most `cap` of them kept.
#[derive(Debug)]
pub(super) struct Configs<T> {
    map: Mutex<Map<T>>,
    /// Number of trees kept (read without the lock).
    len: AtomicUsize,
    /// Past this many trees, new ones are made for their caller and not kept.
    cap: usize,
}

impl<T> Default for Configs<T> {
    fn default() -> Self {
        Configs::with_cap(usize::MAX)
    }
}

impl<T> Configs<T> {
    /// An empty map that keeps at most `cap` trees.
    pub(super) fn with_cap(cap: usize) -> Self {
        Configs {
            map: Mutex::new(Map::default()),
            len: AtomicUsize::new(0),
            cap,
        }
    }
}

impl<T: Keyed> Configs<T> {
    /// The tree of the cut-out `topo`, made by `make(topo, packed)` the first time (kept
    /// unless the map is full).
    pub(super) fn find(
        &self,
        topo: Topology,
        make: impl FnOnce(&Topology, PackedTopology) -> T,
    ) -> Arc<T> {
        let packed = PackedTopology::new(&topo);
        debug_assert!(
            {
                let (mut a, mut b) = (Vec::new(), Vec::new());
                topo.structure_key(&mut a);
                packed.unpack().structure_key(&mut b);
                a == b
            },
            "a packed cut-out unpacks to another topology"
        );
        let hash = {
            let mut h = FxHasher::default();
            packed.as_bytes().hash(&mut h);
            h.finish()
        };
        let mut map = lock(&self.map);
        let bucket = map.entry(hash).or_default();
        if let Some(tree) = bucket.iter().find(|t| *t.key() == packed) {
            return tree.clone();
        }
        let tree = Arc::new(make(&topo, packed));
        if self.len.load(Ordering::Relaxed) < self.cap {
            bucket.push(tree.clone());
            self.len.fetch_add(1, Ordering::Relaxed);
        }
        tree
    }

    /// Number of trees kept.
    pub(super) fn len(&self) -> usize {
        self.len.load(Ordering::Relaxed)
    }
}
