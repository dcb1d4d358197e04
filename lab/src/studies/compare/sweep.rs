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

/// A grid's method and its axes (key, values), keys in alphabetical order.
type Axes = (String, Vec<(String, Vec<String>)>);

fn axes(grid: &toml::Table, at: &str) -> std::result::Result<Axes, String> {
    let method = match grid.get("method") {
        Some(toml::Value::String(m)) => m.clone(),
        Some(_) => return Err(format!("{at}: `method` must be a string")),
        None => return Err(format!("{at}: missing `method = \"…\"`")),
    };
    let mut axes: Vec<(String, Vec<String>)> = Vec::new();
    for (key, value) in grid.iter().filter(|(k, _)| *k != "method") {
        let values: Vec<String> = match value {
            toml::Value::Array(items) if items.is_empty() => {
                return Err(format!("{at}: `{key}` is an empty list"))
            }
            toml::Value::Array(items) => items
                .iter()
                .map(|v| {
                    scalar(v).ok_or_else(|| {
                        format!("{at}: `{key}` holds {v}, not a number, string or boolean")
                    })
                })
                .collect::<std::result::Result<_, _>>()?,
            v => vec![scalar(v).ok_or_else(|| {
                format!("{at}: `{key}` = {v} is not a number, string, boolean or list of them")
            })?],
        };
        axes.push((key.clone(), values));
    }
    Ok((method, axes))
}

/// Configurations a grid expands to (saturating: a grid too large to hold is still counted).
fn count(axes: &[(String, Vec<String>)]) -> usize {
    axes.iter()
        .fold(1usize, |n, (_, values)| n.saturating_mul(values.len()))
}

/// One grid → its method specs (`adaptive:p_m=0,scope=local`, …), the last key varying fastest.
/// Each spec is written once, from an odometer over the axes: time linear in the output.
fn expand((method, axes): &Axes) -> Vec<String> {
    let pairs: Vec<Vec<String>> = axes
        .iter()
        .map(|(key, values)| values.iter().map(|v| format!("{key}={v}")).collect())
        .collect();
    let mut digits = vec![0usize; pairs.len()];
    let mut specs = Vec::with_capacity(count(axes));
    loop {
        let mut spec = method.clone();
        for (i, (axis, &d)) in pairs.iter().zip(&digits).enumerate() {
            spec.push(if i == 0 { ':' } else { ',' });
            spec.push_str(&axis[d]);
        }
        specs.push(spec);
        // Advance the odometer from the last axis; done when the first rolls over.
        let mut i = pairs.len();
        loop {
            if i == 0 {
                return specs;
            }
            i -= 1;
            digits[i] += 1;
            if digits[i] < pairs[i].len() {
                break;
            }
            digits[i] = 0;
        }
    }
}

/// Spec text → method specs, in file order (plain `methods` first). Errors name `origin`.
pub fn parse_spec(text: &str, origin: &str) -> Result<Vec<String>> {
    parse_spec_within(text, origin, usize::MAX)
}

/// As [`parse_spec`], refusing a spec of more than `max` configurations before expanding it
/// (`--max-configs`), so a grid of billions neither fills memory nor runs for hours.
pub fn parse_spec_within(text: &str, origin: &str, max: usize) -> Result<Vec<String>> {
    let err = |m: String| Error::param(format!("{origin}: {m}"));
    let spec: SweepSpec = toml::from_str(text).map_err(|e| {
        let msg = e.message().replace('\n', " ").trim().to_string();
        err(match crate::error::toml_position(text, &e) {
            Some((line, col)) => format!("line {line}, column {col}: {msg}"),
            None => msg,
        })
    })?;
    let grids = spec
        .grid
        .iter()
        .enumerate()
        .map(|(i, g)| axes(g, &format!("grid {}", i + 1)))
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(err)?;
    let total = grids
        .iter()
        .fold(spec.methods.len(), |n, g| n.saturating_add(count(&g.1)));
    super::plan::check_count(total, max, origin)?;
    let mut specs = Vec::with_capacity(total);
    for m in spec.methods {
        crate::methods::Method::parse(&m, &[]).map_err(|e| err(format!("methods: {e}")))?;
        specs.push(m);
    }
    for (i, grid) in grids.iter().enumerate() {
        let at = format!("grid {}", i + 1);
        for m in expand(grid) {
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

/// Reads and parses a spec file, refusing more than `max` configurations.
pub fn read_spec(path: &std::path::Path, max: usize) -> Result<Vec<String>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::io(path, format!("cannot read sweep spec: {e}")))?;
    parse_spec_within(&text, &path.display().to_string(), max)
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
        assert_eq!(
            parse_spec("[[grid]]\nmethod = \"adaptive\"\np_m = inf\n", "t").unwrap(),
            ["adaptive:p_m=inf"]
        );
    }

    #[test]
    fn malformed_specs_are_errors() {
        for bad in [
            "[[grid]]\nmethod = \"regular\"\nn = [",     // TOML syntax
            "[[grid]]\nn = [3, 5]",                      // no method
            "[[grid]]\nmethod = \"regular\"\nn = []",    // empty list
            "[[grid]]\nmethod = \"regular\"\nn = [[3]]", // nested list
            "[[grid]]\nmethod = \"regular\"\nn = { a = 1 }", // table
            "grids = []",                                // unknown key
            "",                                          // nothing to run
        ] {
            let e = parse_spec(bad, "spec.toml").unwrap_err().to_string();
            assert!(e.starts_with("spec.toml: "), "{bad:?}: {e}");
            assert!(!e.contains('\n'), "one line: {e}");
        }
    }

    /// 400 × 100 values: expanded in order, every spec once; one more value than `max` allows is
    /// refused before anything is expanded, even for a grid of 10^18.
    #[test]
    fn a_40000_configuration_grid_expands_and_the_limit_refuses_before_expanding() {
        let list = |n: usize, from: usize| {
            (from..from + n)
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let text = format!(
            "[[grid]]\nmethod = \"adaptive\"\ngrowth = [{}]\np_m = [{}]\n",
            list(100, 1),
            list(400, 0)
        );
        let specs = parse_spec(&text, "big.toml").unwrap();
        assert_eq!(specs.len(), 40_000);
        assert_eq!(
            (specs[0].as_str(), specs[1].as_str()),
            ("adaptive:growth=1,p_m=0", "adaptive:growth=1,p_m=1")
        );
        assert_eq!(specs[39_999], "adaptive:growth=100,p_m=399");
        assert_eq!(
            specs.iter().collect::<std::collections::HashSet<_>>().len(),
            40_000
        );
        assert_eq!(
            super::super::plan::check_count(specs.len(), 40_000, "x").ok(),
            Some(())
        );
        let e = super::parse_spec_within(&text, "big.toml", 39_999)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "big.toml: 40000 configurations, more than --max-configs 39999; pass --max-configs 40000 to run them all");
        let huge = format!(
            "[[grid]]\nmethod = \"adaptive\"\n{}",
            (0..6)
                .map(|k| format!("k{k} = [{}]\n", list(1000, 0)))
                .collect::<String>()
        );
        let e = super::parse_spec_within(&huge, "huge.toml", 10_000)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "huge.toml: 1000000000000000000 configurations, more than --max-configs 10000"
            ),
            "{e}"
        );
    }
}
