//! Coordinates a scene may hold: finite, and small enough that f32 projections keep precision.
//! Every part of the scene format checks its points here.

use crate::{Error, Result};
use glam::Vec3;

/// Scene coordinates beyond this lose all precision in f32 projections (and overflow products).
pub const MAX_COORDINATE: f32 = 1e6;

/// `v` as a point, or one line naming `what` when a coordinate is not finite or too large.
pub(super) fn finite<const N: usize>(origin: &str, what: &str, v: [f32; N]) -> Result<Vec3> {
    if v.iter().any(|x| !x.is_finite()) {
        return Err(Error::scene(
            origin,
            format!("{what} has a NaN or infinite coordinate: {v:?}"),
        ));
    }
    if v.iter().any(|x| x.abs() > MAX_COORDINATE) {
        return Err(Error::scene(origin, format!("{what} = {v:?}: coordinates must be within ±{MAX_COORDINATE:e} (f32 has no precision left beyond)")));
    }
    Ok(Vec3::from_slice(&[
        v[0],
        *v.get(1).unwrap_or(&0.0),
        *v.get(2).unwrap_or(&0.0),
    ]))
}
