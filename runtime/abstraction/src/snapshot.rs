//! What the learned abstraction reads: participants (bodies that can enter relations) and their
//! world poses at one time step.

/// A rigid transform (rotation, then translation), in metres and radians.
pub type Pose = nalgebra::Isometry3<f64>;

/// A body that can enter relations.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Participant {
    /// The object name, unique within a demonstration (and a PDDL identifier).
    pub name: String,
    /// The object type (a PDDL identifier).
    pub type_name: String,
    /// What kind of body it is.
    pub role: Role,
}

/// What kind of body a participant is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Role {
    /// A robot link (always the primary of its pairs); `gripper` if it can hold objects.
    RobotPart { gripper: bool },
    /// An object; `movable` if it can be carried.
    Object { movable: bool },
}

impl Role {
    /// The rank used to choose the primary of a pair: robot parts, then static, then movable.
    pub fn primary_rank(self) -> u8 {
        match self {
            Role::RobotPart { .. } => 0,
            Role::Object { movable: false } => 1,
            Role::Object { movable: true } => 2,
        }
    }

    /// Whether it is a robot link.
    pub fn is_robot_part(self) -> bool {
        matches!(self, Role::RobotPart { .. })
    }

    /// Its kind in words, for messages.
    pub fn describe(self) -> &'static str {
        match self {
            Role::RobotPart { gripper: true } => "a gripper robot part",
            Role::RobotPart { gripper: false } => "a robot part",
            Role::Object { movable: true } => "a movable object",
            Role::Object { movable: false } => "a static object",
        }
    }
}

/// The state of every participant at one time step.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// World pose per participant, in participant order.
    pub poses: Vec<Pose>,
    /// (gripper participant, held participant) index pairs.
    pub held: Vec<(usize, usize)>,
}
