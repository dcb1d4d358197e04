//! `penumbra report results/<name>`: a committed results folder as one self-contained page (its
//! README, then every rows file as a table), and bad folders refused in one line before anything is
//! written. No GPU: nothing is rendered.

mod common;
use common::{penumbra, temp_dir};
use std::path::Path;

/// Runs `penumbra report DIR --out OUT`; on failure the one `error:` line, with no output folder.
fn report(dir: &Path, out: &Path) -> Result<String, String> {
    let run = penumbra(&[
        "report",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    if run.status.success() {
        return Ok(std::fs::read_to_string(out.join("report.html")).unwrap());
    }
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "one line: {stderr}");
    assert!(!out.exists(), "no output on an error: {}", out.display());
    Err(lines[0].to_string())
}

#[test]
fn a_committed_folder_renders_its_readme_and_every_rows_file() {
    let out = temp_dir("results_folder_ok").join("out");
    let html = report(&common::root().join("results/same-v"), &out).unwrap();
    assert!(html.contains("<title>Results: same-v</title>"), "title");
    assert!(
        html.contains("<h1>V unchanged, old binary against new</h1>"),
        "the README, as HTML"
    );
    assert!(
        html.contains("<h2 id=\"reliability-fixes.csv\">reliability-fixes.csv (60 rows)</h2>")
            && html.contains("<h2 id=\"two-crates.csv\">two-crates.csv (60 rows)</h2>"),
        "both tables"
    );
    assert!(
        html.contains("<tr><th>verdict</th><th>scene</th><th>method</th></tr>"),
        "header row"
    );
    assert!(
        html.contains("<tr><td>same</td><td>default</td><td>hard</td></tr>"),
        "a row as written"
    );
    assert!(
        !html.contains("src=\"http") && !html.contains("<script"),
        "self-contained"
    );

    // JSON Lines: every key a column.
    let out = temp_dir("results_folder_jsonl").join("out");
    let html = report(&common::root().join("results/slat-roof"), &out).unwrap();
    assert!(
        html.contains(">compare-512.jsonl (") && html.contains(">frontier-128.jsonl ("),
        "{}",
        &html[..html.len().min(2000)]
    );
}

#[test]
fn every_committed_results_folder_renders() {
    let out = temp_dir("results_folder_all");
    let mut folders: Vec<_> = std::fs::read_dir(common::root().join("results"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    folders.sort();
    assert!(folders.len() >= 60, "{} results folders", folders.len());
    for dir in &folders {
        let name = dir.file_name().unwrap().to_str().unwrap();
        let html = report(dir, &out.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            html.contains(&format!("<title>Results: {name}</title>")) && html.contains("<table>"),
            "{name}"
        );
    }
}

#[test]
fn cells_are_read_by_the_csv_rules_and_shown_as_text() {
    let dir = temp_dir("results_folder_quoted");
    std::fs::write(
        dir.join("README.md"),
        "# Quoted\n\nCommand: `penumbra x`\n\nRows: [the rows](rows.csv).\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("rows.csv"),
        "name,value\n\"a, <b>\",\"1.5\"\n\"say \"\"hi\"\"\",2\n",
    )
    .unwrap();
    let html = report(&dir, &dir.join("out")).unwrap();
    assert!(
        html.contains("<p>Command: <code>penumbra x</code></p>"),
        "{html}"
    );
    // A link to a rows file goes to its table on the page.
    assert!(
        html.contains("<a href=\"#rows.csv\">the rows</a>")
            && html.contains("<h2 id=\"rows.csv\">rows.csv (2 rows)</h2>"),
        "{html}"
    );
    assert!(
        html.contains("<tr><td>a, &lt;b&gt;</td><td>1.5</td></tr>"),
        "{html}"
    );
    assert!(
        html.contains("<tr><td>say \"hi\"</td><td>2</td></tr>"),
        "{html}"
    );
}

#[test]
fn bad_folders_are_one_line_naming_the_file() {
    let base = temp_dir("results_folder_bad");
    let out = base.join("out");

    let missing = base.join("no-such");
    let e = report(&missing, &out).unwrap_err();
    assert_eq!(
        e,
        format!(
            "error: report: {}: no such results folder",
            missing.display()
        )
    );

    let bare = base.join("bare");
    std::fs::create_dir_all(&bare).unwrap();
    std::fs::write(bare.join("rows.csv"), "a\n1\n").unwrap();
    let e = report(&bare, &out).unwrap_err();
    assert!(
        e.starts_with(&format!(
            "error: report: {}: a results folder needs its README.md",
            bare.join("README.md").display()
        )),
        "{e}"
    );

    let empty = base.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    std::fs::write(empty.join("README.md"), "# x\n").unwrap();
    let e = report(&empty, &out).unwrap_err();
    assert_eq!(
        e,
        format!(
            "error: report: {}: no rows: the folder holds no .csv or .jsonl file",
            empty.display()
        )
    );

    let ragged = base.join("ragged");
    std::fs::create_dir_all(&ragged).unwrap();
    std::fs::write(ragged.join("README.md"), "# x\n").unwrap();
    std::fs::write(
        ragged.join("rows.csv"),
        "scene,method,rmse\ndefault,hard,0.1\ndefault,pcf\n",
    )
    .unwrap();
    let e = report(&ragged, &out).unwrap_err();
    assert_eq!(
        e,
        format!(
            "error: report: {}: line 3: 2 fields where the header has 3",
            ragged.join("rows.csv").display()
        )
    );

    let bad_json = base.join("bad-json");
    std::fs::create_dir_all(&bad_json).unwrap();
    std::fs::write(bad_json.join("README.md"), "# x\n").unwrap();
    std::fs::write(bad_json.join("rows.jsonl"), "{\"a\":1}\n[2]\n").unwrap();
    let e = report(&bad_json, &out).unwrap_err();
    assert_eq!(
        e,
        format!(
            "error: report: {}: line 2: not a JSON object",
            bad_json.join("rows.jsonl").display()
        )
    );

    // A folder goes alone, and --baseline compares rows files only.
    let run = penumbra(&[
        "report",
        "results/same-v",
        "x.jsonl",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        String::from_utf8_lossy(&run.stderr).trim(),
        "error: report results/same-v: a results folder is reported alone, not with other files"
    );
    let run = penumbra(&[
        "report",
        "results/same-v",
        "--baseline",
        "old.jsonl",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(String::from_utf8_lossy(&run.stderr).trim(), "error: --baseline old.jsonl: compares results.jsonl rows, not a results folder (results/same-v)");
    assert!(!out.exists());
}
