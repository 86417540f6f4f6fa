//! Skills shared by the demonstrators: plan a collision-free path for one joint group and
//! record every state along it at the checking resolution, touch, grab and release.

use lamp_geometry::{Pose, Rotation, Vec3};
use lamp_robot::IkConfig;
use lamp_world::{LinkGoal, MotionConfig, Scene, densify, plan_motion, straight_line};
use rand_chacha::ChaCha8Rng;

use lamp_world::Recorder;

/// The motion settings of every demonstrator: the world's default resolutions (5 mm,
/// 0.01 rad) and RRT-Connect with an iteration budget but no wall-clock limit, so that the same
/// seed gives the same demonstration on any machine.
pub(crate) fn motion_config() -> MotionConfig {
    let mut config = MotionConfig::default();
    config.rrt.timeout = None;
    config
}

/// Why one attempt at a demonstration failed; the demonstrator retries with fresh choices.
pub(crate) type Attempt<T> = Result<T, String>;

/// Where `robot` is now.
fn configuration_of(scene: &Scene, robot: usize) -> Attempt<Vec<f64>> {
    scene
        .robots()
        .get(robot)
        .map(|r| r.configuration().to_vec())
        .ok_or_else(|| "the robot is not in the scene".to_string())
}

/// The gripper pose that puts what `robot` holds at a placement drawn by `draw`, where `reach`
/// finds a configuration for it and the resting rule accepts letting go there; `draws` tries,
/// each a fresh draw (then `reach`, in that order, for the random stream).
pub(crate) fn accepted_placement(
    scene: &Scene,
    robot: usize,
    draws: usize,
    rng: &mut ChaCha8Rng,
    mut draw: impl FnMut(&mut ChaCha8Rng) -> Pose,
    mut reach: impl FnMut(&Scene, &Pose, &mut ChaCha8Rng) -> Attempt<Vec<f64>>,
) -> Attempt<Option<Pose>> {
    let held = scene.held(robot).ok_or_else(|| "the grab did not hold".to_string())?;
    let grasp = held.grasp;
    Ok((0..draws).find_map(|_| {
        let gripper = draw(rng) * grasp.inverse();
        let q = reach(scene, &gripper, rng).ok()?;
        let mut trial = scene.clone();
        trial.set_configuration(robot, &q);
        trial.release_at_rest(robot).ok()?;
        Some(gripper)
    }))
}

/// Moves `group` of `robot` from where it is to `goal` along a planned path, recording it.
pub(crate) fn move_to(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    group: &str,
    goal: &[f64],
    rng: &mut ChaCha8Rng,
) -> Attempt<()> {
    let config = motion_config();
    let start = configuration_of(scene, robot)?;
    let plan =
        plan_motion(scene, robot, group, &start, goal, &config, rng).map_err(
            |error| match scene.first_contact(robot, goal) {
                Some(contact) => format!("motion planning ({group}): {error} ({contact})"),
                None => format!("motion planning ({group}): {error}"),
            },
        )?;
    let model = scene.robots()[robot].robot().clone();
    let states = densify(&model, &plan.waypoints, &config)
        .map_err(|error| format!("motion planning ({group}): {error}"))?;
    recorder.follow(scene, robot, &states);
    Ok(())
}

/// Moves the gripper of `robot` in a straight line to `target` with `group`, recording it: the
/// way into a grasp and out of a placement, where the fingers straddle the can.
pub(crate) fn move_straight(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    group: &str,
    target: &Pose,
    ik: &IkConfig,
) -> Attempt<()> {
    let config = motion_config();
    let start = configuration_of(scene, robot)?;
    let path = straight_line(
        scene,
        &LinkGoal { robot, group, link: None, target, start: &start },
        &config,
        ik,
    )
    .map_err(|error| format!("straight move ({group}): {error}"))?;
    let model = scene.robots()[robot].robot().clone();
    let states = densify(&model, &path, &config)
        .map_err(|error| format!("straight move ({group}): {error}"))?;
    recorder.follow(scene, robot, &states);
    Ok(())
}

/// Grabs `body` where the gripper is and records the step where the held flag changes.
pub(crate) fn grab(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    body: usize,
) -> Attempt<()> {
    scene.grab(robot, body).map_err(|error| error.to_string())?;
    recorder.record(scene);
    Ok(())
}

/// Brings a gripper without fingers (a magnet) straight to contact with `body`, as the solver does
/// before it takes hold, and records the way.
pub(crate) fn touch(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    body: usize,
) -> Attempt<()> {
    let config = motion_config();
    let states = lamp_world::contact_approach(scene, robot, body, &config)
        .map_err(|error| format!("touch: {error}"))?;
    recorder.follow(scene, robot, &states);
    if let Some(last) = states.last() {
        scene.set_configuration(robot, last);
    }
    Ok(())
}

/// Releases what the gripper holds, settled to rest by lamp-world's rule (the one the solver and
/// its replay use), and records the step where the held flag changes.
pub(crate) fn release(scene: &mut Scene, recorder: &mut Recorder, robot: usize) -> Attempt<()> {
    scene
        .release_at_rest(robot)
        .map_err(|error| format!("release: {error}"))?
        .ok_or_else(|| "the gripper holds nothing".to_string())?;
    recorder.record(scene);
    Ok(())
}

/// Noise of a recorded marker about the object's final pose: 1.5 mm along the world's level, 0.5 mm
/// in height (both in the object's frame), 1° about its z. Without it "on the marker" would be as
/// thin as the resting rule's rounding.
const MARKER_POSITION_NOISE: f64 = 0.0015;
const MARKER_HEIGHT_NOISE: f64 = 0.0005;
const MARKER_YAW_NOISE: f64 = std::f64::consts::PI / 180.0;

/// Records a marker of `marker_type` at each placed body's final pose, give or take a marker's
/// noise, in every step: `loc_<body>`. A marker has no geometry, so markers that stood there from
/// the start change nothing the robot did; a demonstration cut before its placement keeps its
/// moved body's marker where the body was heading.
pub(crate) fn mark_placed(
    recording: &mut crate::Recording,
    placed: &[usize],
    marker_type: &str,
    rng: &mut ChaCha8Rng,
) {
    let Some(last) = recording.steps.last() else { return };
    let finals: Vec<(String, Pose)> = placed
        .iter()
        .map(|&body| (recording.header.bodies[body].name.clone(), last.body_poses[body]))
        .collect();
    for (name, at) in finals {
        let noise = marker_noise(rng, MARKER_POSITION_NOISE, MARKER_HEIGHT_NOISE, MARKER_YAW_NOISE);
        add_marker(recording, &format!("loc_{name}"), marker_type, at * noise);
    }
}

/// A marker's offset from the pose it marks: up to `level` along x and y, `height` along z and
/// `yaw` about z, drawn in that order.
pub(crate) fn marker_noise(rng: &mut ChaCha8Rng, level: f64, height: f64, yaw: f64) -> Pose {
    use rand::RngExt;
    let mut draw = |half: f64| rng.random_range(-half..=half);
    let (x, y, z) = (draw(level), draw(level), draw(height));
    pose(x, y, z, 0.0, 0.0, draw(yaw))
}

/// Adds a marker body `name` of `marker_type` standing at `at` in every step of `recording`.
pub(crate) fn add_marker(
    recording: &mut crate::Recording,
    name: &str,
    marker_type: &str,
    at: Pose,
) {
    recording.header.bodies.push(lamp_trajectory::BodyDescription {
        name: name.to_string(),
        type_name: marker_type.to_string(),
    });
    for step in &mut recording.steps {
        step.body_poses.push(at);
    }
}

/// A pose from a translation and roll, pitch, yaw (radians; `Rz(yaw)·Ry(pitch)·Rx(roll)`).
pub(crate) fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Pose {
    Pose::from_parts(Vec3::new(x, y, z).into(), Rotation::from_euler_angles(roll, pitch, yaw))
}

/// The level top of a static surface: its world pose (frame at the centre of the top face) and
/// the half extents of its footprint along the frame's x and y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SurfaceTop {
    pub(crate) pose: Pose,
    pub(crate) half_x: f64,
    pub(crate) half_y: f64,
}

impl SurfaceTop {
    /// The top of a body with these parts (in its frame) at `pose`: the footprint is the
    /// bounding box of every part, the widest of which is the top for a table or a counter.
    pub(crate) fn of_parts(pose: Pose, parts: &[(Pose, lamp_geometry::Shape)]) -> Option<Self> {
        let shape = lamp_geometry::CollisionShape::compound(parts).ok()?;
        let bounds = shape.aabb(&Pose::identity());
        let half_x = bounds.maxs.x.min(-bounds.mins.x);
        let half_y = bounds.maxs.y.min(-bounds.mins.y);
        (half_x > 0.0 && half_y > 0.0).then_some(SurfaceTop { pose, half_x, half_y })
    }

    /// The world point at surface-frame (x, y, z).
    pub(crate) fn point(&self, x: f64, y: f64, z: f64) -> Vec3 {
        (self.pose * lamp_geometry::Point3::new(x, y, z)).coords
    }
}

/// Where a mobile base stands relative to the edge of a surface it faces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Approach {
    /// Distance from the edge to the base's origin, metres.
    pub(crate) standoff: f64,
    /// The base keeps at least this far from the ends of the edge it faces, metres.
    pub(crate) edge_margin: f64,
    /// Added along the edge after aligning with the target point, metres.
    pub(crate) lateral_offset: f64,
    /// Added to the yaw that faces the edge squarely, radians.
    pub(crate) yaw_offset: f64,
}

/// A planar base pose (z = 0) facing the edge of `top` nearest to the surface-frame point
/// (x, y): `standoff` out from that edge, level with the point along the edge (kept
/// `edge_margin` from the edge's ends), looking squarely at the surface — the pose from which an
/// arm on the base reaches the point over the shortest stretch of the top.
pub(crate) fn base_pose_facing(top: &SurfaceTop, x: f64, y: f64, approach: &Approach) -> Pose {
    // (outward normal, half extent along it, half length of the edge, the point's distance in)
    let edges = [
        (Vec3::x(), top.half_x, top.half_y, top.half_x - x),
        (-Vec3::x(), top.half_x, top.half_y, top.half_x + x),
        (Vec3::y(), top.half_y, top.half_x, top.half_y - y),
        (-Vec3::y(), top.half_y, top.half_x, top.half_y + y),
    ];
    let (normal, depth, half_length, _) = edges
        .into_iter()
        .min_by(|a, b| a.3.total_cmp(&b.3))
        .unwrap_or((Vec3::x(), top.half_x, top.half_y, 0.0));
    let along = Vec3::new(-normal.y, normal.x, 0.0);
    let reach = (half_length - approach.edge_margin).max(0.0);
    let lateral = Vec3::new(x, y, 0.0).dot(&along).clamp(-reach, reach) + approach.lateral_offset;
    let local = normal * (depth + approach.standoff) + along * lateral;
    let world = top.pose * lamp_geometry::Point3::from(local);
    let facing = top.pose.rotation * -normal;
    let yaw = facing.y.atan2(facing.x) + approach.yaw_offset;
    pose(world.x, world.y, 0.0, 0.0, 0.0, yaw)
}

/// The yaw of the horizontal direction from `from` to `to`.
pub(crate) fn bearing(from: &Vec3, to: &Vec3) -> f64 {
    (to.y - from.y).atan2(to.x - from.x)
}
