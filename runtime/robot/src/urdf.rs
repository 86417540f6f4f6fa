//! From URDF text to a [`Robot`]: reading the file, tree building, joints and coordinates,
//! collision geometry.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;

use lamp_geometry::{Point3, Pose, Rotation, Shape, Vec3};
use nalgebra::Unit;

use crate::collision::compute_self_collision_pairs;
use crate::error::RobotError;
use crate::mount::Mount;
use crate::robot::{
    ALL_GROUP, ARM_GROUP, BASE_GROUP, Coordinate, CoordinateKind, GRIPPER_GROUP, Joint, JointGroup,
    Link, LinkGeometry, LinkId, Motion, Robot,
};
use crate::timing::{
    DEFAULT_ACCELERATION, DEFAULT_JOINT_VELOCITY, MOUNT_ANGULAR_VELOCITY, MOUNT_LINEAR_VELOCITY,
};

/// The largest URDF file read: the bundled robots' are under 100 KiB, so 64 MiB is beyond any
/// robot description, while a wrong path (a log, a device) cannot fill the memory.
pub const MAX_URDF_BYTES: u64 = 64 << 20;

/// The link the end-effector search prefers when it exists.
const PREFERRED_END_EFFECTOR: &str = "gripper_link";
/// Axis vectors shorter than this are rejected (they define no direction).
const MINIMUM_AXIS_NORM: f64 = 1e-9;
/// Points per ring when a capsule is approximated by a convex hull.
const CAPSULE_RING_POINTS: usize = 16;
/// Rings per hemisphere when a capsule is approximated by a convex hull.
const CAPSULE_HEMISPHERE_RINGS: usize = 4;

impl Robot {
    /// Loads a URDF file of at most [`MAX_URDF_BYTES`]; meshes are resolved against the file's
    /// folder.
    pub fn from_urdf_file(path: &Path, mount: Mount) -> Result<Robot, RobotError> {
        use std::io::Read as _;
        let read = |source| RobotError::Read { file: path.to_path_buf(), source };
        let file = std::fs::File::open(path).map_err(read)?;
        let size = file.metadata().map_err(read)?.len();
        let too_large =
            |size| RobotError::TooLarge { file: path.to_path_buf(), size, limit: MAX_URDF_BYTES };
        if size > MAX_URDF_BYTES {
            return Err(too_large(size));
        }
        let mut text = String::new();
        // One byte past the limit tells a file that grew while it was read.
        file.take(MAX_URDF_BYTES + 1).read_to_string(&mut text).map_err(read)?;
        if text.len() as u64 > MAX_URDF_BYTES {
            return Err(too_large(text.len() as u64));
        }
        let base_dir = path.parent().unwrap_or(Path::new(""));
        build(&text, &path.display().to_string(), Some(base_dir), mount)
    }

    /// Loads URDF text. Relative mesh paths are resolved against `base_dir` (an error without it).
    pub fn from_urdf_str(
        urdf: &str,
        base_dir: Option<&Path>,
        mount: Mount,
    ) -> Result<Robot, RobotError> {
        build(urdf, "<string>", base_dir, mount)
    }
}

pub(crate) fn build(
    text: &str,
    file: &str,
    base_dir: Option<&Path>,
    mount: Mount,
) -> Result<Robot, RobotError> {
    let urdf = urdf_rs::read_from_string(text).map_err(|error| RobotError::UrdfParse {
        file: file.to_string(),
        message: error.to_string(),
    })?;
    check_unique_names(&urdf, file)?;

    let link_index: BTreeMap<&str, usize> =
        urdf.links.iter().enumerate().map(|(index, link)| (link.name.as_str(), index)).collect();
    // parent_joint[child urdf index] = urdf joint index
    let mut parent_joint: Vec<Option<usize>> = vec![None; urdf.links.len()];
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); urdf.links.len()];
    for (joint_index, joint) in urdf.joints.iter().enumerate() {
        let missing = |link: &str| RobotError::MissingLink {
            file: file.to_string(),
            joint: joint.name.clone(),
            link: link.to_string(),
        };
        let parent = *link_index
            .get(joint.parent.link.as_str())
            .ok_or_else(|| missing(&joint.parent.link))?;
        let child =
            *link_index.get(joint.child.link.as_str()).ok_or_else(|| missing(&joint.child.link))?;
        if parent_joint[child].is_some() {
            return Err(RobotError::NotATree {
                file: file.to_string(),
                reason: format!("link `{}` is the child of more than one joint", joint.child.link),
            });
        }
        parent_joint[child] = Some(joint_index);
        children[parent].push(joint_index);
    }
    let roots: Vec<usize> =
        (0..urdf.links.len()).filter(|&index| parent_joint[index].is_none()).collect();
    let root = match roots.as_slice() {
        [root] => *root,
        [] => {
            return Err(RobotError::NotATree {
                file: file.to_string(),
                reason: if urdf.links.is_empty() {
                    "there are no links".into()
                } else {
                    "every link has a parent (a cycle)".into()
                },
            });
        }
        _ => {
            let names: Vec<&str> =
                roots.iter().map(|&index| urdf.links[index].name.as_str()).collect();
            return Err(RobotError::NotATree {
                file: file.to_string(),
                reason: format!("several links have no parent: {}", names.join(", ")),
            });
        }
    };

    // Depth-first preorder, children in document order: parents get smaller ids than children.
    let mut order: Vec<usize> = Vec::with_capacity(urdf.links.len());
    let mut stack = vec![root];
    while let Some(current) = stack.pop() {
        order.push(current);
        for &joint_index in children[current].iter().rev() {
            let child = link_index[urdf.joints[joint_index].child.link.as_str()];
            stack.push(child);
        }
    }
    if order.len() != urdf.links.len() {
        return Err(RobotError::NotATree {
            file: file.to_string(),
            reason: "some links are not reachable from the root (a cycle)".into(),
        });
    }
    let mut id_of_urdf = vec![0usize; urdf.links.len()];
    for (id, &urdf_index) in order.iter().enumerate() {
        id_of_urdf[urdf_index] = id;
    }

    let mut coordinates = mount_coordinates(&mount);
    let mut links = Vec::with_capacity(order.len());
    for &urdf_index in &order {
        let urdf_link = &urdf.links[urdf_index];
        let (parent, joint) = match parent_joint[urdf_index] {
            None => (None, None),
            Some(joint_index) => {
                let urdf_joint = &urdf.joints[joint_index];
                let parent = id_of_urdf[link_index[urdf_joint.parent.link.as_str()]];
                let joint = convert_joint(urdf_joint, file, &mut coordinates)?;
                (Some(parent), Some(joint))
            }
        };
        links.push(Link { name: urdf_link.name.clone(), parent, joint });
    }

    let mut geometry = Vec::new();
    for (id, &urdf_index) in order.iter().enumerate() {
        let urdf_link = &urdf.links[urdf_index];
        for collision in &urdf_link.collision {
            let origin =
                convert_pose(&collision.origin).ok_or_else(|| RobotError::InvalidGeometry {
                    file: file.to_string(),
                    link: urdf_link.name.clone(),
                    reason: "non-finite origin".into(),
                })?;
            let shape = convert_geometry(&collision.geometry, file, &urdf_link.name, base_dir)?;
            geometry.push(LinkGeometry { link: id, origin, shape });
        }
    }

    let end_effector = find_end_effector(&links);
    let coordinate_names = coordinates.iter().map(|coordinate| coordinate.name.clone()).collect();
    let mut robot = Robot {
        name: urdf.name.clone(),
        links,
        mount,
        coordinates,
        coordinate_names,
        groups: BTreeMap::new(),
        geometry,
        self_collision_pairs: Vec::new(),
        end_effector,
    };
    robot.groups = builtin_groups(&robot);
    robot.self_collision_pairs = compute_self_collision_pairs(&robot);
    Ok(robot)
}

fn check_unique_names(urdf: &urdf_rs::Robot, file: &str) -> Result<(), RobotError> {
    let mut seen = std::collections::BTreeSet::new();
    for link in &urdf.links {
        if !seen.insert(link.name.as_str()) {
            return Err(RobotError::DuplicateName {
                file: file.into(),
                element: "link",
                name: link.name.clone(),
            });
        }
    }
    let mut seen = std::collections::BTreeSet::new();
    for joint in &urdf.joints {
        if !seen.insert(joint.name.as_str()) {
            return Err(RobotError::DuplicateName {
                file: file.into(),
                element: "joint",
                name: joint.name.clone(),
            });
        }
    }
    Ok(())
}

fn mount_coordinates(mount: &Mount) -> Vec<Coordinate> {
    let linear = |name: &str| Coordinate {
        name: name.into(),
        kind: CoordinateKind::Linear,
        lower: f64::NEG_INFINITY,
        upper: f64::INFINITY,
        weight: 1.0,
        velocity: MOUNT_LINEAR_VELOCITY,
        acceleration: DEFAULT_ACCELERATION,
    };
    let rotation = |name: &str, component: u8| Coordinate {
        name: name.into(),
        kind: CoordinateKind::Rotation(component),
        lower: -PI,
        upper: PI,
        weight: 1.0,
        velocity: MOUNT_ANGULAR_VELOCITY,
        acceleration: DEFAULT_ACCELERATION,
    };
    match mount {
        Mount::Fixed(_) => Vec::new(),
        Mount::Planar => vec![
            linear("base_x"),
            linear("base_y"),
            Coordinate {
                name: "base_yaw".into(),
                kind: CoordinateKind::WrappedAngle,
                lower: -PI,
                upper: PI,
                weight: 1.0,
                velocity: MOUNT_ANGULAR_VELOCITY,
                acceleration: DEFAULT_ACCELERATION,
            },
        ],
        Mount::Floating => vec![
            linear("base_x"),
            linear("base_y"),
            linear("base_z"),
            rotation("base_rx", 0),
            rotation("base_ry", 1),
            rotation("base_rz", 2),
        ],
    }
}

fn convert_pose(pose: &urdf_rs::Pose) -> Option<Pose> {
    let [x, y, z] = pose.xyz.0;
    let [roll, pitch, yaw] = pose.rpy.0;
    if ![x, y, z, roll, pitch, yaw].iter().all(|value| value.is_finite()) {
        return None;
    }
    // URDF rpy is fixed-axis roll about x, then pitch about y, then yaw about z: R = Rz·Ry·Rx,
    // which is exactly nalgebra's `from_euler_angles(roll, pitch, yaw)`.
    Some(Pose::from_parts(Vec3::new(x, y, z).into(), Rotation::from_euler_angles(roll, pitch, yaw)))
}

fn convert_joint(
    joint: &urdf_rs::Joint,
    file: &str,
    coordinates: &mut Vec<Coordinate>,
) -> Result<Joint, RobotError> {
    let invalid = |reason: String| RobotError::InvalidJoint {
        file: file.to_string(),
        joint: joint.name.clone(),
        reason,
    };
    let origin = convert_pose(&joint.origin).ok_or_else(|| invalid("non-finite origin".into()))?;
    let axis = || {
        let [x, y, z] = joint.axis.xyz.0;
        let vector = Vec3::new(x, y, z);
        if !vector.iter().all(|value| value.is_finite()) || vector.norm() < MINIMUM_AXIS_NORM {
            return Err(invalid(format!("axis ({x}, {y}, {z}) is not a direction")));
        }
        Ok(Unit::new_normalize(vector))
    };
    let limits = || {
        let (lower, upper) = (joint.limit.lower, joint.limit.upper);
        if lower.is_nan() || upper.is_nan() || lower > upper {
            return Err(invalid(format!("limits [{lower}, {upper}] are not an interval")));
        }
        Ok((lower, upper))
    };
    // URDF requires `velocity` on a moving joint's limit; urdf-rs reads a missing <limit> as 0,
    // which cannot mean "never moves" for a joint a planner moves, so 0 takes the default.
    let velocity = || {
        let value = joint.limit.velocity;
        if value == 0.0 {
            Ok(DEFAULT_JOINT_VELOCITY)
        } else if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(invalid(format!("velocity limit {value} is not a speed")))
        }
    };
    let first_coordinate = coordinates.len();
    let motion = match joint.joint_type {
        urdf_rs::JointType::Fixed => Motion::Fixed,
        urdf_rs::JointType::Revolute => {
            let (lower, upper) = limits()?;
            coordinates.push(Coordinate {
                name: joint.name.clone(),
                kind: CoordinateKind::Angle,
                lower,
                upper,
                weight: 1.0,
                velocity: velocity()?,
                acceleration: DEFAULT_ACCELERATION,
            });
            Motion::Revolute { axis: axis()? }
        }
        urdf_rs::JointType::Continuous => {
            coordinates.push(Coordinate {
                name: joint.name.clone(),
                kind: CoordinateKind::WrappedAngle,
                lower: -PI,
                upper: PI,
                weight: 1.0,
                velocity: velocity()?,
                acceleration: DEFAULT_ACCELERATION,
            });
            Motion::Revolute { axis: axis()? }
        }
        urdf_rs::JointType::Prismatic => {
            let (lower, upper) = limits()?;
            coordinates.push(Coordinate {
                name: joint.name.clone(),
                kind: CoordinateKind::Linear,
                lower,
                upper,
                weight: 1.0,
                velocity: velocity()?,
                acceleration: DEFAULT_ACCELERATION,
            });
            Motion::Prismatic { axis: axis()? }
        }
        urdf_rs::JointType::Planar => {
            let normal = axis()?;
            // Any orthonormal pair spanning the plane; documented as the joint's x and y.
            let helper = if normal.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
            let e1 = normal.cross(&helper).cross(&normal).normalize();
            let e2 = normal.cross(&e1);
            for (suffix, kind) in [
                ("x", CoordinateKind::Linear),
                ("y", CoordinateKind::Linear),
                ("yaw", CoordinateKind::WrappedAngle),
            ] {
                let (lower, upper) = if kind == CoordinateKind::Linear {
                    (f64::NEG_INFINITY, f64::INFINITY)
                } else {
                    (-PI, PI)
                };
                coordinates.push(Coordinate {
                    name: format!("{}/{suffix}", joint.name),
                    kind,
                    lower,
                    upper,
                    weight: 1.0,
                    velocity: velocity()?,
                    acceleration: DEFAULT_ACCELERATION,
                });
            }
            Motion::Planar { normal, e1, e2 }
        }
        urdf_rs::JointType::Floating => {
            for suffix in ["x", "y", "z"] {
                coordinates.push(Coordinate {
                    name: format!("{}/{suffix}", joint.name),
                    kind: CoordinateKind::Linear,
                    lower: f64::NEG_INFINITY,
                    upper: f64::INFINITY,
                    weight: 1.0,
                    velocity: velocity()?,
                    acceleration: DEFAULT_ACCELERATION,
                });
            }
            for (component, suffix) in ["rx", "ry", "rz"].into_iter().enumerate() {
                coordinates.push(Coordinate {
                    name: format!("{}/{suffix}", joint.name),
                    kind: CoordinateKind::Rotation(component as u8),
                    lower: -PI,
                    upper: PI,
                    weight: 1.0,
                    velocity: velocity()?,
                    acceleration: DEFAULT_ACCELERATION,
                });
            }
            Motion::Floating
        }
        urdf_rs::JointType::Spherical => {
            return Err(invalid(
                "spherical joints are not supported; use three revolute joints".into(),
            ));
        }
    };
    Ok(Joint { name: joint.name.clone(), origin, motion, first_coordinate })
}

fn convert_geometry(
    geometry: &urdf_rs::Geometry,
    file: &str,
    link: &str,
    base_dir: Option<&Path>,
) -> Result<Shape, RobotError> {
    let invalid = |reason: String| RobotError::InvalidGeometry {
        file: file.to_string(),
        link: link.to_string(),
        reason,
    };
    let positive = |value: f64| value.is_finite() && value > 0.0;
    match geometry {
        urdf_rs::Geometry::Box { size } => {
            let [x, y, z] = size.0;
            if ![x, y, z].into_iter().all(positive) {
                return Err(invalid(format!("box size ({x}, {y}, {z}) must be positive")));
            }
            Ok(Shape::Box { half_extents: Vec3::new(x, y, z) / 2.0 })
        }
        urdf_rs::Geometry::Cylinder { radius, length } => {
            if !positive(*radius) || !positive(*length) {
                return Err(invalid(format!(
                    "cylinder radius {radius} and length {length} must be positive"
                )));
            }
            Ok(Shape::Cylinder { radius: *radius, half_height: length / 2.0 })
        }
        urdf_rs::Geometry::Sphere { radius } => {
            if !positive(*radius) {
                return Err(invalid(format!("sphere radius {radius} must be positive")));
            }
            Ok(Shape::Sphere { radius: *radius })
        }
        urdf_rs::Geometry::Capsule { radius, length } => {
            if !positive(*radius) || !positive(*length) {
                return Err(invalid(format!(
                    "capsule radius {radius} and length {length} must be positive"
                )));
            }
            Ok(Shape::ConvexHull { points: capsule_points(*radius, length / 2.0) })
        }
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.map_or(Vec3::new(1.0, 1.0, 1.0), |scale| {
                Vec3::new(scale.0[0], scale.0[1], scale.0[2])
            });
            crate::mesh::load_convex_hull(filename, scale, base_dir).map_err(|reason| {
                RobotError::Mesh {
                    file: file.to_string(),
                    link: link.to_string(),
                    mesh: filename.clone(),
                    reason,
                }
            })
        }
    }
}

/// Points on a capsule along z (two hemispheres); their convex hull approximates it from inside.
fn capsule_points(radius: f64, half_length: f64) -> Vec<Point3> {
    let mut points = vec![
        Point3::new(0.0, 0.0, half_length + radius),
        Point3::new(0.0, 0.0, -half_length - radius),
    ];
    for ring in 0..CAPSULE_HEMISPHERE_RINGS {
        let elevation = (ring as f64) * (PI / 2.0) / (CAPSULE_HEMISPHERE_RINGS as f64);
        let (ring_radius, height) = (radius * elevation.cos(), radius * elevation.sin());
        for step in 0..CAPSULE_RING_POINTS {
            let azimuth = (step as f64) * 2.0 * PI / (CAPSULE_RING_POINTS as f64);
            let (x, y) = (ring_radius * azimuth.cos(), ring_radius * azimuth.sin());
            points.push(Point3::new(x, y, half_length + height));
            points.push(Point3::new(x, y, -half_length - height));
        }
    }
    points
}

fn find_end_effector(links: &[Link]) -> Option<LinkId> {
    if let Some(id) = links.iter().position(|link| link.name == PREFERRED_END_EFFECTOR) {
        return Some(id);
    }
    let depth = |mut id: LinkId| {
        let mut depth = 0usize;
        while let Some(parent) = links[id].parent {
            depth += 1;
            id = parent;
        }
        depth
    };
    // Deepest first; ties broken by the smaller id (tree order) for determinism.
    links
        .iter()
        .enumerate()
        .filter(|(_, link)| link.name.contains("gripper") && !link.name.contains("finger"))
        .map(|(id, _)| (std::cmp::Reverse(depth(id)), id))
        .min()
        .map(|(_, id)| id)
}

fn builtin_groups(robot: &Robot) -> BTreeMap<String, JointGroup> {
    let mount_count = robot.mount.coordinate_count();
    let joint_coordinates = |link: LinkId| {
        robot.links[link]
            .joint
            .as_ref()
            .map(|joint| {
                (joint.first_coordinate..joint.first_coordinate + joint.coordinate_count())
                    .collect::<Vec<_>>()
            })
            .unwrap_or_default()
    };
    let (arm, gripper): (Vec<usize>, Vec<usize>) = match robot.end_effector {
        Some(end_effector) => {
            let arm = robot.chain(end_effector).into_iter().flat_map(joint_coordinates).collect();
            let gripper = (0..robot.links.len())
                .filter(|&link| link != end_effector && robot.chain(link).contains(&end_effector))
                .flat_map(joint_coordinates)
                .collect();
            (arm, gripper)
        }
        None => ((mount_count..robot.coordinates.len()).collect(), Vec::new()),
    };
    let mut groups = BTreeMap::new();
    let mut insert = |name: &str, mut coordinates: Vec<usize>| {
        coordinates.sort_unstable();
        if !coordinates.is_empty() {
            groups.insert(name.to_string(), JointGroup { name: name.to_string(), coordinates });
        }
    };
    insert(BASE_GROUP, (0..mount_count).collect());
    insert(ARM_GROUP, arm);
    insert(GRIPPER_GROUP, gripper);
    insert(ALL_GROUP, (0..robot.coordinates.len()).collect());
    groups
}
