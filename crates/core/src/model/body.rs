//! Bodies: a model is a list of bodies, each a part of the mesh with its own material, density and
//! thickness, its own strain-energy and gravity terms, and fixed (Dirichlet) edges.
//!
//! The first body is the pendulum (the hinge, the proxy angle θ, the torque act on it). Further
//! bodies ([`BodySpec`]: the wall block of the contact tutorial, a block in a test) are meshed
//! separately and appended: the model's mesh holds every body's nodes, body after body, and every
//! body's elements, body after body, so one sparsity pattern and one symbolic factorisation serve
//! the coupled system. Each [`Body`] keeps a view of the model's mesh with only its own elements
//! and boundary edges over the model's node numbering; its terms are built on that view and
//! assemble into the shared pattern from their [`Body::first_element`] on.
//!
//! Fixed edges hold both components of every node on them at zero. They are imposed after
//! assembly ([`crate::assembly::Dirichlet`]), so the pattern is the same with or without them.

use std::ops::Range;
use std::sync::Arc;

use super::shared::{shared, try_shared, Key};
use crate::config::{self, Config};
use crate::error::Error;
use crate::fe::FeCache;
use crate::material::Material;
use crate::mesh::{BoundaryEdge, Mesh};
use crate::post::{NodalStress, StressRecovery};
use crate::quadrature::TriangleRule;
use crate::terms::{Elastic, Gravity};

/// A body to add to a model after the pendulum.
#[derive(Clone, Debug)]
pub struct BodySpec {
    /// Name (for reports and output blocks).
    pub name: String,
    /// Its own mesh (own node numbering; appended to the model's).
    pub mesh: Mesh,
    /// Constitutive law and density.
    pub material: config::Material,
    /// Thickness \[m\].
    pub thickness: f64,
    /// Whether gravity (`gravity.g` of the configuration) acts on it.
    pub gravity: bool,
    /// Names of its boundaries whose nodes are held fixed.
    pub fixed: Vec<String>,
}

/// One body of a model (see the module doc).
pub struct Body {
    /// Name.
    pub name: String,
    /// The body's elements and boundary edges over the model's nodes (node indices of the model,
    /// element indices of the body, boundary names of the model).
    pub mesh: Mesh,
    /// The body's nodes in the model's numbering.
    pub nodes: Range<usize>,
    /// Index of its first element among the model's elements.
    pub first_element: usize,
    /// Constitutive law.
    pub material: Material,
    /// Mass density \[kg/m³\].
    pub density: f64,
    /// Thickness \[m\].
    pub thickness: f64,
    /// Strain energy.
    pub elastic: Elastic,
    /// Gravity (a zero load when gravity does not act on the body).
    pub gravity: Arc<Gravity>,
    /// Stresses at its nodes.
    pub stress: Arc<StressRecovery>,
    /// Its fixed degrees of freedom (model numbering).
    pub fixed_dofs: Vec<usize>,
}

/// What a body is made of: material, thickness \[m\], gravity \[m/s²\], fixed boundaries.
struct Makeup<'a> {
    material: &'a config::Material,
    thickness: f64,
    g: f64,
    fixed: &'a [String],
}

impl Body {
    /// The time a pressure wave of the undeformed material takes to cross the body's thinnest
    /// element at its node spacing \[s\]: half the smallest altitude of a triangle (quadratic
    /// elements have a node at each edge's midpoint) over `c_p = √((λ + 2μ)/ρ)` with the Lamé
    /// parameters of the 2-D law (plane stress or strain). A step this short resolves the fastest
    /// motion the mesh carries, and the inertia `M/Δt²` of its Newton matrix outweighs the
    /// elements' stiffness (see [`crate::config::Cutbacks`]).
    pub fn wave_time(&self) -> f64 {
        let nodes = &self.mesh.nodes;
        let thinnest = self
            .mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = [nodes[t[0]], nodes[t[1]], nodes[t[2]]];
                let area2 = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
                let longest = [(a, b), (b, c), (c, a)]
                    .iter()
                    .map(|(p, q)| (q[0] - p[0]).hypot(q[1] - p[1]))
                    .fold(0.0, f64::max);
                area2 / longest
            })
            .fold(f64::INFINITY, f64::min);
        let m = &self.material;
        let speed = ((m.lambda + 2.0 * m.mu) / self.density).sqrt();
        0.5 * thinnest / speed
    }

    /// Builds a body on its `view` of the model's mesh; `key` names the view (the model's mesh and
    /// the body's elements): the element data are shared with the bodies of other models on the
    /// same view ([`super::shared`]).
    fn new(
        name: &str,
        view: Mesh,
        key: Key,
        nodes: Range<usize>,
        first_element: usize,
        makeup: Makeup,
    ) -> Result<Self, Error> {
        let Makeup {
            material,
            thickness,
            g,
            fixed,
        } = makeup;
        let law = Material::from_config(material);
        // the element data of the strain energy on one thread, the rest on another
        let (cache, (gravity, stress)) = rayon::join(
            || {
                try_shared(&key.clone().with_f64(&[thickness]), || {
                    FeCache::new(&view, &TriangleRule::degree4(), thickness)
                })
            },
            || {
                (
                    shared(&key.clone().with_f64(&[material.density, thickness, g]), || {
                        Gravity::gravity(&view, material.density, thickness, g)
                    }),
                    try_shared(&key, || StressRecovery::new(&view)),
                )
            },
        );
        let mut elastic = Elastic::new(law, &view, cache?);
        elastic.first_element = first_element;
        let stress = stress?;
        let mut fixed_dofs = Vec::new();
        for boundary in fixed {
            let on = view.nodes_on(boundary);
            if on.is_empty() {
                return Err(Error::Config(format!(
                    "body \"{name}\": no boundary named \"{boundary}\" to hold fixed (its boundaries: {})",
                    view.boundary_names.join(", ")
                )));
            }
            fixed_dofs.extend(on.iter().flat_map(|&n| [2 * n, 2 * n + 1]));
        }
        Ok(Self {
            name: name.to_string(),
            mesh: view,
            nodes,
            first_element,
            material: law,
            density: material.density,
            thickness,
            elastic,
            gravity,
            stress,
            fixed_dofs,
        })
    }

    /// Nodal stresses of the body (zeros at the nodes of other bodies).
    pub fn nodal_stress(&self, u: &[f64]) -> NodalStress {
        self.stress.nodal(&self.material, u)
    }
}

/// One body's part of the model's mesh (see [`parts`]).
pub(super) struct Part {
    name: String,
    /// Its nodes and elements in the model's numbering.
    pub nodes: Range<usize>,
    pub elements: Range<usize>,
    /// Its view of the model's mesh (see [`Body::mesh`]).
    pub view: Mesh,
    /// Mass density \[kg/m³\] and thickness \[m\].
    pub density: f64,
    pub thickness: f64,
}

impl Part {
    /// The key of its view of the model's mesh of key `mesh` ([`super::shared`]).
    pub fn key(&self, mesh: &Key) -> Key {
        mesh.clone().with(&[self.elements.start, self.elements.end])
    }
}

/// The model's mesh of the pendulum `first` and the `others` appended, and each body's part of it
/// (the pendulum's first).
pub(super) fn parts(config: &Config, first: Mesh, others: &[BodySpec]) -> (Mesh, Vec<Part>) {
    let mut model_mesh = first;
    let mut ranges = vec![(
        model_mesh.region_name.clone(),
        0..model_mesh.num_nodes(),
        0..model_mesh.triangles.len(),
        0..model_mesh.boundary_edges.len(),
    )];
    for spec in others {
        let (nodes, elements, edges) = append(&mut model_mesh, &spec.mesh);
        ranges.push((spec.name.clone(), nodes, elements, edges));
    }
    let parts = ranges
        .into_iter()
        .enumerate()
        .map(|(k, (name, nodes, elements, edges))| {
            let m = makeup(config, others, k);
            let (density, thickness) = (m.material.density, m.thickness);
            Part {
                view: view_of(&model_mesh, &name, elements.clone(), edges),
                name,
                nodes,
                elements,
                density,
                thickness,
            }
        })
        .collect();
    (model_mesh, parts)
}

/// What body `k` is made of: the pendulum's (`k = 0`) from `config`, the others' from their specs.
fn makeup<'a>(config: &'a Config, others: &'a [BodySpec], k: usize) -> Makeup<'a> {
    let g = config.gravity.g;
    match k {
        0 => Makeup {
            material: &config.material,
            thickness: config.geometry.thickness,
            g,
            fixed: &[],
        },
        _ => {
            let spec = &others[k - 1];
            Makeup {
                material: &spec.material,
                thickness: spec.thickness,
                g: if spec.gravity { g } else { 0.0 },
                fixed: &spec.fixed,
            }
        }
    }
}

/// The bodies on the `parts` of [`parts`] (the pendulum's first, then the `others`'); `mesh` is the
/// key of the model's mesh ([`super::shared`]).
pub(super) fn bodies(config: &Config, parts: &[Part], others: &[BodySpec], mesh: &Key) -> Result<Vec<Body>, Error> {
    parts
        .iter()
        .enumerate()
        .map(|(k, part)| {
            let m = makeup(config, others, k);
            Body::new(
                &part.name,
                part.view.clone(),
                part.key(mesh),
                part.nodes.clone(),
                part.elements.start,
                m,
            )
        })
        .collect()
}

/// Appends `other` to `mesh` (its nodes after `mesh`'s, its elements after `mesh`'s, its boundary
/// names merged by name); returns the ranges of its nodes, elements and boundary edges.
fn append(mesh: &mut Mesh, other: &Mesh) -> (Range<usize>, Range<usize>, Range<usize>) {
    let (n0, e0, b0) = (mesh.nodes.len(), mesh.triangles.len(), mesh.boundary_edges.len());
    mesh.nodes.extend_from_slice(&other.nodes);
    mesh.num_vertices += other.num_vertices;
    mesh.triangles.extend(other.triangles.iter().map(|t| t.map(|n| n + n0)));
    let names: Vec<usize> = other
        .boundary_names
        .iter()
        .map(|name| match mesh.boundary_id(name) {
            Some(id) => id,
            None => {
                mesh.boundary_names.push(name.clone());
                mesh.boundary_names.len() - 1
            }
        })
        .collect();
    mesh.boundary_edges
        .extend(other.boundary_edges.iter().map(|e| BoundaryEdge {
            nodes: e.nodes.map(|n| n + n0),
            name: names[e.name],
            triangle: e.triangle + e0,
            local_edge: e.local_edge,
        }));
    (
        n0..mesh.nodes.len(),
        e0..mesh.triangles.len(),
        b0..mesh.boundary_edges.len(),
    )
}

/// The view of one body: every node of `mesh`, the body's elements and boundary edges (their
/// element indices counted within the body).
fn view_of(mesh: &Mesh, name: &str, elements: Range<usize>, edges: Range<usize>) -> Mesh {
    let e0 = elements.start;
    Mesh {
        nodes: mesh.nodes.clone(),
        num_vertices: mesh.num_vertices,
        triangles: mesh.triangles[elements].to_vec(),
        boundary_edges: mesh.boundary_edges[edges]
            .iter()
            .map(|e| BoundaryEdge {
                triangle: e.triangle - e0,
                ..*e
            })
            .collect(),
        boundary_names: mesh.boundary_names.clone(),
        region_name: name.to_string(),
        order: mesh.order,
    }
}
