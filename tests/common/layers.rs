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
        // Product code: `#[cfg(test)]` items and comment lines left out.
        let code: String = product_lines(&text)
            .into_iter()
            .map(|(_, l)| l)
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
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

/// The product lines of one source file, numbered from 1: every line but those of its
/// `#[cfg(test)]` items. An item runs from its attribute to the `;` that ends it or to the brace
/// that closes its first `{`, matched outside comments and string and char literals; the lines
/// after it count again (a test helper partway through a file hides nothing below it).
pub fn product_lines(text: &str) -> Vec<(usize, &str)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let code = lines[i].trim_start();
        if let Some(after) = code.strip_prefix("#[cfg(test)]") {
            i = item_end(&lines, i, after) + 1;
            continue;
        }
        out.push((i + 1, lines[i]));
        i += 1;
    }
    out
}

/// The index of the line where the item whose attribute ends on line `start` (its rest `after`)
/// ends.
fn item_end(lines: &[&str], start: usize, after: &str) -> usize {
    let mut lexer = Lexer::default();
    let mut depth = 0usize;
    for (n, line) in std::iter::once(after)
        .chain(lines[start + 1..].iter().copied())
        .enumerate()
    {
        for c in lexer.code_chars(line) {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        return start + n;
                    }
                }
                ';' if depth == 0 => return start + n,
                _ => {}
            }
        }
    }
    lines.len() - 1
}

/// Where a scan stands between lines: in code, a block comment (nested `depth`), a string, or
/// a raw string closed by `"` and `hashes` `#`.
#[derive(Default)]
enum Lexer {
    #[default]
    Code,
    Block(usize),
    Str,
    Raw(usize),
}

impl Lexer {
    /// The characters of `line` that are code: comments and literals left out.
    fn code_chars(&mut self, line: &str) -> Vec<char> {
        let c: Vec<char> = line.chars().collect();
        let mut out = Vec::new();
        let mut i = 0;
        while i < c.len() {
            let next = c.get(i + 1).copied();
            match *self {
                Lexer::Block(depth) => match (c[i], next) {
                    ('*', Some('/')) => {
                        *self = if depth == 1 {
                            Lexer::Code
                        } else {
                            Lexer::Block(depth - 1)
                        };
                        i += 1;
                    }
                    ('/', Some('*')) => {
                        *self = Lexer::Block(depth + 1);
                        i += 1;
                    }
                    _ => {}
                },
                Lexer::Str => match c[i] {
                    '\\' => i += 1,
                    '"' => *self = Lexer::Code,
                    _ => {}
                },
                Lexer::Raw(hashes) => {
                    if c[i] == '"' && c[i + 1..].iter().take_while(|h| **h == '#').count() >= hashes
                    {
                        *self = Lexer::Code;
                        i += hashes;
                    }
                }
                Lexer::Code => match (c[i], next) {
                    ('/', Some('/')) => break,
                    ('/', Some('*')) => {
                        *self = Lexer::Block(1);
                        i += 1;
                    }
                    ('"', _) => *self = Lexer::Str,
                    ('r', Some('"' | '#'))
                        if i == 0 || !(c[i - 1].is_alphanumeric() || c[i - 1] == '_') =>
                    {
                        let hashes = c[i + 1..].iter().take_while(|h| **h == '#').count();
                        if c.get(i + 1 + hashes) == Some(&'"') {
                            *self = Lexer::Raw(hashes);
                            i += 1 + hashes;
                        } else {
                            out.push('r');
                        }
                    }
                    // A char literal ('{', '\''), not a lifetime ('a).
                    ('\'', Some('\\')) => {
                        i += 3;
                        while i < c.len() && c[i] != '\'' {
                            i += 1;
                        }
                    }
                    ('\'', Some(_)) if c.get(i + 2) == Some(&'\'') => i += 2,
                    (x, _) => out.push(x),
                },
            }
            i += 1;
        }
        out
    }
}
