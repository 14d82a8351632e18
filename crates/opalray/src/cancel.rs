//! Cooperative cancellation: a flag a caller sets when it stops waiting for a stage (a time
//! limit passed, Ctrl-C), looked at by the stages' drivers at coarse grain so that the
//! stopped work returns within a fraction of a second and frees its cores.
//!
//! A caller runs the work inside [`Cancel::scope`]; a driver takes the token of its thread
//! with [`Cancel::current`] before it fans out over rayon (whose workers do not share the
//! caller's thread) and looks at it once per grain, row, tile or pass
//! ([`Cancel::is_cancelled`]: one relaxed load). A skipped row leaves its pixels unwritten:
//! the frame of a cancelled render is never shown, [`Prepared::render_cancellable`]
//! (crate::render::Prepared::render_cancellable) returns [`Error::Cancelled`] instead. Work
//! not run under a scope (and a driver already inside a rayon task) is never cancelled, and
//! a token never set changes no byte of any image.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crate::error::{Error, Result};

thread_local! {
    /// The token of the work this thread runs, if any.
    static CURRENT: RefCell<Option<Cancel>> = const { RefCell::new(None) };
}

/// A shared stop flag: clones share it; once set it stays set.
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token not set.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Stop the work that looks at this token (from any thread).
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether [`Cancel::cancel`] has been called: one relaxed load, for a driver's loop.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// `Err(Error::Cancelled)` once set: for a stage between its steps.
    pub fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }

    /// Run `work` on this thread with `self` as its [current](Cancel::current) token (the
    /// previous one back afterwards, even if `work` panics).
    pub fn scope<T>(&self, work: impl FnOnce() -> T) -> T {
        struct Restore(Option<Cancel>);
        impl Drop for Restore {
            fn drop(&mut self) {
                let previous = self.0.take();
                CURRENT.with(|c| *c.borrow_mut() = previous);
            }
        }
        let previous = CURRENT.with(|c| c.borrow_mut().replace(self.clone()));
        let _restore = Restore(previous);
        work()
    }

    /// The token of the work this thread runs ([`Cancel::scope`]), or one never set.
    pub fn current() -> Cancel {
        CURRENT.with(|c| c.borrow().clone()).unwrap_or_default()
    }

    /// [`Cancel::check`] on this thread's current token.
    pub fn check_current() -> Result<()> {
        CURRENT.with(|c| c.borrow().as_ref().map_or(Ok(()), Cancel::check))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scope_gives_its_token_to_its_thread_and_restores_the_previous() {
        let outer = Cancel::new();
        let inner = Cancel::new();
        outer.scope(|| {
            inner.scope(|| {
                inner.cancel();
                assert!(Cancel::current().is_cancelled());
                assert!(matches!(Cancel::check_current(), Err(Error::Cancelled)));
            });
            assert!(!Cancel::current().is_cancelled());
            assert!(Cancel::check_current().is_ok());
        });
        assert!(!Cancel::current().is_cancelled());
    }

    #[test]
    fn another_thread_sees_no_token_unless_handed_one() {
        let token = Cancel::new();
        token.cancel();
        token.scope(|| {
            let seen = Cancel::current();
            let other = std::thread::spawn(|| Cancel::current().is_cancelled());
            assert!(!other.join().unwrap());
            let handed = std::thread::spawn(move || seen.is_cancelled());
            assert!(handed.join().unwrap());
        });
    }
}
