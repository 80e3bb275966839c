//! One way to share work among the cores, for every part that does: the row reader, the
//! positions export, `info FOLDER` and the FK benchmark. Workers take the next piece of work
//! until none is left; results go on in the pieces' order.

use std::collections::BTreeMap;
use std::sync::{Condvar, Mutex, PoisonError};

/// Runs `worker` on `threads` threads, this one among them, and returns when every one has
/// returned. Each worker takes its own work from whatever state they share.
pub fn on_threads(threads: usize, worker: impl Fn() + Sync) {
    if threads <= 1 {
        worker();
        return;
    }
    std::thread::scope(|scope| {
        for _ in 1..threads {
            scope.spawn(&worker);
        }
        worker();
    });
}

/// What the workers of [`map_in_order`] share.
struct Order<R, D> {
    /// The next index to hand out, and the next to hand to `done`.
    claimed: usize,
    emitted: usize,
    /// Results that wait for an earlier one.
    waiting: BTreeMap<usize, R>,
    done: D,
    stopped: bool,
}

/// Computes `map(i)` for every `i` in `0..count` on `threads` threads, each taking the next index,
/// and hands the results to `done(i, result)` in index order: each as soon as it and every
/// earlier one are ready, so output can stream while later pieces are computed. No more than
/// `ahead` results wait for an earlier one (workers pause instead), which bounds the memory
/// however slow one piece is. `done` returns false to stop: no further piece is started.
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
        done,
        stopped: false,
    });
    let turn = Condvar::new();
    let lock = || state.lock().unwrap_or_else(PoisonError::into_inner);
    on_threads(threads.clamp(1, count.max(1)), || {
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
            loop {
                let next = order.emitted;
                let Some(result) = order.waiting.remove(&next) else {
                    break;
                };
                order.emitted += 1;
                if !order.stopped && !(order.done)(next, result) {
                    order.stopped = true;
                }
            }
            turn.notify_all();
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
