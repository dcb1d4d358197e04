//! `methods/auto/` keeps its search in types (the ladder of grids, a try read `At`, one frame's
//! `Search`), so no function there takes more than four arguments besides `self`, and its frame
//! is a sequence of named steps, none longer than a screen. This reads the sources.

use std::path::Path;

/// Each `fn` in `src`: its name, its arguments besides `self`, and its lines (signature to the
/// closing brace at its indentation).
fn functions(src: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = src.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim_start();
        let indent = &line[..line.len() - t.len()];
        let Some(at) = t.find("fn ").filter(|&k| {
            let head = &t[..k];
            head.is_empty() || head.starts_with("pub") || head.starts_with("const")
        }) else {
            continue;
        };
        if t.starts_with("//") {
            continue;
        }
        let name: String = t[at + 3..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // The signature, to its body's `{` or a `;`, with `->` out of the way of `<>` depth.
        let mut sig = String::new();
        let mut end = i;
        for (k, l) in lines.iter().enumerate().skip(i) {
            sig.push_str(l);
            sig.push('\n');
            end = k;
            let s = l.trim_end();
            if (s.ends_with('{') || s.ends_with(';') || s.ends_with('}'))
                && sig.matches('(').count() <= sig.matches(')').count()
            {
                break;
            }
        }
        let sig = sig.replace("->", "~");
        let open = sig.find(&format!("fn {name}")).unwrap() + 3 + name.len();
        let (mut depth, mut args, mut cur) = (0, Vec::new(), String::new());
        for c in sig[open..].chars() {
            match c {
                '(' | '<' | '[' => depth += 1,
                ')' | '>' | ']' => depth -= 1,
                _ => {}
            }
            if depth == 0 {
                break;
            }
            if c == ',' && depth == 1 {
                args.push(std::mem::take(&mut cur));
            } else if depth > 1 || c != '(' {
                cur.push(c);
            }
        }
        args.push(cur);
        let n = args
            .iter()
            .map(|a| a.trim())
            .filter(|a| !a.is_empty() && !a.trim_start_matches(['&', ' ']).ends_with("self"))
            .count();
        let close = format!("{indent}}}");
        let last = if sig.trim_end().ends_with('{') {
            (end + 1..lines.len())
                .find(|&k| lines[k] == close)
                .unwrap_or(end)
        } else {
            end
        };
        out.push((name, n, last - i + 1));
    }
    out
}

fn auto_functions() -> Vec<(String, String, usize, usize)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/methods/auto");
    let mut all = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let src = std::fs::read_to_string(&path).unwrap();
        // Product code only: the tests module is the file's last item.
        let code = src.split("#[cfg(test)]").next().unwrap_or("");
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        for (name, n, len) in functions(code) {
            all.push((file.clone(), name, n, len));
        }
    }
    all
}

#[test]
fn no_auto_function_takes_more_than_four_arguments() {
    let over: Vec<_> = auto_functions().into_iter().filter(|f| f.2 > 4).collect();
    assert!(over.is_empty(), "(file, fn, arguments, lines): {over:?}");
}

#[test]
fn autos_longest_function_fits_a_screen() {
    let all = auto_functions();
    let longest = all.iter().max_by_key(|f| f.3).unwrap();
    // certified_frame (the certified decision, its typed record spelled out field by field: 183
    // lines) is the longest and the next to split; the frame's own run was 237 lines before it
    // was split into named steps.
    assert!(longest.3 <= 185, "{longest:?}");
    let run = all
        .iter()
        .find(|f| f.0 == "mod.rs" && f.1 == "run")
        .unwrap();
    assert!(run.3 <= 50, "{run:?}");
}

#[test]
fn the_reader_counts_arguments_and_lines() {
    let src = "impl A {\n    pub(super) fn f(\n        &mut self,\n        a: u32,\n        g: &mut dyn FnMut(&mut T) -> Result<Option<R>>,\n    ) -> u32 {\n        1\n    }\n}\nfn h(x: (u32, u32), y: &[f32]) {}\n";
    let f = functions(src);
    assert_eq!(
        f,
        vec![("f".to_string(), 2, 7), ("h".to_string(), 2, 1)],
        "{f:?}"
    );
}
