//! An instance's life, for both FMI versions: instantiation (the token check), freeing, debug
//! logging, reset, and the refusal of a function the FMU does not offer.

use std::ffi::c_int;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::pointers::text;
use super::{with_instance, with_instance_in_any_state, Component, FmiString};
use crate::instance::{Instance, Status};
use crate::variables::guid;

/// Instantiates: reads the instance name and the token the importer passed (`fmi2Instantiate`'s
/// GUID, `fmi3InstantiateCoSimulation`'s `instantiationToken`), makes the instance with `make`
/// from the name (`None`: refused, the reason logged through the instance), and returns it as a
/// handle when the token is this binary's or empty (not given). Otherwise null, logged with `what`
/// (the function and the argument) in front; a panic also gives null.
///
/// # Safety
/// `instance_name` and `token` are null or NUL-terminated.
pub(crate) unsafe fn instantiate(
    what: &str,
    instance_name: FmiString,
    token: FmiString,
    make: impl FnOnce(&str) -> Option<Instance>,
) -> Component {
    let made = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's contract.
        let (name, wanted) = unsafe { (text(instance_name), text(token)) };
        let inst = make(&name)?;
        if !wanted.is_empty() && wanted != guid() {
            inst.error(&format!(
                "{what} {wanted} is not this binary's {} (a modelDescription.xml of another build)",
                guid()
            ));
            return None;
        }
        Some(Box::into_raw(Box::new(inst)).cast())
    }));
    made.ok().flatten().unwrap_or(std::ptr::null_mut())
}

/// Frees an instance (`fmi2FreeInstance`, `fmi3FreeInstance`).
///
/// # Safety
/// `c` is null or an instance handle of this library not yet freed.
pub(crate) unsafe fn free_instance(c: Component) {
    if !c.is_null() {
        // SAFETY: a handle from the instantiation, freed once (the caller's contract).
        let inst = unsafe { Box::from_raw(c.cast::<Instance>()) };
        let _ = catch_unwind(AssertUnwindSafe(move || drop(inst)));
    }
}

/// Turns debug logging (the non-error messages) on or off (`fmi2SetDebugLogging`,
/// `fmi3SetDebugLogging`; the categories are not used).
pub(crate) fn set_debug_logging(c: Component, what: &str, logging_on: bool) -> c_int {
    with_instance(c, what, |inst| {
        inst.logging_on = logging_on;
        Status::Ok
    })
}

/// Back to the instantiated state with the start values, from every phase, the error state
/// included (`fmi2Reset`, `fmi3Reset`).
pub(crate) fn reset(c: Component, what: &str) -> c_int {
    with_instance_in_any_state(c, what, |inst| {
        inst.reset();
        Status::Ok
    })
}

/// Refuses `what` with `Error` and the message `"{what}: {why}"`: a function this FMU does not
/// offer, exported so that every importer loads the library.
pub(crate) fn refuse(c: Component, what: &str, why: &str) -> c_int {
    with_instance(c, what, |inst| inst.error(&format!("{what}: {why}")))
}

/// Exports each function, refused with `Error` and the message `"{name}: {why}"` ([`refuse`]):
/// `name(args) => why;`, the instance handle first and implied.
macro_rules! refused {
    ($($name:ident($($arg:ident: $t:ty),*) => $why:expr;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(instance: $crate::ffi::Component, $($arg: $t),*) -> std::ffi::c_int {
            $crate::ffi::lifecycle::refuse(instance, stringify!($name), $why)
        }
    )*};
}
pub(crate) use refused;
