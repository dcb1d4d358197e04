//! No GPU needed: every kernel parses and validates with naga, the Rust `Gpu*` structs match the
//! WGSL layouts member by member, and Rust dispatches with the workgroup sizes the kernels declare.

use penumbra::kernels::{self, KERNELS};
use penumbra::layout::all_layouts;

#[test]
fn every_kernel_validates_with_naga() {
    let errors: Vec<String> = KERNELS.iter().filter_map(|k| kernels::validate(k.name).err().map(|e| e.to_string())).collect();
    assert!(KERNELS.len() >= 3, "kernel registry is unexpectedly small");
    assert!(errors.is_empty(), "{} kernel(s) failed naga validation:\n{}", errors.len(), errors.join("\n"));
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
    for (kernel, entry, size) in penumbra::compute::WORKGROUP_SIZES {
        let declared = kernels::workgroup_size(kernel, entry).expect("kernel has the entry point");
        assert_eq!(declared, *size, "{kernel}::{entry}: Rust dispatches with {size:?}, WGSL declares {declared:?}");
    }
}
