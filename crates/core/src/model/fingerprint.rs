//! The model fingerprint: what a model is made of (configuration values, mesh, torque table) as
//! three FNV-1a hashes, how two fingerprints differ in words, and its display.

use crate::config::Config;
use crate::mesh::Mesh;
use crate::store::{fnv1a, Fnv};
use crate::terms::torque::TorqueTable;

/// What a model is made of, part by part, as FNV-1a hashes: what determines its dynamics, not the
/// names of the files it was read from. A snapshot (`crate::simulation::Snapshot`) restores only into a
/// model with an equal fingerprint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fingerprint {
    /// The configuration as JSON without `time.end` and `[output]` (they do not change the state of
    /// a step) and without the file paths `mesh.file` and `torque.file` (their contents count, in
    /// `mesh` and `torque_table`); then the settings of bodies not described by the configuration.
    pub config: u64,
    /// The mesh of every body: each node coordinate (IEEE bits), each triangle's node numbers,
    /// each boundary edge's nodes and name.
    pub mesh: u64,
    /// The torque table (`torque.profile = "table"`) as read: its times and torques (IEEE bits);
    /// the hash of no bytes without a table.
    pub torque_table: u64,
}

/// The fingerprint of a model of `config` on `mesh` (every body's) with the torque table `table`
/// read from `torque.file` (see [`Fingerprint`]).
pub fn fingerprint(config: &Config, mesh: &Mesh, table: Option<&TorqueTable>) -> Fingerprint {
    let mut json = serde_json::to_value(config).unwrap_or(serde_json::Value::Null);
    if let Some(obj) = json.as_object_mut() {
        obj.remove("output");
        for (section, key) in [("time", "end"), ("mesh", "file"), ("torque", "file")] {
            if let Some(section) = obj.get_mut(section).and_then(|t| t.as_object_mut()) {
                section.remove(key);
            }
        }
    }
    let mut m = Fnv::new();
    for p in &mesh.nodes {
        m.write(&p[0].to_bits().to_le_bytes());
        m.write(&p[1].to_bits().to_le_bytes());
    }
    for t in &mesh.triangles {
        for &n in t {
            m.write(&(n as u64).to_le_bytes());
        }
    }
    for e in &mesh.boundary_edges {
        for &n in &e.nodes {
            m.write(&(n as u64).to_le_bytes());
        }
        let name = mesh.boundary_names.get(e.name).map_or("", String::as_str);
        m.write(&(name.len() as u64).to_le_bytes());
        m.write(name.as_bytes());
    }
    let mut t = Fnv::new();
    if let Some(table) = table {
        t.write(&(table.times.len() as u64).to_le_bytes());
        for x in table.times.iter().chain(&table.torques) {
            t.write(&x.to_bits().to_le_bytes());
        }
    }
    Fingerprint {
        config: fnv1a(json.to_string().as_bytes()),
        mesh: m.0,
        torque_table: t.0,
    }
}

impl Fingerprint {
    /// Mixes `bytes` (the settings of a further body) into the configuration part.
    pub fn add_settings(&mut self, bytes: &[u8]) {
        self.config = fnv1a(&[self.config.to_le_bytes().as_slice(), bytes].concat());
    }

    /// `None` when equal; else which parts of `self` (a snapshot's) differ from `model`'s, as a
    /// clause for an error message ("the torque table (times and torques of torque.file = t.csv)
    /// differs"; `config` is the model's, for the names of its files).
    pub fn differences(&self, model: &Fingerprint, config: &Config) -> Option<String> {
        let mut parts = Vec::new();
        if self.config != model.config {
            parts.push("the configuration's values".to_string());
        }
        if self.mesh != model.mesh {
            parts.push(match &config.mesh.file {
                Some(f) => format!("the mesh (nodes, triangles, boundaries of mesh.file = {})", f.display()),
                None => "the mesh (nodes, triangles, boundaries)".to_string(),
            });
        }
        if self.torque_table != model.torque_table {
            let table = config.torque.profile == crate::config::TorqueProfile::Table;
            parts.push(match config.torque.file.as_ref().filter(|_| table) {
                Some(f) => format!("the torque table (times and torques of torque.file = {})", f.display()),
                None => "the torque table (this model has none)".to_string(),
            });
        }
        match parts.as_slice() {
            [] => None,
            [one] => Some(format!("{one} differs")),
            [first @ .., last] => Some(format!("{} and {last} differ", first.join(", "))),
        }
    }
}

impl std::fmt::Display for Fingerprint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:016x}-{:016x}-{:016x}", self.config, self.mesh, self.torque_table)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::config::TorqueProfile;
    use std::path::PathBuf;

    /// The default configuration with a torque table read from `file`.
    pub(crate) fn table_config(file: &str) -> Config {
        let mut cfg = Config::default();
        cfg.torque.profile = TorqueProfile::Table;
        cfg.torque.file = Some(PathBuf::from(file));
        cfg
    }

    #[test]
    fn the_fingerprint_ignores_file_paths_but_sees_a_table_value_and_a_moved_mesh_node() {
        let mesh = crate::mesh::generate(&Config::default()).unwrap();
        let table = TorqueTable::parse("time_s,torque_Nm\n0,0\n0.5,0.2\n1,0\n", "t.csv").unwrap();
        let mut relative = table_config("t.csv");
        relative.mesh.file = Some(PathBuf::from("m.msh"));
        let base = fingerprint(&relative, &mesh, Some(&table));
        // the same model through other paths, a longer end and other outputs
        let mut absolute = table_config("/data/run 1/t.csv");
        absolute.mesh.file = Some(PathBuf::from("/data/meshes/m.msh"));
        absolute.time.end = 9.0;
        absolute.output.plots = !absolute.output.plots;
        assert_eq!(fingerprint(&absolute, &mesh, Some(&table)), base);
        assert_eq!(base.differences(&base, &relative), None);

        let mut edited = table.clone();
        edited.torques[1] = 0.2000000001;
        let other = fingerprint(&relative, &mesh, Some(&edited));
        assert_eq!((other.config, other.mesh), (base.config, base.mesh));
        assert_ne!(other.torque_table, base.torque_table);
        let why = other.differences(&base, &relative).unwrap();
        assert_eq!(
            why,
            "the torque table (times and torques of torque.file = t.csv) differs"
        );
        let mut later = table.clone();
        later.times[2] = 1.5;
        assert_ne!(
            fingerprint(&relative, &mesh, Some(&later)).torque_table,
            base.torque_table
        );

        let mut moved = mesh.clone();
        moved.nodes[7][0] += 1e-12;
        let other = fingerprint(&relative, &moved, Some(&table));
        assert_eq!((other.config, other.torque_table), (base.config, base.torque_table));
        assert_ne!(other.mesh, base.mesh);
        let why = other.differences(&base, &relative).unwrap();
        assert!(
            why.starts_with("the mesh (") && why.contains("mesh.file = m.msh"),
            "{why}"
        );

        let mut denser = relative.clone();
        denser.material.density *= 2.0;
        let other = fingerprint(&denser, &moved, None);
        let why = other.differences(&base, &denser).unwrap();
        assert!(
            why.starts_with("the configuration's values, the mesh")
                && why.ends_with("torque table (times and torques of torque.file = t.csv) differ"),
            "{why}"
        );
    }
}
