//! `penumbra oracle` on a tiny scene whose answer can be checked by hand: at a loose target every
//! candidate meets it, so the oracle pays one candidate's maps and its tests on the tiles that
//! are not uniformly lit or dark, nothing else; at a tight one its frame meets the target, its
//! bound is at most its frame, and both beat the cheapest single setting. Then the output set and
//! bad input.

#[macro_use]
mod common;
use common::{ok, penumbra, temp_dir};
use serde_json::Value;
use std::path::Path;

/// A box over a ground that fills the 32² screen (16 tiles of 8×8) under a 2×2 light: some tiles
/// are lit ground only, some hold the box's soft shadow.
fn scene(dir: &Path) -> String {
    let text = concat!(tiny_scene_head!(), "\n[[mesh]]\nbuiltin = \"plane\"\nscale = 100.0\n\n[[mesh]]\nbuiltin = \"box\"\ntranslate = [-1.0, 1.5, 0.0]\n");
    let path = dir.join("tiny.toml");
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

fn f(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"))
}

#[test]
fn the_oracle_on_a_hand_checked_scene() {
    let dir = temp_dir("oracle_tiny");
    let scene = scene(&dir);
    let out = dir.join("out");
    let args = [
        "oracle",
        "--scene",
        &scene,
        "--resolutions",
        "32",
        "--targets",
        "0.5,0.02",
        "--n",
        "1,4",
        "--sizes",
        "64,256",
        "--singles",
        "pcss",
        "--hybrid",
        "none",
        "--adaptive",
        "none",
        "--repeats",
        "1",
        "--samples",
        "16",
        "--out",
        out.to_str().unwrap(),
    ];
    let stdout = String::from_utf8(ok(penumbra(&args), "oracle").stdout).unwrap();
    println!("{stdout}");
    let o: Value =
        serde_json::from_slice(&std::fs::read(out.join("oracle.json")).unwrap()).unwrap();
    let cands = o["candidates"].as_array().unwrap();
    let names: Vec<&str> = cands.iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        ["n=1@64", "n=4@64", "pcss@64", "n=1@256", "n=4@256", "pcss@256"]
    );
    let price = |c: &Value, k: &str| f(&c["price"], k);
    let mut fixed: Vec<f64> = cands.iter().map(|c| price(c, "fixed_ms")).collect();
    fixed.sort_by(f64::total_cmp);
    let fixed = (fixed[2] + fixed[3]) / 2.0;
    let rows = o["rows"].as_array().unwrap();
    // Two menus (grids, family) × two targets.
    assert_eq!(rows.len(), 4);
    for r in rows {
        assert_eq!(
            (
                r["tiles"].as_u64(),
                r["tile_cols"].as_u64(),
                r["tile_rows"].as_u64()
            ),
            (Some(16), Some(4), Some(4)),
            "every pixel is ground: {r}"
        );
        let free = r["free_tiles"].as_u64().unwrap() as usize;
        assert!(
            (2..14).contains(&free),
            "lit ground and the box's shadow both: {r}"
        );
        let choice: Vec<i64> = r["choice"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_i64().unwrap())
            .collect();
        assert_eq!(choice.iter().filter(|&&c| c == -1).count(), free);
        let split = r["split"].as_array().unwrap();
        let counted: u64 = split.iter().map(|c| c["tiles"].as_u64().unwrap()).sum();
        assert_eq!(counted as usize + free, 16, "{r}");
        for (i, c) in split.iter().enumerate() {
            assert_eq!(
                choice.iter().filter(|&&k| k == i as i64).count() as u64,
                c["tiles"].as_u64().unwrap()
            );
        }
        let menu = r["menu"].as_str().unwrap();
        let t = f(r, "target");
        let inside: Vec<&Value> = cands
            .iter()
            .filter(|c| menu == "family" || c["kind"] == "grid")
            .collect();
        // The single setting: the cheapest of the menu by its model time that meets T.
        let model = |c: &Value| fixed + price(c, "maps_ms") + price(c, "tests_ms");
        let single = inside
            .iter()
            .filter(|c| f(c, "rmse") <= t)
            .min_by(|a, b| model(a).total_cmp(&model(b)))
            .unwrap();
        assert_eq!(r["single"], single["name"], "{r}");
        assert!((f(r, "single_model_ms") - model(single)).abs() < 1e-9);
        let (frame, bound) = (f(r, "oracle_ms"), f(r, "bound_ms"));
        assert!(
            f(r, "oracle_rmse") <= t + 1e-12 && bound <= frame + 1e-9,
            "{r}"
        );
        assert!((f(r, "gain_bound") - model(single) / bound).abs() < 1e-9);
        // The single setting on every tile that pays is one of the oracle's choices.
        let paying = (16 - free) as f64 * 64.0 / 1024.0;
        assert!(
            frame <= fixed + price(single, "maps_ms") + price(single, "tests_ms") * paying + 1e-9,
            "{r}"
        );
        if t == 0.5 {
            // By hand: every candidate meets 0.5, so one candidate serves every paying tile (a
            // second would only add maps), the one with the least maps plus tests on them.
            let want = inside
                .iter()
                .map(|c| fixed + price(c, "maps_ms") + price(c, "tests_ms") * paying)
                .fold(f64::INFINITY, f64::min);
            assert!(inside.iter().all(|c| f(c, "rmse") <= 0.5));
            assert_eq!(split.len(), 1, "{r}");
            assert!(
                (frame - want).abs() < 1e-9 && (bound - want).abs() <= 1e-6 * want,
                "frame {frame}, bound {bound}, by hand {want}"
            );
        }
    }
    // The grids alone never do better than the family, which holds them.
    for t in [0.5, 0.02] {
        let at = |menu: &str| {
            rows.iter()
                .find(|r| r["menu"] == menu && f(r, "target") == t)
                .unwrap()
        };
        assert!(f(at("family"), "oracle_ms") <= f(at("grids"), "oracle_ms") + 1e-9);
    }
    // The output set: rows with gain_bound as a column, candidates with their prices, pictures.
    let csv = std::fs::read_to_string(out.join("oracle.csv")).unwrap();
    let head: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert!(
        head.contains(&"gain_bound") && head.contains(&"bound_ms") && head.contains(&"split"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), 5);
    let cand_csv = std::fs::read_to_string(out.join("candidates.csv")).unwrap();
    assert!(
        cand_csv.starts_with("scene,resolution,name,spec,map_config,kind,maps,rmse,frame_ms,")
            && cand_csv.lines().count() == 7,
        "{cand_csv}"
    );
    for t in ["0.5", "0.02"] {
        let base = format!("tiles/tiny-32-family-T{t}");
        assert!(
            std::fs::read(out.join(format!("{base}.png"))).is_ok_and(|b| b.starts_with(b"\x89PNG")),
            "{t}"
        );
        let svg = std::fs::read_to_string(out.join(format!("{base}.svg"))).unwrap();
        assert_eq!(
            svg.matches("<rect x=").count() - svg.matches("width=\"12\"").count(),
            16 + 1,
            "16 tiles and a frame: {svg}"
        );
    }
    assert!(std::fs::read_to_string(out.join("charts/gain_bound.svg"))
        .unwrap()
        .contains("gain_bound"));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for bad in ["<script", "<link", "src=\"http", "href=\"http"] {
        assert!(!html.contains(bad), "report holds {bad}");
    }
    assert!(
        stdout.contains("/tiny.toml | 32² | 0.02 | family |"),
        "{stdout}"
    );
}

#[test]
fn bad_input_is_one_line_and_writes_nothing() {
    let dir = temp_dir("oracle_bad_input");
    let scene = scene(&dir);
    let file = dir.join("a_file");
    std::fs::write(&file, "x").unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec!["--targets", "0.9"],
            "--targets `0.9`: a target RMSE of V in 0.0005..=0.5".into(),
        ),
        (
            vec!["--targets", "0.03,0.030"],
            "--targets `0.030`: listed twice (as `0.03`)".into(),
        ),
        (
            vec!["--resolutions", "4"],
            "--resolutions `4`: a screen side in 8..=4096 pixels".into(),
        ),
        (vec!["--n", "0"], "--n `0`: n must be in 1..=128".into()),
        (
            vec!["--sizes", "big"],
            "--sizes: map configuration `big`: not a whole number".into(),
        ),
        (
            vec!["--singles", "regular"],
            "--singles `regular`: not a method of one map".into(),
        ),
        (
            vec!["--adaptive", "fast"],
            "--adaptive `fast`: not a preset (seed, balanced, seed-local, balanced-local; or none)"
                .into(),
        ),
        (
            vec!["--hybrid", "2048/3"],
            "--hybrid: map configuration `2048/3`: levels must be 1 or 2".into(),
        ),
        (
            vec!["--set", "shadow_map_size=512"],
            "--set shadow_map_size=512: the oracle sets map sizes, map kinds and the screen itself"
                .into(),
        ),
        (
            vec!["--set", "resolution=64"],
            "--set resolution=64: the oracle sets map sizes".into(),
        ),
        (
            vec!["--repeats", "0"],
            "--repeats must be in 1..=1000, got 0".into(),
        ),
        // Per 64² side 8 grids, pcss, pcf, msm and 4 presets; on hybrid maps 8 grids, pcss and pcf.
        (
            vec!["--max-configs", "3"],
            "oracle: 25 configurations, more than --max-configs 3; pass --max-configs 25".into(),
        ),
        (
            vec!["--out", file.to_str().unwrap()],
            format!("--out {}: is a file, not a folder", file.display()),
        ),
    ];
    for (extra, want) in cases {
        let mut args = vec![
            "oracle",
            "--scene",
            &scene,
            "--resolutions",
            "32",
            "--sizes",
            "64",
        ];
        if !extra.contains(&"--out") {
            args.extend(["--out", o]);
        }
        args.extend(&extra);
        let r = penumbra(&args);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{extra:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{extra:?}: {stderr}");
        assert!(
            stderr.starts_with(&format!("error: {want}")),
            "{extra:?}: {stderr}"
        );
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
}
