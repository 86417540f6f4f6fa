//! The names, schema text and metadata layout that make a file a lamp trajectory, and the
//! conversion of the header to and from its MCAP metadata record.
//!
//! `docs/formats.md` documents every constant here; change them together.

use std::collections::BTreeMap;

use crate::model::{BodyDescription, RobotDescription, TrajectoryHeader};

/// The version of the file format this crate writes and the only one it reads.
pub const FORMAT_VERSION: u32 = 1;

/// The topic of the per-step messages.
pub const WORLD_TOPIC: &str = "/lamp/world";

/// The ROS 2 type name of the per-step messages.
pub const WORLD_STEP_SCHEMA_NAME: &str = "lamp_msgs/msg/WorldStep";

/// The MCAP schema encoding: a ROS 2 `.msg` definition with its dependencies appended.
pub const SCHEMA_ENCODING: &str = "ros2msg";

/// The MCAP message encoding: ROS 2 CDR.
pub const MESSAGE_ENCODING: &str = "cdr";

/// The MCAP profile of a ROS 2 bag.
pub const PROFILE: &str = "ros2";

/// The name of the MCAP metadata record that holds the header.
pub const METADATA_NAME: &str = "lamp";

/// A dependency of a ROS 2 message definition as rosbag2 appends it: a line of `=`, a `MSG:`
/// line naming the type, then the type's definition. The standard types used by several
/// channels are defined once below and composed with `concat!`, so that their texts, which
/// readers compare with the published ones, cannot drift apart.
macro_rules! ros_dependency {
    ($name:literal, $definition:literal) => {
        concat!(
            "================================================================================\n",
            "MSG: ",
            $name,
            "\n",
            $definition
        )
    };
}

/// `builtin_interfaces/Time` as a dependency.
macro_rules! time_dependency {
    () => {
        $crate::schema::ros_dependency!("builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n")
    };
}

/// `std_msgs/Header` and its `builtin_interfaces/Time` as dependencies.
macro_rules! header_dependencies {
    () => {
        concat!(
            $crate::schema::ros_dependency!(
                "std_msgs/Header",
                "builtin_interfaces/Time stamp\nstring frame_id\n"
            ),
            $crate::schema::time_dependency!()
        )
    };
}

/// `geometry_msgs/Quaternion` as a dependency.
macro_rules! quaternion_dependency {
    () => {
        $crate::schema::ros_dependency!(
            "geometry_msgs/Quaternion",
            "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"
        )
    };
}

/// A three-component `float64` vector type (`geometry_msgs/Point`, `geometry_msgs/Vector3`) as
/// a dependency.
macro_rules! xyz_dependency {
    ($name:literal) => {
        $crate::schema::ros_dependency!($name, "float64 x\nfloat64 y\nfloat64 z\n")
    };
}

pub(crate) use {
    header_dependencies, quaternion_dependency, ros_dependency, time_dependency, xyz_dependency,
};

/// The definition of `lamp_msgs/msg/WorldStep` in the concatenated form rosbag2 writes
/// (the type itself, then each dependency after a line of `=` and a `MSG:` line).
pub const WORLD_STEP_SCHEMA: &str = concat!(
    "# One time step of a lamp world.\n",
    "# Bodies and robots appear in the order of the file's `lamp` metadata record.\n",
    "builtin_interfaces/Time stamp  # time since the start of the recording\n",
    "geometry_msgs/Pose[] body_poses  # world pose of every body\n",
    "lamp_msgs/RobotState[] robots  # state of every robot\n",
    time_dependency!(),
    ros_dependency!("geometry_msgs/Pose", "Point position\nQuaternion orientation\n"),
    xyz_dependency!("geometry_msgs/Point"),
    quaternion_dependency!(),
    ros_dependency!(
        "lamp_msgs/RobotState",
        "float64[] positions  # in the order of the robot's coordinates (metres, radians)\n\
         string[] held  # per gripper: name of the held body, empty if none\n"
    ),
);

/// Metadata keys of the `lamp` record (values are UTF-8 strings).
pub mod keys {
    /// Always [`super::FORMAT_NAME`].
    pub const FORMAT: &str = "format";
    /// The format version, a decimal integer.
    pub const FORMAT_VERSION: &str = "format_version";
    /// The spec or domain name.
    pub const DOMAIN: &str = "domain";
    /// The seed, a decimal `u64`.
    pub const SEED: &str = "seed";
    /// One line per body: `name type_name`.
    pub const BODIES: &str = "bodies";
    /// One line per robot name.
    pub const ROBOTS: &str = "robots";
    /// Prefix of `robot.<name>.coordinates` (space-separated names).
    pub const ROBOT_PREFIX: &str = "robot.";
    /// Suffix of the per-robot coordinate list key.
    pub const COORDINATES_SUFFIX: &str = ".coordinates";
    /// Suffix of the per-robot gripper list key.
    pub const GRIPPERS_SUFFIX: &str = ".grippers";
    /// Prefix of free provenance entries: `provenance.<key>`.
    pub const PROVENANCE_PREFIX: &str = "provenance.";
}

/// The value of the `format` key, so that a `lamp` record from another tool is not mistaken
/// for ours.
pub const FORMAT_NAME: &str = "lamp-trajectory";

/// The header as the entries of the `lamp` metadata record; a `BTreeMap`, so written sorted.
pub fn header_to_metadata(header: &TrajectoryHeader) -> BTreeMap<String, String> {
    let mut metadata = BTreeMap::new();
    metadata.insert(keys::FORMAT.to_string(), FORMAT_NAME.to_string());
    metadata.insert(keys::FORMAT_VERSION.to_string(), FORMAT_VERSION.to_string());
    metadata.insert(keys::DOMAIN.to_string(), header.domain.clone());
    metadata.insert(keys::SEED.to_string(), header.seed.to_string());
    let bodies: Vec<String> =
        header.bodies.iter().map(|body| format!("{} {}", body.name, body.type_name)).collect();
    metadata.insert(keys::BODIES.to_string(), bodies.join("\n"));
    let robots: Vec<&str> = header.robots.iter().map(|robot| robot.name.as_str()).collect();
    metadata.insert(keys::ROBOTS.to_string(), robots.join("\n"));
    for robot in &header.robots {
        metadata
            .insert(robot_key(&robot.name, keys::COORDINATES_SUFFIX), robot.coordinates.join(" "));
        metadata.insert(robot_key(&robot.name, keys::GRIPPERS_SUFFIX), robot.grippers.join(" "));
    }
    for (key, value) in &header.provenance {
        metadata.insert(format!("{}{key}", keys::PROVENANCE_PREFIX), value.clone());
    }
    metadata
}

fn robot_key(robot: &str, suffix: &str) -> String {
    format!("{}{robot}{suffix}", keys::ROBOT_PREFIX)
}

/// Why a `lamp` metadata record is not a header this crate can read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MetadataProblem {
    /// The record is from another tool or another major version; not a lamp file we can read.
    Schema(String),
    /// The record is ours but malformed.
    Header(String),
}

/// Parses the `lamp` metadata record back into a header; unknown keys are ignored so that
/// later minor additions do not break older readers.
pub fn header_from_metadata(
    metadata: &BTreeMap<String, String>,
) -> Result<TrajectoryHeader, MetadataProblem> {
    let format = metadata.get(keys::FORMAT).map(String::as_str);
    if format != Some(FORMAT_NAME) {
        return Err(MetadataProblem::Schema(format!(
            "its `{METADATA_NAME}` metadata record has `{}` = {format:?}, expected `{FORMAT_NAME}`",
            keys::FORMAT
        )));
    }
    let version = required(metadata, keys::FORMAT_VERSION)?;
    if version.parse::<u32>().ok() != Some(FORMAT_VERSION) {
        return Err(MetadataProblem::Schema(format!(
            "format version `{version}` is not supported (this reader reads version {FORMAT_VERSION})"
        )));
    }
    let domain = required(metadata, keys::DOMAIN)?.to_string();
    let seed_text = required(metadata, keys::SEED)?;
    let seed = seed_text.parse::<u64>().map_err(|_| {
        MetadataProblem::Header(format!(
            "`{}` = `{seed_text}` is not an unsigned integer",
            keys::SEED
        ))
    })?;

    let mut bodies = Vec::new();
    for line in lines(required(metadata, keys::BODIES)?) {
        let mut fields = line.split(' ');
        let (Some(name), Some(type_name), None) = (fields.next(), fields.next(), fields.next())
        else {
            return Err(MetadataProblem::Header(format!(
                "`{}` line `{line}` is not `name type_name`",
                keys::BODIES
            )));
        };
        bodies.push(BodyDescription { name: name.to_string(), type_name: type_name.to_string() });
    }

    let mut robots = Vec::new();
    for name in lines(required(metadata, keys::ROBOTS)?) {
        let coordinates = words(required(metadata, &robot_key(name, keys::COORDINATES_SUFFIX))?);
        let grippers = words(required(metadata, &robot_key(name, keys::GRIPPERS_SUFFIX))?);
        robots.push(RobotDescription { name: name.to_string(), coordinates, grippers });
    }

    let provenance = metadata
        .iter()
        .filter_map(|(key, value)| {
            key.strip_prefix(keys::PROVENANCE_PREFIX).map(|key| (key.to_string(), value.clone()))
        })
        .collect();

    let header = TrajectoryHeader { domain, seed, provenance, bodies, robots };
    header.check().map_err(MetadataProblem::Header)?;
    Ok(header)
}

fn required<'m>(
    metadata: &'m BTreeMap<String, String>,
    key: &str,
) -> Result<&'m str, MetadataProblem> {
    metadata.get(key).map(String::as_str).ok_or_else(|| {
        MetadataProblem::Header(format!(
            "the `{METADATA_NAME}` metadata record has no `{key}` entry"
        ))
    })
}

/// Non-empty lines; an empty value is an empty list.
fn lines(text: &str) -> impl Iterator<Item = &str> {
    text.split('\n').filter(|line| !line.is_empty())
}

fn words(text: &str) -> Vec<String> {
    text.split(' ').filter(|word| !word.is_empty()).map(str::to_string).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> TrajectoryHeader {
        TrajectoryHeader {
            domain: "packing".into(),
            seed: 7,
            provenance: [("cut_at".to_string(), "12".to_string())].into(),
            bodies: vec![
                BodyDescription { name: "can_0".into(), type_name: "can".into() },
                BodyDescription { name: "box".into(), type_name: "box".into() },
            ],
            robots: vec![RobotDescription {
                name: "gripper".into(),
                coordinates: vec!["x".into(), "y".into()],
                grippers: vec!["magnet".into()],
            }],
        }
    }

    #[test]
    fn metadata_layout_is_the_documented_one() {
        let metadata = header_to_metadata(&header());
        let entries: Vec<(&str, &str)> =
            metadata.iter().map(|(key, value)| (key.as_str(), value.as_str())).collect();
        assert_eq!(
            entries,
            [
                ("bodies", "can_0 can\nbox box"),
                ("domain", "packing"),
                ("format", "lamp-trajectory"),
                ("format_version", "1"),
                ("provenance.cut_at", "12"),
                ("robot.gripper.coordinates", "x y"),
                ("robot.gripper.grippers", "magnet"),
                ("robots", "gripper"),
                ("seed", "7"),
            ]
        );
        assert_eq!(header_from_metadata(&metadata).unwrap(), header());
    }

    #[test]
    fn another_version_or_tool_is_a_schema_problem() {
        let mut metadata = header_to_metadata(&header());
        metadata.insert("format_version".into(), "2".into());
        assert!(matches!(header_from_metadata(&metadata), Err(MetadataProblem::Schema(_))));
        metadata.insert("format".into(), "other".into());
        assert!(matches!(header_from_metadata(&metadata), Err(MetadataProblem::Schema(_))));
    }

    #[test]
    fn malformed_entries_are_header_problems() {
        let mut metadata = header_to_metadata(&header());
        metadata.insert("bodies".into(), "can_0 can\ncan_0 can".into());
        assert!(matches!(header_from_metadata(&metadata), Err(MetadataProblem::Header(_))));
        let mut metadata = header_to_metadata(&header());
        metadata.remove("robot.gripper.grippers");
        assert!(matches!(header_from_metadata(&metadata), Err(MetadataProblem::Header(_))));
        let mut metadata = header_to_metadata(&header());
        metadata.insert("seed".into(), "-1".into());
        assert!(matches!(header_from_metadata(&metadata), Err(MetadataProblem::Header(_))));
    }
}
