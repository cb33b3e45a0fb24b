//! The library's integration tests, as one test binary. Each module is one topic (one
//! former `tests/*.rs` file); `cargo test -p subsurf --test integration spline::` runs one.
//!
//! One binary links the library and its dependencies once instead of once per file, which
//! keeps a clean `cargo test` quick to link and small on disk. `tests/plan_no_alloc.rs` stays
//! a binary of its own: its counting global allocator would count the other tests'
//! allocations too.

mod common;

mod adjustable;
mod bilinear_limit_golden;
mod blend;
mod blend_rational;
mod cross_scheme;
mod fvar_golden;
mod fvar_limit_golden;
mod fvar_threads;
mod g2cap;
mod g2cap_iges;
mod g2cap_mixed;
mod gltf;
mod gltf_input;
mod interpolate;
mod interpolate_host;
mod interpolate_junctions;
mod limit_builder;
mod limit_golden;
mod limit_ngon_golden;
mod limit_second_derivatives;
mod limit_stencils;
mod loop_limit_golden;
mod mesh_input;
mod nurbs;
mod nurss;
mod nurss_fvar;
mod nurss_surface;
mod obj_groups;
mod obj_io;
mod osd_golden;
mod osd_golden_schemes;
mod ply_io;
mod properties;
mod regularity;
mod render;
mod replay;
mod spline;
mod tessellate;
