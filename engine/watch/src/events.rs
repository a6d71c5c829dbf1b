//! What a reloader tells its owner, kept in a queue of bounded length.
//!
//! In a running team nobody reads reload events (the log says it all); only tests and tools
//! do. An unbounded channel would keep every rejection of a long session, each with the
//! report and text it quotes, so the queue keeps the newest few and drops the oldest.

use std::collections::VecDeque;
use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// How many undelivered events a reloader keeps unless told otherwise.
pub const DEFAULT_EVENT_CAPACITY: usize = 16;

/// A queue of at most `capacity` items shared by a reloader (pushing) and its owner.
#[derive(Debug)]
pub struct Events<T> {
    queue: Mutex<Queue<T>>,
    arrived: Condvar,
}

#[derive(Debug)]
struct Queue<T> {
    items: VecDeque<T>,
    capacity: usize,
    pushed: u64,
    dropped: u64,
}

impl<T> Default for Events<T> {
    fn default() -> Self {
        Self::with_capacity(DEFAULT_EVENT_CAPACITY)
    }
}

impl<T> Events<T> {
    pub fn with_capacity(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Self {
            queue: Mutex::new(Queue {
                items: VecDeque::with_capacity(capacity),
                capacity,
                pushed: 0,
                dropped: 0,
            }),
            arrived: Condvar::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Queue<T>> {
        // A panic elsewhere while holding the lock leaves the queue itself intact.
        self.queue.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Adds `item`, dropping the oldest when full.
    pub fn push(&self, item: T) {
        let mut queue = self.lock();
        if queue.items.len() >= queue.capacity {
            queue.items.pop_front();
            queue.dropped += 1;
        }
        queue.items.push_back(item);
        queue.pushed += 1;
        drop(queue);
        self.arrived.notify_all();
    }

    /// A copy of the newest event not yet taken, leaving the queue as it is (a viewer's peek).
    pub fn newest(&self) -> Option<T>
    where
        T: Clone,
    {
        self.lock().items.back().cloned()
    }

    /// Every event not yet taken, oldest first.
    pub fn drain(&self) -> Vec<T> {
        self.lock().items.drain(..).collect()
    }

    /// Waits up to `timeout` for the next event.
    pub fn next(&self, timeout: Duration) -> Option<T> {
        let deadline = Instant::now() + timeout;
        let mut queue = self.lock();
        loop {
            if let Some(item) = queue.items.pop_front() {
                return Some(item);
            }
            let remaining = deadline.saturating_duration_since(Instant::now());
            if remaining.is_zero() {
                return None;
            }
            queue = self
                .arrived
                .wait_timeout(queue, remaining)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
    }

    /// Events waiting now (never more than the capacity).
    pub fn len(&self) -> usize {
        self.lock().items.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Events pushed since the start, taken or not.
    pub fn pushed(&self) -> u64 {
        self.lock().pushed
    }

    /// Events dropped unread because the queue was full.
    pub fn dropped(&self) -> u64 {
        self.lock().dropped
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn a_full_queue_drops_the_oldest() {
        let events = Events::with_capacity(3);
        for i in 0..1000 {
            events.push(i);
            assert!(events.len() <= 3);
        }
        assert_eq!((events.pushed(), events.dropped()), (1000, 997));
        assert_eq!(events.drain(), vec![997, 998, 999]);
        assert!(events.is_empty());
    }

    #[test]
    fn next_waits_for_a_push_from_another_thread() {
        let events = Arc::new(Events::default());
        assert_eq!(events.next(Duration::from_millis(10)), None);
        let pusher = Arc::clone(&events);
        let thread = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(30));
            pusher.push("reloaded");
        });
        assert_eq!(events.next(Duration::from_secs(5)), Some("reloaded"));
        thread.join().unwrap();
    }
}
