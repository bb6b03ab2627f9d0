//! # pendulum-fem-core
//!
//! The numerical core of pendulum-fem: configuration, geometry, mesh, elements, materials, energy
//! terms, Newton, time stepping and the [`Simulation`] stepper. No command line, plotting or
//! progress-bar dependencies: the run driver and its CSV files are in `pendulum-fem-run`, the
//! ParaView files and pictures in `pendulum-fem-render`, the command line in `pendulum-fem`.
//!
//! ## What it simulates
//!
//! A finite-element simulator of a deformable pendulum: a thin steel plate (a rod with a ring-shaped
//! head) swinging on a hinge under gravity, hyperelastic, optionally driven by a torque at the pivot.
//! It reproduces the NGSolve tutorial "FEM Pendulum: Basics" and its sequels.
//!
//! ## The model
//!
//! Total Lagrangian, plane stress (or strain), thickness `t`, reference domain `Ω₀`, displacement
//! `u(X, t)`, deformation gradient `F = I + ∇₀u`:
//!
//! ```text
//! ρ t ü = ∇₀·(t P) + ρ t g        in Ω₀,        P = ∂ψ/∂F,
//! (1/|Γ_rot|) ∫_Γrot u ds = 0     (hinge: two Lagrange multipliers, the reaction force).
//! ```
//!
//! Time is discretised by default by an energy-momentum scheme, the midpoint rule with discrete
//! gradients that conserves energy and angular momentum at any step
//! ([`scheme::energy_momentum`]); each step is a constrained nonlinear system solved by Newton's
//! method ([`newton`]) over a sparse Cholesky factorisation whose symbolic analysis is done once
//! per run ([`linsolve`]). The tutorial's Newmark rule (and HHT-α) remain, written as an
//! incremental potential ([`scheme::newmark`]). A reduced body ([`reduced`]: a floating frame and
//! a few modes) can stand in for the full one behind the same stepper.
//!
//! ## Driving a simulation
//!
//! [`Simulation`] is the stepper that the CLI drives too: [`Simulation::step`] with any positive
//! `dt` (a failed step changes nothing), the held input [`Simulation::set_torque`], outputs on
//! request, and [`Simulation::snapshot`] / [`Simulation::restore`] of the complete state
//! ([`Snapshot`], also as bytes).
//!
//! ## Units
//!
//! SI throughout: m, kg, s, Pa, N, J, rad.
//!
//! ## Layers (module map)
//!
//! Each module uses only the modules on the lines above it (none uses this crate root):
//!
//! 1. [`error`], [`element`], [`quadrature`]
//! 2. [`store`] (bytes, hashes, atomic files, the cache folder, CSV tables), [`config`]
//! 3. [`geometry`], [`material`]
//! 4. [`mesh`]
//! 5. [`fe`], [`assembly`]
//! 6. [`rigid`] (best-fit angle, unwrapping, turning about the pivot), [`constraint`],
//!    [`linsolve`]
//! 7. [`terms`] (each physical effect an energy)
//! 8. [`newton`], [`post`] (stresses)
//! 9. [`model`] (the full model's operators)
//! 10. [`modal`], [`scheme`] (the full body's time schemes)
//! 11. [`reduced`] (the reduced body, built from the model's operators)
//! 12. [`simulation`] (the stepper, owning one body of either kind)
//!
//! The run driver (`pendulum-fem-run`) and the writers (`pendulum-fem-render`) observe the stepper.
#![warn(missing_docs)]

pub mod config;
pub mod error;
pub mod geometry;
pub mod mesh;

pub use config::Config;
pub use error::Error;
pub use mesh::Mesh;
pub use simulation::{
    BodySpec, ContactEvent, ContactEventKind, Energies, Frame, Model, Simulation, Snapshot, StepRecord,
};
pub mod assembly;
pub mod constraint;
pub mod element;
pub mod fe;
pub mod linsolve;
pub mod material;
pub mod modal;
pub mod model;
pub mod newton;
pub mod post;
pub mod quadrature;
pub mod reduced;
pub mod rigid;
pub mod scheme;
pub mod simulation;
pub mod store;
pub mod terms;
