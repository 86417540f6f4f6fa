//! The Jenga demonstrator: a Fetch arm on a fixed base builds a small part of a tower.
//!
//! Layout per attempt: the spec's table (the widest static body of its first problem); a
//! training structure (`tower::draw_training`) anchored at a random spot of the table top with a
//! random yaw; its blocks but the last already placed at their poses (give or take the placement
//! noise) and settled by the resting rule; the last block and the spare ones (the spec's
//! `objects` blocks in all) lying on the table at random, collision-free, well clear of the
//! structure. Script: an arm path to 10 cm above a top grasp of the last block (fingers across
//! its width), a straight line down, grab, straight up; an arm path to 10 cm above its structure
//! pose (give or take the noise, 1 mm higher), straight down, release by the resting rule,
//! straight up, an arm path to the spec's `tuck`. A marker of the spec's marker type is recorded
//! at each placed block's final pose.

use std::f64::consts::{FRAC_PI_2, PI};

use lamp_geometry::{CollisionShape, Pose};
use lamp_robot::{ARM_GROUP, IkConfig};
use lamp_spec::{Mobility, RobotKind};
use lamp_world::{Body, LinkGoal, RESTING_GAP, Scene, SpecWorld, reach};
use nalgebra::Translation3;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::Recording;
use crate::error::DemoError;
use crate::layout::{Scatter, Table, add_at, add_settled, numbered_body};
use crate::skills::{
    Attempt, SurfaceTop, accepted_placement, grab, mark_placed, move_straight, move_to, pose,
    release,
};
use crate::tower::{BlockSize, draw_training};
use lamp_world::{Recorder, trajectory_header as header};

/// The named configuration the arm starts and ends in (fingers open as the spec gives them).
const TUCK: &str = "tuck";
/// Where a structure's anchor is drawn: table-top x and y within these half ranges of the
/// table's centre, yaw uniform.
const ANCHOR_RANGE: (f64, f64) = (0.08, 0.12);
/// Where spare blocks are drawn: table-top |y| within this (±0.3 m, the reach the spec is
/// checked for), |x| within the table less this margin.
const SPARE_Y: f64 = 0.30;
const SPARE_EDGE_MARGIN: f64 = 0.09;
/// A spare block's centre keeps this far from the anchor: the structure's footprint (a
/// two-block layer, 0.108 m to its corners) plus a spare's half diagonal (0.080 m) plus 3 cm,
/// so that no spare is in any learned block–block region of a structure block.
const SPARE_CLEARANCE: f64 = 0.22;
/// Least distance between two spare blocks' centres (their half diagonals are 8 cm).
const SPARE_SPACING: f64 = 0.17;
/// Layout draws before an attempt gives up.
const LAYOUT_DRAWS: usize = 200;
/// Placement noise about a structure pose: along the top and in yaw (±1.5 mm, ±1°); a placed
/// block is let go of 1 mm above its rest, give or take half a millimetre upwards.
const PLACE_NOISE: f64 = 0.0015;
const PLACE_YAW_NOISE: f64 = PI / 180.0;
const PLACE_CLEARANCE: (f64, f64) = (0.001, 0.0015);
/// Placement noise draws before an attempt gives up on a release the resting rule accepts.
const PLACE_DRAWS: usize = 5;
/// Top grasp: the gripper origin this far above the block's centre, so that the finger tips (3 cm
/// beyond it) stop 3 mm above the block's bottom and never reach the table or the layer below;
/// give or take a millimetre, and a little along the block and in yaw.
const GRASP_HEIGHT: f64 = 0.018;
const GRASP_HEIGHT_NOISE: f64 = 0.001;
const GRASP_SHIFT_NOISE: f64 = 0.003;
const GRASP_YAW_NOISE: f64 = 0.02;
/// The gripper comes down to a grasp and a placement, and leaves them, straight along the
/// vertical over this distance.
const APPROACH: f64 = 0.10;
/// IK tolerances: tight, so that a placed block is let go of within 0.1 mm of its target.
const IK_POSITION_TOLERANCE: f64 = 1e-4;
const IK_ORIENTATION_TOLERANCE: f64 = 1e-3;
const IK_RESTARTS: usize = 60;
const IK_ITERATIONS: usize = 300;

/// What the Jenga demonstrator needs from the spec, checked once.
pub(crate) struct Jenga<'a> {
    world: &'a SpecWorld,
    robot: String,
    table: (Body, Pose),
    top: SurfaceTop,
    block_type: String,
    size: BlockSize,
    marker_type: String,
    /// Blocks per demonstration.
    objects: usize,
    /// The arm in `tuck`, fingers as the spec gives them.
    tucked: Vec<f64>,
}

impl<'a> Jenga<'a> {
    pub(crate) fn new(world: &'a SpecWorld, objects: u32) -> Result<Jenga<'a>, DemoError> {
        let mismatch = |what: &str| DemoError::SpecMismatch {
            demonstrator: "jenga".to_string(),
            what: what.to_string(),
        };
        let spec = world.spec();
        let robot = spec
            .robots
            .iter()
            .find(|robot| robot.kind == RobotKind::FixedArm)
            .ok_or_else(|| mismatch("a fixed-arm robot"))?;
        let Table { body: table_body, pose: table_pose, top, .. } =
            Table::of(world).ok_or_else(|| mismatch("a table in its first problem"))?;
        let block_type = spec
            .object_types
            .iter()
            .find(|ty| ty.mobility == Mobility::Movable)
            .ok_or_else(|| mismatch("a movable block type"))?;
        let block = world
            .body("block1", &block_type.name)
            .ok_or_else(|| mismatch("a movable block type"))?;
        let bounds = CollisionShape::compound(&block.parts)
            .map_err(|_| mismatch("a block type with a shape"))?
            .aabb(&Pose::identity());
        let extent = bounds.maxs - bounds.mins;
        let size = BlockSize { length: extent.x, width: extent.y, height: extent.z };
        let marker_type = spec
            .object_types
            .iter()
            .find(|ty| ty.mobility == Mobility::Marker)
            .ok_or_else(|| mismatch("a marker type (`type loc { marker }`)"))?;
        let tucked = world
            .placement_configuration(&robot.name, None, Some(TUCK))
            .map_err(|_| mismatch("a `tuck` configuration"))?;
        Ok(Jenga {
            world,
            robot: robot.name.clone(),
            table: (table_body, table_pose),
            top,
            block_type: block_type.name.clone(),
            size,
            marker_type: marker_type.name.clone(),
            objects: objects as usize,
            tucked,
        })
    }

    /// One attempt: a fresh layout and the whole script, or why it failed.
    pub(crate) fn attempt(&self, seed: u64, rng: &mut ChaCha8Rng) -> Attempt<Recording> {
        let training = draw_training(&self.size, self.objects, rng);
        let anchor = self.top.pose
            * pose(
                rng.random_range(-ANCHOR_RANGE.0..=ANCHOR_RANGE.0),
                rng.random_range(-ANCHOR_RANGE.1..=ANCHOR_RANGE.1),
                0.0,
                0.0,
                0.0,
                rng.random_range(-PI..PI),
            );
        let mut scene = Scene::new();
        scene.add_body(self.table.0.clone(), self.table.1).map_err(|e| e.to_string())?;
        let placed_count = training.poses.len() - 1;
        let pre_placed: Vec<Pose> = training.poses[..placed_count]
            .iter()
            .map(|local| anchor * *local * self.noise(rng, (0.0, 0.0005)))
            .collect();
        let mut placed = add_settled(&mut scene, &pre_placed, |index| self.block(index))?;
        let spares = self
            .spares()
            .poses(&self.top, &anchor, self.objects - placed_count, rng)
            .ok_or_else(|| "no room on the table for the spare blocks".to_string())?;
        let loose = add_at(&mut scene, &spares, |offset| self.block(placed_count + offset))?;
        let moved = loose[0];
        let robot = self
            .world
            .add_robot(&mut scene, &self.robot, self.tucked.clone())
            .map_err(|e| e.to_string())?;
        if !scene.is_valid(robot, &self.tucked) {
            return Err(format!(
                "`tuck` in collision: {:?}",
                scene.first_contact(robot, &self.tucked)
            ));
        }
        let mut recorder = Recorder::default();
        recorder.record(&scene);

        // Pick: a top grasp across the block's width.
        let block_pose = scene.body_pose(moved);
        let grasp = block_pose
            * pose(
                rng.random_range(-GRASP_SHIFT_NOISE..=GRASP_SHIFT_NOISE),
                0.0,
                GRASP_HEIGHT + rng.random_range(-GRASP_HEIGHT_NOISE..=GRASP_HEIGHT_NOISE),
                0.0,
                0.0,
                rng.random_range(-GRASP_YAW_NOISE..=GRASP_YAW_NOISE),
            )
            * top_down();
        let above = |target: &Pose| Translation3::new(0.0, 0.0, APPROACH) * *target;
        let pre_q = self
            .reach(&scene, robot, &above(&grasp), rng)
            .map_err(|e| format!("pre-grasp: {e}"))?;
        move_to(&mut scene, &mut recorder, robot, ARM_GROUP, &pre_q, rng)
            .map_err(|e| format!("to the pre-grasp: {e}"))?;
        move_straight(&mut scene, &mut recorder, robot, ARM_GROUP, &grasp, &ik_config())
            .map_err(|e| format!("down to the grasp: {e}"))?;
        grab(&mut scene, &mut recorder, robot, moved)?;
        move_straight(&mut scene, &mut recorder, robot, ARM_GROUP, &above(&grasp), &ik_config())
            .map_err(|e| format!("lift: {e}"))?;

        // Place: at the structure pose, give or take the noise, 1 mm up; the resting rule must
        // accept the release there, else fresh noise.
        let local = training.poses[placed_count];
        let place = accepted_placement(
            &scene,
            robot,
            PLACE_DRAWS,
            rng,
            |rng| anchor * local * self.noise(rng, PLACE_CLEARANCE),
            |scene, gripper, rng| self.reach(scene, robot, gripper, rng),
        )?
        .ok_or_else(|| {
            format!("no placement of the {} block the resting rule accepts", training.name)
        })?;
        let pre_q = self
            .reach(&scene, robot, &above(&place), rng)
            .map_err(|e| format!("pre-place: {e}"))?;
        move_to(&mut scene, &mut recorder, robot, ARM_GROUP, &pre_q, rng)
            .map_err(|e| format!("to the pre-place: {e}"))?;
        move_straight(&mut scene, &mut recorder, robot, ARM_GROUP, &place, &ik_config())
            .map_err(|e| format!("down to the placement: {e}"))?;
        release(&mut scene, &mut recorder, robot)?;
        let retreat_at = recorder.len();

        // Retreat: straight up, then the arm to `tuck`.
        let now = scene.robots()[robot].configuration().to_vec();
        let gripper = scene.gripper_pose(robot, &now).ok_or_else(|| "no gripper".to_string())?;
        move_straight(&mut scene, &mut recorder, robot, ARM_GROUP, &above(&gripper), &ik_config())
            .map_err(|e| format!("up from the placement: {e}"))?;
        move_to(&mut scene, &mut recorder, robot, ARM_GROUP, &self.tucked, rng)
            .map_err(|e| format!("tuck: {e}"))?;

        placed.push(moved);
        let header = header(self.world.spec(), &scene, seed);
        let mut recording = Recording { header, steps: recorder.steps, retreat_at, scene };
        mark_placed(&mut recording, &placed, &self.marker_type, rng);
        Ok(recording)
    }

    /// Block number `index` (named `block<index + 1>`).
    fn block(&self, index: usize) -> Attempt<Body> {
        numbered_body(self.world, "block", &self.block_type, index)
    }

    /// Placement noise: along the top, in yaw, and a height drawn from `lift`.
    fn noise(&self, rng: &mut ChaCha8Rng, lift: (f64, f64)) -> Pose {
        let height = if lift.1 > lift.0 { rng.random_range(lift.0..=lift.1) } else { lift.0 };
        pose(
            rng.random_range(-PLACE_NOISE..=PLACE_NOISE),
            rng.random_range(-PLACE_NOISE..=PLACE_NOISE),
            height,
            0.0,
            0.0,
            rng.random_range(-PLACE_YAW_NOISE..=PLACE_YAW_NOISE),
        )
    }

    /// Where the spare blocks lie: flat on the table at random, clear of the structure and of
    /// each other, 1 mm above the top.
    fn spares(&self) -> Scatter {
        Scatter {
            half: (
                (self.top.half_x - SPARE_EDGE_MARGIN).max(0.0),
                SPARE_Y.min(self.top.half_y - SPARE_EDGE_MARGIN).max(0.0),
            ),
            height: RESTING_GAP + self.size.height / 2.0,
            clearance: SPARE_CLEARANCE,
            spacing: SPARE_SPACING,
            draws: LAYOUT_DRAWS,
        }
    }

    /// A collision-free arm configuration putting the gripper at `target`, searched from `tuck`.
    fn reach(
        &self,
        scene: &Scene,
        robot: usize,
        target: &Pose,
        rng: &mut ChaCha8Rng,
    ) -> Attempt<Vec<f64>> {
        reach(
            scene,
            &LinkGoal { robot, group: ARM_GROUP, link: None, target, start: &self.tucked },
            &ik_config(),
            rng,
        )
        .map_err(|error| format!("inverse kinematics: {error}"))
    }
}

/// The gripper's frame pointing straight down (its approach axis x along the object's −z), its
/// fingers (y) along the object's y: a top grasp across a block's width.
pub(crate) fn top_down() -> Pose {
    pose(0.0, 0.0, 0.0, 0.0, FRAC_PI_2, 0.0)
}

/// The demonstrator's IK settings: tight tolerances, and more restarts than the default.
pub(crate) fn ik_config() -> IkConfig {
    let mut config = IkConfig::new();
    config.position_tolerance = IK_POSITION_TOLERANCE;
    config.orientation_tolerance = IK_ORIENTATION_TOLERANCE;
    config.restarts = IK_RESTARTS;
    config.max_iterations = IK_ITERATIONS;
    config
}
