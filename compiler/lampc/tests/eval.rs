//! `lampc eval` as a user runs it, on a copy of the Packing spec with small test problems: the
//! outputs and their schema, a relaxed goal counted as a failure, rows independent of the job
//! count, and an interrupted or cut-short evaluation continued to the same rows.

mod common;

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// `lampc` with `args`, which must succeed.
fn run<S: AsRef<OsStr>>(args: impl IntoIterator<Item = S>) -> Output {
    let output = common::lampc(args);
    assert!(output.status.success(), "lampc failed:\n{}", stderr(&output));
    output
}

/// Writes into `scratch` a copy of the Packing spec (robots found where they are) with three
/// more problems: `pack2`, two cans of `pack4_01` (solved in a few dozen candidates);
/// `unreachable`, whose goal wants the can in the box and outside it (no plan reaches both, so
/// the solver drops an atom and reaches the rest: a relaxed goal, which is not a success); and
/// `pack6`, six cans for a box that holds four, which plans but never refines, so its search
/// runs for many seconds unless it is stopped.
fn scratch_spec(scratch: &Path) -> PathBuf {
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/packing/packing.lamp");
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots/");
    let mut text = std::fs::read_to_string(bundled)
        .expect("the bundled spec")
        .replace("\"../robots/", &format!("\"{}/", robots.display()));
    let start = "  scene {\n    table table1 at (0, 0, 0) m\n    surface box1 at (0.25, 0.15, 0) m rpy (0, 0, 30) deg\n";
    let end = "    robot gripper at (0, 0, 0.45) m rpy (180, 0, 0) deg\n  }\n";
    text.push_str(&format!(
        "problem pack2 {{\n{start}    can can1 at (-0.25, -0.2, 0.001) m\n    can can2 at (-0.1, -0.25, 0.001) m rpy (0, 0, 45) deg\n{end}  goal {{\n    in_box(can1, box1)\n    in_box(can2, box1)\n  }}\n}}\n"
    ));
    text.push_str(&format!(
        "problem unreachable {{\n{start}    can can1 at (-0.25, -0.2, 0.001) m\n{end}  goal {{\n    in_box(can1, box1)\n    surface_can_0(box1, can1)\n  }}\n}}\n"
    ));
    let mut cans = String::new();
    for (index, (x, y)) in
        [(-0.3, -0.3), (-0.15, -0.3), (0.0, -0.3), (-0.3, -0.1), (-0.15, -0.1), (-0.3, 0.1)]
            .iter()
            .enumerate()
    {
        cans.push_str(&format!("    can can{} at ({x}, {y}, 0.001) m\n", index + 1));
    }
    let goal: String = (1..=6).map(|index| format!("    in_box(can{index}, box1)\n")).collect();
    text.push_str(&format!("problem pack6 {{\n{start}{cans}{end}  goal {{\n{goal}  }}\n}}\n"));
    let path = scratch.join("packing.lamp");
    std::fs::write(&path, text).expect("writes the spec");
    path
}

/// `lampc eval` of the two quick problems: 40 and 30 demonstrations, two runs each.
fn eval(spec: &Path, out: &Path, jobs: &str) -> Output {
    let flags = ["--demos", "40,30", "--runs", "2", "--problems", "pack2,unreach*", "--jobs", jobs];
    let mut args: Vec<&OsStr> = vec![OsStr::new("eval"), spec.as_os_str()];
    args.extend(flags.iter().map(OsStr::new));
    args.extend([OsStr::new("--out"), out.as_os_str()]);
    run(args)
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).expect("eval.json is written");
    serde_json::from_str(&text).expect("eval.json is JSON")
}

/// The rows of `eval.json` without the columns that depend on the machine.
fn deterministic_rows(document: &Value) -> Vec<Value> {
    let rows = document["rows"].as_array().expect("rows").clone();
    rows.into_iter()
        .map(|mut row| {
            let object = row.as_object_mut().expect("a row is an object");
            for column in lamp_eval::MACHINE_COLUMNS {
                assert!(object.remove(column).is_some(), "every row has `{column}`");
            }
            row
        })
        .collect()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The job an evaluation hands a worker for `pack2` of `spec` (whose text is `text`), after 40
/// demonstrations and a build in `scratch`.
fn pack2_job(scratch: &Path, spec: &Path, text: &str) -> Value {
    let (demos, build) = (scratch.join("demos"), scratch.join("build"));
    run([OsStr::new("demos"), spec.as_os_str(), OsStr::new("--count"), OsStr::new("40")]
        .into_iter()
        .chain([OsStr::new("--out"), demos.as_os_str()]));
    run([OsStr::new("build"), spec.as_os_str(), OsStr::new("--demos"), demos.as_os_str()]
        .into_iter()
        .chain([OsStr::new("--out"), build.as_os_str()]));
    let model = |path: &str| std::fs::read_to_string(build.join("model").join(path)).expect("read");
    let manifest: Value = serde_json::from_str(&model("manifest.json")).expect("the manifest");
    serde_json::json!({
        "spec": spec,
        "spec_text": text,
        "model_sources": manifest["sources"]["model"],
        "problem": "pack2",
        "seed": 1,
        "timeout": null,
        "domain": model("domain.pddl"),
        "problem_pddl": model("problems/pack2.pddl"),
        "samplers": model("samplers.json"),
    })
}

/// The one result row `lampc eval-worker`, started in `directory`, writes for `job`.
fn worker_row(job: &Value, directory: &Path) -> Value {
    let output = worker_output(job, directory);
    assert!(output.status.success(), "{}", stderr(&output));
    serde_json::from_slice(&output.stdout).expect("one result row")
}

/// What `lampc eval-worker`, started in `directory`, does with `job`.
fn worker_output(job: &Value, directory: &Path) -> Output {
    let mut worker = Command::new(env!("CARGO_BIN_EXE_lampc"))
        .arg("eval-worker")
        .current_dir(directory)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the worker starts");
    let mut input = worker.stdin.take().expect("its input");
    std::io::Write::write_all(&mut input, job.to_string().as_bytes()).expect("writes the job");
    drop(input);
    worker.wait_with_output().expect("the worker ends")
}

#[test]
fn an_evaluation_writes_its_rows_report_and_plots_the_same_for_any_job_count_and_after_a_resume() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());

    // With --jobs 2; no demonstrations yet, so the pool is generated first.
    let two = scratch.path().join("two");
    let first = eval(&spec, &two, "2");
    assert!(
        stderr(&first).contains("generating 40 packing demonstration(s)"),
        "{}",
        stderr(&first)
    );
    assert_eq!(
        std::fs::read_dir(scratch.path().join("build/demos")).expect("the pool").count(),
        40
    );
    // The pool's files are what `lampc demos` writes, with the channels viewers read.
    let generated = std::fs::read(scratch.path().join("build/demos/packing_0000.mcap"));
    common::assert_viewer_channels(&generated.expect("a generated file"), "packing_0000.mcap");
    let document = read_json(&two.join("eval.json"));
    assert_eq!(document["format"], "lamp-eval");
    assert_eq!(document["version"], 1);
    assert_eq!(document["counts"], serde_json::json!([40, 30]));
    assert_eq!(document["runs"], 2);
    assert_eq!(
        document["problems"],
        serde_json::json!([{"name": "pack2", "objects": 2}, {"name": "unreachable", "objects": 1}])
    );
    assert_eq!(document["pool"]["demonstrations"], 40);
    assert_eq!(document["pool"]["generated"], 40);
    assert_eq!(document["pool"]["max_objects"], 1);
    assert!(document["pool"]["digest"].as_str().is_some_and(|d| d.starts_with("fnv1a64:")));
    assert_eq!(document["settings"]["timeout"], Value::Null);
    let csv = std::fs::read_to_string(two.join("eval.csv")).expect("eval.csv is written");
    let header: Vec<&str> = csv.lines().next().expect("a header").split(',').collect();
    let rows = document["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 8, "2 counts × 2 runs × 2 problems");
    assert_eq!(csv.lines().count(), 9);
    for row in rows {
        let mut keys: Vec<&str> =
            row.as_object().expect("a row").keys().map(String::as_str).collect();
        let mut columns = header.clone();
        keys.sort_unstable();
        columns.sort_unstable();
        assert_eq!(keys, columns, "the CSV has the JSON rows' columns");
        match row["problem"].as_str() {
            Some("pack2") => {
                assert_eq!(row["outcome"], "solved", "{row}");
                assert_eq!(row["solved"], true);
                assert!(row["plan_length"].as_u64().is_some_and(|steps| steps > 0), "{row}");
                assert!(row["peak_memory_bytes"].as_u64().is_some_and(|bytes| bytes > 1 << 20));
            }
            Some("unreachable") => {
                assert_eq!(row["outcome"], "relaxed_goal", "{row}");
                assert_eq!(row["solved"], false, "a relaxed goal is not a success");
                assert_eq!(row["relaxed"].as_array().map(Vec::len), Some(1), "{row}");
                assert!(row["reason"].as_str().is_some_and(|r| r.contains("relaxed")), "{row}");
            }
            other => panic!("an unexpected problem {other:?}"),
        }
    }
    let report = std::fs::read_to_string(two.join("report.md")).expect("report.md is written");
    assert!(report.contains("| `pack2` | 2 | 2/2 | 2/2 |"), "{report}");
    assert!(report.contains("| `unreachable` | 1 | 0/2 | 0/2 |"), "{report}");
    // 21 of 40, and 16 of 30, reach their goal (19 of the pool's 40 are cut short).
    assert!(report.contains("| 40 | 21 | 2 | 50.0 % ± 0.0 % |"), "{report}");
    assert!(report.contains("| 30 | 16 | 2 |"), "{report}");
    assert!(report.contains("= 2 ÷ 1 = **2×** (`pack2`)"), "{report}");
    for plot in ["success.svg", "sample_efficiency.svg"] {
        let svg = std::fs::read_to_string(two.join(plot)).expect("the plot is written");
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>\n"), "{plot}");
    }

    // With --jobs 1: the pool is reused, and the rows are the same.
    let one = scratch.path().join("one");
    let second = eval(&spec, &one, "1");
    assert!(!stderr(&second).contains("generating"), "{}", stderr(&second));
    let single = read_json(&one.join("eval.json"));
    assert_eq!(single["pool"]["generated"], 0);
    assert_eq!(deterministic_rows(&single), deterministic_rows(&document));

    // Cut short: a journal that lost its last lines (as after Ctrl-C) is continued to the same rows.
    let resumed = scratch.path().join("resumed");
    std::fs::create_dir_all(&resumed).expect("creates the folder");
    let journal = std::fs::read_to_string(one.join("journal.jsonl")).expect("a journal");
    let lines: Vec<&str> = journal.lines().collect();
    assert_eq!(lines.len(), 6, "the two runs of 40 share their subset: 6 distinct solves");
    std::fs::write(resumed.join("journal.jsonl"), format!("{}\n", lines[..3].join("\n")))
        .expect("writes the cut journal");
    let third = eval(&spec, &resumed, "2");
    assert!(stderr(&third).contains("already in the journal"), "{}", stderr(&third));
    assert!(!stderr(&third).contains(", 0 already in the journal"), "{}", stderr(&third));
    let continued = read_json(&resumed.join("eval.json"));
    assert_eq!(deterministic_rows(&continued), deterministic_rows(&single));
    let journal = std::fs::read_to_string(resumed.join("journal.jsonl")).expect("a journal");
    assert_eq!(journal.lines().count(), 6, "only the missing solves ran");
}

/// Ctrl-C stops the evaluation: finished rows stay in the journal, the unfinished solve is
/// killed, nothing else is written, and the next run takes the finished rows from the journal.
#[cfg(unix)]
#[test]
fn ctrl_c_keeps_the_finished_rows_and_the_next_run_continues_from_them() {
    interrupt_keeps_finished_rows_and_leaves_no_worker("-INT");
}

/// SIGTERM, what `timeout` and CI runners send, stops the evaluation as Ctrl-C does: its workers
/// are killed rather than left running on their own, and the finished rows are kept.
#[test]
fn sigterm_stops_the_workers_and_keeps_the_finished_rows() {
    interrupt_keeps_finished_rows_and_leaves_no_worker("-TERM");
}

/// The worker processes `pid` has started (Linux lists every thread's children).
fn children_of(pid: u32) -> Vec<u32> {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else { return Vec::new() };
    let mut children = Vec::new();
    for task in tasks.flatten() {
        let text = std::fs::read_to_string(task.path().join("children")).unwrap_or_default();
        children.extend(text.split_whitespace().filter_map(|child| child.parse::<u32>().ok()));
    }
    children
}

/// `lampc eval` of `unreachable` and `pack6` from 40 demonstrations, one at a time, with `extra`
/// flags: `unreachable` comes first in spec order and ends at once; `pack6` runs on.
fn start_unreachable_and_pack6(spec: &Path, out: &Path, extra: &[&str]) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
        .arg("eval")
        .arg(spec)
        .args(["--demos", "40", "--runs", "1", "--problems", "unreachable,pack6", "--jobs", "1"])
        .args(extra)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("lampc starts")
}

/// Waits until the first row is in the journal and `pack6`'s solve runs (`running`, given the
/// evaluation's process id).
fn wait_for_first_row_while_pack6_runs(
    child: &mut std::process::Child,
    out: &Path,
    running: impl Fn(u32) -> bool,
) {
    let journal = out.join("journal.jsonl");
    let started = Instant::now();
    while std::fs::read_to_string(&journal).map_or(0, |text| text.lines().count()) < 1
        || !running(child.id())
    {
        assert!(started.elapsed() < Duration::from_secs(300), "the first row never came");
        assert!(child.try_wait().expect("waits").is_none(), "lampc ended before Ctrl-C");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn interrupt_keeps_finished_rows_and_leaves_no_worker(signal: &str) {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let out = scratch.path().join("eval");
    let mut child = start_unreachable_and_pack6(&spec, &out, &[]);
    wait_for_first_row_while_pack6_runs(&mut child, &out, |child| !children_of(child).is_empty());
    let workers = children_of(child.id());
    let pid = child.id().to_string();
    let kill = Command::new("kill").args([signal, &pid]).status().expect("kill runs");
    assert!(kill.success());
    let output = child.wait_with_output().expect("lampc ends");
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(130), "{message}");
    assert!(message.contains("interrupted; 1 of 2 solves are kept"), "{message}");
    assert!(!out.join("eval.json").exists(), "an interrupted evaluation writes no results");
    for worker in workers {
        let alive = Path::new(&format!("/proc/{worker}")).exists();
        assert!(!alive, "worker {worker} outlives the evaluation after `kill {signal}`");
    }

    let next = run([
        OsStr::new("eval"),
        spec.as_os_str(),
        OsStr::new("--demos"),
        OsStr::new("40"),
        OsStr::new("--runs"),
        OsStr::new("1"),
        OsStr::new("--problems"),
        OsStr::new("unreachable"),
        OsStr::new("--out"),
        out.as_os_str(),
    ]);
    assert!(
        stderr(&next)
            .contains("1 solves (1 count(s) × 1 run(s) × 1 problem(s)), 1 already in the journal"),
        "{}",
        stderr(&next)
    );
    let document = read_json(&out.join("eval.json"));
    assert_eq!(document["rows"][0]["outcome"], "relaxed_goal");
}

#[test]
fn a_problem_glob_that_matches_nothing_and_bad_counts_are_refused() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let refused = |flag: &str, value: &str| {
        let output = common::lampc([
            OsStr::new("eval"),
            spec.as_os_str(),
            OsStr::new(flag),
            OsStr::new(value),
        ]);
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{message}");
        message
    };
    let message = refused("--problems", "pack2,cafe*");
    assert!(message.contains("`cafe*` matches no problem; the spec has: pack4_01"), "{message}");
    let message = refused("--demos", "40,0");
    assert!(message.contains("lamp::eval::counts"), "{message}");
    let message = refused("--demos", "50000");
    assert!(message.contains("`--demos`: 50000 is out of range"), "{message}");
    assert!(!scratch.path().join("build").exists(), "nothing is generated or written");
}

/// A problem to evaluate whose can starts in the air is refused at its line before any
/// demonstration is made, instead of every row failing the final physics check.
#[test]
fn a_problem_starting_in_the_air_is_refused_at_its_line_before_any_work() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let text = std::fs::read_to_string(&spec).expect("the spec");
    let pack2 = text.find("problem pack2 {").expect("pack2");
    let can = "    can can1 at (-0.25, -0.2, 0.001) m\n";
    let at = pack2 + text[pack2..].find(can).expect("pack2's can1");
    let floating = "    can can1 at (-0.25, -0.2, 2.5) m\n";
    std::fs::write(&spec, format!("{}{floating}{}", &text[..at], &text[at + can.len()..]))
        .expect("writes the spec");
    let out = scratch.path().join("eval");
    let output = common::lampc([
        OsStr::new("eval"),
        spec.as_os_str(),
        OsStr::new("--problems"),
        OsStr::new("pack2,unreachable"),
        OsStr::new("--out"),
        out.as_os_str(),
    ]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    for expected in [
        "lamp::build::scene_unsupported",
        "problem `pack2`: `can1` cannot rest where the scene places it",
        "    can can1 at (-0.25, -0.2, 2.5) m",
        "`can1` is placed here",
        "1 finding(s) in the initial scenes of the problems to evaluate",
    ] {
        assert!(message.contains(expected), "`{expected}` in:\n{message}");
    }
    assert!(!scratch.path().join("build").exists(), "no demonstration is generated");
    assert!(!out.join("eval.json").exists(), "nothing is evaluated");
}

/// An output folder that cannot keep the results is refused before any demonstration is made: one
/// inside a build's model folder (the next build deletes it), and a journal that is a named pipe
/// (reading it would wait forever) or a link to a device (it would never end).
#[test]
fn an_output_folder_that_cannot_keep_the_results_is_refused_before_any_work() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let refused = |out: &Path| {
        let output = common::lampc([
            OsStr::new("eval"),
            spec.as_os_str(),
            OsStr::new("--demos"),
            OsStr::new("40"),
            OsStr::new("--out"),
            out.as_os_str(),
        ]);
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{message}");
        message
    };
    let model = scratch.path().join("built").join("model");
    std::fs::create_dir_all(&model).expect("a model folder");
    std::fs::write(model.join("manifest.json"), "{}").expect("a manifest");
    let message = refused(&model.join("eval"));
    assert!(message.contains("is inside the model folder"), "{message}");
    assert!(message.contains("give `--out` a folder outside it"), "{message}");

    let piped = scratch.path().join("piped");
    std::fs::create_dir_all(&piped).expect("a folder");
    let mkfifo = Command::new("mkfifo").arg(piped.join("journal.jsonl")).status();
    assert!(mkfifo.expect("mkfifo runs").success());
    let message = refused(&piped);
    assert!(message.contains("journal.jsonl: it is a named pipe, not a file"), "{message}");

    let endless = scratch.path().join("endless");
    std::fs::create_dir_all(&endless).expect("a folder");
    std::os::unix::fs::symlink("/dev/zero", endless.join("journal.jsonl")).expect("a link");
    let message = refused(&endless);
    assert!(message.contains("it is a character device, not a file"), "{message}");
    assert!(!scratch.path().join("build").exists(), "no demonstration is generated");
}

/// One evaluation writes into a folder at a time, and its five outputs are one set: a write that
/// fails leaves the previous set whole, never new figures beside an old report.
#[test]
fn outputs_are_replaced_as_one_set_by_one_evaluation_at_a_time() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let out = scratch.path().join("eval");
    let quick = |problems: &str| {
        common::lampc([
            OsStr::new("eval"),
            spec.as_os_str(),
            OsStr::new("--demos"),
            OsStr::new("30"),
            OsStr::new("--problems"),
            OsStr::new(problems),
            OsStr::new("--out"),
            out.as_os_str(),
        ])
    };
    let first = quick("pack2");
    assert!(first.status.success(), "{}", stderr(&first));
    let outputs = ["eval.json", "eval.csv", "report.md", "success.svg", "sample_efficiency.svg"];
    let before: Vec<Vec<u8>> =
        outputs.iter().map(|name| std::fs::read(out.join(name)).expect("written")).collect();

    // Another evaluation holds the folder.
    let lock = std::fs::File::create(scratch.path().join(".eval.lock")).expect("a lock file");
    lock.lock().expect("locked");
    let refused = quick("pack2,unreachable");
    let message = stderr(&refused);
    assert_eq!(refused.status.code(), Some(1), "{message}");
    assert!(message.contains("lamp::output::locked"), "{message}");
    drop(lock);

    // The third output cannot be written: nothing of the new set replaces the old one.
    std::fs::create_dir(out.join(".report.md.tmp")).expect("a folder in the way");
    let failed = quick("pack2,unreachable");
    let message = stderr(&failed);
    assert_eq!(failed.status.code(), Some(1), "{message}");
    assert!(message.contains("the previous results in"), "{message}");
    for (name, bytes) in outputs.iter().zip(&before) {
        assert_eq!(&std::fs::read(out.join(name)).expect("kept"), bytes, "{name} is the old one");
    }
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .expect("readable")
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".tmp"))
        .collect();
    names.sort();
    assert_eq!(names, [".report.md.tmp"], "no other temporary file is left");
}

/// A worker answers the spec the evaluation started with, whatever the file says by the time the
/// worker runs: the job carries the text the settings key was made from. Here the file on disk
/// has lost the problem by then, and the worker still solves it from the job.
#[test]
fn a_worker_solves_the_spec_the_evaluation_started_with_not_the_file_on_disk() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let text = std::fs::read_to_string(&spec).expect("the spec");
    let job = pack2_job(scratch.path(), &spec, &text);
    let start = text.find("problem pack2 {").expect("pack2");
    let end = start + text[start..].find("\n}\n").expect("its end") + 3;
    std::fs::write(&spec, format!("{}{}", &text[..start], &text[end..])).expect("edits the spec");

    let row = worker_row(&job, scratch.path());
    assert_eq!(row["outcome"], "solved", "{row}");
}

/// The job carries the spec's text but not the robot files it names, which the worker reads
/// again: one edited since the evaluation started (a collision box 2 mm longer) is an error row
/// saying so, not a solve of another robot with the old robot's model.
#[test]
fn a_worker_refuses_a_robot_model_edited_since_the_evaluation_started() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let repo_robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots/");
    let robots = scratch.path().join("robots");
    std::fs::create_dir_all(&robots).expect("a robots folder");
    let urdf = robots.join("magnetic_gripper.urdf");
    std::fs::copy(repo_robots.join("magnetic_gripper.urdf"), &urdf).expect("copies the URDF");
    let text = std::fs::read_to_string(&spec).expect("the spec");
    let text = text.replace(&format!("\"{}/", repo_robots.display()), "\"robots/");
    assert!(text.contains("\"robots/magnetic_gripper.urdf\""), "the spec names the copy");
    std::fs::write(&spec, &text).expect("writes the spec");
    let job = pack2_job(scratch.path(), &spec, &text);
    let robot = std::fs::read_to_string(&urdf).expect("the copied URDF");
    let longer = robot.replacen("0.025 0.025 0.11168", "0.025 0.025 0.11368", 1);
    assert_ne!(longer, robot, "the box is in the URDF");
    std::fs::write(&urdf, longer).expect("edits the URDF");

    let output = worker_output(&job, scratch.path());
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "no row but a failure of where it runs: {message}");
    assert!(output.stdout.is_empty(), "no row: {}", String::from_utf8_lossy(&output.stdout));
    assert!(
        message.contains(
            "cannot run this job here: a robot model or mesh file the spec names changed since \
             the evaluation started"
        ),
        "{message}"
    );
}

/// A worker started where the spec's relative path leads nowhere (a node of a cluster in another
/// folder) writes no row that would count as a failed solve: it fails, naming the spec, the
/// folder and what to do.
#[test]
fn a_worker_that_cannot_read_the_spec_where_it_runs_fails_instead_of_writing_a_row() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let text = std::fs::read_to_string(&spec).expect("the spec");
    let mut job = pack2_job(scratch.path(), &spec, &text);
    // The spec names its robots relative to its folder, which the worker's folder is not.
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/robots/");
    let text = text.replace(&format!("\"{}/", robots.display()), "\"robots/");
    assert!(text.contains("\"robots/magnetic_gripper.urdf\""), "the spec names them so");
    job["spec"] = Value::from("packing.lamp");
    job["spec_text"] = Value::from(text);
    let elsewhere = tempfile::tempdir().expect("another folder");

    let output = worker_output(&job, elsewhere.path());
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(output.stdout.is_empty(), "no row");
    assert!(
        message.contains("cannot run this job here: the spec packing.lamp, read from"),
        "{message}"
    );
    assert!(message.contains("does not check here"), "{message}");
    assert!(message.contains("run the worker in the folder `lampc eval` runs in"), "{message}");
}

/// `lampc eval` of `pack2` and `unreachable` from 30 demonstrations, one run, with `extra` flags.
fn quick_eval(spec: &Path, out: &Path, extra: &[&str]) -> Output {
    quick_eval_of(spec, out, extra, "pack2,unreachable", "30")
}

/// `lampc eval` of `problems` from `demos` demonstrations, one run, two jobs, `extra` flags.
fn quick_eval_of(spec: &Path, out: &Path, extra: &[&str], problems: &str, demos: &str) -> Output {
    let flags = ["--demos", demos, "--runs", "1", "--problems", problems, "--jobs", "2"];
    let mut args: Vec<&OsStr> = vec![OsStr::new("eval"), spec.as_os_str()];
    args.extend(flags.iter().chain(extra).map(OsStr::new));
    args.extend([OsStr::new("--out"), out.as_os_str()]);
    common::lampc(args)
}

/// The journal's lines, parsed.
fn journal_lines(out: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(out.join("journal.jsonl")).expect("a journal");
    text.lines().map(|line| serde_json::from_str(line).expect("a journal line")).collect()
}

/// Figures accumulate: a later evaluation with more runs solves only the new runs' problems, and
/// every row says which commit made it with which model; a row whose model this lampc no longer
/// learns (an earlier learner's) is solved again, stays in the journal, and is reported apart,
/// counted in no figure.
#[test]
fn rows_accumulate_and_an_earlier_learners_rows_are_solved_again_and_kept_apart() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let out = scratch.path().join("accumulated");
    let evaluate = |runs: &str| {
        let flags = ["--demos", "40,30", "--runs", runs, "--problems", "pack2", "--jobs", "2"];
        let mut args: Vec<&OsStr> = vec![OsStr::new("eval"), spec.as_os_str()];
        args.extend(flags.iter().map(OsStr::new));
        args.extend([OsStr::new("--out"), out.as_os_str()]);
        let output = common::lampc(args);
        assert!(output.status.success(), "{}", stderr(&output));
        output
    };

    evaluate("1");
    let lines = journal_lines(&out);
    assert_eq!(lines.len(), 2, "one subset of 40 and one of 30");
    for line in &lines {
        let commit = line["row"]["commit"].as_str().expect("a commit");
        let is_commit = commit.len() == 40 && commit.chars().all(|c| c.is_ascii_hexdigit());
        assert!(is_commit || commit == "unknown", "{commit}");
        let model = line["row"]["model"].as_str().expect("a model digest");
        assert!(model.starts_with("fnv1a64:"), "{model}");
    }

    // A second run per count: the 40 of a pool of 40 is the same subset again, the 30 a new one.
    let second = evaluate("2");
    assert!(stderr(&second).contains(", 3 already in the journal"), "{}", stderr(&second));
    assert!(!stderr(&second).contains("again"), "{}", stderr(&second));
    let summary = String::from_utf8_lossy(&second.stdout);
    assert!(summary.contains("(1 solve(s) run now; 2 from the journal)"), "{summary}");
    assert_eq!(journal_lines(&out).len(), 3, "only the new subset's problem was solved");
    let accumulated = read_json(&out.join("eval.json"));
    assert_eq!(accumulated["rows"].as_array().map(Vec::len), Some(4));

    // The same rows as an earlier learner's: another model, another commit.
    let earlier: Vec<String> = journal_lines(&out)
        .into_iter()
        .map(|mut line| {
            line["row"]["model"] = Value::from("fnv1a64:0000000000000000");
            line["row"]["commit"] = Value::from("0123456789abcdef0123");
            format!("{line}\n")
        })
        .collect();
    std::fs::write(out.join("journal.jsonl"), earlier.concat()).expect("rewrites the journal");
    let third = evaluate("2");
    assert!(stderr(&third).contains("solved 3 journaled solve(s) again"), "{}", stderr(&third));
    assert_eq!(journal_lines(&out).len(), 6, "the earlier rows stay");
    let resolved = read_json(&out.join("eval.json"));
    assert_eq!(deterministic_rows(&resolved), deterministic_rows(&accumulated));
    let report = std::fs::read_to_string(out.join("report.md")).expect("report.md");
    assert!(report.contains("## Rows from another learner"), "{report}");
    assert!(report.contains("| `0123456789ab` | 30 | 2 | 2 |"), "{report}");
    assert!(report.contains("| `0123456789ab` | 40 | 1 | 1 |"), "{report}");
    assert!(report.contains("| 30 | 16 | 2 | 100.0 % ± 0.0 % |"), "{report}");
}

/// The settings keys of a journal's lines.
fn journal_keys(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("journal.jsonl")).unwrap_or_default();
    text.lines()
        .map(|line| {
            let entry: Value = serde_json::from_str(line).expect("a journal line");
            entry["settings"].as_str().expect("a settings key").to_string()
        })
        .collect()
}

/// Solves run through an `--executor` command give the rows the local worker gives, under the
/// same journal key; a command that prints no result row, or fails, stops the evaluation with
/// its diagnostic, and nothing is recorded for the problem (the next run solves it).
#[test]
fn an_executor_command_gives_the_same_rows_and_a_broken_one_records_nothing() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let local = scratch.path().join("local");
    let output = quick_eval(&spec, &local, &[]);
    assert!(output.status.success(), "{}", stderr(&output));

    let through = scratch.path().join("through");
    let executor = format!("'{}' eval-worker", env!("CARGO_BIN_EXE_lampc"));
    let output = quick_eval(&spec, &through, &["--executor", &executor]);
    let message = stderr(&output);
    assert!(output.status.success(), "{message}");
    assert!(message.contains(&format!("2 at once through `{executor}`")), "{message}");
    let (expected, got) =
        (read_json(&local.join("eval.json")), read_json(&through.join("eval.json")));
    assert_eq!(deterministic_rows(&got), deterministic_rows(&expected));
    assert_eq!(got["settings"], expected["settings"], "the executor is not a setting");
    assert_eq!(journal_keys(&through), journal_keys(&local), "nor part of the journal's key");

    // Prints something that is not a result row: tried once more, then the evaluation stops.
    let broken = scratch.path().join("broken");
    let output = quick_eval(&spec, &broken, &["--executor", "sh -c 'cat >/dev/null; echo nope'"]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("lamp::eval::executor_output"), "{message}");
    assert!(
        message.contains("the executor `sh -c 'cat >/dev/null; echo nope'` printed no result row"),
        "{message}"
    );
    assert!(message.contains(r#"its standard output began "nope\n""#), "{message}");
    assert!(message.contains("trying that solve once more"), "{message}");
    assert!(message.contains("stopped by the executor's failure"), "{message}");
    assert!(message.contains("0 of 2 solves are kept"), "{message}");
    assert!(journal_keys(&broken).is_empty(), "nothing is journaled");
    assert!(!broken.join("eval.json").exists(), "no results are written");

    // Exits non-zero: the same, with the end of its standard error.
    let failing = "sh -c 'cat >/dev/null; echo node lost >&2; exit 3'";
    let output = quick_eval(&spec, &broken, &["--executor", failing]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("lamp::eval::executor_failed"), "{message}");
    assert!(message.contains("failed (exit status: 3) without a result row"), "{message}");
    assert!(message.contains("its standard error ended: node lost"), "{message}");
    assert!(journal_keys(&broken).is_empty(), "nothing is journaled");

    // Fixed, the same command solves every problem and gives the local worker's rows.
    let output = quick_eval(&spec, &broken, &[]);
    let message = stderr(&output);
    assert!(output.status.success(), "{message}");
    assert!(message.contains(", 0 already in the journal"), "{message}");
    let fixed = read_json(&broken.join("eval.json"));
    assert_eq!(deterministic_rows(&fixed), deterministic_rows(&expected));
}

/// An executor whose program is not there is refused before any demonstration is made, naming
/// the command and why.
#[test]
fn an_executor_that_does_not_exist_is_refused_before_any_work() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let out = scratch.path().join("eval");
    let missing = "/nonexistent/lampc-executor eval-worker";
    let output = quick_eval(&spec, &out, &["--executor", missing]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("lamp::eval::executor_start"), "{message}");
    assert!(message.contains(&format!("cannot start the executor `{missing}`")), "{message}");
    assert!(message.contains("No such file or directory"), "{message}");
    let output = quick_eval(&spec, &out, &["--executor", "lampc-executor-nowhere eval-worker"]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("`lampc-executor-nowhere` is in no folder of PATH"), "{message}");
    let output = quick_eval(&spec, &out, &["--executor", "sh -c 'echo"]);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{message}");
    assert!(message.contains("lamp::eval::executor_syntax"), "{message}");
    assert!(!scratch.path().join("build").exists(), "no demonstration is generated");
    assert!(!out.exists(), "nothing is written");
}

/// `--keep-models` writes each run's model as a build folder: the solver solves a problem with
/// it exactly as the evaluation's worker did, and a rerun whose solves are all in the journal
/// still writes the models (they are learned again from the same subsets, byte for byte).
#[test]
fn kept_models_are_build_folders_the_solver_reads_and_a_resumed_evaluation_writes_them_too() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let out = scratch.path().join("eval");
    let output = quick_eval(&spec, &out, &["--keep-models"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let build = out.join("models/30-1");
    let domain = std::fs::read(build.join("model/domain.pddl")).expect("the run's domain is kept");
    let vocabulary =
        std::fs::read_to_string(build.join("model/vocabulary.md")).expect("its report");
    assert!(vocabulary.contains("Learned from 30 demonstrations"), "{vocabulary}");

    let document = read_json(&out.join("eval.json"));
    let row = document["rows"]
        .as_array()
        .expect("rows")
        .iter()
        .find(|row| row["problem"] == "pack2")
        .expect("a row for pack2")
        .clone();
    assert_eq!(row["solved"], true, "{row}");
    let solution = scratch.path().join("solution");
    let args = [
        OsStr::new("solve"),
        spec.as_os_str(),
        OsStr::new("--build"),
        build.as_os_str(),
        OsStr::new("--problem"),
        OsStr::new("pack2"),
        OsStr::new("--out"),
        solution.as_os_str(),
    ];
    let output = run(args);
    let printed = String::from_utf8_lossy(&output.stdout);
    assert!(printed.contains("pack2: solved"), "{printed}");
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(solution.join("summary.json")).expect("a summary"),
    )
    .expect("JSON");
    assert_eq!(summary["candidates"], row["candidates"], "{summary}");
    assert_eq!(
        summary["plan"].as_array().map(Vec::len),
        row["plan_length"].as_u64().map(|n| n as usize)
    );

    std::fs::remove_dir_all(out.join("models")).expect("removes the kept models");
    let output = quick_eval(&spec, &out, &["--keep-models"]);
    let message = stderr(&output);
    assert!(output.status.success(), "{message}");
    assert!(message.contains("2 already in the journal"), "{message}");
    let again = std::fs::read(build.join("model/domain.pddl")).expect("written again");
    assert_eq!(again, domain);
}

/// A run whose model cannot be written (here an alias whose example no learned region holds)
/// fails its solves as `build_failed`, and `--keep-models` keeps what the run learned, the
/// vocabulary report, in the run's `failed/` folder.
#[test]
fn a_run_whose_build_fails_keeps_what_it_learned() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let text = std::fs::read_to_string(&spec).expect("the spec");
    let far = "region of can in surface containing (0.5, 0.5, 0.3) m";
    let moved = text.replace("region of can in surface containing (0, 0, 0.001) m", far);
    assert_ne!(moved, text, "the spec's `in_box` alias");
    std::fs::write(&spec, moved).expect("writes the spec");
    let out = scratch.path().join("eval");
    let output = quick_eval(&spec, &out, &["--keep-models"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let document = read_json(&out.join("eval.json"));
    let rows = document["rows"].as_array().expect("rows");
    assert!(
        !rows.is_empty() && rows.iter().all(|row| row["outcome"] == "build_failed"),
        "{rows:?}"
    );
    let build = out.join("models/30-1");
    assert!(!build.join("model").exists(), "no model is written");
    let report =
        std::fs::read_to_string(build.join("failed/vocabulary.md")).expect("what the run learned");
    assert!(report.contains("Learned from 30 demonstrations"), "{report}");
    assert!(report.contains("### `surface_can`"), "{report}");
}

/// A goal that one problem cannot state with the learned model (an AtGoal, where no
/// demonstration put a can onto a marker) fails that problem's solves only: the problems are
/// written on their own when they cannot be written together, and every other problem is solved.
#[test]
fn a_problem_whose_goal_cannot_be_written_fails_only_its_own_solves() {
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let mut text = std::fs::read_to_string(&spec).expect("the spec");
    text.push_str("type spot {\n  marker\n}\n");
    text.push_str(concat!(
        "problem placed {\n  scene {\n    table table1 at (0, 0, 0) m\n",
        "    surface box1 at (0.25, 0.15, 0) m rpy (0, 0, 30) deg\n",
        "    can can1 at (-0.25, -0.2, 0.001) m\n",
        "    robot gripper at (0, 0, 0.45) m rpy (180, 0, 0) deg\n  }\n",
        "  goal {\n    at can1 (-0.3, 0.2, 0.001) m within 0.02 m 180 deg\n  }\n}\n",
    ));
    std::fs::write(&spec, text).expect("writes the spec");
    let out = scratch.path().join("eval");
    let output = quick_eval_of(&spec, &out, &[], "pack2,placed", "30");
    assert!(output.status.success(), "{}", stderr(&output));
    let document = read_json(&out.join("eval.json"));
    let rows = document["rows"].as_array().expect("rows");
    let row = |problem: &str| {
        rows.iter().find(|row| row["problem"] == problem).unwrap_or_else(|| panic!("{rows:?}"))
    };
    assert_eq!(row("placed")["outcome"], "build_failed", "{rows:?}");
    let reason = row("placed")["reason"].as_str().expect("a reason");
    assert!(reason.contains("lamp::build::at_goal: problem `placed`"), "{reason}");
    assert_ne!(row("pack2")["outcome"], "build_failed", "{rows:?}");
}

/// A Ray cluster of two nodes on this machine (`ray start --head`, then a second node joining
/// it), one CPU each, stopped when dropped. `ray stop` stops every Ray process of the user on the
/// machine, so no other test may start a cluster.
struct RayCluster {
    address: String,
    _sessions: tempfile::TempDir,
}

impl RayCluster {
    fn ray(args: &[&str]) -> Output {
        Command::new("python3")
            .args(["-m", "ray.scripts.scripts"])
            .args(args)
            .env("RAY_USAGE_STATS_ENABLED", "0")
            .output()
            .expect("python3 runs")
    }

    fn start() -> RayCluster {
        let sessions = tempfile::Builder::new().prefix("ray").tempdir().expect("a session folder");
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|listener| listener.local_addr())
            .expect("a free port")
            .port();
        let address = format!("127.0.0.1:{port}");
        let cluster = RayCluster { address, _sessions: sessions };
        let temp = format!("--temp-dir={}", cluster._sessions.path().display());
        let head = RayCluster::ray(&[
            "start",
            "--head",
            &format!("--port={port}"),
            "--num-cpus=1",
            "--include-dashboard=false",
            "--disable-usage-stats",
            &temp,
        ]);
        assert!(head.status.success(), "the head node starts: {}", stderr(&head));
        let node = RayCluster::ray(&[
            "start",
            &format!("--address={}", cluster.address),
            "--num-cpus=1",
            "--disable-usage-stats",
        ]);
        assert!(node.status.success(), "the second node joins: {}", stderr(&node));
        cluster
    }
}

impl Drop for RayCluster {
    fn drop(&mut self) {
        let _ = RayCluster::ray(&["stop", "--force"]);
    }
}

/// The processes running `lampc eval-worker` of this build as a Ray task: their parent is a
/// Ray worker, which names itself `ray::…` (the other tests' workers are children of `lampc`).
fn ray_eval_workers() -> Vec<u32> {
    let Ok(processes) = std::fs::read_dir("/proc") else { return Vec::new() };
    processes
        .flatten()
        .filter_map(|entry| {
            let pid = entry.file_name().to_str()?.parse::<u32>().ok()?;
            let command = std::fs::read(entry.path().join("cmdline")).ok()?;
            let words: Vec<&[u8]> = command.split(|byte| *byte == 0).collect();
            let lampc = env!("CARGO_BIN_EXE_lampc").as_bytes();
            if words.first() != Some(&lampc) || words.get(1) != Some(&&b"eval-worker"[..]) {
                return None;
            }
            let status = std::fs::read_to_string(entry.path().join("status")).ok()?;
            let parent = status.lines().find_map(|line| line.strip_prefix("PPid:"))?.trim();
            let parent = std::fs::read(format!("/proc/{parent}/cmdline")).ok()?;
            parent.starts_with(b"ray::").then_some(pid)
        })
        .collect()
}

/// The Ray executor of `domains/tools/` on a real two-node Ray cluster gives the local worker's
/// rows; interrupted, the evaluation cancels its task on the cluster, and the next run continues
/// from the journal.
#[cfg(unix)]
#[test]
fn a_ray_cluster_gives_the_local_rows_and_an_interrupted_ray_evaluation_resumes() {
    if !lamp_test_support::python_oracle("ray", "ray==2.60.0") {
        return;
    }
    let cluster = RayCluster::start();
    let scratch = tempfile::tempdir().expect("a scratch directory");
    let spec = scratch_spec(scratch.path());
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/tools/ray_eval_worker.py");
    let executor = format!(
        "python3 '{}' --lampc '{}' --address {}",
        script.display(),
        env!("CARGO_BIN_EXE_lampc"),
        cluster.address
    );

    let local = scratch.path().join("local");
    let output = quick_eval(&spec, &local, &[]);
    assert!(output.status.success(), "{}", stderr(&output));
    let through = scratch.path().join("ray");
    let output = quick_eval(&spec, &through, &["--executor", &executor]);
    let message = stderr(&output);
    assert!(output.status.success(), "{message}");
    let (expected, got) =
        (read_json(&local.join("eval.json")), read_json(&through.join("eval.json")));
    assert_eq!(deterministic_rows(&got), deterministic_rows(&expected));
    assert_eq!(journal_keys(&through), journal_keys(&local), "the same journal key");

    // `unreachable` ends at once; `pack6` runs on until the evaluation is interrupted.
    let out = scratch.path().join("interrupted");
    let mut child = start_unreachable_and_pack6(&spec, &out, &["--executor", &executor]);
    wait_for_first_row_while_pack6_runs(&mut child, &out, |_| !ray_eval_workers().is_empty());
    let pid = child.id().to_string();
    assert!(Command::new("kill").args(["-INT", &pid]).status().expect("kill runs").success());
    let output = child.wait_with_output().expect("lampc ends");
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(130), "{message}");
    assert!(message.contains("interrupted; 1 of 2 solves are kept"), "{message}");
    // The solve on the cluster is cancelled, not left running for nobody.
    let stopping = Instant::now();
    while !ray_eval_workers().is_empty() {
        assert!(stopping.elapsed() < Duration::from_secs(30), "a worker outlives the evaluation");
        std::thread::sleep(Duration::from_millis(100));
    }

    let next = quick_eval_of(&spec, &out, &["--executor", &executor], "unreachable", "40");
    let message = stderr(&next);
    assert!(next.status.success(), "{message}");
    assert!(message.contains("1 already in the journal"), "{message}");
    assert_eq!(read_json(&out.join("eval.json"))["rows"][0]["outcome"], "relaxed_goal");
}
