//! A study's Markdown tables as one self-contained HTML page with its SVG charts as data URIs: opens
//! offline, no scripts, no links (the hybrid, frontier, cascades and estimate studies' `report.html`,
//! and `penumbra report` on a results folder).

use pulldown_cmark::{html, Event, Options, Parser, Tag, TagEnd};

/// `md`: CommonMark with pipe tables; `charts`: (heading, SVG) after the tables.
pub fn page(title: &str, md: &str, charts: &[(&str, &str)]) -> String {
    let mut body = body(md);
    for (heading, svg) in charts {
        // As a data URI: the page names no resource, not even the SVG namespace.
        body += &format!(
            "<h2>{}</h2>\n<div class=\"chart\"><img src=\"{}\" alt=\"{}\"></div>\n",
            escape(heading),
            super::files::data_uri("image/svg+xml", svg.as_bytes()),
            escape(heading)
        );
    }
    document(title, &body)
}

/// `body` in the house page: a title, one inline style sheet, nothing fetched.
pub fn document(title: &str, body: &str) -> String {
    format!(
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>{}</title>\n<style>\
         body{{font-family:sans-serif;max-width:1100px;margin:2em auto}}table{{border-collapse:collapse;margin:1em 0}}\
         td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}th{{background:#eee}}.chart img{{max-width:100%;height:auto}}\
         </style></head><body>\n{body}</body></html>\n",
        escape(title)
    )
}

/// The HTML of `md`. Raw HTML in the text is shown as text, not passed through: a row's label
/// such as `<2 ms` stays a label, and the page can name no resource by way of a tag. A Markdown
/// image or link keeps its target only where that is a `data:` URI or a relative path (a file
/// beside the page, an anchor on it); any other (`http:`, `javascript:`, `//host`) becomes its
/// text, so the page fetches nothing when it opens and holds no live link out.
pub fn body(md: &str) -> String {
    // Quotes too: the shown text of a tag (`src="http…"`) must not read as an attribute to a check
    // that the page names no resource.
    let shown = |t: &str| escape(t).replace('"', "&quot;").into();
    // Per open link or image: whether its tags are dropped (its text stays).
    let mut dropped: Vec<bool> = Vec::new();
    let events = Parser::new_ext(md, Options::ENABLE_TABLES).filter_map(|e| match e {
        Event::Html(t) => Some(Event::Html(shown(&t))),
        Event::InlineHtml(t) => Some(Event::InlineHtml(shown(&t))),
        Event::Start(Tag::Link { ref dest_url, .. } | Tag::Image { ref dest_url, .. }) => {
            let drop = !offline_target(dest_url);
            dropped.push(drop);
            (!drop).then_some(e)
        }
        Event::End(TagEnd::Link | TagEnd::Image) => (!dropped.pop().unwrap_or(false)).then_some(e),
        e => Some(e),
    });
    let mut out = String::new();
    html::push_html(&mut out, events);
    out
}

/// A target the page may name: a `data:` URI, or a relative path or anchor (no scheme, no host).
pub fn offline_target(url: &str) -> bool {
    let url = url.trim();
    if url
        .get(..5)
        .is_some_and(|s| s.eq_ignore_ascii_case("data:"))
    {
        return true;
    }
    // A scheme is letters, digits, `+`, `-`, `.` before the first `:`, ahead of any `/`, `?`, `#`.
    let scheme = url
        .split(['/', '?', '#'])
        .next()
        .is_some_and(|head| head.contains(':'));
    !scheme && !url.starts_with("//") && !url.starts_with('\\')
}

pub(super) fn escape(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

#[cfg(test)]
mod tests {
    #[test]
    fn code_spans_become_code_elements() {
        let page = super::page("t", "a `b<c` d\n\n| x |\n|---|\n| `y` |", &[]);
        assert!(page.contains("<p>a <code>b&lt;c</code> d</p>"), "{page}");
        assert!(page.contains("<td><code>y</code></td>"), "{page}");
        // An unpaired backtick stays as it is.
        assert!(super::body("one ` alone").contains("<p>one ` alone</p>"));
    }

    #[test]
    fn dash_lines_become_one_list() {
        let page = super::page(
            "t",
            "Intro.\n\n- one `a`;\n- two,\n  carried on;\n- three.\n\nAfter.\n- last",
            &[],
        );
        // CommonMark keeps the continuation line's break as a newline inside the item.
        assert!(
            page.contains("<p>Intro.</p>\n<ul>\n<li>one <code>a</code>;</li>\n<li>two,\ncarried on;</li>\n<li>three.</li>\n</ul>\n<p>After.</p>\n<ul>\n<li>last</li>\n</ul>\n"),
            "{page}"
        );
        assert!(!page.contains("<p>- "), "{page}");
    }

    #[test]
    fn links_and_images_out_of_the_page_become_their_text() {
        let md = "![x](http://h/p.png) [click](javascript:alert(1)) <https://h/> [ok](rows.csv) [top](#t) ![d](data:image/png;base64,AA==) [w](//h/p) [J](JaVaScRiPt:x)";
        let page = super::body(md);
        for attr in [
            "href=\"http",
            "src=\"http",
            "href=\"javascript",
            "href=\"JaVaScRiPt",
            "href=\"//",
        ] {
            assert!(!page.contains(attr), "{attr} in {page}");
        }
        // The dropped ones keep their text.
        assert!(page.contains("<p>x click https://h/ <a href"), "{page}");
        assert!(
            page.contains("<a href=\"rows.csv\">ok</a>")
                && page.contains("<a href=\"#t\">top</a>")
                && page.contains("<img src=\"data:image/png;base64,AA==\""),
            "{page}"
        );
        assert!(
            !page.contains("<img src=\"http") && page.matches("<a ").count() == 2,
            "{page}"
        );
    }

    #[test]
    fn tags_in_the_text_stay_text() {
        let page = super::page(
            "a <b>",
            "x <img src=\"http://h/p.png\"> y\n\n<script>1</script>\n",
            &[],
        );
        assert!(page.contains("<title>a &lt;b&gt;</title>"), "{page}");
        assert!(
            page.contains("x &lt;img src=&quot;http://h/p.png&quot;&gt; y"),
            "{page}"
        );
        assert!(page.contains("&lt;script&gt;1&lt;/script&gt;"), "{page}");
        assert!(
            !page.contains("<script") && !page.contains("<img") && !page.contains("src=\"http"),
            "{page}"
        );
    }
}
