//! Physical effects as energy terms `Π_i(u, cx)`.
//!
//! The incremental potential of a time step is the sum of the inertia term and the terms here;
//! the Newton solver sees only their sum. Each term gives its energy, adds its gradient into a
//! caller-owned vector and its Hessian into the values of the fixed sparsity pattern
//! ([`crate::assembly::Pattern`]). A term that couples degrees of freedom outside the element
//! pattern lists those entries once with [`Term::hessian_entries`]; it must then write exactly those
//! entries at every call (zeros when inactive), so the symbolic factorisation stays valid.
//!
//! Energies are in joules, gradients in newtons, Hessians in N/m; `u` is the interleaved nodal
//! displacement vector \[m\]. An energy of `+∞` marks an inadmissible state.
//!
//! **Step context.** Besides `u`, a term reads only its [`StepContext`]: the time of the evaluated
//! state, the start of the step it belongs to (displacement, time, unwrapped proxy angle) and the
//! inputs held over the step (the torque of [`crate::simulation::Simulation::set_torque`]). Terms keep no
//! mutable state: a term is a function of `(u, context)`, so a snapshot of the stepper's state is
//! all there is to save.
//!
//! **Discrete gradients.** The energy-momentum scheme ([`crate::scheme::energy_momentum`]) replaces the
//! gradient at one end of a step by a *discrete gradient* `∇ᵈΠ(u₀, u₁)` over the step, with
//!
//! ```text
//! ∇ᵈΠ(u₀, u₁) · (u₁ − u₀) = Π(u₁) − Π(u₀)        (directionality)
//! ∇ᵈΠ(u, u) = ∇Π(u)                              (consistency)
//! ```
//!
//! and, for the terms that are invariant under rotations about the pivot, a moment about the
//! pivot of the forces `−∇ᵈΠ` taken at the mid-step positions that vanishes
//! ([`Term::add_discrete_gradient`]). For a time-dependent external load (the torque) the first
//! line reads `∇ᵈΠ · Δu = −W`, `W` the work of [`Term::external_work`].

use crate::assembly::Pattern;

pub mod contact;
pub mod elastic;
pub mod inertia;
pub mod linear;
pub mod torque;

pub use contact::WallContact;
pub use elastic::Elastic;
pub use inertia::Inertia;
pub use linear::{Gravity, Linear};
pub use torque::{Torque, TorqueMode, TorqueTable, HUB_STRESS_LIMIT};

/// One additive contribution to the potential.
pub trait Term: Send + Sync {
    /// Short name for reports.
    fn name(&self) -> &'static str;

    /// `Π(u, cx)` \[J\]; `+∞` for an inadmissible state.
    fn energy(&self, u: &[f64], cx: &StepContext) -> f64;

    /// `g += ∂Π/∂u`.
    fn add_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]);

    /// `K += ∂²Π/∂u²` into the upper-triangle `values` of `pattern`.
    fn add_hessian(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, values: &mut [f64]);

    /// Energy and gradient in one pass (`g += ∂Π/∂u`; returns `Π`).
    fn energy_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]) -> f64 {
        self.add_gradient(u, cx, g);
        self.energy(u, cx)
    }

    /// Energy, gradient and Hessian in one pass (terms override this when fusing saves work).
    fn assemble(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, g: &mut [f64], values: &mut [f64]) -> f64 {
        self.add_gradient(u, cx, g);
        self.add_hessian(u, cx, pattern, values);
        self.energy(u, cx)
    }

    /// Entries `(row, col)` outside the element pattern that this term writes; called once.
    fn hessian_entries(&self) -> Vec<(usize, usize)> {
        Vec::new()
    }

    /// The work \[J\] done on the body by this term's load over the step from the context's start
    /// (`cx.u0` at `cx.t0`) to `(u1, cx.t)`, for external loads whose energy is not part of the
    /// reported total (the torque). Default: 0.
    fn external_work(&self, _u1: &[f64], _cx: &StepContext) -> f64 {
        0.0
    }

    /// Data of the start of a step (`cx.u0` at `cx.t0`) that [`Term::add_discrete_gradient`] reads
    /// on every call (the elastic term's strains and energies at the quadrature points). Default:
    /// none.
    fn discrete_start(&self, _cx: &StepContext) -> Vec<f64> {
        Vec::new()
    }

    /// `values += factor · ∂(∇ᵈΠ(u₀, u₁))/∂u₁`, the Jacobian of the discrete gradient, for a term
    /// whose Hessian at `u₁` is a poor approximation of it (the contact's secant across the face);
    /// returns whether it did. Default: `false`, and [`DiscreteGradient`] takes the Hessian at `u₁`.
    fn add_discrete_hessian(
        &self,
        _start: &StepStart,
        _u1: &[f64],
        _cx: &StepContext,
        _factor: f64,
        _pattern: &Pattern,
        _values: &mut [f64],
    ) -> bool {
        false
    }

    /// `g += factor · ∇ᵈΠ(u₀, u₁)`, a discrete gradient over the step from `start` to `(u1, cx.t)`
    /// (see the module doc). Returns `+∞` for an inadmissible `u1`, otherwise a finite value:
    /// `Π(u1)` where that costs nothing extra, 0 where it would (the strain energy).
    fn add_discrete_gradient(&self, start: &StepStart, u1: &[f64], cx: &StepContext, factor: f64, g: &mut [f64])
        -> f64;
}

/// Every pair `(dofs[i], dofs[j])`, `i ≤ j`: the entries of a dense block of the Hessian among
/// `dofs`, for [`Term::hessian_entries`].
pub fn dense_block(dofs: &[usize]) -> Vec<(usize, usize)> {
    let mut e = Vec::with_capacity(dofs.len() * (dofs.len() + 1) / 2);
    for (i, &a) in dofs.iter().enumerate() {
        for &b in &dofs[i..] {
            e.push((a, b));
        }
    }
    e
}

/// What a term reads besides the displacement it is evaluated at (see the module doc).
#[derive(Clone, Copy, Debug)]
pub struct StepContext<'a> {
    /// Time of the evaluated state \[s\].
    pub t: f64,
    /// Time at the start of the step \[s\] (`t` for a state outside a step). Kept as the stepper
    /// holds it, not recomputed as `t − dt`: `(t₀ + Δt) − Δt` can miss `t₀` by a rounding, and a
    /// step torque switching on at a step's start was then off in the step's work and on in its
    /// dynamics (half a step's work of the torque missing from the energy balance).
    pub t0: f64,
    /// Length of the step \[s\] (0 for a state outside a step: the initial equilibrium, a report).
    pub dt: f64,
    /// Displacement at the start of the step \[m\].
    pub u0: &'a [f64],
    /// Proxy angle at the start of the step, unwrapped \[rad\]: the branch of angle-valued
    /// quantities (the torque's hub angle) over the step.
    pub theta0: f64,
    /// The torque held as an input \[N m\] (`None`: the configured profile acts).
    pub torque: Option<f64>,
}

impl<'a> StepContext<'a> {
    /// The context of a state by itself: at time `t`, with `u` as its own start.
    pub fn at(u: &'a [f64], t: f64, theta: f64, torque: Option<f64>) -> Self {
        Self {
            t,
            t0: t,
            dt: 0.0,
            u0: u,
            theta0: theta,
            torque,
        }
    }
}

/// The start of a time step, as a discrete gradient needs it.
#[derive(Clone, Copy, Debug)]
pub struct StepStart<'a> {
    /// Displacement at the start \[m\].
    pub u: &'a [f64],
    /// What the term's [`Term::discrete_start`] returned for the start.
    pub data: &'a [f64],
    /// Numerical dissipation `χ ∈ [0, 1)` of the strain energy (see [`crate::scheme::energy_momentum`]);
    /// other terms ignore it.
    pub dissipation: f64,
}

/// A term multiplied by a constant factor (the `(1 + α)` weight of HHT-α).
pub struct Scaled<'a> {
    /// The term.
    pub term: &'a dyn Term,
    /// The factor.
    pub factor: f64,
}

impl Term for Scaled<'_> {
    fn name(&self) -> &'static str {
        self.term.name()
    }

    fn energy(&self, u: &[f64], cx: &StepContext) -> f64 {
        self.factor * self.term.energy(u, cx)
    }

    fn add_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]) {
        let mut own = vec![0.0; g.len()];
        self.term.add_gradient(u, cx, &mut own);
        g.iter_mut().zip(&own).for_each(|(a, b)| *a += self.factor * b);
    }

    fn energy_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]) -> f64 {
        let mut own = vec![0.0; g.len()];
        let e = self.term.energy_gradient(u, cx, &mut own);
        g.iter_mut().zip(&own).for_each(|(a, b)| *a += self.factor * b);
        self.factor * e
    }

    fn add_hessian(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, values: &mut [f64]) {
        let mut own = vec![0.0; values.len()];
        self.term.add_hessian(u, cx, pattern, &mut own);
        values.iter_mut().zip(&own).for_each(|(a, b)| *a += self.factor * b);
    }

    fn assemble(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, g: &mut [f64], values: &mut [f64]) -> f64 {
        let (mut own_g, mut own_k) = (vec![0.0; g.len()], vec![0.0; values.len()]);
        let e = self.term.assemble(u, cx, pattern, &mut own_g, &mut own_k);
        g.iter_mut().zip(&own_g).for_each(|(a, b)| *a += self.factor * b);
        values.iter_mut().zip(&own_k).for_each(|(a, b)| *a += self.factor * b);
        self.factor * e
    }

    fn discrete_start(&self, cx: &StepContext) -> Vec<f64> {
        self.term.discrete_start(cx)
    }

    fn add_discrete_gradient(
        &self,
        start: &StepStart,
        u1: &[f64],
        cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        self.factor * self.term.add_discrete_gradient(start, u1, cx, factor * self.factor, g)
    }
}

/// A term's discrete gradient over one step as a term of the energy-momentum system
/// ([`crate::scheme::energy_momentum`]): gradient `gradient_factor · ∇ᵈΠ(u₀, u)`, and as its approximate
/// Jacobian the term's own Jacobian of the discrete gradient where it has one
/// ([`Term::add_discrete_hessian`]), otherwise `hessian_factor · ∇²Π(u)`. Its "energy" only flags
/// inadmissible states (`+∞`): the energy-momentum system has no potential.
pub struct DiscreteGradient<'a> {
    /// The term.
    pub term: &'a dyn Term,
    /// The start of the step (with the term's own start data).
    pub start: StepStart<'a>,
    /// Factor of the discrete gradient.
    pub gradient_factor: f64,
    /// Factor of the Hessian at the current point.
    pub hessian_factor: f64,
}

impl Term for DiscreteGradient<'_> {
    fn name(&self) -> &'static str {
        self.term.name()
    }

    fn energy(&self, u: &[f64], cx: &StepContext) -> f64 {
        self.term.energy(u, cx)
    }

    fn add_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]) {
        self.term
            .add_discrete_gradient(&self.start, u, cx, self.gradient_factor, g);
    }

    fn energy_gradient(&self, u: &[f64], cx: &StepContext, g: &mut [f64]) -> f64 {
        self.term
            .add_discrete_gradient(&self.start, u, cx, self.gradient_factor, g)
    }

    fn add_hessian(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, values: &mut [f64]) {
        if self
            .term
            .add_discrete_hessian(&self.start, u, cx, self.gradient_factor, pattern, values)
        {
            return;
        }
        if self.hessian_factor == 1.0 {
            self.term.add_hessian(u, cx, pattern, values);
        } else {
            let mut own = vec![0.0; values.len()];
            self.term.add_hessian(u, cx, pattern, &mut own);
            values
                .iter_mut()
                .zip(&own)
                .for_each(|(a, b)| *a += self.hessian_factor * b);
        }
    }

    fn assemble(&self, u: &[f64], cx: &StepContext, pattern: &Pattern, g: &mut [f64], values: &mut [f64]) -> f64 {
        self.add_hessian(u, cx, pattern, values);
        self.energy_gradient(u, cx, g)
    }

    fn add_discrete_gradient(
        &self,
        start: &StepStart,
        u1: &[f64],
        cx: &StepContext,
        factor: f64,
        g: &mut [f64],
    ) -> f64 {
        self.term.add_discrete_gradient(start, u1, cx, factor, g)
    }
}
