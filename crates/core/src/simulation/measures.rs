//! Measures of the current state of a [`Simulation`], computed on request: the CSV record, the
//! nodal fields of a frame, the consistent acceleration field, the rigid-body rates and energies
//! ([`Kinematics`], cached until the state changes), and the contact readings of the fields.

use super::{ContactRecord, FrameData, Model, Simulation, StepRecord};
use crate::constraint::Hinge;
use crate::linsolve::Cholesky;
use crate::newton::Timings;
use crate::terms::StepContext;

/// Rigid-body measures of a state (see [`Simulation::angular_rates`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Kinematics {
    /// Best-fit angular velocity \[rad/s\].
    pub omega: f64,
    /// Best-fit angular acceleration \[rad/s²\].
    pub alpha: f64,
    /// Kinetic energy \[J\].
    pub kinetic: f64,
    /// Angular momentum about the pivot \[kg m²/s\].
    pub momentum: f64,
    /// The largest nodal inertia force `|M a|` \[N\] (the full body; NaN for the reduced body),
    /// for the scale of a step's residual check.
    pub inertia_force: f64,
}

fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

impl Simulation {
    /// Accumulated solver timings.
    pub fn timings(&self) -> Timings {
        self.body.timings()
    }

    /// Post-processes the current state into a CSV record.
    pub fn record(&mut self, newton_iterations: usize) -> StepRecord {
        let von_mises_max = self.von_mises_max();
        StepRecord {
            von_mises_max,
            ..self.record_without_stress(newton_iterations)
        }
    }

    /// [`Simulation::record`] but the largest von Mises stress (0 here), which costs a pass over
    /// every element node: what a step checks of the state it reached.
    pub(super) fn record_without_stress(&mut self, newton_iterations: usize) -> StepRecord {
        let theta = self.now.theta;
        let Kinematics {
            omega,
            alpha,
            kinetic,
            momentum,
            ..
        } = self.kinematics();
        let energies = self.energies_with(kinetic);
        let m = &self.model;
        let s = &self.now.state;
        let contact = m.wall.as_ref().map(|_| ContactRecord {
            gap: self.gap(),
            force: self.contact_force(),
            energy: energies.contact,
            impacts: self.contact.count,
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
            hinge_force: Hinge::reaction(self.now.lambda),
            von_mises_max: 0.0,
            newton_iterations,
            torque: m.applied_torque(s.t, self.now.held_torque),
            torque_work: self.now.torque_work,
            angular_momentum: momentum,
            contact,
        }
    }

    /// The [`StepContext`] of the current state by itself (its time, unwrapped θ and held inputs).
    pub fn context(&self) -> StepContext<'_> {
        self.now.context()
    }

    /// Angular momentum about the pivot of the current state, `Σ_ab M_ab x_a × v_b` \[kg m²/s\].
    pub fn angular_momentum(&mut self) -> f64 {
        self.kinematics().momentum
    }

    /// Nodal fields of the current state.
    pub fn frame_data(&mut self, theta: f64) -> FrameData {
        self.body.sync_fields(&mut self.now);
        let acceleration = pairs(&self.acceleration_field());
        FrameData {
            step: self.step,
            time: self.now.state.t,
            theta,
            displacement: pairs(&self.now.state.u),
            velocity: pairs(&self.now.state.v),
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
        self.body.sync_fields(&mut self.now);
        if !crate::scheme::for_config(&self.model.config).keeps_mean_acceleration() || self.step == 0 {
            return self.now.state.a.clone();
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
        let s = &self.now.state;
        let cx = self.now.context();
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

    /// Best-fit angular velocity and acceleration of the current state \[rad/s, rad/s²\].
    pub fn angular_rates(&mut self) -> (f64, f64) {
        let k = self.kinematics();
        (k.omega, k.alpha)
    }

    /// Rigid-body measures of the current state (cached until the state changes).
    pub(super) fn kinematics(&mut self) -> Kinematics {
        self.body.kinematics(&self.model, &mut self.now, self.step)
    }
}

/// The gap of the displacement `u` \[m\], positive while apart: with a wall, the smallest gap of
/// the head's arc to its face (negative: the largest penetration); without one, the smallest
/// signed distance of the arc's nodes to the plane `x = wall.x` (`+∞` for a mesh without the arc).
pub(super) fn gap_of_fields(model: &Model, u: &[f64]) -> f64 {
    if let Some(wall) = &model.wall {
        return wall.smallest_gap(u);
    }
    let (mesh, face_x) = (&model.mesh, model.config.wall.x);
    mesh.edges_named(super::CONTACT_BOUNDARY)
        .flat_map(|e| e.nodes)
        .map(|n| mesh.nodes[n][0] + u[2 * n] - face_x)
        .fold(f64::INFINITY, f64::min)
}

/// The wall's normal force on the head at the displacement `u` \[N\] (a negative zero as 0; 0
/// without a wall).
pub(super) fn contact_force_of_fields(model: &Model, u: &[f64]) -> f64 {
    model
        .wall
        .as_ref()
        .map_or(0.0, |wall| crate::post::unsigned_zero(wall.normal_force(u)))
}
