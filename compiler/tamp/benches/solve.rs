//! End-to-end solve time on Packing: four cans into the box, from the model learned on the
//! shared set-up's demonstrations (plan, refine with IK and RRT-Connect, validate by replay).
//! Target: median ≤ 5 s per four-can problem.

#[path = "../tests/support/learned.rs"]
mod learned;

use criterion::{Criterion, criterion_group, criterion_main};

fn four_cans(c: &mut Criterion) {
    // Learn once, outside the measurement.
    let _ = &*learned::PACKING;
    let mut group = c.benchmark_group("solve_packing");
    group.sample_size(10);
    for name in ["pack4_01", "pack4_05", "pack4_09", "pack4_12"] {
        group.bench_function(name, |b| {
            b.iter(|| learned::solve_problem(&learned::PACKING, name, 1).expect("solved"));
        });
    }
    group.finish();
}

criterion_group!(benches, four_cans);
criterion_main!(benches);
