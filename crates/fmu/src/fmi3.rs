//! The FMI 3.0 C interface of `PendulumFem3`: every function of `fmi3Functions.h`, exported
//! unmangled from the same shared object as the `fmi2*` ones (the names do not clash), over the
//! same [`Instance`] (made by `fmi3InstantiateCoSimulation` with its [`crate::instance::Api::Fmi3`]
//! face: FMI 3.0 names in messages, event mode, impacts as events; see [`crate::instance`]).
//!
//! Each function is a thin adapter onto the implementation it shares with the FMI 2.0 functions
//! (module `ffi`: the panic guard, instantiation, values, FMU states, refusals): a caught panic
//! returns `fmi3Error` and puts the instance into its error state; a null array with a positive
//! length is refused. What FMI 3.0 adds: typed getters and setters with a value count
//! (`Float64`, `Int32`, `Boolean` are this FMU's types; every other type's answers `fmi3Error` for
//! any value reference), `fmi3Boolean` as one byte (C99 `bool`), the non-variadic logger
//! `fmi3LogMessageCallback`, event mode and early return in `fmi3DoStep`.
//! Model Exchange, Scheduled Execution, clocks, configuration mode and derivatives are not
//! offered: their functions exist (fmpy resolves every symbol) and return `fmi3Error` with a
//! logged message (the instantiation functions return null).
//!
//! # Safety
//!
//! The functions are `unsafe extern "C"`: the caller (an FMI importer) must follow the FMI 3.0
//! standard: an instance pointer from `fmi3InstantiateCoSimulation` not yet freed, arrays of the
//! given length, NUL-terminated strings, and no concurrent calls on one instance.
#![allow(clippy::missing_safety_doc)]
// the standard's function names
#![allow(non_snake_case)]

mod lifecycle;
mod state;
mod unsupported;
mod values;

use std::ffi::{c_int, c_void};

use crate::ffi::{c_text, FmiString};
use crate::instance::{LogSink, Status};

// only named in the documentation's links
#[cfg(doc)]
use crate::instance::Instance;

/// `fmi3Instance`.
type Instance3 = crate::ffi::Component;
/// `fmi3Boolean` behind a pointer: C99 `bool`, one byte, read as a byte so that any value is safe.
type Boolean = u8;

/// `fmi3LogMessageCallback`.
type LogMessage = unsafe extern "C" fn(*mut c_void, c_int, FmiString, FmiString);

/// A log sink calling the importer's `logMessage`.
fn log_sink(logger: Option<LogMessage>, env: *mut c_void) -> LogSink {
    Box::new(move |status: Status, category: &str, message: &str| {
        if let Some(logger) = logger {
            let (category, message) = (c_text(category), c_text(message));
            // SAFETY: the importer's fmi3LogMessageCallback with its instance environment; both
            // strings are NUL-terminated and outlive the call.
            unsafe { logger(env, status as c_int, category.as_ptr(), message.as_ptr()) };
        }
    })
}

/// Writes `value` to an importer's out-argument when it is not null.
///
/// # Safety
/// `p` is null or valid for a write of `T`.
unsafe fn put<T>(p: *mut T, value: T) {
    if !p.is_null() {
        // SAFETY: the caller's contract.
        unsafe { p.write(value) };
    }
}
