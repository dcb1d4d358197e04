//! The engine writes nothing to the terminal: what it has to say goes into values its caller
//! reads (a frame's record, a scene's `warnings`) and into the notice callback the embedding
//! program registers (`progress::notice`; the `penumbra` binary prints it). This counts the
//! printing macros in `src/` outside comments and `#[cfg(test)]` items.

use std::path::Path;

const MACROS: [&str; 5] = ["println!(", "eprintln!(", "print!(", "eprint!(", "dbg!("];

/// The text of `src` with comments and every `#[cfg(test)]` item (to its closing brace) blanked.
fn product_code(src: &str) -> String {
    let mut out = String::new();
    let mut lines = src.lines();
    while let Some(line) = lines.next() {
        let t = line.trim_start();
        if t.starts_with("#[cfg(test)]") {
            // Skip the item that follows: to the brace that closes its first opening one.
            let mut depth = 0i32;
            let mut opened = false;
            for l in lines.by_ref() {
                let code = l.split("//").next().unwrap_or("");
                depth += code.matches('{').count() as i32 - code.matches('}').count() as i32;
                opened |= code.contains('{');
                if (opened && depth <= 0) || (!opened && code.trim_end().ends_with(';')) {
                    break;
                }
            }
            continue;
        }
        if t.starts_with("//") {
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// Each printing macro called in `code`, with its line. `print!(` is inside `eprint!(` and
/// `println!(`: whole words only.
fn calls(code: &str) -> Vec<String> {
    let mut found = Vec::new();
    for line in code.lines() {
        for m in MACROS {
            let whole = |(i, _): &(usize, &str)| {
                !line[..*i].ends_with(|c: char| c.is_alphanumeric() || c == '_')
            };
            for _ in line.match_indices(m).filter(whole) {
                found.push(format!("{m} in `{}`", line.trim()));
            }
        }
    }
    found
}

fn count(dir: &Path, found: &mut Vec<String>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            count(&path, found);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let code = product_code(&std::fs::read_to_string(&path).unwrap());
            found.extend(
                calls(&code)
                    .into_iter()
                    .map(|c| format!("{}: {c}", path.display())),
            );
        }
    }
}

#[test]
fn the_engine_prints_nothing() {
    let mut found = Vec::new();
    count(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut found,
    );
    assert!(
        found.is_empty(),
        "the engine prints {} time(s); return it in a value or hand it to progress::notice:\n{}",
        found.len(),
        found.join("\n")
    );
}

#[test]
fn the_count_sees_prints_and_skips_tests_and_comments() {
    let src = "fn a() {\n    eprintln!(\"x\");\n    print!(\"y\");\n}\n// println!(\"doc\")\n#[cfg(test)]\nmod tests {\n    fn b() {\n        println!(\"t\");\n    }\n}\nfn c() { dbg!(1); }\n";
    let code = product_code(src);
    assert_eq!(calls(&code).len(), 3, "{code}");
    assert!(!code.contains("\"t\"") && !code.contains("doc"), "{code}");
    // A call whose arguments run over several lines counts once.
    assert_eq!(
        calls("    eprintln!(\n        \"waiting for {}\",\n").len(),
        1
    );
}
