//! `lampc render`: draw a problem's initial scene, a demonstration or a trajectory as SVG.
//!
//! The drawing is lamp-render's; this module reads the spec and the trajectory file, picks the
//! problem or step, and writes the SVG (beside the input unless `--out` says otherwise).

use std::path::{Path, PathBuf};

use lamp_render::{RenderOptions, render_scene, render_trajectory};
use lamp_world::SpecWorld;
use miette::MietteDiagnostic;

use crate::commands::{Failure, Finished, Outcome};

/// Arguments of `lampc render`.
#[derive(clap::Args)]
pub(crate) struct Args {
    /// A spec (`.lamp`: a problem's initial scene) or a demonstration or trajectory (`.mcap`).
    pub(crate) file: PathBuf,
    /// The spec an `.mcap` file belongs to (its robots and object types).
    #[arg(long, value_name = "SPEC")]
    pub(crate) spec: Option<PathBuf>,
    /// The problem whose scene to draw [default: the spec's first].
    #[arg(long, value_name = "NAME")]
    pub(crate) problem: Option<String>,
    /// The step of an `.mcap` file to draw over the faded first step [default: the last].
    #[arg(long, value_name = "N")]
    pub(crate) step: Option<usize>,
    /// Where to write the SVG [default: FILE with the extension `.svg`].
    #[arg(long, value_name = "OUT.svg")]
    pub(crate) out: Option<PathBuf>,
}

/// What kind of file is drawn, by its extension.
enum Input {
    Spec,
    Trajectory,
}

pub(crate) fn run(args: &Args) -> Outcome {
    let colour = crate::terminal::colour();
    let (what, out) = render(args, colour)?;
    println!("{}: drew {what} into {}", args.file.display(), out.display());
    Ok(Finished::Done)
}

/// Draws and writes; returns what was drawn and where.
fn render(args: &Args, colour: bool) -> Result<(String, PathBuf), Failure> {
    let input = input_kind(&args.file)?;
    let spec_path = match input {
        Input::Spec => {
            refuse_option(args.spec.is_some(), "--spec", "a spec file")?;
            refuse_option(args.step.is_some(), "--step", "a spec file")?;
            args.file.clone()
        }
        Input::Trajectory => {
            refuse_option(args.problem.is_some(), "--problem", "an .mcap file")?;
            args.spec.clone().ok_or_else(|| {
                diagnostic(
                    "lamp::render::spec_required",
                    format!("drawing {} needs the spec it belongs to", args.file.display()),
                    "name it with `--spec`, for example `lampc render demo.mcap --spec \
                     domains/packing/packing.lamp`; the file's bodies and robots are drawn with \
                     the spec's object types and robot models",
                )
            })?
        }
    };
    let spec = check_spec(&spec_path, colour)?;
    let spec_dir = spec_path.parent().unwrap_or(Path::new("")).to_path_buf();
    let world = SpecWorld::load(&spec_dir, &spec)?;
    let (svg, what) = match input {
        Input::Spec => draw_problem(&world, &spec, args.problem.as_deref())?,
        Input::Trajectory => {
            let limit = crate::files::DEMONSTRATION_FILE_LIMIT;
            let bytes = crate::files::read_limited(&args.file, limit, "trajectory file").map_err(
                |error| {
                    diagnostic(
                        "lamp::render::read",
                        format!("cannot read {}: {error}", args.file.display()),
                        "name a demonstration or trajectory file that `lampc demos` or `lampc \
                         solve` wrote",
                    )
                },
            )?;
            let name = args.file.display().to_string();
            let trajectory = read_trajectory(&world, &spec, bytes, name)?;
            let svg = render_trajectory(&world, &trajectory, args.step, &RenderOptions::default())?;
            let shown = args.step.unwrap_or(trajectory.steps.len().saturating_sub(1));
            (svg, format!("step {shown} of {} steps", trajectory.steps.len()))
        }
    };
    let out = args.out.clone().unwrap_or_else(|| args.file.with_extension("svg"));
    std::fs::write(&out, svg).map_err(|error| {
        diagnostic(
            "lamp::render::write",
            format!("cannot write {}: {error}", out.display()),
            "check that the folder exists and is writable, or choose another path with `--out`",
        )
    })?;
    Ok((what, out))
}

/// The file as a lamp trajectory; a ROS 2 bag of standard messages (no `lamp` record) is read
/// through the spec's `files … as ros2 { … }` mapping, as `lampc build` learns from it (the
/// first such source when the spec has several).
fn read_trajectory(
    world: &SpecWorld,
    spec: &lamp_spec::Spec,
    bytes: Vec<u8>,
    name: String,
) -> Result<lamp_trajectory::Trajectory, Failure> {
    let error = match lamp_trajectory::Trajectory::from_bytes(&bytes, name.clone()) {
        Ok(trajectory) => return Ok(trajectory),
        Err(error) => error,
    };
    let mapping = spec.demonstrations.iter().find_map(|source| match source {
        lamp_spec::DemoSource::Files { ros2: Some(mapping), .. } => Some(mapping),
        _ => None,
    });
    match (&error, mapping) {
        (lamp_trajectory::TrajectoryError::Schema { .. }, Some(mapping)) => {
            let bag = lamp_build::DemoFile { name, bytes };
            Ok(lamp_build::ros2_demonstration(world, mapping, &bag)?.trajectory)
        }
        _ => Err(error.into()),
    }
}

fn input_kind(file: &Path) -> Result<Input, Failure> {
    let extension = file.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("lamp") => Ok(Input::Spec),
        Some("mcap") => Ok(Input::Trajectory),
        _ => Err(diagnostic(
            "lamp::render::file_kind",
            format!("cannot tell what {} is from its extension", file.display()),
            "lampc render draws a spec (`.lamp`, a problem's initial scene) or a demonstration \
             or trajectory (`.mcap`)",
        )),
    }
}

fn refuse_option(given: bool, option: &str, what: &str) -> Result<(), Failure> {
    if !given {
        return Ok(());
    }
    let help = match option {
        "--problem" => "a trajectory holds one run; leave out `--problem`",
        "--spec" => "a spec file is drawn on its own; `--spec` goes with an .mcap file",
        _ => "`--step` picks a step of an .mcap file; leave it out for a spec",
    };
    Err(diagnostic("lamp::render::option", format!("`{option}` does not apply to {what}"), help))
}

/// Checks the spec, printing its diagnostics if it has any.
fn check_spec(path: &Path, colour: bool) -> Result<lamp_spec::Spec, Failure> {
    crate::spec_input::check_spec(path, colour, crate::spec_input::Demonstrations::Unread)
        .map(|checked| checked.spec)
        .ok_or(Failure::Said)
}

/// The initial scene of the named problem (or the first), and a description of it.
fn draw_problem(
    world: &SpecWorld,
    spec: &lamp_spec::Spec,
    name: Option<&str>,
) -> Result<(String, String), Failure> {
    let names = || spec.problems.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ");
    let problem = match name {
        Some(name) => spec.problem(name).ok_or_else(|| {
            diagnostic(
                "lamp::render::unknown_problem",
                format!("spec `{}` has no problem `{name}`", spec.domain),
                &format!("its problems are: {}", names()),
            )
        })?,
        None => spec.problems.first().ok_or_else(|| {
            diagnostic(
                "lamp::render::no_problem",
                format!("spec `{}` has no problem to draw", spec.domain),
                "add a `problem NAME { scene { … } goal { … } }` declaration",
            )
        })?,
    };
    let scene = world.problem_scene(problem)?;
    let options = RenderOptions {
        title: Some(format!("{} \u{b7} {} (initial scene)", spec.domain, problem.name)),
        ..RenderOptions::default()
    };
    Ok((render_scene(&scene, &options), format!("problem `{}`", problem.name)))
}

fn diagnostic(code: &str, message: String, help: &str) -> Failure {
    Failure::Report(Box::new(
        MietteDiagnostic::new(message).with_code(code.to_string()).with_help(help.to_string()),
    ))
}
