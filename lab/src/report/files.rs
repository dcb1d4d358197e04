//! File-level helpers: atomic writes, safe file names, PNG sniffing, data URIs.

use std::fs;
use std::io::Write;
use std::path::Path;

use base64::Engine;

use super::ReportError;

/// Writes via a temporary sibling and a rename, so readers never see a partial file and a
/// failed write leaves nothing behind.
pub(super) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    let io = |source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = path
        .parent()
        .ok_or_else(|| io(std::io::Error::other("path has no parent")))?;
    let name = path
        .file_name()
        .ok_or_else(|| io(std::io::Error::other("path has no file name")))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp); // best effort: the original error is what matters
    }
    result.map_err(io)
}

/// Lower-case ASCII letters, digits and `_`/`-` only, runs of anything else as one `_`.
pub(super) fn slug(text: &str) -> String {
    let mut out = String::new();
    for c in text.chars() {
        if c.is_ascii_alphanumeric() || c == '-' {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    let out = out.trim_matches('_').to_string();
    if out.is_empty() {
        "item".into()
    } else {
        out
    }
}

/// Unique slugs for a list of names (`a`, `a_2`, …), in order. Linear: a sweep may name tens of
/// thousands of configurations.
pub(crate) fn unique_slugs<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut seen: std::collections::HashSet<String> = std::collections::HashSet::new();
    // Per base, the suffix to try next: the taken set only grows, so smaller ones stay taken.
    let mut next: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    for name in names {
        let base = slug(name);
        let mut s = base.clone();
        if seen.contains(&s) {
            let k = next.entry(base.clone()).or_insert(2);
            loop {
                s = format!("{base}_{k}");
                *k += 1;
                if !seen.contains(&s) {
                    break;
                }
            }
        }
        seen.insert(s.clone());
        out.push(s);
    }
    out
}

pub(super) fn is_png(bytes: &[u8]) -> bool {
    bytes.starts_with(b"\x89PNG\r\n\x1a\n")
}

pub(crate) fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!(
        "data:{mime};base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slugs() {
        assert_eq!(
            slug("adaptive(p_m=0, scope=local)"),
            "adaptive_p_m_0_scope_local"
        );
        assert_eq!(slug("../../etc"), "etc");
        assert_eq!(slug("()"), "item");
        assert_eq!(
            unique_slugs(["a b", "a-b", "a  b"]),
            vec!["a_b", "a-b", "a_b_2"]
        );
        // A name that is already a suffixed slug is skipped over, as are repeated names.
        assert_eq!(
            unique_slugs(["x_2", "x", "x", "x", "x_3"]),
            vec!["x_2", "x", "x_3", "x_4", "x_3_2"]
        );
        let many = unique_slugs(std::iter::repeat_n("z", 20_000));
        assert_eq!(
            (many[1].as_str(), many[19_999].as_str()),
            ("z_2", "z_20000")
        );
    }
}
