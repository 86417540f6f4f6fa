//! Refiners: a grounded action and the world state in, a resumable stream of candidate target
//! configurations out. The stream is how the runtime backtracks: when a later step fails, it asks
//! the same stream for its next candidate.

use serde::{Deserialize, Serialize};

use crate::error::PluginError;
use crate::host::{HostServices, Pose};

/// A ground atom, for example `(on_can_table_1 can3 table1)`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct GroundAtom {
    /// The predicate's name.
    pub predicate: String,
    /// Its objects, in order.
    pub arguments: Vec<String>,
}

/// A ground action of a plan, with the atoms that define what it must achieve.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct GroundedAction {
    /// The action's name as in the domain.
    pub name: String,
    /// The objects bound to its parameters, in parameter order.
    pub arguments: Vec<String>,
    /// Ground preconditions.
    pub preconditions: Vec<GroundAtom>,
    /// Ground atoms that must be false before it. Absent from documents written before the field
    /// existed, which had none.
    #[serde(default)]
    pub negative_preconditions: Vec<GroundAtom>,
    /// Ground add effects: what must hold after the action.
    pub add_effects: Vec<GroundAtom>,
    /// Ground delete effects.
    pub delete_effects: Vec<GroundAtom>,
}

/// An object the robot holds, rigidly attached to one of its links.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeldObject {
    /// The object's name.
    pub object: String,
    /// The link holding it.
    pub link: String,
    /// The object's pose in the link's frame.
    pub grasp: Pose,
}

/// A robot link that takes part in learned relations, named as the PDDL problem names it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RobotPart {
    /// The object name of the part in the PDDL problem, for example `fetch_gripper`.
    pub object: String,
    /// The part's type in the PDDL domain, for example `gripper`.
    pub object_type: String,
    /// The robot link it is.
    pub link: String,
    /// Whether the part can hold objects.
    pub gripper: bool,
}

/// A robot in the world state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotState {
    /// The robot's name, as the host's oracles know it.
    pub name: String,
    /// Its current configuration (host layout).
    pub configuration: Vec<f64>,
    /// What it holds.
    pub held: Vec<HeldObject>,
    /// Its links that take part in relations (added without a wire version change: older
    /// documents read as having none).
    #[serde(default)]
    pub parts: Vec<RobotPart>,
}

/// An object in the world state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObjectState {
    /// The object's name, as in the PDDL problem.
    pub name: String,
    /// Its type, as in the PDDL domain.
    pub object_type: String,
    /// Its world pose.
    pub pose: Pose,
}

/// The world as a refiner sees it: robots and objects, sorted by name.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WorldState {
    /// The robots.
    pub robots: Vec<RobotState>,
    /// The objects.
    pub objects: Vec<ObjectState>,
}

impl WorldState {
    /// The robot named `name`.
    #[must_use]
    pub fn robot(&self, name: &str) -> Option<&RobotState> {
        self.robots.iter().find(|robot| robot.name == name)
    }

    /// The object named `name`.
    #[must_use]
    pub fn object(&self, name: &str) -> Option<&ObjectState> {
        self.objects.iter().find(|object| object.name == name)
    }
}

/// What a refiner is asked.
#[derive(Clone, Debug, PartialEq)]
pub struct RefineRequest {
    /// The action to refine.
    pub action: GroundedAction,
    /// The world before the action.
    pub world: WorldState,
    /// Seed for the stream's own `ChaCha8Rng`.
    pub seed: u64,
}

/// A configuration a robot should reach.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotTarget {
    /// The robot's name.
    pub robot: String,
    /// The target configuration (host layout).
    pub configuration: Vec<f64>,
}

/// The world pose an object has after the action.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObjectPose {
    /// The object's name.
    pub object: String,
    /// Its world pose.
    pub pose: Pose,
}

/// A gripper taking hold of an object or letting go of it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct GraspChange {
    /// The robot.
    pub robot: String,
    /// The gripper link.
    pub link: String,
    /// The object.
    pub object: String,
}

/// One way to carry out an action: let go of `releases` where the robot stands, move each robot
/// to its target, then take hold of `grabs` where the robot arrived.
///
/// `releases` and `grabs` were added without a wire version change: older documents read as
/// having none.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Where each moving robot must go.
    pub targets: Vec<RobotTarget>,
    /// Objects the action moves, with their poses afterwards.
    pub object_poses: Vec<ObjectPose>,
    /// Objects let go of before moving.
    #[serde(default)]
    pub releases: Vec<GraspChange>,
    /// Objects taken hold of after moving.
    #[serde(default)]
    pub grabs: Vec<GraspChange>,
}

/// A resumable stream of candidates for one action. Each call to [`next`](Self::next) continues
/// where the previous one stopped, so the runtime can come back for another sample after a
/// failure further down the plan.
pub trait CandidateStream: Send {
    /// The next candidate, or `None` when the stream is exhausted.
    ///
    /// # Errors
    /// [`PluginError`] when sampling failed (not when it merely found nothing more).
    fn next(&mut self, host: &dyn HostServices) -> Result<Option<Candidate>, PluginError>;
}

/// A refiner: opens one candidate stream per action to refine.
///
/// # Example
/// A refiner for a robot on a rail: `(goto ?robot ?marker)` is refined by configurations near
/// the marker object's x position, nearest first, keeping only those the host says are valid.
/// ```
/// use lamp_plugin_api::{
///     Candidate, CandidateStream, GroundedAction, HostError, HostServices, ObjectState,
///     PluginError, RefineRequest, Refiner, RobotTarget, WorldState, IDENTITY_POSE,
/// };
///
/// struct RailRefiner;
///
/// struct Offsets {
///     robot: String,
///     center: f64,
///     next_index: usize,
/// }
///
/// const OFFSETS: [f64; 3] = [0.0, 0.5, -0.5];
///
/// impl CandidateStream for Offsets {
///     fn next(&mut self, host: &dyn HostServices) -> Result<Option<Candidate>, PluginError> {
///         while let Some(offset) = OFFSETS.get(self.next_index) {
///             self.next_index += 1;
///             let configuration = vec![self.center + offset];
///             if host.configuration_is_valid(&self.robot, &configuration)? {
///                 let targets = vec![RobotTarget { robot: self.robot.clone(), configuration }];
///                 return Ok(Some(Candidate { targets, ..Candidate::default() }));
///             }
///         }
///         Ok(None)
///     }
/// }
///
/// impl Refiner for RailRefiner {
///     fn refine(
///         &mut self,
///         request: &RefineRequest,
///         _host: &dyn HostServices,
///     ) -> Result<Box<dyn CandidateStream>, PluginError> {
///         let [robot, marker] = request.action.arguments.as_slice() else {
///             return Err(PluginError::invalid_request("goto takes a robot and a marker"));
///         };
///         let marker = request
///             .world
///             .object(marker)
///             .ok_or_else(|| PluginError::invalid_request(format!("no object {marker}")))?;
///         let center = marker.pose[0];
///         Ok(Box::new(Offsets { robot: robot.clone(), center, next_index: 0 }))
///     }
/// }
///
/// struct Rail; // valid below x = 3.2
/// impl HostServices for Rail {
///     fn configuration_is_valid(&self, _: &str, q: &[f64]) -> Result<bool, HostError> {
///         Ok(q[0] < 3.2)
///     }
/// }
///
/// let marker = ObjectState { name: "m".into(), object_type: "marker".into(), pose: IDENTITY_POSE };
/// let mut world = WorldState { robots: Vec::new(), objects: vec![marker] };
/// world.objects[0].pose[0] = 3.0;
/// let action = GroundedAction {
///     name: "goto".into(),
///     arguments: vec!["cart".into(), "m".into()],
///     preconditions: Vec::new(),
///     negative_preconditions: Vec::new(),
///     add_effects: Vec::new(),
///     delete_effects: Vec::new(),
/// };
/// let request = RefineRequest { action, world, seed: 7 };
/// let mut stream = RailRefiner.refine(&request, &Rail).unwrap();
/// let first = stream.next(&Rail).unwrap().unwrap();
/// assert_eq!(first.targets[0].configuration, vec![3.0]);
/// // Backtracking: the next candidate skips 3.5 (invalid) and yields 2.5.
/// let second = stream.next(&Rail).unwrap().unwrap();
/// assert_eq!(second.targets[0].configuration, vec![2.5]);
/// assert_eq!(stream.next(&Rail).unwrap(), None);
/// ```
pub trait Refiner: Send {
    /// Opens a candidate stream for `request`.
    ///
    /// # Errors
    /// [`PluginError`] when the action or world cannot be refined at all (for example an
    /// unknown action).
    fn refine(
        &mut self,
        request: &RefineRequest,
        host: &dyn HostServices,
    ) -> Result<Box<dyn CandidateStream>, PluginError>;
}
