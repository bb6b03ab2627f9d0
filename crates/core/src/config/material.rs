//! The `[material]` section (the constitutive law, its parameters and the plane reduction) and
//! the `[gravity]` section, with their rules.

use serde::{Deserialize, Serialize};

use super::ranges::{non_negative, positive, range, Mistakes};

/// Constitutive model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MaterialModel {
    /// The tutorial's compressible Neo-Hookean law, `ψ = μ/2 (tr C − 2) + μ²/λ (det C^(−λ/2μ) − 1)`.
    NeoHookean,
    /// St. Venant–Kirchhoff, `ψ = λ/2 (tr E)² + μ tr(E²)`.
    SaintVenantKirchhoff,
}

/// Two-dimensional reduction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Plane {
    /// Thin plate, `σ_zz = 0`: `λ* = Eν/(1 − ν²)`.
    Stress,
    /// Long body, `ε_zz = 0`: `λ = Eν/((1 + ν)(1 − 2ν))`.
    Strain,
}

/// Material parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Material {
    /// Constitutive model.
    pub model: MaterialModel,
    /// Young's modulus \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson's ratio \[-\].
    pub poisson_ratio: f64,
    /// Mass density \[kg/m³\].
    pub density: f64,
    /// Plane stress or plane strain.
    pub plane: Plane,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            model: MaterialModel::NeoHookean,
            youngs_modulus: 2.1e11,
            poisson_ratio: 0.3,
            density: 7800.0,
            plane: Plane::Stress,
        }
    }
}

impl Material {
    /// Lamé parameters `(λ, μ)` of the 2-D model \[Pa\] (plane stress uses `λ*`).
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = match self.plane {
            Plane::Stress => e * nu / (1.0 - nu * nu),
            Plane::Strain => e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        };
        (lambda, mu)
    }

    /// The `[material]` rules.
    pub(super) fn validate(&self, m: &mut Mistakes) {
        let mat = self;
        m.check(positive("material.youngs_modulus", mat.youngs_modulus, "Pa"));
        if !(mat.poisson_ratio > -1.0 && mat.poisson_ratio < 0.5) {
            m.keep(range(
                "material.poisson_ratio",
                mat.poisson_ratio,
                "-1 < poisson_ratio < 0.5",
            ));
        } else if mat.model == MaterialModel::NeoHookean && mat.poisson_ratio <= 0.0 {
            m.keep(range(
                "material.poisson_ratio",
                mat.poisson_ratio,
                "0 < poisson_ratio < 0.5 for the neo-hookean model (its energy divides by λ)",
            ));
        }
        m.check(positive("material.density", mat.density, "kg/m^3"));
    }
}

/// Gravity along −y.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Gravity {
    /// Magnitude \[m/s²\]; 0 switches gravity off.
    pub g: f64,
}

impl Default for Gravity {
    fn default() -> Self {
        Self { g: 9.81 }
    }
}

impl Gravity {
    /// The `[gravity]` rules.
    pub(super) fn validate(&self, m: &mut Mistakes) {
        m.check(non_negative("gravity.g", self.g, "m/s^2"));
    }
}
