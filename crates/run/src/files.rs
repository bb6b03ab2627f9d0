//! A run's configuration as a file that reads back from anywhere ([`portable_toml`]). Every file a
//! run replaces (checkpoints, summaries, ParaView frames) goes through the core's
//! [`write_atomically`](pendulum_fem_core::store::write_atomically), so a run stopped meanwhile
//! leaves the previous version intact and never a torn file.

use pendulum_fem_core::{Config, Error};

/// `cfg` as TOML that reads back to the same configuration from any folder: the input files
/// (`mesh.file`, `torque.file`) made absolute. `name` names the file in an error. One rule for a
/// checkpoint's configuration, a study case's and a pickled Python simulation's.
pub fn portable_toml(cfg: &Config, name: &str) -> Result<String, Error> {
    let mut cfg = cfg.clone();
    for file in [&mut cfg.mesh.file, &mut cfg.torque.file].into_iter().flatten() {
        if let Ok(abs) = std::path::absolute(&*file) {
            *file = abs;
        }
    }
    toml::to_string(&cfg).map_err(|e| Error::Input(format!("{name}: {e}")))
}
