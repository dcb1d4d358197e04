//! examples/embed.rs (the engine's example) against the `penumbra` binary: a program with its own
//! wgpu device gets the same V as `penumbra render`, value for value.

mod common;

// The example's functions, compiled into this test (its `main` is unused here).
#[allow(dead_code)]
#[path = "../../examples/embed.rs"]
mod embed;

const SIZE: u32 = 64;

/// Channel 0 of an EXR as `penumbra render` writes V.
fn read_exr(path: &std::path::Path) -> (u32, u32, Vec<f32>) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb32f();
    (
        img.width(),
        img.height(),
        img.pixels().map(|p| p[0]).collect(),
    )
}

#[test]
fn embedded_v_equals_penumbra_render() {
    let dir = common::temp_dir("embed_example");
    for (k, method) in [
        "hard",
        "pcss",
        "regular:n=5,layout=centred",
        "adaptive:preset=balanced",
    ]
    .into_iter()
    .enumerate()
    {
        let (v, adapter) = embed::render(method, SIZE).unwrap_or_else(|e| panic!("{method}: {e}"));
        assert_eq!(
            (v.width, v.height, v.values.len()),
            (SIZE, SIZE, (SIZE * SIZE) as usize)
        );
        let ours = dir.join(format!("embed-{k}"));
        embed::write(&v, &ours).unwrap();
        let theirs = dir.join(format!("render-{k}"));
        let resolution = format!("resolution={SIZE}");
        let args = [
            "render",
            "--scene",
            "analytic-square",
            "--method",
            method,
            "--set",
            &resolution,
            "--adapter",
            &adapter,
            "--out",
            theirs.to_str().unwrap(),
        ];
        common::ok(common::penumbra(&args), method);
        let (w, h, rendered) = read_exr(&theirs.join("visibility.exr"));
        assert_eq!((w, h), (SIZE, SIZE));
        let (_, _, written) = read_exr(&ours.join("visibility.exr"));
        assert_eq!(written, v.values, "{method}: the example's EXR holds its V");
        let differ = rendered
            .iter()
            .zip(&v.values)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        let penumbra = v.values.iter().filter(|&&x| x > 0.0 && x < 1.0).count();
        assert_eq!(
            differ,
            0,
            "{method}: {differ} of {} pixels differ from penumbra render's V",
            v.values.len()
        );
        assert!(
            penumbra > 20 || method == "hard",
            "{method}: only {penumbra} penumbra pixels, the comparison would prove little"
        );
        println!(
            "{method}: identical to penumbra render ({penumbra} penumbra pixels, {} maps)",
            v.shadow_maps
        );
    }
}
