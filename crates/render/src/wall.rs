//! The wall as the pictures and the ParaView files draw it ([`WallOutput`]): its face, the block
//! drawn for the rigid wall, and the contact pressure on the head's boundary nodes.

use crate::Mesh;

/// The wall of a run (`wall.kind` other than `"none"`) as the outputs draw it.
#[derive(Clone, Debug, PartialEq)]
pub struct WallOutput {
    /// `x` of the contact face \[m\]; the wall is `x ≤ face_x`.
    pub face_x: f64,
    /// Penalty stiffness `k` \[N/m³\] (`contact.stiffness`): the contact pressure is
    /// `k · max(−gap, 0)`.
    pub stiffness: f64,
    /// The nodes of the head's contact boundary (model numbering), sorted.
    pub contact_nodes: Vec<usize>,
    /// The block drawn for the rigid wall in ParaView, `[xmin, ymin, xmax, ymax]` \[m\]
    /// (`wall.width` to the left of the face, `wall.height` about `wall.center_y`).
    pub extent: [f64; 4],
    /// Whether the wall is rigid (`wall.kind = "rigid"`): only a rigid wall gets a block of its
    /// own in ParaView; a deformable one is a body of the mesh.
    pub rigid: bool,
}

impl WallOutput {
    /// The wall of `cfg` over the model mesh `mesh` (pendulum first); `None` without a wall.
    pub fn of(cfg: &crate::Config, mesh: &Mesh) -> Option<Self> {
        let w = &cfg.wall;
        if !w.is_present() {
            return None;
        }
        Some(Self {
            face_x: w.x,
            stiffness: cfg.contact.stiffness,
            contact_nodes: mesh.nodes_on(crate::simulation::CONTACT_BOUNDARY),
            extent: [
                w.x - w.width,
                w.center_y - 0.5 * w.height,
                w.x,
                w.center_y + 0.5 * w.height,
            ],
            rigid: w.kind == crate::config::WallKind::Rigid,
        })
    }

    /// The contact pressure per node \[Pa\]: `k · max(−gap, 0)` at the contact nodes, with the
    /// gap `x + u_x − face_x` of the displaced node; 0 at every other node.
    pub fn pressure(&self, mesh: &Mesh, displacement: &[[f64; 2]]) -> Vec<f64> {
        let mut p = vec![0.0; mesh.num_nodes()];
        for &n in &self.contact_nodes {
            if let (Some(x), Some(u)) = (mesh.nodes.get(n), displacement.get(n)) {
                let gap = x[0] + u[0] - self.face_x;
                p[n] = self.stiffness * (-gap).max(0.0);
            }
        }
        p
    }
}
