//! What is learned from real Café demonstrations means what a person would name it: the base
//! standing at a surface (tables and the counter alike), the arm tucked, the gripper at a grasp
//! and holding a can, a can on a surface; actions that drive to a surface with the arm tucked,
//! grab, release, lift a can off a surface and put it on one while standing there and holding it
//! (found by their effects, not their names); the alias binds; the demonstrations use the counter
//! as well as the tables; and two-can and six-can problems are solvable with a plan
//! lamp-planner's validator accepts.

mod support;

use std::sync::LazyLock;

use lamp_build::Artifacts;
use lamp_learn::{LiftedAtom, Model, Region, SideReason};
use lamp_planner::{Algorithm, Budget, Status};
use lamp_trajectory::{Step, TrajectoryHeader};

use support::{actions_changing, artifact, has, regions};

/// How many real demonstrations these tests learn from. The spec asks for 200; Café
/// demonstrations are long (thousands of steps each), and the first 100 of the spec's seed learn
/// the same five regions as the 200.
const DEMOS: u32 = 100;

/// The surfaces a full demonstration carries its can from and to.
type Journey = (String, String);

/// The first [`DEMOS`] demonstrations of the Café spec's own `simulate` source, built once, with
/// the surfaces each full one carries its can between.
static CAFE_BUILD: LazyLock<(Model, Artifacts, Vec<Journey>)> = LazyLock::new(|| {
    let (spec, world) = lamp_test_support::domain("cafe");
    let demonstrations = support::simulated(&spec, &world, DEMOS);
    let journeys = demonstrations
        .iter()
        .filter(|demonstration| demonstration.cut_at.is_none())
        .map(|demonstration| {
            let steps = &demonstration.trajectory.steps;
            let header = &demonstration.trajectory.header;
            let last = steps.last().expect("a demonstration has steps");
            (surface_under(header, &steps[0]), surface_under(header, last))
        })
        .collect();
    let files = support::demo_files("cafe", demonstrations);
    let (model, artifacts) = lamp_build::build(&spec, "cafe.lamp", &world, &files)
        .unwrap_or_else(|error| panic!("the demonstrations build: {error}"));
    (model, artifacts, journeys)
});

/// The surface whose top the can stands on in `step` (its origin within the top, 1 mm above).
fn surface_under(header: &TrajectoryHeader, step: &Step) -> String {
    let can = header.body_index("can1").expect("a can");
    let can_pose = &step.body_poses[can];
    header
        .bodies
        .iter()
        .zip(&step.body_poses)
        .find(|(body, pose)| {
            let p = (pose.inverse() * can_pose).translation.vector;
            body.type_name == "surface" && p.x.abs() < 0.45 && p.y.abs() < 0.45 && p.z.abs() < 0.002
        })
        .map(|(body, _)| body.name.clone())
        .expect("the can stands on a surface")
}

/// Height range of the tops above the floor (tables, the counter), which the base stands on.
const TOPS: std::ops::RangeInclusive<f64> = 0.72..=0.91;

/// The one region of the pair whose centre (and held flag) passes `test`.
fn one_region(
    model: &Model,
    (primary, secondary): (&str, &str),
    what: &str,
    test: impl Fn(u8, [f64; 3]) -> bool,
) -> String {
    let found: Vec<&Region> = regions(model, primary, secondary)
        .into_iter()
        .filter(|region| test(region.summary.g, region.summary.centre))
        .collect();
    assert_eq!(found.len(), 1, "one {primary}-{secondary} region: {what}");
    found[0].relation.clone()
}

/// A surface ahead of the base, within arm's reach of its near edge, at a top's height.
fn standing_at(model: &Model) -> String {
    one_region(model, ("base", "surface"), "standing at it", |g, [x, y, z]| {
        g == 0 && (0.6..=1.0).contains(&x) && y.abs() < 0.2 && TOPS.contains(&z)
    })
}

/// The gripper's resting place beside the torso (`tuck`), and nothing else.
fn tucked(model: &Model) -> String {
    let rests = regions(model, "base", "gripper");
    assert_eq!(rests.len(), 1, "tucked, nothing else");
    let [x, y, _] = rests[0].summary.centre;
    assert!(rests[0].summary.g == 0 && x.abs() < 0.3 && y.abs() < 0.3);
    rests[0].relation.clone()
}

/// The gripper at a side grasp (the can's axis 2 cm ahead, its base 10 cm below): held or not.
fn grasp(model: &Model, held: bool) -> String {
    one_region(model, ("gripper", "can"), "at a grasp", |g, [x, y, z]| {
        g == u8::from(held) && x.abs() < 0.13 && y.abs() < 0.01 && (z + 0.10).abs() < 0.01
    })
}

/// A can standing on the top (its frame is at the can's base, the surface's at the top).
fn standing_on(model: &Model) -> String {
    one_region(model, ("surface", "can"), "a can on the top", |g, [x, y, z]| {
        g == 0 && x.abs() < 0.1 && y.abs() < 0.1 && z.abs() < 0.005
    })
}

#[test]
fn relations_read_as_standing_at_tucked_grasp_holding_and_on_and_the_alias_binds() {
    let (model, artifacts, _) = &*CAFE_BUILD;
    let at_surface = standing_at(model);
    let tucked = tucked(model);
    let at_grasp = grasp(model, false);
    let holding = grasp(model, true);
    let on = standing_on(model);
    assert_eq!(artifacts.summary.aliases["on"], on);
    let predicates: Vec<String> = model.predicates().iter().map(|p| p.name.clone()).collect();
    for relation in [&at_surface, &tucked, &at_grasp, &holding, &on] {
        assert!(predicates.contains(relation), "{relation} is a predicate of the domain");
    }
    // A surface holds several cans: no "no can on it" relation; a can stands on one surface at a
    // time: "on no surface" exists.
    assert!(!predicates.iter().any(|name| name.starts_with("clear_surface_can")));
    assert!(predicates.contains(&format!("nowhere_{on}")));
}

#[test]
fn a_can_is_put_on_a_surface_only_from_no_surface_and_lifting_it_off_says_so() {
    let (model, _, _) = &*CAFE_BUILD;
    let on = standing_on(model);
    let on_no_surface = format!("nowhere_{on}");
    // Decided by the shapes: two cans fit on a top at once, a can cannot stand on two tops.
    let sides = model.region(&on).expect("the region").summary.sides;
    assert_eq!((sides.clear.on, sides.clear.reason), (false, SideReason::TwoFit));
    assert_eq!((sides.nowhere.on, sides.nowhere.reason), (true, SideReason::OneAtATime));
    let put_on = actions_changing(model, "surface_can_0", &on)[0];
    let lift_off = actions_changing(model, &on, "surface_can_0")[0];
    let can_atom = |atoms: &[LiftedAtom]| {
        atoms.iter().any(|atom| atom.predicate == on_no_surface && atom.arguments == ["?can_p1"])
    };
    assert!(can_atom(&put_on.preconditions), "put-on requires the can on no surface");
    assert!(can_atom(&put_on.delete), "put-on deletes it");
    assert!(can_atom(&lift_off.add), "lift-off adds it");
    // No "surface empty" precondition anywhere.
    assert!(model.actions.iter().all(|action| !has(&action.preconditions, &format!("clear_{on}"))));
}

#[test]
fn the_demonstrations_carry_cans_from_and_to_the_counter_as_well_as_the_tables() {
    let (_, _, journeys) = &*CAFE_BUILD;
    let from_counter = journeys.iter().filter(|(from, _)| from.starts_with("counter")).count();
    let to_counter = journeys.iter().filter(|(_, to)| to.starts_with("counter")).count();
    assert!(journeys.len() >= 40, "{} full demonstrations", journeys.len());
    assert!(
        from_counter >= 3 && to_counter >= 3,
        "{from_counter} from, {to_counter} to the counter"
    );
    assert!(journeys.iter().all(|(from, to)| from != to));
}

#[test]
fn actions_drive_to_a_surface_grab_release_and_move_cans_while_standing_there() {
    let (model, _, _) = &*CAFE_BUILD;
    let at_surface = standing_at(model);
    let tucked = tucked(model);
    let at_grasp = grasp(model, false);
    let holding = grasp(model, true);
    let on = standing_on(model);
    let shapes = [
        ("drive to a surface", "base_surface_0", at_surface.as_str()),
        ("drive away from a surface", at_surface.as_str(), "base_surface_0"),
        ("untuck", tucked.as_str(), "base_gripper_0"),
        ("tuck", "base_gripper_0", tucked.as_str()),
        ("approach", "gripper_can_0", at_grasp.as_str()),
        ("grab", at_grasp.as_str(), holding.as_str()),
        ("release", holding.as_str(), at_grasp.as_str()),
        ("lift off a surface", on.as_str(), "surface_can_0"),
        ("put on a surface", "surface_can_0", on.as_str()),
    ];
    for (shape, from, to) in shapes {
        let found = actions_changing(model, from, to);
        assert_eq!(found.len(), 1, "one {shape} action: from {from} to {to}");
    }
    for (from, to) in
        [(at_surface.as_str(), "base_surface_0"), ("base_surface_0", at_surface.as_str())]
    {
        let action = actions_changing(model, from, to)[0];
        assert!(has(&action.preconditions, &tucked), "the base drives with the arm tucked");
    }
    for (from, to) in [(on.as_str(), "surface_can_0"), ("surface_can_0", on.as_str())] {
        let action = actions_changing(model, from, to)[0];
        assert!(has(&action.preconditions, &holding), "a can is moved on or off while held");
        assert!(has(&action.preconditions, &at_surface), "a can is moved at the surface");
    }
    assert!(
        (9..=20).contains(&model.actions.len()),
        "about a dozen actions, not {}",
        model.actions.len()
    );
}

fn solve(artifacts: &Artifacts, problem: &str) -> usize {
    let domain = lamp_pddl::parse_domain(artifact(artifacts, "domain.pddl")).expect("parses");
    let path = format!("problems/{problem}.pddl");
    let problem = lamp_pddl::parse_problem(artifact(artifacts, &path), &domain).expect("parses");
    let output = lamp_planner::plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default())
        .expect("plans");
    assert_eq!(output.status, Status::Solved, "{path}");
    let plan = &output.plans[0];
    lamp_planner::validate(&domain, &problem, plan)
        .unwrap_or_else(|error| panic!("{path}: {error}\n{plan}"));
    plan.len()
}

#[test]
fn table_problems_are_solved_by_lamp_planner_with_valid_plans() {
    let (_, artifacts, _) = &*CAFE_BUILD;
    // Per can at least: drive there, approach, grab, lift, drive on, put down, release.
    assert!(solve(artifacts, "cafe2_01") >= 2 * 7);
    assert!(solve(artifacts, "cafe6_01") >= 5 * 7);
}

#[test]
fn domain_and_report_snapshots() {
    let (_, artifacts, _) = &*CAFE_BUILD;
    insta::assert_snapshot!("cafe_domain", artifact(artifacts, "domain.pddl"));
    insta::assert_snapshot!("cafe_vocabulary", artifact(artifacts, "vocabulary.md"));
}
