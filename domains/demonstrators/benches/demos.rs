//! Demonstrations per second per domain: the time of one demonstration (its whole script,
//! including retries), on one thread. The targets: 200 Packing demonstrations in
//! under 30 s and 200 Café demonstrations in under 3 min on two cores.

#[path = "../tests/support/mod.rs"]
mod support;

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use lamp_demonstrators::{Simulation, generate};

fn demos(c: &mut Criterion) {
    let mut group = c.benchmark_group("demos");
    group.sample_size(10);
    {
        let domain = "packing";
        let (spec, world) = support::domain(domain);
        let simulation = Simulation::from_spec(&spec).unwrap_or_else(|error| panic!("{error}"));
        let mut index = 0;
        group.bench_function(domain, |b| {
            b.iter(|| {
                index += 1;
                black_box(
                    generate(&world, &simulation, index).map(|demo| demo.trajectory.steps.len()),
                )
            })
        });
    }
    group.finish();
}

criterion_group!(benches, demos);
criterion_main!(benches);
