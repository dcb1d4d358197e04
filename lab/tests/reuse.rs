//! Shadow maps kept from frame to frame (docs/reuse.md). A kept map is bit for bit the map a new
//! renderer would rasterize, so V with reuse equals V without on every frame: for every method
//! that lights with the rectangle, along a camera, a light and an occluder path. A moved mesh
//! redraws only the texels it covered before or covers now, and the rest of each map is not
//! written at all.

#[macro_use]
mod common;
use penumbra::research::frame::{Detached, FrameOptions, FrameResult, Renderer};
use penumbra::research::gpu::readback;
use penumbra::research::gpu::timing::TimingMode;
use penumbra::research::methods::fixed_samples::FixedBuffers;
use penumbra::research::methods::{Method, REGISTRY};
use penumbra::research::scene::Scene;
use penumbra_lab::studies::sequence::path::{Animation, Path, Subject};

const FRAMES: u32 = 3;

fn options() -> FrameOptions {
    FrameOptions {
        mode: TimingMode::Frame,
        pictures: false,
    }
}

/// The three paths: the last mesh moves a little, so it touches a small part of each map.
fn paths() -> [(&'static str, Animation); 3] {
    [
        (
            "camera",
            Animation {
                subject: Subject::Camera,
                path: Path::Orbit { degrees: 12.0 },
                mesh: None,
            },
        ),
        (
            "light",
            Animation {
                subject: Subject::Light,
                path: Path::Segment {
                    offset: [1.0, 0.0, -0.5],
                },
                mesh: None,
            },
        ),
        (
            "occluder",
            Animation {
                subject: Subject::Occluder,
                path: Path::Segment {
                    offset: [0.4, 0.0, 0.2],
                },
                mesh: None,
            },
        ),
    ]
}

/// A frame of `scene` on the renderer `kept` left (or a new one), and what it leaves.
fn frame_on<'a>(
    ctx: &'a penumbra::research::gpu::GpuContext,
    scene: &'a Scene,
    method: &Method,
    kept: Option<Detached>,
    reuse: bool,
) -> (FrameResult, Detached) {
    let mut r = match kept {
        Some(d) => d.attach(ctx, scene).unwrap(),
        None => Renderer::with_reuse(ctx, scene, method, reuse).unwrap(),
    };
    let f = r.frame(options()).unwrap();
    (f, r.detach())
}

fn differing(a: &[f32], b: &[f32]) -> usize {
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

#[test]
fn reuse_changes_no_pixel_on_any_path() {
    let ctx = common::gpu();
    let base = Scene::parse(
        &common::random_scene_toml(7, 48, 128),
        "random-7",
        None,
        &[],
    )
    .unwrap();
    // Every registered method the rectangle lights (the environment methods light with a
    // panorama and cascades with a sun; neither keeps maps), with its defaults, and the settings
    // whose maps are kept differently: centred and culled grids, the adaptive presets and scopes,
    // the GPU-steered loop, the hysteresis, auto priced without timing, regions without culling.
    let mut specs: Vec<String> = REGISTRY
        .iter()
        .map(|m| Method::parse(m.name, &[]).unwrap())
        .filter(|m| {
            m.family() != penumbra::research::methods::Family::Environment
                && m.check_light(&base).is_ok()
        })
        .map(|m| m.label())
        .filter(|l| l != "auto")
        .collect();
    specs.extend(
        [
            "regular:n=3",
            "regular:n=4,layout=centred",
            "regular:n=3,cull=on",
            "adaptive:preset=balanced",
            "adaptive:scope=local",
            "adaptive:steer=gpu",
            "adaptive:p_m=0,max_level=3,weights=coons,hold=6",
            "auto:target=0.1,cost=texels,filters=none,max_size=512,max_n=5",
            "regions:cull=off",
        ]
        .map(String::from),
    );
    let mut kept_somewhere = std::collections::BTreeMap::new();
    for (name, path) in paths() {
        // A moving light keeps nothing: two frames show it.
        let frames = if name == "light" { 2 } else { FRAMES };
        let scenes: Vec<Scene> = (0..frames).map(|i| path.frame(&base, i, frames)).collect();
        for spec in &specs {
            let start = std::time::Instant::now();
            let method = Method::parse(spec, &[]).unwrap();
            let (mut off, mut on) = (None, None);
            for (i, scene) in scenes.iter().enumerate() {
                let (a, d) = frame_on(ctx, scene, &method, off.take(), false);
                off = Some(d);
                let (b, d) = frame_on(ctx, scene, &method, on.take(), true);
                on = Some(d);
                let differ = differing(&a.visibility, &b.visibility);
                assert_eq!(
                    differ, 0,
                    "{spec}, {name} path, frame {i}: V with reuse differs in {differ} pixels"
                );
                assert_eq!(
                    a.output.shadow_maps, b.output.shadow_maps,
                    "{spec}, {name} path, frame {i}: maps"
                );
                let r = b.reuse;
                assert_eq!(
                    r.rendered + r.kept + r.redrawn,
                    b.output.shadow_maps,
                    "{spec}, {name} path, frame {i}: every map is rendered, kept or redrawn: {r:?}"
                );
                assert_eq!(
                    a.reuse.kept + a.reuse.redrawn,
                    0,
                    "{spec}, {name} path, frame {i}: without reuse every map is rendered"
                );
                if i == 0 || name == "light" {
                    // Nothing to keep: the first frame, and a light that moves every frame.
                    assert_eq!(
                        r.kept + r.redrawn,
                        0,
                        "{spec}, {name} path, frame {i}: {r:?}"
                    );
                }
                if spec == "regular:n=17" {
                    // 289 maps of 128² fit the default budget: nothing is evicted.
                    assert_eq!(r.evicted, 0, "{spec}, {name} path, frame {i}: {r:?}");
                }
                if i > 0 {
                    *kept_somewhere.entry((name, spec.clone())).or_insert(0) += r.kept + r.redrawn;
                }
            }
            println!(
                "{name} path, {spec}: {:.1} s",
                start.elapsed().as_secs_f64()
            );
        }
        println!(
            "{name} path: {} methods, {frames} frames each, V equal with and without reuse",
            specs.len()
        );
    }
    // What is kept where: a regular grid keeps all its maps on the camera path, adaptive the
    // lattice maps it rendered; a moved mesh leaves the maps it does not touch kept and redraws
    // part of the others; maps that serve only this frame's pixels (culled) are never kept.
    let kept = |path: &str, spec: &str| kept_somewhere[&(path, spec.to_string())];
    assert_eq!(kept("camera", "regular:n=3"), 9 * (FRAMES - 1));
    assert_eq!(kept("camera", "regular:n=17"), 289 * (FRAMES - 1));
    assert!(kept("camera", "adaptive:preset=balanced") > 4 * (FRAMES - 1));
    assert!(kept("camera", "adaptive:scope=local") > 4 * (FRAMES - 1));
    assert_eq!(kept("camera", "regular:n=3,cull=on"), 0);
    assert_eq!(kept("camera", "adaptive:steer=gpu"), 0);
    assert!(kept("occluder", "regular:n=3") > 0);
    assert!(
        kept(
            "camera",
            "auto:target=0.1,cost=texels,filters=none,max_size=512,max_n=5"
        ) > 0
    );
}

/// The budget holds fewer maps than the method uses: a fixed grid keeps its first maps and draws
/// the rest every frame in the layers left; adaptive evicts the least recently used map. V still
/// equals the frame without reuse.
#[test]
fn a_full_cache_evicts_and_changes_no_pixel() {
    let ctx = common::gpu();
    // 128² maps are 64 KiB: a 1 MiB budget holds 16.
    let sets = [("shadow_map_budget_mib".to_string(), "1".to_string())];
    let base = Scene::parse(
        &common::random_scene_toml(11, 48, 128),
        "random-11",
        None,
        &sets,
    )
    .unwrap();
    let (_, camera) = &paths()[0];
    let scenes: Vec<Scene> = (0..FRAMES)
        .map(|i| camera.frame(&base, i, FRAMES))
        .collect();
    for spec in ["regular:n=5", "adaptive:p_m=-1,max_level=2,weights=area"] {
        let method = Method::parse(spec, &[]).unwrap();
        let (mut off, mut on) = (None, None);
        for (i, scene) in scenes.iter().enumerate() {
            let (a, d) = frame_on(ctx, scene, &method, off.take(), false);
            off = Some(d);
            let (b, d) = frame_on(ctx, scene, &method, on.take(), true);
            let bytes = d.maps_kept().bytes();
            on = Some(d);
            assert_eq!(
                differing(&a.visibility, &b.visibility),
                0,
                "{spec}, frame {i}"
            );
            assert!(
                bytes <= 1024 * 1024,
                "{spec}: {bytes} bytes kept over the 1 MiB budget"
            );
            if i > 0 {
                // 25 maps in 16 layers: some kept, some drawn again over maps the frame before
                // kept there, and the counts say so (the sequence prints them).
                assert!(
                    b.reuse.kept > 0 && b.reuse.rendered > 0 && b.reuse.evicted > 0,
                    "{spec}, frame {i}: {:?}",
                    b.reuse
                );
                assert!(b.reuse.evicted <= b.reuse.rendered, "{:?}", b.reuse);
            }
        }
    }
}

/// The maps' layers of `owner` after a frame, as u32 words.
fn layers(
    ctx: &penumbra::research::gpu::GpuContext,
    d: &Detached,
    owner: &str,
    maps: u32,
) -> Vec<Vec<u32>> {
    d.maps_kept().with_kept(owner, |k| {
        let k = k.expect("kept maps");
        (0..maps)
            .map(|l| readback::read_texture::<u32>(ctx, &k.arrays[0].texture, l, 4).unwrap())
            .collect()
    })
}

/// One small mesh moves: each kept map redraws the rectangle the mesh covered before or covers
/// now, and equals a new renderer's map bit for bit; under the compute raster, whose layers take
/// writes, every texel outside that rectangle keeps a marker written before the frame: it was not
/// written at all.
#[test]
fn a_moved_mesh_redraws_only_what_it_touches() {
    let ctx = common::gpu();
    let text = format!(
        "{}[[mesh]]\nbuiltin = \"plane\"\nscale = [12.0, 1.0, 12.0]\n\n[[mesh]]\nbuiltin = \"box\"\ntranslate = [-1.5, 1.0, 0.0]\nscale = 1.2\n\n[[mesh]]\nbuiltin = \"box\"\ntranslate = [1.5, 2.5, 0.5]\nscale = 0.3\n",
        tiny_scene_head!()
    );
    let method = Method::parse("regular:n=2", &[]).unwrap();
    let moved = Animation {
        subject: Subject::Occluder,
        path: Path::Segment {
            offset: [0.2, 0.0, 0.1],
        },
        mesh: None,
    };
    for raster in ["compute", "hardware"] {
        let sets = [
            ("raster".to_string(), raster.to_string()),
            ("shadow_map_size".to_string(), "128".to_string()),
            ("width".to_string(), "64".to_string()),
            ("height".to_string(), "64".to_string()),
        ];
        let base = Scene::parse(&text, "tiny-moved", None, &sets).unwrap();
        let (before, after) = (moved.frame(&base, 0, 2), moved.frame(&base, 1, 2));
        let (_, d) = frame_on(ctx, &before, &method, None, true);
        const MARK: u32 = 0x0bad_f00d;
        if raster == "compute" {
            d.maps_kept().with_kept("fixed", |k| {
                let k = k.expect("kept maps");
                let words = vec![MARK; 128 * 128];
                for l in 0..4 {
                    ctx.queue.write_texture(
                        wgpu::TexelCopyTextureInfo {
                            texture: &k.arrays[0].texture,
                            mip_level: 0,
                            origin: wgpu::Origin3d { x: 0, y: 0, z: l },
                            aspect: wgpu::TextureAspect::All,
                        },
                        bytemuck::cast_slice(&words),
                        wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(128 * 4),
                            rows_per_image: Some(128),
                        },
                        wgpu::Extent3d {
                            width: 128,
                            height: 128,
                            depth_or_array_layers: 1,
                        },
                    );
                }
            });
        }
        let (f, d) = frame_on(ctx, &after, &method, Some(d), true);
        assert_eq!(
            (f.reuse.redrawn, f.reuse.rendered),
            (4, 0),
            "{raster}: every map redraws a rectangle: {:?}",
            f.reuse
        );
        let kept = layers(ctx, &d, "fixed", 4);
        let (_, fresh): (_, FixedBuffers) = common::inspected(ctx, &after, &method, options());
        let mut written = 0u64;
        for (l, (got, want)) in kept.iter().zip(&fresh.maps).enumerate() {
            let want: Vec<u32> = want.iter().map(|x| x.to_bits()).collect();
            if raster == "compute" {
                let rewritten: Vec<usize> = (0..got.len()).filter(|&t| got[t] != MARK).collect();
                for &t in &rewritten {
                    assert_eq!(
                        got[t], want[t],
                        "{raster}: map {l}, texel {t} redrawn differs from a new renderer's"
                    );
                }
                written += rewritten.len() as u64;
                assert!(!rewritten.is_empty(), "{raster}: map {l}: nothing redrawn");
            } else {
                let differ = got.iter().zip(&want).filter(|(a, b)| a != b).count();
                assert_eq!(differ, 0, "{raster}: map {l} kept and redrawn differs from a new renderer's in {differ} texels");
            }
        }
        let total = 4 * 128 * 128;
        if raster == "compute" {
            assert_eq!(
                written, f.reuse.texels,
                "the texels counted are the texels written"
            );
        }
        assert!(
            f.reuse.texels * 10 < total,
            "{raster}: the small mesh redrew {} of {total} texels",
            f.reuse.texels
        );
        println!(
            "{raster}: the moved mesh redrew {} of {total} texels ({:.1}%)",
            f.reuse.texels,
            100.0 * f.reuse.texels as f64 / total as f64
        );
    }
}

/// The hysteresis (`hold`): with a margin no quad reaches, a frame splits only quads the previous
/// frame split; without one, the moving light makes it split others.
#[test]
fn a_held_decision_splits_only_what_it_split_before() {
    let ctx = common::gpu();
    let base = Scene::parse(
        &common::random_scene_toml(7, 48, 128),
        "random-7",
        None,
        &[],
    )
    .unwrap();
    // Two light widths in four frames: the penumbrae move across the quads.
    let light = Animation {
        subject: Subject::Light,
        path: Path::Segment {
            offset: [5.0, 0.0, -4.0],
        },
        mesh: None,
    };
    let scenes: Vec<Scene> = (0..4).map(|i| light.frame(&base, i, 4)).collect();
    let split_sets = |spec: &str| -> Vec<Vec<u32>> {
        let method = Method::parse(spec, &[]).unwrap();
        let mut kept: Option<Detached> = None;
        let mut sets = Vec::new();
        for scene in &scenes {
            let mut r = match kept.take() {
                Some(d) => d.attach(ctx, scene).unwrap(),
                None => Renderer::new(ctx, scene, &method).unwrap(),
            };
            r.frame(options()).unwrap();
            let trace: penumbra::research::methods::adaptive::AdaptiveTrace =
                r.inspect().unwrap().expect("a trace");
            let bits = penumbra::research::methods::adaptive::split_quads(&trace.levels);
            sets.push(
                (0..341u32)
                    .filter(|&n| (bits[(n / 32) as usize] >> (n % 32)) & 1 == 1)
                    .collect(),
            );
            kept = Some(r.detach());
        }
        sets
    };
    let free = split_sets("adaptive:p_m=2");
    let held = split_sets("adaptive:p_m=2,hold=1000000");
    assert_eq!(
        free[0], held[0],
        "the first frame has no history: the same decision"
    );
    let new_splits = |sets: &[Vec<u32>]| {
        sets.windows(2)
            .map(|w| w[1].iter().filter(|n| !w[0].contains(n)).count())
            .sum::<usize>()
    };
    assert!(
        new_splits(&free) > 0,
        "the light's move splits new quads without hysteresis: {free:?}"
    );
    assert_eq!(
        new_splits(&held),
        0,
        "a held frame split a quad the previous frame did not: {held:?}"
    );
}
