//! CPU twins of the compute kernels, written loop for loop like the WGSL with the same inputs.
//! Tests compare them with the GPU (exactly for counts).

pub mod shadow;
pub mod shade;
