//! Bad `[environment]` sections and environment-method parameters stop with one clear line that
//! names the key and the value (no GPU needed).

mod common;
use penumbra::research::methods::Method;
use penumbra::research::scene::Scene;
use std::path::Path;

const HEAD: &str = "[camera]\neye = [0.0, 6.0, 8.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 45.0\n\n[render]\nwidth = 32\nheight = 32\n\n[[mesh]]\nbuiltin = \"plane\"\n\n";

fn write_panorama(dir: &Path, name: &str, w: u32, h: u32) {
    let img = image::Rgb32FImage::from_fn(w, h, |_, y| image::Rgb([1.0 + y as f32, 1.0, 1.0]));
    img.save_with_format(dir.join(name), image::ImageFormat::OpenExr)
        .unwrap();
}

fn load(dir: &Path, environment: &str) -> Result<Scene, String> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, format!("{HEAD}{environment}")).unwrap();
    Scene::load(path.to_str().unwrap(), &[]).map_err(|e| e.to_string())
}

#[test]
fn environment_sections_are_checked() {
    let dir = common::temp_dir("env_bad_input");
    write_panorama(&dir, "sky.exr", 16, 8);
    write_panorama(&dir, "square.exr", 8, 8);
    let ok = load(
        &dir,
        "[environment]\npanorama = \"sky.exr\"\nrotation_deg = 45.0\nintensity = 2.0\n",
    )
    .unwrap();
    let env = ok.environment.as_ref().expect("the environment loads");
    assert_eq!(
        (
            env.panorama.width,
            env.panorama.height,
            env.rotation_deg,
            env.intensity
        ),
        (16, 8, 45.0, 2.0)
    );
    let cases = [
        (
            "[environment]\npanorama = \"missing.exr\"\n",
            vec!["environment.panorama = `missing.exr`", "no such file"],
        ),
        (
            "[environment]\npanorama = \"square.exr\"\n",
            vec![
                "environment.panorama = `square.exr`",
                "8x8 is not an equirectangular panorama",
            ],
        ),
        (
            "[environment]\npanorama = \"scene.toml\"\n",
            vec!["environment.panorama = `scene.toml`", "not an EXR or HDR"],
        ),
        (
            "[environment]\npanorama = \"sky.exr\"\nintensity = -1.0\n",
            vec!["environment.intensity = -1", "positive"],
        ),
        (
            "[environment]\npanorama = \"sky.exr\"\nrotation_deg = inf\n",
            vec!["environment.rotation_deg = inf"],
        ),
        (
            "[environment]\npanorama = \"sky.exr\"\nexposure = 2.0\n",
            vec!["exposure", "line"],
        ),
        ("", vec!["no [light] and no [environment]"]),
    ];
    for (text, wanted) in cases {
        let e = load(&dir, text).expect_err(text);
        assert!(!e.contains('\n'), "one line: {e}");
        for w in wanted {
            assert!(e.contains(w), "`{text}`: message `{e}` lacks `{w}`");
        }
    }
}

#[test]
fn environment_method_parameters_are_checked() {
    for (spec, wanted) in [
        ("env-pixels:res=32", "env-pixels: res = `32`"),
        ("env-pixels:ssao=yes", "env-pixels: ssao = `yes`"),
        ("env-pixels:at=face", "env-pixels: parameter at = `face`: use one of pixel, vertex"),
        ("env-shadowmaps:k=3", "k = 3"),
        ("env-shadowmaps:pcf_radius=9", "pcf_radius = 9"),
        ("env-shadowmaps:filter=gauss", "env-shadowmaps: parameter filter = `gauss`: use one of box, bilinear, poisson, stratified, rotated"),
        ("env-shadowmaps:filter=poisson,taps=5", "env-shadowmaps: taps = 5 with filter = poisson: use 4, 16, 32 or 64"),
        ("env-shadowmaps:filter=box,taps=17", "env-shadowmaps: taps = 17 is outside 1..=16"),
        ("env-adaptive:max_level=7", "max_level = 7"),
        ("env-adaptive:contrast=0.5", "contrast = 0.5"),
        ("env-adaptive:count_stride=0", "count_stride = 0"),
        ("ssao:ao_samples=0", "ao_samples = 0"),
        ("ssao:k=4", "has no parameter `k`"),
    ] {
        let e = Method::parse(spec, &[]).unwrap_err().to_string();
        assert!(!e.contains('\n'), "{spec}: one line: {e}");
        assert!(e.contains(wanted), "{spec}: `{e}` lacks `{wanted}`");
    }
    assert_eq!(
        Method::parse("env-adaptive", &[]).unwrap().label(),
        "env-adaptive"
    );
    assert_eq!(
        Method::parse("env-shadowmaps:filter=box,taps=3", &[])
            .unwrap()
            .label(),
        "env-shadowmaps:k=16"
    );
    assert_eq!(
        Method::parse("env-pixels:at=pixel", &[]).unwrap().label(),
        "env-pixels:res=32x16"
    );
    assert_eq!(
        Method::parse("env-pixels:res=16x8,at=vertex", &[])
            .unwrap()
            .label(),
        "env-pixels:res=16x8,at=vertex"
    );
    assert_eq!(
        Method::parse("env-shadowmaps:filter=poisson,pcf_radius=2", &[])
            .unwrap()
            .label(),
        "env-shadowmaps:k=16,filter=poisson,pcf_radius=2"
    );
    assert_eq!(
        Method::parse("env-pixels:res=64x32,ssao=on", &[])
            .unwrap()
            .label(),
        "env-pixels:res=64x32,ssao=on,ao_samples=16,ao_radius=0.05"
    );
}
