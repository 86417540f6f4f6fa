//! lamp-participants: a scene as the learner sees it.
//!
//! The build abstracts every problem's initial scene with it, and the solver every scene it
//! reaches, so the two always agree on participant names and order. [`ParticipantMap`] says which
//! links of a spec's robots and which object types take part in relations; [`scene_snapshot`]
//! turns a scene into the participants and their snapshot.

mod map;
mod snapshot;

pub use map::{Part, ParticipantMap, RobotParts, part_participant_name};
pub use snapshot::scene_snapshot;
