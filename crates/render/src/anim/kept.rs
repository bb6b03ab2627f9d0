//! The frames an animation keeps: what a picture needs of each frame ([`KeptFrame`]), the bounded,
//! evenly thinned store of them ([`KeptFrames`]), and the automatic magnification over them.

use crate::Frame;

/// The part of one frame kept for the animations and the viewer.
#[derive(Clone, Debug, PartialEq)]
pub struct KeptFrame {
    /// Step number.
    pub step: usize,
    /// Time \[s\].
    pub time: f64,
    /// Proxy angle \[rad\].
    pub theta: f64,
    /// Elastic displacement `u − (R(θ)X − X)` per node \[m\].
    pub elastic: Vec<[f32; 2]>,
    /// |elastic| per node \[m\]: what `displacement.gif` and the viewer colour. The total |u| is
    /// nearly all rigid rotation, while the shape drawn magnifies the elastic part: colouring |u|
    /// would show the swing's angle, not the deformation drawn.
    pub elastic_abs: Vec<f32>,
    /// Von Mises stress per node \[Pa\].
    pub von_mises: Vec<f32>,
    /// The nodes `0..rotating` (the pendulum's) turn with θ; the nodes after them (a second
    /// body, such as a deformable wall) do not: their `elastic` is their whole displacement and
    /// they are drawn at `X + m · u`.
    pub rotating: usize,
}

impl KeptFrame {
    /// Extracts what the pictures need from a frame of the mesh `nodes`.
    pub fn from_frame(nodes: &[[f64; 2]], frame: &Frame<'_>) -> Self {
        Self::from_frame_of_bodies(nodes, nodes.len(), frame)
    }

    /// [`KeptFrame::from_frame`] for a model of several bodies: only the nodes `0..rotating` (the
    /// pendulum's) turn with θ (see [`KeptFrame::rotating`]).
    pub fn from_frame_of_bodies(nodes: &[[f64; 2]], rotating: usize, frame: &Frame<'_>) -> Self {
        let (s, c) = frame.theta.sin_cos();
        let elastic: Vec<[f32; 2]> = nodes
            .iter()
            .zip(frame.displacement)
            .enumerate()
            .map(|(i, (x, u))| {
                if i >= rotating {
                    return [u[0] as f32, u[1] as f32];
                }
                let rigid = [c * x[0] - s * x[1] - x[0], s * x[0] + c * x[1] - x[1]];
                [(u[0] - rigid[0]) as f32, (u[1] - rigid[1]) as f32]
            })
            .collect();
        Self {
            step: frame.step,
            time: frame.time,
            theta: frame.theta,
            elastic_abs: elastic.iter().map(|e| e[0].hypot(e[1])).collect(),
            elastic,
            von_mises: frame.von_mises.iter().map(|&v| v as f32).collect(),
            rotating,
        }
    }

    /// Drawn positions `R(θ)X + m · elastic` \[m\].
    pub fn drawn_positions(&self, nodes: &[[f64; 2]], magnification: f64) -> Vec<[f64; 2]> {
        let (s, c) = self.theta.sin_cos();
        nodes
            .iter()
            .zip(&self.elastic)
            .enumerate()
            .map(|(i, (x, e))| {
                let at = if i < self.rotating {
                    [c * x[0] - s * x[1], s * x[0] + c * x[1]]
                } else {
                    *x
                };
                [at[0] + magnification * e[0] as f64, at[1] + magnification * e[1] as f64]
            })
            .collect()
    }
}

/// A bounded, evenly thinned collection of frames (at most `max_frames`).
///
/// Offered frames are numbered `0, 1, 2, …` in arrival order; frame `k` is kept when `k` is a
/// multiple of the stride. When a kept frame would exceed `max_frames`, every second kept frame is
/// dropped and the stride doubles. The most recent offered frame is held aside so that
/// [`KeptFrames::into_frames`] can end on the last state of the run.
#[derive(Clone, Debug)]
pub struct KeptFrames {
    max_frames: usize,
    stride: usize,
    offered: usize,
    frames: Vec<KeptFrame>,
    last: Option<KeptFrame>,
}

impl KeptFrames {
    /// An empty collection keeping at most `max_frames` (at least 2) frames.
    pub fn new(max_frames: usize) -> Self {
        Self {
            max_frames: max_frames.max(2),
            stride: 1,
            offered: 0,
            frames: Vec::new(),
            last: None,
        }
    }

    /// Offers the next frame.
    pub fn push(&mut self, frame: KeptFrame) {
        let k = self.offered;
        self.offered += 1;
        if !k.is_multiple_of(self.stride) {
            self.last = Some(frame);
            return;
        }
        self.last = None;
        if self.frames.len() == self.max_frames {
            // Keep indices that are multiples of 2·stride: the even positions of the kept list.
            let mut i = 0;
            self.frames.retain(|_| {
                i += 1;
                (i - 1) % 2 == 0
            });
            self.stride *= 2;
            if !k.is_multiple_of(self.stride) {
                self.last = Some(frame);
                return;
            }
        }
        self.frames.push(frame);
    }

    /// Number of frames currently kept (not counting the held-aside last one).
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty() && self.last.is_none()
    }

    /// Current stride between kept frames (in offered frames).
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The kept frames in time order, ending with the last offered one (at most `max_frames`).
    pub fn into_frames(mut self) -> Vec<KeptFrame> {
        if let Some(last) = self.last.take() {
            if self.frames.len() == self.max_frames {
                self.frames.pop();
            }
            self.frames.push(last);
        }
        self.frames
    }
}

/// The automatic magnification: the largest elastic displacement over `frames` is drawn as 5 % of
/// the pendulum size (largest `|X|`), rounded to two significant digits; 1 when nothing deforms.
pub fn auto_magnification(nodes: &[[f64; 2]], frames: &[KeptFrame]) -> f64 {
    let size = nodes.iter().map(|x| x[0].hypot(x[1])).fold(0.0, f64::max);
    let e_max = frames
        .iter()
        .flat_map(|f| f.elastic.iter())
        .map(|e| (e[0] as f64).hypot(e[1] as f64))
        .fold(0.0, f64::max);
    if size.is_nan() || size <= 0.0 || e_max.is_nan() || e_max <= size * 1e-12 {
        return 1.0;
    }
    let m = 0.05 * size / e_max;
    let mag = 10f64.powf(m.log10().floor() - 1.0);
    ((m / mag).round() * mag).max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anim::AnimField;

    fn dummy(step: usize) -> KeptFrame {
        KeptFrame {
            step,
            time: step as f64,
            theta: 0.0,
            elastic: vec![],
            elastic_abs: vec![],
            von_mises: vec![],
            rotating: 0,
        }
    }

    /// `keep` applied to a frame of two nodes displaced by `u` at angle `theta` (no velocity,
    /// acceleration or stress).
    fn two_node_frame(theta: f64, u: &[[f64; 2]; 2], keep: impl Fn(&Frame<'_>) -> KeptFrame) -> KeptFrame {
        let zeros = [[0.0; 2]; 2];
        keep(&Frame {
            step: 1,
            time: 0.01,
            theta,
            displacement: u,
            velocity: &zeros,
            acceleration: &zeros,
            von_mises: &[0.0; 2],
            cauchy: &[[0.0; 3]; 2],
        })
    }

    #[test]
    fn the_displacement_animation_colours_the_elastic_part_it_magnifies_not_the_rigid_swing() {
        // node 0 turned rigidly by θ (|u| = 0.06 m, no elastic part); node 1 the same plus 1 µm
        let nodes = [[0.0, -0.3], [0.01, -0.3]];
        let theta: f64 = 0.2;
        let (s, c) = theta.sin_cos();
        let rigid = |x: [f64; 2]| [c * x[0] - s * x[1] - x[0], s * x[0] + c * x[1] - x[1]];
        let (r0, r1) = (rigid(nodes[0]), rigid(nodes[1]));
        let u = [r0, [r1[0] + 1e-6, r1[1]]];
        let f = two_node_frame(theta, &u, |frame| KeptFrame::from_frame(&nodes, frame));
        let shown = AnimField::Displacement.values(&f);
        // f32 storage: the rigid part of 0.06 m cancels to within its rounding, ~1e-8 m
        assert!(shown[0] < 1e-8, "rigid node coloured {}", shown[0]);
        assert!((shown[1] - 1e-6).abs() < 2e-8, "elastic node coloured {}", shown[1]);
    }

    #[test]
    fn nodes_of_a_second_body_do_not_turn_with_the_pendulum() {
        // node 0 is the pendulum's, node 1 a wall's; both displaced by the same u
        let nodes = [[0.0, -0.3], [-0.1, -0.3]];
        let theta: f64 = 0.2;
        let u = [[0.3 * theta.sin(), 0.3 - 0.3 * theta.cos()], [1e-6, 0.0]];
        let f = two_node_frame(theta, &u, |frame| KeptFrame::from_frame_of_bodies(&nodes, 1, frame));
        assert!(
            f.elastic[0][0].abs() < 1e-7 && f.elastic[0][1].abs() < 1e-7,
            "{:?}",
            f.elastic[0]
        );
        assert_eq!(f.elastic[1], [1e-6, 0.0]);
        let p = f.drawn_positions(&nodes, 1e4);
        assert!(
            (p[0][0] - u[0][0]).abs() < 1e-6 && (p[0][1] - (-0.3 + u[0][1])).abs() < 1e-6,
            "{:?}",
            p[0]
        );
        assert!((p[1][0] - (-0.1 + 1e-2)).abs() < 1e-9 && p[1][1] == -0.3, "{:?}", p[1]);
        // one body: every node turns, as before
        assert_eq!(
            two_node_frame(theta, &u, |frame| KeptFrame::from_frame(&nodes, frame)).rotating,
            2
        );
    }

    #[test]
    fn kept_frames_stay_bounded_and_evenly_spaced() {
        let mut k = KeptFrames::new(10);
        for s in 0..1000 {
            k.push(dummy(s));
            assert!(k.len() <= 10);
        }
        let frames = k.into_frames();
        assert!(frames.len() <= 10 && frames.len() >= 5, "{}", frames.len());
        assert_eq!(frames[0].step, 0);
        assert_eq!(frames.last().unwrap().step, 999, "ends on the last state");
        let d = frames[1].step - frames[0].step;
        for w in frames[..frames.len() - 1].windows(2) {
            assert_eq!(w[1].step - w[0].step, d);
        }
    }

    #[test]
    fn thinning_holds_for_every_bound_and_run_length() {
        for max in 2..20 {
            for n in 1..300 {
                let mut k = KeptFrames::new(max);
                for s in 0..n {
                    k.push(dummy(s));
                }
                let frames = k.into_frames();
                assert!(frames.len() <= max, "max {max}, n {n}: {}", frames.len());
                assert!(
                    frames.len() >= max.min(n) / 2,
                    "max {max}, n {n}: only {}",
                    frames.len()
                );
                assert_eq!(frames[0].step, 0);
                assert_eq!(frames.last().unwrap().step, n - 1);
                assert!(frames.windows(2).all(|w| w[1].step > w[0].step));
            }
        }
    }

    #[test]
    fn few_frames_are_all_kept() {
        let mut k = KeptFrames::new(10);
        for s in 0..7 {
            k.push(dummy(s));
        }
        let steps: Vec<usize> = k.into_frames().iter().map(|f| f.step).collect();
        assert_eq!(steps, (0..7).collect::<Vec<_>>());
    }

    #[test]
    fn auto_magnification_makes_elastic_five_percent_of_size() {
        let nodes = [[0.0, 0.0], [0.0, -0.3]];
        let mut f = dummy(0);
        f.elastic = vec![[0.0, 0.0], [1e-6, 0.0]];
        let m = auto_magnification(&nodes, &[f]);
        assert!((m * 1e-6 - 0.015).abs() < 0.015 * 0.05, "{m}");
    }
}
