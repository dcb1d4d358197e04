//! The embedding API: soft shadows from one rectangular area light, rendered on a wgpu device the
//! caller owns (a game engine's, an editor's), with any of penumbra's methods.
//!
//! The result is V, the unweighted visible fraction of the light at each pixel's surface point
//! (0 = umbra, 1 = fully lit, 0 on background pixels), as `Vec<f32>` or as an `R32Float` texture.
//! Multiply it into the light's contribution to shade with it.
//!
//! 1. [`Shadows::new`] takes the caller's adapter, device and queue; it creates no device and
//!    checks that the device has what the kernels need (an error names each missing limit or
//!    capability). Request the device with [`required_limits`] (and [`OPTIONAL_FEATURES`] where the
//!    adapter has them).
//! 2. [`SceneBuilder`] takes world-space meshes ([`Mesh`]), a [`Camera`] and a [`RectLight`], and
//!    render settings by the keys of `penumbra render --set` ([`SceneBuilder::set`]).
//! 3. [`Shadows::renderer`] builds one method, named by its spec as on the command line
//!    (`"adaptive:preset=balanced"`, `"regular:n=5,layout=centred"`, `"pcss"`; `penumbra methods`
//!    lists them all).
//! 4. [`ShadowRenderer::render`] returns V on the CPU; [`ShadowRenderer::render_to_texture`]
//!    also leaves it in a texture to bind.
//!
//! ```no_run
//! # fn main() -> penumbra::Result<()> {
//! # let (adapter, device, queue): (wgpu::Adapter, wgpu::Device, wgpu::Queue) = unimplemented!();
//! use penumbra::{Camera, Mesh, RectLight, SceneBuilder, Shadows};
//!
//! let shadows = Shadows::new(&adapter, &device, &queue)?;
//! let ground = Mesh::new(vec![[-15.0, 0.0, 15.0], [15.0, 0.0, 15.0], [15.0, 0.0, -15.0], [-15.0, 0.0, -15.0]], vec![0, 1, 2, 0, 2, 3]);
//! let occluder = Mesh::new(vec![[-2.0, 4.0, 2.0], [2.0, 4.0, 2.0], [2.0, 4.0, -2.0], [-2.0, 4.0, -2.0]], vec![0, 1, 2, 0, 2, 3]);
//! let scene = SceneBuilder::new(
//!     Camera::look_at([0.0, 16.0, 14.0], [0.0, 0.0, -1.0], 50.0),
//!     RectLight { center: [0.0, 10.0, 0.0], edge_u: [4.0, 0.0, 0.0], edge_v: [0.0, 0.0, 4.0] },
//! )
//! .mesh(ground)
//! .mesh(occluder)
//! .resolution(256, 256)
//! .set("cull", "none")
//! .build()?;
//! let mut renderer = shadows.renderer(&scene, "adaptive:preset=balanced")?;
//! let v = renderer.render()?; // v.values: width × height, row-major, top row first
//! # Ok(()) }
//! ```
//!
//! **What a change costs.** [`ShadowRenderer::set_camera`] is free: only the G-buffer reads the
//! camera, and it is drawn every frame. The light, the meshes and the render settings are baked
//! into the method's pipelines and buffers when it is built (shadow-map frusta, the light lattice,
//! buffer sizes): change them on the [`ShadowScene`] and build a new renderer, which costs what the
//! first frame costs (pipelines, the mesh upload and, on lavapipe, shader compilation at first
//! dispatch). Every frame reads V back to the CPU (the methods' own decisions need read-backs and
//! the background mask is applied there); the texture is filled from that copy.

mod requirements;

use crate::frame::{FrameOptions, Renderer};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::{Family, Method};
use crate::scene::light::AreaLight;
use crate::scene::{GivenMesh, Scene};
use crate::{Error, Result};
use glam::Vec3;

/// Features penumbra uses when the device has them and does without otherwise:
/// `INDIRECT_FIRST_INSTANCE` lets culled shadow-map draws pick their sample on the GPU; the
/// timestamp features record GPU stage times (on real GPUs only).
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::INDIRECT_FIRST_INSTANCE
    .union(wgpu::Features::TIMESTAMP_QUERY)
    .union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

/// `base` with every limit the kernels and raster passes need raised to at least that need: pass
/// the result as `wgpu::DeviceDescriptor::required_limits` (the adapter must support it).
///
/// The needs are read from the kernels (bindings per stage, workgroup sizes and storage) and from
/// the G-buffer (three `Rgba32Float` targets: more colour-attachment bytes than WebGPU's default).
/// Sizes that grow with the scene (texture dimensions for the resolution and shadow maps, buffer
/// sizes for the mesh) are not raised: for large scenes start from `adapter.limits()`.
pub fn required_limits(base: wgpu::Limits) -> wgpu::Limits {
    requirements::raised(base)
}

/// Penumbra on a caller's wgpu device. Cheap to keep for the device's lifetime; every
/// [`ShadowRenderer`] borrows it.
pub struct Shadows {
    ctx: GpuContext,
}

impl Shadows {
    /// Wraps the caller's device (the handles are cloned; wgpu handles are shared references).
    ///
    /// Fails, naming each one, when the adapter lacks a capability the pipeline needs (compute
    /// shaders, renderable `Rgba32Float`, sampled `Depth32Float`) or when the device was requested
    /// with a limit below a need (see [`required_limits`]).
    pub fn new(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Shadows> {
        let name = adapter.get_info().name;
        let missing = crate::gpu::adapter::missing_capabilities(adapter);
        if !missing.is_empty() {
            return Err(Error::NoAdapter(format!(
                "{name} cannot run penumbra: {}",
                missing.join("; ")
            )));
        }
        let short = requirements::shortfalls(&device.limits());
        if !short.is_empty() {
            return Err(Error::Limit(format!(
                "the device on {name} was requested with limits below what penumbra needs: {}; request it with `required_limits: penumbra::required_limits(...)`",
                short.join("; ")
            )));
        }
        let ctx = GpuContext::from_device(
            adapter.clone(),
            device.clone(),
            queue.clone(),
            "the caller's device".to_string(),
        );
        Ok(Shadows { ctx })
    }

    /// Builds `method` (a spec as `penumbra render --method` takes it) for `scene`: its pipelines,
    /// buffers and the mesh upload. Environment-lit methods are refused: this API lights with a
    /// rectangle.
    pub fn renderer<'a>(
        &'a self,
        scene: &'a ShadowScene,
        method: &str,
    ) -> Result<ShadowRenderer<'a>> {
        let method = Method::parse(method, &[])?;
        if method.family() == Family::Environment {
            return Err(Error::Param(format!(
                "method `{}` lights with a panorama; the embedding API renders a rectangular area light (use hard, pcf, pcss, the filtered maps, regular or adaptive)",
                method.name()
            )));
        }
        let inner = Renderer::new(&self.ctx, &scene.scene, &method)?;
        Ok(ShadowRenderer {
            inner,
            ctx: &self.ctx,
            scene: &scene.scene,
            method,
            texture: None,
        })
    }
}

impl std::fmt::Debug for Shadows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shadows")
            .field("adapter", &self.ctx.summary.name)
            .field("backend", &self.ctx.summary.backend)
            .finish()
    }
}

/// A triangle mesh in world space.
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<[f32; 3]>,
    indices: Vec<u32>,
    normals: Option<Vec<[f32; 3]>>,
    albedo: [f32; 3],
}

impl Mesh {
    /// Positions and three indices per triangle (counter-clockwise seen from the front; with
    /// `cull` at its default `back`, shadow maps draw front faces only). Normals default to
    /// area-weighted vertex normals and the albedo to 0.8 grey (it only colours shaded pictures;
    /// V does not depend on it).
    pub fn new(positions: Vec<[f32; 3]>, indices: Vec<u32>) -> Mesh {
        Mesh {
            positions,
            indices,
            normals: None,
            albedo: [0.8; 3],
        }
    }

    /// Per-vertex normals (normalised here), one per position.
    pub fn with_normals(mut self, normals: Vec<[f32; 3]>) -> Mesh {
        self.normals = Some(normals);
        self
    }

    /// The surface colour in linear RGB.
    pub fn with_albedo(mut self, albedo: [f32; 3]) -> Mesh {
        self.albedo = albedo;
        self
    }
}

/// A pinhole camera; V has one value per pixel of its image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: [f32; 3],
    pub target: [f32; 3],
    pub up: [f32; 3],
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f32,
}

impl Camera {
    /// A camera at `eye` looking at `target`, +Y up.
    pub fn look_at(eye: [f32; 3], target: [f32; 3], fov_y_deg: f32) -> Camera {
        Camera {
            eye,
            target,
            up: [0.0, 1.0, 0.0],
            fov_y_deg,
        }
    }

    fn inner(&self) -> crate::scene::Camera {
        crate::scene::Camera {
            eye: self.eye.into(),
            target: self.target.into(),
            up: self.up.into(),
            fov_y_deg: self.fov_y_deg,
        }
    }
}

/// A rectangular area light: the points `center + s·edge_u + t·edge_v` for s, t in [−½, ½]. It
/// emits to the side of `edge_u × edge_v` only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectLight {
    pub center: [f32; 3],
    pub edge_u: [f32; 3],
    pub edge_v: [f32; 3],
}

impl RectLight {
    fn inner(&self) -> AreaLight {
        AreaLight {
            center: Vec3::from(self.center),
            edge_u: Vec3::from(self.edge_u),
            edge_v: Vec3::from(self.edge_v),
        }
    }
}

/// Collects a scene; [`SceneBuilder::build`] checks it as a scene file is checked.
#[derive(Clone, Debug)]
pub struct SceneBuilder {
    camera: Camera,
    light: RectLight,
    meshes: Vec<Mesh>,
    settings: Vec<(String, String)>,
}

impl SceneBuilder {
    /// An empty scene seen from `camera` under `light`, with the default render settings (512×512,
    /// 512² shadow maps, back faces culled; docs/scene-format.md).
    pub fn new(camera: Camera, light: RectLight) -> SceneBuilder {
        SceneBuilder {
            camera,
            light,
            meshes: Vec::new(),
            settings: Vec::new(),
        }
    }

    /// Adds a mesh; meshes keep their order (material index = position in this list).
    pub fn mesh(mut self, mesh: Mesh) -> SceneBuilder {
        self.meshes.push(mesh);
        self
    }

    /// V's size in pixels.
    pub fn resolution(self, width: u32, height: u32) -> SceneBuilder {
        self.set("width", &width.to_string())
            .set("height", &height.to_string())
    }

    /// One render setting by its `penumbra render --set` key: `shadow_map_size`, `cull`
    /// (`back`, `front`, `none`), `bias.constant`, `self_shadow`, `maps`, … (docs/scene-format.md).
    /// Later settings of a key win; [`SceneBuilder::build`] reports unknown keys and bad values.
    pub fn set(mut self, key: &str, value: &str) -> SceneBuilder {
        self.settings.retain(|(k, _)| k != key);
        self.settings.push((key.to_string(), value.to_string()));
        self
    }

    /// The checked scene: finite coordinates, indices in range, a light with area that faces the
    /// meshes, a camera that sees them, valid render settings.
    pub fn build(self) -> Result<ShadowScene> {
        const ORIGIN: &str = "embedded scene";
        let render = crate::scene::settings_from_pairs(ORIGIN, &self.settings)?;
        let given: Vec<GivenMesh> = self
            .meshes
            .iter()
            .map(|m| GivenMesh {
                positions: &m.positions,
                indices: &m.indices,
                normals: m.normals.as_deref(),
                albedo: m.albedo,
            })
            .collect();
        let scene = Scene::from_meshes(
            ORIGIN,
            &self.camera.inner(),
            &self.light.inner(),
            render,
            &given,
        )?;
        Ok(ShadowScene { scene })
    }
}

/// A checked scene: meshes, camera, light and render settings. Renderers borrow it.
pub struct ShadowScene {
    scene: Scene,
}

impl ShadowScene {
    /// V's width in pixels.
    pub fn width(&self) -> u32 {
        self.scene.render.width
    }

    /// V's height in pixels.
    pub fn height(&self) -> u32 {
        self.scene.render.height
    }

    /// Triangles over all meshes.
    pub fn triangle_count(&self) -> usize {
        self.scene.triangle_count()
    }

    /// Moves the camera for renderers built from now on (a live renderer moves with
    /// [`ShadowRenderer::set_camera`]).
    pub fn set_camera(&mut self, camera: Camera) -> Result<()> {
        self.scene.camera = self.scene.check_camera(&camera.inner())?;
        Ok(())
    }

    /// Moves or resizes the light for renderers built from now on (a renderer bakes the light in
    /// when it is built).
    pub fn set_light(&mut self, light: RectLight) -> Result<()> {
        self.scene.light = self.scene.check_light(&light.inner())?;
        Ok(())
    }
}

impl std::fmt::Debug for ShadowScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShadowScene")
            .field("width", &self.width())
            .field("height", &self.height())
            .field("triangles", &self.triangle_count())
            .finish()
    }
}

/// V on the CPU.
#[derive(Clone, Debug, PartialEq)]
pub struct Visibility {
    pub width: u32,
    pub height: u32,
    /// `width × height` values in [0, 1], row-major, top row first; 0 where no mesh is hit.
    pub values: Vec<f32>,
    /// Shadow maps the method rendered for this frame.
    pub shadow_maps: u32,
}

/// One method built for one scene on one device: every frame reuses its pipelines and buffers.
pub struct ShadowRenderer<'a> {
    inner: Renderer<'a>,
    ctx: &'a GpuContext,
    scene: &'a Scene,
    method: Method,
    texture: Option<wgpu::Texture>,
}

impl std::fmt::Debug for ShadowRenderer<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShadowRenderer")
            .field("method", &self.method.label())
            .finish()
    }
}

impl<'a> ShadowRenderer<'a> {
    /// The method's label, its parameters that differ from the defaults (`adaptive:preset=balanced`).
    pub fn method(&self) -> String {
        self.method.label()
    }

    /// Renders from `camera` from the next frame on, with nothing rebuilt. Fails when the camera
    /// is malformed or sees none of the meshes' bounds.
    pub fn set_camera(&mut self, camera: &Camera) -> Result<()> {
        let camera = self.scene.check_camera(&camera.inner())?;
        self.inner.set_camera(&camera);
        Ok(())
    }

    /// Renders one frame and returns V. Fails when no mesh covers a pixel.
    pub fn render(&mut self) -> Result<Visibility> {
        // Frame timing and no decision pictures: the fewest waits and read-backs.
        let r = self.inner.frame(FrameOptions {
            mode: TimingMode::Frame,
            pictures: false,
        })?;
        Ok(Visibility {
            width: r.gbuffer.width,
            height: r.gbuffer.height,
            values: r.visibility,
            shadow_maps: r.output.shadow_maps,
        })
    }

    /// Renders one frame and writes V into an `R32Float` texture of the scene's size (created on
    /// first use, then reused), which the caller's next submission on the same queue sees. Its
    /// usages are `TEXTURE_BINDING | COPY_SRC | COPY_DST`; `R32Float` is unfilterable without
    /// `FLOAT32_FILTERABLE`, so read it with `textureLoad` or a non-filtering sampler.
    pub fn render_to_texture(&mut self) -> Result<&wgpu::Texture> {
        let v = self.render()?;
        let size = wgpu::Extent3d {
            width: v.width,
            height: v.height,
            depth_or_array_layers: 1,
        };
        let device = &self.ctx.device;
        let texture = self.texture.get_or_insert_with(|| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("penumbra visibility"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC
                    | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            })
        });
        self.ctx.queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&v.values),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(v.width * 4),
                rows_per_image: Some(v.height),
            },
            size,
        );
        Ok(texture)
    }
}
