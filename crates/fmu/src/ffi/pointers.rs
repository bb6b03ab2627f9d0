//! The checks and conversions of the C arguments: a null array with a positive length is refused
//! with a message, arrays and strings from the importer become slices and text.

use std::ffi::CStr;

use super::FmiString;
use crate::instance::{Instance, Status};

/// `Err(Error)`, logged, when an array of `n > 0` values is null (`arrays`: each by name, whether
/// it is null).
pub(crate) fn check_arrays(inst: &Instance, what: &str, n: usize, arrays: &[(&str, bool)]) -> Result<(), Status> {
    match arrays.iter().find(|(_, null)| *null) {
        Some((name, _)) if n > 0 => Err(inst.error(&format!("{what}: {name} is null with nvr = {n}"))),
        _ => Ok(()),
    }
}

/// `n` values at `p` (empty for `n = 0`, whatever `p`).
///
/// # Safety
/// For `n > 0`, `p` points to `n` initialised values that stay valid and unaliased for `'a`.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if n == 0 || p.is_null() {
        &[]
    } else {
        // SAFETY: the caller's contract.
        unsafe { std::slice::from_raw_parts(p, n) }
    }
}

/// `n` writable values at `p` (empty for `n = 0`).
///
/// # Safety
/// For `n > 0`, `p` points to `n` writable values, valid and unaliased for `'a`.
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> &'a mut [T] {
    if n == 0 || p.is_null() {
        &mut []
    } else {
        // SAFETY: the caller's contract.
        unsafe { std::slice::from_raw_parts_mut(p, n) }
    }
}

/// A C string as text (`""` for null).
///
/// # Safety
/// A non-null `p` is NUL-terminated and valid for the call.
pub(crate) unsafe fn text(p: FmiString) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: the caller's contract.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}
