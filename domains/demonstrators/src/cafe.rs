//! The Café demonstrator: a Fetch-like mobile manipulator carries one can from one surface (a
//! table or the counter) to another.
//!
//! Layout per attempt: the furniture of the spec's first café problem (`cafe2_01`: floor, four
//! tables, the counter), the same in every demonstration; a start and a different goal surface
//! drawn from all surfaces; the can upright at a random x, y on the start surface's top (clear of
//! its edges), random yaw, 1 mm above the top; the robot at a random collision-free base pose in
//! the room, arm tucked, fingers open. Script: base path to a pose facing the start surface's
//! edge nearest the can; arm path to a pre-grasp 10 cm back from the grasp, then a straight
//! approach to a side grasp at the can's mid-height; grab; arm path to the spec's `tuck`
//! configuration; base path to a pose facing the goal surface's edge nearest a random placement
//! spot; arm path to the placement (can upright, 1 mm above the top); release; a straight
//! retreat; arm path to `tuck`; base path to a random pose. Base motions keep the arm in `tuck`,
//! empty-handed or holding (one resting configuration, as in the reference set-up, so that
//! "the arm is at rest" is one learned relation and every drive needs it); arm motions keep the
//! base still; arm and base paths are planned with RRT-Connect on one joint group.
//!
//! The grasp approaches from the one of the can's four sides (its frame's ±x, ±y) that faces the
//! robot best, give or take a little yaw: the can's yaw is random, so the can's pose in the
//! gripper's frame falls in four narrow rotation clusters instead of being spread over every yaw,
//! which would leave no rotation cell visited often enough to be critical (as in the reference
//! set-up, whose grasps are the can's frame turned by multiples of 90°).

use std::f64::consts::{FRAC_PI_2, PI};

use lamp_geometry::{CollisionShape, Pose, Vec3};
use lamp_robot::{ARM_GROUP, BASE_GROUP, GRIPPER_GROUP, IkConfig, wrap_angle};
use lamp_spec::{Mobility, RobotKind};
use lamp_world::{Body, LinkGoal, Scene, SpecWorld, reach};
use nalgebra::Translation3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::Recording;
use crate::error::DemoError;
use crate::skills::{
    Approach, Attempt, SurfaceTop, add_marker, base_pose_facing, bearing, grab, marker_noise,
    move_straight, move_to, pose, release,
};
use lamp_world::{Recorder, trajectory_header as header};

/// The problem whose furniture every demonstration uses (else the spec's first problem).
const FURNITURE_PROBLEM: &str = "cafe2_01";
/// The names of the recorded markers: where the object starts and where it is put.
const START_MARKER: &str = "start";
const TARGET_MARKER: &str = "target";
/// Noise of a recorded marker about where the object came to rest, as a motion-capture marker
/// or one put down by hand has: 2 mm along the top, 1 mm in height. A marker lies flat on its
/// top: no tilt, as the objects stand upright (the learned rotation cells of an upright object
/// are flat, and a tilt of a quarter degree leaves them). Without noise, "on the marker" would
/// be as thin as the demonstrator's IK error in height, and an object exactly on its marker
/// could fall outside it.
///
/// A marker's yaw is drawn at random: the objects this demonstrator carries are round (it grasps
/// them from the side as cylinders), so a marker says where one stands, not which way it faces.
/// Recorded at the object's own yaw, "on the marker" would also mean "turned as the marker",
/// and a glass picked up from one side of the counter could then only be set down from that
/// same side of the room: most of the arm's placements at a table the robot faces from another
/// side would be refused, and a goal's yaw tolerance would have no say.
const MARKER_POSITION_NOISE: f64 = 0.002;
const MARKER_HEIGHT_NOISE: f64 = 0.001;
/// The named configuration the arm rests in while the base moves, empty-handed or holding.
const TUCK: &str = "tuck";
/// Height of a resting can's origin above its support.
const REST: f64 = 0.001;
/// Least distance between the can's side and the edges of the surface it starts or ends on.
const EDGE_CLEARANCE: f64 = 0.05;
/// Range of the base origin's distance from the edge it faces: within arm reach of the middle
/// of a table, and clear of the counter's front.
const STANDOFF: (f64, f64) = (0.42, 0.50);
/// The base stays this far from the ends of the edge it faces (it aligns with the can inside).
const EDGE_MARGIN: f64 = 0.30;
/// Noise on the base's position along the edge and on its yaw.
const LATERAL_NOISE: f64 = 0.05;
const BASE_YAW_NOISE: f64 = 0.15;
/// The can's axis is this far beyond the gripper origin along the approach, give or take the
/// noise: the palm (3.5 cm behind the origin) clears the can's 4.5 cm radius by 1 cm or so.
const GRASP_DEPTH: f64 = 0.02;
const GRASP_DEPTH_NOISE: f64 = 0.003;
/// Noise on the grasp's yaw about the can's axis, and on the placement's approach yaw.
const GRASP_YAW_NOISE: f64 = 0.05;
const PLACE_YAW_NOISE: f64 = 0.15;
/// The gripper comes to a grasp, and leaves a placement, in a straight line along its approach
/// axis over this distance: with the fingers straddling the can, any other way is a narrow
/// passage.
const BACK_OFF: f64 = 0.10;
/// When pulling straight back would fold the arm into the torso, the fingers leave the can
/// upwards instead (they slide along its sides, clear of its top): this far up, in the world,
/// and this far back along the approach axis.
const LIFT_OFF: (f64, f64) = (0.12, 0.04);
/// Random base poses (start, end) lie within the furniture's footprint grown by this much.
const ROOM_PADDING: f64 = 1.0;
/// Draws of a random base pose before an attempt gives up on finding a free one.
const POSE_DRAWS: usize = 200;
/// IK tolerances: tight, so that a placed can rests 1 mm above the top to within 0.2 mm.
const IK_POSITION_TOLERANCE: f64 = 1e-4;
const IK_ORIENTATION_TOLERANCE: f64 = 1e-3;
/// Restarts and iterations per IK call: the counter top is high, and its poses sit where few
/// restarts converge without the elbow touching the head.
const IK_RESTARTS: usize = 100;
const IK_ITERATIONS: usize = 300;

/// What the Café demonstrator needs from the spec, checked once.
pub(crate) struct Cafe<'a> {
    world: &'a SpecWorld,
    robot: String,
    /// The furniture: every static body of the furniture problem, with its pose.
    furniture: Vec<(Body, Pose)>,
    /// The tops of the furniture that takes part in relations (tables, the counter), by name.
    surfaces: Vec<(String, SurfaceTop)>,
    /// The objects a demonstration may carry, one type each: every movable type of the spec.
    carried: Vec<Carried>,
    /// The spec's marker type, if any: markers of it are recorded where the object starts and
    /// where it is put.
    marker_type: Option<String>,
    /// The robot at the origin, arm tucked, fingers open.
    tucked: Vec<f64>,
    /// The coordinates of the arm group (torso and arm joints).
    arm: Vec<usize>,
    /// Where random base poses are drawn: (x min, x max, y min, y max).
    room: (f64, f64, f64, f64),
}

impl<'a> Cafe<'a> {
    pub(crate) fn new(world: &'a SpecWorld) -> Result<Cafe<'a>, DemoError> {
        let mismatch = |what: &str| DemoError::SpecMismatch {
            demonstrator: "cafe".to_string(),
            what: what.to_string(),
        };
        let spec = world.spec();
        let robot = spec
            .robots
            .iter()
            .find(|robot| robot.kind == RobotKind::MobileArm)
            .ok_or_else(|| mismatch("a mobile-arm robot"))?;
        let model = world.robots.get(&robot.name).ok_or_else(|| mismatch("a loaded robot"))?;
        let problem = spec
            .problems
            .iter()
            .find(|problem| problem.name == FURNITURE_PROBLEM)
            .or(spec.problems.first())
            .ok_or_else(|| mismatch("a problem whose scene has the furniture"))?;
        let mut furniture = Vec::new();
        let mut surfaces = Vec::new();
        let mut bounds: Option<lamp_geometry::Aabb> = None;
        for object in &problem.scene.objects {
            let Some(body) = world.body(&object.name, &object.type_name) else {
                return Err(mismatch(&format!("an object type `{}`", object.type_name)));
            };
            if body.movable {
                continue;
            }
            if !body.world {
                let top = SurfaceTop::of_parts(object.pose, &body.parts)
                    .ok_or_else(|| mismatch(&format!("a top on `{}`", object.name)))?;
                let footprint = CollisionShape::compound(&body.parts)
                    .map_err(|_| mismatch(&format!("shapes for `{}`", object.name)))?
                    .aabb(&object.pose);
                bounds = Some(bounds.map_or(footprint, |b| b.union(&footprint)));
                surfaces.push((object.name.clone(), top));
            }
            furniture.push((body, object.pose));
        }
        let bounds = bounds.ok_or_else(|| mismatch("at least two surfaces"))?;
        if surfaces.len() < 2 {
            return Err(mismatch("at least two surfaces"));
        }
        let mut carried = Vec::new();
        for object_type in spec.object_types.iter().filter(|ty| ty.mobility == Mobility::Movable) {
            let name = format!("{}1", object_type.name);
            let body = world
                .body(&name, &object_type.name)
                .ok_or_else(|| mismatch("a movable object type"))?;
            let bounds = CollisionShape::compound(&body.parts)
                .map_err(|_| mismatch("a movable type with shapes"))?
                .aabb(&Pose::identity());
            carried.push(Carried {
                radius: bounds.maxs.x.max(bounds.maxs.y),
                middle: 0.5 * (bounds.mins.z + bounds.maxs.z),
                body,
            });
        }
        if carried.is_empty() {
            return Err(mismatch("a movable object type"));
        }
        let marker_type = spec
            .object_types
            .iter()
            .find(|ty| ty.mobility == Mobility::Marker)
            .map(|ty| ty.name.clone());
        let named = |name: &str| {
            world
                .placement_configuration(&robot.name, None, Some(name))
                .map_err(|_| mismatch(&format!("a `{name}` configuration")))
        };
        let mut tucked = named(TUCK)?;
        let group = |name: &str| {
            model
                .group(name)
                .map(|group| group.coordinates.clone())
                .ok_or_else(|| mismatch(&format!("a `{name}` joint group")))
        };
        // Fingers fully open, so that they clear the can's sides on the way in and out.
        for index in group(GRIPPER_GROUP)? {
            let upper = model.coordinates()[index].upper;
            if upper.is_finite() {
                tucked[index] = upper;
            }
        }
        group(BASE_GROUP)?;
        Ok(Cafe {
            world,
            robot: robot.name.clone(),
            furniture,
            surfaces,
            carried,
            marker_type,
            tucked,
            arm: group(ARM_GROUP)?,
            room: (
                bounds.mins.x - ROOM_PADDING,
                bounds.maxs.x + ROOM_PADDING,
                bounds.mins.y - ROOM_PADDING,
                bounds.maxs.y + ROOM_PADDING,
            ),
        })
    }

    /// One attempt: a fresh layout and the whole script, or why it failed.
    pub(crate) fn attempt(&self, seed: u64, rng: &mut ChaCha8Rng) -> Attempt<Recording> {
        let start = rng.random_range(0..self.surfaces.len());
        let mut goal = rng.random_range(0..self.surfaces.len() - 1);
        if goal >= start {
            goal += 1;
        }
        let ((from_name, from), (to_name, to)) = (&self.surfaces[start], &self.surfaces[goal]);
        // Drawn only when there is a choice, so that one movable type keeps the stream as it was.
        let object = match self.carried.len() {
            1 => &self.carried[0],
            count => &self.carried[rng.random_range(0..count)],
        };
        let mut recording = self
            .carry_between(object, from, to, seed, rng)
            .map_err(|reason| format!("from `{from_name}` to `{to_name}`: {reason}"))?;
        if let Some(marker_type) = &self.marker_type {
            mark_start_and_target(&mut recording, object, marker_type, rng);
        }
        Ok(recording)
    }

    /// The whole script for a can carried from the top `from` to the top `to`.
    fn carry_between(
        &self,
        object: &Carried,
        from: &SurfaceTop,
        to: &SurfaceTop,
        seed: u64,
        rng: &mut ChaCha8Rng,
    ) -> Attempt<Recording> {
        let mut scene = Scene::new();
        for (body, body_pose) in &self.furniture {
            scene.add_body(body.clone(), *body_pose).map_err(|e| e.to_string())?;
        }
        let (u, v) = self.spot(object, from, rng);
        let can_pose = upright(from.point(u, v, REST), rng.random_range(-PI..PI));
        let can = scene.add_body(object.body.clone(), can_pose).map_err(|e| e.to_string())?;
        let robot = self
            .world
            .add_robot(&mut scene, &self.robot, self.tucked.clone())
            .map_err(|e| e.to_string())?;
        let q = self.free_base(&scene, robot, rng)?;
        scene.set_configuration(robot, &q);
        let mut recorder = Recorder::default();
        recorder.record(&scene);

        // To the start surface, then a side grasp at mid-height from the can's side that faces
        // the robot best.
        let base = base_pose_facing(from, u, v, &self.approach(rng));
        self.drive(&mut scene, &mut recorder, robot, &base, rng)
            .map_err(|e| format!("to the start surface: {e}"))?;
        let facing = bearing(&base.translation.vector, &can_pose.translation.vector);
        let can_yaw = yaw_of(&can_pose);
        let side = (wrap_angle(facing - can_yaw) / FRAC_PI_2).round() * FRAC_PI_2;
        let grasp_yaw = side + rng.random_range(-GRASP_YAW_NOISE..=GRASP_YAW_NOISE);
        let depth = GRASP_DEPTH + rng.random_range(-GRASP_DEPTH_NOISE..=GRASP_DEPTH_NOISE);
        let grasp = can_pose
            * pose(0.0, 0.0, object.middle, 0.0, 0.0, grasp_yaw)
            * pose(-depth, 0.0, 0.0, 0.0, 0.0, 0.0);
        let back = pose(-BACK_OFF, 0.0, 0.0, 0.0, 0.0, 0.0);
        let tucked = self.at_rest(&scene, robot, &self.tucked);
        let pre_q = self
            .reach(&scene, robot, &(grasp * back), &tucked, rng)
            .map_err(|e| format!("pre-grasp: {e}"))?;
        move_to(&mut scene, &mut recorder, robot, ARM_GROUP, &pre_q, rng)
            .map_err(|e| format!("to the pre-grasp: {e}"))?;
        move_straight(&mut scene, &mut recorder, robot, ARM_GROUP, &grasp, &ik_config())
            .map_err(|e| format!("approach: {e}"))?;
        grab(&mut scene, &mut recorder, robot, can)?;
        self.rest_arm(&mut scene, &mut recorder, robot, &self.tucked, rng)
            .map_err(|e| format!("tuck holding: {e}"))?;

        // To the goal surface, then the can upright on its top, approached from the base.
        let (u, v) = self.spot(object, to, rng);
        let base = base_pose_facing(to, u, v, &self.approach(rng));
        self.drive(&mut scene, &mut recorder, robot, &base, rng)
            .map_err(|e| format!("to the goal surface: {e}"))?;
        let held = scene.held(robot).ok_or_else(|| "the grab did not hold".to_string())?;
        let spot = to.point(u, v, REST);
        let approach_yaw = bearing(&base.translation.vector, &spot)
            + rng.random_range(-PLACE_YAW_NOISE..=PLACE_YAW_NOISE);
        let carried = pose(0.0, 0.0, 0.0, 0.0, 0.0, approach_yaw) * held.grasp;
        let target = upright(spot, yaw_of(&carried));
        let tucked = self.at_rest(&scene, robot, &self.tucked);
        let goal_q = self
            .reach(&scene, robot, &(target * held.grasp.inverse()), &tucked, rng)
            .map_err(|e| format!("placement: {e}"))?;
        move_to(&mut scene, &mut recorder, robot, ARM_GROUP, &goal_q, rng)
            .map_err(|e| format!("place: {e}"))?;
        release(&mut scene, &mut recorder, robot)?;
        let retreat_at = recorder.len();

        // Retreat: back the open fingers off the can along the approach (or up, where that
        // folds the arm into the torso), tuck, then drive to a random pose.
        let now = scene.robots()[robot].configuration().to_vec();
        let gripper = scene.gripper_pose(robot, &now).ok_or_else(|| "no gripper".to_string())?;
        let lift = Translation3::new(0.0, 0.0, LIFT_OFF.0)
            * gripper
            * pose(-LIFT_OFF.1, 0.0, 0.0, 0.0, 0.0, 0.0);
        move_straight(&mut scene, &mut recorder, robot, ARM_GROUP, &(gripper * back), &ik_config())
            .or_else(|_| {
                move_straight(&mut scene, &mut recorder, robot, ARM_GROUP, &lift, &ik_config())
            })
            .map_err(|e| format!("back off: {e}"))?;
        self.rest_arm(&mut scene, &mut recorder, robot, &self.tucked, rng)
            .map_err(|e| format!("tuck: {e}"))?;
        let q = self.free_base(&scene, robot, rng)?;
        move_to(&mut scene, &mut recorder, robot, BASE_GROUP, &q, rng)
            .map_err(|e| format!("leave: {e}"))?;

        let header = header(self.world.spec(), &scene, seed);
        Ok(Recording { header, steps: recorder.steps, retreat_at, scene })
    }

    /// A random spot (surface-frame x, y) on `top` where the object stands clear of the edges.
    fn spot(&self, object: &Carried, top: &SurfaceTop, rng: &mut ChaCha8Rng) -> (f64, f64) {
        let clearance = object.radius + EDGE_CLEARANCE;
        let draw = |half: f64, rng: &mut ChaCha8Rng| {
            let range = (half - clearance).max(0.0);
            if range > 0.0 { rng.random_range(-range..=range) } else { 0.0 }
        };
        let x = draw(top.half_x, rng);
        (x, draw(top.half_y, rng))
    }

    /// A random way of standing in front of a surface.
    fn approach(&self, rng: &mut ChaCha8Rng) -> Approach {
        Approach {
            standoff: rng.random_range(STANDOFF.0..=STANDOFF.1),
            edge_margin: EDGE_MARGIN,
            lateral_offset: rng.random_range(-LATERAL_NOISE..=LATERAL_NOISE),
            yaw_offset: rng.random_range(-BASE_YAW_NOISE..=BASE_YAW_NOISE),
        }
    }

    /// The robot's configuration now with the base moved to `base` (arm unchanged).
    fn at_base(&self, scene: &Scene, robot: usize, base: &Pose) -> Vec<f64> {
        let state = &scene.robots()[robot];
        let mut q = state.configuration().to_vec();
        state.robot().mount().write_coordinates(base, &mut q);
        q
    }

    /// A random collision-free base pose in the room, the arm as it is now.
    fn free_base(&self, scene: &Scene, robot: usize, rng: &mut ChaCha8Rng) -> Attempt<Vec<f64>> {
        let (x_min, x_max, y_min, y_max) = self.room;
        (0..POSE_DRAWS)
            .map(|_| {
                let x = rng.random_range(x_min..x_max);
                let y = rng.random_range(y_min..y_max);
                let yaw = rng.random_range(-PI..PI);
                self.at_base(scene, robot, &pose(x, y, 0.0, 0.0, 0.0, yaw))
            })
            .find(|q| scene.is_valid(robot, q))
            .ok_or_else(|| "no free base pose in the room".to_string())
    }

    /// Drives the base to `base` along a planned path, the arm as it is.
    fn drive(
        &self,
        scene: &mut Scene,
        recorder: &mut Recorder,
        robot: usize,
        base: &Pose,
        rng: &mut ChaCha8Rng,
    ) -> Attempt<()> {
        let q = self.at_base(scene, robot, base);
        move_to(scene, recorder, robot, BASE_GROUP, &q, rng)
    }

    /// Moves the arm to the arm coordinates of `rest`, the base still.
    fn rest_arm(
        &self,
        scene: &mut Scene,
        recorder: &mut Recorder,
        robot: usize,
        rest: &[f64],
        rng: &mut ChaCha8Rng,
    ) -> Attempt<()> {
        let q = self.at_rest(scene, robot, rest);
        move_to(scene, recorder, robot, ARM_GROUP, &q, rng)
    }

    /// The robot's configuration now with the arm coordinates of `rest`.
    fn at_rest(&self, scene: &Scene, robot: usize, rest: &[f64]) -> Vec<f64> {
        let mut q = scene.robots()[robot].configuration().to_vec();
        for &index in &self.arm {
            q[index] = rest[index];
        }
        q
    }

    /// A collision-free arm configuration (base still) putting the gripper at `target`, searched
    /// from `seed` first.
    fn reach(
        &self,
        scene: &Scene,
        robot: usize,
        target: &Pose,
        seed: &[f64],
        rng: &mut ChaCha8Rng,
    ) -> Attempt<Vec<f64>> {
        reach(
            scene,
            &LinkGoal { robot, group: ARM_GROUP, link: None, target, start: seed },
            &ik_config(),
            rng,
        )
        .map_err(|error| format!("inverse kinematics: {error}"))
    }
}

/// An object a demonstration may carry: its body, its radius and the height of its middle.
struct Carried {
    body: Body,
    radius: f64,
    middle: f64,
}

/// Records two markers in every step, give or take a marker's noise: `start` where the object
/// stood at the first step and `target` where it came to rest (as the paper's Dinner set-up
/// marks each object's initial and target locations). A marker has no geometry, so markers
/// that stood there from the start would have changed nothing the robot did. A demonstration
/// cut before its placement keeps the target too: where the robot was heading.
fn mark_start_and_target(
    recording: &mut Recording,
    object: &Carried,
    marker_type: &str,
    rng: &mut ChaCha8Rng,
) {
    let bodies = &recording.header.bodies;
    let Some(index) = bodies.iter().position(|body| body.name == object.body.name) else { return };
    let (Some(first), Some(last)) = (recording.steps.first(), recording.steps.last()) else {
        return;
    };
    let (start, placed) = (first.body_poses[index], last.body_poses[index]);
    for (name, at) in [(START_MARKER, start), (TARGET_MARKER, placed)] {
        // Round objects: a marker at any yaw, so that "on the marker" does not mean "turned as".
        let noise = marker_noise(rng, MARKER_POSITION_NOISE, MARKER_HEIGHT_NOISE, PI);
        add_marker(recording, name, marker_type, at * noise);
    }
}

/// The demonstrator's IK settings: tight tolerances, and more restarts than the default, for
/// the poses at the edge of the arm's reach over the counter.
fn ik_config() -> IkConfig {
    let mut config = IkConfig::new();
    config.position_tolerance = IK_POSITION_TOLERANCE;
    config.orientation_tolerance = IK_ORIENTATION_TOLERANCE;
    config.restarts = IK_RESTARTS;
    config.max_iterations = IK_ITERATIONS;
    config
}

/// An upright pose at `position` turned by `yaw` about the vertical.
fn upright(position: Vec3, yaw: f64) -> Pose {
    pose(position.x, position.y, position.z, 0.0, 0.0, yaw)
}

/// The yaw of a pose's x axis in the horizontal plane.
fn yaw_of(pose: &Pose) -> f64 {
    let x_axis = pose.rotation * Vec3::x();
    x_axis.y.atan2(x_axis.x)
}
