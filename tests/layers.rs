//! The library's layers, lowest first, and the imports that run back up them. Data flows one way
//! (docs/architecture.md): a module may use the layers below it; an import of a higher layer is
//! listed here by file and counted, and the count may only fall. Needs no GPU.

use std::collections::BTreeSet;
use std::path::Path;

/// Top-level modules of src/, lowest layer first.
const LAYERS: &[&str] = &[
    "error", "progress", "interrupt", "panic_log", "gpu", "scene", "render", "stages", "methods", "frame", "api", "reference", "metrics", "record", "report",
    "studies", "inputs",
];

/// Imports that run back up today, at most: the error type wraps the errors of higher layers
/// (`#[from]`), and the record writes the report beside its rows. Lower it when one goes.
const MOST_UPWARD: usize = 5;

fn layer(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| *l == module)
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

/// (file, higher module) for every `crate::higher` path outside comments, tests excluded.
fn upward_imports() -> BTreeSet<(String, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut up = BTreeSet::new();
    for f in files {
        let rel = f.strip_prefix(&src).unwrap().to_string_lossy().replace('\\', "/");
        let top = rel.split('/').next().unwrap().trim_end_matches(".rs").to_string();
        if top == "main" || top == "cli" || top == "lib" || rel.ends_with("/tests.rs") || rel.contains("/tests/") {
            continue; // the binary sits above every layer; unit tests may reach anywhere
        }
        let Some(own) = layer(&top) else { panic!("src/{rel}: top-level module `{top}` is in no layer of tests/layers.rs") };
        let text = std::fs::read_to_string(&f).unwrap();
        let code: String = text.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n");
        // `#[cfg(test)] mod tests { … }` at the end of a file: not product code.
        let code = code.split("#[cfg(test)]").next().unwrap();
        for (i, _) in code.match_indices("crate::") {
            let rest = &code[i + 7..];
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            let names: Vec<String> = if name.is_empty() && rest.starts_with('{') {
                rest[1..rest.find('}').unwrap_or(1)].split(',').map(|s| s.trim().split("::").next().unwrap_or("").to_string()).collect()
            } else {
                vec![name]
            };
            for n in names {
                if let Some(l) = layer(&n) {
                    if l > own {
                        up.insert((format!("src/{rel}"), n));
                    }
                }
            }
        }
    }
    up
}

#[test]
fn imports_run_down_the_layers_but_for_a_known_few() {
    let up = upward_imports();
    for (file, target) in &up {
        println!("{file} uses {target}");
    }
    println!("{} imports run back up the layers", up.len());
    assert!(up.len() <= MOST_UPWARD, "{} imports run back up (at most {MOST_UPWARD}): {up:#?}", up.len());
}
