//! Data parallelism: rayon when the `parallel` feature is on (the default), and the same calls
//! run in sequence without it, for targets without threads (`wasm32-unknown-unknown`, where
//! the browser page runs the library in one Web Worker).
//!
//! Every module writes `use crate::par::*;` where it would write `use rayon::prelude::*;`,
//! and `par::join` / `par::current_num_threads` for rayon's functions, so a call site reads
//! the same in both builds. Without `parallel`, `par_iter`, `into_par_iter`,
//! `par_chunks`, `par_sort_*` and `par_extend` are their standard-library counterparts, and
//! the few rayon adaptors the standard iterators lack by that name (`flat_map_iter`,
//! `find_map_first`, `reduce_with`) are defined on every [`Iterator`]; everything else a
//! chain calls (`map`, `zip`, `collect`, `sum`, …) is already [`Iterator`]'s. The sorts
//! are one trait for both builds ([`ParallelSliceMut`]); with `parallel` too, a short slice
//! gets the standard library's sort.
//!
//! Results are the same in both builds: the crate's parallel stages already give results
//! that do not depend on the thread count (they collect in item order or sort by stable
//! keys), and one thread is a thread count. Only what the crate calls is provided, so a new
//! rayon call that has no sequential twin here is a compile error of the sequential build,
//! which CI builds (`--no-default-features`).
//!
//! A run enters the pool through [`on_pool_or_inline`], which keeps small runs on the
//! calling thread: with `parallel`, the entry methods (`into_par_iter`, `par_iter`,
//! `par_iter_mut`, `par_chunks`) are rayon's held to one job per loop on such a thread, and
//! `join` runs its halves in turn there, so no loop of the run reaches the pool.
//!
//! Hand-written because the crates that offer such a stand-in either keep rayon as a
//! dependency or differ from rayon's signatures where std's methods share its names.

#[cfg(feature = "parallel")]
pub(crate) use parallel::*;

#[cfg(not(feature = "parallel"))]
pub(crate) use sequential::*;

/// rayon's sorts by their names, one declaration for both builds: with `parallel`, rayon's
/// own for `parallel::PAR_SORT_FROM` items or more on a thread that is not running inline,
/// else the standard library's sorts of the same stability.
pub(crate) trait ParallelSliceMut<T> {
    fn par_sort_unstable(&mut self)
    where
        T: Ord;
    fn par_sort_unstable_by<F>(&mut self, compare: F)
    where
        F: Fn(&T, &T) -> std::cmp::Ordering + Sync;
    fn par_sort_unstable_by_key<K: Ord, F: Fn(&T) -> K + Sync>(&mut self, key: F);
}

/// `0..count` cut into consecutive ranges of `size` items (the last one shorter): the blocks
/// a loop hands to its parallel tasks.
pub(crate) fn block_ranges(
    count: usize,
    size: usize,
) -> impl Iterator<Item = std::ops::Range<usize>> {
    (0..count)
        .step_by(size)
        .map(move |first| first..count.min(first + size))
}

/// `slice` cut into consecutive parts of `lengths` (which sum to at most its length), for
/// handing each part to its own task.
pub(crate) fn split_lengths_mut<T>(
    slice: &mut [T],
    lengths: impl IntoIterator<Item = usize>,
) -> Vec<&mut [T]> {
    let mut rest = slice;
    (lengths.into_iter())
        .map(|length| {
            let (part, tail) = std::mem::take(&mut rest).split_at_mut(length);
            rest = tail;
            part
        })
        .collect()
}

/// How long a loop of costly items in a run that runs inline goes on here before it judges
/// whether the rest is worth the pool.
const JUDGE_AFTER: std::time::Duration = std::time::Duration::from_micros(100);

/// The time left in a loop, at the pace of its first chunks, from which the pool pays. On
/// 2 cores here, handing a loop over (waking sleeping workers, which then split it between
/// them, while this thread waits) cost about 0.1 ms more than running it inline on the 120
/// intersecting pairs of two unit cubes (0.06–0.19 ms left after the first 0.1 ms), and
/// gained nothing on the exact splits of two cubes turned by 1e-7 rad (0.5–1 ms left):
/// inline, rotated_xyz_intersection took 1.37 ms against 1.53 (medians of 11 interleaved
/// runs). Where another process keeps a core busy, a woken worker can wait milliseconds for
/// one while this thread waits for it: with one busy core, the same case's median went from
/// 1.92 ms (handed over from 0.5 ms left) to 1.37 ms (inline), rotated_z_union's from 2.35
/// to 1.69 ms.
const POOL_PAYS_FROM: std::time::Duration = std::time::Duration::from_millis(2);

/// Runs `run` on `items` in chunks, each appending its chunk's results to the vector it is
/// given; returns the results in item order. The loop for items that cost microseconds each
/// (exact intersections, splits, pair tests), where the caller wants to act between chunks
/// (progress, cancellation) or the items are too few for rayon's own splitting to balance.
///
/// On a thread that runs a small run inline ([`on_pool_or_inline`]), the chunks run here
/// for [`JUDGE_AFTER`]; if what is left would take [`POOL_PAYS_FROM`] or more at that pace,
/// it goes to the pool, else it runs here too. A loop of cheap items ends inline, one of
/// costly items (exact splits of nearly coincident crossings) still spreads, and the loop's
/// running time, not a guess of the cost of its items, tells them apart.
pub(crate) fn chunks<T: Sync, R: Send>(
    items: &[T],
    run: impl Fn(&[T], &mut Vec<R>) + Sync,
) -> Vec<R> {
    let chunk_len = chunk_len(items.len());
    let mut out = Vec::new();
    let mut rest = items;
    if is_inline() {
        let clock = web_time::Instant::now();
        // Chunks double here: a short loop (the 120 pairs of two unit cubes) then ends in a
        // few chunks, each of which allocates its own results, instead of 32.
        let mut inline_len = chunk_len;
        loop {
            let chunk;
            (chunk, rest) = rest.split_at(inline_len.min(rest.len()));
            inline_len = (2 * inline_len).min(MAX_CHUNK_LEN);
            run(chunk, &mut out);
            if rest.is_empty() {
                return out;
            }
            let spent = clock.elapsed();
            if spent >= JUDGE_AFTER {
                let done = items.len() - rest.len();
                let left = spent.mul_f64(rest.len() as f64 / done as f64);
                if left < POOL_PAYS_FROM {
                    run(rest, &mut out);
                    return out;
                }
                break;
            }
        }
    }
    on_pool(|| {
        out.par_extend(rest.par_chunks(chunk_len).flat_map_iter(|chunk| {
            let mut chunk_out = Vec::new();
            run(chunk, &mut chunk_out);
            chunk_out
        }));
    });
    out
}

/// The items per chunk of [`chunks`]: about 8 chunks per thread, so the scheduler still
/// balances the load, and at most 1024, so a chunk of the costliest items (exact triangle
/// splits) ends within milliseconds of a cancellation. Not more chunks: each is a job of the
/// pool and a record of results, and at 32 per thread the intersect stage of two 10 k
/// triangle spheres (492 pairs, 7 a chunk) took 0.74 ms against 0.55 at 8 per thread
/// (warm medians, 2 cores), the splits and classification alike at both.
fn chunk_len(items: usize) -> usize {
    (items / (8 * current_num_threads())).clamp(1, MAX_CHUNK_LEN)
}

/// The most items a chunk of [`chunks`] holds.
const MAX_CHUNK_LEN: usize = 1024;

#[cfg(feature = "parallel")]
mod parallel {
    use std::cell::Cell;
    use std::sync::atomic::{AtomicBool, Ordering};

    use rayon::iter::MinLen;
    pub(crate) use rayon::prelude::{IndexedParallelIterator, ParallelExtend, ParallelIterator};

    /// The work size, in input faces, from which a run is worth the thread pool: below it,
    /// [`on_pool_or_inline`] runs it on the calling thread. Measured on the peers harness's cases
    /// (interleaved medians, 2 cores): two unit cubes touching (24 faces) take 30–45 % less time
    /// inline, where a hand-over to a sleeping worker and the wake-ups of the other cost more
    /// than the loops; two cubes rotated by 1e-7 rad (24 faces, whose exact splits spread through
    /// [`chunks`]) and Menger level 1 (48) take the same. Up to a few thousand faces the pool
    /// still gains nothing (11 fresh CLI runs each, op medians, pool from 100 faces → from
    /// 4,096): sphere_sphere_1k_union (1,960 faces) 2.30 → 2.17 ms, its difference 2.33 →
    /// 2.26, Menger level 2 (1,080 faces in 31 operands) 5.67 → 5.36; with another process
    /// keeping one core busy 2.31 → 2.15 and 8.38 → 7.13. Above it the pool pays (warm in one
    /// process, one thread against two): pair_ball_union (6,560 faces) 4.65 → 4.38 ms,
    /// sphere_sphere_10k_union (20,480) 9.27 → 7.48.
    const POOL_FROM_SIZE: usize = 4096;

    thread_local! {
        /// Whether this thread is running a small run inline ([`on_pool_or_inline`]).
        static INLINE: Cell<bool> = const { Cell::new(false) };
    }

    /// The least number of items rayon may give one job: all of them while this thread
    /// runs inline, so no loop splits and none reaches the pool (a split is a `join`,
    /// which from outside the pool injects a job and blocks until a worker takes it).
    fn min_len() -> usize {
        if INLINE.get() { usize::MAX } else { 1 }
    }

    /// Runs `f` on a worker thread of the pool when `size` (input faces) is
    /// [`POOL_FROM_SIZE`] or more, else on this thread with every parallel loop inside it run
    /// as one sequential job.
    ///
    /// Inline is a property of the thread, not of an argument passed down the stages: a
    /// run that never leaves its thread has every loop of its stages on that thread, so a
    /// thread-local flag reaches all of them, and the loops of a run on the pool, which
    /// run on workers, never see it.
    pub(crate) fn on_pool_or_inline<R: Send>(size: usize, f: impl FnOnce() -> R + Send) -> R {
        if INLINE.get() {
            // A run inside a small run stays where that run is.
            return f();
        }
        if size >= POOL_FROM_SIZE {
            // One hand-over to the pool for the whole run: the stages' loops then start on
            // a worker thread, where rayon splits work onto its own queue, instead of each
            // loop injecting its job from outside and blocking until a worker wakes.
            let from_outside = rayon::current_thread_index().is_none();
            let run_ended = AtomicBool::new(false);
            return rayon::scope(|scope| {
                if from_outside && rayon::current_num_threads() > 1 {
                    scope.spawn(|_| help_until(&run_ended));
                }
                // Ends the helper's wait when the run ends, by return or by unwinding.
                let _ended = OnDrop(|| run_ended.store(true, Ordering::Relaxed));
                f()
            });
        }
        INLINE.set(true);
        // Clears the flag when the run ends, by return or by unwinding.
        let _reset = OnDrop(|| INLINE.set(false));
        f()
    }

    /// Calls its closure when dropped: what a run does at its end, by return or by
    /// unwinding.
    struct OnDrop<F: FnMut()>(F);

    impl<F: FnMut()> Drop for OnDrop<F> {
        fn drop(&mut self) {
            (self.0)();
        }
    }

    /// How long [`help_until`] waits for work before it lets its worker sleep.
    const HELPER_PATIENCE: std::time::Duration = std::time::Duration::from_millis(2);

    /// A worker that takes every job the run's loops split off (`rayon::yield_now`) and
    /// otherwise spins, until the run ends (`run_ended`) or no job came for
    /// [`HELPER_PATIENCE`]; one per run that enters the pool from outside it.
    ///
    /// Why: a rayon worker with nothing to do sleeps after a few dozen rounds of yielding,
    /// and each parallel loop that follows pays to wake it (a futex call on the splitting
    /// thread, then the wake-up's latency before the other half starts): a boolean of a few
    /// thousand faces runs dozens of loops of tens of microseconds between short serial
    /// steps. With one worker kept awake through the run, as OpenMP runtimes keep theirs
    /// spinning between parallel regions, the fresh CLI's op on sphere_sphere_10k_union took
    /// 6.82 ms against 7.61, pair_ball_union 4.08 against 4.44, sphere_sphere_100k_intersection
    /// 44.1 against 48.1, sphere_sphere_1M_union the same (medians of 9 interleaved runs, 2
    /// cores). Only one worker, so a many-core machine does not burn all its cores on the
    /// serial steps, and only for runs entered from outside the pool: a run on a worker (one
    /// of several a caller runs side by side) already has the pool busy. The patience bounds
    /// the spin through a long serial step, and bounds the wait should the run's own thread
    /// take this job itself while it waits for a stolen half (the job is the oldest on its
    /// queue, which thieves take first).
    fn help_until(run_ended: &AtomicBool) {
        let mut last_work = web_time::Instant::now();
        while !run_ended.load(Ordering::Relaxed) {
            if rayon::yield_now() == Some(rayon::Yield::Executed) {
                last_work = web_time::Instant::now();
            } else if last_work.elapsed() > HELPER_PATIENCE {
                return;
            } else {
                std::hint::spin_loop();
            }
        }
    }

    /// Runs `f`, a loop whose items are costly enough to be worth the pool even in a run
    /// small enough to run inline, on the pool: from an inline thread, with one hand-over
    /// (and every loop inside it split as rayon splits), else here. A small run on a worker
    /// thread (one of several a caller runs side by side) stays inline here too: rayon
    /// runs `f` on that worker, where the flag still holds its loops, and the pool is busy
    /// with the caller's other work.
    pub(crate) fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
        if INLINE.get() {
            rayon::scope(|_| f())
        } else {
            f()
        }
    }

    /// Whether this thread runs a small run inline.
    pub(crate) fn is_inline() -> bool {
        INLINE.get()
    }

    /// `rayon::join`, or `a` then `b` while this thread runs inline.
    pub(crate) fn join<A, B, RA, RB>(a: A, b: B) -> (RA, RB)
    where
        A: FnOnce() -> RA + Send,
        B: FnOnce() -> RB + Send,
        RA: Send,
        RB: Send,
    {
        if INLINE.get() {
            (a(), b())
        } else {
            rayon::join(a, b)
        }
    }

    /// The threads a loop may run on: one while this thread runs inline.
    pub(crate) fn current_num_threads() -> usize {
        if INLINE.get() {
            1
        } else {
            rayon::current_num_threads()
        }
    }

    /// The length from which a sort is worth rayon's: below it, and while this thread runs
    /// inline, the standard library's sort of the same stability. rayon's sorts fall back to
    /// their own sequential merge sort and quicksort below 2,000 items, which took about
    /// twice the standard library's time on the few hundred contact marks of two unit cubes.
    const PAR_SORT_FROM: usize = 4096;

    /// rayon's sorts, on one thread for a short slice or while this thread runs inline.
    impl<T: Send> super::ParallelSliceMut<T> for [T] {
        fn par_sort_unstable(&mut self)
        where
            T: Ord,
        {
            if sorts_inline(self.len()) {
                self.sort_unstable();
            } else {
                rayon::slice::ParallelSliceMut::par_sort_unstable(self);
            }
        }
        fn par_sort_unstable_by<F>(&mut self, compare: F)
        where
            F: Fn(&T, &T) -> std::cmp::Ordering + Sync,
        {
            if sorts_inline(self.len()) {
                self.sort_unstable_by(compare);
            } else {
                rayon::slice::ParallelSliceMut::par_sort_unstable_by(self, compare);
            }
        }
        fn par_sort_unstable_by_key<K: Ord, F: Fn(&T) -> K + Sync>(&mut self, key: F) {
            if sorts_inline(self.len()) {
                self.sort_unstable_by_key(key);
            } else {
                rayon::slice::ParallelSliceMut::par_sort_unstable_by_key(self, key);
            }
        }
    }

    /// Whether a sort of `len` items runs on this thread with the standard library's sort.
    fn sorts_inline(len: usize) -> bool {
        len < PAR_SORT_FROM || INLINE.get()
    }

    /// rayon's `into_par_iter`, held to one job while this thread runs inline.
    pub(crate) trait IntoParallelIterator:
        rayon::iter::IntoParallelIterator + Sized
    where
        Self::Iter: IndexedParallelIterator,
    {
        fn into_par_iter(self) -> MinLen<Self::Iter> {
            rayon::iter::IntoParallelIterator::into_par_iter(self).with_min_len(min_len())
        }
    }

    impl<T> IntoParallelIterator for T
    where
        T: rayon::iter::IntoParallelIterator,
        T::Iter: IndexedParallelIterator,
    {
    }

    /// rayon's `par_iter`, held to one job while this thread runs inline.
    pub(crate) trait IntoParallelRefIterator<'data> {
        type Iter: IndexedParallelIterator;
        fn par_iter(&'data self) -> MinLen<Self::Iter>;
    }

    impl<'data, C> IntoParallelRefIterator<'data> for C
    where
        C: rayon::iter::IntoParallelRefIterator<'data> + ?Sized,
        C::Iter: IndexedParallelIterator,
    {
        type Iter = C::Iter;
        fn par_iter(&'data self) -> MinLen<Self::Iter> {
            rayon::iter::IntoParallelRefIterator::par_iter(self).with_min_len(min_len())
        }
    }

    /// rayon's `par_iter_mut`, held to one job while this thread runs inline.
    pub(crate) trait IntoParallelRefMutIterator<'data> {
        type Iter: IndexedParallelIterator;
        fn par_iter_mut(&'data mut self) -> MinLen<Self::Iter>;
    }

    impl<'data, C> IntoParallelRefMutIterator<'data> for C
    where
        C: rayon::iter::IntoParallelRefMutIterator<'data> + ?Sized,
        C::Iter: IndexedParallelIterator,
    {
        type Iter = C::Iter;
        fn par_iter_mut(&'data mut self) -> MinLen<Self::Iter> {
            rayon::iter::IntoParallelRefMutIterator::par_iter_mut(self).with_min_len(min_len())
        }
    }

    /// rayon's `par_chunks`, held to one job while this thread runs inline.
    pub(crate) trait ParallelSlice<T: Sync> {
        fn par_chunks(&self, size: usize) -> MinLen<rayon::slice::Chunks<'_, T>>;
    }

    impl<T: Sync> ParallelSlice<T> for [T] {
        fn par_chunks(&self, size: usize) -> MinLen<rayon::slice::Chunks<'_, T>> {
            rayon::slice::ParallelSlice::par_chunks(self, size).with_min_len(min_len())
        }
    }
}

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

    /// Without threads, every run is inline, and there is no pool to hand a loop to.
    pub(crate) fn is_inline() -> bool {
        false
    }

    /// Runs `f` here: without threads, there is no pool.
    pub(crate) fn on_pool<R>(f: impl FnOnce() -> R) -> R {
        f()
    }

    /// Runs `f` here: every run is inline without threads.
    pub(crate) fn on_pool_or_inline<R>(_size: usize, f: impl FnOnce() -> R) -> R {
        f()
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
    impl<T> super::ParallelSliceMut<T> for [T] {
        fn par_sort_unstable(&mut self)
        where
            T: Ord,
        {
            self.sort_unstable();
        }
        fn par_sort_unstable_by<F>(&mut self, compare: F)
        where
            F: Fn(&T, &T) -> std::cmp::Ordering + Sync,
        {
            self.sort_unstable_by(compare);
        }
        fn par_sort_unstable_by_key<K: Ord, F: Fn(&T) -> K + Sync>(&mut self, key: F) {
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

#[cfg(all(test, feature = "parallel"))]
mod tests {
    use std::thread::{self, ThreadId};
    use std::time::Duration;

    use super::*;

    fn here() -> ThreadId {
        thread::current().id()
    }

    #[test]
    fn a_small_run_keeps_every_loop_on_its_thread() {
        let threads: Vec<ThreadId> = on_pool_or_inline(10, || {
            let (a, b) = join(
                || {
                    (0..5000)
                        .into_par_iter()
                        .map(|_| here())
                        .collect::<Vec<_>>()
                },
                || {
                    vec![0u8; 5000]
                        .par_iter()
                        .map(|_| here())
                        .collect::<Vec<_>>()
                },
            );
            a.into_iter().chain(b).collect()
        });
        assert!(threads.iter().all(|&t| t == here()));
        assert!(!is_inline(), "the flag outlives the run");
    }

    #[test]
    fn a_run_inside_a_small_run_stays_inline() {
        let (inner, still_inline) = on_pool_or_inline(10, || {
            let inner = on_pool_or_inline(100_000, here);
            (inner, is_inline())
        });
        assert_eq!(inner, here());
        assert!(still_inline, "the inner run cleared the outer run's flag");
        assert!(!is_inline());
    }

    #[test]
    fn a_large_run_goes_to_the_pool() {
        assert_ne!(on_pool_or_inline(100_000, here), here());
    }

    #[test]
    fn a_long_loop_of_a_small_run_hands_its_rest_to_the_pool_in_order() {
        let items: Vec<u32> = (0..1000).collect();
        let slow = |chunk: &[u32], out: &mut Vec<(u32, ThreadId)>| {
            for &i in chunk {
                thread::sleep(Duration::from_micros(2));
                out.push((2 * i, here()));
            }
        };
        let done = on_pool_or_inline(10, || chunks(&items, slow));
        let values: Vec<u32> = done.iter().map(|&(v, _)| v).collect();
        assert_eq!(values, items.iter().map(|i| 2 * i).collect::<Vec<_>>());
        assert_eq!(done[0].1, here(), "the loop starts inline");
        assert!(
            done.iter().any(|&(_, t)| t != here()),
            "the rest went to the pool"
        );
    }

    #[test]
    fn a_panic_in_a_large_run_reaches_the_caller_after_its_helper_ends() {
        // The helper kept awake beside the run ends with it; the scope waits for both.
        let result = std::panic::catch_unwind(|| {
            on_pool_or_inline(100_000, || {
                let sum: u64 = (0..10_000u32).into_par_iter().map(u64::from).sum();
                assert_eq!(sum, 49_995_000);
                panic!("stage failed")
            })
        });
        assert!(result.is_err());
        assert_eq!(
            on_pool_or_inline(100_000, || 7),
            7,
            "the pool still serves runs"
        );
    }

    #[test]
    fn a_panic_in_a_small_run_clears_the_flag() {
        let result = std::panic::catch_unwind(|| on_pool_or_inline(10, || panic!("stage failed")));
        assert!(result.is_err());
        assert!(!is_inline());
    }
}
