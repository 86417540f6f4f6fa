//! What is learned from real Packing demonstrations means what a person would name it: relations
//! for the gripper at a grasp, holding a can and the can in the box; actions that approach, grab,
//! carry in, release and retreat (found by their effects, not their names); and the four-can
//! problem is solvable with a plan lamp-planner's validator accepts.

mod support;

use lamp_learn::{LiftedAtom, Model, Region, SideReason};
use lamp_planner::{Algorithm, Budget, Status};

use support::{PACKING_BUILD, actions_changing, artifact, has, regions};

/// How far the gripper link's origin is from the can's origin when the magnet holds it, or is
/// about to: the spec's `grab distance 0.205 m .. 0.215 m` (the magnet touching the can's top),
/// with a millimetre either side for the regions' spread.
const GRAB_DISTANCE: std::ops::RangeInclusive<f64> = 0.204..=0.216;

/// Half the box's inner floor (0.17 m square less its 0.01 m walls), and the height of a can
/// standing on it.
const BOX_HALF_FLOOR: f64 = 0.075;
const STANDING_HEIGHT: f64 = 0.01;

/// The one gripper–can region at grab distance with the given held flag.
fn gripper_can_region(model: &Model, held: bool) -> String {
    let found: Vec<&Region> = regions(model, "gripper", "can")
        .into_iter()
        .filter(|region| region.summary.g == u8::from(held))
        .filter(|region| {
            let [x, y, z] = region.summary.centre;
            GRAB_DISTANCE.contains(&(x * x + y * y + z * z).sqrt())
        })
        .collect();
    assert_eq!(found.len(), 1, "one gripper-can region with held = {held} at grab distance");
    found[0].relation.clone()
}

/// The one surface–can region of a can standing on the box floor.
fn in_box_region(model: &Model) -> String {
    let found: Vec<&Region> = regions(model, "surface", "can")
        .into_iter()
        .filter(|region| {
            let [x, y, z] = region.summary.centre;
            x.abs() < BOX_HALF_FLOOR && y.abs() < BOX_HALF_FLOOR && z.abs() < STANDING_HEIGHT
        })
        .collect();
    assert_eq!(found.len(), 1, "one region of a can standing in the box");
    found[0].relation.clone()
}

#[test]
fn relations_read_as_grasp_holding_and_in_the_box_and_the_alias_binds_the_box_region() {
    let (model, artifacts) = &*PACKING_BUILD;
    let at_grasp = gripper_can_region(model, false);
    let holding = gripper_can_region(model, true);
    assert_ne!(at_grasp, holding);
    let in_box = in_box_region(model);
    assert_eq!(artifacts.summary.aliases["in_box"], in_box, "`in_box` names the box-floor region");
    let predicates: Vec<String> = model.predicates().iter().map(|p| p.name.clone()).collect();
    for relation in [&at_grasp, &holding, &in_box] {
        assert!(predicates.contains(relation), "{relation} is a predicate of the domain");
    }
}

#[test]
fn actions_approach_grab_carry_in_release_and_retreat() {
    let (model, _) = &*PACKING_BUILD;
    let at_grasp = gripper_can_region(model, false);
    let holding = gripper_can_region(model, true);
    let in_box = in_box_region(model);
    let shapes = [
        ("approach", "gripper_can_0", at_grasp.as_str()),
        ("grab", at_grasp.as_str(), holding.as_str()),
        ("release", holding.as_str(), at_grasp.as_str()),
        ("retreat", at_grasp.as_str(), "gripper_can_0"),
        ("carry in", "surface_can_0", in_box.as_str()),
    ];
    for (shape, from, to) in shapes {
        let found = actions_changing(model, from, to);
        assert_eq!(found.len(), 1, "one {shape} action: from {from} to {to}");
    }
    let carry_in = actions_changing(model, "surface_can_0", &in_box)[0];
    assert!(has(&carry_in.preconditions, &holding), "a can is carried into the box while held");
}

#[test]
fn carrying_in_requires_the_can_in_no_box_and_never_an_empty_box() {
    let (model, _) = &*PACKING_BUILD;
    let in_box = in_box_region(model);
    // Decided by the shapes: two cans fit in the box region at once, a can is in one box at a time.
    let sides = model.region(&in_box).expect("the region").summary.sides;
    assert_eq!((sides.clear.on, sides.clear.reason), (false, SideReason::TwoFit));
    assert_eq!((sides.nowhere.on, sides.nowhere.reason), (true, SideReason::OneAtATime));
    let carry_in = actions_changing(model, "surface_can_0", &in_box)[0];
    let in_no_box = LiftedAtom {
        predicate: format!("nowhere_{in_box}"),
        arguments: vec!["?can_p1".to_string()],
    };
    assert!(carry_in.preconditions.contains(&in_no_box), "the can is in no box before");
    assert!(carry_in.delete.contains(&in_no_box), "and in one after");
    let predicates: Vec<String> = model.predicates().iter().map(|p| p.name.clone()).collect();
    assert!(!predicates.iter().any(|name| name.starts_with("clear_surface_can")));
    assert!(model.actions.iter().all(|action| {
        action.preconditions.iter().all(|atom| !atom.predicate.starts_with("clear_surface"))
    }));
}

#[test]
fn the_four_can_problem_is_solved_by_lamp_planner_with_a_valid_plan() {
    let (_, artifacts) = &*PACKING_BUILD;
    let domain = lamp_pddl::parse_domain(artifact(artifacts, "domain.pddl")).expect("parses");
    let problem = lamp_pddl::parse_problem(artifact(artifacts, "problems/pack4_01.pddl"), &domain)
        .expect("parses");
    let output = lamp_planner::plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default())
        .expect("plans");
    assert_eq!(output.status, Status::Solved);
    let plan = &output.plans[0];
    lamp_planner::validate(&domain, &problem, plan)
        .unwrap_or_else(|error| panic!("{error}\n{plan}"));
    // Each can is approached, grabbed, carried in and released at least.
    assert!(plan.len() >= 4 * 4, "{} steps:\n{plan}", plan.len());
}
