//! `results/budget-promise/retake.sh` (docs/budget.md §5) on a small stand-in: a real frontier of
//! `analytic-square` at 128² with one budget row, then the script renders that `auto` row again
//! beside its oracle. Its one row must parse as CSV, name the frontier's oracle, render the oracle
//! again at the frontier's RMSE exactly, and give a time/oracle from the two medians. With
//! `STRETCH=s` it renders `auto:target=T/s` and reads it against the row's T: s = 2 asks 0.015,
//! `auto`'s default target, whose pictures go to `images/auto/`.

mod common;

#[test]
fn the_retake_script_renders_each_auto_row_beside_its_standing_oracle() {
    let dir = common::temp_dir("budget_retake_script");
    let bin = env!("CARGO_BIN_EXE_penumbra");
    let frontier = std::process::Command::new(bin)
        .args(["frontier", "--scene", "analytic-square", "--set", "resolution=128", "--n", "2", "--sizes", "512", "--hybrid", "none", "--repeats", "1", "--budget", "0.03", "--out"])
        .arg(dir.join("analytic-square"))
        .env("PENUMBRA_NO_PROGRESS", "1")
        .output()
        .unwrap();
    assert!(frontier.status.success(), "{}", String::from_utf8_lossy(&frontier.stderr));
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(dir.join("analytic-square/frontier.jsonl")).unwrap().lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let auto = lines.iter().find(|l| l["spec"] == "auto:target=0.03").expect("the budget row");
    let oracle = auto["oracle"].as_str().expect("a fixed setting reaches 0.03 on analytic-square");
    let oracle_rmse = lines.iter().find(|l| l["kind"] != "error budget" && format!("{} @ {}", l["spec"].as_str().unwrap(), l["map_config"].as_str().unwrap()) == oracle).unwrap()["rmse"].as_f64().unwrap();

    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../results/budget-promise/retake.sh");
    let run = |args: &[&str], stretch: &str| std::process::Command::new("bash").arg(&script).args(args).current_dir(&dir).env("PENUMBRA", bin).env("STRETCH", stretch).output().unwrap();
    let header = run(&["--header"], "1");
    // The script's one row under the header, its columns by name.
    let one_row = |stretch: &str| -> (String, Vec<String>, csv::StringRecord) {
        let rows = run(&["analytic-square"], stretch);
        assert!(rows.status.success(), "{}", String::from_utf8_lossy(&rows.stderr));
        let text = format!("{}{}", String::from_utf8_lossy(&header.stdout), String::from_utf8_lossy(&rows.stdout));
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let names: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
        let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        assert_eq!(rows.len(), 1, "{text}");
        (text, names, rows[0].clone())
    };
    let (text, names, row) = one_row("1");
    let col = |name: &str| &row[names.iter().position(|n| n == name).unwrap()];
    assert_eq!((col("scene"), col("target"), col("oracle")), ("analytic-square", "0.03", oracle), "{text}");
    // The oracle rendered again beside auto reads the frontier's RMSE, bit for bit.
    assert_eq!(col("oracle_rmse").parse::<f64>().unwrap(), oracle_rmse, "{text}");
    assert_eq!(col("frontier_oracle_rmse").parse::<f64>().unwrap(), oracle_rmse, "{text}");
    // auto's own row: its RMSE over T as measured, what it reports, and a ratio of two medians.
    let (rmse, over) = (col("rmse").parse::<f64>().unwrap(), col("measured_over_target").parse::<f64>().unwrap());
    assert!(rmse > 0.0 && (over - rmse / 0.03).abs() < 1e-9, "{text}");
    assert!(matches!(col("target_met"), "true" | "false"), "{text}");
    let (ms, oracle_ms, ratio) = (col("ms").parse::<f64>().unwrap(), col("oracle_ms").parse::<f64>().unwrap(), col("time_over_oracle").parse::<f64>().unwrap());
    assert!(ms > 0.0 && oracle_ms > 0.0 && (ratio - ms / oracle_ms).abs() < 1e-9, "{text}");

    // The stretched row: T/2 asked, measured over the row's own T, the same oracle beside it.
    let (text, names, row) = one_row("2");
    let col = |name: &str| &row[names.iter().position(|n| n == name).unwrap()];
    assert_eq!((col("target"), col("oracle")), ("0.03", oracle), "{text}");
    assert_eq!(col("oracle_rmse").parse::<f64>().unwrap(), oracle_rmse, "{text}");
    let (rmse, over, predicted) = (col("rmse").parse::<f64>().unwrap(), col("measured_over_target").parse::<f64>().unwrap(), col("predicted_rmse").parse::<f64>().unwrap());
    assert!(rmse > 0.0 && (over - rmse / 0.03).abs() < 1e-9, "{text}");
    // Met means predicted at most the asked 0.015, not the row's 0.03.
    assert_eq!(col("target_met") == "true", predicted <= 0.015, "{text}");
}
