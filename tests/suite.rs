//! Every integration test of the command line and the library, one module per file of `tests/`.
//!
//! They are one test binary, not one per file: the shared helpers (`common`) and the generic code
//! they instantiate are compiled and linked once, and libtest runs the tests of all files on its
//! threads together, so a long test of one file runs beside the short tests of the others instead
//! of after them. Run one file's tests with `cargo test --release --test suite FILE::` (for
//! example `cargo test --release --test suite wall::`).

mod common;

mod bodies;
mod checkpoint;
mod cli;
mod config_reference;
mod contact;
mod docs;
mod energy_momentum;
mod fuzz_readers;
mod geometry;
mod gmsh_read;
mod hinge;
mod material;
mod mesh;
mod mesh_cache;
mod mesh_io;
mod mesh_options;
mod modes;
mod newmark;
mod ngsolve_script;
mod non_finite;
mod notebooks;
mod outputs;
mod python_package;
mod reduced;
mod robustness;
mod run_summary;
mod same_outputs;
mod shared_operators;
mod stepper;
mod sweep;
mod terms;
mod torque;
mod validation;
mod viewer;
mod wall;
mod wall_outputs;
