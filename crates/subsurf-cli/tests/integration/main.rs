//! End-to-end tests of the `subsurf` binary, as one test binary. Each module is one topic
//! (one subcommand or concern); `cargo test -p subsurf-cli --test integration cli::` runs one.
//!
//! One test binary instead of one per file links once, which keeps a clean `cargo test`
//! quick to link and small on disk.

mod common;

mod adjustable;
mod bad_inputs;
mod blend;
mod cli;
mod crease_angle;
mod demo;
mod g2;
mod gltf;
mod input_formats;
mod interpolate;
mod interpolate_host;
mod limit;
mod nurbs_files;
mod nurss;
mod regularity;
mod render;
mod repose;
mod schemes;
mod signals;
mod spline;
mod tessellate;
