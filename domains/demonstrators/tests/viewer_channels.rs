//! The standard ROS 2 and Foxglove channels of a Packing and a Café demonstration, decoded by the
//! reference Python readers (`mcap`, `mcap-ros2-support`): every channel is there in its standard
//! schema, `/tf` agrees with `/lamp/world` (bodies, at every step) and with forward kinematics of
//! its robot configuration (each link transform at its stamp, every link at the last step) within
//! 1e-9, frames are refreshed every second, `/joint_states` carries the configuration's values,
//! held objects keep their pose in the gripper, and the `foxglove.SceneUpdate` messages satisfy
//! the file's JSON schema and build the `foxglove-sdk` message types (where it is installed).
//! Skips when the packages are missing unless `LAMP_REQUIRE_ORACLES=1`.

// The oracle helper reports why it skipped, as the test harness shows.
#![allow(clippy::print_stdout, clippy::unwrap_used)] // and a failed step is a failed test

mod support;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

use lamp_demonstrators::{Demonstrator, Simulation, generate};
use lamp_geometry::Pose;
use lamp_spec::TrackingNoise;
use lamp_test_support::{domains_dir, oracles_required, python_oracle};
use lamp_trajectory::{
    DERIVED_FRAME_PERIOD_NANOSECONDS, JOINT_STATE_SCHEMA_NAME, JOINT_STATES_TOPIC,
    ROBOT_DESCRIPTION_TOPIC, SCENE_SCHEMA_NAME, SCENE_TOPIC, STRING_SCHEMA_NAME,
    TF_REFRESH_NANOSECONDS, TF_SCHEMA_NAME, TF_STATIC_TOPIC, TF_TOPIC, Trajectory,
    TrajectoryReader, WORLD_TOPIC,
};
use lamp_world::SpecWorld;
use nalgebra::{Quaternion, Translation3, UnitQuaternion};

/// How far a decoded pose may be from the expected one: the acceptance bound of the channels.
const POSE_TOLERANCE: f64 = 1e-9;

/// Decodes every channel and prints one JSON document; floats survive exactly (`repr`).
const DECODE_SCRIPT: &str = r#"
import json, sys
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

def pose(p, q):
    return [p.x, p.y, p.z, q.x, q.y, q.z, q.w]

out = {"channels": [], "world": [], "tf": [], "tf_static": [], "joint_states": [],
       "descriptions": {}, "scene": [], "qos": {}, "held": []}
with open(sys.argv[1], "rb") as stream:
    reader = make_reader(stream, validate_crcs=True, decoder_factories=[DecoderFactory()])
    summary = reader.get_summary()
    schemas = {}
    for channel in summary.channels.values():
        schema = summary.schemas[channel.schema_id]
        schemas[channel.topic] = schema
        out["channels"].append([channel.topic, channel.message_encoding, schema.name, schema.encoding])
        if "offered_qos_profiles" in channel.metadata:
            out["qos"][channel.topic] = channel.metadata["offered_qos_profiles"]
    for schema, channel, message in reader.iter_messages(topics=["/lamp/scene"]):
        update = json.loads(message.data)
        out["scene"].append({"t": message.log_time, "update": update, "schema": json.loads(schema.data)})
    cdr_topics = [c.topic for c in summary.channels.values() if c.message_encoding == "cdr"]
    for schema, channel, message, decoded in reader.iter_decoded_messages(topics=cdr_topics):
        t = message.log_time
        if channel.topic == "/lamp/world":
            out["world"].append({"t": t,
                "bodies": [pose(b.position, b.orientation) for b in decoded.body_poses],
                "robots": [{"positions": list(r.positions), "held": list(r.held)} for r in decoded.robots]})
        elif channel.topic in ("/tf", "/tf_static"):
            out[channel.topic[1:]].append({"t": t, "transforms": [
                [x.header.frame_id, x.child_frame_id, x.header.stamp.sec, x.header.stamp.nanosec,
                 pose(x.transform.translation, x.transform.rotation)] for x in decoded.transforms]})
        elif channel.topic == "/joint_states":
            out["joint_states"].append({"t": t, "stamp": [decoded.header.stamp.sec, decoded.header.stamp.nanosec],
                "name": list(decoded.name), "position": list(decoded.position),
                "velocity": len(decoded.velocity), "effort": len(decoded.effort)})
        elif channel.topic == "/lamp/held":
            out["held"].append([t, decoded.data])
        elif channel.topic.endswith("robot_description"):
            out["descriptions"][channel.topic] = decoded.data
json.dump(out, sys.stdout)
"#;

/// Checks each scene update against the file's JSON schema, and builds the official Foxglove
/// message types from it when `foxglove-sdk` is installed (unknown fields and wrong types fail).
const SCENE_SCRIPT: &str = r#"
import json, sys
import jsonschema
from mcap.reader import make_reader

with open(sys.argv[1], "rb") as stream:
    reader = make_reader(stream, validate_crcs=True)
    count = 0
    checked_by = ["jsonschema"]
    try:
        import foxglove.messages as fm
    except ImportError:
        fm = None
    for schema, channel, message in reader.iter_messages(topics=["/lamp/scene"]):
        update = json.loads(message.data)
        jsonschema.validate(update, json.loads(schema.data))
        count += 1
        if fm is None:
            continue
        kinds = {"timestamp": fm.Timestamp, "lifetime": fm.Duration, "metadata": fm.KeyValuePair,
                 "cubes": fm.CubePrimitive, "spheres": fm.SpherePrimitive,
                 "cylinders": fm.CylinderPrimitive, "triangles": fm.TriangleListPrimitive,
                 "pose": fm.Pose, "position": fm.Vector3, "orientation": fm.Quaternion,
                 "size": fm.Vector3, "color": fm.Color, "points": fm.Point3,
                 "entities": fm.SceneEntity, "deletions": fm.SceneEntityDeletion}
        def build(kind, value):
            if isinstance(value, list):
                return [build(kind, item) for item in value]
            if isinstance(value, dict):
                return kind(**{k: build(kinds.get(k), v) for k, v in value.items()})
            return value
        encoded = fm.SceneUpdate(**{k: build(kinds[k], v) for k, v in update.items()}).encode()
        assert len(encoded) > 0
        if "foxglove-sdk" not in checked_by:
            checked_by.append("foxglove-sdk")
    print(count, "+".join(checked_by))
"#;

fn run_python(script: &str, file: &Path) -> String {
    let output =
        Command::new("python3").arg("-c").arg(script).arg(file).output().expect("python3 runs");
    assert!(output.status.success(), "python failed:\n{}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).expect("python prints UTF-8")
}

fn pose_of(values: &serde_json::Value) -> Pose {
    let v: Vec<f64> = values.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    Pose::from_parts(
        Translation3::new(v[0], v[1], v[2]),
        UnitQuaternion::new_unchecked(Quaternion::new(v[6], v[3], v[4], v[5])),
    )
}

/// The world pose of `frame`: its poses composed up to the `world` frame.
fn world_pose(tree: &BTreeMap<String, (String, Pose)>, frame: &str) -> Pose {
    let mut pose = Pose::identity();
    let mut current = frame;
    while current != "world" {
        let (parent, local) = &tree[current];
        pose = local * pose;
        current = parent;
    }
    pose
}

fn close(found: &Pose, expected: &Pose) -> bool {
    let position = (found.translation.vector - expected.translation.vector).norm();
    let rotation = (found.rotation.coords - expected.rotation.coords).norm();
    position <= POSE_TOLERANCE && rotation <= POSE_TOLERANCE
}

fn assert_close(found: &Pose, expected: &Pose, what: &str) {
    let position = (found.translation.vector - expected.translation.vector).norm();
    let rotation = (found.rotation.coords - expected.rotation.coords).norm();
    assert!(
        position <= POSE_TOLERANCE && rotation <= POSE_TOLERANCE,
        "{what}: {found:?} differs from {expected:?} by {position} m, {rotation} in the quaternion"
    );
}

/// Writes the demonstration with its channels, decodes it in Python and checks every channel.
fn check_demonstration(world: &SpecWorld, urdf_path: &Path, trajectory: &Trajectory) {
    let (channels, values) = lamp_world::standard_channels(world, trajectory).unwrap();
    let start = std::time::Instant::now();
    let bytes = trajectory.to_bytes_with(&channels, &values).unwrap();
    let with_seconds = start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();
    let plain = trajectory.to_bytes().unwrap().len();
    let plain_seconds = start.elapsed().as_secs_f64();
    let steps = trajectory.steps.len() as f64;
    println!(
        "{}: {steps} steps, {plain} bytes without the standard channels, {} with them ({:.2}×); written at {:.0} and {:.0} steps/s (test profile)",
        trajectory.header.domain,
        bytes.len(),
        bytes.len() as f64 / plain as f64,
        steps / plain_seconds,
        steps / with_seconds,
    );
    // The lamp reader ignores the standard channels and reads the same steps.
    assert_eq!(
        &TrajectoryReader::from_bytes(&bytes, "demo").unwrap().read_all().unwrap(),
        trajectory
    );

    let folder = tempfile::tempdir().unwrap();
    let file = folder.path().join("demo.mcap");
    std::fs::write(&file, &bytes).unwrap();
    let decoded: serde_json::Value =
        serde_json::from_str(&run_python(DECODE_SCRIPT, &file)).unwrap();

    let topics: BTreeMap<String, (String, String, String)> = decoded["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let s = |i: usize| c[i].as_str().unwrap().to_string();
            (s(0), (s(1), s(2), s(3)))
        })
        .collect();
    let ros2 = |schema: &str| ("cdr".to_string(), schema.to_string(), "ros2msg".to_string());
    assert_eq!(topics[TF_TOPIC], ros2(TF_SCHEMA_NAME));
    assert_eq!(topics[ROBOT_DESCRIPTION_TOPIC], ros2(STRING_SCHEMA_NAME));
    assert_eq!(
        topics[SCENE_TOPIC],
        ("json".to_string(), SCENE_SCHEMA_NAME.to_string(), "jsonschema".to_string())
    );
    assert!(topics.contains_key(WORLD_TOPIC));
    assert_eq!(
        decoded["descriptions"][ROBOT_DESCRIPTION_TOPIC],
        std::fs::read_to_string(urdf_path).unwrap()
    );
    assert!(decoded["qos"][ROBOT_DESCRIPTION_TOPIC].as_str().unwrap().contains("durability: 1"));

    let header = &trajectory.header;
    let robot_name = &header.robots[0].name;
    let model = &world.robots[robot_name];
    let world_steps = decoded["world"].as_array().unwrap();
    let tf = decoded["tf"].as_array().unwrap();
    assert_eq!(world_steps.len(), trajectory.steps.len());
    assert_eq!(tf.len(), trajectory.steps.len());

    // Fixed frames are on /tf_static once, at time zero: frame → (parent, pose in the parent).
    let mut static_poses = BTreeMap::new();
    if let Some(messages) = decoded["tf_static"].as_array().filter(|m| !m.is_empty()) {
        assert_eq!(topics[TF_STATIC_TOPIC], ros2(TF_SCHEMA_NAME));
        assert!(decoded["qos"][TF_STATIC_TOPIC].as_str().unwrap().contains("durability: 1"));
        assert_eq!(messages.len(), 1);
        assert_eq!(messages[0]["t"], 0);
        for transform in messages[0]["transforms"].as_array().unwrap() {
            let parent = transform[0].as_str().unwrap().to_string();
            let frame = transform[1].as_str().unwrap().to_string();
            static_poses.insert(frame, (parent, pose_of(&transform[4])));
        }
    }

    let joint_states = decoded["joint_states"].as_array().unwrap();
    let joints: Vec<(String, usize)> = (0..model.link_count())
        .filter_map(|link| model.parent_joint_name(link))
        .filter_map(|joint| match model.joint_coordinates(joint).unwrap()[..] {
            [coordinate] => Some((joint.to_string(), coordinate)),
            _ => None,
        })
        .collect();
    if joints.is_empty() {
        assert!(joint_states.is_empty() && !topics.contains_key(JOINT_STATES_TOPIC));
    } else {
        assert_eq!(topics[JOINT_STATES_TOPIC], ros2(JOINT_STATE_SCHEMA_NAME));
        // Written when a joint moves: at the first step, and not more often than the steps.
        assert_eq!(joint_states[0]["t"].as_u64().unwrap(), trajectory.steps[0].time_nanoseconds);
        assert!(joint_states.len() <= trajectory.steps.len());
    }

    let held_messages = decoded["held"].as_array().unwrap();
    let mut held_next = 0;
    let mut held_frame = None;
    let gripper = world.spec().robot(robot_name).unwrap().gripper_part().unwrap().link.clone();
    let gripper = model.link_id(&gripper).unwrap();
    let mut grasp: Option<(usize, Pose)> = None;
    let mut grasps_seen = 0;
    // The tf tree as a viewer holds it: every frame's latest transform, and when it was written.
    let mut tree = static_poses.clone();
    let mut written_at: BTreeMap<String, u64> = BTreeMap::new();
    let mut joints_next = 0;
    let mut joint_values: Option<&serde_json::Value> = None;
    let mut tf_transforms = 0;
    for (index, step) in trajectory.steps.iter().enumerate() {
        let time = step.time_nanoseconds;
        let last = index + 1 == trajectory.steps.len();
        let message = &tf[index];
        assert_eq!(message["t"].as_u64().unwrap(), time);
        assert_eq!(world_steps[index]["t"].as_u64().unwrap(), time);
        let mut in_message = BTreeSet::new();
        for transform in message["transforms"].as_array().unwrap() {
            let stamp =
                transform[2].as_u64().unwrap() * 1_000_000_000 + transform[3].as_u64().unwrap();
            assert_eq!(stamp, time);
            let parent = transform[0].as_str().unwrap().to_string();
            let frame = transform[1].as_str().unwrap().to_string();
            assert!(in_message.insert(frame.clone()), "a frame twice");
            assert!(!static_poses.contains_key(&frame), "{frame} is on /tf and /tf_static");
            tree.insert(frame.clone(), (parent, pose_of(&transform[4])));
            written_at.insert(frame, time);
            tf_transforms += 1;
        }
        // Every frame's world pose, composed along the tree.
        let frames: BTreeMap<String, Pose> =
            tree.keys().map(|frame| (frame.clone(), world_pose(&tree, frame))).collect();
        assert_eq!(frames.len(), model.link_count() + header.bodies.len());
        for (frame, at) in &written_at {
            assert!(time - at < TF_REFRESH_NANOSECONDS, "step {index}: {frame} not refreshed");
        }
        // Bodies: as /lamp/world says (decoded by Python too), at every step.
        for (body, description) in header.bodies.iter().enumerate() {
            let from_world = pose_of(&world_steps[index]["bodies"][body]);
            assert_close(&from_world, &step.body_poses[body], "the /lamp/world pose");
            assert_eq!(
                tree[&description.name].0, "world",
                "bodies are children of the world frame"
            );
            let found = &frames[&description.name];
            assert_close(found, &from_world, &format!("step {index}, body {}", description.name));
        }
        // Links: each transform is forward kinematics of the configuration at its stamp. A link
        // below the root that is not in this message is where it was, or was written less than
        // a period ago (viewers interpolate); the root is always current.
        let q = &step.robots[0].positions;
        for link in 0..model.link_count() {
            let name = model.link_name(link);
            let expected = match model.parent_link(link) {
                Some(parent) => model.link_pose(q, parent).inverse() * model.link_pose(q, link),
                None => model.link_pose(q, link),
            };
            let (_, found) = &tree[name];
            let what = format!("step {index}, link {name}");
            if in_message.contains(name) || link == 0 || last {
                assert_close(found, &expected, &what);
            } else if !close(found, &expected) {
                let age = time - written_at[name];
                assert!(age < DERIVED_FRAME_PERIOD_NANOSECONDS, "{what}: {age} ns old");
            }
        }
        // At the last step every link is where forward kinematics puts it.
        if last {
            for link in 0..model.link_count() {
                let found = &frames[model.link_name(link)];
                let what = format!("last step, link {}", model.link_name(link));
                assert_close(found, &model.link_pose(q, link), &what);
            }
        }
        if !joints.is_empty() {
            // /joint_states carries the configuration as of its latest message.
            while joint_states.get(joints_next).is_some_and(|m| m["t"].as_u64().unwrap() <= time) {
                joint_values = Some(&joint_states[joints_next]);
                joints_next += 1;
            }
            let state = joint_values.unwrap();
            let stamp = state["stamp"].as_array().unwrap();
            let stamp = stamp[0].as_u64().unwrap() * 1_000_000_000 + stamp[1].as_u64().unwrap();
            assert_eq!(stamp, state["t"].as_u64().unwrap());
            let names: Vec<&str> =
                state["name"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
            let expected: Vec<&str> = joints.iter().map(|(name, _)| name.as_str()).collect();
            assert_eq!(names, expected);
            for (value, (_, coordinate)) in
                state["position"].as_array().unwrap().iter().zip(&joints)
            {
                // serde_json reads decimals to within an ulp, not always exactly.
                assert!((value.as_f64().unwrap() - q[*coordinate]).abs() <= POSE_TOLERANCE);
            }
            assert_eq!((state["velocity"].as_u64(), state["effort"].as_u64()), (Some(0), Some(0)));
        }
        // /lamp/held names the held object's frame, as of the latest message at or before the step.
        while held_messages.get(held_next).is_some_and(|m| m[0].as_u64().unwrap() <= time) {
            held_frame = held_messages[held_next][1].as_str().map(String::from);
            held_next += 1;
        }
        let expected = step.robots[0].held[0].map_or("", |body| header.bodies[body].name.as_str());
        assert_eq!(held_frame.as_deref(), Some(expected), "step {index}: the held frame");
        // A held object (its frame on /tf) keeps its pose in the gripper link's frame.
        match step.robots[0].held[0] {
            Some(body) => {
                let relative =
                    model.link_pose(q, gripper).inverse() * frames[&header.bodies[body].name];
                match grasp {
                    Some((held, first)) if held == body => {
                        assert_close(&relative, &first, &format!("step {index}, held object"));
                    }
                    _ => {
                        grasps_seen += 1;
                        grasp = Some((body, relative));
                    }
                }
            }
            None => grasp = None,
        }
    }
    println!(
        "{} transforms on /tf for {} steps, {} /joint_states messages",
        tf_transforms,
        trajectory.steps.len(),
        joint_states.len()
    );
    assert!(grasps_seen >= 1, "the demonstration grasps something");

    // One scene update at time zero: one entity per body in its own frame, one primitive per shape.
    let scene = decoded["scene"].as_array().unwrap();
    assert_eq!(scene.len(), 1);
    assert_eq!(scene[0]["t"], 0);
    let entities = scene[0]["update"]["entities"].as_array().unwrap();
    assert_eq!(entities.len(), header.bodies.len());
    for (entity, body) in entities.iter().zip(&header.bodies) {
        assert_eq!(entity["frame_id"], body.name.as_str());
        assert_eq!(entity["frame_locked"], true);
        let count: usize = ["cubes", "spheres", "cylinders", "triangles"]
            .iter()
            .map(|list| entity[list].as_array().unwrap().len())
            .sum();
        assert_eq!(count, world.type_parts[&body.type_name].len(), "shapes of {}", body.name);
    }

    if python_oracle("jsonschema", "jsonschema") {
        let checked = run_python(SCENE_SCRIPT, &file);
        println!("scene update checked: {checked}");
        assert!(checked.starts_with("1 jsonschema"), "{checked}");
        if oracles_required() {
            assert!(checked.contains("foxglove-sdk"), "foxglove-sdk is required: {checked}");
        }
    }
}

/// Generates one whole demonstration of `demonstrator` with `seed` and checks its channels, when
/// the Python readers are there.
fn check_domain(demonstrator: Demonstrator, seed: u64) {
    if !python_oracle("mcap, mcap_ros2.decoder", "mcap mcap-ros2-support") {
        return;
    }
    let (spec, world) = support::domain(demonstrator.name());
    let simulation = Simulation {
        demonstrator,
        count: 1,
        cut_fraction: 0.0,
        objects: 1,
        seed,
        noise: TrackingNoise::NONE,
        rate: None,
    };
    let demo = generate(&world, &simulation, 0).unwrap();
    let urdf = domains_dir().join(demonstrator.name()).join(&spec.robots[0].urdf);
    check_demonstration(&world, &urdf, &demo.trajectory);
}

#[test]
fn a_packing_demonstration_decodes_with_every_standard_channel_consistent() {
    check_domain(Demonstrator::Packing, 5);
}

#[test]
fn a_cafe_demonstration_decodes_with_every_standard_channel_consistent() {
    check_domain(Demonstrator::Cafe, 3);
}

#[test]
fn a_jenga_demonstration_decodes_with_every_standard_channel_consistent() {
    check_domain(Demonstrator::Jenga, 7);
}
