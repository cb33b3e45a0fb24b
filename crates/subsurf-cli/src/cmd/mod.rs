//! One module per subcommand; each turns its arguments into one library call.

pub mod adjustable;
pub mod bench;
pub mod blend;
pub mod demo;
pub mod fill;
pub mod g2;
pub mod info;
pub mod interpolate;
pub mod limit;
pub mod nurbs;
pub mod regularity;
pub mod render;
pub mod repose;
pub mod spline;
pub mod subdivide;
pub mod tessellate;
