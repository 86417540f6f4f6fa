//! A finding of structure transcription (`structure_goals`), as a diagnostic of its own: each
//! names the problem, and the structure object it is about when there is one, so that `lampc`
//! can point at the structure goal or at the object's line in the structure.

use miette::Diagnostic;
use thiserror::Error;

/// Why a structure goal cannot be written as a goal the solver can reach. Every finding is an
/// error: a structure out of range, that intersects itself or floats cannot be built, an object without a goal
/// atom would be left wherever the plan leaves it, and an atom no action adds makes the problem
/// unsolvable.
#[derive(Debug, Clone, PartialEq, Eq, Error, Diagnostic)]
pub enum StructureIssue {
    /// An object's target is farther than [`crate::MAX_DISTANCE`] from the origin (or not a
    /// number): an offset in the structure or in its goal is absurd.
    #[error(
        "problem `{problem}`: structure `{structure}` puts `{object}` at {position} m, more than {max} m from the origin",
        max = crate::MAX_DISTANCE
    )]
    #[diagnostic(
        code(lamp::build::structure_range),
        help(
            "A structure is built within a robot's reach of its anchor: check the object's pose in the structure and the goal's offset for a slip of the unit or the exponent (each coordinate at most 1000 m, as `lampc check` requires)."
        )
    )]
    OutOfRange { problem: String, structure: String, object: String, position: String },

    /// Two objects of the placed structure, or one and a static body, touch or overlap.
    #[error(
        "problem `{problem}`: structure `{structure}` intersects itself: `{object}` and `{other}` touch or overlap at their poses"
    )]
    #[diagnostic(
        code(lamp::build::structure_contact),
        help(
            "Objects closer than 1 µm count as touching: keep 1 mm between an object and what it rests on, and apart from its neighbours, as the bundled structures do."
        )
    )]
    Contact { problem: String, structure: String, object: String, other: String },

    /// An object of the placed structure does not rest on the static world or on another
    /// structure object, by lamp-world's resting rule.
    #[error("problem `{problem}`: structure `{structure}` does not stand: {reason}")]
    #[diagnostic(
        code(lamp::build::structure_unsupported),
        help(
            "Every object must rest 1 mm above the table or another object of the structure, with its centre of mass over what holds it up (the resting rule of docs/world.md); check its height and position."
        )
    )]
    Unsupported { problem: String, structure: String, object: String, reason: String },

    /// No learned relation holds between an object at its place and the rest of the structure
    /// or its marker, so the goal could not say where it goes.
    #[error(
        "problem `{problem}`: `{object}` of structure `{structure}` gets no goal atom: no learned relation holds between it at its place and {partners}"
    )]
    #[diagnostic(
        code(lamp::build::structure_no_goal),
        help(
            "A structure object's place is said by the learned relations it takes part in there: record demonstrations that put a {type_name} where this one goes, on its marker and beside the objects next to it (a spec needs a marker type, e.g. `type loc {{ marker }}`, for objects resting on the table), or change the structure."
        )
    )]
    NoGoalAtom {
        problem: String,
        structure: String,
        object: String,
        type_name: String,
        /// What it was compared with, in words.
        partners: String,
    },

    /// A goal atom that no learned action adds: no demonstration made that relation.
    #[error(
        "problem `{problem}`: structure `{structure}` needs `{atom}`, which no learned action adds: no demonstration puts a {secondary_type} at {pose} in the frame of a {primary_type} by moving it there"
    )]
    #[diagnostic(
        code(lamp::build::structure_unlearned),
        help(
            "The relation was seen but never made: record demonstrations that place a {secondary_type} so relative to a {primary_type}, or change the structure so that it is built from arrangements the demonstrations show."
        )
    )]
    Unlearned {
        problem: String,
        structure: String,
        /// The structure object the atom is about (its secondary, or its primary for a marker).
        object: String,
        atom: String,
        primary_type: String,
        secondary_type: String,
        /// The secondary's pose in the primary's frame, as a spec writes one.
        pose: String,
    },
}

impl StructureIssue {
    /// The problem the finding is about.
    pub fn problem(&self) -> &str {
        match self {
            StructureIssue::OutOfRange { problem, .. }
            | StructureIssue::Contact { problem, .. }
            | StructureIssue::Unsupported { problem, .. }
            | StructureIssue::NoGoalAtom { problem, .. }
            | StructureIssue::Unlearned { problem, .. } => problem,
        }
    }

    /// The structure and the object of it the finding is about.
    pub fn structure_object(&self) -> (&str, &str) {
        match self {
            StructureIssue::OutOfRange { structure, object, .. }
            | StructureIssue::Contact { structure, object, .. }
            | StructureIssue::Unsupported { structure, object, .. }
            | StructureIssue::NoGoalAtom { structure, object, .. }
            | StructureIssue::Unlearned { structure, object, .. } => (structure, object),
        }
    }
}
