//! Demonstrations per second per domain: the time of one demonstration (its whole script,
//! including retries), on one thread. The targets: 200 Packing demonstrations in
//! under 30 s and 200 Café demonstrations in under 3 min on two cores.

#[path = "../tests/support/mod.rs"]
mod support;

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use lamp_demonstrators::{Simulation, generate};

/// One demonstration per iteration, each a new index (so a new layout); the throughput is the
/// mean file size of demonstrations 0–3, so that a run also shows how big the files get.
fn bench_domain(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    domain: &str,
) {
    let (spec, world) = support::domain(domain);
    let simulation = Simulation::from_spec(&spec).unwrap_or_else(|error| panic!("{error}"));
    // Criterion reports bytes per second at this many bytes per iteration; with the time per
    // iteration it gives the size of a demonstration file.
    let bytes: usize = (0..4)
        .map(|index| {
            let demo = generate(&world, &simulation, index).unwrap_or_else(|e| panic!("{e}"));
            demo.to_bytes().unwrap_or_else(|e| panic!("{e}")).len()
        })
        .sum();
    group.throughput(Throughput::Bytes((bytes / 4) as u64));
    let mut index = 0;
    group.bench_function(domain, |b| {
        b.iter(|| {
            index += 1;
            black_box(generate(&world, &simulation, index).map(|demo| demo.trajectory.steps.len()))
        })
    });
}

fn demos(c: &mut Criterion) {
    let mut group = c.benchmark_group("demos");
    group.sample_size(10);
    bench_domain(&mut group, "packing");
    bench_domain(&mut group, "cafe");
    group.finish();
}

criterion_group!(benches, demos);
criterion_main!(benches);
