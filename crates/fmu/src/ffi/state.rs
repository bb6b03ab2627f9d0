//! The exported FMI functions of FMU states: get, set and free a state, and its serialisation to
//! and from the importer's byte buffers.

use std::ffi::{c_int, c_void};

use super::pointers::{slice, slice_mut};
use super::{with_instance, with_instance_in_any_state};
use super::{Byte, Component, FmuStatePtr};
use crate::instance::{FmuState, Status};

/// Stores `state` at `*slot`: into the existing `FmuState` there, or a new one.
///
/// # Safety
/// `slot` is valid; a non-null `*slot` is a live `Box<FmuState>` from this library.
unsafe fn store_state(slot: *mut FmuStatePtr, state: FmuState) {
    // SAFETY: the caller's contract.
    unsafe {
        if (*slot).is_null() {
            *slot = Box::into_raw(Box::new(state)).cast::<c_void>();
        } else {
            *(*slot).cast::<FmuState>() = state;
        }
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, state: *mut FmuStatePtr) -> c_int {
    with_instance(c, "fmi2GetFMUstate", |inst| {
        if state.is_null() {
            return inst.error("fmi2GetFMUstate: FMUstate pointer is null");
        }
        match inst.get_state() {
            Ok(s) => {
                // SAFETY: `state` is the importer's fmi2FMUstate slot: null or a state of ours.
                unsafe { store_state(state, s) };
                Status::Ok
            }
            Err(status) => status,
        }
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Component, state: FmuStatePtr) -> c_int {
    with_instance(c, "fmi2SetFMUstate", |inst| {
        if state.is_null() {
            return inst.error("fmi2SetFMUstate: FMUstate is null");
        }
        // SAFETY: a state made by fmi2GetFMUstate or fmi2DeSerializeFMUstate of this library.
        let s = unsafe { &*state.cast::<FmuState>() };
        inst.set_state(s)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, state: *mut FmuStatePtr) -> c_int {
    // allowed in the error state too: it only releases the master's memory
    with_instance_in_any_state(c, "fmi2FreeFMUstate", |_| {
        // SAFETY: `state` is null or the slot of a state of ours, freed once (then nulled).
        unsafe {
            if !state.is_null() && !(*state).is_null() {
                drop(Box::from_raw((*state).cast::<FmuState>()));
                *state = std::ptr::null_mut();
            }
        }
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(c: Component, state: FmuStatePtr, size: *mut usize) -> c_int {
    with_instance(c, "fmi2SerializedFMUstateSize", |inst| {
        if state.is_null() || size.is_null() {
            return inst.error("fmi2SerializedFMUstateSize: null FMUstate or size");
        }
        // SAFETY: a state of ours and a writable size (the caller's contract).
        unsafe { *size = (*state.cast::<FmuState>()).to_bytes().len() };
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Component,
    state: FmuStatePtr,
    serialized: *mut Byte,
    size: usize,
) -> c_int {
    with_instance(c, "fmi2SerializeFMUstate", |inst| {
        if state.is_null() || serialized.is_null() {
            return inst.error("fmi2SerializeFMUstate: null FMUstate or buffer");
        }
        // SAFETY: a state of ours (the caller's contract).
        let bytes = unsafe { &*state.cast::<FmuState>() }.to_bytes();
        if bytes.len() > size {
            return inst.error(&format!(
                "fmi2SerializeFMUstate: buffer of {size} bytes for a state of {} (ask fmi2SerializedFMUstateSize)",
                bytes.len()
            ));
        }
        // SAFETY: `serialized` has room for `size >= bytes.len()` bytes.
        let out = unsafe { slice_mut(serialized.cast::<u8>(), bytes.len()) };
        out.copy_from_slice(&bytes);
        Status::Ok
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Component,
    serialized: *const Byte,
    size: usize,
    state: *mut FmuStatePtr,
) -> c_int {
    with_instance(c, "fmi2DeSerializeFMUstate", |inst| {
        if state.is_null() || (serialized.is_null() && size > 0) {
            return inst.error("fmi2DeSerializeFMUstate: null buffer or FMUstate slot");
        }
        // SAFETY: `serialized` holds `size` bytes (the caller's contract).
        let bytes = unsafe { slice(serialized.cast::<u8>(), size) };
        match FmuState::from_bytes(bytes) {
            Ok(s) => {
                // SAFETY: `state` is the importer's fmi2FMUstate slot: null or a state of ours.
                unsafe { store_state(state, s) };
                Status::Ok
            }
            Err(e) => inst.error(&format!("fmi2DeSerializeFMUstate: {e}")),
        }
    })
}
