//! End to end on Packing: real demonstrations made in memory, learned with lamp-build, and four-can
//! problems solved with the first-party plugins linked in. The trajectory is checked for what a
//! robot engineer cares about, independently of the solver's own replay: every can ends standing
//! on the box floor inside its walls, nothing collides along the way, and the same seed gives the
//! same trajectory.

#[path = "support/learned.rs"]
mod learned;

use lamp_build::SamplersFile;
use lamp_motion_rrt::{RrtConnectPlanner, RrtOptions};
use lamp_participants::ParticipantMap;
use lamp_planner_builtin::{BuiltinAlgorithm, BuiltinPlanner};
use lamp_plugin_api::{
    HostServices, MotionBudget, PlanBudget, PlanRequest, PlanResponse, Planner, PluginError,
};
use lamp_refiner_gmm::{GmmRefiner, RefinerOptions};
use lamp_tamp::MotionSettings;
use lamp_tamp::{Plugins, Solution, SolveError, SolveInput, SolveSettings, solve};
use lamp_world::{MotionConfig, trajectory_header};
use learned::{Learned, PACKING, artifact};

fn solve_problem(name: &str, seed: u64) -> Result<Solution, SolveError> {
    learned::solve_problem(&PACKING, name, seed)
}

/// Replays the trajectory in a fresh scene: no step collides; at the end every can stands on the
/// box floor, inside its walls, released.
fn check_packed(name: &str, solution: &Solution) {
    let scene = learned::replay_collision_free(&PACKING, name, solution);
    let steps = &solution.trajectory.steps;
    let last = steps.last().expect("a trajectory");
    assert_eq!(last.robots[0].held, vec![None], "the last can is released");
    let box_index = scene.body_index("box1").expect("the box");
    let box_pose = last.body_poses[box_index];
    for can in ["can1", "can2", "can3", "can4"] {
        let pose = box_pose.inv_mul(&last.body_poses[scene.body_index(can).expect("a can")]);
        let t = pose.translation.vector;
        let inner = 0.075 - 0.0325;
        assert!(
            t.x.abs() <= inner && t.y.abs() <= inner,
            "{name}: {can} inside the walls: {t:?}; plan {:?}",
            solution.summary.plan
        );
        assert!((-1e-9..=0.006).contains(&t.z), "{can} stands on the floor: {t:?}");
        let up = pose.rotation * nalgebra::Vector3::z();
        assert!(up.z > 0.99, "{can} upright");
    }
}

/// Every carry leaves the can's support straight up and comes down onto its place straight
/// down: over the first and the last 5 cm of height the can moves by less than 1 mm across.
/// (A carry that slides a can along the table, or comes in over a wall at the height of its
/// rim, is collision-free but hits what it passes on a robot that tracks it within millimetres.)
fn assert_carries_are_vertical_at_their_ends(name: &str, solution: &Solution) {
    let steps = &solution.trajectory.steps;
    let held = |step: &lamp_trajectory::Step| step.robots[0].held.first().copied().flatten();
    let mut index = 0;
    while index < steps.len() {
        let Some(can) = held(&steps[index]) else {
            index += 1;
            continue;
        };
        let end =
            (index..steps.len()).find(|&k| held(&steps[k]) != Some(can)).unwrap_or(steps.len());
        let carry: Vec<_> =
            steps[index..end].iter().map(|s| s.body_poses[can].translation.vector).collect();
        for ends in [carry.clone(), carry.iter().rev().copied().collect::<Vec<_>>()] {
            let from = ends[0];
            for at in ends.iter().take_while(|at| at.z < from.z + 0.05) {
                let across = (at.xy() - from.xy()).norm();
                assert!(
                    across < 1e-3,
                    "{name}: a carry of body {can} moves {across} m across near its end"
                );
            }
        }
        index = end;
    }
}

#[test]
fn four_cans_are_packed_and_the_trajectory_is_collision_free() {
    for name in ["pack4_01", "pack4_09"] {
        let solution = solve_problem(name, 1).unwrap_or_else(|error| panic!("{name}: {error}"));
        assert!(solution.summary.success);
        assert_eq!(
            solution.summary.plan.len(),
            19,
            "{name}: per can approach, grab, carry in, release, and a retreat between cans"
        );
        // Each can is put upright into the box where the next ones still fit, so no step runs
        // out of candidates (with draws leaning as the box region's coarse rotation cells let
        // them, the fourth can found no upright place and the plan backtracked 52 times).
        assert_eq!(solution.summary.backtracks, 0, "{name}: no step runs out of candidates");
        check_packed(name, &solution);
        assert_carries_are_vertical_at_their_ends(name, &solution);
    }
}

/// The free-flying gripper may start anywhere above the table, turned any way about the vertical:
/// a problem whose bundled start is above the table's centre solves from two other starts.
#[test]
fn the_gripper_may_start_anywhere_above_the_table() {
    let name = "pack4_01";
    for (x, y, z, yaw) in [(0.3, -0.3, 0.5, 120.0_f64), (-0.35, 0.3, 0.6, -75.0)] {
        let down = nalgebra::UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
        let turned = nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, yaw.to_radians());
        let start =
            nalgebra::Isometry3::from_parts(nalgebra::Translation3::new(x, y, z), turned * down);
        let solution = learned::solve_from(&PACKING, name, &start)
            .unwrap_or_else(|error| panic!("{name} from ({x}, {y}, {z}) at {yaw}°: {error}"));
        assert!(solution.summary.success, "{name} from ({x}, {y}, {z}) at {yaw}°");
        let first = &solution.trajectory.steps[0].robots[0].positions;
        assert!((first[0] - x).abs() < 1e-9 && (first[1] - y).abs() < 1e-9, "{first:?}");
        check_packed(name, &solution);
    }
}

/// The built-in planner, except that its first plan lacks its second step: once the first step
/// is refined, the rest of that plan does not run from the reached state.
struct SkipsTheSecondStep {
    inner: BuiltinPlanner,
    calls: usize,
}

impl Planner for SkipsTheSecondStep {
    fn plan(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        self.calls += 1;
        let mut response = self.inner.plan(request, host)?;
        if self.calls == 1 {
            response.plans[0].steps.remove(1);
        }
        Ok(response)
    }
}

#[test]
fn a_plan_whose_rest_breaks_is_replanned_from_the_reached_state() {
    let mut planner =
        SkipsTheSecondStep { inner: BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf), calls: 0 };
    let solution = learned::solve_with_planner(&PACKING, "pack4_01", 1, &mut planner)
        .unwrap_or_else(|error| panic!("{error}"));
    assert!(solution.summary.replans >= 1, "{:?}", solution.summary);
    assert_eq!(planner.calls, 1 + solution.summary.replans, "one call per replan");
    assert_eq!(solution.summary.plan.len(), 19, "the plan refined is the replanned one");
    // The summary says where: after the first step, in a state no different from the one the
    // plan predicted (the plan was wrong, not the world), and the plan's text marks it.
    let points = &solution.summary.replan_points;
    assert_eq!(points.len(), 1, "{points:?}");
    assert_eq!(points[0].after_step, 1);
    assert!(points[0].added.is_empty() && points[0].deleted.is_empty(), "{points:?}");
    assert!(points[0].poses.is_empty(), "no atom differs, so no object is named: {points:?}");
    let text = solution.summary.plan_text();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 20, "{text}");
    assert_eq!(lines[1], "; replan after step 1: added none; deleted none");
    check_packed("pack4_01", &solution);
}

/// A planner that says it solved the task and returns no plan, as a misconfigured one may.
struct SolvedWithoutAPlan;

impl Planner for SolvedWithoutAPlan {
    fn plan(
        &mut self,
        _request: &PlanRequest,
        _host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        Ok(PlanResponse { status: lamp_plugin_api::PlanStatus::Solved, plans: vec![] })
    }
}

/// A planner answering `solved` without a plan was taken as one that found no plan, and the
/// solve blamed the learned model; it is the planner's failure.
#[test]
fn a_planner_that_says_solved_without_a_plan_fails_as_the_planner() {
    let error = learned::solve_with_planner(&PACKING, "pack4_01", 1, &mut SolvedWithoutAPlan)
        .err()
        .expect("no plan to refine");
    assert!(
        matches!(&error, SolveError::PluginAnswer { kind: "planner", reason }
            if reason.contains("returned no plan")),
        "{error}"
    );
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::solve::plugin"));
    assert!(!error.to_string().contains("no way"), "{error}");
}

/// A planner whose budget runs out before it finds a plan, as one with a short `timeout` on a
/// large task does.
struct OutOfBudget;

impl Planner for OutOfBudget {
    fn plan(
        &mut self,
        _request: &PlanRequest,
        _host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        Ok(PlanResponse { status: lamp_plugin_api::PlanStatus::BudgetExhausted, plans: vec![] })
    }
}

/// A planner out of budget has not shown that no plan reaches the goal: the goal is not relaxed
/// (which dropped a goal atom, then another, and ended saying the learned model has no way to
/// the goal), and the failure says a plan may exist and how to give the planner more time.
#[test]
fn a_planner_out_of_budget_relaxes_no_goal_and_says_a_plan_may_exist() {
    let error = learned::solve_relaxing_with_planner(&PACKING, "pack4_01", &mut OutOfBudget)
        .err()
        .expect("no plan to refine");
    assert!(
        matches!(&error, SolveError::PlannerBudget { relaxed } if relaxed.is_empty()),
        "{error}"
    );
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::solve::planner_budget"));
    let help = miette::Diagnostic::help(&error).map(|help| help.to_string()).unwrap_or_default();
    assert!(help.contains("A plan may exist") && help.contains("timeout"), "{help}");
    assert!(!error.to_string().contains("no way"), "{error}");
}

/// The built-in planner's first plan without its second step, and then no plan, its budget run
/// out: the replan from the reached state is out of budget.
struct SkipsThenRunsOut {
    inner: BuiltinPlanner,
    calls: usize,
}

impl Planner for SkipsThenRunsOut {
    fn plan(
        &mut self,
        request: &PlanRequest,
        host: &dyn HostServices,
    ) -> Result<PlanResponse, PluginError> {
        self.calls += 1;
        if self.calls > 1 {
            return Ok(PlanResponse {
                status: lamp_plugin_api::PlanStatus::BudgetExhausted,
                plans: vec![],
            });
        }
        let mut response = self.inner.plan(request, host)?;
        response.plans[0].steps.remove(1);
        Ok(response)
    }
}

/// A replan whose planner ran out of budget refuses the candidate saying so, not that no plan
/// reaches the goal from there.
#[test]
fn a_replan_out_of_budget_is_not_called_unreachable() {
    let mut planner =
        SkipsThenRunsOut { inner: BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf), calls: 0 };
    let error = learned::solve_with_planner(&PACKING, "pack4_01", 1, &mut planner)
        .err()
        .expect("no rest of the plan is found");
    let message = error.to_string();
    assert!(
        message.contains("the planner's budget ran out before it found a plan from there"),
        "{message}"
    );
    assert!(!message.contains("no plan reaches the goal from there"), "{message}");
}

/// The learned domain and pack4_01's problem, the `in_box` atom of can1 and the "not in the box"
/// relation the only placing action deletes (no action adds it back).
fn placing() -> (String, String, lamp_pddl::Atom, String) {
    let artifacts = &PACKING.artifacts;
    let domain_text = artifact(artifacts, "domain.pddl").to_string();
    let problem_text = artifact(artifacts, "problems/pack4_01.pddl").to_string();
    let domain = lamp_pddl::parse_domain(&domain_text).expect("parses");
    let problem = lamp_pddl::parse_problem(&problem_text, &domain).expect("parses");
    let in_box = problem.goal.iter().find(|l| l.atom.arguments.len() == 2).expect("in_box");
    let placing = domain
        .actions
        .iter()
        .find(|action| action.add.iter().any(|atom| atom.predicate == in_box.atom.predicate))
        .expect("an action puts a can into the box");
    let outside = placing.delete.iter().find(|atom| atom.arguments.len() == 2).expect("deletes");
    (domain_text, problem_text, in_box.atom.clone(), outside.predicate.clone())
}

#[test]
fn a_goal_relaxed_to_reach_the_rest_is_a_partial_result_not_a_success() {
    let (domain, problem, in_box, outside) = placing();
    let can = in_box.arguments.iter().map(|a| a.name()).collect::<Vec<_>>().join(" ");
    let unreachable = format!("({outside} {can})");
    let problem = problem.replacen("\n  ))", &format!("\n    {unreachable}\n  ))"), 1);
    let error = learned::solve_edited(&PACKING, "pack4_01", (&domain, &problem), false)
        .err()
        .expect("without relaxation, no plan");
    assert!(matches!(error, SolveError::NoPlan { .. }), "{error}");
    let solution = learned::solve_edited(&PACKING, "pack4_01", (&domain, &problem), true)
        .unwrap_or_else(|error| panic!("{error}"));
    let summary = &solution.summary;
    assert!(!summary.success && summary.is_partial(), "{summary:?}");
    assert_eq!(summary.relaxed_goal, [unreachable]);
    assert_eq!(summary.plan.len(), 19, "the rest of the goal is reached");
    check_packed("pack4_01", &solution);
}

#[test]
fn a_goal_relaxed_until_nothing_is_left_to_achieve_is_a_failure() {
    let (domain, problem, in_box, _) = placing();
    let mut parsed = lamp_pddl::parse_domain(&domain).expect("parses");
    parsed.actions.retain(|action| !action.add.iter().any(|a| a.predicate == in_box.predicate));
    let domain = lamp_pddl::write_domain(&parsed);
    let error = learned::solve_edited(&PACKING, "pack4_01", (&domain, &problem), true)
        .err()
        .expect("not a success with an empty plan");
    let SolveError::GoalRelaxedAway { dropped, .. } = &error else { panic!("{error}") };
    assert_eq!(dropped.matches(&format!("({} ", in_box.predicate)).count(), 4, "{dropped}");
    let code = miette::Diagnostic::code(&error).map(|code| code.to_string());
    assert_eq!(code.as_deref(), Some("lamp::solve::goal_relaxed_away"));
}

#[test]
fn the_same_seed_gives_the_same_trajectory() {
    let first = solve_problem("pack4_04", 7).expect("solved");
    let second = solve_problem("pack4_04", 7).expect("solved");
    assert_eq!(
        first.trajectory.to_bytes().expect("encodes"),
        second.trajectory.to_bytes().expect("encodes")
    );
}

#[test]
fn a_stale_problem_file_is_refused() {
    let Learned { spec, world, artifacts, .. } = &*PACKING;
    let problem = spec.problems.iter().find(|p| p.name == "pack4_01").expect("exists");
    let mut scene = world.problem_scene(problem).expect("the scene loads");
    // Move can1 into the box after the problem file was written.
    let box_pose = scene.body_pose(scene.body_index("box1").expect("box"));
    let can = scene.body_index("can1").expect("can");
    scene.set_body_pose(can, box_pose * nalgebra::Translation3::new(0.0, 0.0, 0.001));
    let participants = ParticipantMap::new(spec, &world.robots).expect("a participant map");
    let samplers = SamplersFile::from_json(artifact(artifacts, "samplers.json")).expect("samplers");
    let never = || false;
    let settings = SolveSettings {
        seed: 1,
        plan_count: 1,
        planner_budget: PlanBudget::default(),
        rounds: 1,
        max_refused: 10,
        motion: MotionSettings {
            config: MotionConfig::default(),
            budget: MotionBudget::default(),
            grab_ranges: Vec::new(),
        },
        relax_goal: false,
        cancelled: &never,
    };
    let input = SolveInput {
        scene: &scene,
        domain: artifact(artifacts, "domain.pddl"),
        problem: artifact(artifacts, "problems/pack4_01.pddl"),
        artifact: &samplers.artifact,
        participants: &participants,
        targets: &[],
        header: trajectory_header(spec, &scene, 1),
    };
    let mut planner = BuiltinPlanner::new(BuiltinAlgorithm::GbfsFf);
    let mut refiner =
        GmmRefiner::new(samplers.artifact.clone(), RefinerOptions::default()).expect("valid");
    let mut motion = RrtConnectPlanner::new(RrtOptions::default());
    let mut plugins = Plugins { planner: &mut planner, refiner: &mut refiner, motion: &mut motion };
    let error = solve(&input, &mut plugins, &settings, &|_| {}).err().expect("refused");
    assert!(matches!(error, SolveError::StaleProblem { .. }), "{error}");
    assert!(error.to_string().contains("can1"), "{error}");
}
