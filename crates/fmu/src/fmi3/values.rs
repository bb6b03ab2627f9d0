//! The exported FMI 3.0 getters and setters. `Float64`, `Int32` and `Boolean` are this FMU's types
//! (the FMI 2.0 `Real`, `Integer` and `Boolean` of the one variable table) and go through the
//! shared getters and setters (module `ffi::values`) once the value count is checked; every other
//! type's functions answer `fmi3Error` with a message for any value reference (there is no variable
//! of that type), `fmi3OK` for none.

use std::ffi::c_int;

use super::{Boolean, FmiString, Instance3};
use crate::ffi::values::{get_values, no_values, set_values};
use crate::ffi::{with_instance, ValueReference};
use crate::variables::Kind;

/// `Err(fmi3Error)`, logged, unless there are as many values as value references (every variable
/// of this FMU is a scalar).
fn check_counts(instance: Instance3, what: &str, n_vr: usize, n_values: usize) -> Result<(), c_int> {
    if n_vr == n_values {
        return Ok(());
    }
    Err(with_instance(instance, what, |inst| {
        inst.error(&format!(
            "{what}: nValues = {n_values} for nValueReferences = {n_vr}; every variable is a scalar, so they must be equal"
        ))
    }))
}

macro_rules! typed_accessors {
    ($($get:ident, $set:ident, $kind:expr, $t:ty, $to:expr, $from:expr;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: Instance3,
            vr: *const ValueReference,
            n_vr: usize,
            values: *mut $t,
            n_values: usize,
        ) -> c_int {
            if let Err(status) = check_counts(instance, stringify!($get), n_vr, n_values) {
                return status;
            }
            // SAFETY: forwarded caller contract.
            unsafe { get_values(instance, stringify!($get), $kind, vr, n_vr, values, $to) }
        }

        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: Instance3,
            vr: *const ValueReference,
            n_vr: usize,
            values: *const $t,
            n_values: usize,
        ) -> c_int {
            if let Err(status) = check_counts(instance, stringify!($set), n_vr, n_values) {
                return status;
            }
            // SAFETY: forwarded caller contract.
            unsafe { set_values(instance, stringify!($set), $kind, vr, n_vr, values, $from) }
        }
    )*};
}

typed_accessors! {
    fmi3GetFloat64, fmi3SetFloat64, Kind::Real, f64, |v| v, |v| v;
    fmi3GetInt32, fmi3SetInt32, Kind::Integer, i32, |v| v as i32, f64::from;
    fmi3GetBoolean, fmi3SetBoolean, Kind::Boolean, Boolean, |v| u8::from(v != 0.0), |v: Boolean| f64::from(u8::from(v != 0));
}

/// The answer of a getter or setter of a type this FMU has no variables of (`get`: a getter):
/// `fmi3OK` for no value references, else `fmi3Error` naming the first.
fn no_variables_of_type(instance: Instance3, what: &str, get: bool, vr: *const ValueReference, n_vr: usize) -> c_int {
    let why = || {
        // SAFETY: asked for only with `n_vr > 0` value references, checked non-null.
        let first = unsafe { *vr };
        format!(
            "no variable of this type has value reference {first}; this FMU's variables are Float64, Int32 and \
             Boolean"
        )
    };
    no_values(instance, what, get, n_vr, &[("valueReferences", vr.is_null())], why)
}

macro_rules! absent_accessors {
    ($($get:ident, $set:ident, $t:ty;)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $get(
            instance: Instance3,
            vr: *const ValueReference,
            n_vr: usize,
            _values: *mut $t,
            _n_values: usize,
        ) -> c_int {
            no_variables_of_type(instance, stringify!($get), true, vr, n_vr)
        }

        #[no_mangle]
        pub unsafe extern "C" fn $set(
            instance: Instance3,
            vr: *const ValueReference,
            n_vr: usize,
            _values: *const $t,
            _n_values: usize,
        ) -> c_int {
            no_variables_of_type(instance, stringify!($set), false, vr, n_vr)
        }
    )*};
}

absent_accessors! {
    fmi3GetFloat32, fmi3SetFloat32, f32;
    fmi3GetInt8, fmi3SetInt8, i8;
    fmi3GetUInt8, fmi3SetUInt8, u8;
    fmi3GetInt16, fmi3SetInt16, i16;
    fmi3GetUInt16, fmi3SetUInt16, u16;
    fmi3GetUInt32, fmi3SetUInt32, u32;
    fmi3GetInt64, fmi3SetInt64, i64;
    fmi3GetUInt64, fmi3SetUInt64, u64;
    fmi3GetString, fmi3SetString, FmiString;
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    instance: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    _value_sizes: *mut usize,
    _values: *mut *const u8,
    _n_values: usize,
) -> c_int {
    no_variables_of_type(instance, "fmi3GetBinary", true, vr, n_vr)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    instance: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    _value_sizes: *const usize,
    _values: *const *const u8,
    _n_values: usize,
) -> c_int {
    no_variables_of_type(instance, "fmi3SetBinary", false, vr, n_vr)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetClock(
    instance: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    _values: *mut Boolean,
) -> c_int {
    no_variables_of_type(instance, "fmi3GetClock", true, vr, n_vr)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetClock(
    instance: Instance3,
    vr: *const ValueReference,
    n_vr: usize,
    _values: *const Boolean,
) -> c_int {
    no_variables_of_type(instance, "fmi3SetClock", false, vr, n_vr)
}
