//! Loading: the shipped robots, typed errors naming the file and element, meshes as convex hulls,
//! collision geometry and self-collision pairs (including a tuck pose free of self-collision).

mod common;

use std::io::Write;

use lamp_geometry::{Pose, Shape, Vec3};
use lamp_robot::{Mount, Robot, RobotError};
use miette::Diagnostic;

#[test]
fn shipped_robots_load_with_expected_structure() {
    let fetch = common::fetch_fixed();
    assert_eq!(fetch.name(), "fetch");
    assert_eq!(fetch.dof(), 10);
    for link in [
        "base_link",
        "torso_lift_link",
        "shoulder_pan_link",
        "shoulder_lift_link",
        "upperarm_roll_link",
        "elbow_flex_link",
        "forearm_roll_link",
        "wrist_flex_link",
        "wrist_roll_link",
        "gripper_link",
        "l_gripper_finger_link",
        "r_gripper_finger_link",
    ] {
        let id = fetch.link_id(link).unwrap_or_else(|| panic!("missing {link}"));
        assert!(
            fetch.collision_geometry().iter().any(|geometry| geometry.link == id),
            "{link} has no geometry"
        );
    }
    assert_eq!(fetch.link_id("base_link"), Some(0));
    assert_eq!(
        fetch.parent_link(fetch.link_id("gripper_link").expect("gripper")),
        fetch.link_id("wrist_roll_link")
    );

    let yumi = common::yumi_fixed();
    assert_eq!(yumi.dof(), 9);
    let names: Vec<&str> = yumi
        .group("arm")
        .expect("arm")
        .coordinates
        .iter()
        .map(|&i| yumi.coordinate_names()[i].as_str())
        .collect();
    assert_eq!(
        names,
        [
            "yumi_joint_1_l",
            "yumi_joint_2_l",
            "yumi_joint_7_l",
            "yumi_joint_3_l",
            "yumi_joint_4_l",
            "yumi_joint_5_l",
            "yumi_joint_6_l"
        ]
    );

    let magnetic = common::load("magnetic_gripper.urdf", Mount::Floating);
    assert_eq!(magnetic.dof(), 6);
    assert_eq!(magnetic.link_count(), 1);
    assert_eq!(
        magnetic.collision_geometry()[0].shape,
        Shape::Box { half_extents: Vec3::new(0.0125, 0.0125, 0.05584) }
    );
    assert!(magnetic.self_collision_pairs().is_empty());

    let two_finger = common::load("two_finger_gripper.urdf", Mount::Floating);
    assert_eq!(two_finger.dof(), 6);
    let q = two_finger.neutral_configuration();
    let left = two_finger.link_pose(&q, two_finger.link_id("l_finger_link").expect("left finger"));
    assert!((left.translation.x - 0.02906).abs() < 1e-12);
    // Fingers are rigidly attached to the palm: no self-collision pairs at all.
    assert!(two_finger.self_collision_pairs().is_empty());
}

#[test]
fn self_collision_pairs_exclude_adjacent_and_fixed_connected_links() {
    let fetch = common::fetch_fixed();
    let id = |name: &str| fetch.link_id(name).expect("link exists");
    let pairs = fetch.self_collision_pairs();
    let has = |a: &str, b: &str| {
        let (a, b) = (id(a), id(b));
        pairs.contains(&(a.min(b), a.max(b)))
    };
    assert!(pairs.windows(2).all(|pair| pair[0] < pair[1]), "sorted and unique");
    assert!(pairs.iter().all(|&(a, b)| a < b));
    // Parent-child through a moving joint.
    assert!(!has("shoulder_pan_link", "shoulder_lift_link"));
    assert!(!has("gripper_link", "l_gripper_finger_link"));
    assert!(!has("base_link", "torso_lift_link"));
    // Fixed joints merge links: the head is part of the torso, the torso column part of the base,
    // and the gripper part of the wrist roll link (so the wrist flex link is adjacent to the gripper).
    assert!(!has("torso_lift_link", "head_tilt_link"));
    assert!(!has("head_pan_link", "shoulder_pan_link"));
    assert!(!has("torso_fixed_link", "torso_lift_link"));
    assert!(!has("wrist_flex_link", "gripper_link"));
    // Non-adjacent pairs are checked.
    assert!(has("base_link", "gripper_link"));
    assert!(has("torso_lift_link", "elbow_flex_link"));
    assert!(has("l_gripper_finger_link", "r_gripper_finger_link"));
    assert!(has("head_tilt_link", "gripper_link"));

    let count = pairs.len();
    let fewer = fetch
        .with_ignored_collisions(&[("r_gripper_finger_link", "l_gripper_finger_link")])
        .expect("links exist");
    assert_eq!(fewer.self_collision_pairs().len(), count - 1);
    let error = fewer.with_ignored_collisions(&[("nope", "base_link")]).unwrap_err();
    assert!(matches!(error, RobotError::UnknownLink { .. }));
}

// ----- conservative self-collision check by oriented bounding boxes (separating axis test) -----

/// An oriented box in the world: centre, axes (columns), half extents.
struct OrientedBox {
    pose: Pose,
    half_extents: Vec3,
}

/// The box enclosing a primitive shape (so "boxes disjoint" implies "shapes disjoint").
fn enclosing_box(world: Pose, shape: &Shape) -> OrientedBox {
    let half_extents = match shape {
        Shape::Box { half_extents } => *half_extents,
        Shape::Cylinder { radius, half_height } => Vec3::new(*radius, *radius, *half_height),
        Shape::Sphere { radius } => Vec3::new(*radius, *radius, *radius),
        other => panic!("shipped robots use primitives only, found {other:?}"),
    };
    OrientedBox { pose: world, half_extents }
}

fn boxes_disjoint(a: &OrientedBox, b: &OrientedBox) -> bool {
    let axes_a: Vec<Vec3> = (0..3).map(|i| a.pose.rotation * Vec3::ith(i, 1.0)).collect();
    let axes_b: Vec<Vec3> = (0..3).map(|i| b.pose.rotation * Vec3::ith(i, 1.0)).collect();
    let mut candidates = axes_a.clone();
    candidates.extend(axes_b.iter().copied());
    for x in &axes_a {
        for y in &axes_b {
            let cross = x.cross(y);
            if cross.norm() > 1e-9 {
                candidates.push(cross.normalize());
            }
        }
    }
    let offset = b.pose.translation.vector - a.pose.translation.vector;
    candidates.iter().any(|axis| {
        let radius = |axes: &[Vec3], half: &Vec3| {
            (0..3).map(|i| half[i] * axes[i].dot(axis).abs()).sum::<f64>()
        };
        offset.dot(axis).abs() > radius(&axes_a, &a.half_extents) + radius(&axes_b, &b.half_extents)
    })
}

/// Pairs whose enclosing boxes overlap (a superset of the truly colliding pairs).
fn possibly_colliding_pairs(robot: &Robot, q: &[f64]) -> Vec<(String, String)> {
    let mut poses = vec![Pose::identity(); robot.link_count()];
    robot.forward_kinematics(q, &mut poses);
    let mut result = Vec::new();
    for &(a, b) in robot.self_collision_pairs() {
        for geometry_a in robot.collision_geometry().iter().filter(|geometry| geometry.link == a) {
            for geometry_b in
                robot.collision_geometry().iter().filter(|geometry| geometry.link == b)
            {
                let box_a = enclosing_box(poses[a] * geometry_a.origin, &geometry_a.shape);
                let box_b = enclosing_box(poses[b] * geometry_b.origin, &geometry_b.shape);
                if !boxes_disjoint(&box_a, &box_b) {
                    result.push((robot.link_name(a).to_string(), robot.link_name(b).to_string()));
                }
            }
        }
    }
    result
}

#[test]
fn fetch_tuck_and_yumi_neutral_are_free_of_self_collision() {
    let fetch = common::fetch_fixed();
    let mut q = fetch.neutral_configuration();
    fetch
        .apply_named_configuration(
            [
                ("torso_lift_joint", 0.0),
                ("shoulder_pan_joint", 1.32),
                ("shoulder_lift_joint", 1.40),
                ("upperarm_roll_joint", -0.20),
                ("elbow_flex_joint", 1.72),
                ("forearm_roll_joint", 0.0),
                ("wrist_flex_joint", 1.66),
                ("wrist_roll_joint", 0.0),
            ],
            &mut q,
        )
        .expect("tuck joints exist");
    assert_eq!(possibly_colliding_pairs(&fetch, &q), Vec::<(String, String)>::new());
    // With the torso raised and the gripper open too.
    fetch
        .apply_named_configuration(
            [
                ("torso_lift_joint", 0.38),
                ("l_gripper_finger_joint", 0.05),
                ("r_gripper_finger_joint", 0.05),
            ],
            &mut q,
        )
        .expect("joints exist");
    assert_eq!(possibly_colliding_pairs(&fetch, &q), Vec::<(String, String)>::new());

    let yumi = common::yumi_fixed();
    assert_eq!(
        possibly_colliding_pairs(&yumi, &yumi.neutral_configuration()),
        Vec::<(String, String)>::new()
    );

    // The check is not vacuous: folding the Fetch elbow fully back into the upper arm collides.
    fetch
        .apply_named_configuration(
            [("shoulder_lift_joint", 0.0), ("elbow_flex_joint", 2.25), ("wrist_flex_joint", 2.16)],
            &mut q,
        )
        .expect("joints exist");
    assert!(!possibly_colliding_pairs(&fetch, &q).is_empty());
}

// ----- errors -----

fn diagnostic_code(error: &RobotError) -> String {
    error.code().map(|code| code.to_string()).unwrap_or_default()
}

#[test]
fn missing_file_is_a_read_error_naming_the_file() {
    let error = Robot::from_urdf_file(std::path::Path::new("no/such/robot.urdf"), Mount::Planar)
        .unwrap_err();
    assert!(matches!(error, RobotError::Read { .. }));
    assert_eq!(diagnostic_code(&error), "lamp::robot::read");
    assert!(error.to_string().contains("no/such/robot.urdf"), "{error}");
}

#[test]
fn a_file_too_large_for_a_robot_is_refused_unread() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("huge.urdf");
    // Sparse: as long as the limit and one byte, nothing written.
    let file = std::fs::File::create(&path).expect("create");
    file.set_len(lamp_robot::MAX_URDF_BYTES + 1).expect("sparse length");
    let error = Robot::from_urdf_file(&path, Mount::Planar).unwrap_err();
    assert_eq!(diagnostic_code(&error), "lamp::robot::too_large");
    assert!(error.to_string().contains("huge.urdf"), "{error}");
}

#[test]
fn bad_xml_is_a_parse_error_naming_the_file() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("broken.urdf");
    std::fs::write(&path, "<robot name=\"r\"><link name=\"a\"></robot>").expect("write");
    let error = Robot::from_urdf_file(&path, Mount::Planar).unwrap_err();
    assert_eq!(diagnostic_code(&error), "lamp::robot::urdf_parse");
    assert!(error.to_string().contains("broken.urdf"), "{error}");
}

#[test]
fn unknown_parent_link_names_the_joint_and_link() {
    let urdf = r#"<robot name="r"><link name="a"/><link name="b"/>
        <joint name="j" type="fixed"><parent link="ghost"/><child link="b"/></joint></robot>"#;
    let error = Robot::from_urdf_str(urdf, None, Mount::Planar).unwrap_err();
    assert_eq!(diagnostic_code(&error), "lamp::robot::missing_link");
    let message = error.to_string();
    assert!(
        message.contains("<string>") && message.contains("`j`") && message.contains("`ghost`"),
        "{message}"
    );
}

#[test]
fn structural_errors_are_typed() {
    let two_roots = r#"<robot name="r"><link name="a"/><link name="b"/></robot>"#;
    assert!(matches!(
        Robot::from_urdf_str(two_roots, None, Mount::Planar),
        Err(RobotError::NotATree { .. })
    ));
    let cycle = r#"<robot name="r"><link name="root"/><link name="a"/><link name="b"/>
        <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
        <joint name="j2" type="fixed"><parent link="b"/><child link="a"/></joint></robot>"#;
    assert!(matches!(
        Robot::from_urdf_str(cycle, None, Mount::Planar),
        Err(RobotError::NotATree { .. })
    ));
    let duplicate = r#"<robot name="r"><link name="a"/><link name="a"/></robot>"#;
    assert!(matches!(
        Robot::from_urdf_str(duplicate, None, Mount::Planar),
        Err(RobotError::DuplicateName { .. })
    ));
    let zero_axis = r#"<robot name="r"><link name="a"/><link name="b"/>
        <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 0"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#;
    let error = Robot::from_urdf_str(zero_axis, None, Mount::Planar).unwrap_err();
    assert_eq!(diagnostic_code(&error), "lamp::robot::joint");
    let inverted = r#"<robot name="r"><link name="a"/><link name="b"/>
        <joint name="j" type="prismatic"><parent link="a"/><child link="b"/>
        <limit lower="1" upper="-1" effort="1" velocity="1"/></joint></robot>"#;
    assert!(matches!(
        Robot::from_urdf_str(inverted, None, Mount::Planar),
        Err(RobotError::InvalidJoint { .. })
    ));
    let negative_speed = r#"<robot name="r"><link name="a"/><link name="b"/>
        <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
        <limit lower="-1" upper="1" effort="1" velocity="-2"/></joint></robot>"#;
    let error = Robot::from_urdf_str(negative_speed, None, Mount::Planar).unwrap_err();
    assert!(error.to_string().contains("velocity limit -2 is not a speed"), "{error}");
    let negative_box = r#"<robot name="r"><link name="a"><collision><geometry><box size="1 -1 1"/></geometry></collision></link></robot>"#;
    assert!(matches!(
        Robot::from_urdf_str(negative_box, None, Mount::Planar),
        Err(RobotError::InvalidGeometry { .. })
    ));
}

/// Writes a binary STL of an axis-aligned box (12 triangles).
fn write_box_stl(path: &std::path::Path, half: [f32; 3]) {
    let corner = |i: usize| {
        [
            if i & 1 == 0 { -half[0] } else { half[0] },
            if i & 2 == 0 { -half[1] } else { half[1] },
            if i & 4 == 0 { -half[2] } else { half[2] },
        ]
    };
    let faces: [[usize; 3]; 12] = [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&(faces.len() as u32).to_le_bytes());
    for face in faces {
        bytes.extend_from_slice(&[0u8; 12]);
        for vertex in face {
            for value in corner(vertex) {
                bytes.extend_from_slice(&value.to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0u8; 2]);
    }
    std::fs::File::create(path).and_then(|mut file| file.write_all(&bytes)).expect("write STL");
}

#[test]
fn meshes_load_as_convex_hulls_with_relative_and_package_paths() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let package = directory.path().join("my_robot");
    std::fs::create_dir_all(package.join("meshes")).expect("mesh folder");
    std::fs::create_dir_all(package.join("urdf")).expect("urdf folder");
    write_box_stl(&package.join("meshes/box.stl"), [0.1, 0.2, 0.3]);
    let urdf = r#"<robot name="meshy">
        <link name="a"><collision><geometry><mesh filename="../meshes/box.stl"/></geometry></collision></link>
        <link name="b"><collision><geometry><mesh filename="package://my_robot/meshes/box.stl" scale="2 2 2"/></geometry></collision></link>
        <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#;
    let urdf_path = package.join("urdf/meshy.urdf");
    std::fs::write(&urdf_path, urdf).expect("write URDF");
    let robot =
        Robot::from_urdf_file(&urdf_path, Mount::Fixed(Pose::identity())).expect("meshes load");
    let hull = |index: usize| match &robot.collision_geometry()[index].shape {
        Shape::ConvexHull { points } => points.clone(),
        other => panic!("expected a convex hull, got {other:?}"),
    };
    let relative = hull(0);
    assert_eq!(relative.len(), 8, "the 36 STL vertices deduplicate to the 8 box corners");
    let maximum = |points: &[lamp_geometry::Point3], axis: usize| {
        points.iter().map(|p| p[axis]).fold(f64::MIN, f64::max)
    };
    assert!((maximum(&relative, 2) - 0.3).abs() < 1e-6);
    let packaged = hull(1);
    assert!((maximum(&packaged, 1) - 0.4).abs() < 1e-6, "scale applied");

    // A missing mesh names the URDF, the link and the mesh.
    let missing = urdf.replace("../meshes/box.stl", "../meshes/gone.stl");
    let error =
        Robot::from_urdf_str(&missing, Some(&package.join("urdf")), Mount::Planar).unwrap_err();
    assert_eq!(diagnostic_code(&error), "lamp::robot::mesh");
    let message = error.to_string();
    assert!(message.contains("`a`") && message.contains("gone.stl"), "{message}");
    // Without a base directory a relative mesh cannot be resolved.
    assert!(matches!(
        Robot::from_urdf_str(urdf, None, Mount::Planar),
        Err(RobotError::Mesh { .. })
    ));
}

#[test]
fn robot_is_clone_send_and_sync() {
    fn shareable<T: Clone + Send + Sync>() {}
    shareable::<Robot>();
    shareable::<lamp_robot::IkConfig>();
}
