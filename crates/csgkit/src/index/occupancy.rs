//! A coarse uniform grid of the cells some boxes overlap: a filter that finds, before any tree
//! is built, the few boxes of one set that can overlap a box of another.
//!
//! Two surfaces whose bounding boxes overlap over most of their extent (two offset spheres)
//! meet along a curve, and only the triangles near that curve can form a candidate pair. A
//! tree over everything in the overlap of the operand boxes indexes both whole surfaces
//! there (750 k triangles of each 1 M-triangle sphere); the grid, marked by one operand and
//! read by the other, keeps only the triangles in cells both occupy.
//!
//! # Why it never drops an overlapping pair
//! A box covers the cells `cell(min) ..= cell(max)` on each axis, with
//! `cell(x) = ⌊(x − frame.min) · side / extent⌋` clamped to the grid, evaluated in f64. Each
//! step (a subtraction, a product by a positive constant, truncation, clamping) is monotone
//! in `x`, so the evaluated `cell` is too, though not exact. Two closed boxes that overlap
//! share the point `p` whose coordinates are the larger of their minima (f64 values), and
//! by monotonicity each box's cell range contains `cell(p)` on every axis (wherever `p` is:
//! clamping is monotone too): the cell of `p` is marked by one box and covered by the other.

use crate::par::*;

use std::ops::RangeInclusive;

use super::Aabb;

/// The largest grid side: 128³ cells (a 256 KB bitset), cell indices of 7 bits per axis.
const MAX_SIDE: usize = 128;

/// Boxes marked per parallel task (each task fills a bitset of its own).
const MARK_CHUNK: usize = 1 << 16;

/// The most boxes [`Occupancy::size_samples`] picks: a few thousand set a cell size as well
/// as all of them.
const SIZE_SAMPLES: usize = 2048;

/// The cells of a uniform grid over a frame that a set of boxes overlaps.
#[derive(Clone, Debug)]
pub struct Occupancy {
    frame_min: [f64; 3],
    /// Cells per unit length on each axis (zero on an axis where the frame is flat).
    scale: [f64; 3],
    side: usize,
    /// Bit `x + side (y + side z)` is set when a marked box overlaps cell `(x, y, z)`.
    bits: Vec<u64>,
}

/// The cells a box covers, packed in 42 bits: the first cell on each axis and the number of
/// cells after it on that axis, 7 bits each. Eight bytes per box, so that a second pass over
/// a million boxes reads these rather than recomputing every box from its triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellSpan(u64);

impl CellSpan {
    /// The span of a box outside the frame: no cell.
    pub const NONE: CellSpan = CellSpan(u64::MAX);

    fn new(first: [usize; 3], last: [usize; 3]) -> CellSpan {
        let field =
            |k: usize| (first[k] as u64) << (7 * k) | ((last[k] - first[k]) as u64) << (21 + 7 * k);
        CellSpan(field(0) | field(1) | field(2))
    }

    /// The first and last cell on each axis.
    fn bounds(self) -> [(usize, usize); 3] {
        let bits = |shift: usize| (self.0 >> shift & 0x7f) as usize;
        std::array::from_fn(|k| (bits(7 * k), bits(7 * k) + bits(21 + 7 * k)))
    }
}

impl Occupancy {
    /// The grid side over `frame` at which a cell is about as large as the mean of the
    /// `samples` boxes that overlap the frame (their longest sides, against the frame's
    /// longest), at most [`MAX_SIDE`]: each box then covers a few cells, so marking and
    /// reading cost a few bit operations per box, and a cell is still small enough to keep
    /// only the boxes near another set's. Finer cells gain nothing (a box near the other set
    /// is kept however fine the grid) and cost a cube of their ratio: two 1 k-triangle spheres
    /// on a √n-cell grid covered about a hundred cells per triangle.
    pub fn side_for(frame: &Aabb, samples: impl Iterator<Item = Aabb>) -> usize {
        let longest = |b: &Aabb| (0..3).map(|k| b.max[k] - b.min[k]).fold(0.0, f64::max);
        let (total, count) = (samples.filter(|b| b.overlaps(frame)))
            .fold((0.0, 0usize), |(total, count), b| {
                (total + longest(&b), count + 1)
            });
        if count == 0 {
            return 1;
        }
        let cells = longest(frame) / (total / count as f64);
        // NaN (a frame or boxes of no size) and infinity clamp like any other value.
        if cells.is_nan() {
            MAX_SIDE
        } else {
            cells.ceil().clamp(1.0, MAX_SIDE as f64) as usize
        }
    }

    /// Indices `0..len` spread evenly, at most [`SIZE_SAMPLES`] of them: which of a set's
    /// boxes to give [`Occupancy::side_for`].
    pub fn size_samples(len: usize) -> impl Iterator<Item = usize> {
        (0..len).step_by(len.div_ceil(SIZE_SAMPLES).max(1))
    }

    /// The cells of a `side`³ grid over `frame` (`side` at most [`MAX_SIDE`]) that the boxes
    /// `box_of(0) .. box_of(len - 1)` overlapping `frame` overlap, and the cells of each box
    /// ([`CellSpan::NONE`] for those outside the frame).
    pub fn of(
        frame: &Aabb,
        side: usize,
        len: usize,
        box_of: impl Fn(usize) -> Aabb + Sync,
    ) -> (Occupancy, Vec<CellSpan>) {
        let side = side.clamp(1, MAX_SIDE);
        let scale = std::array::from_fn(|k| {
            let extent = frame.max[k] - frame.min[k];
            if extent > 0.0 {
                side as f64 / extent
            } else {
                0.0
            }
        });
        let mut grid = Occupancy {
            frame_min: frame.min,
            scale,
            side,
            bits: Vec::new(),
        };
        let words = (side * side * side).div_ceil(64);
        let mut spans = vec![CellSpan::NONE; len];
        let parts: Vec<&mut [CellSpan]> = spans.chunks_mut(MARK_CHUNK).collect();
        let marked = (parts.into_par_iter().enumerate())
            .map(|(part, out)| {
                let mut bits = vec![0u64; words];
                for (span, i) in out.iter_mut().zip(part * MARK_CHUNK..) {
                    let b = box_of(i);
                    if b.overlaps(frame) {
                        *span = grid.span(&b);
                        grid.any_row(*span, |row| {
                            for (w, mask) in row_words(row) {
                                bits[w] |= mask;
                            }
                            false
                        });
                    }
                }
                bits
            })
            .reduce_with(|mut a, b| {
                (a.iter_mut().zip(&b)).for_each(|(x, y)| *x |= y);
                a
            });
        grid.bits = marked.unwrap_or_else(|| vec![0; words]);
        (grid, spans)
    }

    /// The cells box `b` covers, in this grid.
    pub fn span(&self, b: &Aabb) -> CellSpan {
        CellSpan::new(
            std::array::from_fn(|k| self.cell(k, b.min[k])),
            std::array::from_fn(|k| self.cell(k, b.max[k])),
        )
    }

    /// Whether a box covering `span` (of a grid with this frame and side) overlaps a marked
    /// cell: always when it overlaps a marked box (see the module docs), rarely otherwise.
    pub fn touches(&self, span: CellSpan) -> bool {
        span != CellSpan::NONE
            && self.any_row(span, |row| {
                row_words(row).any(|(w, mask)| self.bits[w] & mask != 0)
            })
    }

    /// Calls `visit` with each row of cells in `span` (the cells along x at one y and z,
    /// whose indices `x + side (y + side z)` are consecutive), until it returns `true`;
    /// whether one did.
    ///
    /// Why rows: a row is at most three words of the bitset, read or set with a mask, where
    /// cell by cell a large box (a long face of a model on a grid sized to the small pieces
    /// along a curve) costs one step per cell, and a box that touches stops at the first
    /// marked row. A visitor rather than an iterator of rows, which marking would simply
    /// loop over: chained `flat_map`s over the rows took the broad phase of two 10 k
    /// triangle spheres from 857 to 964 µs (warm medians).
    fn any_row(
        &self,
        span: CellSpan,
        mut visit: impl FnMut(RangeInclusive<usize>) -> bool,
    ) -> bool {
        let [(x0, x1), (y0, y1), (z0, z1)] = span.bounds();
        for z in z0..=z1 {
            for y in y0..=y1 {
                let start = self.side * (y + self.side * z);
                if visit(start + x0..=start + x1) {
                    return true;
                }
            }
        }
        false
    }

    /// The cell index of coordinate `x` on axis `k`: monotone in `x`.
    fn cell(&self, k: usize, x: f64) -> usize {
        // `as` saturates: below the frame (or NaN) is cell 0.
        (((x - self.frame_min[k]) * self.scale[k]) as usize).min(self.side - 1)
    }
}

/// The words of a bitset that hold the bits `cells`, each with the mask of those bits in it.
fn row_words(cells: RangeInclusive<usize>) -> impl Iterator<Item = (usize, u64)> {
    let (first, last) = (*cells.start(), *cells.end());
    (first / 64..=last / 64).map(move |w| {
        let low = if w == first / 64 { first % 64 } else { 0 };
        let high = if w == last / 64 { last % 64 } else { 63 };
        (w, (u64::MAX >> (63 - high)) & (u64::MAX << low))
    })
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn boxes() -> impl Strategy<Value = Vec<Aabb>> {
        let corner = [-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0];
        let size = [0.0f64..0.5, 0.0f64..0.5, 0.0f64..0.5];
        prop::collection::vec((corner, size), 0..40).prop_map(|v| {
            (v.into_iter())
                .map(|(min, size)| Aabb {
                    min,
                    max: std::array::from_fn(|k| min[k] + size[k]),
                })
                .collect()
        })
    }

    proptest! {
        #[test]
        fn a_box_that_overlaps_a_marked_box_touches_the_grid(
            a in boxes(),
            b in boxes(),
            side in 1usize..20,
        ) {
            let frame = Aabb {
                min: [-1.0, -1.5, -1.0],
                max: [1.0, 0.5, 1.0 + 1e-9],
            };
            let (marked, spans) = Occupancy::of(&frame, side, b.len(), |i| b[i]);
            for (y, span) in b.iter().zip(&spans) {
                prop_assert_eq!(*span == CellSpan::NONE, !y.overlaps(&frame));
            }
            for x in &a {
                let meets = b.iter().any(|y| y.overlaps(x) && y.overlaps(&frame));
                let touches = marked.touches(marked.span(x));
                prop_assert!(!meets || touches, "{x:?} overlaps a marked box");
            }
        }
    }

    proptest! {
        /// Marking and reading by rows of cells (masks over words) mark and read exactly
        /// the cells of each span, on grids whose rows cross word boundaries.
        #[test]
        fn rows_mark_and_read_exactly_the_cells_of_a_span(
            a in boxes(),
            b in boxes(),
            side in 1usize..=MAX_SIDE,
        ) {
            let frame = Aabb {
                min: [-2.0; 3],
                max: [2.5; 3],
            };
            let (marked, spans) = Occupancy::of(&frame, side, b.len(), |i| b[i]);
            let cells = |span: CellSpan| {
                let [(x0, x1), (y0, y1), (z0, z1)] = span.bounds();
                let side = marked.side;
                (z0..=z1).flat_map(move |z| {
                    (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| x + side * (y + side * z)))
                })
            };
            let expected: std::collections::HashSet<usize> = (spans.iter())
                .filter(|&&span| span != CellSpan::NONE)
                .flat_map(|&span| cells(span))
                .collect();
            let set = (0..side * side * side).filter(|&c| marked.bits[c / 64] >> (c % 64) & 1 == 1);
            prop_assert_eq!(set.collect::<std::collections::HashSet<_>>(), expected.clone());
            for x in &a {
                let span = marked.span(x);
                prop_assert_eq!(marked.touches(span), cells(span).any(|c| expected.contains(&c)));
            }
        }
    }

    #[test]
    fn side_makes_cells_about_as_large_as_the_boxes() {
        let frame = Aabb {
            min: [0.0; 3],
            max: [2.0, 1.0, 1.0],
        };
        let cube = |at: f64, size: f64| Aabb {
            min: [at; 3],
            max: [at + size; 3],
        };
        let sized = |size: f64| (0..10).map(move |i| cube(f64::from(i) * 0.1, size));
        assert_eq!(Occupancy::side_for(&frame, sized(0.1)), 20);
        assert_eq!(Occupancy::side_for(&frame, sized(0.3)), 7);
        assert_eq!(Occupancy::side_for(&frame, sized(1e-6)), MAX_SIDE);
        // Boxes outside the frame say nothing about it.
        let outside = (0..10).map(|_| cube(5.0, 1e-6));
        assert_eq!(Occupancy::side_for(&frame, sized(0.1).chain(outside)), 20);
        assert_eq!(Occupancy::side_for(&frame, std::iter::empty()), 1);
    }

    #[test]
    fn far_boxes_do_not_touch() {
        let frame = Aabb {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let corner = Aabb {
            min: [0.0; 3],
            max: [0.1; 3],
        };
        let (marked, _) = Occupancy::of(&frame, 8, 1, |_| corner);
        let far = Aabb {
            min: [0.9; 3],
            max: [1.0; 3],
        };
        assert!(marked.touches(marked.span(&corner)));
        assert!(!marked.touches(marked.span(&far)));
        // Touching at a corner point counts, as for the boxes themselves.
        let touching = Aabb {
            min: [0.1; 3],
            max: [0.2; 3],
        };
        assert!(marked.touches(marked.span(&touching)));
    }
}
