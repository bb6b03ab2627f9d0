//! The exported FMI functions that read and write variable values (`fmi2Get*`, `fmi2Set*`), and
//! the derivative functions this FMU does not provide (refused with a message).

use std::ffi::c_int;

use super::pointers::{check_arrays, slice, slice_mut};
use super::with_instance;
use super::{Boolean, Component, FmiString, Integer, Real, ValueReference};
use crate::instance::{Status, GET_PHASES};
use crate::variables::Kind;

/// Reads `nvr` values of `kind` and converts them with `convert` into `value` (`what`: the function).
///
/// # Safety
/// `vr` and `value` are null or arrays of `nvr` elements.
pub(crate) unsafe fn get_values<T>(
    c: Component,
    what: &str,
    kind: Kind,
    vr: *const ValueReference,
    nvr: usize,
    value: *mut T,
    convert: impl Fn(f64) -> T,
) -> c_int {
    with_instance(c, what, |inst| {
        if let Err(status) = check_arrays(inst, what, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]) {
            return status;
        }
        // SAFETY: `vr` and `value` are arrays of `nvr` elements (FMI 2.0, 2.1.7).
        let (vrs, out) = unsafe { (slice(vr, nvr), slice_mut(value, nvr)) };
        let mut buffer = vec![0.0; nvr];
        let status = inst.get(kind, vrs, &mut buffer);
        if status == Status::Ok {
            for (o, &b) in out.iter_mut().zip(&buffer) {
                *o = convert(b);
            }
        }
        status
    })
}

/// Writes `nvr` values of `kind`, converted with `convert` (`what`: the function).
///
/// # Safety
/// `vr` and `value` are null or arrays of `nvr` elements.
pub(crate) unsafe fn set_values<T: Copy>(
    c: Component,
    what: &str,
    kind: Kind,
    vr: *const ValueReference,
    nvr: usize,
    value: *const T,
    convert: impl Fn(T) -> f64,
) -> c_int {
    with_instance(c, what, |inst| {
        if let Err(status) = check_arrays(inst, what, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]) {
            return status;
        }
        // SAFETY: `vr` and `value` are arrays of `nvr` elements (FMI 2.0, 2.1.7).
        let (vrs, values) = unsafe { (slice(vr, nvr), slice(value, nvr)) };
        let values: Vec<f64> = values.iter().map(|&v| convert(v)).collect();
        inst.set(kind, vrs, &values)
    })
}

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
    const WHAT: &str = "fmi2GetString";
    with_instance(c, WHAT, |inst| {
        let checked = inst
            .check_phase(WHAT, GET_PHASES)
            .and_then(|()| check_arrays(inst, WHAT, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]));
        match (checked, nvr) {
            (Err(status), _) => status,
            (Ok(()), 0) => Status::Ok,
            (Ok(()), _) => inst.error("fmi2GetString: this FMU has no String variables"),
        }
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
    const WHAT: &str = "fmi2SetString";
    with_instance(c, WHAT, |inst| {
        let checked = inst
            .check_phase(WHAT, crate::instance::SET_PHASES)
            .and_then(|()| check_arrays(inst, WHAT, nvr, &[("vr", vr.is_null()), ("value", value.is_null())]));
        match (checked, nvr) {
            (Err(status), _) => status,
            (Ok(()), 0) => Status::Ok,
            (Ok(()), _) => inst.error("fmi2SetString: this FMU has no String variables"),
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Component,
    _unknown: *const ValueReference,
    _n_unknown: usize,
    _known: *const ValueReference,
    _n_known: usize,
    _dv_known: *const Real,
    _dv_unknown: *mut Real,
) -> c_int {
    with_instance(c, "fmi2GetDirectionalDerivative", |inst| {
        inst.error("fmi2GetDirectionalDerivative: not provided (providesDirectionalDerivative = false)")
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _nvr: usize,
    _order: *const Integer,
    _value: *const Real,
) -> c_int {
    with_instance(c, "fmi2SetRealInputDerivatives", |inst| {
        inst.error("fmi2SetRealInputDerivatives: inputs are held constant (canInterpolateInputs = false)")
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Component,
    _vr: *const ValueReference,
    _nvr: usize,
    _order: *const Integer,
    _value: *mut Real,
) -> c_int {
    with_instance(c, "fmi2GetRealOutputDerivatives", |inst| {
        inst.error("fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder = 0)")
    })
}
