//! Finding and reading the plan files a run left in its scratch folder.
//!
//! Fast Downward writes `sas_plan` (or `sas_plan.1`, `sas_plan.2`, … for anytime searches, each
//! better than the last); K* writes `found_plans/sas_plan.1`, `sas_plan.2`, … in the order found.

use std::path::{Path, PathBuf};

use crate::error::ExternalError;
use crate::sas_plan::{SasPlan, parse_sas_plan};

/// The plan file's name, and the numbered names of several plans.
const PLAN_FILE: &str = "sas_plan";
/// K*'s folder of numbered plan files.
const KSTAR_FOLDER: &str = "found_plans";

/// A plan read from a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlanFile {
    /// The file's name relative to the scratch folder, for messages.
    pub name: String,
    /// The plan.
    pub parsed: SasPlan,
}

/// Fast Downward's plan: `sas_plan`, else the last numbered one; `None` when there is none.
///
/// # Errors
/// [`ExternalError::Io`] or [`ExternalError::PlanSyntax`] for a file that cannot be read as a plan.
pub fn single_plan(folder: &Path) -> Result<Option<PlanFile>, ExternalError> {
    let plain = folder.join(PLAN_FILE);
    let path = if plain.is_file() { Some(plain) } else { numbered(folder)?.pop() };
    path.map(|path| read(folder, &path)).transpose()
}

/// K*'s plans in the order found, at most `count`.
///
/// A run cut short may leave its last file half written: with `complete_only`, files that do not
/// parse or lack the closing cost line are left out instead of failing the call.
///
/// # Errors
/// [`ExternalError::Io`] or [`ExternalError::PlanSyntax`] (unless `complete_only`).
pub fn numbered_plans(
    folder: &Path,
    count: usize,
    complete_only: bool,
) -> Result<Vec<PlanFile>, ExternalError> {
    let mut plans = Vec::new();
    for path in numbered(&folder.join(KSTAR_FOLDER))?.into_iter().take(count) {
        let plan = match read(folder, &path) {
            Ok(plan) => plan,
            Err(ExternalError::PlanSyntax { .. }) if complete_only => break,
            Err(error) => return Err(error),
        };
        if complete_only && plan.parsed.cost.is_none() {
            break;
        }
        plans.push(plan);
    }
    Ok(plans)
}

/// `sas_plan.N` files of `folder` by increasing `N`; nothing when the folder does not exist.
fn numbered(folder: &Path) -> Result<Vec<PathBuf>, ExternalError> {
    let entries = match std::fs::read_dir(folder) {
        Ok(entries) => entries,
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(source) => {
            return Err(ExternalError::Io { path: folder.display().to_string(), source });
        }
    };
    let mut files: Vec<(u64, PathBuf)> = entries
        .filter_map(Result::ok)
        .filter_map(|entry| {
            let name = entry.file_name();
            let number = name.to_str()?.strip_prefix(PLAN_FILE)?.strip_prefix('.')?.parse().ok()?;
            Some((number, entry.path()))
        })
        .collect();
    files.sort();
    Ok(files.into_iter().map(|(_, path)| path).collect())
}

fn read(folder: &Path, path: &Path) -> Result<PlanFile, ExternalError> {
    let name = path.strip_prefix(folder).unwrap_or(path).display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|source| ExternalError::Io { path: path.display().to_string(), source })?;
    let parsed = parse_sas_plan(&text).map_err(|error| ExternalError::PlanSyntax {
        file: name.clone(),
        message: error.to_string(),
    })?;
    Ok(PlanFile { name, parsed })
}
