//! `penumbra report results/<name>`: a committed results folder (its README.md with the command,
//! build and device, and the rows as CSV or JSON Lines) as one self-contained page: the README,
//! then each rows file as a table, figures exactly as stored.

use std::path::{Path, PathBuf};

use super::md_page::{body, document, escape};
use super::ReportError;
use crate::Result;

/// One rows file: its name, the column names and the rows, every cell as written.
pub struct Rows {
    pub name: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
    /// Each row's line in its file (for messages).
    pub lines: Vec<u64>,
}

/// The page of the results folder `dir`. Every file is read and checked before anything is made:
/// a missing folder or README, a folder with no rows file, a ragged CSV row or a JSON Lines line
/// that is not an object is an error naming the file (and line). Rows files in sub-folders (to
/// [`DEPTH`] levels) get their tables too, named by their path in the folder; an error figure
/// outside [0, 1] (an RMSE of -1) is kept as written and said, on stderr and on the page.
pub fn page(dir: &Path) -> Result<String> {
    let err = |path: &Path, message: String| ReportError::Results {
        path: path.to_path_buf(),
        message,
    };
    if !dir.is_dir() {
        let what = if dir.exists() {
            "not a folder"
        } else {
            "no such results folder"
        };
        return Err(err(dir, what.into()).into());
    }
    let readme_path = dir.join("README.md");
    let readme = crate::scene::input_file::read_text(
        &readme_path,
        crate::scene::input_file::TEXT_CAP,
        "the 256 MiB cap on results files",
    )
    .map_err(|e| {
        err(
            &readme_path,
            format!("a results folder needs its README.md (command, build, device): {e}"),
        )
    })?;
    let mut files = Vec::new();
    rows_files(dir, DEPTH, &mut files)?;
    files.sort();
    if files.is_empty() {
        return Err(err(
            dir,
            "no rows: the folder holds no .csv or .jsonl file".into(),
        )
        .into());
    }
    let tables = files
        .iter()
        .map(|p| read_rows_named(p, &relative(dir, p)))
        .collect::<Result<Vec<_>>>()?;
    // The README's links to its rows files point at their tables on this page.
    let readme = tables.iter().fold(readme, |md, t| {
        md.replace(&format!("]({})", t.name), &format!("](#{})", t.name))
    });
    let mut html = body(&readme);
    for t in &tables {
        let notes = suspect_cells(t);
        for n in &notes {
            eprintln!("warning: {}: {n}", dir.join(&t.name).display());
        }
        html += &table_html(t, &notes);
    }
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| dir.display().to_string());
    Ok(document(&format!("Results: {name}"), &html))
}

/// Sub-folder levels searched for rows files below the folder itself.
const DEPTH: usize = 3;

/// The `.csv` and `.jsonl` files in `dir` and its sub-folders to `depth` levels (hidden ones and
/// links to folders left out: a folder may hold a run's staging folder or a link out of it).
fn rows_files(dir: &Path, depth: usize, out: &mut Vec<PathBuf>) -> Result<()> {
    let listing = std::fs::read_dir(dir).map_err(|e| ReportError::Results {
        path: dir.to_path_buf(),
        message: format!("cannot list: {e}"),
    })?;
    for entry in listing.flatten() {
        let path = entry.path();
        let hidden = entry.file_name().to_string_lossy().starts_with('.');
        let Ok(t) = entry.file_type() else { continue };
        if t.is_dir() && !hidden && depth > 0 {
            rows_files(&path, depth - 1, out)?;
        } else if !t.is_dir()
            && matches!(
                path.extension().and_then(|x| x.to_str()),
                Some("csv" | "jsonl")
            )
        {
            out.push(path);
        }
    }
    Ok(())
}

fn relative(root: &Path, p: &Path) -> String {
    p.strip_prefix(root)
        .unwrap_or(p)
        .to_string_lossy()
        .into_owned()
}

/// Columns that hold an error of V (an RMSE, a mean or largest absolute error), which lies in [0, 1].
fn error_column(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    n == "rmse" || n.ends_with("_rmse") || n.starts_with("rmse_") || n == "mae" || n == "max_abs"
}

/// `line 3: rmse = -1: an error of V lies in [0, 1]` for each such cell outside it (kept as written).
fn suspect_cells(t: &Rows) -> Vec<String> {
    let mut notes = Vec::new();
    for (c, name) in t.header.iter().enumerate().filter(|(_, n)| error_column(n)) {
        for (r, row) in t.rows.iter().enumerate() {
            let Some(Ok(v)) = row
                .get(c)
                .filter(|x| !x.trim().is_empty())
                .map(|x| x.trim().parse::<f64>())
            else {
                continue;
            };
            if !(0.0..=1.0).contains(&v) {
                notes.push(format!(
                    "line {}: {name} = {}: an error of V lies in [0, 1]",
                    t.lines[r], row[c]
                ));
            }
        }
    }
    notes
}

/// Writes `report.html` of the results folder `dir` into `out_dir` (created if missing), after
/// every file is read; returns its path. Only report.html is replaced: the folder may hold a run.
pub fn write(dir: &Path, out_dir: &Path) -> Result<PathBuf> {
    let html = page(dir)?;
    std::fs::create_dir_all(out_dir).map_err(|source| ReportError::Io {
        path: out_dir.to_path_buf(),
        source,
    })?;
    let path = out_dir.join("report.html");
    super::files::write_atomic(&path, html.as_bytes())?;
    Ok(path)
}

/// A `.csv` (header line, then rows of the header's width) or a `.jsonl` (one JSON object a
/// line; the columns are every key in first-seen order, a missing key an empty cell).
pub fn read_rows(path: &Path) -> Result<Rows> {
    read_rows_named(
        path,
        &path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
    )
}

fn read_rows_named(path: &Path, name: &str) -> Result<Rows> {
    let err = |message: String| ReportError::Results {
        path: path.to_path_buf(),
        message,
    };
    let text = crate::scene::input_file::read_text(
        path,
        crate::scene::input_file::TEXT_CAP,
        "the 256 MiB cap on results files",
    )
    .map_err(|e| err(format!("cannot read: {e}")))?;
    let name = name.to_string();
    if path.extension().and_then(|x| x.to_str()) == Some("jsonl") {
        return jsonl_rows(name, &text).map_err(|m| err(m).into());
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| err(csv_message(&e)))?
        .iter()
        .map(str::to_string)
        .collect();
    if header.is_empty() {
        return Err(err("empty: no header line".into()).into());
    }
    let (mut rows, mut lines) = (Vec::new(), Vec::new());
    for record in reader.records() {
        let record = record.map_err(|e| err(csv_message(&e)))?;
        lines.push(record.position().map_or(0, |p| p.line()));
        rows.push(record.iter().map(str::to_string).collect());
    }
    Ok(Rows {
        name,
        header,
        rows,
        lines,
    })
}

/// `line 3: 4 fields where the header has 5`: the csv crate's error in the house's words.
fn csv_message(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            pos,
            expected_len,
            len,
        } => {
            let line = pos
                .as_ref()
                .map_or(String::new(), |p| format!("line {}: ", p.line()));
            format!("{line}{len} fields where the header has {expected_len}")
        }
        _ => e.to_string(),
    }
}

fn jsonl_rows(name: String, text: &str) -> std::result::Result<Rows, String> {
    let mut header: Vec<String> = Vec::new();
    let (mut objects, mut lines) = (Vec::new(), Vec::new());
    for (n, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
    {
        lines.push(n as u64 + 1);
        let value: serde_json::Value =
            serde_json::from_str(line).map_err(|e| format!("line {}: not JSON: {e}", n + 1))?;
        let serde_json::Value::Object(map) = value else {
            return Err(format!("line {}: not a JSON object", n + 1));
        };
        for k in map.keys() {
            if !header.contains(k) {
                header.push(k.clone());
            }
        }
        objects.push(map);
    }
    if objects.is_empty() {
        return Err("no rows".into());
    }
    let cell = |v: Option<&serde_json::Value>| match v {
        None | Some(serde_json::Value::Null) => String::new(),
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(other) => other.to_string(),
    };
    let rows = objects
        .iter()
        .map(|m| header.iter().map(|k| cell(m.get(k))).collect())
        .collect();
    Ok(Rows {
        name,
        header,
        rows,
        lines,
    })
}

fn table_html(t: &Rows, notes: &[String]) -> String {
    let row = |tag: &str, cells: &[String]| {
        format!(
            "<tr>{}</tr>\n",
            cells
                .iter()
                .map(|c| format!("<{tag}>{}</{tag}>", escape(c)))
                .collect::<String>()
        )
    };
    let mut h = format!(
        "<h2 id=\"{}\">{} ({} rows)</h2>\n<table>\n<thead>\n{}</thead>\n<tbody>\n",
        escape(&t.name).replace('"', "&quot;"),
        escape(&t.name),
        t.rows.len(),
        row("th", &t.header)
    );
    for r in &t.rows {
        h += &row("td", r);
    }
    h += "</tbody>\n</table>\n";
    for n in notes {
        h += &format!("<p class=\"note\">{}: {}</p>\n", escape(&t.name), escape(n));
    }
    h
}

#[cfg(test)]
mod tests {
    #[test]
    fn jsonl_columns_are_every_key_in_first_seen_order() {
        let t = super::jsonl_rows(
            "a.jsonl".into(),
            "{\"x\":1,\"y\":\"s\"}\n\n{\"z\":[1,2],\"x\":null}\n",
        )
        .unwrap();
        assert_eq!(t.header, ["x", "y", "z"]);
        assert_eq!(t.rows, [vec!["1", "s", ""], vec!["", "", "[1,2]"]]);
        assert_eq!(
            super::jsonl_rows("a.jsonl".into(), "{}\n[1]\n")
                .err()
                .unwrap(),
            "line 2: not a JSON object"
        );
    }
}
