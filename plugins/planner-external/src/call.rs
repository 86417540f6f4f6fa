//! One planner call: check the PDDL, write it to a scratch folder, run the engine, read its plan
//! files, validate every plan, and say how the call ended.

use std::path::Path;

use lamp_pddl::{Domain, Problem};
use lamp_planner::parse_task;
use lamp_plugin_api::{HostServices, Plan, PlanRequest, PlanResponse, PlanStatus, PlanStep};

use crate::error::ExternalError;
use crate::exit_codes::{Verdict, verdict};
use crate::options::CommandLine;
use crate::plan_files::{PlanFile, numbered_plans, single_plan};
use crate::process::{Ending, log_is_empty, log_tail, run};
use crate::resolve::Engine;

/// Fast Downward's search: lazy greedy best-first with FF and preferred operators, as the LAMP
/// authors run it and as lamp-planner's `gbfs-ff` searches.
const FAST_DOWNWARD_SEARCH: [&str; 4] =
    ["--evaluator", "h=ff()", "--search", "lazy_greedy([h],preferred=[h])"];

/// The scratch folder's input files.
const DOMAIN_FILE: &str = "domain.pddl";
const PROBLEM_FILE: &str = "problem.pddl";

/// Plans `request` with `command`, a driver of `engine`.
///
/// # Errors
/// [`ExternalError`] when the planner cannot run, fails, or writes a plan that does not parse or
/// does not validate; [`ExternalError::Cancelled`] when the host cancels.
pub fn plan_with(
    engine: Engine,
    command: &CommandLine,
    request: &PlanRequest,
    host: &dyn HostServices,
) -> Result<PlanResponse, ExternalError> {
    let (domain, problem) = match parse_task(&request.domain, &request.problem) {
        Ok(task) => task,
        Err(message) => return Ok(PlanResponse::failed(message)),
    };
    let scratch = tempfile::Builder::new()
        .prefix("lamp-external-planner-")
        .tempdir()
        .map_err(|source| ExternalError::Io { path: "a scratch folder".to_string(), source })?;
    let folder = scratch.path();
    let arguments = arguments(engine, folder, request)?;
    host.report_progress(0.0, &format!("running {} ({})", engine.name(), command.display()));
    let ending = run(command, &arguments, folder, request.budget.time_limit, host)?;
    host.report_progress(1.0, "done");
    let failure = |reason: String| ExternalError::Failed {
        command: command.display(),
        reason,
        log: log_tail(folder),
    };
    let wanted = request.plan_count.max(1);
    // A run that ended by itself with an empty log and no plan is no planner's run: its exit
    // code is not taken as a verdict on the task.
    if let Ending::Exited(code) = ending
        && log_is_empty(folder)
        && plan_files(engine, folder, wanted).is_ok_and(|files| files.is_empty())
    {
        return Err(ExternalError::NoOutput { command: command.display(), code });
    }
    let (status, files) = match ending {
        Ending::Cancelled => return Err(ExternalError::Cancelled),
        Ending::Signalled(signal) => return Err(failure(format!("it was stopped ({signal})"))),
        Ending::TimedOut => {
            (PlanStatus::BudgetExhausted, found_before_the_end(engine, folder, wanted)?)
        }
        Ending::Exited(code) => match verdict(code) {
            Verdict::Finished | Verdict::FinishedAtLimit => {
                let files = plan_files(engine, folder, wanted)?;
                let status = finished_status(engine, verdict(code), files.len(), wanted);
                if files.is_empty() && status == PlanStatus::Solved {
                    return Err(failure(format!("it exited with {code} but wrote no plan")));
                }
                (status, files)
            }
            Verdict::Unsolvable(reason) => (
                PlanStatus::Unsolvable { reason: format!("{}: {reason}", engine.name()) },
                Vec::new(),
            ),
            Verdict::OutOfTime => {
                (PlanStatus::BudgetExhausted, found_before_the_end(engine, folder, wanted)?)
            }
            Verdict::Refused(reason) => {
                let message = format!("{}: {reason}\n{}", engine.name(), log_tail(folder));
                return Ok(PlanResponse::failed(message));
            }
            Verdict::Failure(reason) => return Err(failure(format!("exit code {code}: {reason}"))),
        },
    };
    let plans = files
        .iter()
        .map(|file| validated(&domain, &problem, file))
        .collect::<Result<Vec<Plan>, ExternalError>>()?;
    Ok(PlanResponse { status, plans })
}

/// The engine's arguments after its command: the inputs (written here) and the search.
fn arguments(
    engine: Engine,
    folder: &Path,
    request: &PlanRequest,
) -> Result<Vec<String>, ExternalError> {
    let mut arguments = Vec::new();
    for (name, text) in [(DOMAIN_FILE, &request.domain), (PROBLEM_FILE, &request.problem)] {
        let path = folder.join(name);
        std::fs::write(&path, text)
            .map_err(|source| ExternalError::Io { path: path.display().to_string(), source })?;
        arguments.push(path.display().to_string());
    }
    match engine {
        Engine::FastDownward => arguments.extend(FAST_DOWNWARD_SEARCH.map(str::to_string)),
        Engine::KStar => arguments.extend([
            "--search".to_string(),
            format!("kstar(lmcut(),k={},dump_plan_files=true)", request.plan_count.max(1)),
        ]),
    }
    Ok(arguments)
}

fn plan_files(
    engine: Engine,
    folder: &Path,
    wanted: usize,
) -> Result<Vec<PlanFile>, ExternalError> {
    match engine {
        Engine::FastDownward => Ok(single_plan(folder)?.into_iter().collect()),
        Engine::KStar => numbered_plans(folder, wanted, false),
    }
}

/// The plans a run cut short had finished: K* writes each as it finds it; Fast Downward's one
/// plan would end the run, so a run cut short has none to trust.
fn found_before_the_end(
    engine: Engine,
    folder: &Path,
    wanted: usize,
) -> Result<Vec<PlanFile>, ExternalError> {
    match engine {
        Engine::FastDownward => Ok(Vec::new()),
        Engine::KStar => numbered_plans(folder, wanted, true),
    }
}

/// A finished run is solved when it found its plans (the caller refuses a "solved" run that
/// wrote none); K* stopped by a limit with fewer than wanted ran out of budget. K* ending
/// normally found every plan there is, fewer than wanted or none: a task it proves unsolvable
/// ends with its own exit code instead, so a normal end with no plan is no proof of anything.
fn finished_status(engine: Engine, verdict: Verdict, found: usize, wanted: usize) -> PlanStatus {
    match engine {
        Engine::KStar if found < wanted && verdict == Verdict::FinishedAtLimit => {
            PlanStatus::BudgetExhausted
        }
        Engine::FastDownward | Engine::KStar => PlanStatus::Solved,
    }
}

/// The plan of `file`, after lamp-planner's validator accepted it on the request's task.
fn validated(domain: &Domain, problem: &Problem, file: &PlanFile) -> Result<Plan, ExternalError> {
    lamp_planner::validate(domain, problem, &file.parsed.plan).map_err(|error| {
        ExternalError::InvalidPlan { file: file.name.clone(), message: error.to_string() }
    })?;
    let steps = file
        .parsed
        .plan
        .steps
        .iter()
        .map(|step| PlanStep { action: step.action.clone(), arguments: step.arguments.clone() })
        .collect();
    Ok(Plan { steps })
}
