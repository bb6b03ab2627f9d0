//! Reading and writing variable values, for both FMI versions: the getters and setters of this
//! FMU's types (FMI 2.0's `Real`, `Integer`, `Boolean`; FMI 3.0's `Float64`, `Int32`, `Boolean`),
//! each value converted to and from the instance's `f64`, and the answer of a getter or setter of a
//! type the FMU has no variables of.

use std::ffi::c_int;

use super::pointers::{check_arrays, slice, slice_mut};
use super::{with_instance, Component, ValueReference};
use crate::instance::{Status, GET_PHASES, SET_PHASES};
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
        // SAFETY: `vr` and `value` are arrays of `nvr` elements (the caller's contract; checked non-null).
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
        // SAFETY: `vr` and `value` are arrays of `nvr` elements (the caller's contract; checked non-null).
        let (vrs, values) = unsafe { (slice(vr, nvr), slice(value, nvr)) };
        let values: Vec<f64> = values.iter().map(|&v| convert(v)).collect();
        inst.set(kind, vrs, &values)
    })
}

/// A getter or setter of a type this FMU has no variables of (`get`: a getter; `arrays`: the
/// importer's arrays by name, whether each is null): after the phase and null-array checks, `OK`
/// for no value references, else `Error` with the message `"{what}: {why()}"`.
pub(crate) fn no_values(
    c: Component,
    what: &str,
    get: bool,
    n: usize,
    arrays: &[(&str, bool)],
    why: impl FnOnce() -> String,
) -> c_int {
    with_instance(c, what, |inst| {
        let phases = if get { GET_PHASES } else { SET_PHASES };
        if let Err(status) = inst.check_phase(what, phases) {
            return status;
        }
        if let Err(status) = check_arrays(inst, what, n, arrays) {
            return status;
        }
        if n == 0 {
            return Status::Ok;
        }
        inst.error(&format!("{what}: {}", why()))
    })
}
