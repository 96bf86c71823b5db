//! Running the variants on all cores.
//!
//! `jobs` worker threads take the next variant in turn; each worker evaluates inside its own
//! rayon pool of ONE thread, so that an analysis that asks rayon for parallelism (the SVD,
//! the static path's linearised steps, the sparse eigen solver's kernels) runs on that thread
//! alone. Then a variant's record is the same bit for bit whatever the number of workers, and
//! the same as on a Dask worker ([`evaluate_isolated`], the entry of the Python package's
//! distributed runner). The workers are plain threads rather than tasks of one rayon pool: a
//! rayon worker waiting for another pool runs other tasks meanwhile, which would nest variants
//! in one thread.

use crate::evaluate::evaluate;
use crate::record::Record;
use crate::spec::Study;
use crate::Variant;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The number of worker threads for `jobs` (0: one per core) and `n` variants.
pub fn workers(jobs: usize, n: usize) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    (if jobs == 0 { cores } else { jobs }).min(n).max(1)
}

/// A rayon pool of one thread, or `None` if the system refuses another thread.
fn one_thread_pool() -> Option<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new().num_threads(1).build().ok()
}

thread_local! {
    /// The one-thread pool of the calling thread, made at its first variant and kept: a new
    /// pool per variant costs a thread and a cold allocator arena every time (about 1 ms, a
    /// fifth of a five-sheet guide's variant).
    static POOL: Option<rayon::ThreadPool> = one_thread_pool();
}

/// Evaluate one variant with one thread (in a rayon pool of one thread, the calling thread's
/// own, kept between calls): the record every runner produces for this variant, local or
/// distributed.
pub fn evaluate_isolated(study: &Study, v: &Variant) -> Record {
    POOL.with(|pool| match pool {
        Some(pool) => pool.install(|| evaluate(study, v)),
        None => evaluate(study, v),
    })
}

/// Evaluate `variants` on `jobs` worker threads (0: one per core); `sink` receives every record
/// as soon as its variant is done (in the order they finish) and may stop the run by returning
/// `false`: it receives no further record (those of the variants under way are dropped, so a
/// resumed study runs them again), and no new variant starts.
pub fn run(study: &Study, variants: &[Variant], jobs: usize, mut sink: impl FnMut(Record) -> bool) {
    if variants.is_empty() {
        return;
    }
    let next = AtomicUsize::new(0);
    let stop = std::sync::atomic::AtomicBool::new(false);
    let (tx, rx) = std::sync::mpsc::channel::<Record>();
    std::thread::scope(|s| {
        for _ in 0..workers(jobs, variants.len()) {
            let tx = tx.clone();
            let (next, stop) = (&next, &stop);
            s.spawn(move || {
                let pool = one_thread_pool();
                loop {
                    if stop.load(Ordering::Relaxed) {
                        break;
                    }
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(v) = variants.get(i) else { break };
                    let r = match &pool {
                        Some(p) => p.install(|| evaluate(study, v)),
                        None => evaluate(study, v),
                    };
                    if tx.send(r).is_err() {
                        break;
                    }
                }
            });
        }
        drop(tx);
        for r in rx {
            if !sink(r) {
                // no record after the one that stopped the run: a worker may have finished
                // variants before it saw the stop, and the sink must not get them (dropping
                // the receiver ends their sends)
                stop.store(true, Ordering::Relaxed);
                break;
            }
        }
    });
}
