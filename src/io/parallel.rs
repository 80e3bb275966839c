//! One way to share work among the cores, for every part that does: the row reader, the
//! positions export, `info FOLDER` and the FK benchmark. Workers take the next piece of work
//! until none is left; results go on in the pieces' order.
//!
//! The helper threads are started once and kept: starting a thread costs about 50 µs here, as
//! much as loading a 50 KB file, and a script loading a folder file by file would pay it twice
//! per file (load, then positions).

/// Threads to parse and export with: the machine's cores, asked once (the answer comes from
/// cgroup files, too slow to read for every small file). Kept in an atomic, not a `OnceLock`: a
/// child forked while another thread was asking would wait for that thread's answer for good.
pub fn cores() -> usize {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static CORES: AtomicUsize = AtomicUsize::new(0);
    match CORES.load(Ordering::Relaxed) {
        0 => {
            // Two threads asking at once both ask; they get the same answer.
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            CORES.store(cores, Ordering::Relaxed);
            cores
        }
        known => known,
    }
}

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, Ordering};
use std::sync::{Condvar, Mutex, PoisonError};

/// A value of which each process has its own. A child made by `fork` (Python's multiprocessing
/// does) has only the thread that forked: a lock another thread of the parent held at that
/// moment stays locked in the child for good, and threads the value counts on are not there.
/// So the child starts a fresh value, and the parent's copy is left as it is.
pub(crate) struct PerProcess<T: Send + Sync + 'static> {
    /// The process that made the value, and the value. Never freed once published, so a
    /// reference to it lives as long as the program.
    current: AtomicPtr<(Process, T)>,
    make: fn() -> T,
}

/// Which process this is: its id, and how many forks made it. The id alone could name an
/// ancestor's value once ids wrap round (or in a new pid namespace); the count tells them apart.
#[derive(Clone, Copy, PartialEq)]
struct Process {
    id: u32,
    forks: u64,
}

/// Forks since the first `PerProcess` value, counted in the child by a fork handler (which
/// every descendant inherits).
static FORKS: AtomicU64 = AtomicU64::new(0);

impl Process {
    fn this() -> Process {
        Process {
            id: std::process::id(),
            forks: FORKS.load(Ordering::Acquire),
        }
    }
}

/// Counts forks from the first value on; no value exists before, so none was copied uncounted.
fn count_forks() {
    #[cfg(unix)]
    {
        static COUNTING: AtomicBool = AtomicBool::new(false);
        extern "C" fn forked() {
            FORKS.fetch_add(1, Ordering::AcqRel);
        }
        if !COUNTING.swap(true, Ordering::AcqRel) {
            // SAFETY: registers a handler that only bumps an atomic, which is safe in a child.
            // Should it fail (no memory), the process id still tells most children apart.
            unsafe { libc::pthread_atfork(None, None, Some(forked)) };
        }
    }
}

impl<T: Send + Sync + 'static> PerProcess<T> {
    pub(crate) const fn new(make: fn() -> T) -> Self {
        PerProcess {
            current: AtomicPtr::new(std::ptr::null_mut()),
            make,
        }
    }

    /// This process's value, made on first use.
    pub(crate) fn get(&self) -> &'static T {
        let process = Process::this();
        loop {
            let seen = self.current.load(Ordering::Acquire);
            // SAFETY: a published pointer came from `Box::into_raw` and is never freed.
            if let Some((made_in, value)) = unsafe { seen.as_ref() }
                && *made_in == process
            {
                return value;
            }
            count_forks();
            let fresh = Box::into_raw(Box::new((process, (self.make)())));
            match (self.current).compare_exchange(seen, fresh, Ordering::AcqRel, Ordering::Acquire)
            {
                // The value replaced, if any, is an ancestor's: it is left alone (leaked),
                // since a lock in it may be held by a thread that is not in this process.
                // SAFETY: just published, never freed.
                Ok(_) => return unsafe { &(*fresh).1 },
                // Another thread of this process published first: use its value.
                // SAFETY: `fresh` was never shared.
                Err(_) => drop(unsafe { Box::from_raw(fresh) }),
            }
        }
    }
}

/// Runs `worker` on up to `threads` threads, this one among them, and returns when every one
/// has returned. Each worker takes its own work from whatever state they share, so however many
/// of them run, this thread's alone would do it all: helpers that are busy elsewhere (another
/// call, a nested one) when it ends are not waited for, and their turn is called off.
///
/// A panic in any worker is raised here once every worker has returned.
pub fn on_threads(threads: usize, worker: impl Fn() + Sync) {
    if threads <= 1 {
        worker();
        return;
    }
    pool::run(threads - 1, &worker);
}

/// The kept helper threads and the calls waiting for them.
mod pool {
    use super::PerProcess;
    use std::any::Any;
    use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
    use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};

    /// A worker whose borrowed data outlives it: [`run`] does not return (or unwind) while any
    /// helper still runs it.
    type Job = *const (dyn Fn() + Sync + 'static);

    /// A call of [`run`]: turns not yet taken by a helper, and helpers running it.
    struct Call {
        id: u64,
        job: Job,
        turns: usize,
        running: usize,
        panic: Option<Box<dyn Any + Send>>,
    }

    struct State {
        calls: Vec<Call>,
        next_id: u64,
        helpers: usize,
        idle: usize,
    }

    // SAFETY: a `Job` is only called while its `run` waits, and the worker is `Sync`.
    unsafe impl Send for State {}

    /// The helpers of a process: a child made by `fork` has none of its parent's, and starts
    /// its own.
    struct Pool {
        state: Mutex<State>,
        /// Helpers wait here for a turn.
        work: Condvar,
        /// Callers wait here for their running helpers to return.
        finished: Condvar,
    }

    static POOL: PerProcess<Pool> = PerProcess::new(|| Pool {
        state: Mutex::new(State {
            calls: Vec::new(),
            next_id: 0,
            helpers: 0,
            idle: 0,
        }),
        work: Condvar::new(),
        finished: Condvar::new(),
    });

    /// No more helpers than this, whatever is asked.
    const MOST_HELPERS: usize = 63;

    impl Pool {
        fn state(&self) -> MutexGuard<'_, State> {
            self.state.lock().unwrap_or_else(PoisonError::into_inner)
        }
    }

    /// Offers `helpers` turns at `worker`, runs it here too, then waits for the helpers that
    /// took a turn and calls off the rest.
    pub(super) fn run(helpers: usize, worker: &(dyn Fn() + Sync)) {
        let helpers = helpers.min(MOST_HELPERS);
        // SAFETY: only the lifetime is erased; `Finish` below keeps this frame alive until no
        // helper runs the worker, on return and on unwinding alike.
        let job: Job = unsafe {
            std::mem::transmute::<*const (dyn Fn() + Sync + '_), Job>(worker as *const _)
        };
        let pool = POOL.get();
        let id = {
            let mut state = pool.state();
            let id = state.next_id;
            state.next_id += 1;
            state.calls.push(Call {
                id,
                job,
                turns: helpers,
                running: 0,
                panic: None,
            });
            // Start the helpers missing; wake as many waiting ones as there are turns.
            while state.helpers < helpers {
                if std::thread::Builder::new()
                    .name("bvhview-helper".into())
                    .spawn(|| helper(pool))
                    .is_err()
                {
                    break; // no helper, no harm: this thread does the work
                }
                state.helpers += 1;
                state.idle += 1;
            }
            for _ in 0..helpers.min(state.idle) {
                pool.work.notify_one();
            }
            id
        };
        let finish = Finish { pool, id };
        worker();
        drop(finish);
    }

    /// Ends a call: calls off its turns not taken, waits for its running helpers and raises
    /// a panic one of them had.
    struct Finish {
        pool: &'static Pool,
        id: u64,
    }

    impl Drop for Finish {
        fn drop(&mut self) {
            let mut state = self.pool.state();
            let call = loop {
                let i = (state.calls.iter())
                    .position(|c| c.id == self.id)
                    .expect("only the caller removes its call");
                state.calls[i].turns = 0;
                if state.calls[i].running == 0 {
                    break state.calls.swap_remove(i);
                }
                state = (self.pool.finished)
                    .wait(state)
                    .unwrap_or_else(PoisonError::into_inner);
            };
            drop(state);
            if let Some(panic) = call.panic
                && !std::thread::panicking()
            {
                resume_unwind(panic);
            }
        }
    }

    /// A helper's life: take a turn at a call, run it, wait for the next.
    fn helper(pool: &'static Pool) {
        let mut state = pool.state();
        loop {
            let Some(call) = state.calls.iter_mut().find(|c| c.turns > 0) else {
                state = pool
                    .work
                    .wait(state)
                    .unwrap_or_else(PoisonError::into_inner);
                continue;
            };
            call.turns -= 1;
            call.running += 1;
            let (id, job) = (call.id, call.job);
            state.idle -= 1;
            drop(state);
            // SAFETY: the call's `run` waits for `running` to drop to zero before it returns.
            let outcome = catch_unwind(AssertUnwindSafe(|| unsafe { (*job)() }));
            state = pool.state();
            state.idle += 1;
            let call = state
                .calls
                .iter_mut()
                .find(|c| c.id == id)
                .expect("a call stays listed while a helper runs it");
            call.running -= 1;
            if let Err(panic) = outcome {
                call.panic.get_or_insert(panic);
            }
            if call.running == 0 {
                pool.finished.notify_all();
            }
        }
    }
}

/// What the workers of [`map_in_order`] share.
struct Order<R> {
    /// The next index to hand out, and the next to hand to `done`.
    claimed: usize,
    emitted: usize,
    /// Results that wait for an earlier one.
    waiting: BTreeMap<usize, R>,
    /// A worker is handing results to `done` (one at a time, in order).
    emitting: bool,
    stopped: bool,
}

/// Computes `map(i)` for every `i` in `0..count` on `threads` threads, each taking the next index,
/// and hands the results to `done(i, result)` in index order: each as soon as it and every
/// earlier one are ready, so output can stream while later pieces are computed. No more than
/// `ahead` results wait for an earlier one (workers pause instead), which bounds the memory
/// however slow one piece is. `done` runs outside the lock the workers share, so while one
/// worker writes out a result the others go on computing. `done` returns false to stop: no
/// further piece is started. A panic in `map` or `done` stops the rest too and is raised here.
pub fn map_in_order<R: Send>(
    count: usize,
    threads: usize,
    ahead: usize,
    map: impl Fn(usize) -> R + Sync,
    done: impl FnMut(usize, R) -> bool + Send,
) {
    let ahead = ahead.max(1);
    let state = Mutex::new(Order {
        claimed: 0,
        emitted: 0,
        waiting: BTreeMap::new(),
        emitting: false,
        stopped: false,
    });
    // Only the worker that set `emitting` locks it, so it never waits.
    let done = Mutex::new(done);
    let turn = Condvar::new();
    let lock = || state.lock().unwrap_or_else(PoisonError::into_inner);
    let take_pieces = || {
        loop {
            let index = {
                let mut order = lock();
                while !order.stopped
                    && order.claimed < count
                    && order.claimed >= order.emitted + ahead
                {
                    order = turn.wait(order).unwrap_or_else(PoisonError::into_inner);
                }
                if order.stopped || order.claimed >= count {
                    return;
                }
                order.claimed += 1;
                order.claimed - 1
            };
            let result = map(index);
            let mut order = lock();
            order.waiting.insert(index, result);
            if order.emitting {
                // The worker emitting finds this result when it looks for the next one.
                continue;
            }
            order.emitting = true;
            loop {
                let next = order.emitted;
                let Some(result) = order.waiting.remove(&next) else {
                    break;
                };
                let stopped = order.stopped;
                drop(order);
                let go_on =
                    stopped || (done.lock().unwrap_or_else(PoisonError::into_inner))(next, result);
                order = lock();
                order.emitted += 1;
                if !go_on {
                    order.stopped = true;
                }
                turn.notify_all();
            }
            order.emitting = false;
        }
    };
    on_threads(threads.clamp(1, count.max(1)), || {
        // A worker that panics (in `map` or in `done`) stops the others, which would otherwise
        // wait for its result for good; `on_threads` raises the panic once they have returned.
        if let Err(panic) = catch_unwind(AssertUnwindSafe(take_pieces)) {
            lock().stopped = true;
            turn.notify_all();
            resume_unwind(panic);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_arrive_in_order_on_any_number_of_threads() {
        for threads in [1, 2, 4, 8] {
            let mut seen = Vec::new();
            // Later pieces finish first: the order must still hold.
            map_in_order(
                50,
                threads,
                3,
                |i| {
                    std::thread::sleep(std::time::Duration::from_micros(((50 - i) * 20) as u64));
                    i * i
                },
                |i, square| {
                    seen.push((i, square));
                    true
                },
            );
            let want: Vec<(usize, usize)> = (0..50).map(|i| (i, i * i)).collect();
            assert_eq!(seen, want, "{threads} threads");
        }
    }

    /// `done` (writing a block of the export) must not hold up the other workers.
    /// Piece 0 waits for piece 1 to start, piece 1 for piece 0's `done` to start, and that
    /// `done` for piece 2 to start: the thread of piece 1 must be free to take piece 2.
    #[test]
    fn other_workers_go_on_while_done_runs() {
        use std::sync::atomic::AtomicUsize;
        // How far it got: 1 piece 1 started, 2 piece 0's `done` started, 3 piece 2 started.
        let stage = AtomicUsize::new(0);
        let wait_for = |wanted: usize| {
            let start = std::time::Instant::now();
            while stage.load(Ordering::SeqCst) < wanted
                && start.elapsed() < std::time::Duration::from_secs(10)
            {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
            stage.load(Ordering::SeqCst) >= wanted
        };
        let second_on = Mutex::new(None);
        let (mut done_on, mut went_on) = (None, false);
        map_in_order(
            4,
            2,
            3,
            |i| match i {
                0 => {
                    wait_for(1);
                }
                1 => {
                    *second_on.lock().unwrap() = Some(std::thread::current().id());
                    stage.fetch_max(1, Ordering::SeqCst);
                    wait_for(2);
                }
                2 => {
                    stage.fetch_max(3, Ordering::SeqCst);
                }
                _ => {}
            },
            |i, ()| {
                if i == 0 {
                    done_on = Some(std::thread::current().id());
                    stage.fetch_max(2, Ordering::SeqCst);
                    went_on = wait_for(3);
                }
                true
            },
        );
        // Unless one thread did it all (the helper busy with another test's call).
        if second_on.into_inner().unwrap() != done_on {
            assert!(went_on, "no piece started while done ran");
        }
    }

    /// Runs `pieces` pieces of `work` through `on_threads`, each once; returns the threads seen.
    fn share(threads: usize, pieces: usize, work: impl Fn(usize) + Sync) -> usize {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let next = AtomicUsize::new(0);
        let seen = Mutex::new(std::collections::HashSet::new());
        on_threads(threads, || {
            loop {
                let piece = next.fetch_add(1, Ordering::Relaxed);
                if piece >= pieces {
                    return;
                }
                seen.lock().unwrap().insert(std::thread::current().id());
                work(piece);
            }
        });
        assert!(next.into_inner() >= pieces);
        seen.into_inner().unwrap().len()
    }

    /// Threads that have started a piece; [`Meeting::arrive`] holds a piece until `wanted` of
    /// them have (or 20 s have passed), so a test sees the work shared by arrangement, not by
    /// guessing how long a helper takes to wake: no test waits on the clock.
    struct Meeting {
        seen: Mutex<std::collections::HashSet<std::thread::ThreadId>>,
        wanted: usize,
    }

    impl Meeting {
        fn new(wanted: usize) -> Meeting {
            Meeting {
                seen: Mutex::new(std::collections::HashSet::new()),
                wanted,
            }
        }

        fn arrive(&self) {
            self.seen
                .lock()
                .unwrap()
                .insert(std::thread::current().id());
            let start = std::time::Instant::now();
            while self.seen.lock().unwrap().len() < self.wanted
                && start.elapsed() < std::time::Duration::from_secs(20)
            {
                std::thread::yield_now();
            }
        }
    }

    #[test]
    fn kept_helpers_share_the_work() {
        let meeting = Meeting::new(2);
        let threads = share(3, 8, |_| meeting.arrive());
        assert!((2..=3).contains(&threads), "{threads} threads ran");
    }

    #[test]
    fn nested_and_concurrent_calls_each_do_all_their_work() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let done = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..4 {
                scope.spawn(|| {
                    share(4, 16, |_| {
                        share(3, 5, |_| {
                            done.fetch_add(1, Ordering::Relaxed);
                        });
                    });
                });
            }
        });
        assert_eq!(done.into_inner(), 4 * 16 * 5);
    }

    #[test]
    fn a_helpers_panic_reaches_the_caller_after_every_worker_returned() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let running = AtomicUsize::new(0);
        let caller = std::thread::current().id();
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let meeting = Meeting::new(2);
            share(2, 6, |_| {
                running.fetch_add(1, Ordering::SeqCst);
                meeting.arrive();
                let helper = std::thread::current().id() != caller;
                running.fetch_sub(1, Ordering::SeqCst);
                assert!(!helper, "a helper's piece");
            });
        }));
        let message = *outcome
            .expect_err("the panic is raised")
            .downcast::<&str>()
            .unwrap();
        assert_eq!(message, "a helper's piece");
        assert_eq!(
            running.into_inner(),
            0,
            "a worker still ran when the call returned"
        );
        // The helper lived through its panic: the next call is shared again.
        let meeting = Meeting::new(2);
        assert_eq!(share(2, 8, |_| meeting.arrive()), 2);
    }

    /// Runs `call` on a thread of its own: Some(whether it panicked), or None if it had not
    /// returned after 20 s.
    fn panicked_within_20_s(call: impl FnOnce() + Send + 'static) -> Option<bool> {
        let (sender, receiver) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(call));
            let _ = sender.send(outcome.is_err());
        });
        receiver
            .recv_timeout(std::time::Duration::from_secs(20))
            .ok()
    }

    #[test]
    fn a_panic_in_map_or_done_is_raised_and_stops_the_other_workers() {
        let pause = std::time::Duration::from_millis(50);
        for threads in [1, 2, 4] {
            // The piece that panics is slow, so the others fill the room ahead and wait for it.
            let in_map = panicked_within_20_s(move || {
                map_in_order(
                    100,
                    threads,
                    2,
                    |i| {
                        if i == 0 {
                            std::thread::sleep(pause);
                            panic!("piece 0");
                        }
                        i
                    },
                    |_, _| true,
                )
            });
            assert_eq!(in_map, Some(true), "map, {threads} threads");
            let in_done = panicked_within_20_s(move || {
                map_in_order(100, threads, 2, |i| i, |i, _| i != 3 || panic!("result 3"))
            });
            assert_eq!(in_done, Some(true), "done, {threads} threads");
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_forked_child_counts_the_fork_and_makes_its_own_value() {
        static VALUE: PerProcess<Mutex<u32>> = PerProcess::new(|| Mutex::new(7));
        let parents = VALUE.get();
        *parents.lock().unwrap() = 8;
        let forks = FORKS.load(Ordering::Acquire);
        // Held across the fork, as a busy thread would hold it: the child must not wait for it.
        let held = parents.lock().unwrap();
        // SAFETY: the child only reads atomics and locks a fresh mutex, then `_exit`s; an alarm
        // ends it should it wait.
        let child = unsafe { libc::fork() };
        assert!(child >= 0, "fork failed");
        if child == 0 {
            // SAFETY: alarm has no preconditions.
            unsafe { libc::alarm(10) };
            let own = VALUE.get();
            let fine = FORKS.load(Ordering::Acquire) == forks + 1
                && !std::ptr::eq(own, parents)
                && *own.lock().unwrap() == 7;
            // SAFETY: ends the child at once, running nothing of the parent's.
            unsafe { libc::_exit(if fine { 0 } else { 1 }) };
        }
        drop(held);
        let mut status = 0;
        // SAFETY: waits for the child forked above; `status` is a valid int to write.
        assert_eq!(unsafe { libc::waitpid(child, &mut status, 0) }, child);
        assert!(
            libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
            "the child waited or saw its parent's value (status {status:#x})"
        );
        assert!(
            std::ptr::eq(VALUE.get(), parents),
            "the parent keeps its own"
        );
    }

    #[test]
    fn stopping_starts_no_further_piece() {
        let started = std::sync::atomic::AtomicUsize::new(0);
        let mut seen = 0;
        map_in_order(
            1000,
            4,
            2,
            |i| {
                started.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                i
            },
            |i, _| {
                seen += 1;
                i < 9
            },
        );
        assert_eq!(seen, 10);
        // At most `ahead` results wait, and one more piece per thread may be under way.
        assert!(started.into_inner() <= 10 + 2 + 4);
    }
}
