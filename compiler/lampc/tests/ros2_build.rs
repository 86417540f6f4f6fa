//! `lampc build` of a spec whose demonstrations are ROS 2 bags read through a frame mapping
//! (`files "…" as ros2 { … }`): the files `lampc demos` writes, read only through their standard
//! channels, learn the domain the same files learn read natively, also from `--demos DIR` when
//! the bags hold only standard messages, and `lampc eval` and `lampc render` read them too; a
//! mapping that names a frame no bag records is a diagnostic naming the frame at its line in the
//! spec, and an object that only some bags record is absent from the others' demonstrations.

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
        .replace(
            "  simulate packing { count 200  cut 0.5  objects 1  seed 11  rate 50 Hz }",
            source,
        );
    assert!(text.contains(source), "the spec's demonstrations block changed");
    let path = scratch.join(name);
    std::fs::write(&path, text).expect("writes the spec");
    path
}

fn domain_without_comments(build: &Path) -> String {
    let text = std::fs::read_to_string(build.join("model/domain.pddl")).expect("a domain");
    text.lines().filter(|line| !line.starts_with(';')).collect::<Vec<_>>().join("\n")
}

/// Twenty of the bundled Packing spec's demonstrations, written by `lampc demos` into `out`.
fn demonstrate(out: &Path) {
    let output = lampc([
        "demos".as_ref(),
        packing_spec().as_os_str(),
        "--count".as_ref(),
        "20".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
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
    demonstrate(&demos);

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

    // The same files without /lamp/world and the lamp record: plain bags, from --demos DIR.
    let plain = scratch.path().join("plain");
    std::fs::create_dir_all(&plain).expect("a folder");
    for entry in std::fs::read_dir(&demos).expect("the demonstrations") {
        let path = entry.expect("an entry").path();
        let bytes = std::fs::read(&path).expect("readable");
        let keep = |topic: &str, time| (topic != lamp_trajectory::WORLD_TOPIC).then_some(time);
        let bag = lamp_trajectory::filter_bag(&bytes, "bag", keep).expect("a bag");
        std::fs::write(plain.join(path.file_name().expect("a name")), bag).expect("writes");
    }
    let output = lampc([
        "build".as_ref(),
        bags.as_os_str(),
        "--demos".as_ref(),
        plain.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("plain_build").as_os_str(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(domain_without_comments(&scratch.path().join("plain_build")), domain);
    // A frame none of them records is named with the folder they were read from, at the
    // mapping's line.
    let wrong_mapping =
        mapping("can1").replace("object table table1", "object table table1 frame \"table_7\"");
    let wrong = spec_with(scratch.path(), "wrong.lamp", &wrong_mapping);
    let output = lampc([
        "build".as_ref(),
        wrong.as_os_str(),
        "--demos".as_ref(),
        plain.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("wrong").as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("lamp::ros2::frame_in_no_bag"), "{stderr}");
    assert!(stderr.contains("plain/*.mcap`"), "{stderr}");
    assert!(stderr.contains("no bag records this frame"), "{stderr}");
    // Without a mapping, such a bag is no demonstration file.
    let output = lampc([
        "build".as_ref(),
        native.as_os_str(),
        "--demos".as_ref(),
        plain.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("unmapped").as_os_str(),
    ]);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("lamp::trajectory::schema"));

    // lampc render draws such a bag through the spec's mapping too, and without one refuses it.
    let bag =
        std::fs::read_dir(&plain).expect("the bags").next().expect("a bag").expect("an entry");
    let drawing = scratch.path().join("bag.svg");
    let render = |spec: &Path| {
        lampc([
            "render".as_ref(),
            bag.path().as_os_str(),
            "--spec".as_ref(),
            spec.as_os_str(),
            "--out".as_ref(),
            drawing.as_os_str(),
        ])
    };
    let output = render(&bags);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(String::from_utf8_lossy(&output.stdout).contains("drew step"));
    let svg = std::fs::read_to_string(&drawing).expect("the drawing");
    assert!(svg.starts_with("<svg") && svg.contains("</svg>"), "{svg}");
    let output = render(&native);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("lamp::trajectory::schema"));

    // lampc eval reads the pool of a ros2 source through the mapping too.
    std::fs::remove_dir_all(&demos).expect("removes the lamp files");
    std::fs::rename(&plain, &demos).expect("the bags take their place");
    let output = lampc([
        "eval".as_ref(),
        bags.as_os_str(),
        "--demos".as_ref(),
        "10".as_ref(),
        "--runs".as_ref(),
        "1".as_ref(),
        "--problems".as_ref(),
        "pack4_03".as_ref(),
        "--jobs".as_ref(),
        "1".as_ref(),
        "--out".as_ref(),
        scratch.path().join("eval").as_os_str(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(scratch.path().join("eval/eval.json").is_file());

    // The mapping is what reads them: a frame no bag records is named, at its line in the spec.
    let output = lampc([
        "build".as_ref(),
        wrong.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("wrong").as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("lamp::ros2::frame_in_no_bag"), "{stderr}");
    assert!(
        stderr.contains("frame `table_7` of object `table1` has no transform on `/tf` or `/tf_static` in any of the 20 bag(s) of `demos/*.mcap`"),
        "{stderr}"
    );
    assert!(stderr.contains("object table table1 frame \"table_7\""), "{stderr}");
    assert!(stderr.contains("no bag records this frame"), "{stderr}");
}

/// Scenes with different numbers of objects under one mapping: a second can stands in half of
/// the bags; the build learns from all of them and says how many lacked it.
#[test]
fn an_object_some_bags_lack_is_absent_and_counted() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let demos = scratch.path().join("native");
    demonstrate(&demos);
    let (_, world) = lamp_test_support::domain("packing");
    let bags = scratch.path().join("demos");
    std::fs::create_dir_all(&bags).expect("a folder");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&demos)
        .expect("the demonstrations")
        .map(|entry| entry.expect("an entry").path())
        .collect();
    paths.sort();
    for (index, path) in paths.iter().enumerate() {
        let bytes = std::fs::read(path).expect("readable");
        let mut trajectory =
            lamp_trajectory::Trajectory::from_bytes(&bytes, "demo").expect("a demo");
        if index % 2 == 0 {
            let can =
                lamp_trajectory::BodyDescription { name: "can2".into(), type_name: "can".into() };
            trajectory.header.bodies.push(can);
            for step in &mut trajectory.steps {
                step.body_poses.push(nalgebra::Isometry3::translation(0.42, 0.42, 0.001));
            }
        }
        let (channels, values) =
            lamp_world::standard_channels(&world, &trajectory).expect("channels");
        let file = trajectory.to_bytes_with(&channels, &values).expect("a file");
        let keep = |topic: &str, time| (topic != lamp_trajectory::WORLD_TOPIC).then_some(time);
        let bag = lamp_trajectory::filter_bag(&file, "bag", keep).expect("a bag");
        std::fs::write(bags.join(path.file_name().expect("a name")), bag).expect("writes");
    }
    let two_cans = mapping("can1").replace(
        "    object can can1 frame \"can1\"\n",
        "    object can can1 frame \"can1\"\n    object can can2\n",
    );
    assert!(two_cans.contains("can2"));
    let spec = spec_with(scratch.path(), "two_cans.lamp", &two_cans);
    let output = lampc([
        "build".as_ref(),
        spec.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("build").as_os_str(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(
        stdout.contains("  absent          can2 (frame `can2`) in 10 of 20 bags of `demos/*.mcap`"),
        "{stdout}"
    );
    let domain = domain_without_comments(&scratch.path().join("build"));
    assert!(domain.contains("(:action"), "{domain}");
}

/// Only the commands that read a spec's recordings ask its pattern to match a file: `--demos DIR`
/// replaces the pattern, and a model built from bags that were moved away since still solves.
#[test]
fn a_pattern_that_matches_nothing_stops_only_the_commands_that_read_it() {
    let scratch = tempfile::tempdir().expect("a scratch folder");
    let elsewhere = scratch.path().join("elsewhere");
    demonstrate(&elsewhere);
    // The spec's `demos/*.mcap` matches nothing in the scratch folder.
    let spec = spec_with(scratch.path(), "bags.lamp", &mapping("can1"));
    let checked = lampc(["check".as_ref(), spec.as_os_str()]);
    assert!(!checked.status.success(), "nothing matches the pattern");
    let stderr = String::from_utf8_lossy(&checked.stderr);
    assert!(stderr.contains("lamp::check::missing_file"), "{stderr}");
    let refused = lampc(["build".as_ref(), spec.as_os_str()]);
    assert!(!refused.status.success(), "a build that reads the pattern needs its files");

    let build = scratch.path().join("build");
    let output = lampc([
        "build".as_ref(),
        spec.as_os_str(),
        "--demos".as_ref(),
        elsewhere.as_os_str(),
        "--out".as_ref(),
        build.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let output = lampc([
        "solve".as_ref(),
        spec.as_os_str(),
        "--problem".as_ref(),
        "pack4_01".as_ref(),
        "--build".as_ref(),
        build.as_os_str(),
        "--out".as_ref(),
        scratch.path().join("pack4_01").as_os_str(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("pack4_01: solved"), "{stdout}");
}
