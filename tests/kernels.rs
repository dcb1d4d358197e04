//! No GPU needed: every kernel parses and validates with naga, the Rust `Gpu*` structs match the
//! WGSL layouts member by member, the stage table's entry points, workgroup sizes and bindings are
//! the kernels', and every constant mirrored between Rust and WGSL has the same value on both sides.

use penumbra::research::gpu::kernels;
use penumbra::research::gpu::kernels::MapAccess;
use penumbra::research::gpu::structs::all_layouts;
use std::collections::BTreeSet;

#[test]
fn every_kernel_validates_with_naga() {
    let errors: Vec<String> = kernels::all()
        .filter_map(|(s, _)| kernels::validate(s.name).err().map(|e| e.to_string()))
        .collect();
    assert!(
        kernels::all().count() >= 3,
        "kernel registry is unexpectedly small"
    );
    assert!(
        errors.is_empty(),
        "{} kernel(s) failed naga validation:\n{}",
        errors.len(),
        errors.join("\n")
    );
}

#[test]
fn map_reading_kernels_validate_for_every_map_access() {
    let readers: Vec<&str> = kernels::all()
        .filter(|(_, k)| k.reads_maps)
        .map(|(s, _)| s.name)
        .collect();
    assert_eq!(
        readers,
        [
            "shade",
            "estimate",
            "shadow_test",
            "pcf",
            "cascades",
            "pcss",
            "regions"
        ],
        "the kernels that read maps through map_depth"
    );
    let raster_readers: Vec<&str> = kernels::all()
        .filter(|(_, k)| k.reads_raster)
        .map(|(s, _)| s.name)
        .collect();
    assert_eq!(
        raster_readers,
        ["moments", "env_shadowmaps", "hybrid_build"],
        "the kernels that read the raster's layers through layer_depth"
    );
    let mut errors = Vec::new();
    for k in &readers {
        for access in [MapAccess::Words, MapAccess::Hybrid] {
            errors.extend(
                kernels::validate_for(k, access)
                    .err()
                    .map(|e| format!("{k} ({access:?}): {e}")),
            );
        }
    }
    for k in &raster_readers {
        errors.extend(
            kernels::validate_for(k, MapAccess::Words)
                .err()
                .map(|e| format!("{k} (Words): {e}")),
        );
    }
    assert!(
        errors.is_empty(),
        "map access forms failed naga validation:\n{}",
        errors.join("\n")
    );
    assert!(
        kernels::source_for("moments", MapAccess::Hybrid).is_err(),
        "a kernel reading the raster has no hybrid form"
    );
    assert!(
        kernels::source_for("gbuffer", MapAccess::Words).is_err(),
        "a kernel reading no maps has one form"
    );
    // The same binding holds a depth array, an R32Uint array of depth bits, or the hybrid u32 pool.
    let image = |access| {
        let (module, _) = kernels::validate_for("shade", access).unwrap();
        let maps = module
            .global_variables
            .iter()
            .find(|(_, g)| g.name.as_deref() == Some("shadow_maps"))
            .unwrap()
            .1;
        module.types[maps.ty].inner.clone()
    };
    assert!(matches!(
        image(MapAccess::Depth),
        naga::TypeInner::Image {
            dim: naga::ImageDimension::D2,
            arrayed: true,
            class: naga::ImageClass::Depth { .. }
        }
    ));
    assert!(matches!(
        image(MapAccess::Words),
        naga::TypeInner::Image {
            dim: naga::ImageDimension::D2,
            arrayed: true,
            class: naga::ImageClass::Sampled {
                kind: naga::ScalarKind::Uint,
                ..
            }
        }
    ));
    assert!(matches!(
        image(MapAccess::Hybrid),
        naga::TypeInner::Image {
            dim: naga::ImageDimension::D2,
            arrayed: false,
            class: naga::ImageClass::Sampled {
                kind: naga::ScalarKind::Uint,
                ..
            }
        }
    ));
}

/// The shadow test's blocks (their constants are among `mirrored_constants_match_rust`'s).
#[test]
fn block_entry_points_unroll_their_sizes() {
    use penumbra::research::stages::shadow_test::{TEST_BLOCK, TEST_TAILS};
    // The tails halve from half a block down to one sample, as fill_blocks places them.
    assert_eq!(
        TEST_TAILS,
        [
            TEST_BLOCK / 2,
            TEST_BLOCK / 4,
            TEST_BLOCK / 8,
            TEST_BLOCK / 16
        ]
    );
    // One entry point per block size, each unrolling exactly its size.
    let (module, _) = kernels::validate("shadow_test").unwrap();
    for size in std::iter::once(TEST_BLOCK).chain(TEST_TAILS) {
        let entry = module
            .entry_points
            .iter()
            .find(|e| e.name == format!("block{size}"))
            .unwrap_or_else(|| panic!("no `block{size}`"));
        let calls = entry.function.body.iter().filter(|s| matches!(s, naga::Statement::Call { function, .. } if module.functions[*function].name.as_deref() == Some("test_sample"))).count();
        assert_eq!(
            calls as u32, size,
            "block{size} calls test_sample {calls} times"
        );
    }
}

#[test]
fn rust_structs_match_wgsl_layouts() {
    let mut problems = Vec::new();
    let mut checked = 0;
    for layout in all_layouts() {
        // Find the struct in the first kernel that declares it (the prelude is in every kernel).
        let mut found = false;
        for (k, _) in kernels::all() {
            let (module, _) = kernels::validate(k.name).expect("kernel validates");
            let Some(ty) = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(layout.name))
            else {
                continue;
            };
            found = true;
            let naga::TypeInner::Struct { members, span } = &ty.1.inner else {
                problems.push(format!("{}: not a struct in WGSL", layout.name));
                break;
            };
            if *span as usize != layout.size {
                problems.push(format!(
                    "{}: size {} in Rust, {} in WGSL",
                    layout.name, layout.size, span
                ));
            }
            if members.len() != layout.members.len() {
                problems.push(format!(
                    "{}: {} members in Rust, {} in WGSL",
                    layout.name,
                    layout.members.len(),
                    members.len()
                ));
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
    assert!(
        problems.is_empty(),
        "layout mismatches:\n{}",
        problems.join("\n")
    );
    assert!(checked >= 4, "only {checked} structs checked");
}

/// The stage table (src/gpu/stages.rs) against every kernel, in each form it is built for: the same
/// entry points, each with the workgroup size naga reads (what the passes dispatch with), and the
/// same bindings: every global variable the entry point uses, by name, at the @binding the pass
/// binds it to (passes bind the structs the table generates, a field per variable), and no binding
/// the entry point does not use.
#[test]
fn stage_table_matches_every_entry_point() {
    let mut problems = Vec::new();
    let mut checked = 0;
    for (stage, kernel) in kernels::all() {
        for &maps in MapAccess::forms(&kernel) {
            let (module, info) = kernels::validate_for(stage.name, maps).expect("kernel validates");
            let names = |v: Vec<&str>| {
                v.into_iter()
                    .map(String::from)
                    .collect::<BTreeSet<String>>()
            };
            let in_kernel = names(
                module
                    .entry_points
                    .iter()
                    .map(|e| e.name.as_str())
                    .collect(),
            );
            let in_table = names(stage.entries.iter().map(|e| e.name).collect());
            if in_kernel != in_table {
                problems.push(format!("{stage} ({maps:?}): entry points {in_kernel:?} in WGSL, {in_table:?} in the table"));
            }
            for (i, ep) in module.entry_points.iter().enumerate() {
                let Some(entry) = stage.entry(&ep.name) else {
                    continue;
                };
                let workgroup =
                    (ep.stage == naga::ShaderStage::Compute).then_some(ep.workgroup_size);
                if workgroup != entry.workgroup {
                    problems.push(format!(
                        "{stage}::{}: workgroup {:?} in the table, {workgroup:?} in WGSL",
                        ep.name, entry.workgroup
                    ));
                }
                let uses = info.get_entry_point(i);
                let mut used = BTreeSet::new();
                for (handle, global) in module.global_variables.iter() {
                    let (Some(binding), false) = (&global.binding, uses[handle].is_empty()) else {
                        continue;
                    };
                    if binding.group != 0 {
                        problems.push(format!(
                            "{stage}::{}: `{:?}` in group {}, the passes bind group 0 only",
                            ep.name, global.name, binding.group
                        ));
                    }
                    used.insert((global.name.clone().unwrap_or_default(), binding.binding));
                }
                let table: BTreeSet<(String, u32)> = entry
                    .bindings
                    .iter()
                    .map(|&(n, b)| (n.to_string(), b))
                    .collect();
                if used != table {
                    problems.push(format!(
                        "{stage}::{} ({maps:?}): WGSL uses {:?} the table lacks; the table has {:?} WGSL does not use",
                        ep.name,
                        used.difference(&table).collect::<Vec<_>>(),
                        table.difference(&used).collect::<Vec<_>>()
                    ));
                }
                checked += 1;
            }
        }
    }
    assert!(
        problems.is_empty(),
        "the stage table disagrees with the kernels:\n{}",
        problems.join("\n")
    );
    assert!(checked >= 50, "only {checked} entry points checked");
}

/// A `const` as naga reads it from one kernel (None where the kernel does not declare it).
fn wgsl_constant(module: &naga::Module, name: &str) -> Option<f64> {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))?;
    Some(match module.global_expressions[c.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => v as f64,
        naga::Expression::Literal(naga::Literal::I32(v)) => v as f64,
        naga::Expression::Literal(naga::Literal::F32(v)) => v as f64,
        ref e => panic!("`{name}` is {e:?}, not a literal"),
    })
}

/// Every constant that Rust and WGSL both hold, with the Rust value: each kernel (in each form)
/// that declares it must declare this value, and at least one must declare it.
#[test]
fn mirrored_constants_match_rust() {
    use penumbra::research::gpu::structs as gs;
    use penumbra::research::methods::adaptive::buffers as ab;
    use penumbra::research::stages::twin;
    let mirrored: &[(&str, f64)] = &[
        // kernels/shared/common.wgsl
        ("LATTICE_SIDE", ab::LATTICE_SIDE as f64),
        ("LATTICE_POINTS", ab::LATTICE_POINTS as f64),
        ("MASK_WORDS", ab::MASK_WORDS as f64),
        ("NO_SPLIT", ab::NO_SPLIT as f64),
        ("MIXED_WORD", ab::MIXED_WORD as f64),
        ("CULL_TILES", ab::CULL_TILES as f64),
        ("CULL_TILE_WORDS", ab::CULL_TILE_WORDS as f64),
        ("SPLIT_THRESHOLD", gs::SPLIT_THRESHOLD as f64),
        ("SPLIT_ALWAYS", gs::SPLIT_ALWAYS as f64),
        ("SPLIT_NEVER", gs::SPLIT_NEVER as f64),
        ("SPLIT_SHARE", gs::SPLIT_SHARE as f64),
        ("OVERFLOW_QUADS", gs::OVERFLOW_QUADS as f64),
        ("OVERFLOW_ITEMS", gs::OVERFLOW_ITEMS as f64),
        ("OVERFLOW_PROBES", gs::OVERFLOW_PROBES as f64),
        ("PROBE_LIT", twin::probe::PROBE_LIT as f64),
        ("SUMMARY_WORD", twin::shadow_test::SUMMARY_WORD as f64),
        (
            "SUMMARY_GEOMETRY",
            twin::shadow_test::SUMMARY_GEOMETRY as f64,
        ),
        ("SUMMARY_ANY_LIT", twin::shadow_test::SUMMARY_ANY_LIT as f64),
        (
            "SUMMARY_ANY_UNLIT",
            twin::shadow_test::SUMMARY_ANY_UNLIT as f64,
        ),
        ("FRAME_FACING_TEST", twin::shadow::FRAME_FACING_TEST as f64),
        ("FRAME_EVERY_WAY", twin::shadow::FRAME_EVERY_WAY as f64),
        ("LOOKUP_UNLIT", twin::shadow::LOOKUP_UNLIT as f64),
        ("LOOKUP_OUTSIDE", twin::shadow::LOOKUP_OUTSIDE as f64),
        ("LOOKUP_COMPARE", twin::shadow::LOOKUP_COMPARE as f64),
        (
            "TILE_LIST_HEADER",
            penumbra::research::stages::shade::TILE_LIST_HEADER as f64,
        ),
        // stage kernels
        (
            "SHADE_BLOCK",
            penumbra::research::stages::shade::SHADE_BLOCK as f64,
        ),
        (
            "TEST_BLOCK",
            penumbra::research::stages::shadow_test::TEST_BLOCK as f64,
        ),
        (
            "TEST_SLOTS",
            penumbra::research::stages::shadow_test::TEST_SLOTS as f64,
        ),
        (
            "TEST_TAILS",
            penumbra::research::stages::shadow_test::TEST_TAILS.len() as f64,
        ),
        ("CULL_RUN", penumbra::research::gpu::stages::CULL_RUN as f64),
        ("CULL_MARGIN", twin::cull::CULL_MARGIN as f64),
        ("CULL_DEPTH_SLACK", twin::cull::CULL_DEPTH_SLACK as f64),
        ("CULL_SCAN_TILES", twin::cull::CULL_SCAN_TILES as f64),
        (
            "RULE_LEVEL",
            penumbra::research::stages::weights::RULE_LEVEL as f64,
        ),
        (
            "RULE_AREA",
            penumbra::research::stages::weights::RULE_AREA as f64,
        ),
        (
            "RULE_COONS",
            penumbra::research::stages::weights::RULE_COONS as f64,
        ),
        (
            "LEVEL_LCM",
            penumbra::research::methods::adaptive::LEVEL_LCM as f64,
        ),
        ("FILTERED_ESM", twin::moments::FILTERED_ESM as f64),
        ("FILTERED_VSM", twin::moments::FILTERED_VSM as f64),
        ("FILTERED_EVSM", twin::moments::FILTERED_EVSM as f64),
        ("FILTERED_MSM", twin::moments::FILTERED_MSM as f64),
        ("FILTERED_CSM", twin::moments::FILTERED_CSM as f64),
        ("PCF_BOX", twin::pcf::PCF_BOX as f64),
        ("PCF_BILINEAR", twin::pcf::PCF_BILINEAR as f64),
        ("PCF_POISSON", twin::pcf::PCF_POISSON as f64),
        ("PCF_STRATIFIED", twin::pcf::PCF_STRATIFIED as f64),
        ("PCF_ROTATED", twin::pcf::PCF_ROTATED as f64),
        (
            "CASCADE_FILTER_HARD",
            penumbra::research::stages::cascades::FILTER_HARD as f64,
        ),
        (
            "CASCADE_FILTER_PCF",
            penumbra::research::stages::cascades::FILTER_PCF as f64,
        ),
        (
            "NO_CASCADE",
            penumbra::research::stages::cascades::NO_CASCADE as f64,
        ),
        (
            "BVH_STACK",
            penumbra::research::render::bvh::STACK_DEPTH as f64,
        ),
        (
            "HYBRID_POOL_WIDTH_LOG2",
            penumbra::research::stages::hybrid_build::POOL_WIDTH_LOG2 as f64,
        ),
        (
            "HYBRID_CHILDREN",
            penumbra::research::stages::hybrid_build::CHILDREN as f64,
        ),
        (
            "FRAME_HYBRID_LEVELS_SHIFT",
            penumbra::research::stages::hybrid_build::FRAME_LEVELS_SHIFT as f64,
        ),
        (
            "REGION_WORDS",
            penumbra::research::stages::regions::REGION_WORDS as f64,
        ),
        (
            "CLASS_WORDS",
            penumbra::research::stages::regions::CLASS_WORDS as f64,
        ),
        (
            "WEIGHT_SCALE",
            penumbra::research::stages::regions::WEIGHT_SCALE as f64,
        ),
        (
            "SAMPLING_ORDER",
            penumbra::research::stages::regions::SAMPLING_ORDER as f64,
        ),
    ];
    let mut modules = Vec::new();
    for (stage, kernel) in kernels::all() {
        for &maps in MapAccess::forms(&kernel) {
            modules.push((
                format!("{stage} ({maps:?})"),
                kernels::validate_for(stage.name, maps)
                    .expect("kernel validates")
                    .0,
            ));
        }
    }
    let mut problems = Vec::new();
    for &(name, rust) in mirrored {
        let declared: Vec<(&String, f64)> = modules
            .iter()
            .filter_map(|(kernel, module)| Some((kernel, wgsl_constant(module, name)?)))
            .collect();
        let differ: Vec<String> = declared
            .iter()
            .filter(|(_, wgsl)| *wgsl != rust)
            .map(|(kernel, wgsl)| format!("{wgsl} in {kernel}"))
            .collect();
        if declared.is_empty() {
            problems.push(format!("{name}: no kernel declares it"));
        } else if !differ.is_empty() {
            problems.push(format!(
                "{name}: {rust} in Rust, {} of {} kernels differ: {}",
                differ.len(),
                declared.len(),
                differ.join(", ")
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "mirrored constants differ:\n{}",
        problems.join("\n")
    );
}
