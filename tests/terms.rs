//! Term level: gradients and Hessians against finite differences, the patch test, and the
//! rigid-body invariance of the strain energy.

use crate::common;
use common::Extremes;

use pendulum_fem::assembly::Pattern;
use pendulum_fem::config::{self, MaterialModel};
use pendulum_fem::fe::FeCache;
use pendulum_fem::material::Material;
use pendulum_fem::quadrature::TriangleRule;
use pendulum_fem::terms::inertia::MassMatrix;
use pendulum_fem::terms::{Elastic, Gravity, Inertia, StepContext, Term};

fn soft_material(model: MaterialModel) -> Material {
    // soft, so that a finite difference of a few micrometres gives well-resolved force changes
    Material::from_config(&config::Material {
        model,
        youngs_modulus: 1e6,
        poisson_ratio: 0.45,
        ..Default::default()
    })
}

/// Every seventh degree of freedom, a step of 0.1 µm, 1e-5 relative.
fn check_term(term: &dyn Term, pattern: &Pattern, u: &[f64], label: &str) {
    let dofs: Vec<usize> = (0..u.len()).step_by(7).collect();
    let probe = common::Probe {
        dofs: &dofs,
        step: 1e-7,
        tolerance: 1e-5,
        hessian_scale: None,
    };
    common::check_derivatives(term, pattern, u, &probe, label);
}

#[test]
fn elastic_gradient_and_hessian_match_finite_differences() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let pattern = Pattern::new(&mesh, &[]);
    for model in [MaterialModel::NeoHookean, MaterialModel::SaintVenantKirchhoff] {
        let cache = FeCache::new(&mesh, &TriangleRule::degree4(), 0.01).unwrap();
        let elastic = Elastic::new(soft_material(model), &mesh, cache);
        let u = common::wiggle(2 * mesh.num_nodes(), 2e-3, 0.0);
        check_term(&elastic, &pattern, &u, &format!("{model:?}"));
    }
}

#[test]
fn inertia_and_gravity_gradients_match_finite_differences() {
    let mesh = common::hanging_rectangle(0.015, 0.1, 2, 4);
    let pattern = Pattern::new(&mesh, &[]);
    let mass = MassMatrix::new(&mesh, &pattern, 7800.0, 0.01);
    let inertia = Inertia {
        mass: &mass,
        pattern: &pattern,
        factor: 4e4,
        predictor: common::wiggle(2 * mesh.num_nodes(), 1e-3, 0.0),
    };
    let u = common::wiggle(2 * mesh.num_nodes(), 3e-3, 0.0);
    check_term(&inertia, &pattern, &u, "inertia");
    check_term(&Gravity::gravity(&mesh, 7800.0, 0.01, 9.81), &pattern, &u, "gravity");
}

#[test]
fn mass_matrix_reproduces_mass_and_polar_inertia_of_a_rectangle() {
    let (w, l) = (0.015, 0.3);
    let mesh = common::hanging_rectangle(w, l, 2, 6);
    let pattern = Pattern::new(&mesh, &[]);
    let (rho, t) = (7800.0, 0.01);
    let mass = MassMatrix::new(&mesh, &pattern, rho, t);
    let n = 2 * mesh.num_nodes();
    let ones_x: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1.0 } else { 0.0 }).collect();
    let mut m1 = vec![0.0; n];
    pattern.sym_matvec(&mass.values, &ones_x, &mut m1);
    let m: f64 = m1.iter().zip(&ones_x).map(|(a, b)| a * b).sum();
    let exact_m = rho * t * 2.0 * w * l;
    assert!((m / exact_m - 1.0).abs() < 1e-13, "mass {m} vs {exact_m}");
    // rigid rotation velocity field e_z × X: kinetic 2T = I_pivot
    let rot: Vec<f64> = mesh.nodes.iter().flat_map(|p| [-p[1], p[0]]).collect();
    pattern.sym_matvec(&mass.values, &rot, &mut m1);
    let i: f64 = m1.iter().zip(&rot).map(|(a, b)| a * b).sum();
    let exact_i = rho * t * (2.0 * w * l) * ((2.0 * w).powi(2) / 12.0 + l * l / 3.0);
    assert!((i / exact_i - 1.0).abs() < 1e-13, "inertia {i} vs {exact_i}");
}

#[test]
fn affine_displacement_passes_the_patch_test() {
    // A uniform deformation gradient gives a uniform stress: the internal forces of all interior
    // nodes cancel exactly (to rounding), whatever the element shapes.
    let mesh = common::hanging_rectangle(0.02, 0.1, 3, 5);
    for model in [MaterialModel::NeoHookean, MaterialModel::SaintVenantKirchhoff] {
        let cache = FeCache::new(&mesh, &TriangleRule::degree4(), 0.01).unwrap();
        let elastic = Elastic::new(soft_material(model), &mesh, cache);
        let hmat = [[0.01, 0.004], [-0.003, -0.006]];
        let u: Vec<f64> = mesh
            .nodes
            .iter()
            .flat_map(|p| {
                [
                    hmat[0][0] * p[0] + hmat[0][1] * p[1],
                    hmat[1][0] * p[0] + hmat[1][1] * p[1],
                ]
            })
            .collect();
        let mut g = vec![0.0; u.len()];
        elastic.add_gradient(&u, &StepContext::at(&u, 0.0, 0.0, None), &mut g);
        let boundary: std::collections::HashSet<usize> = mesh.boundary_edges.iter().flat_map(|e| e.nodes).collect();
        let scale = g.iter().map(|v| v.abs()).max_of();
        assert!(scale > 0.0);
        for node in 0..mesh.num_nodes() {
            if !boundary.contains(&node) {
                for i in 0..2 {
                    assert!(
                        g[2 * node + i].abs() < 1e-10 * scale,
                        "{model:?}: interior node {node} force {}",
                        g[2 * node + i]
                    );
                }
            }
        }
        // and the total force vanishes (equilibrium of a uniformly stressed free body)
        for i in 0..2 {
            let total: f64 = g.iter().skip(i).step_by(2).sum();
            assert!(total.abs() < 1e-10 * scale);
        }
    }
}

#[test]
fn rigid_rotation_has_zero_elastic_energy_and_force() {
    let mesh = common::hanging_rectangle(0.015, 0.3, 2, 6);
    let cache = FeCache::new(&mesh, &TriangleRule::degree4(), 0.01).unwrap();
    let elastic = Elastic::new(Material::from_config(&config::Material::default()), &mesh, cache);
    let (s, c) = 1.1f64.sin_cos();
    let u: Vec<f64> = mesh
        .nodes
        .iter()
        .flat_map(|p| [c * p[0] - s * p[1] - p[0], s * p[0] + c * p[1] - p[1]])
        .collect();
    // steel: rounding of F = R gives ψ ~ μ ε² per m³; both stay at the rounding level
    assert!(elastic.energy(&u, &StepContext::at(&u, 0.0, 0.0, None)).abs() < 1e-9);
    let mut g = vec![0.0; u.len()];
    elastic.add_gradient(&u, &StepContext::at(&u, 0.0, 0.0, None), &mut g);
    assert!(
        g.iter().all(|x| x.abs() < 1e-3),
        "max force {}",
        g.iter().map(|v| v.abs()).max_of()
    );
}
