//! `scripts/raster-queue-compare.sh` (results/raster-compute-queue/) on a small stand-in case:
//! the same binary as both builds, one round, the compute and the fixed-function raster on
//! `analytic-square` at 512² maps. Its rows must parse as CSV with the method's commas quoted,
//! and carry each frame's map count and a raster stage time.

mod common;

#[test]
fn the_raster_queue_script_writes_one_row_per_build_and_case() {
    let dir = common::temp_dir("raster_queue_script");
    let out = dir.join("out");
    let bin = env!("CARGO_BIN_EXE_penumbra");
    let script =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/raster-queue-compare.sh");
    let run = std::process::Command::new("bash")
        .arg(&script)
        .args([bin, bin, out.to_str().unwrap()])
        .env("ROUNDS", "1")
        .env("CASES", "analytic-square regular:n=2,layout=centred compute 512\nanalytic-square regular:n=2,layout=centred hardware 512")
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(out.join("rows.csv")).unwrap();
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    assert_eq!(
        rows.headers().unwrap().iter().collect::<Vec<_>>(),
        [
            "round",
            "build",
            "scene",
            "method",
            "raster",
            "map_size",
            "maps",
            "total_ms",
            "raster_ms"
        ]
    );
    let rows: Vec<csv::StringRecord> = rows.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 4, "{text}");
    for (row, (build, raster)) in rows.iter().zip([
        ("old", "compute"),
        ("old", "hardware"),
        ("new", "compute"),
        ("new", "hardware"),
    ]) {
        assert_eq!(
            (&row[1], &row[2], &row[3], &row[4], &row[5], &row[6]),
            (
                build,
                "analytic-square",
                "regular:n=2,layout=centred",
                raster,
                "512",
                "4"
            ),
            "{text}"
        );
        let (total, raster_ms): (f64, f64) = (row[7].parse().unwrap(), row[8].parse().unwrap());
        assert!(raster_ms > 0.0 && total > 0.0, "{text}");
    }
}
