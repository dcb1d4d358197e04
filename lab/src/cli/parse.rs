//! The command line as clap reads it, with two changes so that a bad number names its flag and
//! its value in one line, like every other bad input:
//! - A value that starts with `-` is the value of the flag before it when it reads as a number
//!   (`--max-configs -1`), or for a flag that takes a comma list (`--point -0.5,0.5`). Without
//!   this clap takes `-1` for a short flag and says only "unexpected argument '-1' found".
//! - A value that the flag's parser refuses ends the run with `error: --max-mesh-mib: -1 is not
//!   in 1..=1099511627776` and exit status 1, not clap's usage block and status 2.

use anyhow::{anyhow, Result};
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{Arg, Command};

/// The parsed command line; `--help`, `--version` and unknown flags are clap's own.
pub fn parse<T: clap::Parser>() -> Result<T> {
    let matches = negatives_are_values(T::command())
        .try_get_matches()
        .map_err(|e| one_line(e).unwrap_or_else(|e| e.exit()))?;
    T::from_arg_matches(&matches).map_err(|e| one_line(e).unwrap_or_else(|e| e.exit()))
}

/// Every flag of `cmd` and its subcommands that takes a value accepts a negative number as one;
/// a flag whose value is a comma list accepts any value that starts with `-`.
pub fn negatives_are_values(cmd: Command) -> Command {
    cmd.mut_args(|a: Arg| {
        if !a.get_action().takes_values() || a.is_positional() {
            return a;
        }
        let list = a.get_value_delimiter().is_some()
            || a.get_value_names()
                .is_some_and(|n| n.iter().any(|n| n.contains(',')));
        // Only ever turned on: a flag may have asked for it itself (`--shard -1/2`).
        let a = a.allow_negative_numbers(true);
        if list {
            a.allow_hyphen_values(true)
        } else {
            a
        }
    })
    .mut_subcommands(negatives_are_values)
}

/// A value its parser refused, as one line naming the flag and the value; any other clap error
/// is handed back for clap to print.
fn one_line(e: clap::Error) -> std::result::Result<anyhow::Error, clap::Error> {
    if e.kind() != ErrorKind::ValueValidation {
        return Err(e);
    }
    let text = |kind| match e.get(kind) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        _ => None,
    };
    let (Some(arg), Some(value)) = (
        text(ContextKind::InvalidArg),
        text(ContextKind::InvalidValue),
    ) else {
        return Err(e);
    };
    // `--max-configs <N>` → `--max-configs`.
    let flag = arg.split_whitespace().next().unwrap_or(&arg).to_string();
    let source = std::error::Error::source(&e);
    let reason = match source.and_then(|s| s.downcast_ref::<std::num::ParseIntError>()) {
        Some(_) if value.trim_start().starts_with('-') => "must not be negative".to_string(),
        Some(p) if *p.kind() == std::num::IntErrorKind::PosOverflow => "is too large".to_string(),
        Some(_) => "is not a whole number".to_string(),
        None => source.map_or_else(|| e.kind().to_string(), |s| s.to_string()),
    };
    Ok(if reason.contains(&value) {
        anyhow!("{flag}: {reason}")
    } else {
        anyhow!("{flag} `{value}`: {reason}")
    })
}
