//! Cells of the relative-pose space of one type pair: position voxels and rotation cells.
//!
//! Positions use `n` bins over the closed interval `[-R, R]` per axis; the upper edge belongs to the last bin and
//! anything outside falls in no cell. Where no such grid keeps the places the demonstrations stop at apart, the
//! selection gives each place a box of its own instead ([`Grid::with_boxes`]): voxel `[i, 0, 0]` is box `i`, and
//! a position in no box falls in no cell.
//! Rotations use the rotation vector (axis · angle, angle in `[0, π]`), each component in `n` bins over `[-π, π]`.
//! Where the demonstrations leave a turn about an axis of the secondary free ([`FreeTurn`]), the rotation vector is
//! that of the turn from a reference rotation, in the secondary's frame, and its component along the axis has one
//! bin: "upright, at any yaw" is then one cell.
//! The rotation vector jumps where the angle passes π, but regions are connected over position only and each voxel
//! keeps a *set* of rotation cells, so a region around a half turn simply keeps cells on both sides of the jump.
//! Sampling a cell keeps rotation vectors inside the π ball, so every sample lies in the cell it was drawn from.

use std::f64::consts::PI;

use rand::RngExt;

use crate::config::PairSettings;
use crate::demo::Pose;
pub(crate) use lamp_abstraction::FreeTurn;

/// Rotation draws per sample before a too-long rotation vector is shortened onto the π sphere.
const MAX_ROTATION_DRAWS: usize = 256;

/// Indices of a position voxel along x, y and z.
pub type Voxel = [usize; 3];
/// Indices of a rotation cell along the three rotation-vector components.
pub type RotationCell = [usize; 3];

/// The discretisation of one type pair.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    bins: [usize; 3],
    half_range: [f64; 3],
    rotation_bins: usize,
    free_turn: Option<FreeTurn>,
    /// One box per place, per axis `(low, high)`, pairwise disjoint; empty for the uniform grid.
    boxes: Vec<Bounds>,
}

/// The extent of a cell per axis, `(low, high)`.
pub type Bounds = [(f64, f64); 3];

impl Grid {
    /// The grid described by a pair's settings.
    pub fn new(settings: &PairSettings) -> Self {
        Grid {
            bins: settings.position_bins,
            half_range: settings.half_range,
            rotation_bins: settings.rotation_bins,
            free_turn: settings.free_turn,
            boxes: Vec::new(),
        }
    }

    /// The settings' rotation cells over the given position boxes (pairwise disjoint), one voxel each, in place
    /// of the settings' uniform grid.
    pub fn with_boxes(settings: &PairSettings, boxes: Vec<Bounds>) -> Self {
        Grid { boxes, ..Grid::new(settings) }
    }

    /// The position boxes, if the grid is made of boxes rather than uniform bins.
    pub fn boxes(&self) -> &[Bounds] {
        &self.boxes
    }

    /// Bins per position axis.
    pub fn bins(&self) -> [usize; 3] {
        self.bins
    }

    /// Bins per rotation-vector component (but a free turn's, which has one).
    pub fn rotation_bins(&self) -> usize {
        self.rotation_bins
    }

    /// The turn left free, if any.
    pub fn free_turn(&self) -> Option<FreeTurn> {
        self.free_turn
    }

    /// Bins of each rotation-vector component.
    fn component_bins(&self) -> [usize; 3] {
        [0, 1, 2].map(|component| match self.free_turn {
            Some(turn) if turn.axis == component => 1,
            _ => self.rotation_bins,
        })
    }

    /// The rotation vector cells are taken of.
    fn cell_vector(&self, rotation: &nalgebra::UnitQuaternion<f64>) -> nalgebra::Vector3<f64> {
        match self.free_turn {
            Some(turn) => (turn.reference.inverse() * rotation).scaled_axis(),
            None => rotation.scaled_axis(),
        }
    }

    /// The rotation of a cell vector.
    fn cell_rotation(&self, vector: nalgebra::Vector3<f64>) -> nalgebra::UnitQuaternion<f64> {
        let rotation = nalgebra::UnitQuaternion::from_scaled_axis(vector);
        match self.free_turn {
            Some(turn) => turn.reference * rotation,
            None => rotation,
        }
    }

    /// The rotation at the centre of a rotation cell.
    pub fn rotation_cell_centre(&self, cell: RotationCell) -> nalgebra::UnitQuaternion<f64> {
        let bins = self.component_bins();
        let vector = nalgebra::Vector3::from_fn(|component, _| {
            -PI + (cell[component] as f64 + 0.5) * 2.0 * PI / bins[component] as f64
        });
        self.cell_rotation(vector)
    }

    /// The voxel of a position, or `None` outside the range.
    pub fn voxel(&self, pose: &Pose) -> Option<Voxel> {
        let position = pose.translation.vector;
        if !self.boxes.is_empty() {
            let inside = |bounds: &Bounds| {
                (0..3).all(|axis| {
                    position[axis] >= bounds[axis].0 && position[axis] <= bounds[axis].1
                })
            };
            return self.boxes.iter().position(inside).map(|index| [index, 0, 0]);
        }
        let mut voxel = [0; 3];
        for axis in 0..3 {
            voxel[axis] = bin(position[axis], self.half_range[axis], self.bins[axis])?;
        }
        Some(voxel)
    }

    /// The rotation cell of a pose's rotation.
    pub fn rotation_cell(&self, pose: &Pose) -> RotationCell {
        let vector = self.cell_vector(&pose.rotation);
        let bins = self.component_bins();
        // A rotation vector's components never leave [-π, π], so a cell always exists.
        [0, 1, 2].map(|component| {
            bin(vector[component], PI, bins[component]).unwrap_or(bins[component] - 1)
        })
    }

    /// The centre of a voxel.
    pub fn voxel_centre(&self, voxel: Voxel) -> [f64; 3] {
        if !self.boxes.is_empty() {
            return self.voxel_bounds(voxel).map(|(low, high)| 0.5 * (low + high));
        }
        let mut centre = [0.0; 3];
        for axis in 0..3 {
            let width = 2.0 * self.half_range[axis] / self.bins[axis] as f64;
            centre[axis] = -self.half_range[axis] + (voxel[axis] as f64 + 0.5) * width;
        }
        centre
    }

    /// The extent of a voxel, per axis `(low, high)`.
    pub fn voxel_bounds(&self, voxel: Voxel) -> Bounds {
        if let Some(bounds) = self.boxes.get(voxel[0]) {
            return *bounds;
        }
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
        let widths = self.component_bins().map(|bins| 2.0 * PI / bins as f64);
        let mut draw = || {
            nalgebra::Vector3::from_fn(|axis, _| {
                let low = -PI + rotation[axis] as f64 * widths[axis];
                rng.random_range(low..low + widths[axis])
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
        Pose::from_parts(position.into(), self.cell_rotation(vector))
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
