//! What the single-map methods (pcf, pcss and the filtered maps) share: one shadow map from the
//! light's centre, the filter uniform, and the buffers their twin tests read.

use super::hybrid_maps::{HybridMaps, HybridRecord};
use crate::gpu::readback;
use crate::gpu::structs::{GpuFilter, GpuSample};
use crate::gpu::timing::StageTimer;
use crate::render::shadow_raster::{self, RasterJob, ShadowMapArray};
use crate::scene::MapKind;
use crate::stages::raster::RasterTarget;
use crate::stages::FrameGpu;
use crate::Result;

/// The map from the light's centre, allocated once per scene and settings; for a point light the
/// six faces of the cube from its centre (layers 0..5), of which the kernels read the one that
/// holds the pixel's direction (`face_offset` in kernels/shared/common.wgsl).
pub(crate) struct CentreMap {
    /// The first (or only) map's sample.
    pub(crate) sample: GpuSample,
    /// Every map's sample: one, or the point light's six faces.
    pub(crate) faces: Vec<GpuSample>,
    pub(crate) samples: wgpu::Buffer,
    pub(crate) maps: CentreMaps,
}

/// A depth array of one layer, or (`maps = hybrid`) one raster layer merged into a store of one slot.
pub(crate) enum CentreMaps {
    Plain(ShadowMapArray),
    Hybrid(Box<HybridMaps>),
}

impl CentreMap {
    pub(crate) fn new(fg: &FrameGpu) -> Result<Self> {
        Self::sized(fg, fg.scene.render.shadow_map_size)
    }

    /// The centre's map at `size` texels a side (a plain map; the kernels that read it bind a
    /// frame uniform of that `map_size`).
    pub(crate) fn sized(fg: &FrameGpu, size: u32) -> Result<Self> {
        let s = fg.scene;
        // The disk's or the spot's centre, or the sun's central direction (orthographic):
        // `Emitter::sample_map`.
        // A point light's six cube faces (`Emitter::sample_maps`), each in its own layer.
        let mut faces = s
            .emitter
            .sample_maps(&s.light, 0.5, 0.5, &s.bounds, size, u32::MAX);
        for (layer, f) in faces.iter_mut().enumerate() {
            f.layer = layer as u32;
        }
        let n = faces.len() as u32;
        let samples =
            readback::storage_buffer(fg.ctx, "centre sample", &faces, wgpu::BufferUsages::empty());
        let maps = match s.render.maps {
            MapKind::Plain => {
                let array = fg.raster.allocate(fg.ctx, size, n);
                shadow_raster::clear_all(fg.ctx, &array)?;
                CentreMaps::Plain(array)
            }
            MapKind::Hybrid if size != s.render.shadow_map_size => {
                return Err(crate::Error::Limit(format!(
                    "maps=hybrid: the centre map's store is sized for shadow_map_size, not {size}"
                )))
            }
            MapKind::Hybrid => CentreMaps::Hybrid(Box::new(HybridMaps::new(fg, n, n)?)),
        };
        Ok(Self {
            sample: faces[0],
            faces,
            samples,
            maps,
        })
    }

    /// Maps per frame: 1, or 6 for a point light's cube.
    pub(crate) fn count(&self) -> u32 {
        self.faces.len() as u32
    }

    /// The `shadow_raster` stage: one map, or six (with `maps = hybrid`, then `hybrid_build`).
    pub(crate) fn render(&mut self, fg: &FrameGpu, timer: &mut StageTimer) -> Result<()> {
        match &mut self.maps {
            CentreMaps::Plain(array) => timer.stage(fg.ctx, fg.raster.stage(), |enc| {
                let jobs: Vec<RasterJob> = (0..self.faces.len() as u32)
                    .map(|i| RasterJob {
                        sample: i,
                        layer: i,
                        scissor: None,
                    })
                    .collect();
                fg.raster.record(
                    fg.ctx,
                    enc,
                    &RasterTarget {
                        scene: &fg.scene_gpu,
                        samples: &self.samples,
                        array,
                    },
                    &jobs,
                )?;
                Ok(())
            }),
            CentreMaps::Hybrid(h) => {
                h.reset(fg);
                // One map always fits a store sized for it; a cube's six faces are rasterized a
                // batch of transient layers at a time and must all fit, since the kernel reads one
                // store: one that fills up early is an error, never maps dropped. The last flush
                // hands over what the kernel then reads.
                let mut full = |_: &FrameGpu,
                                _: &mut StageTimer,
                                _: &wgpu::TextureView,
                                _: &[u32]|
                 -> Result<()> {
                    Err(crate::Error::Limit("maps=hybrid: the point light's six cube faces do not fit one store; raise shadow_map_budget_mib".into()))
                };
                let slots: Vec<u32> = (0..self.faces.len() as u32).collect();
                for batch in slots.chunks(h.layers() as usize) {
                    h.render(fg, timer, &self.samples, batch, &mut full)?;
                }
                h.flush(fg, timer, &mut |_, _, _, _| Ok(()))
            }
        }
    }

    /// What the filter kernels bind as `shadow_maps`.
    pub(crate) fn view(&self) -> &wgpu::TextureView {
        match &self.maps {
            CentreMaps::Plain(array) => &array.array_view,
            CentreMaps::Hybrid(h) => &h.store.view,
        }
    }

    /// The map as the kernels read it: the raster, or what the lookup twin reads from the store.
    pub(crate) fn read(&self, fg: &FrameGpu) -> Result<Vec<f32>> {
        self.read_layer(fg, 0)
    }

    /// Every map (the point light's six faces), as `read`.
    pub(crate) fn read_all(&self, fg: &FrameGpu) -> Result<Vec<Vec<f32>>> {
        (0..self.count()).map(|k| self.read_layer(fg, k)).collect()
    }

    fn read_layer(&self, fg: &FrameGpu, k: u32) -> Result<Vec<f32>> {
        match &self.maps {
            CentreMaps::Plain(array) => readback::read_texture(fg.ctx, &array.texture, k, 4),
            CentreMaps::Hybrid(h) => {
                let pool = h.store.read_words(fg.ctx, h.store.capacity_words)?;
                Ok(crate::stages::hybrid_pool::decode(
                    &pool,
                    k,
                    h.store.settings.base,
                    h.store.settings.levels,
                ))
            }
        }
    }

    /// Read-backs the representation needs (the hybrid store's allocation state).
    pub(crate) fn syncs(&self) -> u32 {
        match &self.maps {
            CentreMaps::Plain(_) => 0,
            CentreMaps::Hybrid(h) => h.stats.syncs,
        }
    }

    /// A method's record's `hybrid` entry: present when the maps are hybrid.
    pub(crate) fn hybrid_record(&self) -> Option<HybridRecord> {
        match &self.maps {
            CentreMaps::Plain(_) => None,
            CentreMaps::Hybrid(h) => Some(h.record()),
        }
    }

    /// The map's far plane: linear depth of the cleared depth 1, a / (1 + b), or a + b on an
    /// orthographic map.
    pub(crate) fn far_depth(&self) -> f32 {
        let s = &self.sample;
        if s.orthographic != 0 {
            s.depth_lin_a + s.depth_lin_b
        } else {
            s.depth_lin_a / (1.0 + s.depth_lin_b)
        }
    }
}

/// The area light's edge lengths: the light size every single-map method takes from the scene.
pub(crate) fn light_size(fg: &FrameGpu) -> (f32, f32) {
    match fg.scene.emitter {
        // The sun's size is its angle: the disk of directions one unit out, 2·tan(α/2), which
        // PCSS on an orthographic map scales by depth differences alone (docs/lights.md §4).
        crate::scene::Emitter::Sun(sun) => (2.0 * sun.tan_half_angle(), 2.0 * sun.tan_half_angle()),
        // The rectangle's sides; the disk's and the spot's stand-in squares are the disk's or the
        // sphere's diameter on each side.
        _ => (
            fg.scene.light.edge_u.length(),
            fg.scene.light.edge_v.length(),
        ),
    }
}

/// Inputs and intermediate buffers of one single-map frame, read after it for the twins (`inspect`).
#[derive(Clone, Debug, Default)]
pub struct SingleMapBuffers {
    pub map: Vec<f32>,
    pub sample: GpuSample,
    /// A point light's six faces and their maps (face 0 is `sample` and `map`); empty otherwise.
    pub faces: Vec<GpuSample>,
    pub face_maps: Vec<Vec<f32>>,
    pub filter: GpuFilter,
    /// pcf: tap offsets of the disk kernels.
    pub disk: Vec<[f32; 2]>,
    /// Filtered methods: the statistic as `moments` wrote it, after the horizontal blur, after both.
    pub raw: Vec<[f32; 4]>,
    pub scratch: Vec<[f32; 4]>,
    pub filtered: Vec<[f32; 4]>,
}
