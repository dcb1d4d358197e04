//! What moves in a sequence and along which path (docs/sequence.md). Frame i of N sits at
//! s = i/(N−1) along a segment or an orbit (both ends included) and at angle 2π·i/N on a circle
//! (a closed loop: frame N would repeat frame 0).

use crate::scene::light::Bounds;
use crate::scene::Scene;
use crate::{Error, Result};
use glam::{Quat, Vec3};

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Subject {
    Light,
    Camera,
    Occluder,
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "lowercase", tag = "path")]
pub enum Path {
    /// From the scene's position to position + offset.
    Segment { offset: [f32; 3] },
    /// Around the scene's position: in the light's plane for the light, in the xz plane for a mesh.
    Circle { radius: f32 },
    /// The camera's eye about the line through the target along `up`, by `degrees` in all.
    Orbit { degrees: f32 },
}

/// A moving subject and its path; `mesh` is the 0-based index of the moving `[[mesh]]`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Animation {
    pub subject: Subject,
    #[serde(flatten)]
    pub path: Path,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<usize>,
}

/// The command line's words for an animation, checked against the scene.
#[derive(Clone, Debug, Default)]
pub struct AnimationSpec {
    pub animate: String,
    pub path: Option<String>,
    pub offset: Option<String>,
    pub radius: Option<f32>,
    pub degrees: Option<f32>,
    /// 1-based, as scene errors count meshes.
    pub mesh: Option<u32>,
}

fn param(msg: String) -> Error {
    Error::param(msg)
}

fn parse_vec3(text: &str) -> Result<[f32; 3]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let nums: Vec<f32> = parts
        .iter()
        .filter_map(|p| p.parse::<f32>().ok())
        .filter(|x| x.is_finite())
        .collect();
    if parts.len() != 3 || nums.len() != 3 {
        return Err(param(format!(
            "--offset {text}: expected three finite numbers x,y,z"
        )));
    }
    Ok([nums[0], nums[1], nums[2]])
}

/// A path may reach this many scene diagonals: farther, the subject has left the scene (and an
/// offset of 1e30 put the light beyond f32's useful range: the frames are not checked as the file is).
pub const MAX_REACH_DIAGONALS: f32 = 100.0;

/// Checks how far a path reaches (an offset's largest component, a radius) against the scene's size, and the moved subject against the scene
/// file's coordinate bound.
fn within_reach(given: &str, length: f32, subject: Subject, scene: &Scene) -> Result<()> {
    let diagonal = scene.bounds.diagonal();
    let limit = MAX_REACH_DIAGONALS * diagonal;
    if length > limit {
        return Err(param(format!("{given}: reaches {length:e}, beyond {MAX_REACH_DIAGONALS} × the scene's diagonal of {diagonal:.1} (at most {limit:.1})")));
    }
    let (what, far) = match subject {
        Subject::Light => ("light", scene.light.center.abs().max_element()),
        Subject::Camera => (
            "camera",
            scene
                .camera
                .eye
                .abs()
                .max(scene.camera.target.abs())
                .max_element(),
        ),
        Subject::Occluder => (
            "mesh",
            scene
                .bounds
                .min
                .abs()
                .max(scene.bounds.max.abs())
                .max_element(),
        ),
    };
    let bound = crate::scene::MAX_COORDINATE;
    if far + length > bound {
        return Err(param(format!(
            "{given}: moves the {what} beyond ±{bound:e}, the scene file's coordinate bound"
        )));
    }
    Ok(())
}

impl AnimationSpec {
    /// Checks the words and fills in the defaults (docs/sequence.md): the light moves two light
    /// widths along its u edge, the camera orbits 30°, the last mesh moves a tenth of the scene's
    /// diagonal along +x.
    pub fn resolve(&self, scene: &Scene) -> Result<Animation> {
        let subject = match self.animate.as_str() {
            "light" => Subject::Light,
            "camera" => Subject::Camera,
            "occluder" => Subject::Occluder,
            other => {
                return Err(param(format!(
                    "--animate {other}: use light, camera or occluder"
                )))
            }
        };
        if subject == Subject::Light && matches!(scene.emitter, crate::scene::Emitter::Sun(_)) {
            return Err(param(format!(
                "--animate light: {}'s light is a sun (kind = \"sun\"), which has a direction but no position, so moving it changes nothing; animate the camera (--animate camera) or a mesh (--animate occluder)",
                scene.origin
            )));
        }
        let default_path = if subject == Subject::Camera {
            "orbit"
        } else {
            "segment"
        };
        let path_name = self.path.as_deref().unwrap_or(default_path);
        let allowed: &[&str] = match subject {
            Subject::Light | Subject::Occluder => &["segment", "circle"],
            Subject::Camera => &["orbit", "segment"],
        };
        if !allowed.contains(&path_name) {
            return Err(param(format!(
                "--path {path_name}: --animate {} moves along {}",
                self.animate,
                allowed.join(" or ")
            )));
        }
        let unused = |flag: &str, given: bool| -> Result<()> {
            if given {
                return Err(param(format!(
                    "{flag} does not apply to --path {path_name}"
                )));
            }
            Ok(())
        };
        let path = match path_name {
            "segment" => {
                unused("--radius", self.radius.is_some())?;
                unused("--degrees", self.degrees.is_some())?;
                let offset = match &self.offset {
                    Some(text) => {
                        let offset = parse_vec3(text)?;
                        // The largest component: the length of 1e30 overflows f32.
                        within_reach(
                            &format!("--offset {text}"),
                            Vec3::from(offset).abs().max_element(),
                            subject,
                            scene,
                        )?;
                        offset
                    }
                    None => match subject {
                        Subject::Light => (scene.light.edge_u * 2.0).to_array(),
                        _ => [scene.bounds.diagonal() * 0.1, 0.0, 0.0],
                    },
                };
                Path::Segment { offset }
            }
            "circle" => {
                unused("--offset", self.offset.is_some())?;
                unused("--degrees", self.degrees.is_some())?;
                let radius = self.radius.unwrap_or_else(|| match subject {
                    Subject::Light => scene.light.edge_u.length(),
                    _ => scene.bounds.diagonal() * 0.05,
                });
                if !(radius.is_finite() && radius > 0.0) {
                    return Err(param(format!(
                        "--radius {radius}: must be a finite number > 0"
                    )));
                }
                within_reach(&format!("--radius {radius}"), radius, subject, scene)?;
                Path::Circle { radius }
            }
            _ => {
                unused("--offset", self.offset.is_some())?;
                unused("--radius", self.radius.is_some())?;
                let degrees = self.degrees.unwrap_or(30.0);
                if !(degrees.is_finite() && degrees.abs() <= 360.0) {
                    return Err(param(format!("--degrees {degrees}: must be in -360..=360")));
                }
                Path::Orbit { degrees }
            }
        };
        let meshes = scene.albedos.len();
        let mesh = match (subject, self.mesh) {
            (Subject::Occluder, None) => Some(meshes - 1),
            (Subject::Occluder, Some(k)) if k >= 1 && (k as usize) <= meshes => {
                Some(k as usize - 1)
            }
            (Subject::Occluder, Some(k)) => {
                return Err(param(format!(
                    "--mesh {k}: {} has meshes 1..={meshes}",
                    scene.origin
                )));
            }
            (_, Some(k)) => {
                return Err(param(format!(
                    "--mesh {k}: only --animate occluder moves a mesh"
                )))
            }
            (_, None) => None,
        };
        Ok(Animation {
            subject,
            path,
            mesh,
        })
    }
}

impl Animation {
    /// The scene of frame `i` of `frames` (frames ≥ 2).
    pub fn frame(&self, scene: &Scene, i: u32, frames: u32) -> Scene {
        let s = i as f32 / (frames.max(2) - 1) as f32;
        let angle = std::f32::consts::TAU * i as f32 / frames.max(1) as f32;
        let mut out = scene.clone();
        match (self.subject, self.path) {
            (Subject::Light, Path::Segment { offset }) => out.move_light(s * Vec3::from(offset)),
            (Subject::Light, Path::Circle { radius }) => {
                let (u, v) = (
                    scene.light.edge_u.normalize(),
                    scene.light.edge_v.normalize(),
                );
                out.move_light(radius * (angle.cos() * u + angle.sin() * v));
            }
            (Subject::Camera, Path::Orbit { degrees }) => {
                let c = &scene.camera;
                let turn = Quat::from_axis_angle(c.up.normalize(), (s * degrees).to_radians());
                out.camera.eye = c.target + turn * (c.eye - c.target);
            }
            (Subject::Camera, Path::Segment { offset }) => {
                out.camera.eye += s * Vec3::from(offset);
                out.camera.target += s * Vec3::from(offset);
            }
            (Subject::Occluder, _) => {
                let shift = self.shift(i, frames);
                let mesh = self.moving_mesh(scene);
                for v in out.vertices.iter_mut().filter(|v| v.material == mesh) {
                    v.position = (Vec3::from(v.position) + shift).to_array();
                }
                out.bounds = self.swept_bounds(scene, frames);
            }
            // `resolve` admits no other pairing.
            _ => {}
        }
        out
    }

    /// The moving mesh's material index.
    fn moving_mesh(&self, scene: &Scene) -> u32 {
        self.mesh.unwrap_or(scene.albedos.len() - 1) as u32
    }

    /// How far the moving mesh is moved in frame `i` of `frames`.
    fn shift(&self, i: u32, frames: u32) -> Vec3 {
        let s = i as f32 / (frames.max(2) - 1) as f32;
        let angle = std::f32::consts::TAU * i as f32 / frames.max(1) as f32;
        match self.path {
            Path::Segment { offset } => s * Vec3::from(offset),
            Path::Circle { radius } => radius * Vec3::new(angle.cos(), 0.0, angle.sin()),
            Path::Orbit { .. } => Vec3::ZERO,
        }
    }

    /// The scene's bounds over the whole path: the still meshes and every place the moving one
    /// takes. Every frame's shadow maps are fitted to them, so a map's frustum does not follow the
    /// mesh and a map the mesh does not touch stays what it was (docs/reuse.md).
    fn swept_bounds(&self, scene: &Scene, frames: u32) -> Bounds {
        let mesh = self.moving_mesh(scene);
        let empty = || Bounds {
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
        };
        let (mut still, mut moving) = (empty(), empty());
        for v in &scene.vertices {
            let b = if v.material == mesh {
                &mut moving
            } else {
                &mut still
            };
            b.min = b.min.min(Vec3::from(v.position));
            b.max = b.max.max(Vec3::from(v.position));
        }
        for i in 0..frames.max(2) {
            let d = self.shift(i, frames);
            still.min = still.min.min(moving.min + d);
            still.max = still.max.max(moving.max + d);
        }
        still
    }

    /// One line for logs and the report: `light along a segment by (3.2, 0, 0)`.
    pub fn describe(&self, scene: &Scene) -> String {
        let what = match (self.subject, self.mesh) {
            (Subject::Light, _) => "light".to_string(),
            (Subject::Camera, _) => "camera".to_string(),
            (Subject::Occluder, Some(k)) => format!("mesh {} of {}", k + 1, scene.name),
            (Subject::Occluder, None) => "occluder".to_string(),
        };
        match self.path {
            Path::Segment { offset: [x, y, z] } => {
                format!("{what} along a segment by ({x}, {y}, {z})")
            }
            Path::Circle { radius } => format!("{what} around a circle of radius {radius}"),
            Path::Orbit { degrees } => format!("{what} orbiting the target by {degrees}°"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = r#"
[camera]
eye = [0.0, 0.0, 10.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 45.0
[light]
center = [0.0, 8.0, 0.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 0.0, 2.0]
[[mesh]]
builtin = "plane"
[[mesh]]
builtin = "box"
translate = [0.0, 2.0, 0.0]
"#;

    fn scene() -> Scene {
        Scene::parse(SCENE, "test.toml", None, &[]).unwrap()
    }

    fn spec(animate: &str) -> AnimationSpec {
        AnimationSpec {
            animate: animate.into(),
            ..Default::default()
        }
    }

    #[test]
    fn light_segment_ends_at_the_offset() {
        let s = scene();
        let a = AnimationSpec {
            offset: Some("4,0,-2".into()),
            ..spec("light")
        }
        .resolve(&s)
        .unwrap();
        assert_eq!(a.frame(&s, 0, 5).light.center, Vec3::new(0.0, 8.0, 0.0));
        assert_eq!(a.frame(&s, 2, 5).light.center, Vec3::new(2.0, 8.0, -1.0));
        assert_eq!(a.frame(&s, 4, 5).light.center, Vec3::new(4.0, 8.0, -2.0));
    }

    #[test]
    fn a_moved_disk_moves_its_emitter_and_a_sun_is_not_moved() {
        let disk = SCENE.replace(
            "center = [0.0, 8.0, 0.0]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]",
            "kind = \"disk\"\ncenter = [0.0, 8.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nradius = 1.0",
        );
        let s = Scene::parse(&disk, "disk.toml", None, &[]).unwrap();
        let a = AnimationSpec {
            offset: Some("3,0,0".into()),
            ..spec("light")
        }
        .resolve(&s)
        .unwrap();
        let end = a.frame(&s, 1, 2);
        let crate::scene::Emitter::Disk(d) = end.emitter else {
            panic!("not a disk")
        };
        assert_eq!(
            (d.center, end.light.center),
            (Vec3::new(3.0, 8.0, 0.0), Vec3::new(3.0, 8.0, 0.0))
        );
        let sun = SCENE.replace(
            "center = [0.0, 8.0, 0.0]\nedge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 2.0]",
            "kind = \"sun\"\ndirection = [0.3, -1.0, 0.0]\nangular_diameter_deg = 1.0",
        );
        let s = Scene::parse(&sun, "sun.toml", None, &[]).unwrap();
        assert_eq!(
            spec("light").resolve(&s).unwrap_err().to_string(),
            "--animate light: sun.toml's light is a sun (kind = \"sun\"), which has a direction but no position, so moving it changes nothing; animate the camera (--animate camera) or a mesh (--animate occluder)"
        );
    }

    #[test]
    fn light_circle_stays_in_the_light_plane() {
        let s = scene();
        let a = AnimationSpec {
            path: Some("circle".into()),
            radius: Some(3.0),
            ..spec("light")
        }
        .resolve(&s)
        .unwrap();
        let c = a.frame(&s, 1, 4).light.center; // a quarter turn: along edge_v
        assert!((c - Vec3::new(0.0, 8.0, 3.0)).length() < 1e-5, "{c}");
    }

    #[test]
    fn camera_orbit_keeps_the_distance() {
        let s = scene();
        let a = AnimationSpec {
            degrees: Some(90.0),
            ..spec("camera")
        }
        .resolve(&s)
        .unwrap();
        let eye = a.frame(&s, 1, 2).camera.eye;
        assert!((eye - Vec3::new(10.0, 0.0, 0.0)).length() < 1e-4, "{eye}");
    }

    #[test]
    fn occluder_moves_only_its_mesh_and_the_bounds_follow() {
        let s = scene();
        let a = AnimationSpec {
            offset: Some("0,3,0".into()),
            ..spec("occluder")
        }
        .resolve(&s)
        .unwrap();
        assert_eq!(a.mesh, Some(1));
        let end = a.frame(&s, 1, 2);
        for (v0, v1) in s.vertices.iter().zip(&end.vertices) {
            let dy = v1.position[1] - v0.position[1];
            assert_eq!(dy, if v0.material == 1 { 3.0 } else { 0.0 });
        }
        // Every frame's bounds are the path's: the maps' frusta stay put.
        assert_eq!(end.bounds.max.y, s.bounds.max.y + 3.0);
        let start = a.frame(&s, 0, 2);
        assert_eq!(
            (start.bounds.min, start.bounds.max),
            (end.bounds.min, end.bounds.max)
        );
        assert_eq!(start.bounds.min.y, s.bounds.min.y);
    }

    #[test]
    fn bad_words_name_the_flag_and_value() {
        let s = scene();
        let err = |sp: AnimationSpec| sp.resolve(&s).unwrap_err().to_string();
        assert_eq!(
            err(spec("sun")),
            "--animate sun: use light, camera or occluder"
        );
        assert_eq!(
            err(AnimationSpec {
                path: Some("orbit".into()),
                ..spec("light")
            }),
            "--path orbit: --animate light moves along segment or circle"
        );
        assert_eq!(
            err(AnimationSpec {
                offset: Some("1,2".into()),
                ..spec("light")
            }),
            "--offset 1,2: expected three finite numbers x,y,z"
        );
        assert_eq!(
            err(AnimationSpec {
                mesh: Some(3),
                ..spec("occluder")
            }),
            "--mesh 3: test.toml has meshes 1..=2"
        );
        assert_eq!(
            err(AnimationSpec {
                mesh: Some(1),
                ..spec("light")
            }),
            "--mesh 1: only --animate occluder moves a mesh"
        );
        assert_eq!(
            err(AnimationSpec {
                radius: Some(1.0),
                ..spec("light")
            }),
            "--radius does not apply to --path segment"
        );
    }
}
