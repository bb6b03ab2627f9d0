//! Running a step on the pool that computes its elements (rayon's), with the pool's other threads
//! kept awake for the step's duration.
//!
//! A step of the full model alternates short parallel passes over the elements (the discrete
//! gradient at the guess and at the update, the next step's start data) with sequential parts
//! between them (the triangular solves, the mass products, the residual checks). Between two
//! passes rayon's idle threads go to sleep, and the next pass wakes them through the kernel (a
//! futex; on a virtual machine an inter-processor interrupt), a cost of the order of a pass itself
//! at short steps. So while a step runs, every other thread of the pool runs a job that waits for
//! work by spinning (taking any part of a pass the moment it is offered, [`rayon::yield_now`])
//! until the step is done, at most [`AWAKE_AT_MOST`]: for a longer step the wake-ups are a small
//! part and the threads sleep as before. The arithmetic is unchanged, so are the results, bit for
//! bit.
//!
//! The cost is CPU time: the spinning threads are busy for the whole step. Between steps they
//! sleep as before, so a master that computes between two steps has the cores to itself; a step
//! called from a thread of the pool (a sweep's cases, each on its own thread) spins nothing, and
//! neither do the steps of simulations stepped at the same time from several threads (a threaded
//! scheduler's tasks): a thread waiting inside one step could take another step's waiting job and
//! spin in it until that step ends, so with more than one step in flight the waiting jobs return
//! at once.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// The longest a thread spins waiting for the passes of one step.
const AWAKE_AT_MOST: Duration = Duration::from_millis(50);

/// Steps handed to the pool from outside and not yet done.
static IN_FLIGHT: AtomicUsize = AtomicUsize::new(0);

/// Runs `f` on a thread of the pool, handing it there from any other thread for its duration
/// (why: `Simulation::output_step`), with the pool's other threads spinning for its passes (see the
/// module doc). From a thread of the pool, `f` runs as it is.
pub(super) fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() {
        return f();
    }
    let done = AtomicBool::new(false);
    let _in_flight = InFlight::enter();
    rayon::scope(|scope| {
        let done = &done;
        // The waiting jobs sit at the bottom of this thread's queue, which other threads steal
        // from first: when `f` waits for a part of a pass that another thread took, every waiting
        // job was taken before it, so this thread never runs one nested in `f` (which would spin
        // until `f` is done: a deadlock but for the time limit).
        for _ in 1..rayon::current_num_threads() {
            scope.spawn(move |_| {
                let start = Instant::now();
                while !done.load(Ordering::Acquire)
                    && IN_FLIGHT.load(Ordering::Acquire) == 1
                    && start.elapsed() < AWAKE_AT_MOST
                {
                    if rayon::yield_now() != Some(rayon::Yield::Executed) {
                        std::hint::spin_loop();
                    }
                }
            });
        }
        let result = f();
        done.store(true, Ordering::Release);
        result
    })
}

/// A step counted in [`IN_FLIGHT`] while this lives (a step that panics is uncounted too).
struct InFlight;

impl InFlight {
    fn enter() -> Self {
        IN_FLIGHT.fetch_add(1, Ordering::AcqRel);
        Self
    }
}

impl Drop for InFlight {
    fn drop(&mut self) {
        IN_FLIGHT.fetch_sub(1, Ordering::AcqRel);
    }
}
