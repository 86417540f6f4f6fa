//! The build's typed errors: where demonstrations are missing or do not fit the spec, and which
//! goal cannot be written, each with a stable `lamp::build::*` code and help for the user.

use miette::Diagnostic;
use thiserror::Error;

/// Everything that stops a build. No artifact is written when one occurs.
#[derive(Debug, Error, Diagnostic)]
pub enum BuildError {
    /// No demonstration file was found where the spec says they are.
    #[error("no demonstration files found (looked for {searched})")]
    #[diagnostic(
        code(lamp::build::no_demonstrations),
        help(
            "Run `lampc demos SPEC` first to simulate demonstrations, point `--demos DIR` at a folder of .mcap files, or fix the spec's `demonstrations {{ files \"…\" }}` pattern."
        )
    )]
    NoDemonstrations {
        /// The glob patterns that matched nothing, separated by commas.
        searched: String,
    },

    /// A ROS 2 bag could not be read as a demonstration with its source's frame mapping.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Ros2(#[from] Box<crate::ros2::Ros2Error>),

    /// A demonstration file could not be read from disk.
    #[error("cannot read demonstration {file}: {reason}")]
    #[diagnostic(code(lamp::build::read), help("Check that the file exists and is readable."))]
    Read { file: String, reason: String },

    /// A demonstration file holds no step: nothing to learn from, and most likely a recording
    /// that was cut off before it began.
    #[error("{file}: the demonstration has no steps")]
    #[diagnostic(
        code(lamp::build::empty_demonstration),
        help("Record or generate it again, or move it out of the demonstration folder.")
    )]
    EmptyDemonstration { file: String },

    /// A demonstration file was recorded for another spec's domain.
    #[error(
        "{file}: the demonstration is of domain `{found}`, but the spec's domain is `{expected}`"
    )]
    #[diagnostic(
        code(lamp::build::other_domain),
        help(
            "Point `--demos` or the spec's `files` pattern at demonstrations of `{expected}`, or generate them with `lampc demos` on this spec."
        )
    )]
    OtherDomain { file: String, found: String, expected: String },

    /// The file is not a readable lamp trajectory (corrupt, truncated, wrong schema, …).
    #[error(transparent)]
    #[diagnostic(transparent)]
    Trajectory(#[from] lamp_trajectory::TrajectoryError),

    /// A body's type is not declared by the spec.
    #[error("{file}: body `{body}` has type `{type_name}`, which the spec does not declare")]
    #[diagnostic(
        code(lamp::build::undeclared_type),
        help(
            "Declare `type {type_name} {{ … }}` in the spec, or record demonstrations of this spec's objects."
        )
    )]
    UndeclaredType { file: String, body: String, type_name: String },

    /// A robot in the file is not declared by the spec.
    #[error("{file}: robot `{robot}` is not declared in the spec")]
    #[diagnostic(
        code(lamp::build::undeclared_robot),
        help(
            "Declare `robot {robot} {{ … }}` in the spec, or record demonstrations with the spec's robots."
        )
    )]
    UndeclaredRobot { file: String, robot: String },

    /// The file's coordinates of a robot are not the coordinates of the spec's robot model.
    #[error(
        "{file}: robot `{robot}` has coordinates [{found}] in the file, but its model has [{expected}]"
    )]
    #[diagnostic(
        code(lamp::build::coordinates),
        help(
            "The demonstration was recorded with another robot model or mount; record it again with the spec's URDF and kind."
        )
    )]
    Coordinates { file: String, robot: String, expected: String, found: String },

    /// A gripper listed in the file is not a part of the spec's robot.
    #[error(
        "{file}: robot `{robot}` has gripper `{gripper}`, which is not one of its parts ({parts})"
    )]
    #[diagnostic(
        code(lamp::build::gripper),
        help("Name the gripper after a `part` of the robot in the spec (usually `gripper`).")
    )]
    UnknownGripper { file: String, robot: String, gripper: String, parts: String },

    /// A gripper holds a body that cannot take part in relations.
    #[error(
        "{file}, step {step}: robot `{robot}` holds `{body}`, which is part of the static world"
    )]
    #[diagnostic(
        code(lamp::build::held_world),
        help("Only movable objects can be held; check the body's type in the file and the spec.")
    )]
    HeldWorldBody { file: String, step: u64, robot: String, body: String },

    /// The robots or object types of the spec could not be loaded.
    #[error(transparent)]
    #[diagnostic(transparent)]
    World(Box<lamp_world::WorldError>),

    /// Problems whose initial scene the solver cannot start from, with every finding.
    #[error("the initial scene of {problems} problem(s) is not one the solver can start from")]
    #[diagnostic(
        code(lamp::build::initial_scenes),
        help(
            "`lampc build` checks every problem's initial scene before it reads any demonstration: fix the scenes listed below in the spec."
        )
    )]
    InitialScenes {
        /// How many problems have findings.
        problems: usize,
        #[related]
        issues: Vec<crate::scene_issue::SceneIssue>,
    },

    /// Structure goals that cannot be transcribed, with every finding.
    #[error("{problems} problem(s) have structure goals that cannot be written")]
    #[diagnostic(
        code(lamp::build::structures),
        help("Each finding below names the problem, the structure and the object.")
    )]
    Structures {
        /// How many problems have findings.
        problems: usize,
        #[related]
        issues: Vec<crate::structure_issue::StructureIssue>,
    },

    /// A problem's initial scene could not be built.
    #[error("problem `{problem}`: the initial scene cannot be built: {reason}")]
    #[diagnostic(code(lamp::build::scene))]
    Scene { problem: String, reason: String },

    /// Learning failed (too few demonstrations, bad settings, …).
    #[error(transparent)]
    #[diagnostic(transparent)]
    Learn(#[from] lamp_learn::LearnError),

    /// An alias names a type pair for which nothing was learned.
    #[error(
        "relation alias `{alias}`: no region was learned for {secondary} in {primary} (pairs with regions: {learned})"
    )]
    #[diagnostic(
        code(lamp::build::alias_pair),
        help(
            "The demonstrations never put a {secondary} in a region of a {primary} often enough: record more demonstrations, lower the pair's threshold or coarsen its bins."
        )
    )]
    AliasPair { alias: String, primary: String, secondary: String, learned: String },

    /// No learned region of the alias's pair contains its example pose.
    #[error(
        "relation alias `{alias}`: no learned region of {secondary} in {primary} contains the example pose; the regions are: {regions}"
    )]
    #[diagnostic(
        code(lamp::build::alias_region),
        help(
            "Move the example pose into one of the regions (`failed/vocabulary.md` in the build folder, which this build wrote, gives their centres and representative poses), or record demonstrations that visit it."
        )
    )]
    AliasRegion { alias: String, primary: String, secondary: String, regions: String },

    /// An AtGoal whose object-on-marker relation was not learned.
    #[error(
        "problem `{problem}`: the `at` goal on `{object}` cannot be written: for a {object_type} on a {marker_type}, {reason}"
    )]
    #[diagnostic(
        code(lamp::build::at_goal),
        help(
            "An `at` goal is reached through the learned relation of a {object_type} exactly on a {marker_type} marker: record demonstrations that place {object_type}s onto markers (`failed/vocabulary.md` in the build folder, which this build wrote, says what was learned)."
        )
    )]
    AtGoal {
        problem: String,
        object: String,
        marker_type: String,
        object_type: String,
        reason: String,
    },

    /// An AtGoal and a relation goal that put the same object in two places: the relation goal
    /// relates it to a marker whose region does not reach the AtGoal's target.
    #[error(
        "problem `{problem}`: the `at` goal on `{object}` and the goal `{relation_goal}` contradict each other: {reason}"
    )]
    #[diagnostic(
        code(lamp::build::at_goal_contradiction),
        help(
            "An object can be in one place only: drop one of the two goals, or move the `at` goal's target (or the marker `{relation_goal}` names) so that the target lies in that marker's region."
        )
    )]
    AtGoalContradiction {
        problem: String,
        object: String,
        /// The relation goal as the spec writes it, `relation(argument, …)`.
        relation_goal: String,
        /// Where the `at` goal puts the object, how far that is from the marker the relation goal
        /// names, and the learned relation whose region it is outside of.
        reason: String,
    },

    /// A goal names a relation that was not learned.
    #[error("problem `{problem}`: goal relation `{relation}` was not learned")]
    #[diagnostic(
        code(lamp::build::goal_relation),
        help(
            "Learned relations are listed in `failed/vocabulary.md` in the build folder, which this build wrote; relation numbers change when learning changes, so prefer an alias (`relation NAME(T1, T2) = region of … containing …`)."
        )
    )]
    GoalRelation { problem: String, relation: String },

    /// The generated PDDL failed lamp-pddl's checks (a bug, reported rather than written).
    #[error("the generated PDDL for {what} is invalid: {reason}")]
    #[diagnostic(code(lamp::build::emit))]
    Emit { what: String, reason: String },

    /// A sampler file that cannot be read back (not JSON, another format or version, a bad mixture).
    #[error("the sampler file cannot be used: {reason}")]
    #[diagnostic(code(lamp::build::samplers), help("Rebuild it with `lampc build`."))]
    Samplers { reason: String },
}

impl From<lamp_world::WorldError> for BuildError {
    fn from(error: lamp_world::WorldError) -> Self {
        // Boxed: the world's error is large and would bloat every result of the build.
        BuildError::World(Box::new(error))
    }
}
