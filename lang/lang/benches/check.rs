//! Parse + check time of the largest bundled spec (target: well under 10 ms).

use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};

/// The real file system, read once into memory so the benchmark measures the front end alone.
fn preloaded(spec: &Path) -> (String, lamp_lang::MemoryLoader) {
    let root = spec.parent().expect("a spec lives in a folder").to_path_buf();
    let mut files: Vec<(PathBuf, String)> = Vec::new();
    for robot in ["fetch", "yumi", "magnetic_gripper", "two_finger_gripper"] {
        files.push((root.join(format!("../robots/{robot}.urdf")), String::new()));
    }
    let text = std::fs::read_to_string(spec).expect("the bundled spec is readable");
    (text, lamp_lang::MemoryLoader::new(files))
}

fn largest_spec() -> PathBuf {
    let domains = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains");
    ["packing", "cafe", "keva", "jenga", "dinner"]
        .iter()
        .map(|d| domains.join(d).join(format!("{d}.lamp")))
        .max_by_key(|path| std::fs::metadata(path).map(|m| m.len()).unwrap_or(0))
        .expect("five bundled specs")
}

fn bench(c: &mut Criterion) {
    let spec = largest_spec();
    let (text, loader) = preloaded(&spec);
    let base = spec.parent().expect("a spec lives in a folder").to_path_buf();
    c.bench_function("parse_and_check_largest_spec", |b| {
        b.iter(|| {
            let outcome = lamp_lang::check_source("spec.lamp", &text, &base, &loader);
            assert!(outcome.spec.is_some());
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
