//! The cost of the C ABI on the hot path of motion planning: a plugin that checks many
//! configurations through the host's callback table, against the same plugin called directly.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use lamp_plugin_api::{
    HostError, HostServices, MotionBudget, MotionOutcome, MotionPlanner, MotionRequest,
    NoPathReason, PluginError,
};
use lamp_plugin_host::PluginLibrary;
use lamp_plugin_sdk::{Descriptor, PluginFactory, in_process_motion_planner};

/// Configurations checked per planning call.
const CHECKS_PER_CALL: u64 = 1000;

/// Valid inside the unit box.
struct UnitBox;

impl HostServices for UnitBox {
    fn configuration_is_valid(&self, _robot: &str, q: &[f64]) -> Result<bool, HostError> {
        Ok(q.iter().all(|coordinate| (0.0..=1.0).contains(coordinate)))
    }
}

/// Checks `max_iterations` configurations on the segment from start to goal.
struct Scanner;

impl PluginFactory for Scanner {
    fn create(_config: &[u8]) -> Result<Self, PluginError> {
        Ok(Scanner)
    }
}

impl MotionPlanner for Scanner {
    fn plan_path(
        &mut self,
        request: &MotionRequest,
        host: &dyn HostServices,
    ) -> Result<MotionOutcome, PluginError> {
        let checks = request.budget.max_iterations.unwrap_or(1);
        let mut q = request.start.clone();
        for step in 0..checks {
            let t = step as f64 / checks as f64;
            for ((value, start), goal) in q.iter_mut().zip(&request.start).zip(&request.goal) {
                *value = start + (goal - start) * t;
            }
            if !host.configuration_is_valid(&request.robot, &q)? {
                let message = format!("blocked at t = {t}");
                return Ok(MotionOutcome::NoPath { reason: NoPathReason::Other, message });
            }
        }
        Ok(MotionOutcome::Path(vec![request.start.clone(), request.goal.clone()]))
    }
}

fn request() -> MotionRequest {
    MotionRequest {
        robot: "arm".into(),
        start: vec![0.1; 7],
        goal: vec![0.9; 7],
        budget: MotionBudget { max_iterations: Some(CHECKS_PER_CALL), time_limit: None },
        seed: 0,
    }
}

fn host_callbacks(criterion: &mut Criterion) {
    let descriptor = Descriptor { name: "scanner", version: "0", description: "" };
    let library =
        PluginLibrary::from_trusted_entry(in_process_motion_planner::<Scanner>(descriptor))
            .expect("the SDK builds a valid entry");
    let mut loaded = library.create_motion_planner(&[]).expect("no configuration needed");
    let request = request();
    let mut group = criterion.benchmark_group("1000 validity checks, 7-dof");
    group.bench_function("direct", |bencher| {
        bencher.iter(|| Scanner.plan_path(black_box(&request), &UnitBox));
    });
    group.bench_function("through the C ABI", |bencher| {
        bencher.iter(|| loaded.plan_path(black_box(&request), &UnitBox));
    });
    group.finish();
}

criterion_group!(benches, host_callbacks);
criterion_main!(benches);
