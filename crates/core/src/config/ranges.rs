//! The range checks: [`Config::validate`], which applies every section's rules (each section's
//! `validate` method, next to its struct), and the checks of one value whose messages name the key
//! and the allowed range.

use super::Config;
use crate::error::Error;

impl Config {
    /// Checks every value against its allowed range, section by section (each section's rules
    /// are its `validate` method, next to its struct); the message names the key.
    pub fn validate(&self) -> Result<(), Error> {
        self.geometry.validate()?;
        self.mesh.validate(&self.geometry)?;
        self.material.validate()?;
        self.gravity.validate()?;
        self.initial.validate()?;
        self.time.validate()?;
        self.solver.validate()?;
        self.torque.validate()?;
        self.wall.validate()?;
        self.contact.validate(&self.wall, self.time.scheme)?;
        self.output.validate()?;
        self.model.validate(self)
    }
}

pub(super) fn range(key: &str, value: f64, allowed: &str) -> Error {
    Error::Config(format!("{key} = {value}: allowed {allowed}"))
}

pub(super) fn finite(key: &str, v: f64) -> Result<(), Error> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, "a finite number"))
    }
}

pub(super) fn positive(key: &str, v: f64, unit: &str) -> Result<(), Error> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, &format!("a finite value > 0 {unit}")))
    }
}

pub(super) fn non_negative(key: &str, v: f64, unit: &str) -> Result<(), Error> {
    if v >= 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(range(key, v, &format!("a finite value >= 0 {unit}")))
    }
}

pub(super) fn within(key: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), Error> {
    if v >= lo && v <= hi {
        Ok(())
    } else {
        Err(range(key, v, &format!("{lo} to {hi} {unit}")))
    }
}
