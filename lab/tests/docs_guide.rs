//! The docs are a guide and the measurements are data (issue 44): every `results/…` path that
//! docs/ or the README cites exists, every results folder holds a README and rows, no heading in
//! docs/ carries a date or a clock time (a diary), a paragraph that quotes a measured time or
//! speed-up cites a results folder, and docs/README.md links every page. Reads files only: no GPU.

use std::path::{Path, PathBuf};

/// The repository root, where docs/, results/ and the README live.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("lab/ has a parent")
        .to_path_buf()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// docs/*.md and the README, as (path relative to the root, text).
fn pages() -> Vec<(String, String)> {
    let root = root();
    let mut names: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().and_then(|x| x.to_str()) == Some("md"))
        .collect();
    names.sort();
    names.push(root.join("README.md"));
    names
        .iter()
        .map(|p| {
            (
                p.strip_prefix(&root).unwrap().display().to_string(),
                read(p),
            )
        })
        .collect()
}

/// The `results/…` paths a text names: `results/` then path characters, up to the first
/// character that cannot be in one (a backtick, a bracket, a space). `results/<name>` is a
/// pattern, not a path, and is not matched.
fn cited_results(text: &str) -> Vec<String> {
    let ok = |c: char| c.is_ascii_alphanumeric() || "._-/".contains(c);
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("results/") {
        // `penumbra-out/results.jsonl` has no slash after `results`; `foo_results/` is not the folder.
        let before = rest[..i].chars().next_back();
        let tail = &rest[i + "results/".len()..];
        let len = tail.find(|c: char| !ok(c)).unwrap_or(tail.len());
        if len > 0 && !before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
            out.push(format!("results/{}", tail[..len].trim_end_matches('.')));
        }
        rest = tail;
    }
    out
}

/// A Markdown heading with a date (2026-11-27) or a clock time (05:14) in it.
fn dated_heading(line: &str) -> bool {
    let Some(text) = line
        .trim_start_matches('#')
        .strip_prefix(' ')
        .filter(|_| line.starts_with('#'))
    else {
        return false;
    };
    let b = text.as_bytes();
    let digit = |i: usize| b.get(i).is_some_and(u8::is_ascii_digit);
    (0..b.len()).any(|i| {
        let date = (0..4).all(|k| digit(i + k))
            && b.get(i + 4) == Some(&b'-')
            && digit(i + 5)
            && digit(i + 6)
            && b.get(i + 7) == Some(&b'-')
            && digit(i + 8);
        let time = digit(i)
            && b.get(i + 1)
                .is_some_and(|&c| c == b':' || (c.is_ascii_digit() && b.get(i + 2) == Some(&b':')))
            && {
                let colon = if b[i + 1] == b':' { i + 1 } else { i + 2 };
                digit(colon + 1) && digit(colon + 2)
            };
        date || time
    })
}

/// Paragraphs of prose: fenced code dropped, split at blank lines, tables left out (a table's
/// rows are its own data: a key, a default, a limit).
fn paragraphs(text: &str) -> Vec<String> {
    let mut prose = String::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            prose += line;
            prose.push('\n');
        }
    }
    prose
        .split("\n\n")
        .map(str::trim)
        .filter(|p| !p.is_empty() && !p.starts_with('|'))
        .map(str::to_string)
        .collect()
}

/// A measured time (`12.5 ms`, `3 µs`, `took 24 s`) or a speed-up (`2.5× faster`, `3x slower`):
/// figures of one machine on one day, which belong in a results folder.
fn measured_figure(p: &str) -> Option<String> {
    let words: Vec<&str> = p.split_whitespace().collect();
    let number = |w: &str| {
        let w = w.trim_start_matches(['(', '~']);
        !w.is_empty()
            && w.chars().next().is_some_and(|c| c.is_ascii_digit())
            && w.chars().all(|c| c.is_ascii_digit() || ".,–-→".contains(c))
    };
    for (i, w) in words.iter().enumerate() {
        let next = words
            .get(i + 1)
            .map(|n| n.trim_end_matches([',', '.', ';', ')', ':']))
            .unwrap_or("");
        let glued = |unit: &str| {
            w.trim_end_matches([',', '.', ';', ')', ':'])
                .strip_suffix(unit)
                .is_some_and(&number)
        };
        let time = (number(w) && (next == "ms" || next == "µs")) || glued("ms") || glued("µs");
        let took = *w == "took"
            && words.get(i + 1).is_some_and(|n| number(n))
            && matches!(
                words
                    .get(i + 2)
                    .map(|u| u.trim_end_matches([',', '.', ';', ')'])),
                Some("s" | "min" | "minutes")
            );
        let speed = (w.ends_with('×') || w.ends_with('x'))
            && number(&w[..w.len() - w.chars().last().unwrap().len_utf8()])
            && (next == "faster" || next == "slower");
        if time || took || speed {
            return Some(words[i.saturating_sub(3)..(i + 3).min(words.len())].join(" "));
        }
    }
    None
}

#[test]
fn every_cited_results_path_exists_and_every_folder_has_a_readme_and_rows() {
    let root = root();
    let mut cited = 0;
    for (page, text) in pages() {
        for path in cited_results(&text) {
            assert!(
                root.join(&path).exists(),
                "{page} cites {path}, which does not exist"
            );
            cited += 1;
        }
    }
    // The docs cite the measurements they moved out of their prose.
    assert!(
        cited >= 100,
        "only {cited} results paths cited in docs/ and README.md"
    );
    for entry in std::fs::read_dir(root.join("results")).unwrap() {
        let dir = entry.unwrap().path();
        if !dir.is_dir() {
            continue;
        }
        assert!(
            dir.join("README.md").is_file(),
            "{} has no README.md",
            dir.display()
        );
        let rows = std::fs::read_dir(&dir).unwrap().filter(|e| {
            let p = e.as_ref().unwrap().path();
            matches!(
                p.extension().and_then(|x| x.to_str()),
                Some("csv" | "jsonl")
            )
        });
        assert!(
            rows.count() > 0,
            "{} holds no rows (.csv or .jsonl)",
            dir.display()
        );
    }
}

#[test]
fn no_heading_in_the_docs_carries_a_date_or_a_time() {
    for (page, text) in pages() {
        for line in text.lines() {
            assert!(!dated_heading(line), "{page}: a dated heading: {line}");
        }
    }
    // The census script anyone can rerun agrees.
    let out = std::process::Command::new("bash")
        .arg(root().join("scripts/doc-census.sh"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.lines().any(|l| l == "dated sections: 0"), "{text}");
}

#[test]
fn a_paragraph_that_quotes_a_measured_figure_cites_its_results_folder() {
    let mut bad = Vec::new();
    for (page, text) in pages() {
        for p in paragraphs(&text) {
            if let Some(figure) = measured_figure(&p) {
                if cited_results(&p).is_empty() {
                    bad.push(format!("{page}: \"…{figure}…\""));
                }
            }
        }
    }
    assert!(
        bad.is_empty(),
        "paragraphs quoting a measured figure without a results/ path:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_index_links_every_page() {
    let root = root();
    let index = read(&root.join("docs/README.md"));
    for (page, _) in pages() {
        let Some(name) = page.strip_prefix("docs/") else {
            continue;
        };
        if name != "README.md" {
            assert!(
                index.contains(&format!("]({name})")),
                "docs/README.md does not link {name}"
            );
        }
    }
}

#[test]
fn the_checks_themselves_catch_what_they_look_for() {
    assert!(dated_heading(
        "### Measured on an NVIDIA H200 (2026-11-27, 04:40 UTC)"
    ));
    assert!(dated_heading("## At 5:14"));
    assert!(
        !dated_heading("## 5. Cascades")
            && !dated_heading("text 2026-11-27")
            && !dated_heading("## Ratio 3:2x")
    );
    assert_eq!(
        cited_results("see `results/same-v/` and results/<name>, penumbra-out/results.jsonl."),
        ["results/same-v/"]
    );
    assert_eq!(
        measured_figure("the frame took 24 s of wall clock").as_deref(),
        Some("the frame took 24 s")
    );
    assert!(measured_figure("a first frame took 1493 ms against 1133 ms warm").is_some());
    assert!(
        measured_figure("(12.5ms)").is_some()
            && measured_figure("it is 2.5× faster there").is_some()
    );
    assert!(measured_figure("a 17×17 grid of 289 maps, bias 0.5 texel, at most 300 s").is_none());
    assert_eq!(
        paragraphs("a\nb\n\n```\n1 ms\n```\n\n| x | 3 ms |\n\nc"),
        ["a\nb", "c"]
    );
}
