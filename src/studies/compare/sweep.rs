//! Sweep specs (docs/compare-and-report.md): parameter grids expanded into method specs.
//!
//! ```toml
//! methods = ["hard"]              # optional: plain method specs, run as given
//! [[grid]]
//! method = "adaptive"
//! p_m = [0, 10, 100, 1000]        # an array: one run per value
//! scope = "local"                 # a scalar: the same for every run of this grid
//! [[grid]]
//! method = "regular"
//! n = [3, 5, 9, 17]
//! ```
//! A grid is the Cartesian product of its arrays, keys in alphabetical order (the last key varies
//! fastest). Keys must be parameters of the method; values are numbers, strings or booleans.

use crate::{Error, Result};
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepSpec {
    #[serde(default)]
    methods: Vec<String>,
    #[serde(default)]
    grid: Vec<toml::Table>,
}

fn scalar(v: &toml::Value) -> Option<String> {
    match v {
        toml::Value::Integer(i) => Some(i.to_string()),
        toml::Value::Float(f) if f.is_infinite() && *f > 0.0 => Some("inf".into()),
        toml::Value::Float(f) => Some(f.to_string()),
        toml::Value::String(s) => Some(s.clone()),
        toml::Value::Boolean(b) => Some(b.to_string()),
        _ => None,
    }
}

/// One grid → its method specs (`adaptive:p_m=0,scope=local`, …).
fn expand(grid: &toml::Table, at: &str) -> std::result::Result<Vec<String>, String> {
    let method = match grid.get("method") {
        Some(toml::Value::String(m)) => m.clone(),
        Some(_) => return Err(format!("{at}: `method` must be a string")),
        None => return Err(format!("{at}: missing `method = \"…\"`")),
    };
    let mut axes: Vec<(String, Vec<String>)> = Vec::new();
    for (key, value) in grid.iter().filter(|(k, _)| *k != "method") {
        let values: Vec<String> = match value {
            toml::Value::Array(items) if items.is_empty() => return Err(format!("{at}: `{key}` is an empty list")),
            toml::Value::Array(items) => items
                .iter()
                .map(|v| scalar(v).ok_or_else(|| format!("{at}: `{key}` holds {v}, not a number, string or boolean")))
                .collect::<std::result::Result<_, _>>()?,
            v => vec![scalar(v).ok_or_else(|| format!("{at}: `{key}` = {v} is not a number, string, boolean or list of them"))?],
        };
        axes.push((key.clone(), values));
    }
    let mut specs = vec![Vec::<String>::new()];
    for (key, values) in &axes {
        specs = specs.into_iter().flat_map(|prefix| values.iter().map(move |v| [prefix.clone(), vec![format!("{key}={v}")]].concat())).collect();
    }
    Ok(specs.into_iter().map(|pairs| if pairs.is_empty() { method.clone() } else { format!("{method}:{}", pairs.join(",")) }).collect())
}

/// Spec text → method specs, in file order (plain `methods` first). Errors name `origin`.
pub fn parse_spec(text: &str, origin: &str) -> Result<Vec<String>> {
    let err = |m: String| Error::Param(format!("{origin}: {m}"));
    let spec: SweepSpec = toml::from_str(text).map_err(|e| {
        let msg = e.message().replace('\n', " ").trim().to_string();
        err(match crate::error::toml_position(text, &e) {
            Some((line, col)) => format!("line {line}, column {col}: {msg}"),
            None => msg,
        })
    })?;
    let mut specs = Vec::new();
    for m in spec.methods {
        crate::methods::Method::parse(&m, &[]).map_err(|e| err(format!("methods: {e}")))?;
        specs.push(m);
    }
    for (i, grid) in spec.grid.iter().enumerate() {
        let at = format!("grid {}", i + 1);
        for m in expand(grid, &at).map_err(err)? {
            // Checked here, so a bad key or value names the spec and the grid.
            crate::methods::Method::parse(&m, &[]).map_err(|e| err(format!("{at} ({m}): {e}")))?;
            specs.push(m);
        }
    }
    if specs.is_empty() {
        return Err(err("no `methods` and no `[[grid]]`: nothing to run".into()));
    }
    Ok(specs)
}

/// Reads and parses a spec file.
pub fn read_spec(path: &std::path::Path) -> Result<Vec<String>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, format!("cannot read sweep spec: {e}")))?;
    parse_spec(&text, &path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::parse_spec;

    #[test]
    fn grids_expand_in_order() {
        let text = r#"
methods = ["hard"]
[[grid]]
method = "adaptive"
p_m = [0, 10]
scope = ["global", "local"]
[[grid]]
method = "regular"
n = [3, 5]
"#;
        assert_eq!(
            parse_spec(text, "t").unwrap(),
            [
                "hard",
                "adaptive:p_m=0,scope=global",
                "adaptive:p_m=0,scope=local",
                "adaptive:p_m=10,scope=global",
                "adaptive:p_m=10,scope=local",
                "regular:n=3",
                "regular:n=5"
            ]
        );
        assert_eq!(parse_spec("[[grid]]\nmethod = \"adaptive\"\np_m = inf\n", "t").unwrap(), ["adaptive:p_m=inf"]);
    }

    #[test]
    fn malformed_specs_are_errors() {
        for bad in [
            "[[grid]]\nmethod = \"regular\"\nn = [",                  // TOML syntax
            "[[grid]]\nn = [3, 5]",                                   // no method
            "[[grid]]\nmethod = \"regular\"\nn = []",                 // empty list
            "[[grid]]\nmethod = \"regular\"\nn = [[3]]",              // nested list
            "[[grid]]\nmethod = \"regular\"\nn = { a = 1 }",          // table
            "grids = []",                                             // unknown key
            "",                                                       // nothing to run
        ] {
            let e = parse_spec(bad, "spec.toml").unwrap_err().to_string();
            assert!(e.starts_with("spec.toml: "), "{bad:?}: {e}");
            assert!(!e.contains('\n'), "one line: {e}");
        }
    }
}
