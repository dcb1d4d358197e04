//! No GPU needed: every kernel parses and validates with naga, the Rust `Gpu*` structs match the
//! WGSL layouts member by member, and Rust dispatches with the workgroup sizes the kernels declare.

use penumbra::gpu::kernels::{self, KERNELS};
use penumbra::gpu::structs::all_layouts;

#[test]
fn every_kernel_validates_with_naga() {
    let errors: Vec<String> = KERNELS.iter().filter_map(|k| kernels::validate(k.name).err().map(|e| e.to_string())).collect();
    assert!(KERNELS.len() >= 3, "kernel registry is unexpectedly small");
    assert!(errors.is_empty(), "{} kernel(s) failed naga validation:\n{}", errors.len(), errors.join("\n"));
}

#[test]
fn map_reading_kernels_validate_for_hybrid_maps() {
    use penumbra::scene::MapKind;
    let readers: Vec<&str> = KERNELS.iter().filter(|k| k.reads_maps).map(|k| k.name).collect();
    assert_eq!(readers, ["shade", "shadow_test", "pcf", "pcss"], "the kernels that read maps through map_depth");
    let errors: Vec<String> = readers.iter().filter_map(|k| kernels::validate_for(k, MapKind::Hybrid).err().map(|e| e.to_string())).collect();
    assert!(errors.is_empty(), "hybrid forms failed naga validation:\n{}", errors.join("\n"));
    assert!(kernels::source_for("moments", MapKind::Hybrid).is_err(), "a kernel reading the raster directly has no hybrid form");
    // The hybrid form reads a u32 pool where the plain one reads a depth array, at the same binding.
    let (module, _) = kernels::validate_for("shade", MapKind::Hybrid).unwrap();
    let maps = module.global_variables.iter().find(|(_, g)| g.name.as_deref() == Some("shadow_maps")).unwrap().1;
    assert!(matches!(
        module.types[maps.ty].inner,
        naga::TypeInner::Image { dim: naga::ImageDimension::D2, arrayed: false, class: naga::ImageClass::Sampled { kind: naga::ScalarKind::Uint, .. } }
    ));
}

#[test]
fn hybrid_constants_match_rust() {
    use penumbra::stages::hybrid_build::{CHILDREN, FRAME_LEVELS_SHIFT, POOL_WIDTH_LOG2};
    use penumbra::scene::MapKind;
    let constant = |kernel: &str, maps: MapKind, name: &str| -> u32 {
        let (module, _) = kernels::validate_for(kernel, maps).unwrap();
        let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("{kernel}: no `{name}`"));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref e => panic!("{kernel}: `{name}` is {e:?}"),
        }
    };
    for (kernel, maps) in [("shade", MapKind::Hybrid), ("hybrid_build", MapKind::Plain)] {
        assert_eq!(constant(kernel, maps, "HYBRID_POOL_WIDTH_LOG2"), POOL_WIDTH_LOG2, "{kernel}");
        assert_eq!(constant(kernel, maps, "HYBRID_CHILDREN"), CHILDREN, "{kernel}");
    }
    assert_eq!(constant("shade", MapKind::Hybrid, "FRAME_HYBRID_LEVELS_SHIFT"), FRAME_LEVELS_SHIFT);
}

#[test]
fn block_constants_match_rust() {
    use penumbra::stages::shadow_test::{TEST_BLOCK, TEST_SLOTS, TEST_TAILS};
    let constant = |kernel: &str, name: &str| -> u32 {
        let (module, _) = kernels::validate(kernel).unwrap();
        let (_, c) = module.constants.iter().find(|(_, c)| c.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("{kernel}: no `{name}`"));
        match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref e => panic!("{kernel}: `{name}` is {e:?}"),
        }
    };
    assert_eq!(constant("shade", "SHADE_BLOCK"), penumbra::stages::shade::SHADE_BLOCK);
    assert_eq!(constant("shadow_test", "TEST_BLOCK"), TEST_BLOCK);
    assert_eq!(constant("shadow_test", "TEST_SLOTS"), TEST_SLOTS);
    assert_eq!(constant("shadow_test", "TEST_TAILS"), TEST_TAILS.len() as u32);
    // The tails halve from half a block down to one sample, as fill_blocks places them.
    assert_eq!(TEST_TAILS, [TEST_BLOCK / 2, TEST_BLOCK / 4, TEST_BLOCK / 8, TEST_BLOCK / 16]);
    // One entry point per block size, each unrolling exactly its size.
    let (module, _) = kernels::validate("shadow_test").unwrap();
    for size in std::iter::once(TEST_BLOCK).chain(TEST_TAILS) {
        let entry = module.entry_points.iter().find(|e| e.name == format!("block{size}")).unwrap_or_else(|| panic!("no `block{size}`"));
        let calls = entry.function.body.iter().filter(|s| matches!(s, naga::Statement::Call { function, .. } if module.functions[*function].name.as_deref() == Some("test_sample"))).count();
        assert_eq!(calls as u32, size, "block{size} calls test_sample {calls} times");
    }
}

#[test]
fn rust_structs_match_wgsl_layouts() {
    let mut problems = Vec::new();
    let mut checked = 0;
    for layout in all_layouts() {
        // Find the struct in the first kernel that declares it (the prelude is in every kernel).
        let mut found = false;
        for k in KERNELS {
            let (module, _) = kernels::validate(k.name).expect("kernel validates");
            let Some(ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(layout.name)) else { continue };
            found = true;
            let naga::TypeInner::Struct { members, span } = &ty.1.inner else {
                problems.push(format!("{}: not a struct in WGSL", layout.name));
                break;
            };
            if *span as usize != layout.size {
                problems.push(format!("{}: size {} in Rust, {} in WGSL", layout.name, layout.size, span));
            }
            if members.len() != layout.members.len() {
                problems.push(format!("{}: {} members in Rust, {} in WGSL", layout.name, layout.members.len(), members.len()));
            }
            for (m, (name, offset)) in members.iter().zip(&layout.members) {
                let wgsl_name = m.name.as_deref().unwrap_or("?");
                if wgsl_name != *name || m.offset as usize != *offset {
                    problems.push(format!(
                        "{}: Rust `{name}` at offset {offset}, WGSL `{wgsl_name}` at offset {}",
                        layout.name, m.offset
                    ));
                }
            }
            checked += 1;
            break;
        }
        if !found {
            problems.push(format!("{}: no kernel declares it", layout.name));
        }
    }
    assert!(problems.is_empty(), "layout mismatches:\n{}", problems.join("\n"));
    assert!(checked >= 4, "only {checked} structs checked");
}

#[test]
fn dispatch_sizes_match_kernel_workgroup_sizes() {
    for (kernel, entry, size) in penumbra::stages::WORKGROUP_SIZES {
        let declared = kernels::workgroup_size(kernel, entry).expect("kernel has the entry point");
        assert_eq!(declared, *size, "{kernel}::{entry}: Rust dispatches with {size:?}, WGSL declares {declared:?}");
    }
}
