//! The FMI 2.0 C interface: every `fmi2*` function of the standard, exported unmangled from the
//! shared object (importers such as fmpy resolve all of them when they load it).
//!
//! Each function converts its C arguments, runs the call on the [`Instance`] inside
//! [`std::panic::catch_unwind`] and converts the result back. A panic is logged, returned as
//! `fmi2Error` and puts the instance into its error state ([`crate::instance::Phase::Error`]): the state may be
//! half-updated, so every later call but `fmi2Reset` and `fmi2FreeInstance` is refused (and
//! `fmi2FreeFMUstate`, which only releases the master's memory). Nothing unwinds into the importer.
//! A null array with a positive length is refused with a message, never read. An `fmi2Component` is a `Box<Instance>` turned into
//! a raw pointer by `fmi2Instantiate` and back by `fmi2FreeInstance`; an `fmi2FMUstate` likewise a
//! `Box<FmuState>`. There are no globals: instances are independent.
//!
//! Messages go to the importer's logger with the format `"%s"` and the text as its argument (the
//! logger is variadic; a `%` in a message must never be read as a format).
//!
//! Model Exchange is not offered: its functions exist (so that the library loads everywhere) and
//! return `fmi2Error`.
//!
//! # Safety
//!
//! The functions are `unsafe extern "C"`: the caller (an FMI importer) must follow the FMI 2.0
//! standard: a component pointer from `fmi2Instantiate` not yet freed, arrays of the given length,
//! NUL-terminated strings, and no concurrent calls on one instance.
#![allow(clippy::missing_safety_doc)]
// the standard's function names
#![allow(non_snake_case)]

pub(crate) mod lifecycle;
mod model_exchange;
pub(crate) mod pointers;
pub(crate) mod state;
mod status;
pub(crate) mod values;

use std::ffi::{c_char, c_int, c_uint, c_void, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::instance::{Instance, Status, LIVE_PHASES};

pub(crate) type Component = *mut c_void;
pub(crate) type FmuStatePtr = *mut c_void;
pub(crate) type ValueReference = c_uint;
type Real = f64;
type Integer = c_int;
type Boolean = c_int;
type FmiString = *const c_char;
type Byte = c_char;

/// `fmi2CallbackLogger`: variadic, called here with `"%s"` and one string.
type Logger = unsafe extern "C" fn(*mut c_void, FmiString, c_int, FmiString, FmiString, ...);

/// `fmi2CallbackFunctions` (only the logger is used; the other fields give the layout).
#[repr(C)]
#[allow(dead_code)]
pub struct CallbackFunctions {
    logger: Option<Logger>,
    allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    step_finished: Option<unsafe extern "C" fn(*mut c_void, c_int)>,
    component_environment: *mut c_void,
}

/// Text for C: interior NULs (which C cannot carry) become spaces.
pub(crate) fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).expect("no NUL left")
}

/// A log sink calling the importer's logger with `"%s"`.
fn log_sink(logger: Option<Logger>, env: *mut c_void, name: &str) -> crate::instance::LogSink {
    let name = c_text(name);
    Box::new(move |status: Status, category: &str, message: &str| {
        if let Some(logger) = logger {
            let (category, message) = (c_text(category), c_text(message));
            // SAFETY: the logger is the importer's fmi2CallbackLogger and `env` its component
            // environment; every string is NUL-terminated and outlives the call, and the one
            // variadic argument matches the format "%s".
            unsafe {
                logger(
                    env,
                    name.as_ptr(),
                    status as c_int,
                    category.as_ptr(),
                    c"%s".as_ptr(),
                    message.as_ptr(),
                )
            };
        }
    })
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

/// Runs `f` on the instance behind `c` in whatever phase it is: `fmi2Error` for a null component; a
/// caught panic is logged, returned as `fmi2Error` and puts the instance into its error state.
pub(crate) fn with_instance_in_any_state(c: Component, what: &str, f: impl FnOnce(&mut Instance) -> Status) -> c_int {
    if c.is_null() {
        return Status::Error as c_int;
    }
    let ptr = c.cast::<Instance>();
    // SAFETY: a non-null component is a live `Box<Instance>` from fmi2Instantiate (the caller's
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
