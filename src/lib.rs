//! # pendulum-fem
//!
//! A finite-element simulator of a deformable pendulum: a thin steel plate (a rod with a ring-shaped
//! head) swinging on a hinge under gravity, hyperelastic, optionally driven by a torque at the pivot.
//! It reproduces the NGSolve tutorial "FEM Pendulum: Basics" and its sequels.
//!
//! This crate is the command line (`pendulum-fem run`, `mesh`, `bench`, `sweep`, …). Its library
//! gathers the project under one name: the numerical core ([`pendulum_fem_core`], re-exported
//! here at the root: [`Simulation`], [`Config`], [`Model`], [`Snapshot`], …), the run driver and
//! studies ([`run`], crate `pendulum-fem-run`), the files and pictures ([`render`], crate
//! `pendulum-fem-render`), the progress display ([`progress`]) and the subcommands ([`commands`]).
//!
//! The crates of the workspace, each layer using only those above it:
//!
//! | crate | what | depends on |
//! |---|---|---|
//! | `pendulum-fem-core` | the numerics: config, geometry, mesh (and the Gmsh reader), elements, materials, terms, Newton, time stepping, the stepper, snapshots | faer, nalgebra, serde |
//! | `pendulum-fem-run` | the run: driver, step plan, energy audit, checkpoint/restart, `results.csv` and `events.csv`, status, studies; no plotting, no terminal | core, serde, rayon |
//! | `pendulum-fem-render` | files and pictures: VTU/PVD/VTM, Gmsh `.msh`, plots, animations, the HTML viewer, as observers of a run | core, run, plotters, gif, png |
//! | `pendulum-fem` | the command line, the progress bar | core, run, render, clap, indicatif |
//! | `pendulum-fem-fmu` | the FMI 2.0 FMU | core |
//! | `pendulum-fem-python` | the Python module | core, run, pyo3 |
#![warn(missing_docs)]

pub use pendulum_fem_core::*;

/// The run driver, its files and the parameter studies (crate `pendulum-fem-run`).
pub use pendulum_fem_run as run;

/// The files and pictures: ParaView, Gmsh, plots, animations, viewer (crate `pendulum-fem-render`).
pub use pendulum_fem_render as render;

pub mod commands;
pub mod progress;
