//! The scripts behind results/bad-input-census/ on a few of their cases: `scripts/bad-input-census.sh`
//! judges each case good, poor or bad and tallies them; `measure.sh lights` measures the far lights
//! and the wide disks with two builds (here the same binary twice), `measure.sh regions` renders
//! regions across its range. Their rows must parse, and the
//! cases chosen here (one of each kind of check) must come out good on this build.

mod common;
use std::process::Command;

fn rows(path: &std::path::Path) -> Vec<csv::StringRecord> {
    let text = std::fs::read_to_string(path).unwrap();
    csv::Reader::from_reader(text.as_bytes())
        .records()
        .map(Result::unwrap)
        .collect()
}

#[test]
fn the_census_judges_each_case_and_tallies_them() {
    let dir = common::temp_dir("census_script");
    let csv_path = dir.join("cases.csv");
    let run = Command::new("bash")
        .arg(common::root().join("scripts/bad-input-census.sh"))
        .arg(&csv_path)
        .env("PENUMBRA", env!("CARGO_BIN_EXE_penumbra"))
        .env(
            "CENSUS_ONLY",
            "^(scene-dev-zero|calibrate-zero|disk-200|point-h400|regions-hybrid)$",
        )
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        stdout.trim_end().ends_with(&format!(
            "good 5, poor 0, bad 0 (of 5; rows: {})",
            csv_path.display()
        )),
        "{stdout}"
    );
    let rows = rows(&csv_path);
    let ids: Vec<&str> = rows.iter().map(|r| &r[0]).collect();
    assert_eq!(
        ids,
        [
            "point-h400",
            "scene-dev-zero",
            "disk-200",
            "calibrate-zero",
            "regions-hybrid"
        ],
        "{stdout}"
    );
    for r in &rows {
        assert_eq!(&r[7], "good", "{r:?}");
    }
    // A refusal's row carries its one line; the point light's exit 0.
    assert!(
        rows[1][8].contains("is a character device, not a regular file or a pipe")
            && &rows[1][4] == "1",
        "{:?}",
        rows[1]
    );
    assert_eq!(&rows[0][4], "0");
}

#[test]
fn the_lights_driver_writes_a_row_per_light_and_build() {
    let dir = common::temp_dir("census_lights");
    let bin = env!("CARGO_BIN_EXE_penumbra");
    let run = Command::new("bash")
        .arg(common::root().join("results/bad-input-census/measure.sh"))
        .args(["lights", bin, bin, dir.to_str().unwrap()])
        .env("HEIGHTS", "400")
        .env("RADII", "30 200")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let heights = rows(&dir.join("heights.csv"));
    assert_eq!(heights.len(), 4, "point and spot, two builds");
    for r in &heights {
        let (hard, regular): (f64, f64) = (r[3].parse().unwrap(), r[4].parse().unwrap());
        assert!(hard < 0.1 && regular < 0.1, "{r:?}");
    }
    let disks = rows(&dir.join("disks.csv"));
    assert_eq!(disks.len(), 4);
    // Radius 30 (tangent 5.0 at the middle) runs; 200 (tangent 31.2) is refused by this build.
    assert!(
        disks[0][5].parse::<f64>().unwrap() < 0.15 && &disks[0][2] == "5.00",
        "{:?}",
        disks[0]
    );
    assert!(
        disks[3][4].is_empty()
            && disks[3][6]
                .contains("light.radius = 200: seen from the middle of the meshes' bounds")
            && &disks[3][2] == "31.15",
        "{:?}",
        disks[3]
    );
}

#[test]
fn the_regions_driver_writes_a_row_per_setting() {
    let dir = common::temp_dir("census_regions");
    let csv_path = dir.join("regions.csv");
    let run = Command::new("bash")
        .arg(common::root().join("results/bad-input-census/measure.sh"))
        .args([
            "regions",
            env!("CARGO_BIN_EXE_penumbra"),
            csv_path.to_str().unwrap(),
        ])
        .env("FORCES", "23")
        .env("MAX_NS", "")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rows = rows(&csv_path);
    assert_eq!(rows.len(), 1);
    // 529 maps (past one batch of 512) and the decision's centre map; no error.
    assert_eq!(
        (
            &rows[0][0],
            &rows[0][1],
            &rows[0][2],
            &rows[0][3],
            &rows[0][6]
        ),
        ("regions:force=23,force_size=16", "0", "530", "529", ""),
        "{:?}",
        rows[0]
    );
}
