//! The boolean operations, one enum for every engine.
//!
//! An operation is a rule on which operands contain a point, so every engine evaluates it on
//! its own representation of "contains": the exact engine on the inside flags of each
//! surface patch, on both sides of it ([`exact::Expression`](crate::exact::Expression)), the
//! discrete engine on the voxel flags of two depth lists, 64 at a time
//! ([`Solid::op`](crate::discrete::Solid::op)), and the orthogonal engine computes unions.

/// A boolean operation on solids, on any number of operands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Operation {
    /// Points in any operand.
    Union,
    /// Points in every operand.
    Intersection,
    /// Points in the first operand and in none of the others.
    Difference,
    /// Points in an odd number of operands: the symmetric difference (A ⊕ B for two, the
    /// points in exactly one of them).
    Xor,
}

impl Operation {
    /// Every operation, in declaration order.
    pub const ALL: [Operation; 4] = [
        Operation::Union,
        Operation::Intersection,
        Operation::Difference,
        Operation::Xor,
    ];

    /// Whether a point with the given inside flags (one per operand) is in the result. No
    /// operand gives the empty set.
    pub fn contains(self, inside: impl ExactSizeIterator<Item = bool>) -> bool {
        let mut inside = inside;
        match self {
            Operation::Union => inside.any(|x| x),
            Operation::Intersection => inside.len() > 0 && inside.all(|x| x),
            Operation::Difference => inside.next() == Some(true) && !inside.any(|x| x),
            Operation::Xor => inside.filter(|&x| x).count() % 2 == 1,
        }
    }

    /// The operation on two operands, for 64 pairs of inside flags at once (bit `i` of `a`
    /// and of `b`).
    #[inline]
    pub fn apply_mask(self, a: u64, b: u64) -> u64 {
        match self {
            Operation::Union => a | b,
            Operation::Intersection => a & b,
            Operation::Difference => a & !b,
            Operation::Xor => a ^ b,
        }
    }

    /// The operation on one pair of inside flags.
    #[inline]
    pub fn apply(self, a: bool, b: bool) -> bool {
        self.apply_mask(u64::from(a), u64::from(b)) & 1 == 1
    }

    /// The lowercase name of the operation, as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Operation::Union => "union",
            Operation::Intersection => "intersection",
            Operation::Difference => "difference",
            Operation::Xor => "xor",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The n-ary rule folds the binary one from the left, for every operation and every
    /// inside pattern of up to four operands (the difference: the first minus the union of
    /// the others, which is the left fold of binary differences).
    #[test]
    fn n_ary_rule_is_the_left_fold_of_the_binary_one() {
        for op in Operation::ALL {
            for n in 1..=4 {
                for bits in 0u32..1 << n {
                    let flags: Vec<bool> = (0..n).map(|i| bits >> i & 1 == 1).collect();
                    let fold = flags[1..].iter().fold(flags[0], |acc, &x| op.apply(acc, x));
                    assert_eq!(op.contains(flags.iter().copied()), fold, "{op:?} {flags:?}");
                }
            }
            assert!(!op.contains(std::iter::empty()), "{op:?} of no operand");
        }
    }
}
