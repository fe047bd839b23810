//! Two parameters together: the product grid of their keys (Live2D Cubism's multiplied
//! keyforms, Inochi2D's 2D parameters), weighted bilinearly, and the correctives a rig may
//! author at its nodes.
//!
//! **Bilinear weights.** With parameter `a` at `u` in its segment `[a_i, a_{i+1}]` and `b`
//! at `w` in `[b_j, b_{j+1}]`, the node `(a_r, b_s)` of the grid weighs `α_r β_s`, the
//! product of the two parameters' 1D weights ([`super::KeyWeights`]): on the cell's four
//! corners `(1 − u)(1 − w)`, `u(1 − w)`, `(1 − u)w`, `uw` ([`bilinear`]), which sum to 1,
//! and 0 on every other node.
//!
//! **Correctives** (the research notes, `motion.md` §3). A rig combines parameters
//! additively in Kaji's log space: with each other parameter at its default, parameter `a`
//! at key `i` contributes the log-delta `Δa_i = L(a_i) − L(a_d)` (the logarithms of its
//! keyform at `i` and at its default `d`, per triangle: angle, log-stretch, and the
//! centroid's shift; a keyform not set is the rest, whose logarithms are 0). At a node
//! `(a_i, b_j)` the additive sum gives `Δa_i + Δb_j`. A corrective authored there as the
//! pose `P_ij` is stored as the log-delta
//!
//! ```text
//! K_ij = L(P_ij) − Δa_i − Δb_j
//! ```
//!
//! and weighs `α_i β_j` (its node's bilinear weight): at the node, with every other
//! parameter at its default, the blend's logarithms are `Δa_i + Δb_j + K_ij = L(P_ij)` and
//! the rig gives `P_ij` exactly (Kaji's blend reproduces a pose from its own logarithms,
//! position included). In blend weights a corrective of weight `c` is `+c` on its pose,
//! `−c` on `a_i`'s and `b_j`'s keyforms, `+c` on `a_d`'s and `b_d`'s (`Corrective::terms`).
//!
//! What a corrective adds away from its node: along the edges of the grid through the
//! node its weight falls linearly to 0 at the neighbouring nodes; it never acts when either
//! parameter is at its default (the weight has a factor of 0 there: a default key cannot
//! hold a corrective, whose place is then the other parameter's keyform). With correctives
//! at every node off the default row and column, the rig's logarithms are the bilinear
//! interpolation of the nodes' logarithms `Σ α_r β_s L(P_rs)` (with `P_r,d = Δa_r`, `P_d,s =
//! Δb_s`): Live2D's multiplied keyforms, blended in Kaji's log space instead of by vertex
//! positions. With fewer, the missing nodes are the additive sum. Three parameters off their
//! defaults get the pairwise correctives and the additive rest (no triple products).

use super::keyform::Keyform;
use super::parameter::KeyWeights;

/// The weights of a cell's four corners, `(1 − u)(1 − w)`, `u(1 − w)`, `(1 − u)w`, `uw`:
/// corner `(lower, lower)`, `(upper, lower)`, `(lower, upper)`, `(upper, upper)` of the
/// first and second parameter's segments. They sum to 1 (to round-off) for any `u`, `w`.
pub fn bilinear(u: f64, w: f64) -> [f64; 4] {
    [(1.0 - u) * (1.0 - w), u * (1.0 - w), (1.0 - u) * w, u * w]
}

/// The nodes of the cell holding two parameters' values, as `([key of a, key of b],
/// weight)`, in the corner order of [`bilinear`].
pub fn cell_weights(a: KeyWeights, b: KeyWeights) -> [([usize; 2], f64); 4] {
    let [w00, w10, w01, w11] = bilinear(a.u, b.u);
    let (i, j) = (a.lower, b.lower);
    [([i, j], w00), ([i + 1, j], w10), ([i, j + 1], w01), ([i + 1, j + 1], w11)]
}

/// A corrective: the pose authored at one node of two parameters' grid (not on either
/// default), kept as a keyform of the rig.
#[derive(Debug, Clone)]
pub(crate) struct Corrective {
    /// The two parameters (indices in the rig, the smaller first).
    pub(crate) parameters: [usize; 2],
    /// The node: a key index of each.
    pub(crate) keys: [usize; 2],
    /// The authored pose (`None` once cleared).
    pub(crate) keyform: Option<Keyform>,
}

impl Corrective {
    /// Its weight, the node's bilinear weight `α_i β_j`, from the parameters' key weights.
    #[inline]
    pub(crate) fn weight(&self, a: &KeyWeights, b: &KeyWeights) -> f64 {
        a.weight(self.keys[0]) * b.weight(self.keys[1])
    }

    /// Its log-delta as a combination of keyforms: `(parameter, key, coefficient)` of the
    /// parameters' keyforms in `K_ij = L(P_ij) − L(a_i) + L(a_d) − L(b_j) + L(b_d)` (the
    /// corrective's own pose, coefficient +1, is left out). `defaults`: each parameter's
    /// default key.
    pub(crate) fn terms(&self, defaults: [usize; 2]) -> [(usize, usize, f64); 4] {
        let [a, b] = self.parameters;
        let [i, j] = self.keys;
        [(a, i, -1.0), (a, defaults[0], 1.0), (b, j, -1.0), (b, defaults[1], 1.0)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_corners_weigh_their_products_and_sum_to_one() {
        for (u, w) in [(0.0, 0.0), (0.25, 0.5), (1.0, 0.3), (0.7, 1.0), (-0.5, 2.0)] {
            let c = bilinear(u, w);
            assert_eq!(c, [(1.0 - u) * (1.0 - w), u * (1.0 - w), (1.0 - u) * w, u * w]);
            assert!((c.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
        let cell = cell_weights(KeyWeights { lower: 1, u: 0.25 }, KeyWeights { lower: 0, u: 0.5 });
        let nodes: Vec<[usize; 2]> = cell.iter().map(|c| c.0).collect();
        assert_eq!(nodes, vec![[1, 0], [2, 0], [1, 1], [2, 1]]);
        assert_eq!(cell[1].1, 0.25 * 0.5);
        // At a node the weights are one-hot.
        let cell = cell_weights(KeyWeights { lower: 2, u: 0.0 }, KeyWeights { lower: 0, u: 1.0 });
        assert_eq!(cell.map(|c| c.1), [0.0, 0.0, 1.0, 0.0]);
    }
}
