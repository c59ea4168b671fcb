//! Data parallelism: rayon when the `parallel` feature is on (the default), and the same calls
//! run in sequence without it, for targets without threads (`wasm32-unknown-unknown`, where
//! the browser page runs the library in one Web Worker).
//!
//! Every module writes `use crate::par::*;` where it would write `use rayon::prelude::*;`,
//! and `par::join` / `par::scope` / `par::current_num_threads` for rayon's functions, so a
//! call site reads the same in both builds. Without `parallel`, `par_iter`, `into_par_iter`,
//! `par_chunks`, `par_sort_*` and `par_extend` are their standard-library counterparts, and
//! the few rayon adaptors the standard iterators lack by that name (`flat_map_iter`,
//! `find_map_first`, `reduce_with`) are defined on every [`Iterator`]; everything else a
//! chain calls (`map`, `zip`, `collect`, `sum`, …) is already [`Iterator`]'s.
//!
//! Results are the same in both builds: the crate's parallel stages already give results
//! that do not depend on the thread count (they collect in item order or sort by stable
//! keys), and one thread is a thread count. Only what the crate calls is provided, so a new
//! rayon call that has no sequential twin here is a compile error of the sequential build,
//! which CI builds (`--no-default-features`).
//!
//! Hand-written because the crates that offer such a stand-in either keep rayon as a
//! dependency or differ from rayon's signatures where std's methods share its names.

#[cfg(feature = "parallel")]
pub(crate) use rayon::prelude::*;
#[cfg(feature = "parallel")]
pub(crate) use rayon::{current_num_threads, join, scope};

#[cfg(not(feature = "parallel"))]
pub(crate) use sequential::*;

#[cfg(not(feature = "parallel"))]
mod sequential {
    /// Runs `a` then `b`, as `rayon::join` runs them side by side.
    pub(crate) fn join<A, B, RA, RB>(a: A, b: B) -> (RA, RB)
    where
        A: FnOnce() -> RA,
        B: FnOnce() -> RB,
    {
        (a(), b())
    }

    /// The scope of [`scope`]: nothing is spawned on it.
    pub(crate) struct Scope;

    /// Runs `f` here, as `rayon::scope` runs it on a worker thread.
    pub(crate) fn scope<R>(f: impl FnOnce(&Scope) -> R) -> R {
        f(&Scope)
    }

    /// One thread: the one running.
    pub(crate) fn current_num_threads() -> usize {
        1
    }

    /// `into_par_iter`: `into_iter`.
    pub(crate) trait IntoParallelIterator: IntoIterator + Sized {
        fn into_par_iter(self) -> Self::IntoIter {
            self.into_iter()
        }
    }

    impl<T: IntoIterator> IntoParallelIterator for T {}

    /// `par_iter`: `iter`, for every collection whose reference iterates.
    pub(crate) trait IntoParallelRefIterator<'a> {
        type Iter: Iterator;
        fn par_iter(&'a self) -> Self::Iter;
    }

    impl<'a, C: ?Sized + 'a> IntoParallelRefIterator<'a> for C
    where
        &'a C: IntoIterator,
    {
        type Iter = <&'a C as IntoIterator>::IntoIter;
        fn par_iter(&'a self) -> Self::Iter {
            self.into_iter()
        }
    }

    /// `par_iter_mut`: `iter_mut`.
    pub(crate) trait IntoParallelRefMutIterator<'a> {
        type Iter: Iterator;
        fn par_iter_mut(&'a mut self) -> Self::Iter;
    }

    impl<'a, C: ?Sized + 'a> IntoParallelRefMutIterator<'a> for C
    where
        &'a mut C: IntoIterator,
    {
        type Iter = <&'a mut C as IntoIterator>::IntoIter;
        fn par_iter_mut(&'a mut self) -> Self::Iter {
            self.into_iter()
        }
    }

    /// rayon's adaptors whose standard twins have other names or signatures.
    pub(crate) trait ParallelIterator: Iterator + Sized {
        /// `flat_map` whose closure returns a sequential iterator: `flat_map`.
        fn flat_map_iter<U, F>(self, f: F) -> std::iter::FlatMap<Self, U, F>
        where
            U: IntoIterator,
            F: FnMut(Self::Item) -> U,
        {
            self.flat_map(f)
        }

        /// The first result in order that `f` gives: `find_map`.
        fn find_map_first<R, F>(mut self, f: F) -> Option<R>
        where
            F: FnMut(Self::Item) -> Option<R>,
        {
            self.find_map(f)
        }

        /// The reduction of the items by `op`, `None` when there is none: `reduce`.
        fn reduce_with<F>(self, op: F) -> Option<Self::Item>
        where
            F: FnMut(Self::Item, Self::Item) -> Self::Item,
        {
            self.reduce(op)
        }
    }

    impl<I: Iterator> ParallelIterator for I {}

    /// An iterator that rayon could split at any index; every iterator here.
    pub(crate) trait IndexedParallelIterator: Iterator {}

    impl<I: Iterator> IndexedParallelIterator for I {}

    /// `par_chunks`: `chunks`.
    pub(crate) trait ParallelSlice<T> {
        fn par_chunks(&self, size: usize) -> std::slice::Chunks<'_, T>;
    }

    impl<T> ParallelSlice<T> for [T] {
        fn par_chunks(&self, size: usize) -> std::slice::Chunks<'_, T> {
            self.chunks(size)
        }
    }

    /// rayon's sorts: the standard sorts of the same stability.
    pub(crate) trait ParallelSliceMut<T> {
        fn par_sort_unstable(&mut self)
        where
            T: Ord;
        fn par_sort_unstable_by<F>(&mut self, compare: F)
        where
            F: FnMut(&T, &T) -> std::cmp::Ordering;
        fn par_sort_unstable_by_key<K: Ord, F: FnMut(&T) -> K>(&mut self, key: F);
    }

    impl<T> ParallelSliceMut<T> for [T] {
        fn par_sort_unstable(&mut self)
        where
            T: Ord,
        {
            self.sort_unstable();
        }
        fn par_sort_unstable_by<F>(&mut self, compare: F)
        where
            F: FnMut(&T, &T) -> std::cmp::Ordering,
        {
            self.sort_unstable_by(compare);
        }
        fn par_sort_unstable_by_key<K: Ord, F: FnMut(&T) -> K>(&mut self, key: F) {
            self.sort_unstable_by_key(key);
        }
    }

    /// `par_extend`: `extend`, for a vector or a pair of them (an unzip).
    pub(crate) trait ParallelExtend<T> {
        fn par_extend<I: IntoIterator<Item = T>>(&mut self, items: I);
    }

    impl<T, C: Extend<T>> ParallelExtend<T> for C {
        fn par_extend<I: IntoIterator<Item = T>>(&mut self, items: I) {
            self.extend(items);
        }
    }
}
