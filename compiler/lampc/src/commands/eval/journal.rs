//! The journal of finished solves (`journal.jsonl` in the output folder): one JSON line per row
//! as it finishes, so that an interrupted evaluation keeps its rows and a new run of the same
//! command continues where it stopped.
//!
//! A line is `{"settings": KEY, "row": ROW}`; a row is reused for the subset digest and problem
//! it names when KEY is the current settings key and the model this lampc learns for that subset
//! and problem is the row's `model` (so rows accumulate across commits while the learner gives
//! the same models; rows of another learner stay in the file and are reported apart). Lines that
//! do not parse (the last one, cut off by a crash) are skipped.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write as _;
use std::path::{Path, PathBuf};

use lamp_eval::Row;
use serde::{Deserialize, Serialize};

use super::error::EvaluationError;

/// The journal's file name in the output folder.
pub(super) const JOURNAL_FILE: &str = "journal.jsonl";

/// The largest journal read: a row is under a kilobyte, so this holds hundreds of thousands of
/// solves, while a wrong file (a link to a device, a named pipe) is refused before it is read.
const JOURNAL_FILE_LIMIT: u64 = 256 << 20;

/// A solve's key: the subset digest and the problem (the settings key is the journal's filter).
pub(super) type Key = (String, String);

#[derive(Serialize, Deserialize)]
struct Entry {
    settings: String,
    row: Row,
}

/// The journal, open for appending.
pub(super) struct Journal {
    path: PathBuf,
    file: File,
    settings: String,
}

/// What an existing journal holds for `settings`: the rows by key, each key's in file order, and
/// how many lines were skipped because they do not parse or contradict themselves (`solved`
/// against the outcome).
pub(super) fn read(
    path: &Path,
    settings: &str,
) -> Result<(BTreeMap<Key, Vec<Row>>, usize), EvaluationError> {
    let text = match crate::files::read_text_limited(path, JOURNAL_FILE_LIMIT, "journal") {
        Ok(text) => text,
        Err(crate::files::ReadError::Io(error)) if error.kind() == std::io::ErrorKind::NotFound => {
            String::new()
        }
        Err(error) => {
            let path = path.display().to_string();
            return Err(EvaluationError::Journal { path, reason: error.to_string() });
        }
    };
    let mut rows: BTreeMap<Key, Vec<Row>> = BTreeMap::new();
    let mut skipped = 0;
    for line in text.lines().filter(|line| !line.trim().is_empty()) {
        match serde_json::from_str::<Entry>(line) {
            Ok(entry) if entry.settings == settings && entry.row.is_consistent() => {
                let key = (entry.row.subset.clone(), entry.row.problem.clone());
                rows.entry(key).or_default().push(entry.row);
            }
            Ok(entry) if entry.settings == settings => skipped += 1,
            Ok(_) => {}
            Err(_) => skipped += 1,
        }
    }
    Ok((rows, skipped))
}

impl Journal {
    /// Opens (or creates) the journal at `path` for rows of `settings`.
    pub(super) fn open(path: &Path, settings: &str) -> Result<Journal, EvaluationError> {
        if let Some(folder) = path.parent() {
            std::fs::create_dir_all(folder)
                .map_err(|error| EvaluationError::io("create", folder, error))?;
        }
        let mut file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|error| EvaluationError::io("open", path, error))?;
        // A line cut off by a crash must not swallow the next one.
        let length = file.metadata().map(|m| m.len()).unwrap_or(0);
        if length > 0 && !std::fs::read(path).is_ok_and(|bytes| bytes.ends_with(b"\n")) {
            file.write_all(b"\n").map_err(|error| EvaluationError::io("write", path, error))?;
        }
        Ok(Journal { path: path.to_path_buf(), file, settings: settings.to_string() })
    }

    /// Appends `row` as one line and flushes it to the file.
    pub(super) fn append(&mut self, row: &Row) -> Result<(), EvaluationError> {
        let entry = Entry { settings: self.settings.clone(), row: row.clone() };
        let mut line = serde_json::to_string(&entry).map_err(|error| EvaluationError::Encode {
            what: "a journal line",
            reason: error.to_string(),
        })?;
        line.push('\n');
        self.file
            .write_all(line.as_bytes())
            .and_then(|()| self.file.flush())
            .map_err(|error| EvaluationError::io("write", &self.path, error))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lamp_eval::{Outcome, Row, SolveResult};

    /// A row edited to say `solved` beside an outcome that is not is skipped (and so solved
    /// again), never counted: the report would contradict itself.
    #[test]
    fn a_row_whose_solved_flag_contradicts_its_outcome_is_skipped() {
        let scratch = tempfile::tempdir().expect("a scratch directory");
        let path = scratch.path().join("journal.jsonl");
        let failed = SolveResult::failed(Outcome::RefinementBudget, "no plan refined");
        let honest = Row::new(40, 1, "pack2", 2, "fnv1a64:0000000000000001", failed.clone(), None);
        let mut edited = Row::new(40, 1, "pack4", 4, "fnv1a64:0000000000000001", failed, None);
        edited.solved = true;
        let mut journal = Journal::open(&path, "key").expect("opens");
        journal.append(&honest).expect("appends");
        journal.append(&edited).expect("appends");
        let (rows, skipped) = read(&path, "key").expect("reads");
        assert_eq!(skipped, 1);
        assert_eq!(rows.into_values().flatten().collect::<Vec<_>>(), [honest]);
    }
}
