//! # pendulum-fem
//!
//! A finite-element simulator of a deformable pendulum: a thin steel plate (a rod with a ring-shaped
//! head) swinging on a hinge under gravity, hyperelastic, optionally driven by a torque at the pivot.
//! It reproduces the NGSolve tutorial "FEM Pendulum: Basics" and its sequels.
//!
//! This crate is the command line (`pendulum-fem run`, `mesh`, `bench`, …). Its library is the
//! whole project under one name: the numerical core ([`pendulum_fem_core`], re-exported here at
//! the root: [`Simulation`], [`Config`], [`Model`], [`Snapshot`], …), the writers and the run
//! driver ([`io`], from `pendulum-fem-io`) and the subcommands ([`commands`]).
//!
//! The crates of the workspace:
//!
//! | crate | what | depends on |
//! |---|---|---|
//! | `pendulum-fem-core` | config, geometry, mesh, elements, materials, terms, Newton, time stepping, the stepper, snapshots | faer, nalgebra, serde |
//! | `pendulum-fem-io` | writers (CSV, VTU/PVD, Gmsh, plots, GIFs, viewer, status), progress, the run driver | core, plotters, indicatif |
//! | `pendulum-fem` | the command line | core, io, clap |
#![warn(missing_docs)]

pub use pendulum_fem_core::*;

/// The writers, the progress display and the run driver (crate `pendulum-fem-io`).
pub use pendulum_fem_io as io;

/// The progress display (re-exported from [`io`]).
pub use pendulum_fem_io::progress;

pub mod commands;
