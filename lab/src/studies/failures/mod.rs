//! `penumbra failures`: the failure gallery. Every failure scene (embedded: they use built-in meshes
//! only) is rendered with every method at a small resolution and judged against its CPU reference;
//! the report shows the signed error maps side by side with one sentence per scene generated from
//! the figures (`sentence`), and a short sequence where the adaptive decision pops.

pub mod command;
pub(crate) mod sentence;

use crate::frame::{Detached, FrameOptions, Renderer};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::metrics::signed_error_image;
use crate::record::run_files;
use crate::reference::truth::{self, Cache};
use crate::reference::ReferenceMode;
use crate::report::page::data_uri;
use crate::scene::Scene;
use crate::studies::compare::ERROR_SCALE;
use crate::studies::sequence::path::{Animation, Path, Subject};
use crate::studies::sequence::{self, SequenceJob, SequenceOutcome};
use crate::{Error, Result};
use minijinja::value::{Serde, Value};
use sentence::{Figures, Framing};
use serde::Serialize;

/// A failure scene and how its sentence reads.
pub struct Scenario {
    pub name: &'static str,
    pub text: &'static str,
    pub framing: Framing,
}

pub const SCENARIOS: [Scenario; 3] = [
    Scenario {
        name: "pole-between-corners",
        text: include_str!("../../../../scenes/pole-between-corners.toml"),
        framing: Framing {
            subject: Some("adaptive"),
            bright: "misses the pole",
            dark: "is too dark under the pole",
        },
    },
    Scenario {
        name: "overlapping-occluders",
        text: include_str!("../../../../scenes/overlapping-occluders.toml"),
        framing: Framing {
            subject: None,
            bright: "is too bright",
            dark: "is too dark",
        },
    },
    Scenario {
        name: "grazing-ground",
        text: include_str!("../../../../scenes/grazing-ground.toml"),
        framing: Framing {
            subject: None,
            bright: "leaks light at grazing incidence",
            dark: "shows acne on the lit ground",
        },
    },
];

/// The popping sequence: the pole scene with the light sliding along x, so the pole's band of the
/// light crosses the level-0 corners and the adaptive decision flips between frames.
pub const POP_SCENE: &str = "pole-between-corners";
pub const POP_OFFSET: [f32; 3] = [2.0, 0.0, 0.0];

pub struct GalleryJob {
    pub methods: Vec<Method>,
    /// Width and height of every gallery image.
    pub resolution: u32,
    /// Frames of the popping sequence (0: none).
    pub frames: u32,
    pub reference: ReferenceMode,
    pub cache: Cache,
}

#[derive(Serialize)]
pub struct SceneOutcome {
    pub name: String,
    pub description: String,
    pub sentence: String,
    pub figures: Vec<Figures>,
    #[serde(skip)]
    pub reference_png: Vec<u8>,
    /// (method label, signed error map PNG).
    #[serde(skip)]
    pub error_pngs: Vec<(String, Vec<u8>)>,
}

pub struct Gallery {
    pub resolution: u32,
    pub reference: String,
    pub scenes: Vec<SceneOutcome>,
    pub sequence: Option<SequenceOutcome>,
    /// Every output file but the report, relative to the gallery's folder.
    pub files: Vec<(String, Vec<u8>)>,
}

/// The scene of a scenario at the gallery's resolution. The shadow map shrinks with the image (the
/// scene's map-to-image ratio is kept), so texels cover as much of the screen as at full size.
pub fn scene(s: &Scenario, resolution: u32) -> Result<Scene> {
    let origin = format!("{}.toml", s.name);
    let full = Scene::parse(s.text, &origin, None, &[])?;
    let ratio = f64::from(full.render.shadow_map_size)
        / f64::from(full.render.width.max(full.render.height));
    let map = ((f64::from(resolution) * ratio).round() as u32).max(16);
    let set = |k: &str, v: u32| (k.to_string(), v.to_string());
    Ok(Scene::parse(
        s.text,
        &origin,
        None,
        &[
            set("width", resolution),
            set("height", resolution),
            set("shadow_map_size", map),
        ],
    )?)
}

/// Pixels off by more than 1/32 on either side, with the mean V and reference there.
pub fn figures(
    label: &str,
    method: &str,
    maps: u32,
    v: &[f32],
    r: &[f32],
    mask: &[bool],
) -> Figures {
    let mut f = Figures {
        label: label.into(),
        method: method.into(),
        shadow_maps: maps,
        ..Default::default()
    };
    let (mut sq, t) = (0.0f64, crate::metrics::BAD_PIXEL_THRESHOLD);
    for i in (0..v.len()).filter(|&i| mask[i]) {
        let (vi, ri) = (f64::from(v[i]), f64::from(r[i]));
        sq += (vi - ri) * (vi - ri);
        f.pixels += 1;
        if vi - ri > t {
            f.bright += 1;
            f.bright_v += vi;
            f.bright_ref += ri;
        } else if ri - vi > t {
            f.dark += 1;
            f.dark_v += vi;
            f.dark_ref += ri;
        }
    }
    let mean = |s: f64, n: u64| if n == 0 { 0.0 } else { s / n as f64 };
    f.bright_v = mean(f.bright_v, f.bright);
    f.bright_ref = mean(f.bright_ref, f.bright);
    f.dark_v = mean(f.dark_v, f.dark);
    f.dark_ref = mean(f.dark_ref, f.dark);
    f.rmse = mean(sq, f.pixels).sqrt();
    f
}

/// `kept` holds each method's renderer from the scene before, moved to this one.
fn run_scene(
    ctx: &GpuContext,
    s: &Scenario,
    job: &GalleryJob,
    kept: &mut [Option<Detached>],
) -> Result<SceneOutcome> {
    let scene = scene(s, job.resolution)?;
    let (w, h) = (scene.render.width, scene.render.height);
    let (g, reference) = truth::for_scene(ctx, &scene, job.reference, &job.cache)?;
    let mask: Vec<bool> = (0..g.position.len()).map(|i| g.is_geometry(i)).collect();
    let mut out = SceneOutcome {
        name: s.name.into(),
        description: scene.description.clone(),
        sentence: String::new(),
        figures: Vec::new(),
        reference_png: run_files::png(&run_files::shaded_image(&reference.values, &g, &scene))?,
        error_pngs: Vec::new(),
    };
    for (method, kept) in job.methods.iter().zip(kept) {
        let mut renderer = match kept.take() {
            Some(d) => d.attach(ctx, &scene)?,
            None => Renderer::new(ctx, &scene, method)?,
        };
        let f = renderer.frame(FrameOptions {
            mode: TimingMode::Frame,
            pictures: false,
        })?;
        *kept = Some(renderer.detach());
        let differ = (0..mask.len())
            .filter(|&i| f.gbuffer.is_geometry(i) != mask[i])
            .count();
        if differ > 0 {
            return Err(Error::gpu(format!(
                "{} on {}: the G-buffer differs from the reference's in {differ} pixels",
                method.label(),
                s.name
            )));
        }
        out.figures.push(figures(
            &method.label(),
            method.name(),
            f.output.shadow_maps,
            &f.visibility,
            &reference.values,
            &mask,
        ));
        let signed =
            signed_error_image(&f.visibility, &reference.values, &mask, w, h, ERROR_SCALE)?;
        out.error_pngs
            .push((method.label(), run_files::png(&signed)?));
    }
    out.sentence = sentence::sentence(&s.framing, &out.figures);
    Ok(out)
}

/// Runs every scenario, then the popping sequence; `log` gets one line per scene.
pub fn run(ctx: &GpuContext, job: &GalleryJob, log: &dyn Fn(&str)) -> Result<Gallery> {
    if !(16..=2048).contains(&job.resolution) {
        return Err(Error::param(format!(
            "--resolution {}: must be in 16..=2048",
            job.resolution
        )));
    }
    let mut scenes = Vec::new();
    let mut kept: Vec<Option<Detached>> = job.methods.iter().map(|_| None).collect();
    for s in &SCENARIOS {
        let outcome = run_scene(ctx, s, job, &mut kept)?;
        log(&format!(
            "failure gallery, {}: {}",
            s.name, outcome.sentence
        ));
        scenes.push(outcome);
    }
    let sequence = if job.frames >= 2 {
        let s = SCENARIOS
            .iter()
            .find(|s| s.name == POP_SCENE)
            .ok_or_else(|| Error::param(format!("no scenario {POP_SCENE}")))?;
        let scene = scene(s, job.resolution)?;
        let animation = Animation {
            subject: Subject::Light,
            path: Path::Segment { offset: POP_OFFSET },
            mesh: None,
        };
        let seq = SequenceJob {
            scene: &scene,
            methods: popping_methods(&job.methods),
            frames: job.frames,
            animation,
            reference: job.reference,
            cache: job.cache.clone(),
            reuse: sequence::Reuse::On,
            timing: crate::gpu::timing::TimingMode::Frame,
        };
        Some(sequence::run(ctx, &seq, &|_| {})?)
    } else {
        None
    };
    if let Some(seq) = &sequence {
        for line in sequence::section::sentences(seq) {
            log(&format!("failure gallery, popping sequence: {line}"));
        }
    }
    let reference = truth::mode_label(&job.reference);
    let mut gallery = Gallery {
        resolution: job.resolution,
        reference,
        scenes,
        sequence,
        files: Vec::new(),
    };
    gallery.files = files_of(&gallery)?;
    Ok(gallery)
}

/// The popping sequence is about the adaptive decision: the adaptive methods, and the regular grid
/// with the most samples as the steady comparison (the others would only add time to the main job).
pub fn popping_methods(methods: &[Method]) -> Vec<Method> {
    let regular_n = |m: &Method| {
        if m.name() == "regular" {
            m.params_json().get("n").and_then(|n| n.as_u64())
        } else {
            None
        }
    };
    let densest = methods.iter().filter_map(regular_n).max();
    let keep: Vec<Method> = methods
        .iter()
        .filter(|m| {
            m.adaptive_params().is_some() || (regular_n(m).is_some() && regular_n(m) == densest)
        })
        .cloned()
        .collect();
    if keep.is_empty() {
        methods.to_vec()
    } else {
        keep
    }
}

fn files_of(g: &Gallery) -> Result<Vec<(String, Vec<u8>)>> {
    let mut files = Vec::new();
    let record = serde_json::json!({
        "resolution": [g.resolution, g.resolution],
        "reference": g.reference,
        "threshold": "pixels off by more than 1/32: bright = V above the reference, dark = below",
        "version": run_files::version(),
        "scenes": g.scenes,
    });
    let bytes = serde_json::to_vec_pretty(&record)
        .map_err(|e| Error::io_text("gallery.json".into(), e.to_string()))?;
    files.push(("gallery.json".to_string(), bytes));
    for s in &g.scenes {
        files.push((format!("{}/reference.png", s.name), s.reference_png.clone()));
        let slugs = crate::report::unique_slugs(s.error_pngs.iter().map(|(l, _)| l.as_str()));
        for ((_, png), slug) in s.error_pngs.iter().zip(slugs) {
            files.push((format!("{}/{slug}_signed_error.png", s.name), png.clone()));
        }
    }
    if let Some(seq) = &g.sequence {
        files.extend(
            seq.files
                .iter()
                .map(|(p, b)| (format!("popping-sequence/{p}"), b.clone())),
        );
    }
    Ok(files)
}

#[derive(Serialize)]
struct SceneView {
    name: String,
    description: String,
    sentence: String,
    rows: Vec<Vec<String>>,
    /// The reference and every method's signed error map, in the report's viewer.
    viewer: String,
}

/// The gallery's report sections: the scenes, then the popping sequence.
pub fn sections(g: &Gallery) -> Result<Vec<String>> {
    let scenes: Vec<SceneView> = g
        .scenes
        .iter()
        .map(|s| SceneView {
            name: s.name.clone(),
            description: s.description.clone(),
            sentence: s.sentence.clone(),
            rows: s
                .figures
                .iter()
                .map(|f| {
                    vec![
                        f.label.clone(),
                        f.shadow_maps.to_string(),
                        format!("{:.4}", f.rmse),
                        f.bright.to_string(),
                        if f.bright > 0 {
                            format!("{:.2} / {:.2}", f.bright_v, f.bright_ref)
                        } else {
                            "–".into()
                        },
                        f.dark.to_string(),
                        if f.dark > 0 {
                            format!("{:.2} / {:.2}", f.dark_v, f.dark_ref)
                        } else {
                            "–".into()
                        },
                    ]
                })
                .collect(),
            viewer: String::new(),
        })
        .collect();
    let mut scenes = scenes;
    for (view, s) in scenes.iter_mut().zip(&g.scenes) {
        view.viewer = gallery_viewer(s)
            .map_err(|e| Error::io_text("<failures viewer>".into(), e.to_string()))?;
    }
    #[derive(Serialize)]
    struct View {
        resolution: u32,
        reference: String,
        scale: f32,
        scenes: Vec<SceneView>,
    }
    let view = View {
        resolution: g.resolution,
        reference: g.reference.clone(),
        scale: ERROR_SCALE,
        scenes,
    };
    let mut env = minijinja::Environment::new();
    let err = |e: minijinja::Error| Error::io_text("<failures template>".into(), e.to_string());
    env.add_template("failures.html", include_str!("section.html"))
        .map_err(err)?;
    let mut out = vec![env
        .get_template("failures.html")
        .map_err(err)?
        .render(Value::from(Serde(&view)))
        .map_err(err)?];
    if let Some(seq) = &g.sequence {
        out.push(sequence::section::section(seq)?);
    }
    Ok(out)
}

/// A failure scene in the viewer: the shaded reference (0), then each method's signed error map
/// with its row of the table beside it.
fn gallery_viewer(s: &SceneOutcome) -> std::result::Result<String, minijinja::Error> {
    use crate::report::viewer::{render, Item, Layer, Viewer};
    let layer = |name: &str, caption: String, png: &[u8]| Layer {
        name: name.into(),
        caption,
        uri: data_uri("image/png", png),
    };
    let mut items = vec![Item {
        label: "reference".into(),
        reference: true,
        figures: String::new(),
        layers: vec![layer(
            "shaded",
            "reference (shaded)".into(),
            &s.reference_png,
        )],
    }];
    for ((label, png), f) in s.error_pngs.iter().zip(&s.figures) {
        let maps = if f.shadow_maps == 1 {
            "1 map".to_string()
        } else {
            format!("{} maps", f.shadow_maps)
        };
        let figures = format!(
            "{maps} · RMSE {:.4} · {} px too bright · {} px too dark",
            f.rmse, f.bright, f.dark
        );
        items.push(Item {
            label: label.clone(),
            reference: false,
            figures,
            layers: vec![layer("signed_error", format!("{label}: signed error"), png)],
        });
    }
    render(&Viewer {
        title: format!(
            "failure gallery, {}: the reference and every method's signed error",
            s.name
        ),
        scene: s.name.clone(),
        items,
    })
}

/// `penumbra failures --out DIR`: the files, then `report.html` with the gallery alone.
pub fn write(out: &std::path::Path, g: &Gallery) -> Result<std::path::PathBuf> {
    let mut files = g.files.clone();
    let page = crate::report::page::page("Penumbra: failure gallery", &sections(g)?)?;
    files.push(("report.html".to_string(), page.into_bytes()));
    run_files::write_files(out, &files)?;
    Ok(out.join("report.html"))
}

/// The main job: the gallery's files under `out/failures/`, its sections in `out/report.html`.
pub fn attach(out: &std::path::Path, gallery: &Gallery) -> Result<()> {
    run_files::write_files(&out.join("failures"), &gallery.files)?;
    crate::report::page::append_to_page(&out.join("report.html"), &sections(gallery)?)
}
