//! Instancing: one loaded mesh placed many times (a herd, a grove) without repeating it in the file.
//! Each placement is applied after the mesh's own transform: world = placement · mesh transform.

use super::mesh_def::{GridDef, MeshDef};
use glam::{Mat4, Quat, Vec3};

/// Placements a scene may ask for in one `[[mesh]]` (a guard against a typo such as `count = [600, 600]`).
pub(crate) const MAX_INSTANCES: usize = 100_000;

/// The placements of a `[[mesh]]`: its `instances` list, its `grid`, or the identity once.
pub(crate) fn placements(m: &MeshDef) -> Result<Vec<Mat4>, String> {
    match (&m.instances, &m.grid) {
        (Some(_), Some(_)) => Err("give either `instances` or `grid`, not both".into()),
        (Some(list), None) => {
            if list.is_empty() {
                return Err("`instances` is empty".into());
            }
            if list.len() > MAX_INSTANCES {
                return Err(format!(
                    "{} instances (at most {MAX_INSTANCES})",
                    list.len()
                ));
            }
            list.iter()
                .enumerate()
                .map(|(k, &[x, y, z, rot, scale])| place(k, [x, y, z], rot, scale))
                .collect()
        }
        (None, Some(grid)) => grid_placements(grid),
        (None, None) => Ok(vec![Mat4::IDENTITY]),
    }
}

/// `count = [nx, nz]` cells `spacing = [dx, dz]` apart in the xz plane, centred on the origin;
/// instance k (row-major, x fastest) is turned `k · rotate_step_deg` about y, so a herd does not
/// all face one way, deterministically.
fn grid_placements(g: &GridDef) -> Result<Vec<Mat4>, String> {
    let [nx, nz] = g.count;
    if nx == 0 || nz == 0 {
        return Err(format!(
            "grid.count must be at least [1, 1], got [{nx}, {nz}]"
        ));
    }
    let total = nx as usize * nz as usize;
    if total > MAX_INSTANCES {
        return Err(format!(
            "grid of {total} instances (at most {MAX_INSTANCES})"
        ));
    }
    if !(g.spacing.iter().all(|s| s.is_finite()) && g.rotate_step_deg.is_finite()) {
        return Err("grid.spacing and grid.rotate_step_deg must be finite numbers".into());
    }
    let offset = |n: u32, i: u32, d: f32| (i as f32 - (n - 1) as f32 / 2.0) * d;
    let mut out = Vec::with_capacity(total);
    for j in 0..nz {
        for i in 0..nx {
            let k = out.len();
            let at = [
                offset(nx, i, g.spacing[0]),
                0.0,
                offset(nz, j, g.spacing[1]),
            ];
            out.push(place(k, at, k as f32 * g.rotate_step_deg, 1.0)?);
        }
    }
    Ok(out)
}

fn place(k: usize, at: [f32; 3], rot_y_deg: f32, scale: f32) -> Result<Mat4, String> {
    if !(at.iter().all(|v| v.is_finite()) && rot_y_deg.is_finite() && scale.is_finite()) {
        return Err(format!("instance {}: NaN or infinite number", k + 1));
    }
    // A negative scale would mirror the mesh and flip its winding (and its culling).
    if scale <= 0.0 {
        return Err(format!(
            "instance {}: scale must be positive, got {scale}",
            k + 1
        ));
    }
    Ok(Mat4::from_scale_rotation_translation(
        Vec3::splat(scale),
        Quat::from_rotation_y(rot_y_deg.to_radians()),
        Vec3::from(at),
    ))
}
