//! Uniform refinement: topology once ([`TopologyRefiner`]), then any number of primvars
//! through it ([`TopologyRefiner::interpolate`]); or, to re-pose the same mesh many times,
//! a precomputed [`RefinePlan`] (a sparse matrix per level, applied without any topology
//! or mask work).
//!
//! Topology refinement and interpolation run in parallel on the current rayon pool once a
//! level is large enough (tens of thousands of elements); the results are identical,
//! bit for bit, whatever the number of threads.
//!
//! ```
//! use subsurf::mesh::{Options, PolyMesh};
//! use subsurf::refine::TopologyRefiner;
//! use subsurf::Scheme;
//!
//! let quad = PolyMesh::from_faces(
//!     vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
//!     &[[0u32, 1, 2, 3]],
//! ).unwrap();
//! let mut r = TopologyRefiner::new(&quad, Scheme::CatmullClark, Options::default()).unwrap();
//! r.refine_uniform(2);
//! assert_eq!(r.level(2).num_faces(), 16);
//! // Refine positions, and a scalar (say, a temperature) on the same topology.
//! let pos = r.interpolate_all(quad.positions());
//! let temp = r.interpolate_all(&[[0.0], [1.0], [1.0], [0.0]]);
//! assert_eq!(pos.len(), r.level(2).num_vertices());
//! assert!(temp.iter().all(|t| (0.0..=1.0).contains(&t[0])));
//! ```

pub(crate) mod error;
mod face_varying;
mod loop_;
pub(crate) mod nurss;
pub(crate) mod patch;
pub(crate) mod plan;
mod plan_patches;
mod plan_ring;
mod primvar;
mod topology;
mod tri_topology;
pub(crate) mod uniform;

pub(crate) use error::Error;
pub use face_varying::FaceVaryingRefiner;
pub(crate) use loop_::check_triangles;
pub use loop_::interpolate_loop;
pub(crate) use plan::refinement_rows;
pub use plan::{PlanScratch, RefinePlan};
pub use primvar::{interpolate, interpolate_with};
pub(crate) use topology::{refine_topology, refine_topology_for_output};
pub(crate) use tri_topology::refine_tri_topology;

use crate::mesh::{Options, PolyMesh, Topology, TopologyWarning};
use crate::scheme::bilinear::Bilinear;
use crate::scheme::Scheme;
use uniform::Steps;

/// A base [`Topology`] and its uniform refinements with a scheme, level by level
/// (OpenSubdiv's `Far::TopologyRefiner`): the topology once, then any number of primvars
/// through it. Catmull-Clark, the adjustable scheme and bilinear split every face of size
/// `n` into `n` quads; Loop splits every triangle into four. NURSS, whose weights depend on
/// knot intervals refined with the topology, has its own refiner, [`Nurss`](crate::nonuniform::Nurss).
#[derive(Clone, Debug)]
pub struct TopologyRefiner {
    levels: Vec<Topology>,
    options: Options,
    steps: Steps,
    warnings: Vec<TopologyWarning>,
}

impl TopologyRefiner {
    /// Builds the base level of `mesh` (see [`Topology::from_mesh`]) for `scheme`.
    ///
    /// # Errors
    /// [`Error::Mesh`] from [`Topology::from_mesh`], or [`MeshError::NotTriangle`](crate::mesh::MeshError::NotTriangle) naming
    /// the first face that is not a triangle with Loop; [`Error::Unsupported`] for NURSS.
    pub fn new(mesh: &PolyMesh, scheme: Scheme, options: Options) -> Result<Self, Error> {
        let steps = Steps::of(scheme).ok_or(Error::Unsupported {
            what: "a TopologyRefiner (NURSS refines with nurss::Nurss)",
            scheme: scheme.name(),
        })?;
        if steps == Steps::Loop {
            loop_::check_triangles(mesh)?;
        }
        let options = steps.topology_options(&options);
        let (base, warnings) = Topology::from_mesh(mesh, &options)?;
        Ok(Self {
            levels: vec![base],
            options,
            steps,
            warnings,
        })
    }

    /// Refines until there are `levels` levels beyond the base.
    pub fn refine_uniform(&mut self, levels: u32) {
        while self.levels.len() <= levels as usize {
            self.refine_one();
        }
    }

    /// Adds one level.
    pub fn refine_one(&mut self) {
        let last = self.levels.last().expect("the base level always exists");
        let child = self.steps.refine(last, &self.options, true);
        self.levels.push(child);
    }

    /// The last level of [`refine_uniform`](Self::refine_uniform)`(levels)` (complete),
    /// holding no more than two levels at a time.
    pub(crate) fn into_level(mut self, levels: u32) -> Topology {
        for _ in 0..levels {
            self.refine_one();
            self.levels.swap_remove(0);
        }
        self.levels.swap_remove(0)
    }

    /// Level `i` (0 is the base).
    ///
    /// # Panics
    /// If `i > max_level()`.
    pub fn level(&self, i: usize) -> &Topology {
        &self.levels[i]
    }

    /// The deepest level refined so far.
    pub fn max_level(&self) -> usize {
        self.levels.len() - 1
    }

    /// Scheme options (for bilinear, as the topology was built: boundary mode `None` read
    /// as edge-only, [`Bilinear::topology_options`](crate::scheme::bilinear::Bilinear::topology_options)).
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Warnings about the base mesh.
    pub fn warnings(&self) -> &[TopologyWarning] {
        &self.warnings
    }

    /// Interpolates values from level `level - 1` to level `level` with the scheme's masks
    /// for that step.
    pub fn interpolate<const D: usize>(
        &self,
        level: usize,
        src: &[[f64; D]],
        dst: &mut [[f64; D]],
    ) {
        let (p, c, o) = (&self.levels[level - 1], &self.levels[level], &self.options);
        match self.steps {
            Steps::Family(m) if level as u64 <= u64::from(m.steps) => {
                primvar::interpolate_with(p, c, o, m.scheme, src, dst)
            }
            Steps::Family(_) => primvar::interpolate(p, c, o, src, dst),
            Steps::Bilinear => primvar::interpolate_with(p, c, o, Bilinear, src, dst),
            Steps::Loop => loop_::interpolate_loop(p, c, o, src, dst),
        }
    }

    /// Interpolates base-level values to the deepest level.
    pub fn interpolate_all<const D: usize>(&self, base: &[[f64; D]]) -> Vec<[f64; D]> {
        let mut cur = base.to_vec();
        for l in 1..self.levels.len() {
            let mut next = vec![[0.0; D]; self.levels[l].num_vertices()];
            self.interpolate(l, &cur, &mut next);
            cur = next;
        }
        cur
    }
}
