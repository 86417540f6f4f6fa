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
        let mut sum = 0.0;
        for (index, coordinate) in self.coordinates.iter().enumerate() {
            let difference = match coordinate.kind {
                CoordinateKind::Linear | CoordinateKind::Angle => b[index] - a[index],
                CoordinateKind::WrappedAngle => wrap_angle(b[index] - a[index]),
                CoordinateKind::Rotation(0) => {
                    rotation_at(a, index).angle_to(&rotation_at(b, index))
                }
                CoordinateKind::Rotation(_) => 0.0,
            };
            sum += coordinate.weight * difference * difference;
        }
        sum.sqrt()
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
