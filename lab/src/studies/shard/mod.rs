//! Sweeps beyond one process (docs/sharding.md): `--shard i/N` picks a deterministic share of
//! the grid balanced by estimated cost, `merge` joins the shards' outputs, `--jobs K` runs the
//! shards as local processes.

pub mod command;
pub mod merge;

use crate::{Error, Result};

/// Shard `index` of `count`, numbered from 0 (Slurm's `--array=0-(N-1)` task ids).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl Shard {
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// `i/N` with `0 <= i < N`, `1 <= N <= 10000`.
    pub fn parse(text: &str) -> Result<Shard> {
        let bad = |why: &str| Error::param(format!("--shard `{text}`: {why}"));
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| bad("expected INDEX/COUNT, e.g. 0/4"))?;
        // Any run of digits is a whole number: one too large for u32 gets the range message.
        let whole = |t: &str| {
            (!t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()))
                .then(|| t.parse::<u128>().unwrap_or(u128::MAX))
        };
        let index =
            whole(i.trim()).ok_or_else(|| bad("the index is not a non-negative integer"))?;
        let count = whole(n.trim()).ok_or_else(|| bad("the count is not a positive integer"))?;
        if count == 0 || count > 10_000 {
            return Err(bad("the count must be in 1..=10000"));
        }
        if index >= count {
            return Err(bad(&format!(
                "the index must be below the count (shards are numbered 0..{})",
                count - 1
            )));
        }
        Ok(Shard {
            index: index as u32,
            count: count as u32,
        })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Which configurations (indices into `costs`) each of `count` shards runs: longest first onto
/// the least-loaded shard (ties: the lower index), each shard's list in grid order. The same
/// costs always give the same split.
pub fn assign(costs: &[f64], count: u32) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]).then(a.cmp(&b)));
    let mut loads = vec![0.0f64; count as usize];
    let mut shards = vec![Vec::new(); count as usize];
    for i in order {
        let (s, _) = loads
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1).then(a.0.cmp(&b.0)))
            .expect("count >= 1");
        loads[s] += costs[i];
        shards[s].push(i);
    }
    for s in &mut shards {
        s.sort_unstable();
    }
    shards
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_text() {
        assert_eq!(Shard::parse("2/4").unwrap(), Shard { index: 2, count: 4 });
        assert_eq!(Shard::parse("0/1").unwrap().to_string(), "0/1");
        for (bad, why) in [
            (
                "4/4",
                "the index must be below the count (shards are numbered 0..3)",
            ),
            ("1", "expected INDEX/COUNT"),
            ("-1/4", "the index is not"),
            ("0/0", "the count must be in"),
            ("a/b", "the index is not"),
            (
                "99999999999/4",
                "the index must be below the count (shards are numbered 0..3)",
            ),
            (
                "0/99999999999999999999999999999999999999999",
                "the count must be in 1..=10000",
            ),
        ] {
            let e = Shard::parse(bad).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--shard `{bad}`: {why}")), "{e}");
        }
    }

    #[test]
    fn balanced_by_cost_not_count() {
        // One expensive configuration and six cheap ones: the expensive one gets a shard of its own.
        let costs = [100.0, 10.0, 10.0, 10.0, 10.0, 10.0, 10.0];
        let s = assign(&costs, 2);
        assert_eq!(s, vec![vec![0], vec![1, 2, 3, 4, 5, 6]]);
        // Every configuration exactly once, whatever the count.
        for n in 1..=9 {
            let mut all: Vec<usize> = assign(&costs, n).concat();
            all.sort_unstable();
            assert_eq!(all, (0..costs.len()).collect::<Vec<_>>());
        }
        // Loads within the largest single cost of each other.
        let costs: Vec<f64> = (1..=24).map(|i| f64::from(i * i)).collect();
        let loads: Vec<f64> = assign(&costs, 4)
            .iter()
            .map(|s| s.iter().map(|&i| costs[i]).sum())
            .collect();
        let (lo, hi) = (
            loads.iter().copied().fold(f64::MAX, f64::min),
            loads.iter().copied().fold(0.0, f64::max),
        );
        assert!(hi - lo <= 576.0 && hi / lo < 1.05, "{loads:?}");
    }
}
