//! The exported FMI 2.0 functions of FMU states: the shared ones (module `ffi::state`) under the
//! FMI 2.0 names, with `fmi2Byte` buffers passed as bytes.

use std::ffi::c_int;

use super::Byte;
use crate::ffi::state::{deserialize, free_fmu_state, get_fmu_state, serialize, serialized_size, set_fmu_state};
use crate::ffi::{Component, FmuStatePtr};

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, state: *mut FmuStatePtr) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { get_fmu_state(c, "fmi2GetFMUstate", state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, state: FmuStatePtr) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { set_fmu_state(c, "fmi2SetFMUstate", state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, state: *mut FmuStatePtr) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { free_fmu_state(c, "fmi2FreeFMUstate", state) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(c: Component, state: FmuStatePtr, size: *mut usize) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { serialized_size(c, "fmi2SerializedFMUstateSize", state, size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Component,
    state: FmuStatePtr,
    serialized: *mut Byte,
    size: usize,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { serialize(c, "fmi2SerializeFMUstate", state, serialized.cast::<u8>(), size) }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Component,
    serialized: *const Byte,
    size: usize,
    state: *mut FmuStatePtr,
) -> c_int {
    // SAFETY: forwarded caller contract.
    unsafe { deserialize(c, "fmi2DeSerializeFMUstate", serialized.cast::<u8>(), size, state) }
}
