//! `lampc solve` as a user runs it: demonstrations, a build, then a solve of a four-can Packing
//! problem into a scratch folder; the files are there and say what happened. A build folder that
//! was tampered with, mixed or interrupted is refused naming the file; a relaxed goal is a partial
//! result, not a success; the solution folder is replaced whole, under a lock; every first-party
//! plugin loads as a shared library, and solves as its built-in does.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

use common::listing;

fn lampc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
}

fn spec() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/packing/packing.lamp")
}

fn run(command: &mut Command) -> Output {
    let output = command.output().expect("lampc runs");
    assert!(
        output.status.success(),
        "{:?} failed:\n{}",
        command,
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// A build folder learned from the spec's own 200 demonstrations, as the README's first command
/// makes it; made once and shared by the tests of this file.
fn built() -> &'static Path {
    static BUILT: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, build) = BUILT.get_or_init(|| {
        let scratch = tempfile::tempdir().expect("a scratch directory");
        let build = scratch.path().join("build");
        let demos = scratch.path().join("demos");
        run(lampc().arg("demos").arg(spec()).arg("--out").arg(&demos));
        run(lampc().arg("build").arg(spec()).arg("--demos").arg(&demos).arg("--out").arg(&build));
        (scratch, build)
    });
    build
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("folder");
    for entry in std::fs::read_dir(from).expect("a folder").flatten() {
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).expect("copies");
        }
    }
}

/// A copy of the shared build folder's model in `scratch/build`, to tamper with.
fn build_copy(scratch: &Path) -> PathBuf {
    let build = scratch.join("build");
    copy_dir(&built().join("model"), &build.join("model"));
    build
}

/// `lampc solve SPEC --problem pack4_03 --build BUILD --out OUT` with more arguments.
fn solve_command(build: &Path, out: &Path, more: &[&str]) -> Command {
    let mut command = lampc();
    command
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--build"])
        .arg(build)
        .arg("--out")
        .arg(out)
        .args(more)
        .env("NO_COLOR", "1")
        // Long enough that no message is wrapped.
        .env("COLUMNS", "10000");
    command
}

/// What `solve_command` printed and how it ended.
fn solve_into(build: &Path, out: &Path, more: &[&str]) -> Output {
    solve_command(build, out, more).output().expect("lampc runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn solve_writes_a_validated_trajectory_plan_summary_and_picture() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let build = built();
    let out = scratch.path().join("solution");
    // A previous solution's files are replaced as a whole, none left beside the new ones.
    std::fs::create_dir_all(&out).expect("folder");
    std::fs::write(out.join("plan.txt"), "(old)\n").expect("an old plan");
    let output = run(lampc()
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--build"])
        .arg(build)
        .arg("--out")
        .arg(&out));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("pack4_03: solved"), "{stdout}");
    assert_eq!(listing(&out), ["plan.txt", "summary.json", "trajectory.mcap", "trajectory.svg"]);
    assert_eq!(listing(scratch.path()), [".solution.lock", "solution"], "no staging folder left");
    assert!(stdout.contains("validated by replay"), "{stdout}");
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("a summary");
    assert!(summary.contains("\"success\": true"), "{summary}");
    let plan = std::fs::read_to_string(out.join("plan.txt")).expect("a plan");
    assert_eq!(plan.lines().count(), 19, "{plan}");
    let svg = std::fs::read_to_string(out.join("trajectory.svg")).expect("a picture");
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"), "an SVG");
    let bytes = std::fs::read(out.join("trajectory.mcap")).expect("a trajectory");
    let trajectory =
        lamp_trajectory::Trajectory::from_bytes(&bytes, "trajectory.mcap").expect("it reads back");
    assert!(trajectory.steps.len() > 100);
    // The file's stamps are the times the robot takes: every coordinate within its velocity
    // limit, and the summary's execution time is the last stamp.
    let (spec, world) = lamp_test_support::domain("packing");
    let problem = spec.problems.iter().find(|p| p.name == "pack4_03").expect("the problem");
    let scene = world.problem_scene(problem).expect("the scene loads");
    let robots: Vec<&lamp_robot::Robot> =
        scene.robots().iter().map(|robot| robot.robot().as_ref()).collect();
    let worst = lamp_test_support::assert_within_velocity_limits(&trajectory, &robots);
    assert!(worst > 0.5, "the gripper comes near its speed limit: {worst}");
    let json: serde_json::Value = serde_json::from_str(&summary).expect("JSON");
    let last = trajectory.steps.last().expect("steps").time_nanoseconds as f64 / 1e9;
    assert_eq!(json["execution_seconds"].as_f64(), Some(last), "{summary}");
    assert!(stdout.contains(&format!("{last:.1} s to execute")), "{stdout}");
    // Each can rests on the box's floor up to the 1 mm resting gap above it, and the summary
    // says how far the one that goes down farthest would settle.
    let sunk = json["sink"]["metres"].as_f64().expect("a sink");
    assert!(sunk > 0.0 && sunk <= 0.00101, "{summary}");
    assert!(json["sink"]["object"].as_str().is_some_and(|can| can.starts_with("can")), "{summary}");
    assert!(stdout.contains("goes down farthest onto what it rests on"), "{stdout}");
    common::assert_viewer_channels(&bytes, "trajectory.mcap");
    // The plan step being executed is on /lamp/step, each step once, in the plan's order, and
    // the first label comes after the initial state.
    let step_topic = lamp_trajectory::STEP_LABEL_TOPIC;
    let approach_topic = lamp_trajectory::APPROACH_TOPIC;
    let recording = lamp_trajectory::read_standard_channels(
        bytes.as_slice(),
        "trajectory.mcap",
        &[step_topic, approach_topic],
    )
    .expect("the standard channels read back");
    let labels = &recording.strings[step_topic];
    let texts: Vec<&str> = labels.iter().map(|(_, text)| text.as_str()).collect();
    assert_eq!(texts, plan.lines().collect::<Vec<_>>());
    assert!(labels[0].0 > 0, "the initial state carries no label");
    assert!(labels.windows(2).all(|pair| pair[0].0 < pair[1].0), "labels in time order");
    assert_executable(&trajectory, &recording, robots[0]);
    assert_approaches(&trajectory, &json["approaches"], plan.lines().count());
    assert!(stdout.contains("4 put-down(s), 4 contact grasp(s) end in contact"), "{stdout}");
    // The bag says the same as the summary, each approach at the stamp where it begins.
    let in_bag: Vec<(f64, serde_json::Value)> = recording.strings[approach_topic]
        .iter()
        .map(|(nanoseconds, text)| {
            (*nanoseconds as f64 / 1e9, serde_json::from_str(text).expect("a JSON object"))
        })
        .collect();
    let in_summary: Vec<(f64, serde_json::Value)> = json["approaches"]
        .as_array()
        .expect("approaches")
        .iter()
        .map(|approach| (approach["from_seconds"].as_f64().expect("a stamp"), approach.clone()))
        .collect();
    assert_eq!(in_bag, in_summary);
}

/// A Packing solution's straight last approaches: each can is taken by the magnet coming to it
/// and put down by coming straight down, and the summary says where each begins and ends.
fn assert_approaches(
    trajectory: &lamp_trajectory::Trajectory,
    approaches: &serde_json::Value,
    plan_steps: usize,
) {
    let approaches = approaches.as_array().expect("a list of approaches");
    let steps = &trajectory.steps;
    let at = |seconds: f64| {
        steps
            .iter()
            .position(|step| step.time_nanoseconds as f64 / 1e9 == seconds)
            .expect("an approach's stamp is a step's")
    };
    let coordinates = &trajectory.header.robots[0].coordinates;
    let axis = |name: &str| coordinates.iter().position(|c| c == name).expect("a free gripper");
    let (x, y, z) = (axis("base_x"), axis("base_y"), axis("base_z"));
    let mut kinds = Vec::new();
    let mut previous_end = 0;
    for approach in approaches {
        let number = |key: &str| approach[key].as_f64().expect("a number");
        let text = |key: &str| approach[key].as_str().expect("a text");
        let (from, to) = (at(number("from_seconds")), at(number("to_seconds")));
        assert!(previous_end <= from && from <= to, "approaches in order: {approach}");
        previous_end = to;
        let plan_step = number("plan_step") as usize;
        assert!((1..=plan_steps).contains(&plan_step), "{approach}");
        let object = text("object");
        let body = trajectory.header.body_index(object).expect("an object of the scene");
        let held = |step: usize| steps[step].robots[0].held[0];
        let metres = number("metres");
        let kind = text("kind");
        kinds.push((kind.to_string(), object.to_string()));
        match kind {
            "put_down" => {
                // Carried all the way, straight down by the distance the summary gives.
                assert!((from..=to).all(|step| held(step) == Some(body)), "{approach}");
                let q = |step: usize| &steps[step].robots[0].positions;
                for pair in (from..=to).collect::<Vec<_>>().windows(2) {
                    let (a, b) = (q(pair[0]), q(pair[1]));
                    assert!((a[x] - b[x]).abs() < 1e-6 && (a[y] - b[y]).abs() < 1e-6, "{approach}");
                    assert!(b[z] <= a[z] + 1e-9, "only down: {approach}");
                }
                let drop = q(from)[z] - q(to)[z];
                assert!(drop > 0.05 && (drop - metres).abs() < 1e-3, "{drop} m, {approach}");
            }
            "contact" => {
                // From free to holding, a few millimetres at most.
                assert_eq!((held(from), held(to)), (None, Some(body)), "{approach}");
                assert!((0.0..=0.03).contains(&metres), "{approach}");
            }
            other => panic!("an approach of kind {other}"),
        }
    }
    // Four cans: each taken by contact, then put down.
    let expected: Vec<(String, String)> = (1..=4)
        .flat_map(|can| ["contact", "put_down"].map(|kind| (kind.to_string(), format!("can{can}"))))
        .collect();
    let mut sorted = kinds.clone();
    sorted.sort_by(|a, b| (&a.1, &a.0).cmp(&(&b.1, &b.0)));
    assert_eq!(sorted, expected, "{kinds:?}");
}

/// A Packing solution's channels for controllers: the magnet is switched on at the last step
/// before every grasp and off before every release, and every motion between them is one
/// trajectory of the free gripper's coordinates, one point per step at the step's time, within
/// the velocity limits.
fn assert_executable(
    trajectory: &lamp_trajectory::Trajectory,
    recording: &lamp_trajectory::StandardRecording,
    robot: &lamp_robot::Robot,
) {
    let steps = &trajectory.steps;
    let mut expected = Vec::new();
    let mut segments = Vec::new();
    let mut start = 0;
    for index in 1..=steps.len() {
        let change = steps.get(index).map(|step| &step.robots[0].held[0]);
        if change == Some(&steps[index - 1].robots[0].held[0]) {
            continue;
        }
        if let Some(held) = change {
            let position = if held.is_some() { 1.0 } else { 0.0 };
            expected.push((steps[index - 1].time_nanoseconds, position));
        }
        if index - 1 > start {
            segments.push((start, index - 1));
        }
        start = index;
    }
    assert_eq!(expected.len(), 8, "four grasps and four releases");
    let commands = &recording.gripper_commands[lamp_trajectory::GRIPPER_COMMAND_TOPIC];
    let found: Vec<(u64, f64)> =
        commands.iter().map(|command| (command.log_time, command.position)).collect();
    assert_eq!(found, expected);
    assert!(!recording.joint_trajectories.contains_key(lamp_trajectory::JOINT_TRAJECTORY_TOPIC));
    let motions = &recording.joint_trajectories[lamp_trajectory::BASE_TRAJECTORY_TOPIC];
    assert_eq!(motions.len(), segments.len(), "one trajectory per motion");
    for (message, (first, last)) in motions.iter().zip(segments) {
        assert_eq!(message.log_time, steps[first].time_nanoseconds);
        assert_eq!(message.joint_names, robot.coordinate_names());
        assert_eq!(message.points.len(), last - first + 1);
        for (point, step) in message.points.iter().zip(&steps[first..=last]) {
            assert_eq!(point.positions, step.robots[0].positions);
            let since = step.time_nanoseconds - steps[first].time_nanoseconds;
            assert_eq!(point.time_from_start_nanoseconds, since);
            for (velocity, coordinate) in point.velocities.iter().zip(robot.coordinates()) {
                assert!(velocity.abs() <= coordinate.velocity * (1.0 + 1e-9), "{velocity}");
            }
        }
    }
}

/// `domains/tools/validate_plan.py`, which checks a solution's plan, segment by segment, with
/// unified-planning's sequential plan validator.
fn validate_plan_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/tools/validate_plan.py")
}

/// What the independent validator says of the solution in `out` to `problem` of the model in
/// `build`; panics with its words when a segment is not valid.
fn validated(build: &Path, problem: &str, out: &Path) -> String {
    let model = build.join("model");
    let output = Command::new("python3")
        .arg(validate_plan_script())
        .arg(model.join("domain.pddl"))
        .arg(model.join("problems").join(format!("{problem}.pddl")))
        .arg(out)
        .output()
        .expect("python3 runs");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{problem}: the plan does not validate:\n{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

/// Each segment of a solution's plan (split at its replan marks) is a plan of the emitted domain
/// from the state it starts in, by a validator that shares no code with lamp: unified-planning's
/// `PlanValidator` (pinned in tests/oracles.txt). A Packing problem from the shared build, and
/// Keva's `pi_tower_3`, whose plank let go of on its marker settles out of the learned region and
/// is placed again after a replan.
#[test]
fn every_segment_of_a_solution_is_valid_for_an_independent_validator() {
    if !lamp_test_support::python_oracle("unified_planning", "unified-planning") {
        return;
    }
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("pack4_01");
    let mut command = lampc();
    command.arg("solve").arg(spec()).args(["--problem", "pack4_01", "--build"]).arg(built());
    run(command.arg("--out").arg(&out));
    let verdict = validated(built(), "pack4_01", &out);
    assert!(verdict.contains("reaches the goal"), "{verdict}");

    let keva = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/keva/keva.lamp");
    let (demos, build) = (scratch.path().join("keva-demos"), scratch.path().join("keva-build"));
    run(lampc().arg("demos").arg(&keva).arg("--out").arg(&demos));
    run(lampc().arg("build").arg(&keva).arg("--demos").arg(&demos).arg("--out").arg(&build));
    let out = scratch.path().join("pi_tower_3");
    let mut command = lampc();
    command.arg("solve").arg(&keva).args(["--problem", "pi_tower_3", "--build"]).arg(&build);
    run(command.arg("--out").arg(&out));
    let verdict = validated(&build, "pi_tower_3", &out);
    assert!(verdict.contains("reaches the goal"), "{verdict}");
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("a summary");
    let summary: serde_json::Value = serde_json::from_str(&summary).expect("JSON");
    let replans = summary["replan_points"].as_array().expect("a list of replans");
    let segments = verdict.lines().filter(|line| line.starts_with("segment ")).count();
    assert_eq!(segments, replans.len() + 1, "{verdict}");
}

/// Every first-party plugin built as a shared library (with its `shared-library` feature, which
/// exports the entry symbol), by the same cargo into the same target folder and profile as this
/// test, once: the library of each package.
fn plugin_libraries() -> &'static BTreeMap<&'static str, PathBuf> {
    const PACKAGES: [(&str, Option<&str>); 5] = [
        ("lamp-planner-builtin", Some("shared-library")),
        ("lamp-planner-external", Some("shared-library")),
        ("lamp-refiner-gmm", Some("shared-library")),
        ("lamp-motion-rrt", Some("shared-library")),
        ("echo-planner", None),
    ];
    static BUILT: OnceLock<BTreeMap<&'static str, PathBuf>> = OnceLock::new();
    BUILT.get_or_init(|| {
        let mut arguments = vec!["--lib".to_string()];
        for (package, feature) in PACKAGES {
            arguments.extend(["--package".to_string(), package.to_string()]);
            if let Some(feature) = feature {
                arguments.extend(["--features".to_string(), format!("{package}/{feature}")]);
            }
        }
        let arguments: Vec<&str> = arguments.iter().map(String::as_str).collect();
        let profile_dir = lamp_test_support::cargo_build_like_this_test(&arguments);
        PACKAGES
            .iter()
            .map(|(package, _)| {
                (*package, profile_dir.join(lamp_test_support::shared_library_file(package)))
            })
            .collect()
    })
}

/// A planner library that never returns and never checks for cancellation cannot hold a solve
/// past its time limit: the host stops waiting a few seconds after it and says why.
#[test]
fn a_plugin_that_never_returns_cannot_hold_a_solve_past_its_time_limit() {
    let profile_dir = lamp_test_support::cargo_build_like_this_test(&[
        "--package",
        "echo-planner",
        "--example",
        "hanging_planner",
    ]);
    let library = profile_dir
        .join("examples")
        .join(lamp_test_support::shared_library_file("hanging_planner"));
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("solution");
    let started = std::time::Instant::now();
    let output = solve_into(built(), &out, &["--planner", path_text(&library), "--timeout", "1"]);
    let elapsed = started.elapsed();
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("lamp::solve::unresponsive"), "{message}");
    assert!(message.contains("the time limit of 1 s (`--timeout`) ran out 5 s ago"), "{message}");
    assert!(elapsed < std::time::Duration::from_secs(60), "stopped after {elapsed:?}");
    assert!(!out.exists(), "nothing is written");
}

fn path_text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

#[test]
fn every_first_party_plugin_loads_as_a_shared_library_and_solves_as_its_built_in() {
    let libraries = plugin_libraries();
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let (loaded, linked) = (scratch.path().join("loaded"), scratch.path().join("linked"));
    let output = run(&mut solve_command(
        built(),
        &loaded,
        &[
            "--planner",
            path_text(&libraries["lamp-planner-builtin"]),
            "--refiner",
            path_text(&libraries["lamp-refiner-gmm"]),
            "--motion",
            path_text(&libraries["lamp-motion-rrt"]),
        ],
    ));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("pack4_03: solved"), "{stdout}");
    assert!(stdout.contains("validated by replay"), "{stdout}");
    // The built-ins are made by the same factories from the same configuration, so the
    // libraries find the same plan and trajectory, byte for byte.
    run(&mut solve_command(
        built(),
        &linked,
        &["--planner", "gbfs-ff", "--refiner", "gmm", "--motion", "rrt-connect"],
    ));
    for file in ["plan.txt", "trajectory.mcap"] {
        let read = |folder: &Path| std::fs::read(folder.join(file)).expect("a solution file");
        assert!(read(&loaded) == read(&linked), "{file} differs between library and built-in");
    }

    // The example planner loads and plans, but its `achieve` steps are no action of the domain.
    let echo = solve_into(
        built(),
        &scratch.path().join("echo"),
        &["--planner", path_text(&libraries["echo-planner"])],
    );
    let message = stderr(&echo);
    assert_eq!(echo.status.code(), Some(1), "{message}");
    assert!(!message.contains("lamp::plugin::"), "loaded and created: {message}");
    assert!(message.contains("achieve"), "{message}");

    // The external planner loads; it solves where Fast Downward is installed, and otherwise
    // says how to install it.
    let external = solve_into(
        built(),
        &scratch.path().join("external"),
        &["--planner", path_text(&libraries["lamp-planner-external"])],
    );
    let message = stderr(&external);
    if external.status.success() {
        assert!(String::from_utf8_lossy(&external.stdout).contains("pack4_03: solved"));
    } else {
        assert!(
            std::env::var_os("LAMP_REQUIRE_ORACLES").is_none_or(|value| value != "1"),
            "Fast Downward is required: {message}"
        );
        assert!(message.contains("pip install up-fast-downward"), "{message}");
    }
}

#[test]
fn a_solve_writes_the_same_bytes_on_one_thread_as_on_two() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let files = |threads: &str| {
        let out = scratch.path().join(format!("threads-{threads}"));
        let output = solve_into(built(), &out, &["--threads", threads]);
        assert!(output.status.success(), "{}", stderr(&output));
        let read = |name: &str| std::fs::read(out.join(name)).expect("a solution file");
        // The seconds each stage took are the one thing that may differ.
        let summary = String::from_utf8(read("summary.json")).expect("text");
        let summary: Vec<String> = summary
            .lines()
            .filter(|line| !line.trim_start().starts_with("\"seconds_"))
            .map(|line| line.trim_end_matches(',').to_string())
            .collect();
        (read("trajectory.mcap"), read("plan.txt"), read("trajectory.svg"), summary)
    };
    let one = files("1");
    assert!(one.0.len() > 10_000 && one.3.len() > 10, "a solution was written");
    assert!(one == files("2"), "the files differ between one thread and two");

    let refused = solve_into(built(), &scratch.path().join("none"), &["--threads", "0"]);
    assert_eq!(refused.status.code(), Some(2), "a command line that does not parse");
    assert!(stderr(&refused).contains("from 1 to 256"), "{}", stderr(&refused));
}

#[test]
fn an_unknown_problem_is_named_with_the_ones_there_are() {
    let missing =
        lampc().arg("solve").arg(spec()).args(["--problem", "pack9"]).output().expect("runs");
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert_eq!(missing.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no problem `pack9`") && stderr.contains("pack4_01"), "{stderr}");
}

#[test]
fn a_time_limit_stops_the_search_reports_how_far_it_got_and_writes_nothing() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("solution");
    let output = lampc()
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--timeout", "0.001", "--build"])
        .arg(built())
        .arg("--out")
        .arg(&out)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::solve::cancelled"), "{stderr}");
    assert!(stderr.contains("before any plan was refined"), "{stderr}");
    assert!(stderr.contains("the time limit of 0.001 s (`--timeout`) ran out"), "{stderr}");
    assert!(!out.exists(), "nothing is written");

    let refused = lampc()
        .arg("solve")
        .arg(spec())
        .args(["--problem", "pack4_03", "--timeout", "0"])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("the value must be from 0.001 s to 604800 s (one week)"), "{stderr}");
}

/// A copy of the Packing spec with one more problem: six cans for a box that holds four, which
/// plans (the learned model does not count) but never refines, so its search runs its full
/// budget — many seconds — unless it is stopped.
fn overfull_spec(scratch: &Path) -> PathBuf {
    overfull_spec_with(scratch, |text| text)
}

/// [`overfull_spec`] with the bundled spec's text changed by `edit` first.
fn overfull_spec_with(scratch: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots/");
    let mut text = std::fs::read_to_string(spec())
        .expect("the bundled spec")
        .replace("\"../robots/", &format!("\"{}/", robots.display()));
    text.push_str(
        "problem pack6 {\n  scene {\n    table table1 at (0, 0, 0) m\n    surface box1 at (0.25, 0.15, 0) m\n",
    );
    for (index, (x, y)) in
        [(-0.3, -0.3), (-0.15, -0.3), (0.0, -0.3), (-0.3, -0.1), (-0.15, -0.1), (-0.3, 0.1)]
            .iter()
            .enumerate()
    {
        text.push_str(&format!("    can can{} at ({x}, {y}, 0.001) m\n", index + 1));
    }
    text.push_str("    robot gripper at (0, 0, 0.45) m rpy (180, 0, 0) deg\n  }\n  goal {\n");
    for index in 1..=6 {
        text.push_str(&format!("    in_box(can{index}, box1)\n"));
    }
    text.push_str("  }\n}\n");
    let text = edit(text);
    let path = scratch.join("overfull.lamp");
    std::fs::write(&path, text).expect("writes the spec");
    let demos = built().parent().expect("the scratch folder").join("demos");
    run(lampc().arg("build").arg(&path).arg("--demos").arg(&demos));
    path
}

/// Ctrl-C stops the search at its next check: the process says so and how far it got, writes
/// nothing, and exits as interrupted (130) instead of dying with the signal.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_search_and_writes_nothing() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = overfull_spec(scratch.path());
    let out = scratch.path().join("solution");
    let child = lampc()
        .arg("solve")
        .arg(&spec)
        .args(["--problem", "pack6", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    std::thread::sleep(Duration::from_secs(1));
    let pid = child.id().to_string();
    let kill = Command::new("kill").args(["-INT", &pid]).status().expect("kill runs");
    assert!(kill.success());
    let output = child.wait_with_output().expect("ends");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("lamp::solve::cancelled"), "{stderr}");
    assert!(stderr.contains("candidates, deepest step"), "{stderr}");
    assert!(stderr.contains("lampc solve: interrupted"), "{stderr}");
    assert!(!out.exists(), "nothing is written");
}

/// A time limit stops even a search that would run its whole budget, within a second or two of the
/// limit: every loop of the solve polls the cancellation check.
#[test]
fn a_time_limit_stops_a_long_search_soon_after_it_runs_out() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = overfull_spec(scratch.path());
    let out = scratch.path().join("solution");
    let limit = 2.0;
    let started = std::time::Instant::now();
    let output = lampc()
        .arg("solve")
        .arg(&spec)
        .args(["--problem", "pack6", "--timeout", &limit.to_string(), "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    let elapsed = started.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::solve::cancelled"), "{stderr}");
    assert!(stderr.contains("(`--timeout`) ran out"), "{stderr}");
    // Generous for a loaded machine: the process starts, checks and loads the spec and the model
    // before the clock starts, and the search stops within milliseconds of the limit.
    assert!(elapsed < limit + 2.0, "stopped {:.2} s after the start", elapsed);
    assert!(!out.exists(), "nothing is written");
}

/// A solve that fails says where its plans ended and what stopped them there, in the scene's
/// names, and writes the whole account beside the solution folder; the next solve that succeeds
/// into that folder removes it. Six cans for a box that holds four: every plan ends placing the
/// fifth can, which touches the cans already in the box.
#[test]
fn a_failed_solve_says_where_its_plans_ended_and_writes_why() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    // Few draws per step, so that the search runs out of its budget in seconds.
    let spec = overfull_spec_with(scratch.path(), |text| {
        assert!(text.contains("draws 2000"), "the spec sets the refiner's draws");
        text.replace("draws 2000", "draws 100")
    });
    let out = scratch.path().join("solution");
    let failed = scratch.path().join("solution.failed").join("failure.json");
    let solve = |problem: &str| {
        lampc()
            .arg("solve")
            .arg(&spec)
            .args(["--problem", problem, "--plans", "1", "--out"])
            .arg(&out)
            .env("NO_COLOR", "1")
            .env("COLUMNS", "10000")
            .output()
            .expect("runs")
    };
    let output = solve("pack6");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("lamp::solve::refinement_failed"), "{stderr}");
    assert!(stderr.contains(&failed.display().to_string()), "{stderr}");
    assert!(!out.exists(), "no solution is written");

    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&failed).expect("the report is written"))
            .expect("the report is JSON");
    assert_eq!(report["format"], "lamp-failure-report");
    assert_eq!(report["version"], 1);
    assert_eq!(report["problem"], "pack6");
    assert_eq!(report["code"], "lamp::solve::refinement_failed");
    let refinement = &report["refinement"];
    let plans = refinement["plans"].as_u64().expect("a count");
    assert_eq!(refinement["report"]["plans"].as_array().map(Vec::len), Some(plans as usize));
    let ended = &refinement["report"]["deciding"][0];
    let action = ended["action"].as_str().expect("an action");
    assert!(action.contains("box1"), "the plans end placing a can into the box: {action}");
    assert_eq!(ended["plans"].as_u64(), Some(plans), "every plan ends there: {ended}");
    let placed = ["can1", "can2", "can3", "can4", "can5", "can6"]
        .into_iter()
        .find(|can| action.contains(can))
        .expect("a can is placed");
    let causes = ended["causes"].as_array().expect("causes");
    let in_the_way: Vec<&str> = causes
        .iter()
        .filter(|cause| cause["cause"] == "collision" && cause["moving"] == placed)
        .filter_map(|cause| cause["other"].as_str())
        .filter(|other| other.starts_with("can"))
        .collect();
    assert!(in_the_way.len() >= 2, "the held can touches the cans already in the box: {causes:?}");
    // The deepest state reached is drawn, the cans in the way outlined.
    let picture = std::fs::read_to_string(failed.with_file_name("deepest.svg")).expect("drawn");
    assert!(picture.contains("the deepest state reached, before step"), "titled");
    assert!(picture.contains("stroke=\"#d62728\" stroke-width=\"2.4\""), "something is marked");
    let said = format!("held `{placed}` touches `{}`", in_the_way[0]);
    assert!(stderr.contains(&said), "the message names what is in the way ({said}): {stderr}");
    // The help follows from the cause: a full box is no sampling problem.
    assert!(stderr.contains("are in the way of"), "{stderr}");
    assert!(stderr.contains("drawing more samples will not make room"), "{stderr}");
    assert!(!stderr.contains("raise the refiner's `samples`"), "{stderr}");

    let solved = solve("pack4_01");
    assert!(solved.status.success(), "{}", String::from_utf8_lossy(&solved.stderr));
    assert!(out.join("trajectory.mcap").is_file());
    assert!(!failed.exists(), "a success removes the earlier failure's report");
    assert!(!failed.parent().expect("a folder").exists(), "and its picture");
}

/// The model's domain and the problem pack4_03, parsed.
fn parsed(build: &Path) -> (String, lamp_pddl::Domain, String, lamp_pddl::Problem) {
    let model = build.join("model");
    let text = std::fs::read_to_string(model.join("domain.pddl")).expect("a domain");
    let domain = lamp_pddl::parse_domain(&text).expect("parses");
    let problem_text =
        std::fs::read_to_string(model.join("problems/pack4_03.pddl")).expect("a problem");
    let problem = lamp_pddl::parse_problem(&problem_text, &domain).expect("parses");
    (text, domain, problem_text, problem)
}

/// The first `in_box(can, box1)` goal atom: the goal's first atom of two arguments.
fn in_box_atom(problem: &lamp_pddl::Problem) -> &lamp_pddl::Atom {
    let literal = problem.goal.iter().find(|literal| literal.atom.arguments.len() == 2);
    &literal.expect("an in_box atom").atom
}

/// The domain without every action that adds the `in_box` relation, its provenance comments
/// kept: "an action deleted from domain.pddl by hand".
fn domain_without_the_placing_action(build: &Path) -> String {
    let (text, mut domain, _, problem) = parsed(build);
    let in_box = in_box_atom(&problem).predicate.clone();
    let before = domain.actions.len();
    domain.actions.retain(|action| !action.add.iter().any(|atom| atom.predicate == in_box));
    assert!(domain.actions.len() < before, "an action adds {in_box}");
    let comments: String =
        text.lines().take_while(|l| l.starts_with(';')).map(|l| format!("{l}\n")).collect();
    comments + &lamp_pddl::write_domain(&domain)
}

/// A goal atom no plan reaches together with the rest of the goal: the "not in the box" relation
/// of the first `in_box` atom's can, which holds initially and which the only action that puts a
/// can into the box deletes (and none adds back).
fn unreachable_atom(build: &Path) -> String {
    let (_, domain, _, problem) = parsed(build);
    let in_box = in_box_atom(&problem);
    let placing: Vec<&lamp_pddl::Action> = domain
        .actions
        .iter()
        .filter(|action| action.add.iter().any(|atom| atom.predicate == in_box.predicate))
        .collect();
    assert_eq!(placing.len(), 1, "one action puts a can into the box");
    let outside = placing[0]
        .delete
        .iter()
        .find(|atom| atom.arguments.len() == 2)
        .map(|atom| atom.predicate.clone())
        .expect("it deletes the can's not-in-the-box relation");
    let added_back =
        domain.actions.iter().any(|action| action.add.iter().any(|atom| atom.predicate == outside));
    assert!(!added_back, "no action adds {outside}");
    let arguments: Vec<String> =
        in_box.arguments.iter().map(|argument| argument.name().to_string()).collect();
    format!("({outside} {})", arguments.join(" "))
}

/// An action deleted from domain.pddl by hand: refused before anything is used, naming the file;
/// with `--unchecked-build` the solve runs on the edited domain, and, since no plan reaches any
/// goal atom that does not already hold, it fails instead of claiming success with an empty plan.
#[test]
fn an_action_deleted_from_the_domain_is_refused_and_never_a_success() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let build = build_copy(scratch.path());
    let edited = domain_without_the_placing_action(&build);
    std::fs::write(build.join("model/domain.pddl"), edited).expect("edits");
    let out = scratch.path().join("solution");

    let refused = solve_into(&build, &out, &[]);
    let text = stderr(&refused);
    assert_eq!(refused.status.code(), Some(1), "{text}");
    assert!(text.contains("lamp::solve::tampered"), "{text}");
    let file = build.join("model/domain.pddl");
    assert!(
        text.contains(&format!("{} does not match the build's manifest", file.display())),
        "{text}"
    );
    assert!(text.contains("lampc build SPEC") && text.contains("--unchecked-build"), "{text}");
    assert!(text.contains("lampc solve: failed; no solution files were written"), "{text}");
    assert!(!out.exists(), "nothing is written");

    let unchecked = solve_into(&build, &out, &["--unchecked-build"]);
    let text = stderr(&unchecked);
    let stdout = String::from_utf8_lossy(&unchecked.stdout);
    assert_eq!(unchecked.status.code(), Some(1), "{stdout}\n{text}");
    assert!(text.contains("warning: `--unchecked-build`"), "{text}");
    assert!(
        text.contains("does not match the build's manifest") && text.contains("(used as it is)"),
        "{text}"
    );
    assert!(text.contains("lamp::solve::goal_relaxed_away"), "{text}");
    assert!(!stdout.contains("solved"), "{stdout}");
    assert!(!out.exists(), "nothing is written");
}

/// A goal atom no plan reaches, added to the problem by hand: the goal is relaxed, and the result
/// is partial — exit code 3, "partially solved: dropped …", `"success": false` — not a success.
#[test]
fn an_unreachable_goal_atom_gives_a_partial_result() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let build = build_copy(scratch.path());
    let path = build.join("model/problems/pack4_03.pddl");
    let problem = std::fs::read_to_string(&path).expect("a problem");
    let unreachable = unreachable_atom(&build);
    // Last in goal order; relaxation drops the atom whose relation preconditions use least
    // (ties: the last), which is this one.
    let edited = problem.replacen("\n  ))", &format!("\n    {unreachable}\n  ))"), 1);
    assert_ne!(edited, problem, "the goal is edited");
    std::fs::write(&path, edited).expect("edits");
    let out = scratch.path().join("solution");

    let output = solve_into(&build, &out, &["--unchecked-build"]);
    let (stdout, text) = (String::from_utf8_lossy(&output.stdout), stderr(&output));
    assert_eq!(output.status.code(), Some(3), "{stdout}\n{text}");
    assert!(
        stdout.contains(&format!("pack4_03: partially solved: dropped {unreachable}; written to")),
        "{stdout}"
    );
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("a summary");
    assert!(summary.contains("\"success\": false"), "{summary}");
    let json: serde_json::Value = serde_json::from_str(&summary).expect("JSON");
    assert_eq!(json["relaxed_goal"], serde_json::json!([unreachable]));
    let plan = std::fs::read_to_string(out.join("plan.txt")).expect("a plan");
    assert!(plan.lines().count() > 0, "the rest of the goal is reached: {plan}");
}

/// `samplers.json` learned from other demonstrations than `domain.pddl` (its provenance digest
/// changed): refused naming the file, by the manifest and, with `--unchecked-build`, by the
/// provenance of the PDDL.
#[test]
fn samplers_from_other_demonstrations_are_refused() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let build = build_copy(scratch.path());
    let path = build.join("model/samplers.json");
    let text = std::fs::read_to_string(&path).expect("samplers");
    let json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let digest = json["provenance"]["digest"].as_str().expect("a digest").to_string();
    let other = "fnv1a64:0123456789abcdef";
    std::fs::write(&path, text.replace(&digest, other)).expect("edits");
    let out = scratch.path().join("solution");

    let refused = solve_into(&build, &out, &[]);
    let text = stderr(&refused);
    assert_eq!(refused.status.code(), Some(1), "{text}");
    assert!(text.contains("lamp::solve::tampered"), "{text}");
    assert!(text.contains(&format!("{} does not match", path.display())), "{text}");

    let unchecked = solve_into(&build, &out, &["--unchecked-build"]);
    let text = stderr(&unchecked);
    assert_eq!(unchecked.status.code(), Some(1), "{text}");
    assert!(text.contains("lamp::solve::mismatched_build"), "{text}");
    assert!(
        text.contains(&format!(
            "samplers.json was learned from other demonstrations ({other}) than domain.pddl ({digest})"
        )),
        "{text}"
    );
    assert!(!out.exists(), "nothing is written");
}

/// `--out DIR` where `DIR/trajectory.svg` is a folder: refused before solving, with a last line
/// that is true, and nothing written beside it.
#[test]
fn a_solution_folder_with_a_folder_in_the_way_is_refused_and_left_alone() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("solution");
    std::fs::create_dir_all(out.join("trajectory.svg")).expect("a folder in the way");
    let output = solve_into(built(), &out, &[]);
    let text = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{text}");
    assert!(text.contains("lamp::output::occupied"), "{text}");
    let svg = out.join("trajectory.svg");
    assert!(
        text.contains(&format!("{} is a directory, not a solution file", svg.display())),
        "{text}"
    );
    assert!(
        text.contains(&format!(
            "lampc solve: failed; no solution files were written; the previous solution in {} is unchanged",
            out.display()
        )),
        "{text}"
    );
    assert_eq!(listing(&out), ["trajectory.svg"], "no mix of new files and the old folder");

    std::fs::write(out.join("notes.txt"), "mine").expect("a user file");
    let output = solve_into(built(), &out, &[]);
    let text = stderr(&output);
    assert!(text.contains("it holds notes.txt, which is not a solution file"), "{text}");
}

/// A solve is refused while another holds its solution folder's lock, and while a build holds
/// the model's.
#[test]
fn a_locked_solution_folder_or_a_running_build_refuses_the_solve() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("solution");
    let lock = std::fs::File::create(scratch.path().join(".solution.lock")).expect("a lock file");
    lock.try_lock().expect("the test holds the lock");
    let output = solve_into(built(), &out, &[]);
    let text = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{text}");
    assert!(text.contains("lamp::output::locked"), "{text}");
    assert!(
        text.contains(&format!("{} is being written by another lampc", out.display())),
        "{text}"
    );
    assert!(text.contains("Wait for the other `lampc solve` to finish"), "{text}");
    assert!(!out.exists());
    drop(lock);

    let build = build_copy(scratch.path());
    let lock = std::fs::File::create(build.join(".model.lock")).expect("a lock file");
    lock.try_lock().expect("the test holds the lock");
    let output = solve_into(&build, &out, &[]);
    let text = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{text}");
    assert!(text.contains("lamp::output::building"), "{text}");
    assert!(text.contains("Wait for the `lampc build` to finish"), "{text}");
}

/// A build folder without a whole model: a build interrupted between its two renames, the layout
/// of an older lampc, and a file the manifest lists that is gone.
#[test]
fn an_interrupted_old_or_incomplete_build_is_refused_naming_what_is_wrong() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("solution");

    let build = build_copy(scratch.path());
    std::fs::rename(build.join("model"), build.join(".model.old-42-0-0")).expect("renames");
    let text = stderr(&solve_into(&build, &out, &[]));
    assert!(text.contains("lamp::solve::interrupted_build"), "{text}");
    assert!(text.contains(".model.old-42-0-0"), "{text}");

    let old = scratch.path().join("old");
    copy_dir(&built().join("model"), &old);
    std::fs::remove_file(old.join("manifest.json")).expect("removes");
    let text = stderr(&solve_into(&old, &out, &[]));
    assert!(text.contains("lamp::solve::old_build"), "{text}");

    let incomplete = scratch.path().join("incomplete");
    copy_dir(&built().join("model"), &incomplete.join("model"));
    let gone = incomplete.join("model/problems/pack4_07.pddl");
    std::fs::remove_file(&gone).expect("removes");
    let text = stderr(&solve_into(&incomplete, &out, &[]));
    assert!(text.contains("lamp::solve::unreadable_artifact"), "{text}");
    assert!(text.contains(&format!("{} cannot be read", gone.display())), "{text}");
    assert!(!out.exists(), "nothing is written");
}

/// The Packing spec, edited by `edit`, beside a copy of the robot models (so that its paths read
/// as in the original): `scratch/packing/packing.lamp`.
fn edited_spec(scratch: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots/");
    copy_dir(&robots, &scratch.join("robots"));
    let folder = scratch.join("packing");
    std::fs::create_dir_all(&folder).expect("a spec folder");
    let path = folder.join("packing.lamp");
    let text = std::fs::read_to_string(spec()).expect("the bundled spec");
    std::fs::write(&path, edit(text)).expect("writes the spec");
    path
}

/// A build answers the spec it was made from: after a goal or a learning input is edited, solving
/// with the old build is refused, naming what changed, instead of answering the old goal.
#[test]
fn a_spec_edited_since_the_build_is_refused_naming_what_changed() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let out = scratch.path().join("solution");
    let build = build_copy(scratch.path());
    let solve_with = |spec: &Path| {
        let mut command = lampc();
        command.arg("solve").arg(spec).args(["--problem", "pack4_03", "--build"]).arg(&build);
        command.arg("--out").arg(&out).env("NO_COLOR", "1").env("COLUMNS", "10000");
        command.output().expect("lampc runs")
    };

    let unchanged = edited_spec(scratch.path(), |text| text);
    let same = solve_with(&unchanged);
    assert!(same.status.success(), "{}", stderr(&same));
    std::fs::remove_dir_all(&out).expect("removes the solution");

    // pack4_03's goal trimmed to one can: the build's problem file still asks for four.
    let goal_start = |text: &str| text.find("problem pack4_03").expect("pack4_03") + 1;
    let trimmed = edited_spec(scratch.path(), |text| {
        let start = goal_start(&text);
        let goal = start + text[start..].find("    in_box(can2, box1)\n").expect("a can2 goal");
        format!("{}{}", &text[..goal], &text[goal + "    in_box(can2, box1)\n".len()..])
    });
    let output = solve_with(&trimmed);
    let text = stderr(&output);
    assert!(!output.status.success(), "{text}");
    assert!(text.contains("lamp::solve::changed_problem"), "{text}");
    assert!(
        text.contains("problem `pack4_03` changed in packing.lamp since the build (its goal)"),
        "{text}"
    );
    assert!(!out.exists(), "nothing is written");

    // pack4_03's can1 moved 1 cm: the build's initial state is the old scene's.
    let moved = edited_spec(scratch.path(), |text| {
        text.replacen("can can1 at (0, -0.32, 0.001)", "can can1 at (0.01, -0.32, 0.001)", 1)
    });
    let text = stderr(&solve_with(&moved));
    assert!(text.contains("changed in packing.lamp since the build (its scene)"), "{text}");
    assert!(!out.exists(), "nothing is written");

    // Another problem's edit leaves pack4_03's file valid.
    let other =
        edited_spec(scratch.path(), |text| text.replacen("    in_box(can2, box1)\n", "", 1));
    let output = solve_with(&other);
    assert!(output.status.success(), "{}", stderr(&output));
    std::fs::remove_dir_all(&out).expect("removes the solution");

    let reseeded = edited_spec(scratch.path(), |text| text.replacen("\nseed 1\n", "\nseed 2\n", 1));
    let output = solve_with(&reseeded);
    let text = stderr(&output);
    assert!(text.contains("lamp::solve::stale_build"), "{text}");
    assert!(!out.exists(), "nothing is written");

    // The spec as built, but the robot's URDF edited: a collision box 2 mm longer.
    let spec = edited_spec(scratch.path(), |text| text);
    let urdf = scratch.path().join("robots/magnetic_gripper.urdf");
    let model = std::fs::read_to_string(&urdf).expect("the copied URDF");
    let longer = model.replacen("0.025 0.025 0.11168", "0.025 0.025 0.11368", 1);
    assert_ne!(longer, model, "the box is in the URDF");
    std::fs::write(&urdf, longer).expect("writes the URDF");
    let output = solve_with(&spec);
    let text = stderr(&output);
    assert!(text.contains("lamp::solve::stale_build"), "{text}");
    assert!(text.contains("or a robot model or mesh file it names"), "{text}");
    assert!(!out.exists(), "nothing is written");
}
