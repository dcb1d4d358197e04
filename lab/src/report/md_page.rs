//! A study's Markdown tables as one self-contained HTML page with its SVG charts as data URIs: opens
//! offline, no scripts, no links (the hybrid and frontier studies' `report.html`).

/// `md`: `#`/`##` headings, paragraphs, `- ` lists (a line indented two spaces goes on the item
/// above) and pipe tables; `charts`: (heading, SVG) after the tables.
pub fn page(title: &str, md: &str, charts: &[(&str, &str)]) -> String {
    let esc = |t: &str| code_spans(&escape(t));
    let mut body = String::new();
    let mut in_table = false;
    // The list item being read: a list is open while there is one.
    let mut item: Option<String> = None;
    for line in md.lines() {
        if let Some(text) = item.take() {
            if let Some(more) = line.strip_prefix("  ") {
                item = Some(format!("{text} {}", more.trim()));
                continue;
            }
            body += &format!("<li>{}</li>\n", esc(&text));
            if let Some(next) = line.strip_prefix("- ") {
                item = Some(next.to_string());
                continue;
            }
            body += "</ul>\n";
        }
        if let Some(first) = line.strip_prefix("- ") {
            if in_table {
                body += "</table>\n";
                in_table = false;
            }
            body += "<ul>\n";
            item = Some(first.to_string());
            continue;
        }
        if let Some(rest) = line.strip_prefix("|") {
            if line.starts_with("|---") {
                continue;
            }
            let tag = if in_table { "td" } else { "th" };
            if !in_table {
                body += "<table>\n";
                in_table = true;
            }
            body += "<tr>";
            for cell in rest.trim_end_matches('|').split('|') {
                body += &format!("<{tag}>{}</{tag}>", esc(cell.trim()));
            }
            body += "</tr>\n";
            continue;
        }
        if in_table {
            body += "</table>\n";
            in_table = false;
        }
        if let Some(h) = line.strip_prefix("## ") {
            body += &format!("<h2>{}</h2>\n", esc(h));
        } else if let Some(h) = line.strip_prefix("# ") {
            body += &format!("<h1>{}</h1>\n", esc(h));
        } else if !line.trim().is_empty() {
            body += &format!("<p>{}</p>\n", esc(line));
        }
    }
    if in_table {
        body += "</table>\n";
    }
    if let Some(text) = item {
        body += &format!("<li>{}</li>\n</ul>\n", esc(&text));
    }
    for (heading, svg) in charts {
        // As a data URI: the page names no resource, not even the SVG namespace.
        body += &format!("<h2>{}</h2>\n<div class=\"chart\"><img src=\"{}\" alt=\"{}\"></div>\n", esc(heading), super::files::data_uri("image/svg+xml", svg.as_bytes()), esc(heading));
    }
    format!(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>{}</title>\n<style>\
         body{{font-family:sans-serif;max-width:1100px;margin:2em auto}}table{{border-collapse:collapse;margin:1em 0}}\
         td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}th{{background:#eee}}.chart img{{max-width:100%;height:auto}}\
         </style></head><body>\n{body}</body></html>\n",
        escape(title)
    )
}

fn escape(t: &str) -> String {
    t.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// Markdown's `code` spans as <code>: each pair of backticks; an unpaired last one stays as it is.
fn code_spans(t: &str) -> String {
    let parts: Vec<&str> = t.split('`').collect();
    let mut out = String::new();
    for (i, part) in parts.iter().enumerate() {
        let closed = i % 2 == 1 && i + 1 < parts.len();
        match (i % 2, closed) {
            (1, true) => out += &format!("<code>{part}</code>"),
            (1, false) => out += &format!("`{part}"),
            _ => out += part,
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn code_spans_become_code_elements() {
        assert_eq!(super::code_spans("`auto:target=T` chooses `n`"), "<code>auto:target=T</code> chooses <code>n</code>");
        assert_eq!(super::code_spans("one ` alone"), "one ` alone");
        let page = super::page("t", "a `b<c` d\n\n| x |\n|---|\n| `y` |", &[]);
        assert!(page.contains("<p>a <code>b&lt;c</code> d</p>"), "{page}");
        assert!(page.contains("<td><code>y</code></td>"), "{page}");
    }

    #[test]
    fn dash_lines_become_one_list() {
        let page = super::page("t", "Intro.\n\n- one `a`;\n- two,\n  carried on;\n- three.\n\nAfter.\n- last", &[]);
        assert!(
            page.contains("<p>Intro.</p>\n<ul>\n<li>one <code>a</code>;</li>\n<li>two, carried on;</li>\n<li>three.</li>\n</ul>\n<p>After.</p>\n<ul>\n<li>last</li>\n</ul>\n"),
            "{page}"
        );
        assert!(!page.contains("<p>- "), "{page}");
    }
}
