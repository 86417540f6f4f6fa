//! A finding of the initial-scene check (`initial_scene`), as a diagnostic of its own: the
//! build's error lists them.

use miette::Diagnostic;
use thiserror::Error;

/// The `what` of a placement finding about an `at` goal's target.
pub(crate) const TARGET: &str = "the target of";

/// One reason a problem's initial scene is not one the solver can start from.
#[derive(Debug, Clone, PartialEq, Error, Diagnostic)]
pub enum SceneIssue {
    /// A placement with a non-finite number.
    #[error("problem `{problem}`: the pose of {what} `{name}` is not finite")]
    #[diagnostic(
        code(lamp::build::scene_not_finite),
        help("Every coordinate and angle of a placement must be a finite number.")
    )]
    NotFinite { problem: String, what: &'static str, name: String },

    /// A placement beyond [`MAX_DISTANCE`](crate::initial_scene::MAX_DISTANCE).
    #[error(
        "problem `{problem}`: {what} `{name}` is placed at {position} m, farther than {max} m from the origin"
    )]
    #[diagnostic(
        code(lamp::build::scene_range),
        help("Place it within {max} m of the origin; check the number and its unit.")
    )]
    OutOfRange { problem: String, what: &'static str, name: String, position: String, max: f64 },

    /// Two bodies touch or overlap.
    #[error("problem `{problem}`: `{first}` and `{second}` touch or overlap")]
    #[diagnostic(
        code(lamp::build::scene_contact),
        help(
            "Bodies closer than 1 µm count as touching, and the solver cannot move an object that touches another: place them apart, for example an object 1 mm above its support as the bundled specs do."
        )
    )]
    Contact { problem: String, first: String, second: String },

    /// An AtGoal target puts its object into a static body.
    #[error(
        "problem `{problem}`: the `at` goal puts `{object}` where it touches or overlaps `{body}`"
    )]
    #[diagnostic(
        code(lamp::build::target_contact),
        help(
            "An object at its target must stand free: place the target 1 mm above its support, as the bundled specs do, and clear of the furniture."
        )
    )]
    TargetContact { problem: String, object: String, body: String },

    /// Two AtGoal targets put their objects into each other: no plan can leave both there.
    #[error(
        "problem `{problem}`: the `at` goals put `{first}` and `{second}` where they touch or overlap"
    )]
    #[diagnostic(
        code(lamp::build::targets_overlap),
        help(
            "Two objects cannot be at one place: move one of the targets clear of the other (a copied line with the pose left unchanged is the usual cause)."
        )
    )]
    TargetsOverlap { problem: String, first: String, second: String },

    /// An AtGoal target leaves its object where it cannot rest: in the air, over an edge.
    #[error("problem `{problem}`: the `at` goal puts `{object}` where it cannot rest: {reason}")]
    #[diagnostic(
        code(lamp::build::target_unsupported),
        help(
            "An object can only be left standing on something: put the target's height 1 mm above the top of the surface it should stand on, as the bundled specs do, and its centre over that surface."
        )
    )]
    TargetUnsupported { problem: String, object: String, reason: String },

    /// A movable object of the initial scene cannot rest where it is placed: in the air, over
    /// an edge.
    #[error("problem `{problem}`: `{object}` cannot rest where the scene places it: {reason}")]
    #[diagnostic(
        code(lamp::build::scene_unsupported),
        help(
            "An object must start standing on something: place it 1 mm above the top of its support, as the bundled specs do, with its centre over that support."
        )
    )]
    Unsupported { problem: String, object: String, reason: String },

    /// A robot starts in collision.
    #[error("problem `{problem}`: robot `{robot}` starts in collision: {contact}")]
    #[diagnostic(
        code(lamp::build::robot_start_collision),
        help(
            "Place the robot elsewhere, choose another `config`, or move what it touches; it must start free of every body and of itself."
        )
    )]
    RobotCollision { problem: String, robot: String, contact: String },

    /// A robot starts outside its joint limits.
    #[error(
        "problem `{problem}`: robot `{robot}` starts outside its joint limits: `{coordinate}` is {value}, outside [{lower}, {upper}]"
    )]
    #[diagnostic(
        code(lamp::build::robot_start_limits),
        help("Change the robot's `config` so that every joint is within the limits of its URDF.")
    )]
    RobotLimits {
        problem: String,
        robot: String,
        coordinate: String,
        value: f64,
        lower: f64,
        upper: f64,
    },

    /// The scene could not be built at all.
    #[error("problem `{problem}`: the initial scene cannot be built: {reason}")]
    #[diagnostic(code(lamp::build::scene))]
    Unbuildable { problem: String, reason: String },
}

/// Where in the spec a finding's subject is written, for rendering it there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IssuePlace<'a> {
    /// The line of the problem's scene that places this object or robot.
    Scene(&'a str),
    /// The problem's `at` goal on this object.
    AtGoal(&'a str),
}

impl SceneIssue {
    /// What the finding is about, where the spec writes it, in the order the message names them.
    pub fn places(&self) -> Vec<IssuePlace<'_>> {
        use IssuePlace::{AtGoal, Scene};
        match self {
            SceneIssue::NotFinite { what, name, .. }
            | SceneIssue::OutOfRange { what, name, .. } => {
                // A target's pose is its `at` goal's; every other placement is a scene line.
                if *what == TARGET { vec![AtGoal(name)] } else { vec![Scene(name)] }
            }
            SceneIssue::Contact { first, second, .. } => vec![Scene(first), Scene(second)],
            SceneIssue::TargetContact { object, .. }
            | SceneIssue::TargetUnsupported { object, .. } => vec![AtGoal(object)],
            SceneIssue::TargetsOverlap { first, second, .. } => vec![AtGoal(first), AtGoal(second)],
            SceneIssue::Unsupported { object, .. } => vec![Scene(object)],
            SceneIssue::RobotCollision { robot, .. } | SceneIssue::RobotLimits { robot, .. } => {
                vec![Scene(robot)]
            }
            SceneIssue::Unbuildable { .. } => Vec::new(),
        }
    }

    /// The problem the finding is about.
    pub fn problem(&self) -> &str {
        match self {
            SceneIssue::NotFinite { problem, .. }
            | SceneIssue::OutOfRange { problem, .. }
            | SceneIssue::Contact { problem, .. }
            | SceneIssue::TargetContact { problem, .. }
            | SceneIssue::TargetsOverlap { problem, .. }
            | SceneIssue::TargetUnsupported { problem, .. }
            | SceneIssue::Unsupported { problem, .. }
            | SceneIssue::RobotCollision { problem, .. }
            | SceneIssue::RobotLimits { problem, .. }
            | SceneIssue::Unbuildable { problem, .. } => problem,
        }
    }
}
