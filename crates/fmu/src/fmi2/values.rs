//! The exported FMI 2.0 functions that read and write variable values (`fmi2Get*`, `fmi2Set*`):
//! the shared getters and setters (module `ffi::values`) with FMI 2.0's types, and the derivative
//! functions this FMU does not provide (refused with a message).

use std::ffi::c_int;

use super::{Boolean, FmiString, Integer, Real};
use crate::ffi::lifecycle::refused;
use crate::ffi::values::{get_values, no_values, set_values};
use crate::ffi::{Component, ValueReference};
use crate::variables::Kind;

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(c: Component, vr: *const ValueReference, nvr: usize, value: *mut Real) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { get_values(c, "fmi2GetReal", Kind::Real, vr, nvr, value, |v| v) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut Integer,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { get_values(c, "fmi2GetInteger", Kind::Integer, vr, nvr, value, |v| v as Integer) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut Boolean,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe {
        get_values(c, "fmi2GetBoolean", Kind::Boolean, vr, nvr, value, |v| {
            Boolean::from(v != 0.0)
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut FmiString,
) -> c_int {
    let arrays = [("vr", vr.is_null()), ("value", value.is_null())];
    no_values(c, "fmi2GetString", true, nvr, &arrays, || {
        "this FMU has no String variables".into()
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(c: Component, vr: *const ValueReference, nvr: usize, value: *const Real) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { set_values(c, "fmi2SetReal", Kind::Real, vr, nvr, value, |v| v) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const Integer,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { set_values(c, "fmi2SetInteger", Kind::Integer, vr, nvr, value, f64::from) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const Boolean,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe {
        set_values(c, "fmi2SetBoolean", Kind::Boolean, vr, nvr, value, |v| {
            f64::from(u8::from(v != 0))
        })
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: Component,
    vr: *const ValueReference,
    nvr: usize,
    value: *const FmiString,
) -> c_int {
    let arrays = [("vr", vr.is_null()), ("value", value.is_null())];
    no_values(c, "fmi2SetString", false, nvr, &arrays, || {
        "this FMU has no String variables".into()
    })
}

refused! {
    fmi2GetDirectionalDerivative(
        _unknown: *const ValueReference,
        _n_unknown: usize,
        _known: *const ValueReference,
        _n_known: usize,
        _dv_known: *const Real,
        _dv_unknown: *mut Real
    ) => "not provided (providesDirectionalDerivative = false)";
    fmi2SetRealInputDerivatives(
        _vr: *const ValueReference,
        _nvr: usize,
        _order: *const Integer,
        _value: *const Real
    ) => "inputs are held constant (canInterpolateInputs = false)";
    fmi2GetRealOutputDerivatives(
        _vr: *const ValueReference,
        _nvr: usize,
        _order: *const Integer,
        _value: *mut Real
    ) => "not provided (maxOutputDerivativeOrder = 0)";
}
