//! `lampc build` of a spec whose demonstrations are ROS 2 bags read through a frame mapping
//! (`files "…" as ros2 { … }`): the files `lampc demos` writes, read only through their standard
//! channels, learn the domain the same files learn read natively; a mapping that names a frame
//! the bags lack is a diagnostic naming the frame.

mod common;

use std::path::{Path, PathBuf};

use common::lampc;

fn packing_spec() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/packing/packing.lamp")
}

/// The Packing spec in `scratch`, its robot file found where it is, its demonstrations the files
/// of `source`.
fn spec_with(scratch: &Path, name: &str, source: &str) -> PathBuf {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots/");
    let text = std::fs::read_to_string(packing_spec())
        .expect("the bundled spec")
        .replace("\"../robots/", &format!("\"{}/", robots.display()))
        .replace("  simulate packing { count 200  cut 0.5  objects 1  seed 11 }", source);
    assert!(text.contains(source), "the spec's demonstrations block changed");
    let path = scratch.join(name);
    std::fs::write(&path, text).expect("writes the spec");
    path
}

fn domain_without_comments(build: &Path) -> String {
    let text = std::fs::read_to_string(build.join("model/domain.pddl")).expect("a domain");
    text.lines().filter(|line| !line.starts_with(';')).collect::<Vec<_>>().join("\n")
}

fn mapping(can_frame: &str) -> String {
    format!(
        "  files \"demos/*.mcap\" as ros2 {{\n    object table table1\n    object surface box1\n    object can can1 frame \"{can_frame}\"\n    robot gripper frame \"gripper_link\" held topic \"/lamp/held\"\n  }}"
    )
}

#[test]
fn bags_read_through_their_standard_channels_learn_the_native_domain() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let demos = scratch.path().join("demos");
    let output = lampc([
        "demos".as_ref(),
        packing_spec().as_os_str(),
        "--count".as_ref(),
        "20".as_ref(),
        "--out".as_ref(),
        demos.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));

    let native = spec_with(scratch.path(), "native.lamp", "  files \"demos/*.mcap\"");
    let output = lampc([
        "build".as_ref(),
        native.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("native").as_os_str(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let bags = spec_with(scratch.path(), "bags.lamp", &mapping("can1"));
    let output = lampc([
        "build".as_ref(),
        bags.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("bags").as_os_str(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let domain = domain_without_comments(&scratch.path().join("native"));
    assert!(domain.contains("(:action"), "{domain}");
    assert_eq!(domain_without_comments(&scratch.path().join("bags")), domain);

    // The mapping is what reads them: a frame the bags lack is named.
    let wrong = spec_with(scratch.path(), "wrong.lamp", &mapping("can_7"));
    let output = lampc([
        "build".as_ref(),
        wrong.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("wrong").as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("lamp::ros2::missing_frame"), "{stderr}");
    assert!(stderr.contains("frame `can_7` never appears on `/tf` or `/tf_static`"), "{stderr}");
}
