//! Warnings about goals the build wrote: each is located by problem and object, so that `lampc`
//! can point at the goal, or at the structure object, in the spec.

use miette::Diagnostic;
use thiserror::Error;

/// A warning about a goal the build wrote: the problem is written, but may be hard or
/// impossible to solve for the reason it gives.
#[derive(Debug, Clone, PartialEq, Eq, Error, Diagnostic)]
pub enum GoalWarning {
    /// The learned region of the object on its marker is wider than the goal's tolerance.
    #[error(
        "problem `{problem}`: the `at` goal on `{object}` is tighter than what was learned: {share} of the region `{relation}` lies within {position} and {angle} of the target, the goal asks for {tolerance}"
    )]
    #[diagnostic(
        code(lamp::build::at_goal_tolerance),
        severity(Warning),
        help(
            "The solver samples the region and keeps only placements within the tolerance, so it may need more samples or fail; loosen the tolerance, or record demonstrations that place objects onto their markers more precisely."
        )
    )]
    LooserRegion {
        problem: String,
        object: String,
        relation: String,
        /// The quantile, as a percentage.
        share: String,
        /// The quantile's distance and angle from the target.
        position: String,
        angle: String,
        /// The goal's tolerance.
        tolerance: String,
    },

    /// Objects of a structure rest on others at their places, but no learned relation holds
    /// between them there: the goal cannot say which goes first.
    #[error(
        "problem `{problem}`: in structure `{structure}`, {count} object(s) rest on others with no learned relation between them there ({rests}), so the goal cannot say which goes first: a plan may let go of one before what holds it up is in place, and every such plan is refused"
    )]
    #[diagnostic(
        code(lamp::build::structure_rest_unrelated),
        severity(Warning),
        help(
            "The demonstrations do not rest objects this way often enough for it to be a region (`vocabulary.md` lists the ways they do): record more demonstrations of these placements, or build the structure from arrangements they show."
        )
    )]
    UnrelatedRest {
        problem: String,
        structure: String,
        /// The first object resting with no relation, in the structure's order.
        object: String,
        /// How many pairs rest with no relation.
        count: usize,
        /// The pairs, as "`p2` on `p1`", the first few of them.
        rests: String,
    },
}

/// Where in the spec a [`GoalWarning`] belongs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalPlace<'a> {
    /// The `at` goal on an object of a problem.
    AtGoal { problem: &'a str, object: &'a str },
    /// An object of a structure, in a problem's structure goal.
    StructureObject { problem: &'a str, structure: &'a str, object: &'a str },
}

impl GoalWarning {
    /// The goal the warning is about.
    pub fn place(&self) -> GoalPlace<'_> {
        match self {
            GoalWarning::LooserRegion { problem, object, .. } => {
                GoalPlace::AtGoal { problem, object }
            }
            GoalWarning::UnrelatedRest { problem, structure, object, .. } => {
                GoalPlace::StructureObject { problem, structure, object }
            }
        }
    }
}
