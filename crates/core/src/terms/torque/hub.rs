//! The hub angle of the hinge edge: the weights `w_{a,i} = ∫_Γ X_i N_a ds`, the pair `(c, s)`
//! of a displacement, `θ_hub = atan2(s, c)` on a chosen branch and its gradient (equations in
//! the parent module's doc).

use crate::error::Error;
use crate::fe::for_each_edge_point;
use crate::mesh::Mesh;
use crate::rigid::best_fit_angle;

/// The hinge-edge moments of the hub angle (see the module doc).
#[derive(Clone, Debug)]
pub struct HubAngle {
    /// Nodes on the hinge edge, ascending.
    pub nodes: Vec<usize>,
    /// Their reference positions \[m\].
    pub positions: Vec<[f64; 2]>,
    /// `∫_Γ X_x N_a ds` \[m²\].
    pub wx: Vec<f64>,
    /// `∫_Γ X_y N_a ds` \[m²\].
    pub wy: Vec<f64>,
    /// `∫_Γ |X|² ds` (as `Σ_a w_a·X_a`, consistent with the weights) \[m³\].
    pub c0: f64,
    /// `∫_Γ X_x² ds` \[m³\].
    pub xx: f64,
}

impl HubAngle {
    /// The weights on boundary `name` of `mesh` (pivot at the origin).
    pub fn new(mesh: &Mesh, name: &str) -> Result<Self, Error> {
        let mut acc = std::collections::BTreeMap::<usize, [f64; 2]>::new();
        for_each_edge_point(mesh, name, |nodes, n, p, ds| {
            for a in 0..3 {
                let v = acc.entry(nodes[a]).or_default();
                v[0] += p[0] * n[a] * ds;
                v[1] += p[1] * n[a] * ds;
            }
        });
        if acc.is_empty() {
            return Err(Error::Mesh(format!(
                "the mesh has no boundary named \"{name}\" for the torque"
            )));
        }
        let nodes: Vec<usize> = acc.keys().copied().collect();
        let positions: Vec<[f64; 2]> = nodes.iter().map(|&n| mesh.nodes[n]).collect();
        let wx: Vec<f64> = acc.values().map(|v| v[0]).collect();
        let wy: Vec<f64> = acc.values().map(|v| v[1]).collect();
        let c0 = (0..nodes.len())
            .map(|k| wx[k] * positions[k][0] + wy[k] * positions[k][1])
            .sum::<f64>();
        let xx = (0..nodes.len()).map(|k| wx[k] * positions[k][0]).sum::<f64>();
        if !(c0 > 0.0 && xx > 0.0) {
            return Err(Error::Mesh(format!(
                "the boundary \"{name}\" has no extent about the pivot (∫ X_x² ds = {xx:e} m³); the torque needs it"
            )));
        }
        Ok(Self {
            nodes,
            positions,
            wx,
            wy,
            c0,
            xx,
        })
    }

    /// `(c, s)` of the displacement `u` \[m³\].
    pub fn cos_sin(&self, u: &[f64]) -> (f64, f64) {
        let (mut c, mut s) = (self.c0, 0.0);
        for (k, &n) in self.nodes.iter().enumerate() {
            let (ux, uy) = (u[2 * n], u[2 * n + 1]);
            c += self.wx[k] * ux + self.wy[k] * uy;
            s += self.wx[k] * uy - self.wy[k] * ux;
        }
        (c, s)
    }

    /// `θ_hub(u)` \[rad\], the branch within π of `reference`.
    pub fn angle_near(&self, u: &[f64], reference: f64) -> f64 {
        let (c, s) = self.cos_sin(u);
        best_fit_angle(c, s, Some(reference))
    }

    /// `∂θ_hub/∂u` on the hinge-edge degrees of freedom, in the order `[x, y]` per node of
    /// [`HubAngle::nodes`] \[1/m\].
    pub fn gradient_local(&self, u: &[f64]) -> Vec<f64> {
        let (c, s) = self.cos_sin(u);
        let r2 = c * c + s * s;
        let (a, b) = (c / r2, -s / r2); // ∂θ/∂s, ∂θ/∂c
        let mut g = Vec::with_capacity(2 * self.nodes.len());
        for k in 0..self.nodes.len() {
            // ∇s = (−wy, wx), ∇c = (wx, wy)
            g.push(a * -self.wy[k] + b * self.wx[k]);
            g.push(a * self.wx[k] + b * self.wy[k]);
        }
        g
    }
}
