//! Mesh generation (to be written: issue 2).
use crate::{Config, Error, Mesh};

/// Meshes the pendulum described by `cfg`.
pub fn generate(_cfg: &Config) -> Result<Mesh, Error> {
    Err(Error::Mesh("mesh generation is not written yet".into()))
}
