//! Refiners and motion planners through the C ABI, in process: the SDK builds the entry tables,
//! the host validates and adapts them, and every host oracle call crosses the callback table.
//! Each answer through the ABI must equal the answer of the same plugin called directly.

use std::f64::consts::TAU;

use lamp_plugin_api::{
    Candidate, CandidateStream, GroundedAction, HostError, HostServices, MinimalHost, MotionBudget,
    MotionOutcome, MotionPlanner, MotionRequest, NoPathReason, ObjectState, PluginError, Pose,
    RefineRequest, Refiner, RobotState, RobotTarget, WorldState,
};
use lamp_plugin_host::{LoadError, PluginKind, PluginLibrary};
use lamp_plugin_sdk::{Descriptor, PluginFactory, in_process_motion_planner, in_process_refiner};
use miette::Diagnostic;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const ROBOT: &str = "point";
const TOOL: &str = "tool";
const WORLD_SIZE: f64 = 10.0;
const OBSTACLE_CENTER: [f64; 2] = [5.0, 5.0];
const OBSTACLE_RADIUS: f64 = 1.5;
const EDGE_RESOLUTION: f64 = 0.05;
const RING_RADIUS: f64 = 2.0;
const RING_SAMPLES: usize = 32;
const TOLERANCE: f64 = 1e-12;

/// A point robot in a 10 m square with a round obstacle: configuration [x, y], tool at (x, y, 0).
struct PointWorld;

impl PointWorld {
    fn check_robot(robot: &str) -> Result<(), HostError> {
        if robot == ROBOT { Ok(()) } else { Err(HostError::failed(format!("no robot `{robot}`"))) }
    }
}

impl HostServices for PointWorld {
    fn configuration_is_valid(&self, robot: &str, q: &[f64]) -> Result<bool, HostError> {
        Self::check_robot(robot)?;
        let inside = q.iter().all(|coordinate| (0.0..=WORLD_SIZE).contains(coordinate));
        let clear = (q[0] - OBSTACLE_CENTER[0]).hypot(q[1] - OBSTACLE_CENTER[1]) > OBSTACLE_RADIUS;
        Ok(q.len() == 2 && inside && clear)
    }
    fn edge_is_valid(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<bool, HostError> {
        let steps = (self.distance(robot, a, b)? / EDGE_RESOLUTION).ceil().max(1.0) as usize;
        for step in 0..=steps {
            let q = self.interpolate(robot, a, b, step as f64 / steps as f64)?;
            if !self.configuration_is_valid(robot, &q)? {
                return Ok(false);
            }
        }
        Ok(true)
    }
    fn solve_ik(
        &self,
        robot: &str,
        link: &str,
        target: &Pose,
        _seed: &[f64],
    ) -> Result<Option<Vec<f64>>, HostError> {
        Self::check_robot(robot)?;
        if link != TOOL {
            return Err(HostError::failed(format!("no link `{link}`")));
        }
        let q = vec![target[0], target[1]];
        Ok(self.configuration_is_valid(robot, &q)?.then_some(q))
    }
    fn forward_kinematics(&self, robot: &str, q: &[f64], link: &str) -> Result<Pose, HostError> {
        Self::check_robot(robot)?;
        if link != TOOL {
            return Err(HostError::failed(format!("no link `{link}`")));
        }
        Ok([q[0], q[1], 0.0, 0.0, 0.0, 0.0, 1.0])
    }
    fn distance(&self, robot: &str, a: &[f64], b: &[f64]) -> Result<f64, HostError> {
        Self::check_robot(robot)?;
        Ok((a[0] - b[0]).hypot(a[1] - b[1]))
    }
    fn interpolate(
        &self,
        robot: &str,
        a: &[f64],
        b: &[f64],
        t: f64,
    ) -> Result<Vec<f64>, HostError> {
        Self::check_robot(robot)?;
        Ok(a.iter().zip(b).map(|(a, b)| a + (b - a) * t).collect())
    }
}

/// Refines `(reach ?robot ?object ?link)` by tool poses on a ring around the object, at random
/// angles, keeping those the host's inverse kinematics reaches.
struct RingRefiner;

struct RingStream {
    robot: String,
    link: String,
    center: [f64; 2],
    rng: ChaCha8Rng,
    remaining: usize,
}

impl CandidateStream for RingStream {
    fn next(&mut self, host: &dyn HostServices) -> Result<Option<Candidate>, PluginError> {
        while self.remaining > 0 {
            self.remaining -= 1;
            let angle = TAU * self.rng.random::<f64>();
            let target = [
                self.center[0] + RING_RADIUS * angle.cos(),
                self.center[1] + RING_RADIUS * angle.sin(),
                0.0,
                0.0,
                0.0,
                0.0,
                1.0,
            ];
            // An empty seed leaves the start to the host (and makes the SDK grow its buffer).
            if let Some(configuration) = host.solve_ik(&self.robot, &self.link, &target, &[])? {
                let targets = vec![RobotTarget { robot: self.robot.clone(), configuration }];
                return Ok(Some(Candidate { targets, ..Candidate::default() }));
            }
        }
        Ok(None)
    }
}

impl Refiner for RingRefiner {
    fn refine(
        &mut self,
        request: &RefineRequest,
        host: &dyn HostServices,
    ) -> Result<Box<dyn CandidateStream>, PluginError> {
        host.report_progress(0.0, "opening a ring stream");
        let [robot, object, link] = request.action.arguments.as_slice() else {
            return Err(PluginError::invalid_request("reach takes a robot, an object and a link"));
        };
        let object = request
            .world
            .object(object)
            .ok_or_else(|| PluginError::invalid_request(format!("no object {object}")))?;
        Ok(Box::new(RingStream {
            robot: robot.clone(),
            link: link.clone(),
            center: [object.pose[0], object.pose[1]],
            rng: ChaCha8Rng::seed_from_u64(request.seed),
            remaining: RING_SAMPLES,
        }))
    }
}

impl PluginFactory for RingRefiner {
    fn create(_config: &[u8]) -> Result<Self, PluginError> {
        Ok(RingRefiner)
    }
}

/// Tries the straight edge, then random via points, one per iteration.
struct ViaPointPlanner;

impl MotionPlanner for ViaPointPlanner {
    fn plan_path(
        &mut self,
        request: &MotionRequest,
        host: &dyn HostServices,
    ) -> Result<MotionOutcome, PluginError> {
        let (robot, start, goal) = (&request.robot, &request.start, &request.goal);
        let no_path = |reason, message: &str| {
            Ok(MotionOutcome::NoPath { reason, message: message.to_string() })
        };
        if !host.configuration_is_valid(robot, start)? {
            return no_path(NoPathReason::StartInvalid, "the start collides");
        }
        if !host.configuration_is_valid(robot, goal)? {
            return no_path(NoPathReason::GoalInvalid, "the goal collides");
        }
        if host.edge_is_valid(robot, start, goal)? {
            return Ok(MotionOutcome::Path(vec![start.clone(), goal.clone()]));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(request.seed);
        for _ in 0..request.budget.max_iterations.unwrap_or(u64::MAX) {
            let via: Vec<f64> =
                (0..start.len()).map(|_| WORLD_SIZE * rng.random::<f64>()).collect();
            if host.edge_is_valid(robot, start, &via)? && host.edge_is_valid(robot, &via, goal)? {
                return Ok(MotionOutcome::Path(vec![start.clone(), via, goal.clone()]));
            }
        }
        no_path(NoPathReason::BudgetExhausted, "no via point found")
    }
}

impl PluginFactory for ViaPointPlanner {
    fn create(_config: &[u8]) -> Result<Self, PluginError> {
        Ok(ViaPointPlanner)
    }
}

fn descriptor(name: &'static str) -> Descriptor {
    Descriptor { name, version: "0.1.0", description: "test plugin" }
}

fn reach_request(object_x: f64, seed: u64) -> RefineRequest {
    let action = GroundedAction {
        name: "reach".into(),
        arguments: vec![ROBOT.into(), "can1".into(), TOOL.into()],
        preconditions: Vec::new(),
        negative_preconditions: Vec::new(),
        add_effects: Vec::new(),
        delete_effects: Vec::new(),
    };
    let world = WorldState {
        robots: vec![RobotState {
            name: ROBOT.into(),
            configuration: vec![1.0, 1.0],
            held: Vec::new(),
            parts: Vec::new(),
        }],
        objects: vec![ObjectState {
            name: "can1".into(),
            object_type: "can".into(),
            pose: [object_x, 5.0, 0.0, 0.0, 0.0, 0.0, 1.0],
        }],
    };
    RefineRequest { action, world, seed }
}

fn drain(stream: &mut dyn CandidateStream, host: &dyn HostServices) -> Vec<Candidate> {
    std::iter::from_fn(|| stream.next(host).expect("the stream yields")).collect()
}

fn loaded_refiner() -> Box<dyn Refiner> {
    let library = PluginLibrary::from_trusted_entry(in_process_refiner::<RingRefiner>(descriptor(
        "ring-refiner",
    )))
    .expect("the SDK builds a valid entry");
    assert_eq!(library.info().kind, PluginKind::Refiner);
    assert_eq!(library.info().origin, "in-process");
    library.create_refiner(&[]).expect("the refiner takes an empty configuration")
}

fn loaded_motion_planner() -> Box<dyn MotionPlanner> {
    let entry = in_process_motion_planner::<ViaPointPlanner>(descriptor("via-point"));
    let library = PluginLibrary::from_trusted_entry(entry).expect("the SDK builds a valid entry");
    library.create_motion_planner(&[]).expect("the planner takes an empty configuration")
}

#[test]
fn refiner_streams_through_the_abi_equal_direct_calls() {
    let mut loaded = loaded_refiner();
    // The ring around (7.5, 5) passes through the obstacle, so some samples are rejected.
    let request = reach_request(7.5, 11);
    let through_abi = drain(loaded.refine(&request, &PointWorld).unwrap().as_mut(), &PointWorld);
    let direct = drain(RingRefiner.refine(&request, &PointWorld).unwrap().as_mut(), &PointWorld);
    assert_eq!(through_abi, direct);
    assert!(
        !through_abi.is_empty() && through_abi.len() < RING_SAMPLES,
        "{} candidates",
        through_abi.len()
    );
    for candidate in &through_abi {
        let q = &candidate.targets[0].configuration;
        assert!(PointWorld.configuration_is_valid(ROBOT, q).unwrap());
        assert!(((q[0] - 7.5).hypot(q[1] - 5.0) - RING_RADIUS).abs() < TOLERANCE);
    }
}

#[test]
fn streams_resume_after_backtracking_and_follow_the_seed() {
    let mut loaded = loaded_refiner();
    let request = reach_request(2.5, 3);
    let all = drain(loaded.refine(&request, &PointWorld).unwrap().as_mut(), &PointWorld);
    // Two streams open at once, consumed alternately, continue independently where they stopped.
    let mut first = loaded.refine(&request, &PointWorld).unwrap();
    let mut second = loaded.refine(&request, &PointWorld).unwrap();
    assert_eq!(first.next(&PointWorld).unwrap().as_ref(), Some(&all[0]));
    assert_eq!(first.next(&PointWorld).unwrap().as_ref(), Some(&all[1]));
    assert_eq!(second.next(&PointWorld).unwrap().as_ref(), Some(&all[0]));
    assert_eq!(first.next(&PointWorld).unwrap().as_ref(), Some(&all[2]));
    assert_eq!(drain(first.as_mut(), &PointWorld), all[3..].to_vec());
    assert_eq!(first.next(&PointWorld).unwrap(), None);
    // Streams outlive the refiner that opened them.
    drop(loaded);
    assert_eq!(second.next(&PointWorld).unwrap().as_ref(), Some(&all[1]));
    // Another seed samples other angles.
    let other = drain(
        RingRefiner.refine(&reach_request(2.5, 4), &PointWorld).unwrap().as_mut(),
        &PointWorld,
    );
    assert_ne!(other, all);
}

#[test]
fn host_and_plugin_errors_cross_the_boundary_typed() {
    let mut loaded = loaded_refiner();
    let mut request = reach_request(2.5, 3);
    request.action.arguments[2] = "elbow".into();
    let mut stream = loaded.refine(&request, &PointWorld).unwrap();
    assert_eq!(
        stream.next(&PointWorld),
        Err(PluginError::Host(HostError::failed("no link `elbow`")))
    );
    let mut stream = loaded.refine(&reach_request(2.5, 3), &MinimalHost).unwrap();
    assert_eq!(
        stream.next(&MinimalHost),
        Err(PluginError::Host(HostError::unsupported("solve_ik")))
    );
    request.action.arguments.pop();
    assert_eq!(
        loaded.refine(&request, &PointWorld).err(),
        Some(PluginError::invalid_request("reach takes a robot, an object and a link"))
    );
    // A world the host cannot even write is refused before the plugin sees it.
    request.world.objects[0].pose[0] = f64::NAN;
    assert!(matches!(
        loaded.refine(&request, &PointWorld).err(),
        Some(PluginError::InvalidRequest { .. })
    ));
}

#[test]
fn motion_planning_through_the_abi_equals_direct_calls() {
    let mut loaded = loaded_motion_planner();
    let mut request = MotionRequest {
        robot: ROBOT.into(),
        start: vec![1.0, 5.0],
        goal: vec![9.0, 5.0],
        budget: MotionBudget { max_iterations: Some(1000), time_limit: None },
        seed: 5,
    };
    let outcome = loaded.plan_path(&request, &PointWorld).unwrap();
    assert_eq!(outcome, ViaPointPlanner.plan_path(&request, &PointWorld).unwrap());
    let MotionOutcome::Path(path) = outcome else { panic!("no path: {outcome:?}") };
    assert_eq!(path.len(), 3, "the obstacle blocks the straight edge");
    assert_eq!(
        (path[0].as_slice(), path[2].as_slice()),
        ([1.0, 5.0].as_slice(), [9.0, 5.0].as_slice())
    );
    for edge in path.windows(2) {
        assert!(PointWorld.edge_is_valid(ROBOT, &edge[0], &edge[1]).unwrap());
    }

    request.goal = vec![1.0, 9.0];
    assert_eq!(
        loaded.plan_path(&request, &PointWorld).unwrap(),
        MotionOutcome::Path(vec![vec![1.0, 5.0], vec![1.0, 9.0]])
    );
    request.goal = vec![5.0, 5.5];
    assert_eq!(
        loaded.plan_path(&request, &PointWorld).unwrap(),
        MotionOutcome::NoPath {
            reason: NoPathReason::GoalInvalid,
            message: "the goal collides".into()
        }
    );
    request.goal = vec![9.0, 5.0];
    request.budget.max_iterations = Some(0);
    assert!(matches!(
        loaded.plan_path(&request, &PointWorld).unwrap(),
        MotionOutcome::NoPath { reason: NoPathReason::BudgetExhausted, .. }
    ));
    request.robot = "arm".into();
    assert_eq!(
        loaded.plan_path(&request, &PointWorld),
        Err(PluginError::Host(HostError::failed("no robot `arm`")))
    );
}

#[test]
fn in_process_entries_are_validated_like_loaded_ones() {
    let entry = in_process_refiner::<RingRefiner>(descriptor(" "));
    let error = PluginLibrary::from_trusted_entry(entry).unwrap_err();
    assert!(
        matches!(&error, LoadError::InvalidDescriptor { problem, .. } if problem == "the name is empty")
    );
    let library = PluginLibrary::from_trusted_entry(in_process_motion_planner::<ViaPointPlanner>(
        descriptor("via-point"),
    ))
    .unwrap();
    assert!(matches!(
        library.create_planner(&[]),
        Err(LoadError::WrongKind { found: PluginKind::MotionPlanner, .. })
    ));
}

/// Returns the error its configuration names, to check every error crosses the ABI intact.
struct FailingPlanner {
    error: PluginError,
}

impl PluginFactory for FailingPlanner {
    fn create(config: &[u8]) -> Result<Self, PluginError> {
        let error = match config {
            b"invalid" => PluginError::invalid_request("bad domain"),
            b"unsupported" => PluginError::Host(HostError::unsupported("solve_ik")),
            b"host" => PluginError::Host(HostError::failed("no robot `arm`")),
            b"cancelled" => PluginError::Cancelled,
            b"panicked" => PluginError::Panicked { message: "reported as a panic".into() },
            b"failed" => PluginError::failed("out of ideas"),
            b"panic" => panic!("create panicked deliberately"),
            other => return Err(PluginError::invalid_request(format!("unknown case {other:?}"))),
        };
        Ok(Self { error })
    }
}

impl lamp_plugin_api::Planner for FailingPlanner {
    fn plan(
        &mut self,
        _request: &lamp_plugin_api::PlanRequest,
        _host: &dyn HostServices,
    ) -> Result<lamp_plugin_api::PlanResponse, PluginError> {
        Err(self.error.clone())
    }
}

#[test]
fn every_plugin_error_crosses_the_abi_unchanged() {
    let entry = lamp_plugin_sdk::in_process_planner::<FailingPlanner>(descriptor("failing"));
    let library = PluginLibrary::from_trusted_entry(entry).expect("the SDK builds a valid entry");
    let request = lamp_plugin_api::PlanRequest::new("(define (domain d))", "(define (problem p))");
    for case in ["invalid", "unsupported", "host", "cancelled", "panicked", "failed"] {
        let expected = FailingPlanner::create(case.as_bytes()).expect("a known case").error;
        let mut planner = library.create_planner(case.as_bytes()).expect("a known case");
        assert_eq!(planner.plan(&request, &MinimalHost), Err(expected), "{case}");
    }
    let Err(LoadError::Create { source, .. }) = library.create_planner(b"other") else {
        panic!("an unknown case must be refused")
    };
    assert_eq!(source, PluginError::invalid_request("unknown case [111, 116, 104, 101, 114]"));
    let Err(error) = library.create_planner(b"panic") else { panic!("a panic must be reported") };
    assert_eq!(
        error.code().map(|code| code.to_string()).as_deref(),
        Some("lamp::plugin::panicked")
    );
    assert!(matches!(
        error,
        LoadError::Panicked { message, .. } if message == "create panicked deliberately"
    ));
}

/// Samples `dimension` coordinates uniformly in [0, 10) from its own generator seeded with the
/// seed it is given, and offers nothing else.
struct UniformBox {
    dimension: usize,
}

impl HostServices for UniformBox {
    fn sample_configuration(&self, robot: &str, seed: u64) -> Result<Vec<f64>, HostError> {
        PointWorld::check_robot(robot)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        Ok((0..self.dimension).map(|_| WORLD_SIZE * rng.random::<f64>()).collect())
    }
}

/// Answers with the host's samples for the request's seed, the seed after it, and the seed again:
/// a path of three waypoints that shows what crossed the boundary.
struct SamplingProbe;

impl MotionPlanner for SamplingProbe {
    fn plan_path(
        &mut self,
        request: &MotionRequest,
        host: &dyn HostServices,
    ) -> Result<MotionOutcome, PluginError> {
        let seeds = [request.seed, request.seed.wrapping_add(1), request.seed];
        let samples = seeds.map(|seed| host.sample_configuration(&request.robot, seed));
        Ok(MotionOutcome::Path(samples.into_iter().collect::<Result<_, _>>()?))
    }
}

impl PluginFactory for SamplingProbe {
    fn create(_config: &[u8]) -> Result<Self, PluginError> {
        Ok(SamplingProbe)
    }
}

#[test]
fn sampled_configurations_cross_the_abi_and_a_host_without_sampling_is_unsupported() {
    let entry = in_process_motion_planner::<SamplingProbe>(descriptor("sampling-probe"));
    let library = PluginLibrary::from_trusted_entry(entry).expect("the SDK builds a valid entry");
    let mut loaded = library.create_motion_planner(&[]).unwrap();
    // 2 values fit the SDK's first buffer; 40 make it grow.
    for dimension in [2, 40] {
        let host = UniformBox { dimension };
        let request = MotionRequest {
            robot: ROBOT.into(),
            start: vec![0.0; dimension],
            goal: vec![0.0; dimension],
            budget: MotionBudget::default(),
            seed: 21,
        };
        let outcome = loaded.plan_path(&request, &host).unwrap();
        assert_eq!(outcome, SamplingProbe.plan_path(&request, &host).unwrap());
        let MotionOutcome::Path(samples) = outcome else { panic!("the probe always answers") };
        assert_eq!(samples[0], samples[2], "the same seed gives the same configuration");
        assert_ne!(samples[0], samples[1]);
        assert!(samples[0].iter().all(|x| (0.0..WORLD_SIZE).contains(x)));

        let unknown = MotionRequest { robot: "arm".into(), ..request.clone() };
        assert_eq!(
            loaded.plan_path(&unknown, &host),
            Err(PluginError::Host(HostError::failed("no robot `arm`")))
        );
        // Hosts that implement every other oracle but not sampling answer `Unsupported`.
        assert_eq!(
            loaded.plan_path(&request, &PointWorld),
            Err(PluginError::Host(HostError::unsupported("sample_configuration")))
        );
    }
}
