//! The `[wall]` section (no wall, a rigid one or the deformable block) and the `[contact]` section
//! (how the head's contact with it is evaluated), with their rules.

use serde::{Deserialize, Serialize};

use super::ranges::{finite, positive, range, Mistakes};
use super::Scheme;

/// What the wall is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WallKind {
    /// No wall (the basics tutorial).
    None,
    /// A rigid obstacle, the half-plane `x <= wall.x` (no mesh).
    Rigid,
    /// The contact tutorial's steel block, meshed as a second body, fixed on its left, top and
    /// bottom edges; its right edge (`x = wall.x`) is the contact face.
    Deformable,
}

/// The wall (see [`WallKind`]); the block's keys apply to `kind = "deformable"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Wall {
    /// Rigid or deformable, or none.
    pub kind: WallKind,
    /// `x` of the contact face \[m\] (the hanging head's leftmost point is at −0.06 m).
    pub x: f64,
    /// Width of the block, to the left of the face \[m\].
    pub width: f64,
    /// Height of the block \[m\].
    pub height: f64,
    /// `y` of the block's centre \[m\].
    pub center_y: f64,
    /// Young's modulus of the block \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson's ratio of the block \[-\].
    pub poisson_ratio: f64,
    /// Density of the block \[kg/m³\].
    pub density: f64,
    /// Thickness of the block \[m\].
    pub thickness: f64,
    /// Element size in the block \[m\] (the tutorial's `r_head/5`).
    pub mesh_size: f64,
    /// Element size along the contact face \[m\] (the tutorial's `r_head/20`).
    pub face_size: f64,
}

impl Default for Wall {
    fn default() -> Self {
        Self {
            kind: WallKind::None,
            x: -0.06,
            width: 0.025,
            height: 0.25,
            center_y: -0.24,
            youngs_modulus: 2.1e11,
            poisson_ratio: 0.3,
            density: 7800.0,
            thickness: 0.01,
            mesh_size: 0.012,
            face_size: 0.003,
        }
    }
}

impl Wall {
    /// Whether there is a wall (`kind` other than `"none"`): the one test of it for the model, the
    /// outputs and the studies.
    pub fn is_present(&self) -> bool {
        self.kind != WallKind::None
    }

    /// The `[wall]` rules (the wall's overlap with the pendulum at its release angle is checked
    /// with the mesh, by the model).
    pub(super) fn validate(&self, m: &mut Mistakes) {
        let w = self;
        m.check(finite("wall.x", w.x));
        m.check(finite("wall.center_y", w.center_y));
        if w.kind != WallKind::Deformable {
            return;
        }
        let block = m.check(positive("wall.width", w.width, "m")) & m.check(positive("wall.height", w.height, "m"));
        m.check(positive("wall.youngs_modulus", w.youngs_modulus, "Pa"));
        if !(w.poisson_ratio > 0.0 && w.poisson_ratio < 0.5) {
            m.keep(range("wall.poisson_ratio", w.poisson_ratio, "0 < poisson_ratio < 0.5"));
        }
        m.check(positive("wall.density", w.density, "kg/m^3"));
        m.check(positive("wall.thickness", w.thickness, "m"));
        for (key, size) in [("wall.mesh_size", w.mesh_size), ("wall.face_size", w.face_size)] {
            if m.check(positive(key, size, "m")) && block && (size > w.width.max(w.height) || size < 1e-5 * w.height) {
                m.keep(range(
                    key,
                    size,
                    &format!(
                        "1e-5 x wall.height <= size <= the block's size ({} m)",
                        w.width.max(w.height)
                    ),
                ));
            }
        }
    }
}

/// How the contact force is evaluated over a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactMethod {
    /// The secant (discrete gradient) of the contact energy over the step, with the impact located
    /// and resolved in sub-steps: the work of the contact force equals the change of contact energy.
    EnergyConsistent,
    /// The tutorial's: the penalty force at the end of the step, no impact location. It gains
    /// energy at impacts; kept to show the difference.
    Penalty,
}

/// Contact between the head's arc and the wall face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Contact {
    /// How the force is evaluated over a step.
    pub method: ContactMethod,
    /// Normal pressure per unit penetration \[N/m³\]: energy `½ k g²` per unit reference contact
    /// area. The default 2e10 is the tutorial's `kₙ = 1e10`: its energy density `kₙ g²` has no ½.
    pub stiffness: f64,
    /// Gauss points per edge of the head's arc.
    pub points_per_edge: usize,
    /// Sub-steps per contact time scale `δ_max / v` while the head is in contact (see
    /// [`crate::simulation`]'s impact resolution). The default 10 meets the converged references
    /// (rebound within 4e-4°, penetration within 0.3 %, the stiff contact's rebound within 0.03°);
    /// 20, twice the impacts' sub-steps, changes them by less than 1e-4°.
    pub substeps: usize,
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            method: ContactMethod::EnergyConsistent,
            stiffness: 2e10,
            points_per_edge: 8,
            substeps: 10,
        }
    }
}

impl Contact {
    /// The `[contact]` rules; the energy-consistent method with a wall needs the energy-momentum
    /// `scheme`.
    pub(super) fn validate(&self, w: &Wall, scheme: Scheme, m: &mut Mistakes) {
        let c = self;
        m.check(positive("contact.stiffness", c.stiffness, "N/m^3"));
        if !(1..=64).contains(&c.points_per_edge) {
            m.push(
                "contact.points_per_edge",
                format!("contact.points_per_edge = {}: allowed range 1 to 64", c.points_per_edge),
            );
        }
        if !(4..=1000).contains(&c.substeps) {
            m.push(
                "contact.substeps",
                format!("contact.substeps = {}: allowed range 4 to 1000", c.substeps),
            );
        }
        if w.kind != WallKind::None && c.method == ContactMethod::EnergyConsistent && scheme != Scheme::EnergyMomentum {
            m.push(
                "contact.method",
                format!(
                    "contact.method = \"energy-consistent\" needs time.scheme = \"energy-momentum\" (this run has \"{}\"); \
                     the Newmark schemes evaluate the contact force at the end of the step: set contact.method = \"penalty\"",
                    scheme.name()
                ),
            );
        }
    }
}
