//! A wall-clock budget and a cancellation flag for every solve run inside a scope.
//!
//! An observer design runs dozens of solves in loops that know nothing of time (a window
//! bisection, a gain refinement, a BMI alternation). Rather than thread a deadline through
//! every such call, the caller opens a scope with [`within`]; every interior-point solve
//! started on the same thread inside it checks [`exhausted`] once per iteration and, once the
//! budget is spent, stops with [`crate::Status::Interrupted`] at the best point it has. The
//! loops around it then end quickly (each further solve stops at its first iteration), and
//! the caller, which knows the budget ran out, reports so.
//!
//! Scopes nest: the inner scope runs to the earlier of the two deadlines, and a cancellation
//! of either flag stops it.

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long the solves of a scope may run, and a flag another thread may raise to stop them.
#[derive(Debug, Clone, Default)]
pub struct Budget {
    deadline: Option<Instant>,
    cancel: Vec<Arc<AtomicBool>>,
}

impl Budget {
    /// No limit.
    pub fn unlimited() -> Self {
        Self::default()
    }

    /// Until `limit` from now (`None`: no time limit).
    pub fn for_duration(limit: Option<Duration>) -> Self {
        Self {
            deadline: limit.map(|d| Instant::now() + d),
            cancel: Vec::new(),
        }
    }

    /// Until `deadline`.
    pub fn until(deadline: Instant) -> Self {
        Self {
            deadline: Some(deadline),
            cancel: Vec::new(),
        }
    }

    /// Also stops when `flag` is raised (e.g. by a signal handler or another thread).
    pub fn with_cancel(mut self, flag: Arc<AtomicBool>) -> Self {
        self.cancel.push(flag);
        self
    }

    /// The deadline, if any.
    pub fn deadline(&self) -> Option<Instant> {
        self.deadline
    }

    /// Whether the deadline has passed or a cancellation flag is raised.
    pub fn is_exhausted(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
            || self.cancel.iter().any(|c| c.load(Ordering::Relaxed))
    }

    /// Whether a cancellation flag (not the deadline) stopped the scope.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.iter().any(|c| c.load(Ordering::Relaxed))
    }

    /// The tighter of `self` and `outer`: the earlier deadline, every flag.
    fn nested_in(mut self, outer: &Budget) -> Self {
        self.deadline = match (self.deadline, outer.deadline) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        self.cancel.extend(outer.cancel.iter().cloned());
        self
    }
}

thread_local! {
    static CURRENT: RefCell<Budget> = RefCell::new(Budget::unlimited());
}

/// Runs `f` with `budget` (tightened by any enclosing scope) as the budget of every solve
/// started on this thread inside it; the enclosing budget is restored afterwards, also when
/// `f` panics.
pub fn within<R>(budget: Budget, f: impl FnOnce() -> R) -> R {
    struct Restore(Option<Budget>);
    impl Drop for Restore {
        fn drop(&mut self) {
            if let Some(b) = self.0.take() {
                CURRENT.with(|c| *c.borrow_mut() = b);
            }
        }
    }
    let outer = CURRENT.with(|c| c.borrow().clone());
    let inner = budget.nested_in(&outer);
    CURRENT.with(|c| *c.borrow_mut() = inner);
    let _restore = Restore(Some(outer));
    f()
}

/// The budget of the current scope on this thread.
pub fn current() -> Budget {
    CURRENT.with(|c| c.borrow().clone())
}

/// Whether the current scope's budget is spent (see [`Budget::is_exhausted`]).
pub fn exhausted() -> bool {
    CURRENT.with(|c| c.borrow().is_exhausted())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scopes_nest_to_the_earlier_deadline_and_restore_the_outer_one() {
        assert!(!exhausted());
        let soon = Instant::now() + Duration::from_millis(50);
        within(Budget::until(soon), || {
            assert_eq!(current().deadline(), Some(soon));
            within(
                Budget::for_duration(Some(Duration::from_secs(3600))),
                || {
                    assert_eq!(current().deadline(), Some(soon));
                },
            );
            within(Budget::unlimited(), || {
                assert_eq!(current().deadline(), Some(soon))
            });
            std::thread::sleep(Duration::from_millis(60));
            assert!(exhausted());
        });
        assert!(!exhausted());
        assert_eq!(current().deadline(), None);
    }

    #[test]
    fn a_raised_flag_exhausts_the_scope_and_its_inner_scopes() {
        let flag = Arc::new(AtomicBool::new(false));
        within(Budget::unlimited().with_cancel(flag.clone()), || {
            within(Budget::unlimited(), || {
                assert!(!exhausted());
                flag.store(true, Ordering::Relaxed);
                assert!(exhausted());
                assert!(current().is_cancelled());
            })
        });
        assert!(!exhausted());
    }

    #[test]
    fn the_outer_budget_is_restored_after_a_panic() {
        let r = std::panic::catch_unwind(|| {
            within(Budget::until(Instant::now()), || panic!("inside"));
        });
        assert!(r.is_err());
        assert!(!exhausted());
    }
}
