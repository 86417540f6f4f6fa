//! The Keva demonstrator: a free-flying two-finger gripper builds a small part of a plank
//! structure.
//!
//! Layout per attempt: the spec's table (the widest static body of its first problem) and a
//! drop area (the spec's other static type) at a random spot of the table top with a random yaw;
//! a training structure (`planks::draw_training`) anchored on it; its planks but the last
//! already placed at their poses (give or take the placement noise) and settled by the resting
//! rule; the last plank and the spare ones (the spec's `objects` planks in all) lying flat on the
//! table at random, clear of the structure and of each other. Script: the gripper from a random
//! pose above the table to 10 cm above a top grasp of the last plank (fingers across its width),
//! straight down, grab, straight up; a path to 9 cm above the placement (the structure pose give
//! or take the noise, 0.2–0.5 mm above its rest), straight down onto it in one recorded step,
//! release by the resting rule, straight back along the gripper's approach axis, a path to a
//! random pose above the table. A marker of the spec's marker type is recorded at each placed
//! plank's final pose.
//!
//! The one step down is what makes a placement one learned action: the plank enters its resting
//! relations to the planks around it and its marker in the same recorded step, and no recorded
//! pose of the way down lies in a plank–plank region (docs/demonstrations.md).

use std::f64::consts::PI;

use lamp_geometry::{CollisionShape, Pose, Vec3};
use lamp_spec::{Mobility, RobotKind};
use lamp_world::{Body, RESTING_GAP, Recorder, Scene, SpecWorld, trajectory_header as header};
use nalgebra::{Translation3, UnitQuaternion};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::Recording;
use crate::error::DemoError;
use crate::layout::{Scatter, Table, add_at, add_settled, numbered_body};
use crate::planks::{PlankSize, draw_training};
use crate::skills::{
    Attempt, SurfaceTop, accepted_placement, grab, mark_placed, move_to, pose, release,
};

/// The free gripper's joint group: its six mount coordinates.
const GROUP: &str = "all";
/// Where a structure's anchor (the drop area) is drawn: table-top x and y within this of the
/// table's centre, yaw uniform.
const ANCHOR_RANGE: f64 = 0.15;
/// Where loose planks are drawn: table-top x and y within this of the table's centre.
const SPARE_RANGE: f64 = 0.40;
/// A loose plank's centre keeps this far from the anchor: the structure's planks lie within
/// 5 cm of it, and a loose plank keeps the spacing below from each of them.
const SPARE_CLEARANCE: f64 = 0.20;
/// Least distance between two loose planks' centres: beyond √2 times the spec's plank–plank
/// half-range (8.5 cm), so that no loose plank is in any plank–plank region of another.
const SPARE_SPACING: f64 = 0.13;
/// Layout draws before an attempt gives up.
const LAYOUT_DRAWS: usize = 300;
/// The gripper's free poses (start, end): within this of the table's centre, this high above
/// its top, pointing down.
const FREE_RANGE: f64 = 0.30;
const FREE_HEIGHT: (f64, f64) = (0.30, 0.50);
/// Placement noise about a structure pose: along the table top and in yaw (±1 mm, ±1°); a
/// placed plank is let go of 0.2–0.5 mm above its rest, so that where it is let go of and where
/// it settles are in one plank–plank cell (2.3 mm high) as a rule, not in two neighbours of which
/// the upper is visited only by the one step before each release.
const PLACE_NOISE: f64 = 0.001;
const PLACE_YAW_NOISE: f64 = PI / 180.0;
const PLACE_CLEARANCE: (f64, f64) = (0.0002, 0.0005);
/// Placement noise draws before an attempt gives up on a release the resting rule accepts.
const PLACE_DRAWS: usize = 5;
/// Top grasp: the gripper origin this far from the plank's bottom face along its z (the middle
/// of the spec's grab distance, 0.12–0.15 m, and where the YuMi's finger tips stop 1.3 mm above
/// that face), give or take half a millimetre; a little along the plank and in yaw.
const GRASP_DISTANCE: f64 = 0.135;
const GRASP_DISTANCE_NOISE: f64 = 0.0005;
const GRASP_SHIFT_NOISE: f64 = 0.003;
const GRASP_YAW_NOISE: f64 = 0.02;
/// The gripper comes down to a grasp, and leaves a placement, straight over this distance, in
/// steps of at most the recording resolution.
const APPROACH: f64 = 0.10;
const RETREAT: f64 = 0.05;
const STEP: f64 = 0.005;
/// The way down onto a placement: straight, from this far above it, checked for collisions every
/// `DESCENT_STEP` and recorded in one step. It begins beyond the spec's plank–plank range (8.5 cm
/// along a plank, 8.18 cm through it) from every plank the placed one comes to rest by, so that
/// the plank is in no plank–plank region until it is at rest: recorded in small steps, the way
/// down would be a column of cells every placement visits, one region "above" each resting one,
/// and a tall structure holds planks in those columns (a log cabin's plank two storeys up stands
/// in the column above the plank below).
const DESCENT: f64 = 0.09;
const DESCENT_STEP: f64 = 0.0015;

/// What the Keva demonstrator needs from the spec, checked once.
pub(crate) struct Keva<'a> {
    world: &'a SpecWorld,
    robot: String,
    table: (Body, Pose),
    top: SurfaceTop,
    area_type: String,
    plank_type: String,
    size: PlankSize,
    marker_type: String,
    /// Planks per demonstration.
    objects: usize,
}

impl<'a> Keva<'a> {
    pub(crate) fn new(world: &'a SpecWorld, objects: u32) -> Result<Keva<'a>, DemoError> {
        let mismatch = |what: &str| DemoError::SpecMismatch {
            demonstrator: "keva".to_string(),
            what: what.to_string(),
        };
        let spec = world.spec();
        let robot = spec
            .robots
            .iter()
            .find(|robot| robot.kind == RobotKind::FreeFlying)
            .ok_or_else(|| mismatch("a free-flying robot"))?;
        let Table { body: table_body, pose: table_pose, top, type_name: table_type } =
            Table::of(world).ok_or_else(|| mismatch("a table in its first problem"))?;
        let area_type = spec
            .object_types
            .iter()
            .find(|ty| ty.mobility == Mobility::Static && ty.world && ty.name != table_type)
            .ok_or_else(|| mismatch("a static drop-area type besides the table"))?;
        let plank_type = spec
            .object_types
            .iter()
            .find(|ty| ty.mobility == Mobility::Movable)
            .ok_or_else(|| mismatch("a movable plank type"))?;
        let plank = world
            .body("plank1", &plank_type.name)
            .ok_or_else(|| mismatch("a movable plank type"))?;
        let bounds = CollisionShape::compound(&plank.parts)
            .map_err(|_| mismatch("a plank type with a shape"))?
            .aabb(&Pose::identity());
        if bounds.mins.z.abs() > 1e-9 {
            return Err(mismatch("a plank type whose frame is at the centre of its bottom face"));
        }
        let extent = bounds.maxs - bounds.mins;
        let size = PlankSize { length: extent.x, width: extent.y, thickness: extent.z };
        let marker_type = spec
            .object_types
            .iter()
            .find(|ty| ty.mobility == Mobility::Marker)
            .ok_or_else(|| mismatch("a marker type (`type loc { marker }`)"))?;
        Ok(Keva {
            world,
            robot: robot.name.clone(),
            table: (table_body, table_pose),
            top,
            area_type: area_type.name.clone(),
            plank_type: plank_type.name.clone(),
            size,
            marker_type: marker_type.name.clone(),
            objects: objects as usize,
        })
    }

    /// One attempt: a fresh layout and the whole script, or why it failed.
    pub(crate) fn attempt(&self, seed: u64, rng: &mut ChaCha8Rng) -> Attempt<Recording> {
        let training = draw_training(&self.size, self.objects, rng);
        let anchor = self.top.pose
            * pose(
                rng.random_range(-ANCHOR_RANGE..=ANCHOR_RANGE),
                rng.random_range(-ANCHOR_RANGE..=ANCHOR_RANGE),
                0.0,
                0.0,
                0.0,
                rng.random_range(-PI..PI),
            );
        let mut scene = Scene::new();
        scene.add_body(self.table.0.clone(), self.table.1).map_err(|e| e.to_string())?;
        let area = self
            .world
            .body("area1", &self.area_type)
            .ok_or_else(|| format!("no type `{}`", self.area_type))?;
        scene.add_body(area, anchor).map_err(|e| e.to_string())?;
        let placed_count = training.poses.len() - 1;
        let pre_placed: Vec<Pose> = training.poses[..placed_count]
            .iter()
            .map(|local| anchor * self.noise(local, rng, (0.0, 0.0005)))
            .collect();
        let mut placed = add_settled(&mut scene, &pre_placed, |index| self.plank(index))?;
        let spares = self
            .spares()
            .poses(&self.top, &anchor, self.objects - placed_count, rng)
            .ok_or_else(|| "no room on the table for the loose planks".to_string())?;
        let loose = add_at(&mut scene, &spares, |offset| self.plank(placed_count + offset))?;
        let moved = loose[0];
        let start = self.free_pose(rng);
        let q = self
            .world
            .placement_configuration(&self.robot, Some(&start), None)
            .map_err(|e| e.to_string())?;
        let robot =
            self.world.add_robot(&mut scene, &self.robot, q.clone()).map_err(|e| e.to_string())?;
        if !scene.is_valid(robot, &q) {
            return Err(format!("start pose in collision: {:?}", scene.first_contact(robot, &q)));
        }
        let mut recorder = Recorder::default();
        recorder.record(&scene);

        // Pick: a top grasp across the plank's width, from 10 cm above.
        let grasp = scene.body_pose(moved)
            * pose(
                rng.random_range(-GRASP_SHIFT_NOISE..=GRASP_SHIFT_NOISE),
                0.0,
                GRASP_DISTANCE + rng.random_range(-GRASP_DISTANCE_NOISE..=GRASP_DISTANCE_NOISE),
                0.0,
                0.0,
                rng.random_range(-GRASP_YAW_NOISE..=GRASP_YAW_NOISE),
            )
            * top_grasp();
        let above = |target: &Pose, height: f64| Translation3::new(0.0, 0.0, height) * *target;
        let goal = self.configuration(&scene, robot, &above(&grasp, APPROACH))?;
        move_to(&mut scene, &mut recorder, robot, GROUP, &goal, rng)
            .map_err(|e| format!("to the pre-grasp: {e}"))?;
        glide(&mut scene, &mut recorder, robot, &grasp, STEP).map_err(|e| format!("down: {e}"))?;
        grab(&mut scene, &mut recorder, robot, moved)?;
        glide(&mut scene, &mut recorder, robot, &above(&grasp, APPROACH), STEP)
            .map_err(|e| format!("lift: {e}"))?;

        // Place: at the structure pose, give or take the noise, 0.2–0.5 mm above its rest; the
        // resting rule must accept the release there, else fresh noise.
        let local = training.poses[placed_count];
        let place = accepted_placement(
            &scene,
            robot,
            PLACE_DRAWS,
            rng,
            |rng| anchor * self.noise(&local, rng, PLACE_CLEARANCE),
            |scene, gripper, _| self.configuration(scene, robot, gripper),
        )?
        .ok_or_else(|| {
            format!("no placement of the {} plank the resting rule accepts", training.name)
        })?;
        let goal = self.configuration(&scene, robot, &above(&place, DESCENT))?;
        move_to(&mut scene, &mut recorder, robot, GROUP, &goal, rng)
            .map_err(|e| format!("to above the placement: {e}"))?;
        glide_in_one_step(&mut scene, &mut recorder, robot, &place, DESCENT_STEP)
            .map_err(|e| format!("onto the placement: {e}"))?;
        release(&mut scene, &mut recorder, robot)?;
        let retreat_at = recorder.len();

        // Retreat: back along the approach axis, then to a random pose above the table.
        let back = place * Translation3::new(0.0, 0.0, -RETREAT);
        glide(&mut scene, &mut recorder, robot, &back, STEP)
            .map_err(|e| format!("back from the placement: {e}"))?;
        let end = self.free_pose(rng);
        let goal = self.configuration(&scene, robot, &end)?;
        move_to(&mut scene, &mut recorder, robot, GROUP, &goal, rng)
            .map_err(|e| format!("away: {e}"))?;

        placed.push(moved);
        let header = header(self.world.spec(), &scene, seed);
        let mut recording = Recording { header, steps: recorder.steps, retreat_at, scene };
        mark_placed(&mut recording, &placed, &self.marker_type, rng);
        Ok(recording)
    }

    /// Plank number `index` (named `plank<index + 1>`).
    fn plank(&self, index: usize) -> Attempt<Body> {
        numbered_body(self.world, "plank", &self.plank_type, index)
    }

    /// `local`, a pose in the anchor's frame, moved by the placement noise: along the table top,
    /// about the vertical, and up by a height drawn from `lift`.
    fn noise(&self, local: &Pose, rng: &mut ChaCha8Rng, lift: (f64, f64)) -> Pose {
        let height = if lift.1 > lift.0 { rng.random_range(lift.0..=lift.1) } else { lift.0 };
        let shift = Translation3::new(
            rng.random_range(-PLACE_NOISE..=PLACE_NOISE),
            rng.random_range(-PLACE_NOISE..=PLACE_NOISE),
            height,
        );
        let turn = UnitQuaternion::from_axis_angle(
            &Vec3::z_axis(),
            rng.random_range(-PLACE_YAW_NOISE..=PLACE_YAW_NOISE),
        );
        // The turn is about the plank's own vertical line, not the anchor's.
        let mut moved = *local;
        moved.rotation = turn * local.rotation;
        let shift = shift.vector;
        moved.translation.vector += shift;
        moved
    }

    /// Where the loose planks lie: flat on the table at random, clear of the structure and of
    /// each other, 1 mm above the top.
    fn spares(&self) -> Scatter {
        let half = |top_half: f64| SPARE_RANGE.min(top_half - self.size.length / 2.0).max(0.0);
        Scatter {
            half: (half(self.top.half_x), half(self.top.half_y)),
            height: RESTING_GAP,
            clearance: SPARE_CLEARANCE,
            spacing: SPARE_SPACING,
            draws: LAYOUT_DRAWS,
        }
    }

    /// A random gripper pose above the table, pointing down.
    fn free_pose(&self, rng: &mut ChaCha8Rng) -> Pose {
        self.top.pose
            * pose(
                rng.random_range(-FREE_RANGE..FREE_RANGE),
                rng.random_range(-FREE_RANGE..FREE_RANGE),
                rng.random_range(FREE_HEIGHT.0..FREE_HEIGHT.1),
                PI,
                0.0,
                rng.random_range(-PI..PI),
            )
    }

    /// The configuration putting the gripper at `target`, if it is valid in the scene.
    fn configuration(&self, scene: &Scene, robot: usize, target: &Pose) -> Attempt<Vec<f64>> {
        gripper_configuration(scene, robot, target)
    }
}

/// The free gripper's configuration with its gripper (its root link) at `target`, if valid.
fn gripper_configuration(scene: &Scene, robot: usize, target: &Pose) -> Attempt<Vec<f64>> {
    let state = &scene.robots()[robot];
    let mut q = state.configuration().to_vec();
    state.robot().mount().write_coordinates(target, &mut q);
    match scene.first_contact(robot, &q) {
        None => Ok(q),
        Some(contact) => Err(format!("gripper pose in collision: {contact}")),
    }
}

/// Moves the free gripper in a straight line to `target` (position interpolated, rotation
/// slerped) in equal steps of at most `step`, every state checked, recording each.
fn glide(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    target: &Pose,
    step: f64,
) -> Attempt<()> {
    let states = straight_line(scene, robot, target, step)?;
    recorder.follow(scene, robot, &states);
    Ok(())
}

/// [`glide`], but recorded as one step: only the line's end is recorded.
fn glide_in_one_step(
    scene: &mut Scene,
    recorder: &mut Recorder,
    robot: usize,
    target: &Pose,
    step: f64,
) -> Attempt<()> {
    let states = straight_line(scene, robot, target, step)?;
    let ends: Vec<Vec<f64>> = states.first().into_iter().chain(states.last()).cloned().collect();
    recorder.follow(scene, robot, &ends);
    Ok(())
}

/// The free gripper's configurations along a straight line from where it is to `target`, in
/// equal steps of at most `step`, each checked: the current one first.
fn straight_line(scene: &Scene, robot: usize, target: &Pose, step: f64) -> Attempt<Vec<Vec<f64>>> {
    let now = scene.robots()[robot].configuration().to_vec();
    let from = scene.gripper_pose(robot, &now).ok_or_else(|| "no gripper".to_string())?;
    let distance = (target.translation.vector - from.translation.vector).norm();
    // A step within a micrometre of `step` is that step (rounding of the distance).
    let steps = ((distance / step) - 1e-6).ceil().max(1.0) as usize;
    let mut states = vec![now];
    for index in 1..=steps {
        let t = index as f64 / steps as f64;
        let at = from.lerp_slerp(target, t);
        states.push(gripper_configuration(scene, robot, &at)?);
    }
    Ok(states)
}

/// The gripper's frame pointing straight down onto a plank lying flat (its approach axis z along
/// the plank's −z), its fingers (x) across the plank's width (its y).
pub(crate) fn top_grasp() -> Pose {
    pose(0.0, 0.0, 0.0, PI, 0.0, std::f64::consts::FRAC_PI_2)
}
