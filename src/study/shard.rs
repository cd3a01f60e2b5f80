//! Shards: a deterministic slice of a study's run list, so a study can spread over machines
//! (`--shard i/n`, then `adaptcloth merge`).

use super::StudyError;
use serde::{Deserialize, Serialize};

/// A slice `index/count` of a list (1-based index): item `j` belongs to shard `j % count + 1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 1-based shard number.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl std::str::FromStr for Shard {
    type Err = StudyError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || StudyError::Config(format!("--shard {s}: expected i/n with 1 <= i <= n"));
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if index == 0 || count == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// Whether item `j` (0-based position in the full list) belongs to this shard.
    pub fn contains(&self, j: usize) -> bool {
        j % self.count + 1 == self.index
    }

    /// The items of this shard, in list order.
    pub fn slice<T: Clone>(&self, items: &[T]) -> Vec<T> {
        items
            .iter()
            .enumerate()
            .filter(|(j, _)| self.contains(*j))
            .map(|(_, x)| x.clone())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_slicing_covers_every_configuration_once() {
        let items: Vec<usize> = (0..11).collect();
        for n in 1..=5 {
            let mut seen = vec![0; items.len()];
            for i in 1..=n {
                let shard: Shard = format!("{i}/{n}").parse().unwrap();
                let slice = shard.slice(&items);
                // Deterministic: the same slice twice.
                assert_eq!(slice, shard.slice(&items));
                for x in slice {
                    seen[x] += 1;
                }
            }
            assert!(seen.iter().all(|&k| k == 1), "n = {n}: {seen:?}");
        }
        for bad in ["0/3", "4/3", "1/0", "x/2", "3", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
