//! Twin of `kernels/shared/common.wgsl`: `shadow_lookup` and `shadow_compare`, same operation order.

use crate::gpu::structs::{GpuFrame, GpuSample};
use glam::{Mat4, Vec2, Vec3, Vec4};

pub use crate::gpu::structs::{FRAME_EVERY_WAY, FRAME_FACING_TEST};

pub const LOOKUP_UNLIT: u32 = 0;
pub const LOOKUP_OUTSIDE: u32 = 1;
pub const LOOKUP_COMPARE: u32 = 2;

#[derive(Clone, Copy, Debug)]
pub struct ShadowLookup {
    pub texel: [i32; 2],
    pub kind: u32,
    pub depth_limit: f32,
}

pub fn shadow_lookup(frame: &GpuFrame, s: &GpuSample, p: Vec3, n: Vec3) -> ShadowLookup {
    let mut out = ShadowLookup {
        texel: [0, 0],
        kind: LOOKUP_UNLIT,
        depth_limit: 0.0,
    };
    let to_light = toward_light(s, p);
    let light_side = (p - Vec4::from(frame.light_center).truncate())
        .dot(Vec4::from(frame.light_normal).truncate());
    let facing = n.dot(to_light);
    let other_face = s.cube_face != 0
        && cube_face(p - Vec4::from(frame.light_center).truncate()) + 1 != s.cube_face;
    if (light_side <= 0.0 && frame.flags & FRAME_EVERY_WAY == 0)
        || (facing <= 0.0 && frame.flags & FRAME_FACING_TEST != 0)
        || other_face
    {
        return out;
    }
    let m = Mat4::from_cols_array_2d(&s.light_from_world);
    let depth = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w).dot(Vec4::from((p, 1.0)));
    let texel_world = depth * s.texel_angle;
    let q = p + n * (frame.normal_offset * texel_world);
    let clip = m * Vec4::from((q, 1.0));
    let size = frame.map_size as f32;
    let uv = Vec2::new(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
    let t = if s.cube_face != 0 {
        (uv * size)
            .floor()
            .clamp(Vec2::ZERO, Vec2::splat(size - 1.0))
    } else {
        (uv * size).floor()
    };
    if clip.w <= 0.0 || t.x < 0.0 || t.y < 0.0 || t.x >= size || t.y >= size {
        out.kind = LOOKUP_OUTSIDE;
        return out;
    }
    let cos_angle = facing.abs() / to_light.length();
    let tan_angle =
        ((1.0 - cos_angle * cos_angle).max(0.0).sqrt() / cos_angle.max(1e-6)).min(frame.max_slope);
    out.kind = LOOKUP_COMPARE;
    out.texel = [t.x as i32, t.y as i32];
    let linear = if s.orthographic != 0 {
        s.depth_lin_a * clip.z + s.depth_lin_b
    } else {
        clip.w
    };
    out.depth_limit = linear - texel_world * (frame.bias_constant + frame.bias_slope * tan_angle);
    out
}

/// Twin of `cube_face` (the reference picks its light points' face by the same rule).
pub use crate::scene::emitter::cube_face;

/// Twin of `face_offset`: which of a point light's six consecutive faces holds `p`, by its
/// direction from the sphere's centre (0 for any other sample).
pub fn face_offset(frame: &GpuFrame, s: &GpuSample, p: Vec3) -> usize {
    if s.cube_face != 0 {
        cube_face(p - Vec4::from(frame.light_center).truncate()) as usize
    } else {
        0
    }
}

/// Twin of `toward_light`: to the light point, or the orthographic map's direction.
pub fn toward_light(s: &GpuSample, p: Vec3) -> Vec3 {
    Vec4::from(s.position).truncate() - p * s.position[3]
}

/// Twin of `depth_passes`: linear depth `limit` at or in front of stored depth `stored`.
pub fn depth_passes(s: &GpuSample, limit: f32, stored: f32) -> bool {
    if s.orthographic != 0 {
        limit <= s.depth_lin_a * stored + s.depth_lin_b
    } else {
        limit * (stored + s.depth_lin_b) >= s.depth_lin_a
    }
}

pub fn shadow_compare(s: &GpuSample, lookup: &ShadowLookup, stored: f32) -> u32 {
    match lookup.kind {
        LOOKUP_UNLIT => 0,
        LOOKUP_OUTSIDE => 1,
        _ => depth_passes(s, lookup.depth_limit, stored) as u32,
    }
}

/// lit_i(p) given the sample's map (row-major, `map_size²` depths).
pub fn lit(frame: &GpuFrame, s: &GpuSample, map: &[f32], p: Vec3, n: Vec3) -> u32 {
    let lookup = shadow_lookup(frame, s, p, n);
    let stored = map[(lookup.texel[1] * frame.map_size as i32 + lookup.texel[0]) as usize];
    shadow_compare(s, &lookup, stored)
}

/// Twin of `shadow_lookup_uv`: the continuous texel coordinate `shadow_lookup` floors.
pub fn shadow_lookup_uv(frame: &GpuFrame, s: &GpuSample, p: Vec3, n: Vec3) -> Vec2 {
    let m = Mat4::from_cols_array_2d(&s.light_from_world);
    let depth = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w).dot(Vec4::from((p, 1.0)));
    let texel_world = depth * s.texel_angle;
    let q = p + n * (frame.normal_offset * texel_world);
    let clip = m * Vec4::from((q, 1.0));
    let uv = Vec2::new(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
    uv * frame.map_size as f32
}

/// Twin of `slope_per_texel`: world depth change per texel of offset along p's tangent plane.
pub fn slope_per_texel(frame: &GpuFrame, s: &GpuSample, p: Vec3, n: Vec3) -> f32 {
    let to_light = toward_light(s, p);
    let m = Mat4::from_cols_array_2d(&s.light_from_world);
    let depth = Vec4::new(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w).dot(Vec4::from((p, 1.0)));
    let cos_angle = n.dot(to_light).abs() / to_light.length();
    let tan_angle =
        ((1.0 - cos_angle * cos_angle).max(0.0).sqrt() / cos_angle.max(1e-6)).min(frame.max_slope);
    depth * s.texel_angle * tan_angle
}

/// Twin of `tap_lit`: one tap at continuous texel coordinate `t`; outside the map counts as lit.
pub fn tap_lit(frame: &GpuFrame, s: &GpuSample, map: &[f32], limit: f32, t: Vec2) -> f32 {
    let size = frame.map_size as f32;
    let texel = if s.cube_face != 0 {
        t.floor().clamp(Vec2::ZERO, Vec2::splat(size - 1.0))
    } else {
        t.floor()
    };
    if texel.x < 0.0 || texel.y < 0.0 || texel.x >= size || texel.y >= size {
        return 1.0;
    }
    let stored = map[(texel.y as usize) * frame.map_size as usize + texel.x as usize];
    if depth_passes(s, limit, stored) {
        1.0
    } else {
        0.0
    }
}

/// Twin of `pcg_hash`.
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// Twin of `pixel_random`: uniform in [0, 1) from pixel (x, y) and tap i.
pub fn pixel_random(x: u32, y: u32, i: u32) -> f32 {
    (pcg_hash(x ^ pcg_hash(y ^ pcg_hash(i))) >> 8) as f32 / 16777216.0
}

/// Where a geometry pixel of `g` lands in the map: None for background, else (lookup, uv, slope
/// per texel).
pub fn pixel_lookup(
    frame: &GpuFrame,
    s: &GpuSample,
    g: &crate::render::gbuffer::GBufferCpu,
    index: usize,
) -> Option<(ShadowLookup, Vec2, f32)> {
    if !g.is_geometry(index) {
        return None;
    }
    let p = Vec4::from(g.position[index]).truncate();
    let n = Vec4::from(g.normal[index]).truncate();
    Some((
        shadow_lookup(frame, s, p, n),
        shadow_lookup_uv(frame, s, p, n),
        slope_per_texel(frame, s, p, n),
    ))
}

/// The one-map kernels (pcf, pcss) on a point light's cube: each pixel takes what `one` computes
/// on the face that holds it, as the kernels read `samples[face_offset(samples[0], p)]`.
pub fn by_face(
    frame: &GpuFrame,
    faces: &[GpuSample],
    maps: &[Vec<f32>],
    g: &crate::render::gbuffer::GBufferCpu,
    one: impl Fn(&GpuSample, &[f32]) -> Vec<f32>,
) -> Vec<f32> {
    let per: Vec<Vec<f32>> = faces.iter().zip(maps).map(|(s, m)| one(s, m)).collect();
    (0..g.position.len())
        .map(|i| per[face_offset(frame, &faces[0], Vec4::from(g.position[i]).truncate())][i])
        .collect()
}
