//! Jenga towers: layers of two blocks at the outer positions, each layer turned a quarter turn
//! from the one below, 1 mm between layers; and the training structures the Jenga demonstrator
//! builds from them (at most three blocks).
//!
//! A structure is a list of block poses in its anchor's frame (the anchor lies on the table top,
//! z up), in building order: a block is placed only once every block below it is.

use std::f64::consts::FRAC_PI_2;

use lamp_geometry::Pose;
use lamp_world::RESTING_GAP;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::skills::pose;

/// The size of a block: length (its x), width (its y) and height (its z), metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BlockSize {
    pub(crate) length: f64,
    pub(crate) width: f64,
    pub(crate) height: f64,
}

impl BlockSize {
    /// The pose of block `slot` (0 or 1) of layer `layer` in the anchor's frame: the layer's
    /// blocks lie along the layer's direction, one width either side of the centre line (a
    /// block-wide gap between them), at rest 1 mm above what is below. `yaw` is the layer's yaw
    /// in the anchor's frame (layer 0: 0; a layer above turned ±90° from the one below).
    pub(crate) fn slot(&self, layer: usize, yaw: f64, slot: usize) -> Pose {
        let side = if slot == 0 { 1.0 } else { -1.0 };
        let z = RESTING_GAP + self.height / 2.0 + layer as f64 * (self.height + RESTING_GAP);
        // Across the layer's direction: the block's own y axis.
        let (sin, cos) = yaw.sin_cos();
        let offset = side * self.width;
        pose(-sin * offset, cos * offset, z, 0.0, 0.0, yaw)
    }
}

/// A training structure: the block poses in building order; the demonstration places all but
/// the last beforehand and moves the last.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Training {
    pub(crate) name: &'static str,
    pub(crate) poses: Vec<Pose>,
}

/// Draws a training structure of at most `objects` blocks.
///
/// - a single block on the table (15 % of the draws);
/// - the two blocks of the first layer, in either order (15 %);
/// - a third block across them (70 %: it makes the most relations, and each of its cells is
///   visited by only half of its variants): at either of the two slots of the second layer, turned
///   +90° or −90° from the first layer. A block is the same body turned by a half turn, but the
///   learner sees its frame: in a tower the second layer is turned +90° from the first and the
///   third −90° from the second, so both turns must be demonstrated, and each slot of the upper
///   layer relates to each block below at a different relative position.
///
/// With at most three blocks, no demonstration can show a block placed beside another of its
/// layer and across two below it at once; the spec's block–block range leaves blocks of one
/// layer out of every region, so that every placement in a tower makes only relations some
/// single placement here makes (docs/demonstrations.md).
pub(crate) fn draw_training(size: &BlockSize, objects: usize, rng: &mut ChaCha8Rng) -> Training {
    let u: f64 = rng.random();
    let kind = match objects {
        0 | 1 => 0,
        2 => usize::from(u >= 0.5),
        _ if u < 0.15 => 0,
        _ if u < 0.3 => 1,
        _ => 2,
    };
    let first = rng.random_range(0..2usize);
    let layer0 = [size.slot(0, 0.0, first), size.slot(0, 0.0, 1 - first)];
    match kind {
        0 => Training { name: "single", poses: vec![layer0[0]] },
        1 => Training { name: "layer", poses: layer0.to_vec() },
        _ => {
            let turn = if rng.random::<bool>() { FRAC_PI_2 } else { -FRAC_PI_2 };
            let slot = rng.random_range(0..2usize);
            let mut poses = layer0.to_vec();
            poses.push(size.slot(1, turn, slot));
            Training { name: "across", poses }
        }
    }
}

#[cfg(test)]
mod tests {
    use lamp_geometry::math::relative_pose;

    use super::*;

    const JENGA: BlockSize = BlockSize { length: 0.1524, width: 0.0508, height: 0.03048 };

    /// The tower of `layers` layers whose layer yaws alternate 0, `turn`, 0, …, in building
    /// order (layer by layer, slot 0 first).
    fn tower(size: &BlockSize, layers: usize, turn: f64) -> Vec<Pose> {
        (0..layers)
            .flat_map(|layer| {
                let yaw = if layer % 2 == 0 { 0.0 } else { turn };
                [size.slot(layer, yaw, 0), size.slot(layer, yaw, 1)]
            })
            .collect()
    }

    #[test]
    fn a_layer_has_a_block_wide_gap_and_rests_a_millimetre_above_the_one_below() {
        let tower = tower(&JENGA, 3, FRAC_PI_2);
        let p = |i: usize| tower[i].translation.vector;
        assert!((p(0).y - p(1).y - 2.0 * JENGA.width).abs() < 1e-12);
        assert!((p(2).x - p(3).x).abs() > 2.0 * JENGA.width - 1e-12);
        let step = p(2).z - p(0).z;
        assert!((step - JENGA.height - RESTING_GAP).abs() < 1e-12);
        assert!((p(0).z - JENGA.height / 2.0 - RESTING_GAP).abs() < 1e-12);
        // The third layer is parallel to the first, straight above it.
        assert!((p(4).y - p(0).y).abs() < 1e-12 && (p(4).x - p(0).x).abs() < 1e-12);
    }

    #[test]
    fn an_upper_block_sits_across_both_blocks_below_at_one_width_from_their_centres() {
        let tower = tower(&JENGA, 2, FRAC_PI_2);
        for lower in &tower[..2] {
            for upper in &tower[2..] {
                let relative = relative_pose(lower, upper).translation.vector;
                assert!((relative.x.abs() - JENGA.width).abs() < 1e-12, "{relative:?}");
                assert!((relative.y.abs() - JENGA.width).abs() < 1e-12, "{relative:?}");
            }
        }
    }
}
