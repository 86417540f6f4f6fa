//! The services the host offers to every plugin call: progress, cancellation and geometric oracles.

use crate::error::HostError;

/// A pose as `[x, y, z, qx, qy, qz, qw]`: a position in metres and a unit quaternion.
pub type Pose = [f64; 7];

/// The identity pose.
pub const IDENTITY_POSE: Pose = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];

/// What the host offers a plugin during one call.
///
/// The host owns the layout of a configuration vector: plugins treat configurations as opaque
/// `f64` slices and use [`distance`](Self::distance), [`interpolate`](Self::interpolate) and
/// [`sample_configuration`](Self::sample_configuration) rather than their own arithmetic (angles
/// wrap, quaternion coordinates slerp).
/// Robots and links are named as in the world state the host sends.
///
/// Every method has a default: no progress display, never cancelled, and
/// [`HostError::Unsupported`] for the geometric oracles, so a host for task planning implements
/// only what it offers.
///
/// # Example
/// A host for a one-dimensional robot whose configuration is a position on a rail from 0 to 10.
/// ```
/// use lamp_plugin_api::{HostError, HostServices};
///
/// struct Rail;
///
/// impl HostServices for Rail {
///     fn configuration_is_valid(&self, _robot: &str, q: &[f64]) -> Result<bool, HostError> {
///         Ok(q.len() == 1 && (0.0..=10.0).contains(&q[0]))
///     }
///     fn distance(&self, _robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
///         Ok((a[0] - b[0]).abs())
///     }
///     fn sample_configuration(&self, _robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
///         // A real host seeds a proper generator; one multiplicative hash step shows the idea.
///         let unit = (seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64 / (1u64 << 53) as f64;
///         Ok(vec![10.0 * unit])
///     }
/// }
///
/// assert_eq!(Rail.configuration_is_valid("cart", &[4.0]), Ok(true));
/// assert_eq!(Rail.distance("cart", &[1.0], &[4.0]), Ok(3.0));
/// let sample = Rail.sample_configuration("cart", 7).unwrap();
/// assert!((0.0..10.0).contains(&sample[0]));
/// assert_eq!(Rail.sample_configuration("cart", 7), Ok(sample));
/// assert!(Rail.solve_ik("cart", "tool", &[0.0; 7], &[0.0]).is_err());
/// ```
pub trait HostServices {
    /// Reports progress: `fraction` in [0, 1] and a short message.
    fn report_progress(&self, fraction: f64, message: &str) {
        let _ = (fraction, message);
    }

    /// Whether the host asks the plugin to stop; long loops poll it and return
    /// [`crate::PluginError::Cancelled`].
    fn is_cancelled(&self) -> bool {
        false
    }

    /// Whether configuration `q` of `robot` is within joint limits and collision-free.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable or the robot is unknown.
    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        let _ = (robot, q);
        Err(HostError::unsupported("configuration_is_valid"))
    }

    /// Whether every configuration on the host's interpolation from `a` to `b` is valid.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable or the robot is unknown.
    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        let _ = (robot, a, b);
        Err(HostError::unsupported("edge_is_valid"))
    }

    /// A collision-free configuration placing `link` at `target`, searched from `seed_q`;
    /// `None` when the solver finds none.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable or the robot or link is unknown.
    fn solve_ik(
        &self,
        robot: &str,
        link: &str,
        target: &Pose,
        seed_q: &[f64],
    ) -> Result<Option<Vec<f64>>, HostError> {
        let _ = (robot, link, target, seed_q);
        Err(HostError::unsupported("solve_ik"))
    }

    /// The world pose of `link` at configuration `q`.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable or the robot or link is unknown.
    fn forward_kinematics(&self, robot: &str, q: &[f64], link: &str) -> Result<Pose, HostError> {
        let _ = (robot, q, link);
        Err(HostError::unsupported("forward_kinematics"))
    }

    /// The configuration-space distance between `a` and `b`.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable or the robot is unknown.
    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        let _ = (robot, a, b);
        Err(HostError::unsupported("distance"))
    }

    /// `q` in the form [`nearest`](Self::nearest) reads; by default `q` itself.
    ///
    /// A sampling-based planner compares every new state with every state it keeps, so it keeps
    /// each state's form: a host whose distance derives something costly from a configuration (a
    /// quaternion from a rotation vector) derives it here, once per state.
    ///
    /// # Errors
    /// [`HostError`] when the robot is unknown or `q` is not one of its configurations.
    fn distance_form(&self, robot: &str, q: &[f64]) -> Result<Vec<f64>, HostError> {
        let _ = robot;
        Ok(q.to_vec())
    }

    /// The index of the first of `forms` (the [`distance_form`](Self::distance_form)s of
    /// configurations) whose configuration is strictly nearest, by
    /// [`distance`](Self::distance) from it, to the configuration whose form is `form`; 0 when
    /// none is nearer than infinity. Whatever shortcut a host takes, the answer is the one this
    /// default scan gives, so that a planner's choices do not depend on the host's speed. A host
    /// overriding one of the two form services overrides both.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable, the robot is unknown or a form is not one
    /// of its forms.
    fn nearest(&self, robot: &str, forms: &[Vec<f64>], form: &[f64]) -> Result<usize, HostError> {
        let mut best = (0, f64::INFINITY);
        for (index, candidate) in forms.iter().enumerate() {
            let d = self.distance(robot, candidate, form)?;
            if d < best.1 {
                best = (index, d);
            }
        }
        Ok(best.0)
    }

    /// The configuration a fraction `t` in [0, 1] of the way from `a` to `b`.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable or the robot is unknown.
    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        let _ = (robot, a, b, t);
        Err(HostError::unsupported("interpolate"))
    }

    /// A configuration of `robot` drawn uniformly over its sampling space (host layout) by the
    /// host's own generator seeded with `seed`: the same seed gives the same configuration.
    ///
    /// Only the host knows what uniform means for a configuration (angles wrap, rotations are
    /// scaled-axis triples, unbounded base coordinates are drawn in a sampling box, and only the
    /// moving joint group changes), so a sampling-based planner asks for its random states here
    /// and keeps its own randomness in the generator that draws the seeds.
    ///
    /// # Errors
    /// [`HostError`] when the service is unavailable or the robot is unknown.
    fn sample_configuration(&self, robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
        let _ = (robot, seed);
        Err(HostError::unsupported("sample_configuration"))
    }
}

/// A host with no geometry, no progress display and no cancellation: enough for task planners
/// and tests.
#[derive(Clone, Copy, Debug, Default)]
pub struct MinimalHost;

impl HostServices for MinimalHost {}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a line; a NaN is not one.
    struct Line;

    impl HostServices for Line {
        fn distance(&self, _robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
            if a[0].is_nan() {
                return Err(HostError::failed("not a point"));
            }
            Ok((a[0] - b[0]).abs())
        }
    }

    #[test]
    fn the_default_nearest_is_the_first_strictly_nearest_by_distance() {
        let forms: Vec<Vec<f64>> = [5.0, 2.0, 4.0, 2.0]
            .iter()
            .map(|&x| Line.distance_form("point", &[x]))
            .collect::<Result<_, _>>()
            .expect("the default form is the configuration");
        assert_eq!(forms[1], vec![2.0]);
        // 2 and 4 are both 1 away from 3: the first of them is the nearest.
        assert_eq!(Line.nearest("point", &forms, &[3.0]), Ok(1));
        assert_eq!(Line.nearest("point", &[], &[3.0]), Ok(0));
        assert!(Line.nearest("point", &[vec![1.0], vec![f64::NAN]], &[3.0]).is_err());
    }
}
