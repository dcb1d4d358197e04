//! The environment methods (seed 002): lit by a panorama rather than a rectangle.

pub(crate) mod adaptive;
pub(crate) mod common;
pub(crate) mod picture;
pub mod pixels;
pub mod shadowmaps;
pub(crate) mod vertex;
