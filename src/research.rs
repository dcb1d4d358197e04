//! The research façade: what the lab (the `penumbra` binary, its studies and reports), the Python
//! binding, the benches and the tests use of the engine beyond the embedding API ([`crate::api`]).
//!
//! The engine's modules are private to the crate; this module mirrors their paths
//! (`research::gpu::timing::TimingMode` is `gpu::timing::TimingMode` inside) and re-exports only
//! the items that code outside the crate uses, so everything else stays `pub(crate)` and can change
//! without notice. An item joins the façade when outside code needs it; tests/layers.rs counts the
//! `pub` items of src/ and fails when the count grows past its figure.
//!
//! The CPU twins of the kernels (`research::stages::twin`) are here only with the `twins` feature,
//! which the engine's and the lab's tests and benches turn on through their dev-dependency on the
//! engine; a product build (the binary, the Python module, an embedder) has no twin.

pub mod certify {
    pub use crate::certify::{certificate, sample, Options, OptionsError, Sampled, DEFAULT_DELTA};
    pub mod bound {
        pub use crate::certify::bound::{BoundKind, STRETCH};
    }
    pub mod design {
        pub use crate::certify::design::{band, Design, BAND_DILATE, DEFENSIVE};
    }
    pub mod truth {
        pub use crate::certify::truth::{
            point_of, unsupported, TruthSamples, TruthTracer, REFERENCE_SAMPLES,
        };
    }
}
pub mod frame {
    pub use crate::frame::{
        camera_uniform, frame_uniform, gbuffer_only, render, Detached, FrameOptions, FrameResult,
        Renderer,
    };
    pub mod certify {
        pub use crate::frame::certify::{
            proxy, CertifyRecord, FrameCertifier, Opinion, ProxyKind, SECOND_OPINION,
        };
    }
}
pub mod gpu {
    pub use crate::gpu::{AdapterRequest, AdapterSummary, BackendChoice, GpuContext, Stage};
    pub mod kernels {
        pub use crate::gpu::kernels::{all, source_for, validate, validate_for, MapAccess};
    }
    pub mod readback {
        pub use crate::gpu::readback::{
            read_buffer, read_texture, storage_buffer, uniform_buffer, zeroed_storage,
        };
    }
    pub mod size_plan {
        pub use crate::gpu::size_plan::{mem_available, Bound, DeviceBounds};
    }
    pub mod stages {
        // `bind` whole: the stage table's generated bindings, one struct per entry point; tests
        // drive passes alone with them, and the compile-fail examples on `Bindings` need them
        // reachable from outside the crate.
        pub use crate::gpu::stages::{
            bind, decision_ms, frame_split, outside_frame, Bindings, Split, Stage, CULL_RUN,
        };
    }
    pub mod structs {
        pub use crate::gpu::structs::{
            all_layouts, GpuControl, GpuFrame, GpuLevel, GpuQuad, GpuRasterJob, GpuSample,
            GpuTestBlock, FRAME_EVERY_WAY, FRAME_FACING_TEST, OVERFLOW_ITEMS, OVERFLOW_PROBES,
            OVERFLOW_QUADS, SPLIT_ALWAYS, SPLIT_NEVER, SPLIT_SHARE, SPLIT_THRESHOLD,
        };
    }
    pub mod timing {
        pub use crate::gpu::timing::TimingMode;
    }
}
pub mod methods {
    pub use crate::methods::{
        check_lights, methods_with_param, AdaptiveParams, Criterion, Family, Layout, Method, Scope,
        Weights, FROM_THE_CENTRE, ONE_MAP_PER_POINT, ON_A_RECTANGLE, PCSS_RECTANGLE, REGISTRY,
    };
    pub mod adaptive {
        pub use crate::methods::adaptive::{
            lattice_numerators, level_uniform, sample_weights, split_quads, AdaptiveTrace,
            LevelReport, LEVEL_LCM,
        };
        pub mod buffers {
            pub use crate::methods::adaptive::buffers::{
                list_dispatch, max_items, AdaptiveBuffers, Level, Requests, Shape, CONTROL_BYTES,
                CULL_TILES, CULL_TILE_WORDS, LATTICE_POINTS, LATTICE_SIDE, MASK_WORDS, MIXED_WORD,
                NO_SPLIT, QUAD_CAPACITY,
            };
        }
    }
    pub mod auto {
        pub use crate::methods::auto::{
            predicted_at, At, AutoRecord, Check, Chosen, Costs, FilterCheck, Ladder, MapCost, Try,
            SAMPLING_ORDER,
        };
    }
    pub mod calibration {
        pub use crate::methods::calibration::{
            calibrated_with, factors, Class, Factors, CUBE, EVEN_CUBE_SAMPLING,
            EVEN_PLANE_SAMPLING, MAX_FITTED_EVEN, MIN_FITTED_SIZE, PLANE,
        };
    }
    pub mod cascades {
        pub use crate::methods::cascades::{
            CascadeBuffers, CascadeMaps, FILTERS, MAX_CASCADES, SUN_ONLY,
        };
        pub mod split {
            pub use crate::methods::cascades::split::{forward, Scheme};
        }
    }
    pub mod environment {
        pub use crate::methods::environment::{pixels, shadowmaps};
    }
    pub mod estimate {
        pub use crate::methods::estimate::{predict, Prediction, BOUND_FLOOR};
    }
    pub mod fixed_samples {
        pub use crate::methods::fixed_samples::{regular_points, FixedBuffers, Layout};
    }
    pub mod regions {
        pub use crate::methods::regions::{density_floor, half_octave, Regions, RegionsBuffers};
        pub mod budget {
            pub use crate::methods::regions::budget::{
                edge_weight, map_density, predicted_map, SAMPLING_SHARE,
            };
        }
    }
    pub mod single_map {
        pub use crate::methods::single_map::SingleMapBuffers;
    }
    pub mod sizes {
        pub use crate::methods::sizes::{band_rows, check, check_all, plan};
    }
    pub mod ssao {
        pub use crate::methods::ssao::SsaoBuffers;
    }
}
pub mod progress {
    pub use crate::progress::{register, Bar, Progress};
}
pub mod render {
    pub use crate::render::SceneGpu;
    pub mod bvh {
        pub use crate::render::bvh::STACK_DEPTH;
    }
    pub mod gbuffer {
        pub use crate::render::gbuffer::{camera_uniform, read_back, GBufferCpu, GBufferPass};
    }
    pub mod kept_maps {
        pub use crate::render::kept_maps::ReuseCounts;
    }
    pub mod shadow_order {
        pub use crate::render::shadow_order::shadow_order;
    }
    pub mod shadow_raster {
        pub use crate::render::shadow_raster::{
            allocate, allocate_as, clear_all, RasterJob, ShadowRasterPass,
        };
    }
}
pub mod scene {
    pub use crate::scene::{
        area_light_names, builtin_names, builtin_source, cache_path, catalog, embedded_source,
        is_render_key, parse_obj, register_asset_layer, settings_from_pairs, AssetLayer, BiasDef,
        Camera, CullMode, DiskLight, Emitter, GivenMesh, HybridDef, LightKind, MapKind, MeshDirs,
        PointLight, Scene, SpotLight, Vertex, CACHE_PREFIX, MAX_COORDINATE, MAX_SUN_DIAMETER_DEG,
    };
    pub mod emitter {
        pub use crate::scene::emitter::{
            concentric, cube_face, point_light_point, spot_light_point,
        };
    }
    pub mod environment {
        pub use crate::scene::environment::{Environment, Panorama};
        pub mod lights {
            pub use crate::scene::environment::lights::{irradiance, pixel_lights, EnvLight};
        }
        pub mod panorama {
            pub use crate::scene::environment::panorama::{band_solid_angle, luminance};
        }
    }
    pub mod input_file {
        pub use crate::scene::input_file::{kind, read_capped, read_text, TEXT_CAP};
    }
    pub mod light {
        pub use crate::scene::light::{sample_view, AreaLight, Bounds};
    }
    pub mod light_checks {
        pub use crate::scene::light_checks::{check_scene, MAX_LIGHT_DIAGONALS};
    }
    pub mod mesh_input {
        pub use crate::scene::mesh_input::{
            max_mesh_bytes, open_regular, set_max_mesh_mib, DEFAULT_MAX_MESH_MIB,
        };
    }
    pub mod rays {
        pub use crate::scene::rays::{env_ray_length, ray_offset, RELATIVE_RAY_OFFSET};
    }
}
pub mod stages {
    // The twins whole, for the tests and benches that check kernels against them (`twins`).
    #[cfg(feature = "twins")]
    pub use crate::stages::twin;
    pub mod adaptive_buffers {
        pub use crate::stages::adaptive_buffers::{quad_node, HELD_WORDS, QUAD_NODES};
    }
    pub mod cascades {
        pub use crate::stages::cascades::{FILTER_HARD, FILTER_PCF, NO_CASCADE};
    }
    pub mod compact {
        pub use crate::stages::compact::{Compact, CompactInputs};
    }
    pub mod cull {
        pub use crate::stages::cull::{cull_face, Cull, CullBatch, ARGS_WORDS, CULL_RUN};
    }
    pub mod footprint {
        pub use crate::stages::footprint::Footprint;
    }
    // The product's readers that the twins re-export for their tests.
    pub mod hybrid_pool {
        pub use crate::stages::hybrid_pool::{decode, lookup};
    }
    pub mod regions_rules {
        pub use crate::stages::regions_rules::{footprint, samples_of, total};
    }
    pub mod hybrid_build {
        pub use crate::stages::hybrid_build::{
            CHILDREN, DEPTH_UNIT, FRAME_LEVELS_SHIFT, POOL_WIDTH_LOG2,
        };
    }
    pub mod neighbourhood {
        pub use crate::stages::neighbourhood::Neighbourhood;
    }
    pub mod probe {
        pub use crate::stages::probe::Probe;
    }
    pub mod quad_count {
        pub use crate::stages::quad_count::QuadCount;
    }
    pub mod raster {
        pub use crate::stages::raster::{chain_maps, Raster};
    }
    pub mod raster_compute {
        pub use crate::stages::raster_compute::{
            large_capacity, large_capacity_for, maps_per_chain, RasterCompute, RasterDifference,
            Requests, CLEAR_RUN, FAR, STEER_ARGS_CLEAR, STEER_ARGS_MAIN, STEER_ARGS_STORE,
        };
    }
    pub mod raster_timing {
        pub use crate::stages::raster_timing::least_ms;
    }
    pub mod regions {
        pub use crate::stages::regions::{
            empty_region, ordered, unordered, RegionsParams, CLASS_WORDS, REGION_WORDS,
            SAMPLING_ORDER, WEIGHT_SCALE,
        };
    }
    pub mod reproject_count {
        pub use crate::stages::reproject_count::ReprojectCount;
    }
    pub mod shade {
        pub use crate::stages::shade::{
            blocks, GeometryTiles, ShadePass, SHADE_BLOCK, TILE_LIST_HEADER,
        };
    }
    pub mod shadow_test {
        pub use crate::stages::shadow_test::{
            block_slots, ShadowTest, TestFrame, TEST_BLOCK, TEST_BLOCK_BYTES, TEST_SLOTS,
            TEST_TAILS,
        };
    }
    pub mod subdivide {
        pub use crate::stages::subdivide::Subdivide;
    }
    pub mod weights {
        pub use crate::stages::weights::{WeightsPass, RULE_AREA, RULE_COONS, RULE_LEVEL};
    }
}
