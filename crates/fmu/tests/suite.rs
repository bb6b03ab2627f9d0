//! Every integration test of the FMU crate, one module per file of `tests/`: one test binary, so
//! the shared helpers are built once and the tests of all files share libtest's threads. Run one
//! file's tests with `cargo test --release -p pendulum-fem-fmu --test suite FILE::`.

mod common;

mod conformance;
mod fmi3;
mod fmu_with_importers;
mod instance;
mod portable;
