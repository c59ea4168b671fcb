//! Columns: sorted, disjoint, normalised lists of finest-voxel intervals, and their booleans.
//!
//! A [`Column`] is the inside set of one vertical line of voxels (§B3.1): half-open intervals
//! `[z0, z1)` of finest voxel indices. **Invariant:** every interval is non-empty, intervals
//! are sorted, and consecutive intervals neither overlap nor touch (`z1 < next.z0`), so equal
//! voxel sets have equal columns. [`Column::check_invariants`] verifies it.
//!
//! [`Column::op`] is the column boolean of §B3.3: one merge walk over both endpoint lists
//! evaluating the operation on the two inside flags, `O(a + b)`. All values are integers, so
//! the result is exact.

use smallvec::SmallVec;

use crate::Operation;

/// A half-open range `[z0, z1)` of finest voxel indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Interval {
    /// First voxel inside.
    pub z0: i32,
    /// First voxel above the interval.
    pub z1: i32,
}

/// Why a column breaks its invariant.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ColumnError {
    /// An interval with `z1 <= z0`.
    #[error("interval {index} is empty ({z0}..{z1})")]
    Empty {
        /// Position of the interval in the column.
        index: usize,
        /// Its lower end.
        z0: i32,
        /// Its upper end.
        z1: i32,
    },
    /// Interval `index` overlaps or touches the one before it.
    #[error("interval {index} overlaps or touches the one before it")]
    NotSeparated {
        /// Position of the interval in the column.
        index: usize,
    },
}

/// The inside set of one column: sorted, disjoint, non-touching, non-empty intervals.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Column {
    intervals: SmallVec<[Interval; 2]>,
}

impl Column {
    /// The empty column.
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds a column from intervals in any order, merging overlapping and touching ones and
    /// dropping empty ones.
    pub fn from_intervals(mut intervals: Vec<Interval>) -> Self {
        intervals.retain(|iv| iv.z1 > iv.z0);
        intervals.sort_unstable();
        let mut out = Self::new();
        for iv in intervals {
            out.push_merge(iv.z0, iv.z1);
        }
        out
    }

    /// Appends `[z0, z1)` where `z0` is not below the start of the last interval, merging it
    /// with the last interval if they overlap or touch; empty ranges are ignored.
    pub(crate) fn push_merge(&mut self, z0: i32, z1: i32) {
        if z1 <= z0 {
            return;
        }
        match self.intervals.last_mut() {
            Some(last) if z0 <= last.z1 => last.z1 = last.z1.max(z1),
            _ => self.intervals.push(Interval { z0, z1 }),
        }
    }

    /// The intervals, sorted.
    pub fn intervals(&self) -> &[Interval] {
        &self.intervals
    }

    /// True when no voxel is inside.
    pub fn is_empty(&self) -> bool {
        self.intervals.is_empty()
    }

    /// The number of voxels inside.
    pub fn len(&self) -> u64 {
        self.intervals
            .iter()
            .map(|iv| (i64::from(iv.z1) - i64::from(iv.z0)) as u64)
            .sum()
    }

    /// Whether voxel `z` is inside.
    pub fn contains(&self, z: i32) -> bool {
        let i = self.intervals.partition_point(|iv| iv.z1 <= z);
        self.intervals.get(i).is_some_and(|iv| iv.z0 <= z)
    }

    /// Whether every endpoint is a multiple of `2^level`.
    pub fn is_aligned(&self, level: u8) -> bool {
        let mask = (1i32 << level) - 1;
        self.intervals
            .iter()
            .all(|iv| iv.z0 & mask == 0 && iv.z1 & mask == 0)
    }

    /// Checks the invariant of the module docs.
    ///
    /// # Errors
    /// The first interval that is empty or not separated from its predecessor.
    pub fn check_invariants(&self) -> Result<(), ColumnError> {
        for (index, iv) in self.intervals.iter().enumerate() {
            if iv.z1 <= iv.z0 {
                return Err(ColumnError::Empty {
                    index,
                    z0: iv.z0,
                    z1: iv.z1,
                });
            }
            if index > 0 && self.intervals[index - 1].z1 >= iv.z0 {
                return Err(ColumnError::NotSeparated { index });
            }
        }
        Ok(())
    }

    /// `self op other`, by one merge walk over both endpoint lists.
    pub fn op(&self, other: &Self, op: Operation) -> Self {
        let (a, b) = (self.intervals(), other.intervals());
        let (mut ia, mut ib) = (0, 0);
        let (mut in_a, mut in_b, mut state) = (false, false, false);
        let mut out = Self::new();
        let mut start = 0;
        loop {
            let za = endpoint(a, ia);
            let zb = endpoint(b, ib);
            let z = match (za, zb) {
                (None, None) => break,
                (Some(x), None) | (None, Some(x)) => x,
                (Some(x), Some(y)) => x.min(y),
            };
            if za == Some(z) {
                in_a = !in_a;
                ia += 1;
            }
            if zb == Some(z) {
                in_b = !in_b;
                ib += 1;
            }
            let next = op.apply(in_a, in_b);
            if next && !state {
                start = z;
            } else if !next && state {
                out.push_merge(start, z);
            }
            state = next;
        }
        out
    }
}

/// The `i`-th endpoint of a sorted interval list (`z0, z1, z0, z1, …`).
fn endpoint(list: &[Interval], i: usize) -> Option<i32> {
    list.get(i / 2)
        .map(|iv| if i % 2 == 0 { iv.z0 } else { iv.z1 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

    fn col(pairs: &[(i32, i32)]) -> Column {
        Column::from_intervals(pairs.iter().map(|&(z0, z1)| Interval { z0, z1 }).collect())
    }

    #[test]
    fn from_intervals_normalises() {
        let c = col(&[(5, 7), (0, 2), (2, 3), (6, 9), (4, 4)]);
        assert_eq!(c, col(&[(0, 3), (5, 9)]));
        assert_eq!(c.intervals().len(), 2);
        assert_eq!(c.len(), 7);
        assert!(c.contains(2) && !c.contains(3) && c.contains(8) && !c.contains(9));
        c.check_invariants().unwrap();
    }

    #[test]
    fn invariant_violations_are_named() {
        let mut c = Column::new();
        c.intervals.push(Interval { z0: 0, z1: 2 });
        c.intervals.push(Interval { z0: 2, z1: 4 });
        assert_eq!(
            c.check_invariants(),
            Err(ColumnError::NotSeparated { index: 1 })
        );
        c.intervals[1] = Interval { z0: 5, z1: 5 };
        assert!(matches!(
            c.check_invariants(),
            Err(ColumnError::Empty { index: 1, .. })
        ));
    }

    #[test]
    fn ops_on_a_small_example() {
        let a = col(&[(0, 4), (6, 8)]);
        let b = col(&[(2, 6)]);
        assert_eq!(a.op(&b, Operation::Union), col(&[(0, 8)]));
        assert_eq!(a.op(&b, Operation::Intersection), col(&[(2, 4)]));
        assert_eq!(a.op(&b, Operation::Difference), col(&[(0, 2), (6, 8)]));
        assert_eq!(a.op(&b, Operation::Xor), col(&[(0, 2), (4, 8)]));
        assert!(col(&[(0, 8)]).is_aligned(3) && !a.is_aligned(3));
    }

    fn arb_column() -> impl Strategy<Value = Column> {
        proptest::collection::vec((-20i32..20, 0i32..6), 0..6).prop_map(|v| {
            Column::from_intervals(
                v.into_iter()
                    .map(|(z0, d)| Interval { z0, z1: z0 + d })
                    .collect(),
            )
        })
    }

    #[test]
    fn ops_match_voxelwise_flags() {
        let mut runner = TestRunner::new_with_rng(
            Config::with_cases(300),
            TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
        );
        let ops = Operation::ALL;
        runner
            .run(&(arb_column(), arb_column()), |(a, b)| {
                for op in ops {
                    let r = a.op(&b, op);
                    prop_assert!(r.check_invariants().is_ok());
                    for z in -25..30 {
                        prop_assert_eq!(r.contains(z), op.apply(a.contains(z), b.contains(z)));
                    }
                }
                Ok(())
            })
            .unwrap();
    }
}
