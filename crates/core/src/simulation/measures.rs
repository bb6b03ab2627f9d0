//! Measures of the current state of a [`Simulation`], computed on request: the CSV record, the
//! nodal fields of a frame, the consistent acceleration field, the rigid-body rates and energies
//! ([`Kinematics`], cached until the state changes) and the load scale of a step's residual check.

use super::{ContactRecord, FrameData, Model, Simulation, State, StepRecord};
use crate::config::Scheme;
use crate::constraint::Hinge;
use crate::linsolve::Cholesky;
use crate::newton::Timings;
use crate::terms::{StepContext, Term};

/// Rigid-body measures of a state (see [`Simulation::kinematics`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Kinematics {
    /// Best-fit angular velocity \[rad/s\].
    pub(super) omega: f64,
    /// Best-fit angular acceleration \[rad/s²\].
    pub(super) alpha: f64,
    /// Kinetic energy \[J\].
    pub(super) kinetic: f64,
    /// Angular momentum about the pivot \[kg m²/s\].
    pub(super) momentum: f64,
    /// The largest nodal inertia force `|M a|` \[N\] (full model; NaN for a reduced body), for
    /// [`Simulation::load_scale`].
    pub(super) inertia_force: f64,
}

fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

impl Simulation {
    /// Accumulated solver timings.
    pub fn timings(&self) -> Timings {
        self.solver.timings
    }

    /// Post-processes the current state into a CSV record.
    pub fn record(&mut self, newton_iterations: usize) -> StepRecord {
        let theta = self.theta;
        let von_mises_max = self.von_mises_max();
        let Kinematics {
            omega,
            alpha,
            kinetic,
            momentum,
            ..
        } = self.kinematics();
        let energies = self.energies_with(kinetic);
        let m = &self.model;
        let s = &self.state;
        let contact = m.wall.as_ref().map(|_| ContactRecord {
            gap: self.gap(),
            force: self.contact_force(),
            energy: energies.contact,
            impacts: self.impacts,
        });
        StepRecord {
            step: self.step,
            time: s.t,
            theta,
            omega,
            alpha,
            kinetic,
            strain: energies.strain,
            gravity: energies.gravity,
            total: energies.total,
            hinge_force: Hinge::reaction(self.lambda),
            von_mises_max,
            newton_iterations,
            torque: m.applied_torque(s.t, self.held_torque),
            torque_work: self.torque_work,
            angular_momentum: momentum,
            contact,
        }
    }

    /// The [`StepContext`] of the current state by itself (its time, unwrapped θ and held inputs).
    pub fn context(&self) -> StepContext<'_> {
        StepContext::at(&self.state.u, self.state.t, self.theta, self.held_torque)
    }

    /// Makes the elastic terms' start data of the current state ([`Term::discrete_start`]: `F`,
    /// `E` and `ψ(E)` at every quadrature point, one per body), unless it is made already: the
    /// energy-momentum step starting here needs it, and the strain energy of the state is its sum
    /// ([`crate::terms::Elastic::energy_of_start`]), so an output read between two steps costs no
    /// pass over the elements of its own. The data is kept with the displacement it was made from
    /// and is valid while the state's displacement is that one, bit for bit (whatever changed it:
    /// a step, a roll-back, a restore, a new initial state).
    pub(super) fn elastic_starts(&mut self) {
        if self.current_starts().is_none() {
            let data = starts_of(&self.model, &self.context());
            self.starts = Some((self.state.u.clone(), data));
        }
    }

    /// Makes what the next energy-momentum step of the full model starts from, and what the
    /// outputs read between two steps: the elastic start data ([`Simulation::elastic_starts`]) and
    /// the rigid-body measures ([`Simulation::kinematics`]), side by side on the pool (the one's
    /// mass products beside the other's pass over the elements).
    pub(super) fn prepare_next_step(&mut self) {
        if self.current_starts().is_some() || self.rates.is_some() {
            self.elastic_starts();
            self.kinematics();
            return;
        }
        let cx = self.context();
        let (m, step, s) = (&self.model, self.step, &self.state);
        let (starts, (k, mx)) = rayon::join(|| starts_of(m, &cx), || full_kinematics(m, &cx, step, s));
        self.starts = Some((self.state.u.clone(), starts));
        (self.rates, self.mx) = (Some(k), mx);
    }

    /// The elastic terms' start data if it is that of the current state.
    pub(super) fn current_starts(&self) -> Option<&[Vec<f64>]> {
        let (u, data) = self.starts.as_ref()?;
        let same =
            u.len() == self.state.u.len() && u.iter().zip(&self.state.u).all(|(a, b)| a.to_bits() == b.to_bits());
        same.then_some(data.as_slice())
    }

    /// Angular momentum about the pivot of the current state, `Σ_ab M_ab x_a × v_b` \[kg m²/s\].
    pub fn angular_momentum(&mut self) -> f64 {
        self.kinematics().momentum
    }

    /// Nodal fields of the current state.
    pub fn frame_data(&mut self, theta: f64) -> FrameData {
        self.sync_fields();
        let acceleration = pairs(&self.acceleration_field());
        FrameData {
            step: self.step,
            time: self.state.t,
            theta,
            displacement: pairs(&self.state.u),
            velocity: pairs(&self.state.v),
            acceleration,
            stress: self.nodal_stress(),
        }
    }

    /// The nodal acceleration of the current state \[m/s²\]. The Newmark schemes carry it in the
    /// state. The energy-momentum scheme does not need one (it keeps the step's mean acceleration
    /// as a load scale); here the consistent value at the end of the step is solved from the
    /// equation of motion, `M a = −∇Π(u, t) − Cᵀμ`, `C a = 0`, with a Cholesky factorisation of the
    /// mass matrix made on the first call (on request only: frames, not every step).
    pub fn acceleration_field(&mut self) -> Vec<f64> {
        self.sync_fields();
        if self.model.scheme != Scheme::EnergyMomentum || self.step == 0 {
            return self.state.a.clone();
        }
        if self.mass_solver.is_none() {
            let m = &self.model;
            let mut chol = Cholesky::new(&m.pattern).expect("the symbolic analysis of a mesh pattern succeeds");
            let mut mass = m.mass.values.clone();
            m.fixed.apply_matrix(&mut mass);
            chol.factor(&m.pattern, &mass)
                .expect("a consistent mass matrix is positive definite");
            let n = m.pattern.n;
            let rows = m.hinge.dense_rows(n);
            let mut columns = [rows[0].clone(), rows[1].clone()].concat();
            chol.solve_in_place(&mut columns);
            self.mass_solver = Some((chol, rows, columns));
        }
        let m = &self.model;
        let s = &self.state;
        let cx = StepContext::at(&s.u, s.t, self.theta, self.held_torque);
        let mut force = vec![0.0; s.u.len()];
        for (term, _) in m.body_terms(0.0) {
            term.add_gradient(&s.u, &cx, &mut force);
        }
        for term in m.loads() {
            term.add_gradient(&s.u, &cx, &mut force);
        }
        force.iter_mut().for_each(|f| *f = -*f);
        m.fixed.apply_vector(&mut force);
        let (chol, rows, columns) = self.mass_solver.as_mut().expect("made above");
        chol.solve_in_place(&mut force);
        // C (y − Z μ) = 0 with Z = M⁻¹Cᵀ: a 2×2 system for μ
        let n = force.len();
        let (zx, zy) = columns.split_at(n);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let sm = [
            [dot(&rows[0], zx), dot(&rows[0], zy)],
            [dot(&rows[1], zx), dot(&rows[1], zy)],
        ];
        let b = [dot(&rows[0], &force), dot(&rows[1], &force)];
        let det = sm[0][0] * sm[1][1] - sm[0][1] * sm[1][0];
        let mu = [
            (b[0] * sm[1][1] - b[1] * sm[0][1]) / det,
            (sm[0][0] * b[1] - sm[1][0] * b[0]) / det,
        ];
        (0..n).map(|i| force[i] - zx[i] * mu[0] - zy[i] * mu[1]).collect()
    }

    /// The largest nodal applied force: gravity, the inertia force `M a` of the current state, and for
    /// the actuator torque at time `t` the largest nodal inertia force of the rigid angular
    /// acceleration it drives, `|M(t)|/I · max_a |(M_mass (e_z × x))_a|` \[N\]. (The torque's own nodal
    /// forces sit on the short hinge edge and are about a hundred times the nodal gravity forces;
    /// as a scale they would loosen the residual check for the whole body.)
    pub(super) fn load_scale(&mut self, t: f64) -> f64 {
        let inertia = self.kinematics().inertia_force;
        let m = &self.model;
        let gravity = m.largest_gravity_force();
        let torque = m.applied_torque(t, self.held_torque).abs();
        let mut driven = 0.0;
        if torque > 0.0 {
            // M (e_z × x) = e_z × (M x): the nodal inertia forces of a unit angular acceleration
            let largest = self.mx.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            driven = torque / m.inertia_pivot() * largest;
        }
        (inertia + gravity + driven).max(1e-12)
    }

    /// Best-fit angular velocity and acceleration of the current state \[rad/s, rad/s²\].
    pub fn angular_rates(&mut self) -> (f64, f64) {
        let k = self.kinematics();
        (k.omega, k.alpha)
    }

    /// Rigid-body measures of the current state (cached until the state changes). With
    /// `m_x = M x` for the positions `x = X + u`: `∫ ρ t |x|² dA = x·m_x`, and since `M` is symmetric
    /// and acts on both components alike, `Σ_ab M_ab x_a × w_b = Σ_b (m_x)_b × w_b` for any field `w`:
    /// one mass product serves the angular velocity, the angular momentum and the angular
    /// acceleration; a second one (`M v`) the kinetic energy.
    pub(super) fn kinematics(&mut self) -> Kinematics {
        if let Some(k) = self.rates {
            return k;
        }
        if let Some(k) = self.reduced_kinematics() {
            self.rates = Some(k);
            return k;
        }
        let (k, mx) = full_kinematics(&self.model, &self.context(), self.step, &self.state);
        self.mx = mx;
        self.rates = Some(k);
        k
    }
}

/// Every body's elastic start data at the state of `cx` ([`Term::discrete_start`]).
fn starts_of(m: &Model, cx: &StepContext) -> Vec<Vec<f64>> {
    m.bodies.iter().map(|b| b.elastic.discrete_start(cx)).collect()
}

/// The rigid-body measures of the full model's state `s` ([`Simulation::kinematics`]) at the
/// context `cx` of that state, after `step` steps, and `M x`: a function of the state alone, so
/// that a step can make it beside the next step's start data.
pub(super) fn full_kinematics(m: &Model, cx: &StepContext, step: usize, s: &State) -> (Kinematics, Vec<f64>) {
    // the pendulum's positions (zeros at the other bodies' nodes: the rigid-body measures are
    // the pendulum's; the mass matrix couples no two bodies, so M x stays the pendulum's)
    let mut x = m.positions(&s.u);
    x[2 * m.bodies[0].nodes.end..].iter_mut().for_each(|c| *c = 0.0);
    // M x, M v and M a (for the load scale of the next step) in one pass over the matrix
    let (mut mx, mut mv, mut ma) = (vec![0.0; x.len()], vec![0.0; x.len()], vec![0.0; x.len()]);
    m.mass.apply_each([&x, &s.v, &s.a], [&mut mx, &mut mv, &mut ma]);
    let cross = |w: &[f64]| -> f64 {
        (0..x.len() / 2)
            .map(|b| mx[2 * b] * w[2 * b + 1] - mx[2 * b + 1] * w[2 * b])
            .sum()
    };
    let polar: f64 = x.iter().zip(&mx).map(|(a, b)| a * b).sum();
    let momentum = cross(&s.v);
    let alpha = if m.scheme == Scheme::EnergyMomentum && step > 0 {
        // the consistent end-of-step value: the moment of the external loads at x (the strain
        // energy's forces and the hinge force have none) over the polar moment of inertia
        let mut loads = vec![0.0; x.len()];
        m.bodies[0].gravity.add_gradient(&s.u, cx, &mut loads);
        for term in m.loads() {
            term.add_gradient(&s.u, cx, &mut loads);
        }
        let moment: f64 = (0..x.len() / 2)
            .map(|a| x[2 * a + 1] * loads[2 * a] - x[2 * a] * loads[2 * a + 1])
            .sum();
        moment / polar
    } else {
        cross(&s.a) / polar
    };
    let kinetic = 0.5 * s.v.iter().zip(&mv).map(|(a, b)| a * b).sum::<f64>();
    let k = Kinematics {
        omega: momentum / polar,
        alpha,
        kinetic,
        momentum,
        inertia_force: ma.iter().fold(0.0f64, |a, b| a.max(b.abs())),
    };
    (k, mx)
}
