//! The exported `fmi2Get*Status` functions: the last successful time and the terminated flag; every
//! other status is `fmi2Discard` (`fmi2DoStep` never returns `fmi2Pending`).

use std::ffi::c_int;

use super::{Boolean, FmiString, Integer, Real};
use crate::ffi::{with_instance, Component};
use crate::instance::{Phase, Status};

/// The phases in which the `fmi2Get*Status` functions answer.
const STATUS_PHASES: &[Phase] = &[Phase::StepMode, Phase::Terminated];

const FMI2_LAST_SUCCESSFUL_TIME: c_int = 2;
const FMI2_TERMINATED: c_int = 3;

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(c: Component, _kind: c_int, _value: *mut c_int) -> c_int {
    // fmi2DoStep never returns fmi2Pending, so there is no asynchronous status to ask for
    with_instance(c, "fmi2GetStatus", |inst| {
        match inst.check_phase("fmi2GetStatus", STATUS_PHASES) {
            Ok(()) => Status::Discard,
            Err(status) => status,
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut Real) -> c_int {
    with_instance(c, "fmi2GetRealStatus", |inst| {
        if let Err(status) = inst.check_phase("fmi2GetRealStatus", STATUS_PHASES) {
            return status;
        }
        if kind != FMI2_LAST_SUCCESSFUL_TIME || value.is_null() {
            return Status::Discard;
        }
        // SAFETY: a writable fmi2Real (the caller's contract).
        unsafe { *value = inst.time() };
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(c: Component, _kind: c_int, _value: *mut Integer) -> c_int {
    with_instance(c, "fmi2GetIntegerStatus", |inst| {
        match inst.check_phase("fmi2GetIntegerStatus", STATUS_PHASES) {
            Ok(()) => Status::Discard,
            Err(status) => status,
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(c: Component, kind: c_int, value: *mut Boolean) -> c_int {
    with_instance(c, "fmi2GetBooleanStatus", |inst| {
        if let Err(status) = inst.check_phase("fmi2GetBooleanStatus", STATUS_PHASES) {
            return status;
        }
        if kind != FMI2_TERMINATED || value.is_null() {
            return Status::Discard;
        }
        // SAFETY: a writable fmi2Boolean (the caller's contract).
        unsafe { *value = 0 };
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(c: Component, _kind: c_int, _value: *mut FmiString) -> c_int {
    with_instance(c, "fmi2GetStringStatus", |inst| {
        match inst.check_phase("fmi2GetStringStatus", STATUS_PHASES) {
            Ok(()) => Status::Discard,
            Err(status) => status,
        }
    })
}
