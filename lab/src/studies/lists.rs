//! The one check every list flag makes (`--n`, `--sizes`, `--hybrid`, `--budget`, `--settings`,
//! `--scenes`, `--map-sizes`, …): a value given twice would be measured twice, and its rows,
//! pictures and chart points would collide.

use crate::{Error, Result};

/// Refuses the first value whose key an earlier value already had: ``--n `3`: listed twice``, or
/// ``--hybrid `2048/02`: listed twice (as `2048/2`)`` when the spellings differ. `key` is the
/// parsed value, so two spellings of one setting count as the same.
pub fn listed_once<K: PartialEq>(
    flag: &str,
    values: impl IntoIterator<Item = (impl AsRef<str>, K)>,
) -> Result<()> {
    let mut seen: Vec<(String, K)> = Vec::new();
    for (text, key) in values {
        let text = text.as_ref().trim();
        if let Some((first, _)) = seen.iter().find(|(_, k)| *k == key) {
            let as_first = if first == text {
                String::new()
            } else {
                format!(" (as `{first}`)")
            };
            return Err(Error::param(format!(
                "{flag} `{text}`: listed twice{as_first}"
            )));
        }
        seen.push((text.to_string(), key));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn second_spelling_is_named() {
        assert!(listed_once("--n", [("2", 2), ("3", 3)]).is_ok());
        assert_eq!(
            listed_once("--n", [("3", 3), ("2", 2), ("3", 3)])
                .unwrap_err()
                .to_string(),
            "--n `3`: listed twice"
        );
        assert_eq!(
            listed_once("--sizes", [("512", 512), (" 0512", 512)])
                .unwrap_err()
                .to_string(),
            "--sizes `0512`: listed twice (as `512`)"
        );
    }
}
