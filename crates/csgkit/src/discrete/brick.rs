//! Bricks: 8×8 finest columns as one sorted list of `(z, mask)` events.
//!
//! This is the seed's booltree (Burguet & Malgouyres, list of surfels with a boolean quadtree
//! per depth) flattened into a bitmask (§B3.1): bit `c = x + 8·y` of the prefix XOR of the
//! masks up to and including an event at `z` says whether sub-column `c` is inside from `z`
//! up to the next event. A mask is the set of sub-columns whose inside flag flips at `z`:
//! the seed's surfel quadtree `Q` at that depth.
//!
//! **Invariant:** event depths strictly increase, no mask is zero, and the prefix XOR of all
//! masks is zero (every sub-column ends outside). [`Brick::check_invariants`] verifies it.
//!
//! [`Brick::op`] is the seed's list merge (§4.3 of the paper, §B3.3 here) with masks: walk
//! both event lists by depth, update `S1 ^= m1`, `S2 ^= m2`, form `S' = op(S1, S2)` bitwise
//! and emit `(z, S ^ S')` when it is not zero. Cost `O(a + b)` word operations.

use super::column::Column;
use crate::Operation;

/// Number of sub-columns along each side of a brick.
pub const BRICK_SIDE: i32 = 8;

/// Every sub-column.
const ALL: u64 = u64::MAX;

/// 8×8 finest columns as a sorted list of depth events with 64-bit masks.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Brick {
    events: Vec<(i32, u64)>,
}

/// Why a brick breaks its invariant.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BrickError {
    /// Event `index` is not above the event before it.
    #[error("event {index} is not above the event before it")]
    NotIncreasing {
        /// Position of the event.
        index: usize,
    },
    /// Event `index` flips no sub-column.
    #[error("event {index} has an empty mask")]
    EmptyMask {
        /// Position of the event.
        index: usize,
    },
    /// Some sub-columns are still inside after the last event.
    #[error("sub-columns {0:#018x} are still inside after the last event")]
    Unclosed(u64),
}

impl Brick {
    /// Builds a brick from its 64 sub-columns (`columns[x + 8·y]`).
    pub fn from_columns(columns: &[&Column]) -> Self {
        let mut flips: Vec<(i32, u64)> = Vec::new();
        for (c, column) in columns.iter().enumerate() {
            for iv in column.intervals() {
                flips.push((iv.z0, 1 << c));
                flips.push((iv.z1, 1 << c));
            }
        }
        flips.sort_unstable_by_key(|&(z, _)| z);
        Self::from_sorted_flips(flips)
    }

    /// The brick whose 64 sub-columns all equal `column`.
    pub fn uniform(column: &Column) -> Self {
        let mut events = Vec::with_capacity(2 * column.intervals().len());
        for iv in column.intervals() {
            events.push((iv.z0, ALL));
            events.push((iv.z1, ALL));
        }
        Self { events }
    }

    /// Merges flips sorted by depth into events, dropping those that cancel out.
    fn from_sorted_flips(flips: Vec<(i32, u64)>) -> Self {
        let mut events: Vec<(i32, u64)> = Vec::with_capacity(flips.len());
        for (z, mask) in flips {
            match events.last_mut() {
                Some(last) if last.0 == z => last.1 ^= mask,
                _ => {
                    if events.last().is_some_and(|last| last.1 == 0) {
                        events.pop();
                    }
                    events.push((z, mask));
                }
            }
        }
        if events.last().is_some_and(|last| last.1 == 0) {
            events.pop();
        }
        Self { events }
    }

    /// The events `(z, mask)`, by increasing depth.
    pub fn events(&self) -> &[(i32, u64)] {
        &self.events
    }

    /// True when no voxel is inside.
    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }

    /// Sub-column `c` (`x + 8·y`) as a column.
    pub fn column(&self, c: u32) -> Column {
        let mut out = Column::new();
        let mut start = None;
        for &(z, mask) in &self.events {
            if mask >> c & 1 == 1 {
                match start.take() {
                    Some(z0) => out.push_merge(z0, z),
                    None => start = Some(z),
                }
            }
        }
        out
    }

    /// All 64 sub-columns (`x + 8·y`), decoded in one pass over the events.
    pub fn columns(&self) -> Vec<Column> {
        let mut out = vec![Column::new(); 64];
        let mut start = [0i32; 64];
        let mut state = 0u64;
        for &(z, mask) in &self.events {
            let mut bits = mask;
            while bits != 0 {
                let c = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                if state >> c & 1 == 1 {
                    out[c].push_merge(start[c], z);
                } else {
                    start[c] = z;
                }
            }
            state ^= mask;
        }
        out
    }

    /// The common column when every sub-column is the same, else `None`.
    pub fn as_uniform(&self) -> Option<Column> {
        let mut state = 0u64;
        for &(_, mask) in &self.events {
            state ^= mask;
            if state != 0 && state != ALL {
                return None;
            }
        }
        Some(self.column(0))
    }

    /// Whether voxel `z` of sub-column `c` is inside.
    pub fn contains(&self, c: u32, z: i32) -> bool {
        let upto = self.events.partition_point(|e| e.0 <= z);
        let state = self.events[..upto].iter().fold(0, |s, e| s ^ e.1);
        state >> c & 1 == 1
    }

    /// The number of voxels inside.
    pub fn voxel_count(&self) -> u64 {
        let mut state = 0u64;
        let mut count = 0u64;
        for pair in self.events.windows(2) {
            state ^= pair[0].1;
            let height = (i64::from(pair[1].0) - i64::from(pair[0].0)) as u64;
            count += u64::from(state.count_ones()) * height;
        }
        count
    }

    /// `self op other`, by the seed's list merge with masks.
    pub fn op(&self, other: &Self, op: Operation) -> Self {
        let (a, b) = (&self.events, &other.events);
        let (mut ia, mut ib) = (0, 0);
        let (mut s1, mut s2, mut s) = (0u64, 0u64, 0u64);
        let mut events = Vec::with_capacity(a.len() + b.len());
        while ia < a.len() || ib < b.len() {
            let z = match (a.get(ia), b.get(ib)) {
                (Some(x), Some(y)) => x.0.min(y.0),
                (Some(x), None) | (None, Some(x)) => x.0,
                (None, None) => break,
            };
            if a.get(ia).is_some_and(|e| e.0 == z) {
                s1 ^= a[ia].1;
                ia += 1;
            }
            if b.get(ib).is_some_and(|e| e.0 == z) {
                s2 ^= b[ib].1;
                ib += 1;
            }
            let next = op.apply_mask(s1, s2);
            if next != s {
                events.push((z, s ^ next));
                s = next;
            }
        }
        Self { events }
    }

    /// Checks the invariant of the module docs.
    ///
    /// # Errors
    /// The first event that breaks it.
    pub fn check_invariants(&self) -> Result<(), BrickError> {
        let mut state = 0u64;
        for (index, &(z, mask)) in self.events.iter().enumerate() {
            if index > 0 && self.events[index - 1].0 >= z {
                return Err(BrickError::NotIncreasing { index });
            }
            if mask == 0 {
                return Err(BrickError::EmptyMask { index });
            }
            state ^= mask;
        }
        match state {
            0 => Ok(()),
            open => Err(BrickError::Unclosed(open)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::column::Interval;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

    fn col(pairs: &[(i32, i32)]) -> Column {
        Column::from_intervals(pairs.iter().map(|&(z0, z1)| Interval { z0, z1 }).collect())
    }

    fn arb_brick_columns() -> impl Strategy<Value = Vec<Column>> {
        let column = proptest::collection::vec((-8i32..8, 1i32..5), 0..3).prop_map(|v| {
            Column::from_intervals(
                v.into_iter()
                    .map(|(z0, d)| Interval { z0, z1: z0 + d })
                    .collect(),
            )
        });
        proptest::collection::vec(column, 64)
    }

    #[test]
    fn columns_round_trip_and_count() {
        let empty = Column::new();
        let a = col(&[(0, 3), (5, 6)]);
        let b = col(&[(2, 5)]);
        let mut refs = vec![&empty; 64];
        refs[0] = &a;
        refs[9] = &b;
        refs[63] = &a;
        let brick = Brick::from_columns(&refs);
        brick.check_invariants().unwrap();
        assert_eq!(brick.column(0), a);
        assert_eq!(brick.column(9), b);
        assert_eq!(brick.column(1), empty);
        let all = brick.columns();
        assert_eq!(all.len(), 64);
        assert!((0..64).all(|c| all[c as usize] == brick.column(c)));
        assert_eq!(brick.voxel_count(), 4 + 3 + 4);
        assert!(brick.contains(9, 4) && !brick.contains(9, 5) && brick.contains(63, 5));
        // a at z=3 ends and b at z=2 starts, so depths 0, 2, 3, 5, 6 carry events.
        assert_eq!(brick.events().len(), 5);
        assert_eq!(brick.as_uniform(), None);
    }

    #[test]
    fn uniform_bricks_are_recognised() {
        let a = col(&[(0, 8), (16, 24)]);
        let brick = Brick::uniform(&a);
        brick.check_invariants().unwrap();
        assert_eq!(brick.as_uniform(), Some(a.clone()));
        assert_eq!(Brick::from_columns(&[&a; 64]), brick);
        assert_eq!(brick.voxel_count(), 64 * 16);
    }

    #[test]
    fn invariant_violations_are_named() {
        let b = Brick {
            events: vec![(0, 1), (0, 1)],
        };
        assert_eq!(
            b.check_invariants(),
            Err(BrickError::NotIncreasing { index: 1 })
        );
        let b = Brick {
            events: vec![(0, 3), (2, 1)],
        };
        assert_eq!(b.check_invariants(), Err(BrickError::Unclosed(2)));
        let b = Brick {
            events: vec![(0, 0)],
        };
        assert_eq!(
            b.check_invariants(),
            Err(BrickError::EmptyMask { index: 0 })
        );
    }

    #[test]
    fn brick_ops_match_column_ops() {
        let mut runner = TestRunner::new_with_rng(
            Config::with_cases(60),
            TestRng::from_seed(RngAlgorithm::ChaCha, &[11; 32]),
        );
        let ops = Operation::ALL;
        runner
            .run(&(arb_brick_columns(), arb_brick_columns()), |(ca, cb)| {
                let a = Brick::from_columns(&ca.iter().collect::<Vec<_>>());
                let b = Brick::from_columns(&cb.iter().collect::<Vec<_>>());
                prop_assert!(a.check_invariants().is_ok());
                for op in ops {
                    let r = a.op(&b, op);
                    prop_assert!(r.check_invariants().is_ok());
                    for c in 0..64 {
                        prop_assert_eq!(r.column(c), ca[c as usize].op(&cb[c as usize], op));
                    }
                }
                Ok(())
            })
            .unwrap();
    }
}
