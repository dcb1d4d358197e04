//! weights (scope = global, corner-to-corner lattice): the sample weights on the GPU, from the
//! leaves each level appends and the rendered samples, so shade needs no read-back.

use super::{groups, ComputeKernel, Dispatch, LINE_WORKGROUP};
use crate::gpu::readback;
use crate::gpu::stages::bind;
use crate::gpu::structs::{GpuQuad, GpuWeights};
use crate::gpu::GpuContext;
use crate::gpu::Stage;
use crate::stages::adaptive_buffers::{Decisions, LATTICE_POINTS, QUAD_CAPACITY};
use crate::Result;

/// GpuWeights.rule.
pub const RULE_LEVEL: u32 = 0;
pub const RULE_AREA: u32 = 1;
pub const RULE_COONS: u32 = 2;

pub struct WeightsPass {
    leaves_of_level: ComputeKernel,
    main: ComputeKernel,
    leaves: wgpu::Buffer,
    leaf_count: wgpu::Buffer,
    /// The integer numerators (i32 per lattice sample), kept for tests.
    pub numerators: wgpu::Buffer,
    rule: wgpu::Buffer,
}

impl WeightsPass {
    pub fn new(ctx: &GpuContext, rule: u32) -> Result<Self> {
        // Leaves of all levels: at most 1 + 4 + 16 + 64 + 256.
        let capacity = QUAD_CAPACITY as u64 * 2;
        Ok(Self {
            leaves_of_level: ComputeKernel::new(ctx, Stage::WEIGHTS, "leaves_of_level")?,
            main: ComputeKernel::new(ctx, Stage::WEIGHTS, "main")?,
            leaves: readback::zeroed_storage(
                ctx,
                "leaves",
                capacity * std::mem::size_of::<GpuQuad>() as u64,
            ),
            leaf_count: readback::zeroed_storage(ctx, "leaf count", 4),
            numerators: readback::zeroed_storage(
                ctx,
                "weight numerators",
                LATTICE_POINTS as u64 * 4,
            ),
            rule: readback::uniform_buffer(
                ctx,
                "weights rule",
                &GpuWeights {
                    rule,
                    ..Default::default()
                },
            ),
        })
    }

    /// Starts a frame: no leaves yet.
    pub fn record_begin(&self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.leaf_count, 0, None);
    }

    /// After a level's subdivide: appends the level's unsplit quads (`level.quad_count` of `quads`).
    pub fn record_leaves(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        level: &wgpu::Buffer,
        quads: &wgpu::Buffer,
        decisions: &Decisions,
    ) {
        self.leaves_of_level.dispatch(
            ctx,
            enc,
            bind::weights::LeavesOfLevel {
                level: level.as_entire_binding(),
                quads: quads.as_entire_binding(),
                split_base: decisions.split_base.as_entire_binding(),
                leaves: self.leaves.as_entire_binding(),
                leaf_count: self.leaf_count.as_entire_binding(),
            },
            Dispatch::Direct([groups(QUAD_CAPACITY, LINE_WORKGROUP[0]), 1, 1]),
        );
    }

    /// After the last level: writes ŵ into `weights`.
    pub fn record(
        &self,
        ctx: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        decisions: &Decisions,
        weights: &wgpu::Buffer,
    ) {
        self.main.dispatch(
            ctx,
            enc,
            bind::weights::Main {
                leaf_count: self.leaf_count.as_entire_binding(),
                leaves: self.leaves.as_entire_binding(),
                rule: self.rule.as_entire_binding(),
                lattice_state: decisions.lattice_state.as_entire_binding(),
                sample_level: decisions.sample_level.as_entire_binding(),
                numerators: self.numerators.as_entire_binding(),
                weights: weights.as_entire_binding(),
            },
            Dispatch::Direct([1, 1, 1]),
        );
    }
}
