//! An indexed family of problems run in parallel, as DifferentialEquations.jl's
//! `EnsembleProblem` runs any problem: item `i` is a pure function of `i`, so the results, kept
//! in index order, do not depend on the number of threads or on how the work is split. Progress
//! is reported through a callback (the command line draws the bar), a stop flag is polled before
//! each item (SIGINT/SIGTERM end a run cleanly), and an item's error is kept with its index,
//! never dropped.
//!
//! [`solve`] runs a whole family and returns it; [`solve_chunked`] streams a long one chunk by
//! chunk (the batch engine writes each chunk as soon as its items are done).

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use rayon::prelude::*;

/// How a run reports progress and learns that it should stop.
#[derive(Clone, Copy)]
pub struct Control<'a> {
    /// Called with the number of items just finished (from the worker threads).
    pub progress: &'a (dyn Fn(u64) + Sync),
    /// Polled before each item: once it returns true, no item starts.
    pub stop: &'a (dyn Fn() -> bool + Sync),
}

impl Control<'static> {
    /// No progress report, never stopping.
    pub const QUIET: Control<'static> = Control {
        progress: &|_| {},
        stop: &|| false,
    };
}

/// The items of a run in index order; `None` for an item not started because the run stopped.
#[derive(Debug, Clone, PartialEq)]
pub struct Ensemble<T> {
    /// One slot per index.
    pub items: Vec<Option<T>>,
}

impl<T> Ensemble<T> {
    /// Whether some item was not started because the run stopped.
    pub fn stopped(&self) -> bool {
        self.items.iter().any(Option::is_none)
    }

    /// Every item in index order, or `None` if the run stopped before finishing.
    pub fn complete(self) -> Option<Vec<T>> {
        self.items.into_iter().collect()
    }

    /// Every item of a run that cannot be stopped (run with a `stop` that never fires).
    pub fn all(self) -> Vec<T> {
        self.complete()
            .expect("a run without a stop signal finishes every item")
    }
}

impl<T, E> Ensemble<Result<T, E>> {
    /// The items in index order, or every failed item with its index.
    pub fn results(self) -> Result<Vec<T>, Vec<(usize, E)>> {
        let mut ok = Vec::with_capacity(self.items.len());
        let mut errors = Vec::new();
        for (i, item) in self.items.into_iter().enumerate() {
            match item.expect("a run without a stop signal finishes every item") {
                Ok(x) => ok.push(x),
                Err(e) => errors.push((i, e)),
            }
        }
        if errors.is_empty() {
            Ok(ok)
        } else {
            Err(errors)
        }
    }
}

/// Runs items `0..len` in parallel on the current rayon pool.
pub fn solve<T: Send>(
    len: usize,
    item: impl Fn(usize) -> T + Sync,
    control: &Control<'_>,
) -> Ensemble<T> {
    let items = (0..len)
        .into_par_iter()
        .map(|i| {
            if (control.stop)() {
                return None;
            }
            let x = item(i);
            (control.progress)(1);
            Some(x)
        })
        .collect();
    Ensemble { items }
}

/// One chunk of a streamed run: its number and the item indices it holds.
pub type Chunk = (u64, Range<u64>);

/// What a streamed run did.
#[derive(Debug, Default, PartialEq)]
pub struct ChunkedRun<E> {
    /// Chunks handed to `finish` whose `finish` succeeded.
    pub chunks_finished: u64,
    /// Their items.
    pub items_finished: u64,
    /// Chunks dropped because the run stopped before all their items were done.
    pub chunks_dropped: u64,
    /// Every `finish` that failed, with its chunk number, in the order they failed. After the
    /// first failure no further chunk starts.
    pub errors: Vec<(u64, E)>,
}

/// Streams the chunks in order: up to `in_flight` chunks have their items queued on the
/// current rayon pool at once, and the task that finishes a chunk's last item hands the chunk's
/// items, in index order, to `finish` and queues the next chunk, so no worker idles while a
/// chunk's slowest items finish. A chunk with an item skipped because the run is stopping is
/// dropped, not finished. FIFO spawns: a worker runs its own queued items oldest first, so the
/// oldest chunk in flight always finishes first (LIFO spawns starved chunk 0 on one thread).
pub fn solve_chunked<T: Send, E: Send>(
    chunks: impl Iterator<Item = Chunk> + Send,
    in_flight: usize,
    item: impl Fn(u64) -> T + Sync,
    finish: impl Fn(u64, Vec<T>) -> Result<(), E> + Sync,
    control: &Control<'_>,
) -> ChunkedRun<E> {
    let pipe = Pipeline {
        item: &item,
        finish: &finish,
        control,
        pending: Mutex::new(Box::new(chunks)),
        run: Mutex::new(ChunkedRun {
            chunks_finished: 0,
            items_finished: 0,
            chunks_dropped: 0,
            errors: Vec::new(),
        }),
    };
    rayon::scope_fifo(|s| {
        for _ in 0..in_flight {
            pipe.launch_next(s);
        }
    });
    pipe.run.into_inner().expect("no panic holds the lock")
}

/// The shared state of one streamed run.
struct Pipeline<'a, T, E> {
    item: &'a (dyn Fn(u64) -> T + Sync),
    finish: &'a (dyn Fn(u64, Vec<T>) -> Result<(), E> + Sync),
    control: &'a Control<'a>,
    /// The chunks still to launch, in order (lazily: a huge run starts at once).
    pending: Mutex<Box<dyn Iterator<Item = Chunk> + Send + 'a>>,
    run: Mutex<ChunkedRun<E>>,
}

/// One chunk in flight: a slot per item and how many are still running.
struct ChunkWork<T> {
    chunk: u64,
    lo: u64,
    items: Mutex<Vec<Option<T>>>,
    remaining: AtomicU64,
    /// An item was skipped because the run is stopping: the chunk is not finished.
    dropped: AtomicBool,
}

impl<'a, T: Send, E: Send> Pipeline<'a, T, E> {
    /// Queues every item of the next pending chunk, unless none is left, a chunk failed or the
    /// run is stopping.
    fn launch_next<'s>(&'s self, s: &rayon::ScopeFifo<'s>)
    where
        'a: 's,
    {
        if !self.run.lock().expect("lock").errors.is_empty() || (self.control.stop)() {
            return;
        }
        let Some((chunk, range)) = self.pending.lock().expect("lock").next() else {
            return;
        };
        let work = Arc::new(ChunkWork {
            chunk,
            lo: range.start,
            items: Mutex::new(range.clone().map(|_| None).collect()),
            remaining: AtomicU64::new(range.end - range.start),
            dropped: AtomicBool::new(false),
        });
        for i in range {
            let work = Arc::clone(&work);
            s.spawn_fifo(move |s| {
                if (self.control.stop)() {
                    work.dropped.store(true, Ordering::Release);
                } else {
                    let x = (self.item)(i);
                    (self.control.progress)(1);
                    work.items.lock().expect("lock")[(i - work.lo) as usize] = Some(x);
                }
                if work.remaining.fetch_sub(1, Ordering::AcqRel) == 1 {
                    self.finish_chunk(&work);
                    self.launch_next(s);
                }
            });
        }
    }

    /// Hands a complete chunk to `finish`, or counts it as dropped.
    fn finish_chunk(&self, work: &ChunkWork<T>) {
        if work.dropped.load(Ordering::Acquire) {
            self.run.lock().expect("lock").chunks_dropped += 1;
            return;
        }
        let items: Vec<T> = std::mem::take(&mut *work.items.lock().expect("lock"))
            .into_iter()
            .map(|x| x.expect("every item done"))
            .collect();
        let n = items.len() as u64;
        let result = (self.finish)(work.chunk, items);
        let mut run = self.run.lock().expect("lock");
        match result {
            Ok(()) => {
                run.chunks_finished += 1;
                run.items_finished += n;
            }
            Err(e) => run.errors.push((work.chunk, e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    #[test]
    fn results_are_in_index_order_whatever_the_threads() {
        let one = pool(1).install(|| solve(1000, |i| i * i, &Control::QUIET).all());
        let four = pool(4).install(|| solve(1000, |i| i * i, &Control::QUIET).all());
        assert_eq!(one, four);
        assert_eq!(one[999], 999 * 999);
    }

    #[test]
    fn progress_counts_every_item_and_stop_skips_the_rest() {
        let done = AtomicU64::new(0);
        let progress = |n: u64| {
            done.fetch_add(n, Ordering::Relaxed);
        };
        let control = Control {
            progress: &progress,
            stop: &|| false,
        };
        solve(50, |i| i, &control).all();
        assert_eq!(done.load(Ordering::Relaxed), 50);

        let started = AtomicU64::new(0);
        let stop = || started.load(Ordering::Relaxed) >= 10;
        let control = Control {
            progress: &|_| {},
            stop: &stop,
        };
        let run = pool(1).install(|| {
            solve(
                100,
                |i| {
                    started.fetch_add(1, Ordering::Relaxed);
                    i
                },
                &control,
            )
        });
        assert!(run.stopped());
        assert_eq!(run.items.iter().filter(|x| x.is_some()).count(), 10);
        assert_eq!(run.complete(), None);
    }

    #[test]
    fn errors_are_kept_with_their_index() {
        let run = solve(
            10,
            |i| {
                if i % 4 == 1 {
                    Err(format!("bad {i}"))
                } else {
                    Ok(i)
                }
            },
            &Control::QUIET,
        );
        let errors = run.results().unwrap_err();
        assert_eq!(
            errors,
            vec![
                (1, "bad 1".to_string()),
                (5, "bad 5".into()),
                (9, "bad 9".into())
            ]
        );
    }

    #[test]
    fn chunks_are_finished_whole_in_index_order() {
        let chunks = (0..7u64).map(|c| (c, c * 10..((c + 1) * 10).min(65)));
        let seen = Mutex::new(Vec::new());
        let run = pool(3).install(|| {
            solve_chunked(
                chunks,
                2,
                |i| i,
                |c, items: Vec<u64>| {
                    seen.lock().unwrap().push((c, items));
                    Ok::<(), String>(())
                },
                &Control::QUIET,
            )
        });
        assert_eq!(run.chunks_finished, 7);
        assert_eq!(run.items_finished, 65);
        let mut seen = seen.into_inner().unwrap();
        seen.sort();
        for (c, items) in seen {
            let lo = c * 10;
            assert_eq!(items, (lo..(lo + 10).min(65)).collect::<Vec<_>>());
        }
    }

    #[test]
    fn a_failed_chunk_is_kept_and_no_chunk_starts_after_it() {
        let chunks = (0..50u64).map(|c| (c, c..c + 1));
        let run = pool(1).install(|| {
            solve_chunked(
                chunks,
                1,
                |i| i,
                |c, _| if c == 3 { Err("disk full") } else { Ok(()) },
                &Control::QUIET,
            )
        });
        assert_eq!(run.errors, vec![(3, "disk full")]);
        assert_eq!(run.chunks_finished, 3);
    }
}
