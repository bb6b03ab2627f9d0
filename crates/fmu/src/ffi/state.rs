//! FMU states, for both FMI versions: get, set and free a state, and its serialisation to and
//! from the importer's byte buffers (the adapters pass FMI 2.0's `fmi2Byte` buffers as bytes).

use std::ffi::{c_int, c_void};

use super::pointers::{slice, slice_mut};
use super::{with_instance, with_instance_in_any_state, Component, FmuStatePtr};
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

/// `fmi2GetFMUstate` and `fmi3GetFMUState` (`what`).
///
/// # Safety
/// `state` is null or the importer's FMU state slot: null or a state of this library.
pub(crate) unsafe fn get_fmu_state(c: Component, what: &str, state: *mut FmuStatePtr) -> c_int {
    with_instance(c, what, |inst| {
        if state.is_null() {
            return inst.error(&format!("{what}: FMUState pointer is null"));
        }
        match inst.get_state() {
            Ok(s) => {
                // SAFETY: `state` is the importer's FMU state slot: null or a state of ours.
                unsafe { store_state(state, s) };
                Status::Ok
            }
            Err(status) => status,
        }
    })
}

/// `fmi2SetFMUstate` and `fmi3SetFMUState` (`what`).
///
/// # Safety
/// `state` is null or a state of this library.
pub(crate) unsafe fn set_fmu_state(c: Component, what: &str, state: FmuStatePtr) -> c_int {
    with_instance(c, what, |inst| {
        if state.is_null() {
            return inst.error(&format!("{what}: FMUState is null"));
        }
        // SAFETY: a state made by getting or deserializing a state in this library.
        let s = unsafe { &*state.cast::<FmuState>() };
        inst.set_state(s)
    })
}

/// `fmi2FreeFMUstate` and `fmi3FreeFMUState` (`what`).
///
/// # Safety
/// `state` is null or the slot of a state of this library, freed once.
pub(crate) unsafe fn free_fmu_state(c: Component, what: &str, state: *mut FmuStatePtr) -> c_int {
    // allowed in the error state too: it only releases the master's memory
    with_instance_in_any_state(c, what, |_| {
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

/// `fmi2SerializedFMUstateSize` and `fmi3SerializedFMUStateSize` (`what`).
///
/// # Safety
/// `state` is null or a state of this library; `size` null or writable.
pub(crate) unsafe fn serialized_size(c: Component, what: &str, state: FmuStatePtr, size: *mut usize) -> c_int {
    with_instance(c, what, |inst| {
        if state.is_null() || size.is_null() {
            return inst.error(&format!("{what}: null FMUState or size"));
        }
        // SAFETY: a state of ours and a writable size (the caller's contract).
        unsafe { *size = (*state.cast::<FmuState>()).to_bytes().len() };
        Status::Ok
    })
}

/// `fmi2SerializeFMUstate` and `fmi3SerializeFMUState` (`what`).
///
/// # Safety
/// `state` is null or a state of this library; `serialized` null or `size` writable bytes.
pub(crate) unsafe fn serialize(
    c: Component,
    what: &str,
    state: FmuStatePtr,
    serialized: *mut u8,
    size: usize,
) -> c_int {
    with_instance(c, what, |inst| {
        if state.is_null() || serialized.is_null() {
            return inst.error(&format!("{what}: null FMUState or buffer"));
        }
        // SAFETY: a state of ours (the caller's contract).
        let bytes = unsafe { &*state.cast::<FmuState>() }.to_bytes();
        if bytes.len() > size {
            return inst.error(&format!(
                "{what}: buffer of {size} bytes for a state of {} (ask for the serialized size first)",
                bytes.len()
            ));
        }
        // SAFETY: `serialized` has room for `size >= bytes.len()` bytes.
        let out = unsafe { slice_mut(serialized, bytes.len()) };
        out.copy_from_slice(&bytes);
        Status::Ok
    })
}

/// `fmi2DeSerializeFMUstate` and `fmi3DeserializeFMUState` (`what`).
///
/// # Safety
/// `serialized` holds `size` bytes; `state` is null or the importer's FMU state slot.
pub(crate) unsafe fn deserialize(
    c: Component,
    what: &str,
    serialized: *const u8,
    size: usize,
    state: *mut FmuStatePtr,
) -> c_int {
    with_instance(c, what, |inst| {
        if state.is_null() || (serialized.is_null() && size > 0) {
            return inst.error(&format!("{what}: null buffer or FMUState slot"));
        }
        // SAFETY: `serialized` holds `size` bytes (the caller's contract).
        let bytes = unsafe { slice(serialized, size) };
        match FmuState::from_bytes(bytes) {
            Ok(s) => {
                // SAFETY: `state` is the importer's FMU state slot: null or a state of ours.
                unsafe { store_state(state, s) };
                Status::Ok
            }
            Err(e) => inst.error(&format!("{what}: {e}")),
        }
    })
}
