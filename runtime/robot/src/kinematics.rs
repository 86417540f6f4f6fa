//! Forward kinematics and geometric Jacobians.
//!
//! Jacobian convention: 6 rows, linear velocity of the link origin (world frame) on top, angular
//! velocity (world frame) below, one column per configuration coordinate. For the components of a
//! rotation vector (floating mount or URDF floating joint) the column is not the derivative with
//! respect to the raw coordinate but the tangent direction "rotate about axis k of the rotation's
//! reference frame"; [`Robot::integrate`] applies a velocity in exactly that sense.

use lamp_geometry::{Pose, Rotation, Vec3};
use nalgebra::{Matrix6xX, Translation3};

use crate::mount::Mount;
use crate::robot::{LinkId, Motion, Robot};

impl Robot {
    /// World poses of every link for configuration `q`. Allocation-free.
    ///
    /// Requires `q.len() == dof()` and `out.len() == link_count()`.
    pub fn forward_kinematics(&self, q: &[f64], out: &mut [Pose]) {
        assert_eq!(q.len(), self.dof(), "configuration length must equal the robot's dof");
        assert_eq!(out.len(), self.links.len(), "pose buffer length must equal the link count");
        out[0] = self.mount.root_pose(q);
        for id in 1..self.links.len() {
            let link = &self.links[id];
            let (Some(parent), Some(joint)) = (link.parent, &link.joint) else {
                continue;
            };
            out[id] = out[parent]
                * joint.origin
                * joint_motion(&joint.motion, &q[joint.first_coordinate..]);
        }
    }

    /// The pose of `link` in its parent link's frame at configuration `q`: the joint's origin
    /// times its motion, the factor [`Robot::forward_kinematics`] applies; `None` for the root.
    pub fn joint_transform(&self, q: &[f64], link: LinkId) -> Option<Pose> {
        assert_eq!(q.len(), self.dof(), "configuration length must equal the robot's dof");
        let joint = self.links[link].joint.as_ref()?;
        Some(joint.origin * joint_motion(&joint.motion, &q[joint.first_coordinate..]))
    }

    /// Whether the joint above `link` is fixed, so that [`Robot::joint_transform`] does not
    /// depend on the configuration; false for the root link.
    pub fn has_fixed_joint(&self, link: LinkId) -> bool {
        self.links[link].joint.as_ref().is_some_and(|joint| joint.motion == Motion::Fixed)
    }

    /// World poses of the links of `chain` (root first, each link's parent before it, as
    /// [`Robot::chain`] lists them) for configuration `q`; other entries of `out` are left as
    /// they are. What inverse kinematics needs of a link: its chain's poses feed the Jacobian.
    pub(crate) fn forward_kinematics_chain(&self, q: &[f64], chain: &[LinkId], out: &mut [Pose]) {
        for &id in chain {
            let link = &self.links[id];
            out[id] = match (link.parent, &link.joint) {
                (Some(parent), Some(joint)) => {
                    out[parent]
                        * joint.origin
                        * joint_motion(&joint.motion, &q[joint.first_coordinate..])
                }
                _ => self.mount.root_pose(q),
            };
        }
    }

    /// World pose of one link (walks only the link's chain; allocation-free).
    pub fn link_pose(&self, q: &[f64], link: LinkId) -> Pose {
        assert_eq!(q.len(), self.dof(), "configuration length must equal the robot's dof");
        let mut pose = Pose::identity();
        let mut current = link;
        while let (Some(parent), Some(joint)) =
            (self.links[current].parent, &self.links[current].joint)
        {
            pose = joint.origin * joint_motion(&joint.motion, &q[joint.first_coordinate..]) * pose;
            current = parent;
        }
        self.mount.root_pose(q) * pose
    }

    /// The geometric Jacobian of `link` (see the module docs for the convention).
    pub fn jacobian(&self, q: &[f64], link: LinkId) -> Matrix6xX<f64> {
        let mut poses = vec![Pose::identity(); self.links.len()];
        self.forward_kinematics(q, &mut poses);
        let mut jacobian = Matrix6xX::zeros(self.dof());
        self.jacobian_into(&poses, link, &mut jacobian);
        jacobian
    }

    /// The geometric Jacobian of `link` from poses computed by [`Robot::forward_kinematics`].
    /// Writes every column of `out` (6 × dof). Allocation-free.
    pub fn jacobian_into(&self, poses: &[Pose], link: LinkId, out: &mut Matrix6xX<f64>) {
        assert_eq!(out.ncols(), self.dof(), "Jacobian must have one column per coordinate");
        out.fill(0.0);
        let target = poses[link].translation.vector;
        let mut current = link;
        while let (Some(parent), Some(joint)) =
            (self.links[current].parent, &self.links[current].joint)
        {
            let first = joint.first_coordinate;
            let child_position = poses[current].translation.vector;
            match &joint.motion {
                Motion::Fixed => {}
                Motion::Revolute { axis } => set_rotation(
                    out,
                    target,
                    first,
                    poses[current].rotation * axis.into_inner(),
                    child_position,
                ),
                Motion::Prismatic { axis } => {
                    let world_axis = poses[current].rotation * axis.into_inner();
                    set_linear(out, first, world_axis);
                }
                Motion::Planar { normal, e1, e2 } => {
                    let frame = poses[parent] * joint.origin;
                    set_linear(out, first, frame.rotation * e1);
                    set_linear(out, first + 1, frame.rotation * e2);
                    set_rotation(
                        out,
                        target,
                        first + 2,
                        frame.rotation * normal.into_inner(),
                        child_position,
                    );
                }
                Motion::Floating => {
                    let frame = poses[parent] * joint.origin;
                    for k in 0..3 {
                        let axis = frame.rotation * Vec3::ith(k, 1.0);
                        set_linear(out, first + k, axis);
                        set_rotation(out, target, first + 3 + k, axis, child_position);
                    }
                }
            }
            current = parent;
        }
        let root = poses[0].translation.vector;
        match self.mount {
            Mount::Fixed(_) => {}
            Mount::Planar => {
                set_linear(out, 0, Vec3::x());
                set_linear(out, 1, Vec3::y());
                set_rotation(out, target, 2, Vec3::z(), root);
            }
            Mount::Floating => {
                for k in 0..3 {
                    set_linear(out, k, Vec3::ith(k, 1.0));
                    set_rotation(out, target, 3 + k, Vec3::ith(k, 1.0), root);
                }
            }
        }
    }
}

#[inline]
fn set_linear(out: &mut Matrix6xX<f64>, column: usize, direction: Vec3) {
    out.fixed_view_mut::<3, 1>(0, column).copy_from(&direction);
}

/// A rotation about `axis` through `point`, seen at `target`.
#[inline]
fn set_rotation(out: &mut Matrix6xX<f64>, target: Vec3, column: usize, axis: Vec3, point: Vec3) {
    out.fixed_view_mut::<3, 1>(0, column).copy_from(&axis.cross(&(target - point)));
    out.fixed_view_mut::<3, 1>(3, column).copy_from(&axis);
}

/// The transform a joint adds for its coordinates (`q` starts at the joint's first coordinate).
#[inline]
pub(crate) fn joint_motion(motion: &Motion, q: &[f64]) -> Pose {
    match motion {
        Motion::Fixed => Pose::identity(),
        Motion::Revolute { axis } => {
            Pose::from_parts(Translation3::identity(), Rotation::from_axis_angle(axis, q[0]))
        }
        Motion::Prismatic { axis } => {
            Pose::from_parts(Translation3::from(axis.into_inner() * q[0]), Rotation::identity())
        }
        Motion::Planar { normal, e1, e2 } => Pose::from_parts(
            Translation3::from(e1 * q[0] + e2 * q[1]),
            Rotation::from_axis_angle(normal, q[2]),
        ),
        Motion::Floating => Pose::from_parts(
            Translation3::new(q[0], q[1], q[2]),
            Rotation::from_scaled_axis(Vec3::new(q[3], q[4], q[5])),
        ),
    }
}
