//! What the pipeline needs of a caller's device. The per-stage binding counts, bind groups and
//! workgroup sizes are read from the kernels themselves with naga (compute pipelines use layouts
//! derived from the WGSL), so a new kernel cannot outgrow the check; the raster targets and the
//! vertex layout come from the Rust side that declares them.

use crate::gpu::kernels;
use crate::render::gbuffer::POSITION_FORMAT;
use crate::render::VERTEX_ATTRIBUTES;
use crate::scene::Vertex;
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// One limit the pipeline needs: wgpu's field name in [`wgpu::Limits`], the least value that works,
/// and the stage that needs the most.
#[derive(Clone, Debug)]
pub(crate) struct Need {
    pub limit: &'static str,
    pub value: u64,
    /// Who needs it, for the error message.
    pub why: String,
}

/// Every limit the kernels and raster passes need, computed once.
pub(crate) fn needs() -> &'static [Need] {
    static NEEDS: OnceLock<Vec<Need>> = OnceLock::new();
    NEEDS.get_or_init(compute)
}

fn compute() -> Vec<Need> {
    // limit name → (value, who needs it); the largest wins.
    let mut most: BTreeMap<&'static str, (u64, String)> = BTreeMap::new();
    let mut need = |limit: &'static str, value: u64, why: String| {
        let e = most.entry(limit).or_insert((0, String::new()));
        if value > e.0 {
            *e = (value, why);
        }
    };
    // The G-buffer: position, geometric normal and shading normal, one Rgba32Float target each.
    const GBUFFER_TARGETS: u64 = 3;
    let bytes = POSITION_FORMAT.target_pixel_byte_cost().unwrap_or(16) as u64;
    need(
        "max_color_attachments",
        GBUFFER_TARGETS,
        "the G-buffer's three targets".into(),
    );
    need(
        "max_color_attachment_bytes_per_sample",
        GBUFFER_TARGETS * bytes,
        format!("the G-buffer's three {POSITION_FORMAT:?} targets"),
    );
    need("max_vertex_buffers", 1, "the scene's vertex buffer".into());
    need(
        "max_vertex_attributes",
        VERTEX_ATTRIBUTES.len() as u64,
        "the scene's vertex (position, normal, material)".into(),
    );
    need(
        "max_vertex_buffer_array_stride",
        std::mem::size_of::<Vertex>() as u64,
        "the scene's vertex".into(),
    );

    for (stage, kernel) in kernels::all() {
        for &maps in kernels::MapAccess::forms(&kernel) {
            // A kernel that does not validate fails at pipeline creation with naga's message.
            let Ok((module, info)) = kernels::validate_for(stage.name, maps) else {
                continue;
            };
            let mut layouter = naga::proc::Layouter::default();
            if layouter.update(module.to_ctx()).is_err() {
                continue;
            }
            for (i, ep) in module.entry_points.iter().enumerate() {
                let uses = info.get_entry_point(i);
                let who = format!("kernel `{}` entry `{}`", stage.name, ep.name);
                let mut count: BTreeMap<&'static str, u64> = BTreeMap::new();
                let mut groups: BTreeMap<u32, u32> = BTreeMap::new();
                let mut workgroup_bytes = 0u64;
                for (handle, var) in module.global_variables.iter() {
                    if uses[handle].is_empty() {
                        continue;
                    }
                    if let Some(b) = &var.binding {
                        let top = groups.entry(b.group).or_insert(0);
                        *top = (*top).max(b.binding + 1);
                    }
                    let kind = match var.space {
                        naga::AddressSpace::Uniform => Some("max_uniform_buffers_per_shader_stage"),
                        naga::AddressSpace::Storage { .. } => {
                            Some("max_storage_buffers_per_shader_stage")
                        }
                        naga::AddressSpace::Handle => match module.types[var.ty].inner {
                            naga::TypeInner::Image {
                                class: naga::ImageClass::Storage { .. },
                                ..
                            } => Some("max_storage_textures_per_shader_stage"),
                            naga::TypeInner::Image { .. } => {
                                Some("max_sampled_textures_per_shader_stage")
                            }
                            naga::TypeInner::Sampler { .. } => {
                                Some("max_samplers_per_shader_stage")
                            }
                            _ => None,
                        },
                        naga::AddressSpace::WorkGroup => {
                            // Rounded up to 16 bytes each, as WGSL's workgroup storage is laid out.
                            workgroup_bytes += (layouter[var.ty].size as u64).div_ceil(16) * 16;
                            None
                        }
                        _ => None,
                    };
                    if let Some(k) = kind {
                        *count.entry(k).or_insert(0) += 1;
                    }
                }
                for (k, n) in count {
                    need(k, n, who.clone());
                }
                if let Some((&g, _)) = groups.last_key_value() {
                    need("max_bind_groups", g as u64 + 1, who.clone());
                }
                if let Some(&b) = groups.values().max() {
                    need("max_bindings_per_bind_group", b as u64, who.clone());
                }
                if ep.stage == naga::ShaderStage::Compute {
                    let [x, y, z] = ep.workgroup_size.map(u64::from);
                    need("max_compute_workgroup_size_x", x, who.clone());
                    need("max_compute_workgroup_size_y", y, who.clone());
                    need("max_compute_workgroup_size_z", z, who.clone());
                    need(
                        "max_compute_invocations_per_workgroup",
                        x * y * z,
                        who.clone(),
                    );
                    need(
                        "max_compute_workgroup_storage_size",
                        workgroup_bytes,
                        who.clone(),
                    );
                }
            }
        }
    }
    most.into_iter()
        .filter(|(_, (v, _))| *v > 0)
        .map(|(limit, (value, why))| Need { limit, value, why })
        .collect()
}

/// The value of the `max_*` limit `name` in `l` (every name [`compute`] emits).
pub(crate) fn limit(l: &wgpu::Limits, name: &str) -> Option<u64> {
    Some(match name {
        "max_color_attachments" => l.max_color_attachments as u64,
        "max_color_attachment_bytes_per_sample" => l.max_color_attachment_bytes_per_sample as u64,
        "max_vertex_buffers" => l.max_vertex_buffers as u64,
        "max_vertex_attributes" => l.max_vertex_attributes as u64,
        "max_vertex_buffer_array_stride" => l.max_vertex_buffer_array_stride as u64,
        "max_uniform_buffers_per_shader_stage" => l.max_uniform_buffers_per_shader_stage as u64,
        "max_storage_buffers_per_shader_stage" => l.max_storage_buffers_per_shader_stage as u64,
        "max_storage_textures_per_shader_stage" => l.max_storage_textures_per_shader_stage as u64,
        "max_sampled_textures_per_shader_stage" => l.max_sampled_textures_per_shader_stage as u64,
        "max_samplers_per_shader_stage" => l.max_samplers_per_shader_stage as u64,
        "max_bind_groups" => l.max_bind_groups as u64,
        "max_bindings_per_bind_group" => l.max_bindings_per_bind_group as u64,
        "max_compute_workgroup_size_x" => l.max_compute_workgroup_size_x as u64,
        "max_compute_workgroup_size_y" => l.max_compute_workgroup_size_y as u64,
        "max_compute_workgroup_size_z" => l.max_compute_workgroup_size_z as u64,
        "max_compute_invocations_per_workgroup" => l.max_compute_invocations_per_workgroup as u64,
        "max_compute_workgroup_storage_size" => l.max_compute_workgroup_storage_size as u64,
        _ => return None,
    })
}

/// `l` with `name` raised to at least `value`.
fn raise(l: &mut wgpu::Limits, name: &str, value: u64) {
    let v = u32::try_from(value).unwrap_or(u32::MAX);
    let field = match name {
        "max_color_attachments" => &mut l.max_color_attachments,
        "max_color_attachment_bytes_per_sample" => &mut l.max_color_attachment_bytes_per_sample,
        "max_vertex_buffers" => &mut l.max_vertex_buffers,
        "max_vertex_attributes" => &mut l.max_vertex_attributes,
        "max_vertex_buffer_array_stride" => &mut l.max_vertex_buffer_array_stride,
        "max_uniform_buffers_per_shader_stage" => &mut l.max_uniform_buffers_per_shader_stage,
        "max_storage_buffers_per_shader_stage" => &mut l.max_storage_buffers_per_shader_stage,
        "max_storage_textures_per_shader_stage" => &mut l.max_storage_textures_per_shader_stage,
        "max_sampled_textures_per_shader_stage" => &mut l.max_sampled_textures_per_shader_stage,
        "max_samplers_per_shader_stage" => &mut l.max_samplers_per_shader_stage,
        "max_bind_groups" => &mut l.max_bind_groups,
        "max_bindings_per_bind_group" => &mut l.max_bindings_per_bind_group,
        "max_compute_workgroup_size_x" => &mut l.max_compute_workgroup_size_x,
        "max_compute_workgroup_size_y" => &mut l.max_compute_workgroup_size_y,
        "max_compute_workgroup_size_z" => &mut l.max_compute_workgroup_size_z,
        "max_compute_invocations_per_workgroup" => &mut l.max_compute_invocations_per_workgroup,
        "max_compute_workgroup_storage_size" => &mut l.max_compute_workgroup_storage_size,
        _ => return,
    };
    *field = (*field).max(v);
}

/// `base` raised wherever it is below a need.
pub(crate) fn raised(mut base: wgpu::Limits) -> wgpu::Limits {
    for n in needs() {
        raise(&mut base, n.limit, n.value);
    }
    base
}

/// Every need `have` falls short of, as `name = have (needs value: why)`.
pub(crate) fn shortfalls(have: &wgpu::Limits) -> Vec<String> {
    needs()
        .iter()
        .filter_map(|n| {
            let got = limit(have, n.limit)?;
            (got < n.value).then(|| format!("{} = {got} (needs {}: {})", n.limit, n.value, n.why))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_need_is_a_known_limit_and_raising_meets_it() {
        let needs = needs();
        assert!(
            needs
                .iter()
                .any(|n| n.limit == "max_storage_buffers_per_shader_stage"),
            "{needs:?}"
        );
        for n in needs {
            assert!(
                limit(&wgpu::Limits::default(), n.limit).is_some(),
                "unknown limit {}",
                n.limit
            );
        }
        let low = wgpu::Limits::downlevel_webgl2_defaults();
        assert!(!shortfalls(&low).is_empty());
        assert!(shortfalls(&raised(low)).is_empty());
    }
}
