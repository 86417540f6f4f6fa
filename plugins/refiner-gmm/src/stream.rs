//! The candidate stream of one action: staying put first (grasp changes alone may realise the
//! effects), then region samples turned into link targets by the host's IK, each kept only if the
//! action's effects hold in the learned abstraction of the resulting state.

use std::collections::BTreeSet;
use std::sync::Arc;

use lamp_abstraction::{GroundAtom, Pose, SamplerArtifact};
use lamp_plugin_api::{
    Candidate, CandidateStream, GroundedAction, HostServices, ObjectPose, PluginError, RobotTarget,
};
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::RefinerOptions;
use crate::realise::{Anchor, Mover, Realisation};
use crate::world_view::{Hypothesis, WorldView, link_pose, to_wire};

/// One action's stream.
pub(crate) struct GmmStream {
    pub(crate) artifact: Arc<SamplerArtifact>,
    pub(crate) options: RefinerOptions,
    pub(crate) view: WorldView,
    pub(crate) realisation: Realisation,
    /// What the action changes: a candidate is one whose state has these.
    pub(crate) effects: Effects,
    pub(crate) rng: ChaCha8Rng,
    pub(crate) stayed: bool,
    pub(crate) yielded: usize,
    pub(crate) draws: usize,
    /// Placements found but not yet yielded, best first.
    pub(crate) pool: std::collections::VecDeque<(Candidate, Pose)>,
    /// The mean position of the sampled region's mixture (one region per stream), once known.
    pub(crate) centre: Option<Vector3<f64>>,
    /// The components of the sampled region's mixture drawn first ([`near_components`]) and the
    /// others, once known; `None` inside for the whole mixture.
    pub(crate) ways: Option<Option<[Vec<usize>; 2]>>,
    /// Candidates yielded from region draws (a placement pool counts as one).
    pub(crate) sampled: usize,
}

/// Valid placements gathered before the best is yielded, when an object is put into a region
/// other objects may share.
const PLACEMENT_POOL: usize = 16;

/// How far a yielded placement may slide outward along each axis of the region's frame (5 cm),
/// and the halvings that find how far it can (to within 5 cm / 2⁶ ≈ 0.8 mm).
const SNUG_REACH: f64 = 0.05;
const SNUG_STEPS: usize = 6;
/// What a slid placement leaves between the object and what it was slid against (4 mm): a
/// placement within a millimetre of a wall is one the motion planner must thread the held
/// object into, and a sampling planner rarely finds so narrow a passage (two of the twelve
/// Packing problems lost 0.2–0.5 s to arm paths not found). The Packing box has 2 cm to spare
/// per axis for two cans.
const SNUG_CLEARANCE: f64 = 0.004;

/// How much farther than `displacement` the last draw of a stream may move a link to leave a
/// region: [`widened_displacement`].
const DISPLACEMENT_WIDENING: f64 = 4.0;

/// The longest random displacement of draw `draw` (1-based) of a stream: `displacement` for
/// the first quarter of its draws, then growing in proportion to the draws made, to
/// [`DISPLACEMENT_WIDENING`] times `displacement` at the last.
///
/// A link deep inside a region cannot leave it by a short move: a base standing half a metre
/// inside its learned region before a marker (0.45 m deep in Dinner) is never out of it after
/// a move of at most 0.25 m, and the stream that should drive it away runs dry. Chronological
/// backtracking then retries the steps in between (the arm's tuck, the release), which cannot
/// move the base, until the plan's budget is spent. A stream whose first draws succeed is
/// unchanged.
fn widened_displacement(options: &RefinerOptions, draw: usize) -> f64 {
    let share = draw as f64 / options.draws.max(1) as f64;
    options.displacement * (DISPLACEMENT_WIDENING * share).max(1.0)
}

/// How far a held object may lean, from lying level on one of its faces, when it is let go of:
/// the world's resting rule seats an object leaning up to 5° on its base and refuses one leaning
/// more (`MAX_SETTLE_TILT`, `docs/world.md`).
const SEATED_TILT: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// `pose`, when it leans more than [`SEATED_TILT`], turned about its origin so that the body axis
/// nearest to vertical is vertical; a pose leaning less is kept, for the resting rule to seat
/// when the object is let go of. The position and the turn about the vertical are kept.
///
/// A region's mixture is fitted to poses drawn uniformly from its rotation cells, and a cell is
/// as wide across every rotation component as the demonstrations' spread along one needs: a can
/// set down upright at any yaw gets seven bins of 51°, so the mixture leans its draws by up to
/// 26°, a tilt no demonstration showed and no release accepts. Such a can, put into a box,
/// touches the floor with its rim: in a box that holds four cans with 2 cm to spare, about one
/// draw in a hundred stood upright, and the last can's few places were never drawn upright.
fn level(pose: &Pose) -> Pose {
    let rotation = pose.rotation.to_rotation_matrix();
    let Some(nearest) = rotation
        .matrix()
        .column_iter()
        .map(|axis| axis.into_owned())
        .max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))
    else {
        return *pose;
    };
    if nearest.z.abs() >= SEATED_TILT.cos() {
        return *pose;
    }
    let vertical = Vector3::new(0.0, 0.0, nearest.z.signum());
    let turn = UnitQuaternion::rotation_between(&nearest, &vertical)
        .unwrap_or_else(UnitQuaternion::identity);
    Pose::from_parts(pose.translation, turn * pose.rotation)
}

/// How much more a group of a region's components must be turned from the moving frame than the
/// group nearer to it for the two to be separate ways into the region (a quarter turn):
/// [`near_components`].
const SEPARATE_TURNS: f64 = std::f64::consts::FRAC_PI_2;

/// The components of a region's mixture to draw first, given `turns`, the angle from the moving
/// frame's current orientation (relative to the region's primary) to each component's mean
/// ([`lamp_abstraction::RegionModel::component_turns`]): with the components in order of their
/// turn, those before the first step of more than [`SEPARATE_TURNS`] from one to the next; `None`
/// when there is no such step (the whole mixture is drawn, as always).
///
/// A region learned from demonstrations that reach it in two ways a half turn apart (an object
/// grasped from either side, the same body by its symmetry) is one region of two components. Of
/// a draw from the far one, the link's target is half a turn of the wrist away, and the arm
/// either cannot unwind it on the way on (a grasp taken with the wrist wound to its limit) or
/// cannot turn around what it holds or has just let go of; the near one asks for neither.
/// Components spread over every orientation (an object put down at any yaw) or differing in
/// position alone (a wide region tiled by several) leave no such step: they are one way in, and
/// the mixture's weights alone choose among them.
fn near_components(turns: &[f64]) -> Option<Vec<usize>> {
    let mut order: Vec<usize> = (0..turns.len()).collect();
    order.sort_by(|&a, &b| turns[a].total_cmp(&turns[b]).then(a.cmp(&b)));
    let step =
        order.windows(2).position(|pair| turns[pair[1]] - turns[pair[0]] > SEPARATE_TURNS)?;
    let mut near = order[..=step].to_vec();
    near.sort_unstable();
    Some(near)
}

/// Which way into a region draw `draw` (1-based) of a stream comes from, with `sampled`
/// candidates drawn so far, for a region of `ways` (the near components and the others,
/// [`near_components`]): the near way for the first candidate and each second one after it, the
/// far way for the others, so that a near way that leads nowhere later in the plan (a grasp
/// from which the plank cannot be put where it goes) is followed by the far one when the solver
/// backtracks; `None` (the whole mixture) after the first quarter of the stream's draws, so
/// that a way no draw reaches does not hold the stream.
fn way<'a>(
    options: &RefinerOptions,
    draw: usize,
    sampled: usize,
    ways: &'a [Vec<usize>; 2],
) -> Option<&'a [usize]> {
    (4 * draw <= options.draws.max(1)).then(|| ways[sampled % 2].as_slice())
}

/// An action's ground effects, in the learner's atoms.
pub(crate) struct Effects {
    adds: BTreeSet<GroundAtom>,
    deletes: BTreeSet<GroundAtom>,
}

impl Effects {
    pub(crate) fn of(action: &GroundedAction) -> Effects {
        let convert = |atoms: &[lamp_plugin_api::GroundAtom]| {
            atoms
                .iter()
                .map(|atom| GroundAtom {
                    predicate: atom.predicate.clone(),
                    arguments: atom.arguments.clone(),
                })
                .collect()
        };
        Effects { adds: convert(&action.add_effects), deletes: convert(&action.delete_effects) }
    }

    /// Every add true and every delete false in `state`, in the learned abstraction. What else
    /// changes is the TAMP loop's to judge: it knows the rest of the plan.
    fn hold_in(
        &self,
        view: &WorldView,
        artifact: &SamplerArtifact,
        state: &Hypothesis,
        host: &dyn HostServices,
    ) -> Result<bool, PluginError> {
        view.effects_hold(artifact, state, host, &self.adds, &self.deletes)
    }
}

impl CandidateStream for GmmStream {
    fn next(&mut self, host: &dyn HostServices) -> Result<Option<Candidate>, PluginError> {
        if self.yielded >= self.options.samples {
            return Ok(None);
        }
        if !self.stayed {
            self.stayed = true;
            let configurations = self.view.current.configurations.clone();
            if let Some(candidate) = self.try_state(configurations, host)? {
                self.yielded += 1;
                return Ok(Some(candidate));
            }
        }
        let Some(mover) = self.realisation.mover.clone() else { return Ok(None) };
        let placing =
            matches!(mover.anchor, Anchor::HeldSecondary { .. } | Anchor::HeldPrimary { .. })
                && mover.region.is_some();
        // A region that holds several objects (no clear relation: a box, a table top) is packed
        // from its edges, each object snug; one that holds one at a time (an object on its
        // marker) is filled at its most typical pose, its centre.
        let shared = mover
            .region
            .is_some_and(|(pair, region)| !self.artifact.pairs[pair].regions[region].clear);
        if placing && self.pool.is_empty() {
            self.fill_pool(&mover, shared, host)?;
            self.sampled += 1;
        }
        if placing {
            let Some((candidate, relative)) = self.pool.pop_front() else { return Ok(None) };
            self.yielded += 1;
            if !shared {
                return Ok(Some(candidate));
            }
            let snug = self.snug(&mover, relative, host)?;
            return Ok(Some(snug.unwrap_or(candidate)));
        }
        while self.draws < self.options.draws {
            if let Some((candidate, _, _)) = self.draw(&mover, host)? {
                self.yielded += 1;
                self.sampled += 1;
                return Ok(Some(candidate));
            }
        }
        Ok(None)
    }
}

impl GmmStream {
    /// One draw: a target, IK, and the check of the state it leads to. Returns the candidate and
    /// the drawn relative pose's distance from the region's centre.
    fn draw(
        &mut self,
        mover: &Mover,
        host: &dyn HostServices,
    ) -> Result<Option<(Candidate, f64, Pose)>, PluginError> {
        if host.is_cancelled() {
            return Err(PluginError::Cancelled);
        }
        self.draws += 1;
        let (target, spread, relative) = self.target(mover, host)?;
        Ok(self.candidate_at(mover, &target, host)?.map(|candidate| (candidate, spread, relative)))
    }

    /// The candidate that moves the link to `target`, if IK reaches it and the state is one.
    fn candidate_at(
        &self,
        mover: &Mover,
        target: &Pose,
        host: &dyn HostServices,
    ) -> Result<Option<Candidate>, PluginError> {
        let seed = self.view.current.configurations.get(&mover.robot).cloned().unwrap_or_default();
        let Some(q) = host.solve_ik(&mover.robot, &mover.link, &to_wire(target), &seed)? else {
            return Ok(None);
        };
        let mut configurations = self.view.current.configurations.clone();
        configurations.insert(mover.robot.clone(), q);
        self.try_state(configurations, host)
    }

    /// Slides a placement outward along the primary's x and then y axis, away from the
    /// region's centre, as far as it stays a candidate (in the region, reachable, free), less
    /// [`SNUG_CLEARANCE`]: snug against what bounds it, a wall, an object placed before, or the
    /// region's edge.
    ///
    /// Edge-first ordering alone leaves each object a few millimetres short of the corner it
    /// heads for, and in a box that holds four cans with 2 cm to spare those millimetres decide
    /// whether the fourth still fits. A placement pushed until it would touch leaves the most
    /// room on the other side, as a person packing a box pushes each item into its corner.
    /// `None` when no slid placement is a candidate (the draw as it was is used).
    fn snug(
        &mut self,
        mover: &Mover,
        relative: Pose,
        host: &dyn HostServices,
    ) -> Result<Option<Candidate>, PluginError> {
        let Anchor::HeldSecondary { primary, grasp } = &mover.anchor else { return Ok(None) };
        let Some(centre) = self.centre else { return Ok(None) };
        let primary_pose = self.view.pose_in(&self.view.current, primary, host)?;
        let mut relative = relative;
        let mut best = None;
        for axis in 0..2 {
            let sign = (relative.translation.vector[axis] - centre[axis]).signum();
            let at = |d: f64| {
                let mut moved = relative;
                moved.translation.vector[axis] += sign * d;
                moved
            };
            let (mut inside, mut outside) = (0.0, SNUG_REACH);
            for _ in 0..SNUG_STEPS {
                let middle = 0.5 * (inside + outside);
                let target = primary_pose * at(middle) * grasp.inverse();
                match self.candidate_at(mover, &target, host)? {
                    Some(candidate) => {
                        inside = middle;
                        best = Some(candidate);
                    }
                    None => outside = middle,
                }
            }
            if inside > 0.0 {
                let backed = (inside - SNUG_CLEARANCE).max(0.0);
                let target = primary_pose * at(backed) * grasp.inverse();
                if let Some(candidate) = self.candidate_at(mover, &target, host)? {
                    inside = backed;
                    best = Some(candidate);
                }
            }
            relative = at(inside);
        }
        Ok(best)
    }

    /// Gathers up to [`PLACEMENT_POOL`] valid placements and orders them: into a shared region,
    /// edge first (farthest from the region's centre first), so that objects put into it (cans
    /// into a box) leave room for the next ones, as a person packing a box starts in the
    /// corners, each slid snug ([`Self::snug`]) when it is yielded; into a region that holds one
    /// object at a time, centre first.
    fn fill_pool(
        &mut self,
        mover: &Mover,
        edge_first: bool,
        host: &dyn HostServices,
    ) -> Result<(), PluginError> {
        let mut found = Vec::new();
        while found.len() < PLACEMENT_POOL && self.draws < self.options.draws {
            if let Some(placement) = self.draw(mover, host)? {
                found.push(placement);
            }
        }
        // Stable: equal distances keep their draw order.
        if edge_first {
            found.sort_by(|a, b| b.1.total_cmp(&a.1));
        } else {
            found.sort_by(|a, b| a.1.total_cmp(&b.1));
        }
        self.pool =
            found.into_iter().map(|(candidate, _, relative)| (candidate, relative)).collect();
        Ok(())
    }

    /// A world pose for the moving link: from a region sample, or a random displacement.
    fn target(
        &mut self,
        mover: &Mover,
        host: &dyn HostServices,
    ) -> Result<(Pose, f64, Pose), PluginError> {
        let current = &self.view.current;
        let Some((pair, region)) = mover.region else {
            let here = link_pose(current, &mover.robot, &mover.link, host)?;
            let direction = loop {
                let v = Vector3::new(
                    self.rng.random_range(-1.0..=1.0),
                    self.rng.random_range(-1.0..=1.0),
                    self.rng.random_range(-1.0..=1.0),
                );
                let norm: f64 = v.norm();
                if norm > 1e-3 && norm <= 1.0 {
                    break v / norm;
                }
            };
            let reach = widened_displacement(&self.options, self.draws);
            let distance = self.rng.random_range(0.0..=reach);
            return Ok((Translation3::from(direction * distance) * here, 0.0, Pose::identity()));
        };
        if self.ways.is_none() {
            let turns = self.artifact.pairs[pair].regions[region]
                .model
                .component_turns(&self.current_relative(mover, host)?);
            self.ways = Some(near_components(&turns).map(|near| {
                let far = (0..turns.len()).filter(|component| !near.contains(component)).collect();
                [near, far]
            }));
        }
        let model = &self.artifact.pairs[pair].regions[region].model;
        let ways = self.ways.as_ref().and_then(Option::as_ref);
        let relative =
            match ways.and_then(|ways| way(&self.options, self.draws, self.sampled, ways)) {
                Some(among) => model.sample_among(among, &mut self.rng),
                None => model.sample(&mut self.rng),
            };
        let centre = *self.centre.get_or_insert_with(|| {
            let mixture = model.mixture();
            mixture
                .weights()
                .iter()
                .zip(mixture.means())
                .fold(Vector3::zeros(), |sum, (w, mean)| {
                    sum + *w * Vector3::new(mean[0], mean[1], mean[2])
                })
        });
        let spread = (relative.translation.vector - centre).norm();
        // A held object is put where it is to be let go of, leaning no more than a release
        // accepts ([`level`]).
        let (target, relative) = match &mover.anchor {
            Anchor::PrimaryLink { secondary } => {
                (self.view.pose_in(current, secondary, host)? * relative.inverse(), relative)
            }
            Anchor::HeldSecondary { primary, grasp } => {
                let primary = self.view.pose_in(current, primary, host)?;
                let held = level(&(primary * relative));
                (held * grasp.inverse(), primary.inv_mul(&held))
            }
            Anchor::SecondaryLink { primary } => {
                (self.view.pose_in(current, primary, host)? * relative, relative)
            }
            Anchor::HeldPrimary { secondary, grasp } => {
                let secondary = self.view.pose_in(current, secondary, host)?;
                let held = level(&(secondary * relative.inverse()));
                (held * grasp.inverse(), held.inv_mul(&secondary))
            }
        };
        Ok((target, spread, relative))
    }

    /// Where the sampled pair's secondary is now in its primary's frame, one of them the moving
    /// link or the object it holds.
    fn current_relative(
        &self,
        mover: &Mover,
        host: &dyn HostServices,
    ) -> Result<Pose, PluginError> {
        let current = &self.view.current;
        let link = link_pose(current, &mover.robot, &mover.link, host)?;
        Ok(match &mover.anchor {
            Anchor::PrimaryLink { secondary } => {
                link.inv_mul(&self.view.pose_in(current, secondary, host)?)
            }
            Anchor::HeldSecondary { primary, grasp } => {
                self.view.pose_in(current, primary, host)?.inv_mul(&(link * grasp))
            }
            Anchor::SecondaryLink { primary } => {
                self.view.pose_in(current, primary, host)?.inv_mul(&link)
            }
            Anchor::HeldPrimary { secondary, grasp } => {
                (link * grasp).inv_mul(&self.view.pose_in(current, secondary, host)?)
            }
        })
    }

    /// The candidate reaching `configurations`, if the action's effects hold in the state it
    /// leads to.
    fn try_state(
        &self,
        configurations: std::collections::BTreeMap<String, Vec<f64>>,
        host: &dyn HostServices,
    ) -> Result<Option<Candidate>, PluginError> {
        let current = &self.view.current;
        let mut after = Hypothesis {
            configurations: current.configurations.clone(),
            held: current.held.clone(),
            placed: current.placed.clone(),
        };
        for change in &self.realisation.releases {
            let pose = self.view.pose_in(current, &change.object, host)?;
            after.held.remove(&change.object);
            after.placed.insert(change.object.clone(), pose);
        }
        after.configurations = configurations;
        for change in &self.realisation.grabs {
            let object = self.view.pose_in(&after, &change.object, host)?;
            let link = link_pose(&after, &change.robot, &change.link, host)?;
            after.held.insert(
                change.object.clone(),
                (change.robot.clone(), change.link.clone(), link.inv_mul(&object)),
            );
        }
        if !self.effects.hold_in(&self.view, &self.artifact, &after, host)? {
            return Ok(None);
        }
        let mut targets = Vec::new();
        for (robot, q) in &after.configurations {
            if current.configurations.get(robot) != Some(q) {
                if !host.configuration_is_valid(robot, q)? {
                    return Ok(None);
                }
                targets.push(RobotTarget { robot: robot.clone(), configuration: q.clone() });
            }
        }
        let mut object_poses = Vec::new();
        for object in after.held.keys().chain(after.placed.keys()) {
            let pose = self.view.pose_in(&after, object, host)?;
            object_poses.push(ObjectPose { object: object.clone(), pose: to_wire(&pose) });
        }
        object_poses.sort_by(|a, b| a.object.cmp(&b.object));
        Ok(Some(Candidate {
            targets,
            object_poses,
            releases: self.realisation.releases.clone(),
            grabs: self.realisation.grabs.clone(),
        }))
    }
}

#[cfg(test)]
mod tests {
    use lamp_plugin_api::{
        HostError, IDENTITY_POSE, ObjectState, RefineRequest, Refiner, RobotPart, RobotState,
        WorldState,
    };
    use nalgebra::UnitQuaternion;

    use super::*;
    use crate::GmmRefiner;
    use crate::world_view::to_pose;

    /// A free-flying hand whose configuration is its world pose (x, y, z, qx, qy, qz, qw): IK
    /// reaches every target and every configuration is valid.
    struct FreeHand;

    impl HostServices for FreeHand {
        fn configuration_is_valid(&self, _robot: &str, _q: &[f64]) -> Result<bool, HostError> {
            Ok(true)
        }

        fn solve_ik(
            &self,
            _robot: &str,
            _link: &str,
            target: &[f64; 7],
            _seed_q: &[f64],
        ) -> Result<Option<Vec<f64>>, HostError> {
            Ok(Some(target.to_vec()))
        }

        fn forward_kinematics(
            &self,
            _robot: &str,
            q: &[f64],
            _link: &str,
        ) -> Result<[f64; 7], HostError> {
            Ok(q.try_into().expect("a pose"))
        }
    }

    /// A gripper–block region of two narrow components, the block 10 cm below the gripper, one
    /// with the gripper turned half a turn about the vertical from the other (the block's
    /// frame's x axis along the gripper's, or against it), weighted `weights`.
    fn grasp_artifact(weights: [f64; 2]) -> SamplerArtifact {
        let sigma: f64 = 0.002;
        let covariance: Vec<f64> =
            (0..81).map(|index| if index % 10 == 0 { sigma * sigma } else { 0.0 }).collect();
        let along = [0.0, 0.0, -0.1, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
        let against = [0.0, 0.0, -0.1, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0];
        let json = format!(
            r#"{{"version": {}, "seed": 1, "pairs": [{{"primary": "gripper", "secondary": "block", "regions": [{{"relation": "gripper_block_1", "g": 0, "clear": false, "nowhere": true, "model": {{"g": 0, "mixture": {{"dimension": 9, "weights": {weights:?}, "means": [{along:?}, {against:?}], "covariances": [{covariance:?}, {covariance:?}]}}, "threshold": -100.0, "extent": [[-1.0, 1.0], [-1.0, 1.0], [-1.0, 1.0]]}}}}]}}]}}"#,
            lamp_abstraction::SAMPLER_ARTIFACT_VERSION,
        );
        let artifact: SamplerArtifact = serde_json::from_str(&json).unwrap();
        artifact.validate().unwrap();
        artifact
    }

    /// The yaws (of the block in the gripper's frame) of the candidates a stream yields for
    /// moving the hand into the region, from 40 cm above the block, turned `yaw` about the
    /// vertical.
    fn yielded_yaws(artifact: SamplerArtifact, options: RefinerOptions, yaw: f64) -> Vec<f64> {
        let turn = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw);
        let q = turn.quaternion();
        let start = vec![0.0, 0.0, 0.5, q.i, q.j, q.k, q.w];
        let world = WorldState {
            robots: vec![RobotState {
                name: "hand".into(),
                configuration: start,
                held: Vec::new(),
                parts: vec![RobotPart {
                    object: "hand_gripper".into(),
                    object_type: "gripper".into(),
                    link: "palm".into(),
                    gripper: true,
                }],
            }],
            objects: vec![ObjectState {
                name: "b1".into(),
                object_type: "block".into(),
                pose: IDENTITY_POSE,
            }],
        };
        let atom = lamp_plugin_api::GroundAtom {
            predicate: "gripper_block_1".into(),
            arguments: vec!["hand_gripper".into(), "b1".into()],
        };
        let action = GroundedAction {
            name: "approach".into(),
            arguments: vec!["hand_gripper".into(), "b1".into()],
            preconditions: Vec::new(),
            negative_preconditions: Vec::new(),
            add_effects: vec![atom],
            delete_effects: Vec::new(),
        };
        let mut refiner = GmmRefiner::new(artifact, options).unwrap();
        let mut stream =
            refiner.refine(&RefineRequest { action, world, seed: 7 }, &FreeHand).unwrap();
        let mut yaws = Vec::new();
        while let Some(candidate) = stream.next(&FreeHand).unwrap() {
            let wire: [f64; 7] = candidate.targets[0].configuration.clone().try_into().unwrap();
            let relative = to_pose(&wire).unwrap().inverse();
            yaws.push(relative.rotation.euler_angles().2);
        }
        yaws
    }

    /// Whether `yaw` is within 0.1 rad of a half turn.
    fn half_turned(yaw: f64) -> bool {
        yaw.abs() > std::f64::consts::PI - 0.1
    }

    /// Of a region reached in two ways a half turn apart, the first candidate comes from the way
    /// nearest the hand's current orientation, whichever that is and however the mixture weighs
    /// the two, then the far way and the near one by turns; after the first quarter of a
    /// stream's draws, from the whole mixture.
    #[test]
    fn a_region_is_drawn_first_from_the_component_nearest_the_moving_frame() {
        let options = RefinerOptions { samples: 4, draws: 2000, displacement: 0.25 };
        let by_turns = |yaws: &[f64], near: fn(f64) -> bool| {
            yaws.len() == 4 && yaws.iter().enumerate().all(|(k, &yaw)| near(yaw) == (k % 2 == 0))
        };
        for weights in [[0.5, 0.5], [0.9, 0.1], [0.1, 0.9]] {
            // The hand turned 0.3 rad: the block lies along it (yaw −0.3 in its frame).
            let yaws = yielded_yaws(grasp_artifact(weights), options, 0.3);
            assert!(by_turns(&yaws, |yaw| yaw.abs() < 0.1), "{weights:?}: {yaws:?}");
            // The hand turned 0.3 rad short of a half turn: the block lies against it.
            let yaws = yielded_yaws(grasp_artifact(weights), options, std::f64::consts::PI - 0.3);
            assert!(by_turns(&yaws, half_turned), "{weights:?}: {yaws:?}");
        }
        // With four draws, the first alone is from the near component; the other three come from
        // the whole mixture, here weighted 1 : 9 against the near one.
        let few = RefinerOptions { samples: 4, draws: 4, displacement: 0.25 };
        let yaws = yielded_yaws(grasp_artifact([0.1, 0.9]), few, 0.3);
        assert_eq!(yaws.len(), 4);
        assert!(yaws[0].abs() < 0.1, "{yaws:?}");
        assert!(yaws[1..].iter().filter(|&&yaw| half_turned(yaw)).count() >= 2, "{yaws:?}");
    }

    /// The components drawn first: those before the first step of more than a quarter turn, in
    /// order of their turn from the moving frame; none singled out without such a step.
    #[test]
    fn near_components_are_those_turned_least_from_the_moving_frame() {
        assert_eq!(near_components(&[3.0, 0.2]), Some(vec![1]));
        assert_eq!(near_components(&[2.9, 0.1, 0.5]), Some(vec![1, 2]));
        assert_eq!(near_components(&[0.1, 1.6]), None);
        // Five components around the vertical (an object put down at any yaw): one way in.
        assert_eq!(near_components(&[0.45, 2.93, 0.7, 1.64, 1.99]), None);
        assert_eq!(near_components(&[1.0]), None);
    }

    /// A pose leaning more than a release accepts is turned upright about its origin, keeping its
    /// position and its turn about the vertical; one leaning less is kept as it is.
    #[test]
    fn a_held_object_is_put_down_leaning_no_more_than_a_release_accepts() {
        let yaw = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.7);
        let at = |lean: f64| {
            let tilt = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), lean);
            Pose::from_parts(Translation3::new(0.1, -0.2, 0.3), yaw * tilt)
        };
        let leaning = at(20f64.to_radians());
        let levelled = level(&leaning);
        assert_eq!(levelled.translation, leaning.translation);
        assert!((levelled.rotation.angle_to(&yaw)) < 1e-12, "{levelled:?}");
        let slightly = at(3f64.to_radians());
        assert_eq!(level(&slightly), slightly);
        // Lying on its side: the body axis nearest to vertical is y.
        let side = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 80f64.to_radians());
        let lying = level(&Pose::from_parts(Translation3::identity(), yaw * side));
        assert!((lying.rotation * Vector3::y()).z.abs() > 1.0 - 1e-12, "{lying:?}");
    }

    /// The first quarter of a stream's draws move a link at most `displacement`; later ones
    /// farther, up to four times as far at the last draw.
    #[test]
    fn random_displacements_widen_as_a_stream_draws_on() {
        let options = RefinerOptions { samples: 4, draws: 300, displacement: 0.25 };
        assert_eq!(widened_displacement(&options, 1), 0.25);
        assert_eq!(widened_displacement(&options, 75), 0.25);
        assert!((widened_displacement(&options, 150) - 0.5).abs() < 1e-12);
        assert!((widened_displacement(&options, 300) - 1.0).abs() < 1e-12);
    }
}
