//! `report.md`: the same tables in Markdown, images as files in a folder beside it.

use std::fmt::Write;

use super::table::Table;

/// A file referenced from the Markdown: caption and path relative to the report.
pub(super) struct Link {
    pub caption: String,
    pub path: String,
}

pub(super) struct MethodLinks {
    pub label: String,
    pub tiles: Vec<Link>,
}

/// `|` would end a cell and newlines would end the row.
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

pub(super) fn render(
    title: &str,
    settings: &[(String, String)],
    tables: &[Table],
    charts: &[Link],
    methods: &[MethodLinks],
) -> String {
    let mut md = String::new();
    // `write!` into a String cannot fail; the results are ignored on purpose.
    let _ = writeln!(
        md,
        "# {}\n\n## Settings\n\n| setting | value |\n|---|---|",
        cell(title)
    );
    for (k, v) in settings {
        let _ = writeln!(md, "| {} | {} |", cell(k), cell(v));
    }
    let _ = writeln!(
        md,
        "\n## Results\n\n**Bold**: best in its column (lower is better except PSNR and SSIM; no mark when all \
         values tie). Times: median (min–max) over repeats. PSNR ∞ = identical. Adaptive against the regular \
         grids: an adaptive row dominates a grid when its median frame and its RMSE are both at most the \
         grid's (same run, same adapter); ratios are to the grid."
    );
    for t in tables {
        let _ = writeln!(md, "\n### {}: {}\n", cell(&t.scene), t.kind);
        let _ = writeln!(md, "| {} |", t.header.join(" | "));
        let align: Vec<&str> = (0..t.header.len())
            .map(|i| if i < 1 { "---" } else { "---:" })
            .collect();
        let _ = writeln!(md, "| {} |", align.join(" | "));
        for r in &t.rows {
            let cells: Vec<String> = r
                .iter()
                .map(|c| {
                    if c.best {
                        format!("**{}**", cell(&c.text))
                    } else {
                        cell(&c.text)
                    }
                })
                .collect();
            let _ = writeln!(md, "| {} |", cells.join(" | "));
        }
    }
    if !charts.is_empty() {
        let _ = writeln!(md, "\n## Charts\n");
        for c in charts {
            let _ = writeln!(md, "![{}]({})\n", cell(&c.caption), c.path);
        }
    }
    if !methods.is_empty() {
        let _ = writeln!(md, "\n## Images");
        for m in methods {
            let _ = writeln!(md, "\n### {}\n", cell(&m.label));
            let captions: Vec<String> = m.tiles.iter().map(|t| cell(&t.caption)).collect();
            let _ = writeln!(
                md,
                "| {} |\n|{}",
                captions.join(" | "),
                "---|".repeat(captions.len())
            );
            let imgs: Vec<String> = m
                .tiles
                .iter()
                .map(|t| format!("![{}]({})", cell(&t.caption), t.path))
                .collect();
            let _ = writeln!(md, "| {} |", imgs.join(" | "));
        }
    }
    md
}
