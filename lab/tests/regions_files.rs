//! The per-region method's pictures: `render` writes them with the run files, `compare` shows them
//! in its report; a bad parameter is one line on stderr and nothing written.

mod common;
use common::{ok, penumbra, temp_dir};

#[test]
fn render_writes_and_compare_shows_the_region_pictures() {
    let dir = temp_dir("regions_files");
    let out = dir.join("render");
    ok(
        penumbra(&[
            "render",
            "--scene",
            "canopy-market",
            "--set",
            "resolution=64",
            // The plan alone: its groups' maps are counted below (the certified classes add the
            // filter's map and the step-ups', tests/regions_certified.rs); compare shows the
            // default, certified, below.
            "--method",
            "regions:certify=off",
            "--out",
            out.to_str().unwrap(),
        ]),
        "render",
    );
    for name in ["region_samples.png", "region_texels.png"] {
        let img = image::open(out.join(name))
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .to_rgb8();
        assert_eq!(img.dimensions(), (64, 64), "{name}");
    }
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let classes = run["method_record"]["classes"].as_array().unwrap();
    assert!(
        classes.len() >= 2,
        "canopy-market should split into two classes or more: {classes:?}"
    );
    // The classes of one group share its maps: count each group once.
    let mut groups: Vec<(u64, u64)> = classes
        .iter()
        .map(|c| (c["group"].as_u64().unwrap(), c["maps"].as_u64().unwrap()))
        .collect();
    groups.dedup();
    let maps: u64 = groups.iter().map(|g| g.1).sum();
    assert_eq!(
        run["shadow_maps"].as_u64(),
        Some(maps + 1),
        "the groups' maps and the centre map: {classes:?}"
    );
    assert!(
        classes
            .iter()
            .all(|c| c["n"].as_u64() >= c["decided_n"].as_u64()),
        "a class shaded with fewer samples than decided: {classes:?}"
    );
    assert!(
        run["method_record"]["texels_written"].as_f64().unwrap() > 0.0
            && run["method_record"]["triangle_map_pairs"].as_f64().unwrap() > 0.0
    );
    let cmp = dir.join("compare");
    ok(
        penumbra(&[
            "compare",
            "--scene",
            "canopy-market",
            "--set",
            "resolution=64",
            "--repeats",
            "1",
            "--methods",
            "regions,regular:n=3,layout=centred",
            "--out",
            cmp.to_str().unwrap(),
        ]),
        "compare",
    );
    let html = std::fs::read_to_string(cmp.join("report.html")).unwrap();
    assert!(
        html.contains("<section id=\"regions\">"),
        "no regions section in the report"
    );
    // One regions row: one viewer item with its two pictures as layers.
    assert_eq!(
        html.matches("<figure data-layer=\"region_samples\"><img src=\"data:image/png;base64,")
            .count(),
        1
    );
    assert_eq!(
        html.matches("<figure data-layer=\"region_texels\"><img src=\"data:image/png;base64,")
            .count(),
        1
    );
}

#[test]
fn a_bad_parameter_is_one_line_and_no_output() {
    let dir = temp_dir("regions_bad");
    let out = dir.join("out");
    let r = penumbra(&[
        "render",
        "--scene",
        "canopy-market",
        "--method",
        "regions:target=0.9",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(1));
    let err = String::from_utf8_lossy(&r.stderr);
    // As every method's parameters: the method, the key and the value.
    assert_eq!(
        err.trim(),
        "error: regions: target = 0.9 is outside 0.0005..=0.5",
        "{err}"
    );
    assert!(!out.exists(), "a refused render wrote {}", out.display());
}
