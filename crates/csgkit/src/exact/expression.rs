//! The formula a boolean evaluates: which points it keeps, as a tree of [`Operation`]s over
//! the operands. The select and winding stages evaluate it on the inside flags of every
//! patch; the driver and the CSG layer build it.

use crate::Operation;

/// Which points a boolean keeps, as a formula over which operands contain them: one
/// [`Operation`] on all operands, or a tree of operations (a CSG tree) whose leaves are the
/// operands. The select stage evaluates it on the inside flags of every patch, so a whole
/// tree is computed in one arrangement and rounded once.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Expression {
    /// The points of operand `k`.
    Operand(usize),
    /// The operation on the children's point sets (a difference: the first minus the others).
    Apply(Operation, Vec<Expression>),
}

impl Expression {
    /// `op` on operands `0..count`.
    pub fn of(op: Operation, count: usize) -> Expression {
        Expression::Apply(op, (0..count).map(Expression::Operand).collect())
    }

    /// Whether a point with the given inside flags (one per operand) is in the result.
    ///
    /// # Panics
    /// If an operand index is out of range of `inside`.
    pub fn contains(&self, inside: &[bool]) -> bool {
        match self {
            Expression::Operand(k) => inside[*k],
            Expression::Apply(op, children) => {
                op.contains(children.iter().map(|c| c.contains(inside)))
            }
        }
    }

    /// The highest operand index plus one (0 for an expression without operands).
    pub fn operand_count(&self) -> usize {
        match self {
            Expression::Operand(k) => k + 1,
            Expression::Apply(_, children) => children
                .iter()
                .map(Expression::operand_count)
                .max()
                .unwrap_or(0),
        }
    }
}
