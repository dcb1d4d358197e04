//! The layer tests' scan (tests/layers.rs for the engine, lab/tests/layers.rs for the lab): the
//! imports that run back up a crate's layers.

use std::collections::BTreeSet;
use std::path::Path;

fn layer(layers: &[&str], module: &str) -> Option<usize> {
    layers.iter().position(|l| *l == module)
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// (file, higher module) for every `crate::higher` path in the crate whose sources are `src`,
/// outside comments, tests excluded; `layers` are its top-level modules, lowest first, and
/// `above` the files that sit above every layer (`main`, `lib`, …).
pub fn upward_imports(src: &Path, layers: &[&str], above: &[&str]) -> BTreeSet<(String, String)> {
    let src = src.to_path_buf();
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut up = BTreeSet::new();
    for f in files {
        let rel = f
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        let top = rel
            .split('/')
            .next()
            .unwrap()
            .trim_end_matches(".rs")
            .to_string();
        if above.contains(&top.as_str()) || rel.ends_with("/tests.rs") || rel.contains("/tests/") {
            continue; // the binary and the crate root sit above every layer; unit tests may reach anywhere
        }
        let Some(own) = layer(layers, &top) else {
            panic!(
                "{}/{rel}: top-level module `{top}` is in no layer of its layer test",
                src.display()
            )
        };
        let text = std::fs::read_to_string(&f).unwrap();
        let code: String = text
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        // `#[cfg(test)] mod tests { … }` at the end of a file: not product code.
        let code = code.split("#[cfg(test)]").next().unwrap();
        for (i, _) in code.match_indices("crate::") {
            let rest = &code[i + 7..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            let names: Vec<String> = if name.is_empty() && rest.starts_with('{') {
                rest[1..rest.find('}').unwrap_or(1)]
                    .split(',')
                    .map(|s| s.trim().split("::").next().unwrap_or("").to_string())
                    .collect()
            } else {
                vec![name]
            };
            for n in names {
                if let Some(l) = layer(layers, &n) {
                    if l > own {
                        up.insert((rel.clone(), n));
                    }
                }
            }
        }
    }
    up
}
