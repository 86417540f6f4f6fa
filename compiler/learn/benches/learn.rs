//! Learning speed on the synthetic Packing-like task: the whole pipeline, and abstraction of one snapshot.

use criterion::{Criterion, criterion_group, criterion_main};
use lamp_learn::synthetic::{packing_config, packing_demonstrations, packing_shapes};
use lamp_learn::{abstract_state, learn};

fn learning(c: &mut Criterion) {
    let config = packing_config();
    let shapes = packing_shapes();
    for count in [40, 200] {
        let demonstrations = packing_demonstrations(count, 11);
        c.bench_function(&format!("learn packing, {count} demonstrations"), |b| {
            b.iter(|| learn(&demonstrations, &config, &shapes).expect("learns"))
        });
    }
    let demonstrations = packing_demonstrations(40, 11);
    let model = learn(&demonstrations, &config, &shapes).expect("learns");
    let demonstration = &demonstrations[0];
    c.bench_function("abstract one snapshot", |b| {
        b.iter(|| {
            abstract_state(&model, &demonstration.participants, &demonstration.steps[5])
                .expect("fits")
        })
    });
}

criterion_group!(benches, learning);
criterion_main!(benches);
