//! The environment methods (seed 002): lit by a panorama rather than a rectangle.

pub mod adaptive;
pub mod common;
pub mod picture;
pub mod pixels;
pub mod shadowmaps;
pub mod vertex;
