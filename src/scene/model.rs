//! What a scene is once built: the camera, the light, the meshes as one vertex and index list, and
//! the render settings. Loading and parsing live in mod.rs and format.rs.

use super::mesh::Vertex;
use super::settings::RenderSettings;
use crate::scene::light::{AreaLight, Bounds};
use crate::Error;
use glam::{Mat4, Vec3};

#[derive(Clone, Debug)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
}

impl Camera {
    pub(crate) fn clip_from_world(&self, aspect: f32, bounds: &Bounds) -> Mat4 {
        let dist = (bounds.min.lerp(bounds.max, 0.5) - self.eye).length() + bounds.diagonal();
        let near = (dist * 1e-4).max(1e-4);
        // Reversed depth (near → 1, far → 0): float depth keeps its relative precision far from
        // the eye. The usual order resolved only about 4e-3 units at 14 units on `point-room`, so
        // the ground beat a wall standing on it along their contact line, and those pixels' points
        // lay inside the wall, where every shadow ray leaves through its face.
        glam::camera::rh::proj::directx::perspective(
            self.fov_y_deg.to_radians(),
            aspect,
            dist * 2.0,
            near,
        ) * glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up)
    }
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub description: String,
    /// File path or `builtin:NAME`: every error names it.
    pub origin: String,
    pub camera: Camera,
    pub light: AreaLight,
    /// The light's kind and shape; for `Rect` the rectangle is `light` (docs/lights.md).
    pub emitter: crate::scene::emitter::Emitter,
    /// `[environment]`: the scene is lit by a panorama (docs/environment.md); `light` is then a
    /// nominal square above the meshes that only the area-light methods read.
    pub environment: Option<crate::scene::environment::Environment>,
    pub render: RenderSettings,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub albedos: Vec<[f32; 3]>,
    pub bounds: Bounds,
    /// What loading it found that the user should know, one line each, e.g. an open mesh under
    /// back-face culling (also handed to `progress::notice` as it loads).
    pub warnings: Vec<String>,
}

impl Scene {
    /// Moves the light by `by`: the emitter and the rectangle, or the emitter's stand-in square
    /// built afresh as the scene file's would be, so that the methods and the reference see the
    /// same light (before, a disk's, spot's or point's reference stayed where the file put it).
    pub fn move_light(&mut self, by: Vec3) {
        self.emitter = self.emitter.moved(by);
        match self.emitter.stand_in(&self.bounds) {
            Some(stand_in) => self.light = stand_in,
            None => self.light.center += by,
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The error for a camera that sees none of the meshes (also raised when the G-buffer holds no
    /// geometry pixel): it names the camera, which is where the fix lies.
    pub fn nothing_visible(&self) -> Error {
        self.nothing_visible_from(&self.camera)
    }

    /// [`Self::nothing_visible`] for another camera over these meshes (the embedding API moves it).
    pub(crate) fn nothing_visible_from(&self, c: &Camera) -> Error {
        if self.bounds_within_a_pixel(c) {
            // In view, but smaller than a pixel (a field of view near 180°, or a far camera).
            return Error::scene(
                &self.origin,
                format!(
                    "the meshes are in view but smaller than one pixel at {}x{} (camera.fov_y_deg = {}, camera.eye = {:?}): narrow the field of view, move the camera closer or raise the resolution",
                    self.render.width,
                    self.render.height,
                    c.fov_y_deg,
                    c.eye.to_array()
                ),
            );
        }
        Error::scene(
            &self.origin,
            format!(
                "no mesh is visible from the camera (camera.eye = {:?}, camera.target = {:?}, camera.fov_y_deg = {}; the meshes span {:?} to {:?}): point the camera at them",
                c.eye.to_array(),
                c.target.to_array(),
                c.fov_y_deg,
                self.bounds.min.to_array(),
                self.bounds.max.to_array()
            ),
        )
    }

    /// Whether the meshes' bounding box lies wholly outside the camera's view (then nothing shows).
    pub(crate) fn bounds_outside_view(&self) -> bool {
        self.bounds_outside(&self.camera)
    }

    /// [`Self::bounds_outside_view`] for another camera.
    pub(crate) fn bounds_outside(&self, camera: &Camera) -> bool {
        let aspect = self.render.width as f32 / self.render.height as f32;
        let m = camera.clip_from_world(aspect, &self.bounds);
        let (lo, hi) = (self.bounds.min, self.bounds.max);
        let clip: Vec<glam::Vec4> = (0..8)
            .map(|i| {
                m * Vec3::new(
                    [lo.x, hi.x][i & 1],
                    [lo.y, hi.y][(i >> 1) & 1],
                    [lo.z, hi.z][i >> 2],
                )
                .extend(1.0)
            })
            .collect();
        // One clip plane (left, right, bottom, top, near, far: depth 0..w) with every corner outside.
        let planes: [fn(&glam::Vec4) -> bool; 6] = [
            |c| c.x < -c.w,
            |c| c.x > c.w,
            |c| c.y < -c.w,
            |c| c.y > c.w,
            |c| c.z < 0.0,
            |c| c.z > c.w,
        ];
        planes.iter().any(|outside| clip.iter().all(outside))
    }

    /// Whether the meshes' bounding box lies wholly in front of `c` and projects within one pixel.
    fn bounds_within_a_pixel(&self, c: &Camera) -> bool {
        let (w, h) = (self.render.width as f32, self.render.height as f32);
        let m = c.clip_from_world(w / h, &self.bounds);
        let (lo, hi) = (self.bounds.min, self.bounds.max);
        let (mut min, mut max) = (
            glam::Vec2::splat(f32::INFINITY),
            glam::Vec2::splat(f32::NEG_INFINITY),
        );
        for i in 0..8 {
            let p = m * Vec3::new(
                [lo.x, hi.x][i & 1],
                [lo.y, hi.y][(i >> 1) & 1],
                [lo.z, hi.z][i >> 2],
            )
            .extend(1.0);
            if !(p.w > 0.0 && p.z >= 0.0) {
                return false;
            }
            let ndc = glam::Vec2::new(p.x, p.y) / p.w;
            (min, max) = (min.min(ndc), max.max(ndc));
        }
        // NDC spans 2 across the screen.
        (max.x - min.x) * w / 2.0 < 1.0 && (max.y - min.y) * h / 2.0 < 1.0
    }

    /// World-space triangles, for CPU tracers and tests.
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        self.indices
            .chunks_exact(3)
            .map(|t| [0, 1, 2].map(|k| Vec3::from(self.vertices[t[k] as usize].position)))
            .collect()
    }
}
