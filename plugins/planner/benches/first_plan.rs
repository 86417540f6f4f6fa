//! Time to first plan (parse, ground and search) on the paper's learned domains (Café with 18 cans,
//! Packing with 4 cans), on the Café domain `lampc build` learns from the bundled spec's 200
//! demonstrations with its 18-can problem (`cafe-learned-*`, copied from `domains/cafe/build/`),
//! and fifty plans for Packing. `fast_downward.py` next to this file times Fast Downward on the same
//! files for a ratio.

use criterion::{Criterion, criterion_group, criterion_main};
use lamp_pddl::{parse_domain, parse_problem};
use lamp_planner::{Algorithm, Budget, Status, plan};

fn fixture(name: &str) -> String {
    let path = format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|error| panic!("reading {path}: {error}"))
}

fn first_plan(criterion: &mut Criterion) {
    for (label, domain_file, problem_file) in [
        ("cafe-18", "cafe-domain.pddl", "cafe-18.pddl"),
        ("cafe-learned-18", "cafe-learned-domain.pddl", "cafe-learned-18.pddl"),
        ("packing-4", "packing-domain.pddl", "packing-4.pddl"),
    ] {
        let domain_text = fixture(domain_file);
        let problem_text = fixture(problem_file);
        criterion.bench_function(&format!("first plan {label}"), |bencher| {
            bencher.iter(|| {
                let domain = parse_domain(&domain_text).expect("valid domain");
                let problem = parse_problem(&problem_text, &domain).expect("valid problem");
                let output = plan(&domain, &problem, Algorithm::GbfsFf, &Budget::default())
                    .expect("valid task");
                assert_eq!(output.status, Status::Solved);
                output
            });
        });
    }
}

/// Fifty distinct plans for Packing with 4 cans (the batch size the LAMP authors consume K* plans in).
fn top_fifty(criterion: &mut Criterion) {
    let domain = parse_domain(&fixture("packing-domain.pddl")).expect("valid domain");
    let problem = parse_problem(&fixture("packing-4.pddl"), &domain).expect("valid problem");
    criterion.bench_function("top-50 packing-4", |bencher| {
        bencher.iter(|| {
            let output = plan(&domain, &problem, Algorithm::TopK { k: 50 }, &Budget::default())
                .expect("valid task");
            assert_eq!(output.plans.len(), 50);
            output
        });
    });
}

criterion_group!(benches, first_plan, top_fifty);
criterion_main!(benches);
