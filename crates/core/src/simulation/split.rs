//! How a communication step of a co-simulation master becomes internal steps of the stepper: one
//! rule for the FMU and the Python package (its syssimx adapter), so that both advance the same
//! steps for the same request.
//!
//! A communication step `h > 0` with a longest internal step `h_max` is split into
//! `n = ⌈h / h_max⌉` equal internal steps of `h / n`. Masters compute `h` as a difference of
//! communication points, which carries rounding (fmpy: `(k + 1)·0.01 − k·0.01`); so that the
//! internal steps are those of the CLI and the stepper's clock stays on its grid (`t = k·dt`,
//! computed, not accumulated):
//!
//! * an `h` within [`STEP_SNAP`] (relative) of `n·h_max` is taken as `n` steps of exactly `h_max`;
//! * an internal step within [`STEP_SNAP`] of the previous call's (`last`) is taken as that one.
//!
//! The time advanced then differs from `h` by that rounding only. A request that would need more
//! than [`MAX_INTERNAL_STEPS`] internal steps is refused: it is a unit mistake (an `h_max` in
//! milliseconds read as seconds, a tiny `h_max`) rather than a simulation anyone waits for.

/// Relative tolerance within which a communication step is taken as a multiple of the longest
/// internal step (or an internal step as the previous one).
pub const STEP_SNAP: f64 = 1e-9;

/// The most internal steps one communication step may take.
pub const MAX_INTERNAL_STEPS: u64 = 1_000_000;

/// `(n, step)`: the communication step `h` as `n` internal steps of `step ≤ max_step` (see the
/// module doc). `last` is the internal step of the previous communication step, if any.
///
/// Errors (with a message naming the values and the allowed range) when `h` is not finite and
/// positive, `max_step` is not finite and positive, or more than [`MAX_INTERNAL_STEPS`] steps would
/// be needed.
pub fn internal_steps(h: f64, max_step: f64, last: Option<f64>) -> Result<(u64, f64), String> {
    if !(h.is_finite() && h > 0.0) {
        return Err(format!("communication step {h} s: allowed a finite value > 0 s"));
    }
    if !(max_step.is_finite() && max_step > 0.0) {
        return Err(format!(
            "longest internal step {max_step} s: allowed a finite value > 0 s"
        ));
    }
    let ratio = h / max_step;
    // h and max_step are finite and positive: the ratio is positive, +∞ at worst, never NaN
    if ratio > MAX_INTERNAL_STEPS as f64 * (1.0 + STEP_SNAP) {
        return Err(format!(
            "communication step {h} s would take {ratio:.3e} internal steps of at most {max_step} s; \
             allowed at most {MAX_INTERNAL_STEPS}: raise the longest internal step or shorten the \
             communication step"
        ));
    }
    let nearest = ratio.round();
    if nearest >= 1.0 && (ratio - nearest).abs() <= STEP_SNAP * ratio {
        return Ok((nearest as u64, max_step));
    }
    let n = ratio.ceil().max(1.0) as u64;
    let sub = if n == 1 { h } else { h / n as f64 };
    Ok(match last {
        Some(last) if (sub - last).abs() <= STEP_SNAP * last => (n, last),
        _ => (n, sub),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_multiple_of_the_longest_step_takes_exactly_that_step() {
        // fmpy's rounded difference of communication points
        let h = 3.0 * 0.01 - 2.0 * 0.01;
        assert_eq!(internal_steps(h, 0.01, None).unwrap(), (1, 0.01));
        assert_eq!(internal_steps(0.05 + 1e-18, 0.01, None).unwrap(), (5, 0.01));
    }

    #[test]
    fn other_steps_are_split_evenly_and_reuse_the_previous_internal_step() {
        let (n, sub) = internal_steps(0.025, 0.01, None).unwrap();
        assert_eq!(n, 3);
        assert!((sub - 0.025 / 3.0).abs() < 1e-18);
        let last = 0.025 / 3.0;
        assert_eq!(
            internal_steps(0.025 * (1.0 + 1e-12), 0.01, Some(last)).unwrap(),
            (3, last)
        );
        assert_eq!(internal_steps(0.004, 0.01, None).unwrap(), (1, 0.004));
    }

    #[test]
    fn a_request_of_too_many_internal_steps_or_a_bad_value_is_refused() {
        let e = internal_steps(0.01, 1e-300, None).unwrap_err();
        assert!(e.contains("allowed at most 1000000"), "{e}");
        assert!(internal_steps(1.0, 1e-6, None).is_ok());
        assert!(internal_steps(1.0 + 1e-6, 1e-6, None).is_err());
        for (h, max) in [
            (0.0, 0.01),
            (-1.0, 0.01),
            (f64::NAN, 0.01),
            (0.01, 0.0),
            (0.01, f64::INFINITY),
        ] {
            assert!(internal_steps(h, max, None).is_err(), "h = {h}, max = {max}");
        }
    }
}
