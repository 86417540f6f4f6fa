//! Drawings as SVG text: scenes, trajectories and demonstrations, and learned regions.
//!
//! A pure library: values in (scenes of `lamp-world`, trajectories of `lamp-trajectory`, sample
//! poses), text out. Every drawing has a top view (x–y) and a side view (x–z) side by side at one
//! scale, with a grid and ticks in metres, and is deterministic: the same input gives the same
//! bytes (numbers are written with two decimals, colours come from names, nothing is hashed with
//! a per-process seed).
//!
//! Shapes are drawn as the filled convex hull of their projected outline points, painted back to
//! front (`docs/rendering.md` has the conventions and examples).

mod colour;
mod error;
mod figure;
mod layout;
mod outline;
mod region;
mod replay;
mod scene;
pub mod svg;
mod trajectory;
mod view;

pub use error::RenderError;
pub use layout::RenderOptions;
pub use region::{RegionPlot, SampleSet, render_regions};
pub use replay::{GripperPath, Replay};
pub use scene::render_scene;
pub use trajectory::{render_motion, render_trajectory};
