//! `--methods hard,regular:n=5,adaptive:p_m=0,scope=local`: a comma both separates methods and
//! a method's parameters, so a piece with `=` but no `:` continues the method before it.

use crate::methods::Method;
use crate::{Error, Result};

/// Splits one or more `--methods` values into method specs (unparsed).
pub fn split_specs(values: &[String]) -> Result<Vec<String>> {
    let mut specs: Vec<String> = Vec::new();
    for value in values {
        let mut in_value = false;
        for piece in value.split(',').map(str::trim) {
            if piece.is_empty() {
                return Err(Error::param(format!("--methods `{value}`: empty entry")));
            }
            let continues = piece.contains('=') && !piece.contains(':');
            match specs.last_mut() {
                Some(last) if continues && in_value && last.contains(':') => {
                    last.push(',');
                    last.push_str(piece);
                }
                _ if continues => {
                    return Err(Error::param(format!(
                        "--methods `{value}`: `{piece}` is a parameter with no method before it (write `adaptive:{piece}`)"
                    )))
                }
                _ => specs.push(piece.to_string()),
            }
            in_value = true;
        }
    }
    if specs.is_empty() {
        return Err(Error::param("--methods: no method given".into()));
    }
    Ok(specs)
}

/// Parses every spec; the same label twice is an error (its rows and pictures would collide).
/// Linear in the count: a sweep may list tens of thousands.
pub fn parse_methods(specs: &[String]) -> Result<Vec<Method>> {
    let mut methods: Vec<Method> = Vec::with_capacity(specs.len());
    let mut labels: std::collections::HashSet<String> =
        std::collections::HashSet::with_capacity(specs.len());
    for spec in specs {
        let m = Method::parse(spec, &[])?;
        let label = m.label();
        if labels.contains(&label) {
            return Err(Error::param(format!(
                "method `{spec}` is listed twice (both are `{label}`)"
            )));
        }
        labels.insert(label);
        methods.push(m);
    }
    Ok(methods)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(v: &str) -> Vec<String> {
        split_specs(&[v.to_string()]).unwrap()
    }

    #[test]
    fn commas_split_methods_and_parameters() {
        assert_eq!(
            split("hard,regular:n=5,regular:n=17,adaptive:p_m=0,adaptive:scope=local"),
            [
                "hard",
                "regular:n=5",
                "regular:n=17",
                "adaptive:p_m=0",
                "adaptive:scope=local"
            ]
        );
        assert_eq!(
            split("adaptive:p_m=10,scope=local,hard"),
            ["adaptive:p_m=10,scope=local", "hard"]
        );
        assert_eq!(
            split_specs(&["hard".into(), "adaptive".into()]).unwrap(),
            ["hard", "adaptive"]
        );
    }

    #[test]
    fn the_main_job_runs_the_defaults_then_what_the_tool_recommends() {
        let main = split(crate::studies::compare::MAIN_JOB_METHODS);
        let defaults = split(crate::studies::compare::DEFAULT_METHODS);
        assert_eq!(main[..defaults.len()], defaults[..]);
        assert_eq!(
            main[defaults.len()..],
            ["auto:target=0.02", "regions:target=0.02"]
        );
        let methods = parse_methods(&main).unwrap();
        assert_eq!(
            methods
                .iter()
                .map(|m| m.name())
                .filter(|n| *n == "auto" || *n == "regions")
                .count(),
            2
        );
    }

    #[test]
    fn bad_lists_are_errors() {
        assert!(split_specs(&["p_m=0".into()]).is_err());
        assert!(split_specs(&["hard,,adaptive".into()]).is_err());
        assert!(split_specs(&["hard,p_m=1".into()]).is_err());
        assert!(split_specs(&[]).is_err());
        assert!(parse_methods(&["hard".into(), "hard".into()]).is_err());
        assert!(parse_methods(&["adaptive".into(), "adaptive:p_m=0".into()]).is_err());
        assert!(parse_methods(&["phong".into()]).is_err());
    }
}
