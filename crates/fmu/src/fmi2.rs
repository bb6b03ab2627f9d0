//! The FMI 2.0 C interface of `PendulumFem`: every `fmi2*` function of the standard, exported
//! unmangled from the shared object (importers such as fmpy resolve all of them when they load
//! it), each a thin adapter onto the shared implementation (module `ffi`) and the [`Instance`]:
//! it names itself and converts FMI 2.0's types (`fmi2Boolean` as `int`, `fmi2Byte` buffers).
//!
//! Messages go to the importer's logger with the format `"%s"` and the text as its argument (the
//! logger is variadic; a `%` in a message must never be read as a format).
//!
//! Model Exchange is not offered: its functions exist (so that the library loads everywhere) and
//! return `fmi2Error` with a logged message.
//!
//! # Safety
//!
//! The functions are `unsafe extern "C"`: the caller (an FMI importer) must follow the FMI 2.0
//! standard: a component pointer from `fmi2Instantiate` not yet freed, arrays of the given length,
//! NUL-terminated strings, and no concurrent calls on one instance.
#![allow(clippy::missing_safety_doc)]
// the standard's function names
#![allow(non_snake_case)]

mod lifecycle;
mod model_exchange;
mod state;
mod status;
mod values;

use std::ffi::{c_char, c_int, c_void};

use crate::ffi::{c_text, FmiString};
use crate::instance::{LogSink, Status};

// only named in the documentation's links
#[cfg(doc)]
use crate::instance::Instance;

type Real = f64;
type Integer = c_int;
/// `fmi2Boolean`: an `int`, any non-zero value true.
type Boolean = c_int;
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

/// A log sink calling the importer's logger with `"%s"`.
fn log_sink(logger: Option<Logger>, env: *mut c_void, name: &str) -> LogSink {
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
