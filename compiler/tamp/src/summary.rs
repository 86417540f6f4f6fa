//! The run summary written next to the trajectory: what was solved, how, and how long each phase
//! took.
//!
//! A summary exists only for a validated trajectory. It is a success when the trajectory reaches
//! the whole goal, and a partial result when goal atoms had to be dropped (`relaxed_goal`).
//!
//! Where a step reached a state other than the one its plan predicted and the rest of the plan
//! was planned again from there, the summary says so (`replan_points`), and the plan's text marks
//! the place ([`Summary::plan_text`]): the plan is then made of segments, each a plan from the
//! state it starts in.

use serde::Serialize;

/// What one solve did.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    /// The problem's name.
    pub problem: String,
    /// Whether the validated trajectory reaches the whole goal; false for a partial result, whose
    /// trajectory reaches the goal without the atoms in `relaxed_goal`.
    pub success: bool,
    /// Goal atoms dropped because no plan reaches them, in the order they were dropped (empty when
    /// the goal was kept whole).
    pub relaxed_goal: Vec<String>,
    /// The refined plan, one `(action args…)` per step.
    pub plan: Vec<String>,
    /// The replans `plan` went through, in its order: after which step the state reached
    /// differed from the one predicted, and how. Replans that backtracking undid are not here
    /// (`replans` counts them all).
    pub replan_points: Vec<ReplanPoint>,
    /// Symbolic plans tried (each refinement round counts every plan it tries).
    pub plans_tried: usize,
    /// Refiner candidates tried.
    pub candidates: usize,
    /// Times the refinement went back to an earlier step.
    pub backtracks: usize,
    /// Times a step's side effect broke the rest of the plan and the planner was asked again
    /// from the reached state.
    pub replans: usize,
    /// Times a step let go of an object where nothing held it up yet, and the steps that carry it
    /// were moved later in the plan (`lamp_tamp::postpone`).
    pub postponements: usize,
    /// Motion-planner calls, and how many found no path.
    pub motion_calls: usize,
    pub motion_failures: usize,
    /// Recorded trajectory steps.
    pub trajectory_steps: usize,
    /// How long a robot takes to execute the trajectory, in seconds: the last step's stamp, every
    /// motion within the joints' velocity and acceleration limits and every grasp change
    /// `lamp_world::GRASP_SECONDS` (deterministic, unlike the solver's own times below).
    pub execution_seconds: f64,
    /// Where the trajectory's straight last approaches are, in their order: a carried object
    /// coming down onto its place, a magnet or suction cup coming to what it takes. Each ends in
    /// contact, which a robot tracking within millimetres meets early or late; a controller makes
    /// them compliant or force-limited.
    pub approaches: Vec<ApproachSpan>,
    /// The object of the final scene that goes down farthest onto what it rests on, and how far:
    /// the world leaves every object at rest up to `lamp_world::RESTING_GAP` above its support,
    /// so an object on a stack of n ends about n gaps below its pose in the trajectory. `None`
    /// when nothing rests on anything.
    pub sink: Option<Sink>,
    /// Seconds spent planning, refining (sampling, IK, motion) and validating.
    pub seconds_planning: f64,
    pub seconds_refining: f64,
    pub seconds_validating: f64,
}

/// One straight last approach (`lamp_world::Approach`), as the summary gives it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ApproachSpan {
    /// The trajectory step where it begins; the stamps below say it in the files.
    #[serde(skip)]
    pub from_step: usize,
    /// The plan step (1-based, in `Summary::plan`) whose motion it ends.
    pub plan_step: usize,
    pub kind: ApproachEnd,
    pub robot: String,
    /// The object put down, or taken by contact.
    pub object: String,
    /// The stamps of its first and last trajectory steps, in seconds.
    pub from_seconds: f64,
    pub to_seconds: f64,
    /// How far the gripper travels along it, in metres.
    pub metres: f64,
}

/// What an approach ends in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ApproachEnd {
    /// A carried object on its place.
    PutDown,
    /// A gripper that holds by contact on the object it takes.
    Contact,
}

/// How far an object goes down onto what it rests on.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Sink {
    pub object: String,
    pub metres: f64,
}

/// One replan of the plan as refined: the state reached after a step differed from the one the
/// plan's segment predicted, and the steps after it were planned again from the state reached.
///
/// The segment that ends here starts in the problem's initial state, or in the state reached at
/// the replan before; its steps run in the domain from there to `after_step`. The next segment
/// starts in the state they predict, less `deleted`, plus `added`.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ReplanPoint {
    /// The step (1-based, in `Summary::plan`) after which the state differed; the steps after it
    /// are the new plan.
    pub after_step: usize,
    /// Atoms true in the state reached that the plan predicted false, sorted.
    pub added: Vec<String>,
    /// Atoms the plan predicted true that are false in the state reached, sorted.
    pub deleted: Vec<String>,
    /// Where every object these atoms name was in the state reached (world frame), by name.
    pub poses: Vec<ObjectPose>,
}

/// Where an object (a body or a robot part) was.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ObjectPose {
    pub object: String,
    /// Metres, world frame.
    pub position: [f64; 3],
    /// A unit quaternion, `[x, y, z, w]`.
    pub rotation: [f64; 4],
}

impl Summary {
    /// Whether the trajectory reaches only a relaxed goal: some goal atoms were dropped.
    pub fn is_partial(&self) -> bool {
        !self.relaxed_goal.is_empty()
    }

    /// The plan as text: one step a line, and before the first step of each replanned segment a
    /// comment line `; replan after step N: added … deleted …`, so that the text splits at those
    /// lines into plans of their own.
    pub fn plan_text(&self) -> String {
        let mut text = String::new();
        let mut replans = self.replan_points.iter().peekable();
        for (index, step) in self.plan.iter().enumerate() {
            while let Some(replan) = replans.next_if(|replan| replan.after_step == index) {
                text.push_str(&replan.comment());
                text.push('\n');
            }
            text.push_str(step);
            text.push('\n');
        }
        // A replan after the last step leaves an empty segment; it is still marked.
        for replan in replans {
            text.push_str(&replan.comment());
            text.push('\n');
        }
        text
    }
}

impl ReplanPoint {
    /// `; replan after step N: added (a b) (c d); deleted (e f)`.
    pub fn comment(&self) -> String {
        let atoms = |atoms: &[String]| match atoms.is_empty() {
            true => "none".to_string(),
            false => atoms.join(" "),
        };
        format!(
            "; replan after step {}: added {}; deleted {}",
            self.after_step,
            atoms(&self.added),
            atoms(&self.deleted)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plan_text_marks_each_replan_before_the_steps_planned_again() {
        let summary = Summary {
            plan: ["(pick a)", "(put a)", "(pick b)"].map(String::from).to_vec(),
            replan_points: vec![ReplanPoint {
                after_step: 2,
                added: vec!["(loose a)".to_string()],
                deleted: vec!["(on a box)".to_string(), "(in a box)".to_string()],
                poses: Vec::new(),
            }],
            ..Summary::default()
        };
        assert_eq!(
            summary.plan_text(),
            "(pick a)\n(put a)\n; replan after step 2: added (loose a); deleted (on a box) (in a box)\n(pick b)\n"
        );
        let plain = Summary { replan_points: Vec::new(), ..summary };
        assert_eq!(plain.plan_text(), "(pick a)\n(put a)\n(pick b)\n");
    }
}
