//! A turn about one axis of the secondary's own frame that a region leaves free: a round can set down at any yaw,
//! or held by a magnet at any yaw. The learner finds it in the demonstrations; a region model then neither tests
//! nor fits the angle of that turn, and draws it uniformly.
//!
//! A rotation splits into a swing and a twist about the axis, both taken from a reference rotation in the
//! secondary's frame: `reference⁻¹ · rotation = swing · twist`. Removing the twist leaves `reference · swing`,
//! which is the same for every angle of the turn; its swing, a rotation about an axis across the turn's, has
//! two degrees of freedom, which is what a region model with a free turn is over.

use std::f64::consts::{PI, TAU};

use nalgebra::{Quaternion, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A free turn: about `axis` (0, 1, 2: x, y, z of the secondary's frame), measured from `reference`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeTurn {
    /// The rotation turns are measured from.
    pub reference: UnitQuaternion<f64>,
    /// The axis of the secondary's frame the turn is about.
    pub axis: usize,
}

impl FreeTurn {
    /// The angle, in `(-π, π]`, of the turn about the axis that takes the reference towards `rotation`.
    pub fn twist(&self, rotation: &UnitQuaternion<f64>) -> f64 {
        twist(&self.reference, rotation, self.axis)
    }

    /// `rotation` with its twist removed: the same for every angle of the turn.
    pub fn untwisted(&self, rotation: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
        *rotation * self.turn(-self.twist(rotation))
    }

    /// `rotation` turned by `angle` about the axis, in the secondary's frame.
    pub fn turned(&self, rotation: &UnitQuaternion<f64>, angle: f64) -> UnitQuaternion<f64> {
        *rotation * self.turn(angle)
    }

    /// The two components, across the axis, of the rotation vector of `rotation`'s swing from the
    /// reference (`reference⁻¹ · rotation = swing · twist`): what is left of a rotation once its turn
    /// is taken out, with no wrap near the reference.
    pub fn swing(&self, rotation: &UnitQuaternion<f64>) -> [f64; 2] {
        let swing = (self.reference.inverse() * self.untwisted(rotation)).scaled_axis();
        let [first, second] = self.across();
        [swing[first], swing[second]]
    }

    /// The rotation `reference · swing · turn(angle)` of a swing given as by [`FreeTurn::swing`].
    pub fn rotation(&self, swing: [f64; 2], angle: f64) -> UnitQuaternion<f64> {
        let [first, second] = self.across();
        let mut vector = Vector3::zeros();
        vector[first] = swing[0];
        vector[second] = swing[1];
        self.turned(&(self.reference * UnitQuaternion::from_scaled_axis(vector)), angle)
    }

    /// The two axes across the turn's, in order.
    fn across(&self) -> [usize; 2] {
        match self.axis {
            0 => [1, 2],
            1 => [0, 2],
            _ => [0, 1],
        }
    }

    fn turn(&self, angle: f64) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&Unit::new_unchecked(Vector3::ith(self.axis, 1.0)), angle)
    }

    /// Checks a deserialised turn.
    pub fn validate(&self) -> Result<(), String> {
        if self.axis > 2 {
            return Err(format!("the free turn's axis is {}, not 0, 1 or 2", self.axis));
        }
        if !self.reference.coords.iter().all(|value| value.is_finite()) {
            return Err("the free turn's reference is not finite".to_string());
        }
        Ok(())
    }
}

/// The twist about `axis` of the secondary's frame that turns `reference` towards `rotation`, in `(-π, π]`.
pub fn twist(reference: &UnitQuaternion<f64>, rotation: &UnitQuaternion<f64>, axis: usize) -> f64 {
    let turn = reference.inverse() * rotation;
    let along = turn.imag()[axis.min(2)];
    let angle = 2.0 * along.atan2(turn.w);
    // atan2 gives (-π, π], doubled (-2π, 2π]: back onto one turn.
    if angle > PI {
        angle - TAU
    } else if angle <= -PI {
        angle + TAU
    } else {
        angle
    }
}

/// Serialised as `{ "reference": [w, i, j, k], "axis": n }`.
#[derive(Serialize, Deserialize)]
struct FreeTurnFile {
    reference: [f64; 4],
    axis: usize,
}

impl Serialize for FreeTurn {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let q = self.reference.quaternion();
        FreeTurnFile { reference: [q.w, q.i, q.j, q.k], axis: self.axis }.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for FreeTurn {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let file = FreeTurnFile::deserialize(deserializer)?;
        let [w, i, j, k] = file.reference;
        let quaternion = Quaternion::new(w, i, j, k);
        let norm = quaternion.norm();
        if !norm.is_finite() || norm < 1e-6 {
            return Err(serde::de::Error::custom("the free turn's reference is not a rotation"));
        }
        let turn =
            FreeTurn { reference: UnitQuaternion::new_normalize(quaternion), axis: file.axis };
        turn.validate().map_err(serde::de::Error::custom)?;
        Ok(turn)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removing_the_twist_gives_one_rotation_for_every_angle_of_the_turn() {
        let reference = UnitQuaternion::from_euler_angles(PI, 0.0, 0.3);
        let turn = FreeTurn { reference, axis: 2 };
        let tilt = UnitQuaternion::from_euler_angles(0.02, -0.01, 0.0);
        let base = reference * tilt;
        let untwisted = turn.untwisted(&base);
        for angle in [-3.0, -1.0, 0.0, 0.5, 2.9] {
            let rotation = turn.turned(&base, angle);
            assert!(turn.untwisted(&rotation).angle_to(&untwisted) < 1e-9, "{angle}");
        }
        assert!(turn.twist(&turn.turned(&reference, 1.2)) - 1.2 < 1e-12);
        let text = serde_json::to_string(&turn).expect("serialises");
        let back: FreeTurn = serde_json::from_str(&text).expect("reads back");
        assert!(back.reference.angle_to(&reference) < 1e-12 && back.axis == 2);
        assert!(serde_json::from_str::<FreeTurn>(r#"{"reference":[0,0,0,0],"axis":2}"#).is_err());
        assert!(serde_json::from_str::<FreeTurn>(r#"{"reference":[1,0,0,0],"axis":3}"#).is_err());
    }

    #[test]
    fn a_rotation_is_its_swing_and_twist_about_any_axis() {
        let reference = UnitQuaternion::from_euler_angles(PI, 0.0, 0.3);
        for axis in 0..3 {
            let turn = FreeTurn { reference, axis };
            for (roll, pitch, yaw) in [(0.02, -0.01, 1.0), (0.3, 0.2, -2.5), (-0.4, 0.1, 3.1)] {
                let rotation = reference * UnitQuaternion::from_euler_angles(roll, pitch, yaw);
                let swing = turn.swing(&rotation);
                let back = turn.rotation(swing, turn.twist(&rotation));
                assert!(back.angle_to(&rotation) < 1e-9, "axis {axis}: {back} for {rotation}");
                // The swing is the same whatever the turn.
                let turned = turn.turned(&rotation, 0.7);
                let again = turn.swing(&turned);
                assert!((again[0] - swing[0]).abs() + (again[1] - swing[1]).abs() < 1e-9);
            }
        }
        // A tilt across the axis is the swing itself.
        let turn = FreeTurn { reference: UnitQuaternion::identity(), axis: 2 };
        let tilted = UnitQuaternion::from_euler_angles(0.1, 0.0, 0.0);
        let swing = turn.swing(&tilted);
        assert!((swing[0] - 0.1).abs() < 1e-12 && swing[1].abs() < 1e-12, "{swing:?}");
    }
}
