//! The exported FMI 3.0 functions of FMU states: the shared ones (module `ffi::state`) under the
//! FMI 3.0 names; the states carry the FMI 3.0 event part ([`crate::instance::FmuState`]).

use std::ffi::c_int;

use super::Instance3;
use crate::ffi::state::{deserialize, free_fmu_state, get_fmu_state, serialize, serialized_size, set_fmu_state};
use crate::ffi::FmuStatePtr;

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFMUState(instance: Instance3, state: *mut FmuStatePtr) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { get_fmu_state(instance, "fmi3GetFMUState", state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFMUState(instance: Instance3, state: FmuStatePtr) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { set_fmu_state(instance, "fmi3SetFMUState", state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeFMUState(instance: Instance3, state: *mut FmuStatePtr) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { free_fmu_state(instance, "fmi3FreeFMUState", state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    instance: Instance3,
    state: FmuStatePtr,
    size: *mut usize,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { serialized_size(instance, "fmi3SerializedFMUStateSize", state, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    instance: Instance3,
    state: FmuStatePtr,
    serialized: *mut u8,
    size: usize,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { serialize(instance, "fmi3SerializeFMUState", state, serialized, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    instance: Instance3,
    serialized: *const u8,
    size: usize,
    state: *mut FmuStatePtr,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { deserialize(instance, "fmi3DeserializeFMUState", serialized, size, state) }
}
