//! The factorisation of the tangent: made in the frame of a solve, with the hinge columns
//! `K⁻¹ Cᵀ`, and kept as its matrix and frame ([`FactorState`]) so that it can be remade exactly.

use std::sync::Arc;

use super::{NewtonReport, NewtonSettings, Solver};
use crate::assembly::Pattern;
use crate::error::Error;
use crate::error::NewtonError;

/// The matrix of a factorisation and the frame it was made in: enough to remake it exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorState {
    /// Upper-triangle values of the factorised matrix in the fixed pattern.
    pub values: Vec<f64>,
    /// `(proxy angle, matrix key)` of the factorisation (see [`NewtonSettings`]).
    pub frame: (f64, f64),
}

impl Solver {
    /// Numeric factorisation of `self.k` in the frame of `settings`, and the hinge columns
    /// `K⁻¹ Cᵀ` in that frame; counted in `report`.
    pub(super) fn factorize(
        &mut self,
        pattern: &Pattern,
        settings: &NewtonSettings,
        iteration: usize,
        report: &mut NewtonReport,
    ) -> Result<(), NewtonError> {
        let start = std::time::Instant::now();
        // a deferred symbolic analysis that fails (it only can for want of memory) leaves no
        // factorisation, as a singular tangent does
        let factored = Self::analysed(&mut self.chol, pattern).is_ok_and(|chol| chol.factor(pattern, &self.k).is_ok());
        self.timings.factorization += start.elapsed().as_secs_f64();
        report.factorizations += 1;
        if !factored {
            self.factor_frame = None;
            self.factored = None;
            return Err(NewtonError::SingularTangent { iteration });
        }
        let state = Arc::new(FactorState {
            values: self.k.clone(),
            frame: (settings.frame_angle, settings.matrix_key),
        });
        self.finish_factor(state);
        Ok(())
    }

    /// The hinge columns, frame and diagonal scale of the factorisation of `state` just made.
    fn finish_factor(&mut self, state: Arc<FactorState>) {
        let start = std::time::Instant::now();
        let n = self.g.len();
        self.hinge_columns[..n].copy_from_slice(&self.rows[0]);
        self.hinge_columns[n..].copy_from_slice(&self.rows[1]);
        self.chol
            .as_mut()
            .expect("called after a factorisation")
            .solve_in_place(&mut self.hinge_columns);
        self.timings.solve += start.elapsed().as_secs_f64();
        self.factor_frame = Some(state.frame);
        // the pendulum's: other bodies' rows (a wall at rest, unit rows of fixed nodes) add no rounding
        self.diagonal_max = self.diagonal[..self.rotating]
            .iter()
            .fold(0.0f64, |m, &k| m.max(state.values[k].abs()));
        self.factored = Some(state);
    }

    /// The matrix and frame of the current factorisation (`None` before the first one): what
    /// [`Solver::restore_factor`] needs to remake it. Cheap (a shared pointer).
    pub fn factor_state(&self) -> Option<Arc<FactorState>> {
        self.factored.clone()
    }

    /// Makes `state` the current factorisation again (`None`: none, the next solve factorises).
    /// The numeric factorisation of the same values with the same symbolic analysis is the same
    /// bit for bit (faer's factorisation is deterministic), so the solver continues exactly as it
    /// would have from `state`. Nothing is done when `state` is already the current one.
    pub fn restore_factor(&mut self, pattern: &Pattern, state: Option<Arc<FactorState>>) -> Result<(), Error> {
        let same = match (&self.factored, &state) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if same {
            return Ok(());
        }
        let Some(state) = state else {
            self.factor_frame = None;
            self.factored = None;
            return Ok(());
        };
        if state.values.len() != pattern.nnz() {
            return Err(Error::Input(format!(
                "factorisation state: {} matrix values for a pattern of {} entries",
                state.values.len(),
                pattern.nnz()
            )));
        }
        let start = std::time::Instant::now();
        let factored = Self::analysed(&mut self.chol, pattern)?.factor(pattern, &state.values);
        self.timings.factorization += start.elapsed().as_secs_f64();
        if factored.is_err() {
            self.factor_frame = None;
            self.factored = None;
            return Err(Error::Input(
                "factorisation state: the saved matrix does not factorise".into(),
            ));
        }
        self.finish_factor(state);
        Ok(())
    }
}
