//! The virtual mount: how a robot's root link is placed in the world.
//!
//! A mount is chosen by the caller, not by the URDF: a Fetch's mobile base is a planar mount, a
//! free-flying gripper is a floating mount, a YuMi is bolted down with a fixed mount.

use lamp_geometry::{Pose, Rotation, Vec3};

/// How the robot's root link is placed in the world.
#[derive(Clone, Debug, PartialEq)]
pub enum Mount {
    /// The root link is bolted at this world pose; the mount adds no coordinates.
    Fixed(Pose),
    /// A mobile base on the floor: coordinates `x, y, yaw` (root at `z = 0`, yaw about world z).
    Planar,
    /// A free-flying body: coordinates `x, y, z, rx, ry, rz`, the rotation as a rotation vector.
    Floating,
}

impl Mount {
    /// How many leading configuration coordinates the mount owns.
    pub fn coordinate_count(&self) -> usize {
        match self {
            Mount::Fixed(_) => 0,
            Mount::Planar => 3,
            Mount::Floating => 6,
        }
    }

    /// The world pose of the root link for the mount's coordinates (`q` starts with them).
    pub fn root_pose(&self, q: &[f64]) -> Pose {
        match self {
            Mount::Fixed(pose) => *pose,
            Mount::Planar => Pose::from_parts(
                Vec3::new(q[0], q[1], 0.0).into(),
                Rotation::from_axis_angle(&Vec3::z_axis(), q[2]),
            ),
            Mount::Floating => Pose::from_parts(
                Vec3::new(q[0], q[1], q[2]).into(),
                Rotation::from_scaled_axis(Vec3::new(q[3], q[4], q[5])),
            ),
        }
    }

    /// Writes the coordinates that put the root link at `pose` (planar: the pose's projection on
    /// the floor, keeping only the yaw).
    pub fn write_coordinates(&self, pose: &Pose, q: &mut [f64]) {
        match self {
            Mount::Fixed(_) => {}
            Mount::Planar => {
                q[0] = pose.translation.x;
                q[1] = pose.translation.y;
                let x_axis = pose.rotation * Vec3::x();
                q[2] = x_axis.y.atan2(x_axis.x);
            }
            Mount::Floating => {
                q[0] = pose.translation.x;
                q[1] = pose.translation.y;
                q[2] = pose.translation.z;
                let r = pose.rotation.scaled_axis();
                q[3] = r.x;
                q[4] = r.y;
                q[5] = r.z;
            }
        }
    }
}
