//! Closed axis-aligned boxes.

/// A closed axis-aligned box `[min, max]`.
///
/// **Invariant:** `min[k] <= max[k]` on every axis for boxes built by [`Aabb::from_points`];
/// [`Aabb::EMPTY`] is the one exception (min = +∞, max = −∞), the identity of
/// [`Aabb::union`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest coordinate on each axis.
    pub min: [f64; 3],
    /// Largest coordinate on each axis.
    pub max: [f64; 3],
}

impl Aabb {
    /// The empty box: it overlaps nothing and is the identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    /// The smallest box holding every point (the empty box for no points).
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a [f64; 3]>) -> Aabb {
        points
            .into_iter()
            .fold(Aabb::EMPTY, |b, p| b.union_point(p))
    }

    /// The smallest box holding `self` and `p`.
    pub fn union_point(self, p: &[f64; 3]) -> Aabb {
        Aabb {
            min: std::array::from_fn(|k| self.min[k].min(p[k])),
            max: std::array::from_fn(|k| self.max[k].max(p[k])),
        }
    }

    /// The smallest box holding both boxes.
    pub fn union(self, other: &Aabb) -> Aabb {
        Aabb {
            min: std::array::from_fn(|k| self.min[k].min(other.min[k])),
            max: std::array::from_fn(|k| self.max[k].max(other.max[k])),
        }
    }

    /// The common part of both boxes (empty on some axis when they do not overlap).
    pub fn intersection(self, other: &Aabb) -> Aabb {
        Aabb {
            min: std::array::from_fn(|k| self.min[k].max(other.min[k])),
            max: std::array::from_fn(|k| self.max[k].min(other.max[k])),
        }
    }

    /// True when the closed boxes share a point; touching counts.
    ///
    /// Exact: only comparisons of stored coordinates. The six comparisons are combined with
    /// `&`, not `&&`: the outcome of a query's box test is unpredictable, and one branch
    /// mispredicted costs more than the comparisons a short circuit would skip.
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        (self.min[0] <= other.max[0])
            & (other.min[0] <= self.max[0])
            & (self.min[1] <= other.max[1])
            & (other.min[1] <= self.max[1])
            & (self.min[2] <= other.max[2])
            & (other.min[2] <= self.max[2])
    }

    /// True when the box holds no point.
    pub fn is_empty(&self) -> bool {
        (0..3).any(|k| self.min[k] > self.max[k])
    }

    /// The centre, used only to order boxes (never for a decision).
    pub fn centre(&self) -> [f64; 3] {
        std::array::from_fn(|k| 0.5 * self.min[k] + 0.5 * self.max[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_boxes_overlap() {
        let a = Aabb::from_points(&[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]);
        let b = Aabb::from_points(&[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]);
        let c = Aabb::from_points(&[[1.5, 0.0, 0.0], [2.0, 1.0, 1.0]]);
        assert!(a.overlaps(&b));
        assert!(!a.overlaps(&c));
        assert!(a.intersection(&c).is_empty());
    }

    #[test]
    fn empty_box_is_union_identity_and_overlaps_nothing() {
        let a = Aabb::from_points(&[[0.0, -1.0, 2.0]]);
        assert_eq!(Aabb::EMPTY.union(&a), a);
        assert!(!Aabb::EMPTY.overlaps(&a));
        assert!(Aabb::from_points(std::iter::empty()).is_empty());
    }
}
