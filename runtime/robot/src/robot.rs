//! The robot model: links in tree order, joints, configuration coordinates, groups, geometry.
//!
//! A configuration is a flat `&[f64]` whose layout this crate owns (see `docs/robots.md`):
//! the mount's coordinates first, then one coordinate per revolute, continuous or prismatic joint
//! (three for a URDF planar joint, six for a URDF floating joint), in link tree order.

use std::collections::BTreeMap;

use lamp_geometry::{Pose, Shape, Vec3};
use nalgebra::Unit;

use crate::error::RobotError;
use crate::mount::Mount;

/// Index of a link in a [`Robot`]. Links are numbered in tree order: a parent before its children,
/// the root link is 0.
pub type LinkId = usize;

/// Names of the built-in joint groups.
pub const BASE_GROUP: &str = "base";
/// The actuated joints from the root to the end-effector link (mount coordinates excluded).
pub const ARM_GROUP: &str = "arm";
/// The actuated joints below the end-effector link (fingers).
pub const GRIPPER_GROUP: &str = "gripper";
/// Every coordinate of the configuration.
pub const ALL_GROUP: &str = "all";

/// A named set of configuration coordinates, sorted ascending.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JointGroup {
    pub name: String,
    pub coordinates: Vec<usize>,
}

/// One collision shape rigidly attached to a link.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkGeometry {
    pub link: LinkId,
    /// Pose of the shape's frame in the link's frame.
    pub origin: Pose,
    pub shape: Shape,
}

/// How a coordinate behaves in distance, interpolation and sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordinateKind {
    /// A length (prismatic joint, mount translation): metres, limited or unbounded.
    Linear,
    /// A bounded angle (revolute joint): radians, no wrap.
    Angle,
    /// An angle that wraps at ±π (continuous joint, planar yaw).
    WrappedAngle,
    /// One component (0, 1 or 2) of a rotation vector; the three components of one rotation are
    /// consecutive and always treated together.
    Rotation(u8),
}

/// One coordinate of the configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Coordinate {
    pub name: String,
    pub kind: CoordinateKind,
    /// Lower limit (may be `-inf` for unbounded linear coordinates).
    pub lower: f64,
    /// Upper limit (may be `+inf`).
    pub upper: f64,
    /// Weight of this coordinate in [`Robot::distance`].
    pub weight: f64,
    /// The fastest it may move (metres or radians per second, finite and positive): the URDF
    /// joint's `velocity`, or a default of [`crate::timing`] where the URDF gives none (the mount's
    /// coordinates, a joint whose limit says 0).
    pub velocity: f64,
    /// The fastest its speed may change (per second squared, finite and positive): URDF has no
    /// acceleration limit, so this is [`crate::DEFAULT_ACCELERATION`] unless the caller sets one.
    pub acceleration: f64,
}

/// The motion a joint adds between its frame and its child link.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Motion {
    Fixed,
    Revolute {
        axis: Unit<Vec3>,
    },
    Prismatic {
        axis: Unit<Vec3>,
    },
    /// Translation in the plane normal to `normal` (along `e1`, `e2`) then rotation about `normal`.
    Planar {
        normal: Unit<Vec3>,
        e1: Vec3,
        e2: Vec3,
    },
    /// Translation then rotation vector, both in the joint frame.
    Floating,
}

/// The joint above a (non-root) link.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Joint {
    pub name: String,
    /// Pose of the joint frame in the parent link's frame.
    pub origin: Pose,
    pub motion: Motion,
    /// Index of the joint's first coordinate (meaningless for fixed joints).
    pub first_coordinate: usize,
}

impl Joint {
    pub(crate) fn coordinate_count(&self) -> usize {
        match self.motion {
            Motion::Fixed => 0,
            Motion::Revolute { .. } | Motion::Prismatic { .. } => 1,
            Motion::Planar { .. } => 3,
            Motion::Floating => 6,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Link {
    pub name: String,
    pub parent: Option<LinkId>,
    /// The joint connecting the parent to this link (`None` for the root).
    pub joint: Option<Joint>,
}

/// A robot loaded from URDF with a virtual mount. Immutable after construction.
#[derive(Clone, Debug)]
pub struct Robot {
    pub(crate) name: String,
    pub(crate) links: Vec<Link>,
    pub(crate) mount: Mount,
    pub(crate) coordinates: Vec<Coordinate>,
    pub(crate) coordinate_names: Vec<String>,
    pub(crate) groups: BTreeMap<String, JointGroup>,
    pub(crate) geometry: Vec<LinkGeometry>,
    pub(crate) self_collision_pairs: Vec<(LinkId, LinkId)>,
    pub(crate) end_effector: Option<LinkId>,
}

impl Robot {
    /// The URDF robot name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The mount chosen at construction.
    pub fn mount(&self) -> &Mount {
        &self.mount
    }

    /// Length of a configuration.
    pub fn dof(&self) -> usize {
        self.coordinates.len()
    }

    /// Names of the configuration coordinates, in layout order.
    pub fn coordinate_names(&self) -> &[String] {
        &self.coordinate_names
    }

    /// Name, kind, limits and weight of every coordinate, in layout order.
    pub fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    /// Index of a coordinate by name (a 1-DoF joint's coordinate has the joint's name).
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinate_names.iter().position(|candidate| candidate == name)
    }

    /// Number of links.
    pub fn link_count(&self) -> usize {
        self.links.len()
    }

    /// Name of a link. Panics if `link >= link_count()` (a caller bug, like slice indexing).
    pub fn link_name(&self, link: LinkId) -> &str {
        &self.links[link].name
    }

    /// Id of a link by name.
    pub fn link_id(&self, name: &str) -> Option<LinkId> {
        self.links.iter().position(|link| link.name == name)
    }

    /// The parent link, `None` for the root.
    pub fn parent_link(&self, link: LinkId) -> Option<LinkId> {
        self.links.get(link).and_then(|link| link.parent)
    }

    /// The name of the joint above a link (`None` for the root).
    pub fn parent_joint_name(&self, link: LinkId) -> Option<&str> {
        self.links.get(link).and_then(|link| link.joint.as_ref()).map(|joint| joint.name.as_str())
    }

    /// The end-effector (gripper) link: `gripper_link` if present, otherwise the deepest link whose
    /// name contains `gripper` and not `finger`. `None` if no link qualifies.
    pub fn end_effector(&self) -> Option<LinkId> {
        self.end_effector
    }

    /// The configuration with every joint at zero clamped into its limits and the mount at identity.
    pub fn neutral_configuration(&self) -> Vec<f64> {
        self.coordinates
            .iter()
            .map(|coordinate| 0.0_f64.clamp(coordinate.lower, coordinate.upper))
            .collect()
    }

    /// Collision shapes of all links, grouped by link in tree order.
    pub fn collision_geometry(&self) -> &[LinkGeometry] {
        &self.geometry
    }

    /// Pairs of links (lower id first, sorted) whose shapes must be checked against each other.
    pub fn self_collision_pairs(&self) -> &[(LinkId, LinkId)] {
        &self.self_collision_pairs
    }

    /// Removes link pairs (by name, in either order) from the self-collision pairs.
    pub fn with_ignored_collisions(mut self, pairs: &[(&str, &str)]) -> Result<Robot, RobotError> {
        let mut ignored = Vec::with_capacity(pairs.len());
        for (a, b) in pairs {
            let a = self.require_link(a)?;
            let b = self.require_link(b)?;
            ignored.push((a.min(b), a.max(b)));
        }
        self.self_collision_pairs.retain(|pair| !ignored.contains(pair));
        Ok(self)
    }

    /// A joint group by name: the built-in `base`, `arm`, `gripper`, `all`, or one added with
    /// [`Robot::with_group`].
    pub fn group(&self, name: &str) -> Option<&JointGroup> {
        self.groups.get(name)
    }

    /// All joint groups, sorted by name.
    pub fn groups(&self) -> impl Iterator<Item = &JointGroup> {
        self.groups.values()
    }

    /// Adds (or replaces) a group made of the coordinates of the named joints. Names may also be
    /// coordinate names (`base_x`, ...). The built-in groups cannot be replaced.
    pub fn with_group(mut self, name: &str, joints: &[&str]) -> Result<Robot, RobotError> {
        if [BASE_GROUP, ARM_GROUP, GRIPPER_GROUP, ALL_GROUP].contains(&name) {
            return Err(RobotError::InvalidGroup {
                robot: self.name.clone(),
                group: name.to_string(),
                reason: "this is a built-in group".to_string(),
            });
        }
        let mut coordinates = Vec::new();
        for joint in joints {
            coordinates.extend(self.joint_coordinates(joint)?);
        }
        coordinates.sort_unstable();
        coordinates.dedup();
        if coordinates.is_empty() {
            return Err(RobotError::InvalidGroup {
                robot: self.name.clone(),
                group: name.to_string(),
                reason: "the group has no coordinates (only fixed joints?)".to_string(),
            });
        }
        self.groups.insert(name.to_string(), JointGroup { name: name.to_string(), coordinates });
        Ok(self)
    }

    /// Replaces the limits of one coordinate, e.g. to bound a planar base to a workspace.
    pub fn with_coordinate_limits(
        mut self,
        coordinate: &str,
        lower: f64,
        upper: f64,
    ) -> Result<Robot, RobotError> {
        let index =
            self.coordinate_index(coordinate).ok_or_else(|| RobotError::UnknownCoordinate {
                robot: self.name.clone(),
                coordinate: coordinate.to_string(),
            })?;
        let valid = !lower.is_nan() && !upper.is_nan() && lower <= upper;
        let rotation = matches!(self.coordinates[index].kind, CoordinateKind::Rotation(_));
        if !valid || rotation {
            return Err(RobotError::InvalidLimits {
                robot: self.name.clone(),
                coordinate: coordinate.to_string(),
                lower,
                upper,
            });
        }
        self.coordinates[index].lower = lower;
        self.coordinates[index].upper = upper;
        Ok(self)
    }

    /// The coordinate indices of a joint (or of a single coordinate given by its name).
    pub fn joint_coordinates(&self, name: &str) -> Result<Vec<usize>, RobotError> {
        if let Some(joint) = self
            .links
            .iter()
            .filter_map(|link| link.joint.as_ref())
            .find(|joint| joint.name == name)
        {
            let first = joint.first_coordinate;
            return Ok((first..first + joint.coordinate_count()).collect());
        }
        if let Some(index) = self.coordinate_index(name) {
            return Ok(vec![index]);
        }
        Err(RobotError::UnknownJoint { robot: self.name.clone(), joint: name.to_string() })
    }

    /// Writes named joint values (joint name or coordinate name → value) into `q`.
    /// Multi-coordinate joints must be set by their coordinate names.
    pub fn apply_named_configuration<'a>(
        &self,
        values: impl IntoIterator<Item = (&'a str, f64)>,
        q: &mut [f64],
    ) -> Result<(), RobotError> {
        for (name, value) in values {
            let indices = self.joint_coordinates(name)?;
            match indices.as_slice() {
                [index] => q[*index] = value,
                _ => {
                    return Err(RobotError::UnknownCoordinate {
                        robot: self.name.clone(),
                        coordinate: format!(
                            "{name} (a joint with {} coordinates; name one of them)",
                            indices.len()
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    fn require_link(&self, name: &str) -> Result<LinkId, RobotError> {
        self.link_id(name).ok_or_else(|| RobotError::UnknownLink {
            robot: self.name.clone(),
            link: name.to_string(),
        })
    }

    /// The links on the path from the root to `link`, root first.
    pub fn chain(&self, link: LinkId) -> Vec<LinkId> {
        let mut chain = Vec::new();
        let mut current = Some(link);
        while let Some(id) = current {
            chain.push(id);
            current = self.links[id].parent;
        }
        chain.reverse();
        chain
    }
}
