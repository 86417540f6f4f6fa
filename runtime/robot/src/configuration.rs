//! Configuration-space operations used by motion planning: distance, interpolation, sampling,
//! limits, and applying a velocity step.
//!
//! Wrapped angles (continuous joints, planar yaw) take the short way round at ±π. The three
//! components of a rotation vector are one rotation: distance is the geodesic angle, interpolation is
//! slerp, sampling is uniform over SO(3), and values are kept canonical (angle in [0, π]).

use std::f64::consts::{PI, TAU};

use lamp_geometry::{Rotation, Vec3};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::robot::{CoordinateKind, JointGroup, Robot};

/// How far outside its limits a coordinate may be and still count as within them (rounding slack).
pub const LIMIT_TOLERANCE: f64 = 1e-9;
/// Unbounded coordinates (a planar base's x and y by default) are sampled within this distance of
/// the reference value; bound them with [`Robot::with_coordinate_limits`] to sample a workspace.
pub const UNBOUNDED_SAMPLE_HALF_WIDTH: f64 = 2.0;

/// Wraps an angle into [-π, π).
#[inline]
pub fn wrap_angle(angle: f64) -> f64 {
    (angle + PI).rem_euclid(TAU) - PI
}

#[inline]
fn rotation_at(q: &[f64], start: usize) -> Rotation {
    Rotation::from_scaled_axis(Vec3::new(q[start], q[start + 1], q[start + 2]))
}

/// Values a rotation adds to a configuration's distance form: its unit quaternion.
const QUATERNION_VALUES: usize = 4;

/// The unit quaternion stored at `form[start..start + 4]` as `[i, j, k, w]`.
#[inline]
fn quaternion_at(form: &[f64], start: usize) -> Rotation {
    let quaternion =
        nalgebra::Quaternion::new(form[start + 3], form[start], form[start + 1], form[start + 2]);
    Rotation::new_unchecked(quaternion)
}

/// The smallest vector part [`angle_lower_bound`] bounds: below it the bound is 0. Its square is
/// still a normal number, so no bound falls among the subnormals, where a relative error bound
/// of the arc tangent says little.
const SMALLEST_BOUNDED_VECTOR_NORM: f64 = 1e-150;

/// How far from 1 the squared norm of a quaternion may be for [`angle_lower_bound`] to bound it:
/// a product of two unit quaternions is within some 1e-15, a quaternion far from unit is not
/// bounded.
const UNIT_NORM_SQUARED_SLACK: f64 = 1e-9;

/// A lower bound on `rotation.angle()` as computed, without its arc tangent (0 where the reasoning
/// below does not hold).
///
/// `angle()` is `2φ` with `φ = atan2(n, |w|)` in [0, π/2], of the vector part's norm `n` and the
/// scalar part `w`; so `sin φ = n / r` and `cos φ = |w| / r` with `r = √(n² + w²)`. Snellius'
/// inequality `φ ≥ 3 sin φ / (2 + cos φ)` (its difference grows from 0 with derivative
/// `(1 − cos φ)² / (2 + cos φ)²`) gives `φ ≥ 3n / (2r + |w|)`, within a relative `φ⁴ / 180` of
/// `φ`. With `r²` within [`UNIT_NORM_SQUARED_SLACK`] of 1 that is at least
/// `3n / (2 + |w|) · (1 − 1e-9)`; an arc tangent of any math library is well within a relative
/// 1e-9 of the true value, so shrinking the bound by a relative 1e-6 leaves room for both and for
/// the rounding of the bound itself.
#[inline]
fn angle_lower_bound(rotation: &Rotation) -> f64 {
    let quaternion = rotation.quaternion();
    let vector_norm = quaternion.imag().norm();
    let scalar = quaternion.w.abs();
    let near_unit = vector_norm * vector_norm + scalar * scalar <= 1.0 + UNIT_NORM_SQUARED_SLACK;
    if vector_norm >= SMALLEST_BOUNDED_VECTOR_NORM && near_unit {
        2.0 * (3.0 * vector_norm / (2.0 + scalar)) * (1.0 - 1e-6)
    } else {
        0.0
    }
}

#[inline]
fn write_rotation(rotation: &Rotation, out: &mut [f64], start: usize) {
    let vector = rotation.scaled_axis();
    out[start] = vector.x;
    out[start + 1] = vector.y;
    out[start + 2] = vector.z;
}

/// Geodesic interpolation from `a` to `b` that never panics (antipodal inputs pick one axis).
pub fn slerp(a: &Rotation, b: &Rotation, t: f64) -> Rotation {
    let delta = a.inverse() * b;
    a * Rotation::from_scaled_axis(delta.scaled_axis() * t)
}

impl Robot {
    /// Weighted configuration distance: the square root of the weighted sum of squared coordinate
    /// differences, with wrapped angles taking the short way and each rotation counted once by its
    /// geodesic angle.
    pub fn distance(&self, a: &[f64], b: &[f64]) -> f64 {
        self.weighted_sum(a, b, |start, _| rotation_at(a, start).angle_to(&rotation_at(b, start)))
            .sqrt()
    }

    /// `q` followed by the unit quaternion of each of its rotations (`[i, j, k, w]`, in the order
    /// the rotations come): what [`Robot::nearest_form`] reads. A nearest-neighbour scan compares
    /// one configuration with many, and building a quaternion from a rotation vector (a sine and
    /// a cosine) costs more than the rest of a comparison; a form builds it once per
    /// configuration.
    pub fn distance_form(&self, q: &[f64]) -> Vec<f64> {
        let mut form = Vec::with_capacity(self.distance_form_len());
        form.extend_from_slice(q);
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            if coordinate.kind == CoordinateKind::Rotation(0) {
                let rotation = rotation_at(q, index);
                let quaternion = rotation.quaternion();
                form.extend_from_slice(&[quaternion.i, quaternion.j, quaternion.k, quaternion.w]);
            }
        }
        form
    }

    /// How many values a [`Robot::distance_form`] has.
    pub fn distance_form_len(&self) -> usize {
        let rotations = self
            .coordinates
            .iter()
            .filter(|coordinate| coordinate.kind == CoordinateKind::Rotation(0))
            .count();
        self.coordinates.len() + QUATERNION_VALUES * rotations
    }

    /// The index of the first of `forms` whose configuration is strictly nearest, by
    /// [`Robot::distance`], the configuration whose form is `form`; 0 when none is nearer than
    /// infinity. Exactly the node a scan computing `distance(node, q)` for every node and keeping
    /// the first strictly smaller one picks: the same quaternions enter the same arithmetic.
    ///
    /// Most candidates are ruled out before their rotations' arc tangents are taken. With no
    /// negative weight every term of the weighted sum is non-negative and rounding is monotone,
    /// so a sum whose rotation terms use a lower bound on the angle (`angle_lower_bound`, no arc
    /// tangent), accumulated in the same order, is at most the candidate's sum; when it already
    /// reaches the best candidate's sum, the candidate's distance (its square root, also
    /// monotone) cannot be strictly smaller.
    pub fn nearest_form(&self, forms: &[Vec<f64>], form: &[f64]) -> usize {
        let dof = self.coordinates.len();
        let relative_rotation = |candidate: &[f64], ordinal: usize| {
            let start = dof + QUATERNION_VALUES * ordinal;
            // What `angle_to` measures the angle of.
            quaternion_at(candidate, start).rotation_to(&quaternion_at(form, start))
        };
        let rotation_angle = |candidate: &[f64], ordinal: usize| {
            let start = dof + QUATERNION_VALUES * ordinal;
            quaternion_at(candidate, start).angle_to(&quaternion_at(form, start))
        };
        // Without a rotation the bound is the sum itself and would only be computed twice.
        let has_rotation = self
            .coordinates
            .iter()
            .any(|coordinate| coordinate.kind == CoordinateKind::Rotation(0));
        let prunable =
            has_rotation && self.coordinates.iter().all(|coordinate| coordinate.weight >= 0.0);
        let mut best = (0, f64::INFINITY);
        let mut best_sum = f64::INFINITY;
        for (index, candidate) in forms.iter().enumerate() {
            if prunable {
                let at_most = self.weighted_sum(candidate, form, |_, ordinal| {
                    angle_lower_bound(&relative_rotation(candidate, ordinal))
                });
                if at_most >= best_sum {
                    continue;
                }
            }
            let sum =
                self.weighted_sum(candidate, form, |_, ordinal| rotation_angle(candidate, ordinal));
            let distance = sum.sqrt();
            if distance < best.1 {
                best = (index, distance);
                best_sum = sum;
            }
        }
        best.0
    }

    /// The weighted sum of squared coordinate differences that [`Robot::distance`] is the square
    /// root of, with each rotation's geodesic angle given by `rotation_angle`, called with the
    /// rotation's first coordinate and its ordinal among the robot's rotations.
    #[inline]
    fn weighted_sum(
        &self,
        a: &[f64],
        b: &[f64],
        mut rotation_angle: impl FnMut(usize, usize) -> f64,
    ) -> f64 {
        let mut sum = 0.0;
        let mut rotations = 0;
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            let difference = match coordinate.kind {
                CoordinateKind::Linear | CoordinateKind::Angle => b[index] - a[index],
                CoordinateKind::WrappedAngle => wrap_angle(b[index] - a[index]),
                CoordinateKind::Rotation(0) => {
                    rotations += 1;
                    rotation_angle(index, rotations - 1)
                }
                CoordinateKind::Rotation(_) => 0.0,
            };
            sum += coordinate.weight * difference * difference;
        }
        sum
    }

    /// The configuration a fraction `t` of the way from `a` to `b` (wrap-aware; slerp for rotations).
    pub fn interpolate(&self, a: &[f64], b: &[f64], t: f64, out: &mut [f64]) {
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            match coordinate.kind {
                CoordinateKind::Linear | CoordinateKind::Angle => {
                    out[index] = a[index] + t * (b[index] - a[index])
                }
                CoordinateKind::WrappedAngle => {
                    out[index] = wrap_angle(a[index] + t * wrap_angle(b[index] - a[index]));
                }
                CoordinateKind::Rotation(0) => {
                    let rotation = slerp(&rotation_at(a, index), &rotation_at(b, index), t);
                    write_rotation(&rotation, out, index);
                }
                CoordinateKind::Rotation(_) => {}
            }
        }
    }

    /// The motion from `a` to `b`, one entry per coordinate, in the units its velocity limit is
    /// given in: plain differences, wrapped angles the short way round, and a rotation's three
    /// entries the rotation vector of `b` relative to `a` (about world axes), whose length is the
    /// geodesic angle between them.
    pub fn displacement(&self, a: &[f64], b: &[f64], out: &mut [f64]) {
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            match coordinate.kind {
                CoordinateKind::Linear | CoordinateKind::Angle => out[index] = b[index] - a[index],
                CoordinateKind::WrappedAngle => out[index] = wrap_angle(b[index] - a[index]),
                CoordinateKind::Rotation(0) => {
                    let relative = rotation_at(b, index) * rotation_at(a, index).inverse();
                    write_rotation(&relative, out, index);
                }
                CoordinateKind::Rotation(_) => {}
            }
        }
    }

    /// Rewrites the wrapped angles of `q` (continuous joints, a planar yaw) to the value of the
    /// same angle nearest `previous`, so that a sequence of configurations turns the short way
    /// round instead of jumping by 2π where it crosses ±π. `q` stays the same configuration:
    /// forward kinematics and collision checks do not change, only the recorded number does.
    pub fn unwrap_towards(&self, previous: &[f64], q: &mut [f64]) {
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            if coordinate.kind == CoordinateKind::WrappedAngle {
                q[index] = previous[index] + wrap_angle(q[index] - previous[index]);
            }
        }
    }

    /// Copies `reference` into `out` and resamples the coordinates of `group` uniformly within
    /// their limits (wrapped angles over the full circle, rotations uniformly over SO(3) — all three
    /// components of a rotation are resampled if the group names any of them).
    pub fn sample_uniform(
        &self,
        group: &JointGroup,
        reference: &[f64],
        rng: &mut ChaCha8Rng,
        out: &mut [f64],
    ) {
        out.copy_from_slice(reference);
        let mut last_rotation_start = None;
        for &index in &group.coordinates {
            let coordinate = &self.coordinates[index];
            match coordinate.kind {
                CoordinateKind::Linear | CoordinateKind::Angle => {
                    let lower = if coordinate.lower.is_finite() {
                        coordinate.lower
                    } else {
                        reference[index] - UNBOUNDED_SAMPLE_HALF_WIDTH
                    };
                    let upper = if coordinate.upper.is_finite() {
                        coordinate.upper
                    } else {
                        reference[index] + UNBOUNDED_SAMPLE_HALF_WIDTH
                    };
                    out[index] = lower + (upper - lower) * rng.random::<f64>();
                }
                CoordinateKind::WrappedAngle => out[index] = -PI + TAU * rng.random::<f64>(),
                CoordinateKind::Rotation(component) => {
                    let start = index - usize::from(component);
                    if last_rotation_start != Some(start) {
                        last_rotation_start = Some(start);
                        write_rotation(&uniform_rotation(rng), out, start);
                    }
                }
            }
        }
    }

    /// Whether every coordinate is finite and within its limits (wrapped angles and rotations are
    /// valid at any finite value).
    pub fn within_limits(&self, q: &[f64]) -> bool {
        q.len() == self.coordinates.len() && self.first_outside_limits(q).is_none()
    }

    /// The index of the first coordinate of `q` that is not finite or outside its limits (as
    /// [`Robot::within_limits`] judges), for messages that name it.
    pub fn first_outside_limits(&self, q: &[f64]) -> Option<usize> {
        self.coordinates.iter().zip(q).position(|(coordinate, &value)| {
            !value.is_finite()
                || match coordinate.kind {
                    CoordinateKind::Linear | CoordinateKind::Angle => {
                        value < coordinate.lower - LIMIT_TOLERANCE
                            || value > coordinate.upper + LIMIT_TOLERANCE
                    }
                    CoordinateKind::WrappedAngle | CoordinateKind::Rotation(_) => false,
                }
        })
    }

    /// Clamps bounded coordinates into their limits, wraps wrapped angles into [-π, π) and makes
    /// rotation vectors canonical (angle in [0, π]).
    pub fn clamp(&self, q: &mut [f64]) {
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            match coordinate.kind {
                CoordinateKind::Linear | CoordinateKind::Angle => {
                    q[index] = q[index].clamp(coordinate.lower, coordinate.upper)
                }
                CoordinateKind::WrappedAngle => q[index] = wrap_angle(q[index]),
                CoordinateKind::Rotation(0) => {
                    let rotation = rotation_at(q, index);
                    write_rotation(&rotation, q, index);
                }
                CoordinateKind::Rotation(_) => {}
            }
        }
    }

    /// Moves `q` by a velocity `step` (one entry per coordinate) in the sense of the Jacobian:
    /// plain addition, except that a rotation's three entries are an angular step about the axes of
    /// the rotation's reference frame, applied by left multiplication. Does not clamp.
    pub fn integrate(&self, q: &mut [f64], step: &[f64]) {
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            match coordinate.kind {
                CoordinateKind::Rotation(0) => {
                    let delta = Rotation::from_scaled_axis(Vec3::new(
                        step[index],
                        step[index + 1],
                        step[index + 2],
                    ));
                    let rotation = delta * rotation_at(q, index);
                    write_rotation(&rotation, q, index);
                }
                CoordinateKind::Rotation(_) => {}
                _ => q[index] += step[index],
            }
        }
    }

    /// [`Robot::integrate`] restricted to the coordinates listed in `coordinates` (with `step[i]`
    /// the velocity of `coordinates[i]`).
    pub(crate) fn integrate_sparse(&self, q: &mut [f64], coordinates: &[usize], step: &[f64]) {
        let mut position = 0;
        while position < coordinates.len() {
            let index = coordinates[position];
            match self.coordinates[index].kind {
                CoordinateKind::Rotation(component) => {
                    let start = index - usize::from(component);
                    let mut angular = Vec3::zeros();
                    while position < coordinates.len()
                        && coordinates[position] >= start
                        && coordinates[position] < start + 3
                    {
                        angular[coordinates[position] - start] = step[position];
                        position += 1;
                    }
                    let rotation = Rotation::from_scaled_axis(angular) * rotation_at(q, start);
                    write_rotation(&rotation, q, start);
                }
                _ => {
                    q[index] += step[position];
                    position += 1;
                }
            }
        }
    }
}

/// A rotation drawn uniformly from SO(3) (Shoemake's method).
pub fn uniform_rotation(rng: &mut ChaCha8Rng) -> Rotation {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let quaternion = nalgebra::Quaternion::new(
        b * (TAU * u3).cos(),
        a * (TAU * u2).sin(),
        a * (TAU * u2).cos(),
        b * (TAU * u3).sin(),
    );
    Rotation::new_normalize(quaternion)
}
