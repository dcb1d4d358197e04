//! Compute stages, one module per kernel; CPU twins live in `compute::twin`.

pub mod shade;
pub mod twin;

/// Workgroups needed to cover `n` items with groups of `size` (the one place dispatch sizes are computed).
pub fn groups(n: u32, size: u32) -> u32 {
    n.div_ceil(size)
}

/// Workgroup sizes the Rust side dispatches with; a test asserts naga reads the same from each kernel.
pub const WORKGROUP_SIZES: &[(&str, &str, [u32; 3])] = &[("shade", "main", shade::WORKGROUP)];
