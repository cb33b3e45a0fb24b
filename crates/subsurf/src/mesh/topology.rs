//! (in progress)
/// Invalid index.
pub const INVALID: u32 = u32::MAX;
/// Vertex rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rule { /// smooth
 Smooth }
/// Vertex tag.
#[derive(Clone, Copy, Debug, Default)]
pub struct VertexTag;
/// Edge tag.
#[derive(Clone, Copy, Debug, Default)]
pub struct EdgeTag;
/// Topology.
#[derive(Clone, Debug, Default)]
pub struct Topology;
