//! CPU ray-traced ground truth for rectangular area-light visibility (method.md §1, §5).
//!
//! `V(p)` = fraction of light sample points `y` with `vis(p, y) = 1`, where `vis = 0` when
//! - `p` is on or behind the light's plane (`(p - c)·n <= 0`),
//! - `y` is on or below `p`'s tangent plane (`normal·(y - p) <= 0`: the surface blocks itself),
//! - or the segment from `p` (offset by `ray_offset` along the normal, towards `y`'s side) to `y`
//!   hits any triangle at `t ∈ (0, dist·(1 - LIGHT_END_EPS))`. Triangles are two-sided, edges closed.
//!
//! Samples: [`ReferenceMode::Lattice`] (the 289 points `s = i/16, t = j/16` that a perfect 17×17
//! shadow-map method sees), [`ReferenceMode::Continuous`] (m×m stratified jitter, decorrelated
//! per pixel) or [`ReferenceMode::Point`] (one light point: the exact hard shadow a perfect map
//! from that point gives, so V is 0 or 1). The analytic square scene (`analytic.rs`) validates both.
//! The other light kinds (disk, sun, the sphere of a spot or point) map the same unit-square
//! samples onto their own disk (`emitter.rs`, docs/lights.md); `analytic_lights.rs` holds their
//! closed forms.

pub(crate) mod analytic;
pub mod analytic_lights;
pub(crate) mod cache;
pub mod emitter;
pub mod environment;
pub mod sampling;
pub(crate) mod tracer;
pub mod truth;
pub(crate) mod visibility;

#[cfg(test)]
mod tests;

use glam::Vec3;

pub use analytic::{
    analytic_lattice_margin, analytic_lattice_visibility, analytic_square_visibility,
    AnalyticSquareScene,
};
pub use cache::{
    cache_key, cache_path, load_cached, lock, parse as parse_cache_file, reference_key,
    save_cached, CacheEntry, CacheLock, Lookup, REFERENCE_VERSION,
};
pub use emitter::{try_trace_emitter, RefEmitter};
pub use tracer::{Hit, Tracer};
pub use visibility::{point_visibility, trace_visibility, try_trace_visibility, LIGHT_END_EPS};

/// Rectangular area light: `y(s,t) = center + (s-½)·edge_u + (t-½)·edge_v`, emitting on the side of
/// `normalize(edge_u × edge_v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefLight {
    pub center: Vec3,
    pub edge_u: Vec3,
    pub edge_v: Vec3,
}

impl RefLight {
    /// Light point at `(s, t) ∈ [0,1]²`.
    #[inline]
    pub fn point(&self, s: f32, t: f32) -> Vec3 {
        self.center + (s - 0.5) * self.edge_u + (t - 0.5) * self.edge_v
    }

    /// Unit emission normal, or an error for a degenerate or non-finite light.
    pub fn normal(&self) -> Result<Vec3, ReferenceError> {
        let finite = self.center.is_finite() && self.edge_u.is_finite() && self.edge_v.is_finite();
        let n = self.edge_u.cross(self.edge_v).normalize_or_zero();
        if !finite || n == Vec3::ZERO {
            return Err(ReferenceError::DegenerateLight);
        }
        Ok(n)
    }
}

/// A visible surface point from the G-buffer. `normal` should face the viewer (the lit side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    pub position: Vec3,
    pub normal: Vec3,
}

/// Which light points `V` averages over.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceMode {
    /// The (2^4+1)² = 289 lattice points `s = i/16`, `t = j/16` (method.md §3).
    Lattice,
    /// m×m stratified jittered samples; the jitter is a deterministic hash of `(seed, pixel index)`
    /// so neighbouring pixels do not share one pattern (which would print the strata as banding).
    Continuous { m: u32, seed: u64 },
    /// One light point `(s, t) ∈ [0,1]²` (the centre is (0.5, 0.5)): exact hard-shadow visibility.
    Point { s: f32, t: f32 },
}

impl ReferenceMode {
    /// The documented default: 32×32 samples, fixed seed.
    pub const DEFAULT_CONTINUOUS: ReferenceMode = ReferenceMode::Continuous {
        m: 32,
        seed: 0x5eed,
    };

    /// Samples per pixel (rays per pixel at most).
    pub fn samples_per_pixel(&self) -> usize {
        match *self {
            ReferenceMode::Lattice => sampling::LATTICE_POINTS,
            ReferenceMode::Continuous { m, .. } => (m as usize) * (m as usize),
            ReferenceMode::Point { .. } => 1,
        }
    }

    /// Bytes that identify the mode in a cache key.
    pub fn key_bytes(&self) -> Vec<u8> {
        match *self {
            ReferenceMode::Lattice => b"lattice".to_vec(),
            ReferenceMode::Continuous { m, seed } => {
                let mut v = b"continuous".to_vec();
                v.extend_from_slice(&m.to_le_bytes());
                v.extend_from_slice(&seed.to_le_bytes());
                v
            }
            ReferenceMode::Point { s, t } => {
                let mut v = b"point".to_vec();
                v.extend_from_slice(&s.to_le_bytes());
                v.extend_from_slice(&t.to_le_bytes());
                v
            }
        }
    }
}

/// Errors of this module (wrapped by the crate's `Error::Reference`).
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// `edge_u × edge_v` is zero or a light field is not finite.
    #[error("area light is degenerate (zero area) or not finite")]
    DegenerateLight,
    /// `Continuous { m: 0, .. }`: no samples.
    #[error("continuous reference needs m >= 1")]
    NoSamples,
    /// A buffer's length is not `width × height`.
    #[error("buffer has {got} values, image needs {expected}")]
    SizeMismatch { expected: usize, got: usize },
    #[error("reference cache: {0}")]
    Io(#[from] std::io::Error),
    /// A cache file that exists but cannot be read: refused rather than overwritten unseen.
    #[error("cannot read the reference cache file {}: {source}; remove it, or run with --no-cache to trace the reference without the cache", path.display())]
    CacheRead {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    #[error("cannot write the reference cache file {}: {source}", path.display())]
    CacheWrite {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
}

pub use crate::scene::rays::{env_ray_length, ray_offset, RELATIVE_RAY_OFFSET};
