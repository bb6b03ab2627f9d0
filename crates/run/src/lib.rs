//! # pendulum-fem-run
//!
//! A run of the pendulum from a configuration to its folder of results, without pictures and
//! without a terminal: the driver ([`driver::run`]) steps a
//! [`Simulation`](pendulum_fem_core::Simulation) through its [`StepPlan`]
//! ([`driver::PlanSteps`], the Python package's `run` too), streams `results.csv` ([`rows`],
//! [`csv`]), `events.csv` and `impacts.csv`, keeps the energy balance with its watchdog
//! ([`audit`]), writes checkpoints and restarts from them ([`checkpoint`]), and leaves
//! `status.json` ([`status`]) however it ends. Pictures, ParaView files and a progress bar watch a
//! run through [`driver::RunObserver`] (the crate `pendulum-fem-render` and the CLI supply them),
//! taking its records as they are written. The one reader of what a run wrote is
//! [`rows::read_records`] (through the core's [`Table`](pendulum_fem_core::store::Table)) and
//! [`rows::read_events`]. Parameter studies ([`study`]) run one case per configuration.
//!
//! The layers: `pendulum-fem-core` (the numerics) ← this crate ← `pendulum-fem-render` (files
//! and pictures) ← the CLI; the FMU and the Python module use the core and this crate only.
#![warn(missing_docs)]

pub use pendulum_fem_core::{Config, Error};

pub mod audit;
pub mod checkpoint;
pub mod csv;
pub mod driver;
pub mod files;
pub mod impacts;
pub mod outdir;
pub mod rows;
pub mod status;
pub mod study;

pub use audit::EnergyAudit;
pub use driver::{run, run_with, RunEnd, RunObserver, RunOptions, RunStart, RunSummary};
pub use outdir::prepare_output_dir;
pub use pendulum_fem_core::config::StepPlan;
pub use rows::csv_values;
