//! The C boundary both FMI versions share: one implementation of every call that FMI 2.0 and
//! FMI 3.0 have in common, over the [`Instance`]. The modules `fmi2` and `fmi3` export the
//! standard's functions as thin adapters onto it: each names itself and converts its version's
//! types (booleans, byte buffers, out-arguments, FMI 3.0's value counts); the checks, the messages
//! and the state changes are here and in [`Instance`], written once.
//!
//! Every call on an instance runs inside [`std::panic::catch_unwind`] ([`with_instance`]). A panic
//! is logged, returned as `Error` and puts the instance into its error state
//! ([`crate::instance::Phase::Error`]): the state may be half-updated, so every later call but
//! reset and freeing the instance is refused (and freeing an FMU state, which only releases the
//! master's memory). Nothing unwinds into the importer. A null array with a positive length is
//! refused with a message, never read. An instance handle (`fmi2Component`, `fmi3Instance`) is a
//! `Box<Instance>` turned into a raw pointer by the instantiation ([`lifecycle::instantiate`]) and
//! back by [`lifecycle::free_instance`]; an FMU state handle likewise a `Box<FmuState>`. There are
//! no globals: instances are independent.
//!
//! # Safety
//!
//! The functions that take pointers are `unsafe`: the caller (an adapter, for its importer) passes
//! an instance handle from the instantiation not yet freed, arrays of the given length and
//! NUL-terminated strings, and makes no concurrent calls on one instance.

pub(crate) mod lifecycle;
pub(crate) mod pointers;
pub(crate) mod state;
pub(crate) mod values;

use std::ffi::{c_char, c_int, c_uint, c_void, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::instance::{Instance, Status, LIVE_PHASES};

/// An instance handle: `fmi2Component`, `fmi3Instance`.
pub(crate) type Component = *mut c_void;
/// An FMU state handle: `fmi2FMUstate`, `fmi3FMUState`.
pub(crate) type FmuStatePtr = *mut c_void;
/// `fmi2ValueReference`, `fmi3ValueReference` (both `unsigned int`).
pub(crate) type ValueReference = c_uint;
/// `fmi2String`, `fmi3String`.
pub(crate) type FmiString = *const c_char;

/// Text for C: interior NULs (which C cannot carry) become spaces.
pub(crate) fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("no NUL left")
}

/// The panic payload as text.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Runs `f` on the instance behind `c` unless the instance is in its error state (then the call is
/// refused with the reason): see [`with_instance_in_any_state`].
pub(crate) fn with_instance(c: Component, what: &str, f: impl FnOnce(&mut Instance) -> Status) -> c_int {
    with_instance_in_any_state(c, what, |inst| match inst.check_phase(what, LIVE_PHASES) {
        Ok(()) => f(inst),
        Err(status) => status,
    })
}

/// Runs `f` on the instance behind `c` in whatever phase it is: `Error` for a null handle; a caught
/// panic is logged, returned as `Error` and puts the instance into its error state.
pub(crate) fn with_instance_in_any_state(c: Component, what: &str, f: impl FnOnce(&mut Instance) -> Status) -> c_int {
    if c.is_null() {
        return Status::Error as c_int;
    }
    let ptr = c.cast::<Instance>();
    // SAFETY: a non-null handle is a live `Box<Instance>` from the instantiation (the caller's
    // contract), used by one thread at a time; the borrow ends with the closure.
    let result = catch_unwind(AssertUnwindSafe(|| {
        let inst = unsafe { &mut *ptr };
        if let Some(message) = inst.test_panic.take() {
            panic!("{message}");
        }
        f(inst)
    }));
    match result {
        Ok(status) => status as c_int,
        Err(payload) => {
            let text = panic_text(payload.as_ref());
            // SAFETY: as above; the panicking borrow has ended.
            let inst = unsafe { &mut *ptr };
            inst.enter_error_state(format!("entered when {what} failed with an internal error: {text}"));
            let _ = catch_unwind(AssertUnwindSafe(|| {
                inst.error(&format!(
                    "{what}: internal error: {text}; the instance is now in the error state, which only \
                     {p}Reset or {p}FreeInstance leave",
                    p = inst.api.prefix()
                ))
            }));
            Status::Error as c_int
        }
    }
}
