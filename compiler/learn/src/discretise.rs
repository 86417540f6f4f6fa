//! Cells of the relative-pose space of one type pair: position voxels and rotation cells.
//!
//! Positions use `n` bins over the closed interval `[-R, R]` per axis; the upper edge belongs to the last bin and
//! anything outside falls in no cell.
//! Rotations use the rotation vector (axis · angle, angle in `[0, π]`), each component in `n` bins over `[-π, π]`.
//! The rotation vector jumps where the angle passes π, but regions are connected over position only and each voxel
//! keeps a *set* of rotation cells, so a region around a half turn simply keeps cells on both sides of the jump.
//! Sampling a cell keeps rotation vectors inside the π ball, so every sample lies in the cell it was drawn from.

use std::f64::consts::PI;

use rand::RngExt;

use crate::config::PairSettings;
use crate::demo::Pose;

/// Rotation draws per sample before a too-long rotation vector is shortened onto the π sphere.
const MAX_ROTATION_DRAWS: usize = 256;

/// Indices of a position voxel along x, y and z.
pub type Voxel = [usize; 3];
/// Indices of a rotation cell along the three rotation-vector components.
pub type RotationCell = [usize; 3];

/// The discretisation of one type pair.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Grid {
    bins: [usize; 3],
    half_range: [f64; 3],
    rotation_bins: usize,
}

impl Grid {
    /// The grid described by a pair's settings.
    pub fn new(settings: &PairSettings) -> Self {
        Grid {
            bins: settings.position_bins,
            half_range: settings.half_range,
            rotation_bins: settings.rotation_bins,
        }
    }

    /// Bins per position axis.
    pub fn bins(&self) -> [usize; 3] {
        self.bins
    }

    /// Bins per rotation-vector component.
    pub fn rotation_bins(&self) -> usize {
        self.rotation_bins
    }

    /// The voxel of a position, or `None` outside the range.
    pub fn voxel(&self, pose: &Pose) -> Option<Voxel> {
        let position = pose.translation.vector;
        let mut voxel = [0; 3];
        for axis in 0..3 {
            voxel[axis] = bin(position[axis], self.half_range[axis], self.bins[axis])?;
        }
        Some(voxel)
    }

    /// The rotation cell of a pose's rotation.
    pub fn rotation_cell(&self, pose: &Pose) -> RotationCell {
        let vector = pose.rotation.scaled_axis();
        let mut cell = [0; 3];
        for (component, value) in cell.iter_mut().zip(vector.iter()) {
            // A rotation vector's components never leave [-π, π], so a cell always exists.
            *component = bin(*value, PI, self.rotation_bins).unwrap_or(self.rotation_bins - 1);
        }
        cell
    }

    /// The centre of a voxel.
    pub fn voxel_centre(&self, voxel: Voxel) -> [f64; 3] {
        let mut centre = [0.0; 3];
        for axis in 0..3 {
            let width = 2.0 * self.half_range[axis] / self.bins[axis] as f64;
            centre[axis] = -self.half_range[axis] + (voxel[axis] as f64 + 0.5) * width;
        }
        centre
    }

    /// The extent of a voxel, per axis `(low, high)`.
    pub fn voxel_bounds(&self, voxel: Voxel) -> [(f64, f64); 3] {
        let mut bounds = [(0.0, 0.0); 3];
        for axis in 0..3 {
            let width = 2.0 * self.half_range[axis] / self.bins[axis] as f64;
            let low = -self.half_range[axis] + voxel[axis] as f64 * width;
            bounds[axis] = (low, low + width);
        }
        bounds
    }

    /// A pose drawn uniformly from a cell: position uniform in the voxel, rotation vector uniform in the rotation cell.
    pub fn sample_cell(
        &self,
        voxel: Voxel,
        rotation: RotationCell,
        rng: &mut impl rand::Rng,
    ) -> Pose {
        let bounds = self.voxel_bounds(voxel);
        let position =
            nalgebra::Vector3::from_fn(|axis, _| rng.random_range(bounds[axis].0..bounds[axis].1));
        let width = 2.0 * PI / self.rotation_bins as f64;
        let mut draw = || {
            nalgebra::Vector3::from_fn(|axis, _| {
                let low = -PI + rotation[axis] as f64 * width;
                rng.random_range(low..low + width)
            })
        };
        // A rotation vector longer than π names the same rotation as a shorter one in another cell, so such draws
        // are rejected; a cell that was ever observed reaches inside the π ball, so a draw soon lands there.
        let mut vector = draw();
        for _ in 0..MAX_ROTATION_DRAWS {
            if vector.norm() <= PI {
                break;
            }
            vector = draw();
        }
        if vector.norm() > PI {
            vector *= PI / vector.norm();
        }
        Pose::from_parts(position.into(), nalgebra::UnitQuaternion::from_scaled_axis(vector))
    }
}

/// The bin of `value` among `count` equal bins over `[-half_range, half_range]`.
fn bin(value: f64, half_range: f64, count: usize) -> Option<usize> {
    if !(value >= -half_range && value <= half_range) {
        return None;
    }
    let width = 2.0 * half_range / count as f64;
    let index = ((value + half_range) / width).floor() as usize;
    Some(index.min(count - 1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn grid() -> Grid {
        Grid::new(&PairSettings {
            position_bins: [4, 4, 2],
            half_range: [0.2, 0.2, 0.1],
            rotation_bins: 24,
            ..PairSettings::default()
        })
    }

    #[test]
    fn range_edges_belong_to_the_edge_bins_and_outside_is_no_cell() {
        assert_eq!(bin(-0.2, 0.2, 4), Some(0));
        assert_eq!(bin(0.2, 0.2, 4), Some(3));
        assert_eq!(bin(0.0, 0.2, 4), Some(2));
        assert_eq!(bin(-0.1000001, 0.2, 4), Some(0));
        assert_eq!(bin(0.2000001, 0.2, 4), None);
        assert_eq!(bin(f64::NAN, 0.2, 4), None);
        assert_eq!(grid().voxel(&Pose::translation(0.05, -0.15, 0.1)), Some([2, 0, 1]));
        assert_eq!(grid().voxel(&Pose::translation(0.05, -0.15, 0.11)), None);
    }

    #[test]
    fn voxel_centre_lies_in_its_voxel() {
        let g = grid();
        let centre = g.voxel_centre([1, 3, 0]);
        assert_eq!(g.voxel(&Pose::translation(centre[0], centre[1], centre[2])), Some([1, 3, 0]));
    }

    #[test]
    fn samples_stay_in_their_cell() {
        let g = grid();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for _ in 0..200 {
            let pose = g.sample_cell([3, 1, 0], [5, 12, 20], &mut rng);
            assert_eq!(g.voxel(&pose), Some([3, 1, 0]));
            assert_eq!(g.rotation_cell(&pose), [5, 12, 20]);
            // A cell reaching past the π sphere still yields members of itself.
            let half_turn = g.sample_cell([0, 0, 0], [12, 12, 23], &mut rng);
            assert_eq!(g.rotation_cell(&half_turn), [12, 12, 23]);
        }
    }

    #[test]
    fn half_turns_either_side_of_the_wrap_get_opposite_cells() {
        let g = grid();
        let just_below = Pose::rotation(nalgebra::Vector3::z() * (PI - 0.01));
        let just_above = Pose::rotation(nalgebra::Vector3::z() * -(PI - 0.01));
        assert_eq!(g.rotation_cell(&just_below), [12, 12, 23]);
        assert_eq!(g.rotation_cell(&just_above), [12, 12, 0]);
    }
}
