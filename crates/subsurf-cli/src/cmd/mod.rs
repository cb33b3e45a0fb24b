//! One module per subcommand; each turns its arguments into one library call.

pub mod bench;
pub mod demo;
pub mod info;
pub mod limit;
pub mod nurbs;
pub mod render;
pub mod subdivide;
pub mod tessellate;
