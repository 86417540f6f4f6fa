//! All-or-nothing output folders: the build's model folder and a solution folder are written whole
//! into a fresh staging folder beside them, then put in place with two renames (the old folder
//! aside, the staging folder in), under an advisory lock that refuses a second writer.
//!
//! Every name this module makes sits beside the output folder `F` in its parent: the lock file
//! `.F.lock` (kept: removing a lock file races with a process that has just opened it), staging
//! folders `.F.staging-<unique>` and the old folder while it is swapped out, `.F.old-<unique>`.
//! A process that stops between the two renames leaves no `F` but an `.F.old-…`; readers report
//! that ([`leftovers`]) and the next writer removes such leftovers under the lock.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

use miette::Diagnostic;
use thiserror::Error;

/// Why an output folder was not written or not fully replaced.
#[derive(Debug, Error, Diagnostic)]
pub(crate) enum OutputError {
    /// Another process holds the folder's lock.
    #[error("{folder} is being written by another lampc{holder}")]
    #[diagnostic(
        code(lamp::output::locked),
        help(
            "Wait for the other `lampc {command}` to finish, or give this one another folder with `--out DIR`."
        )
    )]
    Locked { folder: String, holder: String, command: &'static str },

    /// A `lampc build` holds the lock of the model a solve wants to read.
    #[error("{folder} is being rebuilt by another lampc{holder}")]
    #[diagnostic(
        code(lamp::output::building),
        help("Wait for the `lampc build` to finish, then solve again.")
    )]
    Building { folder: String, holder: String },

    /// The lock file cannot be made or locked.
    #[error("cannot lock {folder} ({lock}): {reason}")]
    #[diagnostic(
        code(lamp::output::lock),
        help(
            "Check that the folder's parent is writable and on a file system that supports locks."
        )
    )]
    Lock { folder: String, lock: String, reason: String },

    /// What is in the way is not ours to replace.
    #[error("cannot replace {folder}: {reason}")]
    #[diagnostic(
        code(lamp::output::occupied),
        help(
            "Move it away or give another folder with `--out DIR`; lampc replaces only what it wrote itself."
        )
    )]
    Occupied { folder: String, reason: String },

    /// Writing into the staging folder failed; the staging folder is removed again.
    #[error("cannot write {file}: {reason}")]
    #[diagnostic(
        code(lamp::output::write),
        help("Check the name, the free space and the permissions of the output folder.")
    )]
    Write { file: String, reason: String },

    /// Moving the old folder aside or the new one in failed.
    #[error("cannot move {from} to {to}: {reason}")]
    #[diagnostic(
        code(lamp::output::swap),
        help("Check the permissions of the output folder's parent, then run the command again.")
    )]
    Swap { from: String, to: String, reason: String, state: String },
}

/// An output folder that is replaced as a whole.
pub(crate) struct OutputFolder {
    target: PathBuf,
    parent: PathBuf,
    name: String,
}

/// The folder's advisory lock, released when dropped (with its file handle).
pub(crate) struct FolderLock {
    _file: File,
}

/// What a successful replacement left behind: the old folder, when it could not be removed.
pub(crate) struct Replaced {
    pub(crate) kept: Option<(PathBuf, String)>,
}

impl OutputFolder {
    /// The output folder at `target`; it needs a file name (not `/` or `..`).
    pub(crate) fn new(target: &Path) -> Result<Self, OutputError> {
        let name = target.file_name().map(|name| name.to_string_lossy().into_owned());
        let Some(name) = name.filter(|_| !target.ends_with("..")) else {
            return Err(OutputError::Occupied {
                folder: target.display().to_string(),
                reason: "it has no name of its own to write beside".to_string(),
            });
        };
        let parent = match target.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        Ok(OutputFolder { target: target.to_path_buf(), parent, name })
    }

    /// The folder itself.
    pub(crate) fn path(&self) -> &Path {
        &self.target
    }

    /// The lock file beside the folder.
    fn lock_path(&self) -> PathBuf {
        self.parent.join(format!(".{}.lock", self.name))
    }

    /// Takes the folder's lock for writing, or says who holds it; creates the parent folders.
    pub(crate) fn lock(&self, command: &'static str) -> Result<FolderLock, OutputError> {
        let lock = self.lock_path();
        let failed = |reason: String| OutputError::Lock {
            folder: self.target.display().to_string(),
            lock: lock.display().to_string(),
            reason,
        };
        std::fs::create_dir_all(&self.parent).map_err(|error| failed(error.to_string()))?;
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&lock)
            .map_err(|error| failed(error.to_string()))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let holder = holder(&mut file);
                return Err(OutputError::Locked {
                    folder: self.target.display().to_string(),
                    holder,
                    command,
                });
            }
            Err(TryLockError::Error(error)) => return Err(failed(error.to_string())),
        }
        // The holder's process id, for the message of a process that is refused.
        let _ = file.set_len(0).and_then(|()| writeln!(file, "{}", std::process::id()));
        Ok(FolderLock { _file: file })
    }

    /// Takes the folder's lock for reading when a writer ever made one; `None` when there is
    /// no lock file (no writer has ever run here, so none is running).
    pub(crate) fn lock_for_reading(&self) -> Result<Option<FolderLock>, OutputError> {
        let lock = self.lock_path();
        let mut file = match File::open(&lock) {
            Ok(file) => file,
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(error) => {
                return Err(OutputError::Lock {
                    folder: self.target.display().to_string(),
                    lock: lock.display().to_string(),
                    reason: error.to_string(),
                });
            }
        };
        match file.try_lock_shared() {
            Ok(()) => Ok(Some(FolderLock { _file: file })),
            Err(TryLockError::WouldBlock) => Err(OutputError::Building {
                folder: self.target.display().to_string(),
                holder: holder(&mut file),
            }),
            Err(TryLockError::Error(error)) => Err(OutputError::Lock {
                folder: self.target.display().to_string(),
                lock: lock.display().to_string(),
                reason: error.to_string(),
            }),
        }
    }

    /// Staging and swapped-out folders an earlier writer left beside the folder, sorted.
    pub(crate) fn leftovers(&self) -> Vec<PathBuf> {
        let prefixes = [format!(".{}.staging-", self.name), format!(".{}.old-", self.name)];
        let Ok(entries) = std::fs::read_dir(&self.parent) else { return Vec::new() };
        let mut found: Vec<PathBuf> = entries
            .flatten()
            .filter(|entry| {
                let name = entry.file_name().to_string_lossy().into_owned();
                prefixes.iter().any(|prefix| name.starts_with(prefix.as_str()))
            })
            .map(|entry| entry.path())
            .collect();
        found.sort();
        found
    }

    /// Removes what [`OutputFolder::leftovers`] finds; only a lock holder may, since another
    /// writer's staging folder looks the same.
    pub(crate) fn remove_leftovers(&self, _lock: &FolderLock) {
        for leftover in self.leftovers() {
            // A leftover that cannot be removed does no harm: it is never read.
            let _ = std::fs::remove_dir_all(&leftover);
        }
    }

    /// Writes `files` (paths relative to the folder) into a staging folder, then replaces the
    /// folder with it. On an error nothing has changed, except as [`OutputError::Swap`]'s `state`
    /// says.
    pub(crate) fn replace(
        &self,
        _lock: &FolderLock,
        files: &[(&Path, &[u8])],
    ) -> Result<Replaced, OutputError> {
        let staging = self.fresh("staging")?;
        if let Err(error) = write_files(&staging, files) {
            let _ = std::fs::remove_dir_all(&staging);
            return Err(error);
        }
        let aside = match std::fs::symlink_metadata(&self.target) {
            Ok(_) => {
                let aside = self.unique("old");
                if let Err(error) = std::fs::rename(&self.target, &aside) {
                    let _ = std::fs::remove_dir_all(&staging);
                    return Err(OutputError::Swap {
                        from: self.target.display().to_string(),
                        to: aside.display().to_string(),
                        reason: error.to_string(),
                        state: format!("{} is unchanged", self.target.display()),
                    });
                }
                Some(aside)
            }
            Err(_) => None,
        };
        if let Err(error) = std::fs::rename(&staging, &self.target) {
            let target = self.target.display();
            // Put the old folder back; only if that fails too are both kept, for the user.
            let restored =
                aside.as_ref().is_none_or(|aside| std::fs::rename(aside, &self.target).is_ok());
            let state = match &aside {
                Some(_) if restored => format!("{target} is unchanged"),
                Some(aside) => format!(
                    "{target} is missing: the previous one is in {}, the new one in {}",
                    aside.display(),
                    staging.display()
                ),
                None => format!("{target} was not created"),
            };
            if restored {
                let _ = std::fs::remove_dir_all(&staging);
            }
            return Err(OutputError::Swap {
                from: staging.display().to_string(),
                to: self.target.display().to_string(),
                reason: error.to_string(),
                state,
            });
        }
        let kept = aside.and_then(|aside| {
            remove_any(&aside).err().map(|error| (aside.clone(), error.to_string()))
        });
        Ok(Replaced { kept })
    }

    /// A name beside the folder that nothing else uses: `.F.<kind>-<process>-<count>-<nanos>`.
    fn unique(&self, kind: &str) -> PathBuf {
        static COUNT: AtomicU64 = AtomicU64::new(0);
        let count = COUNT.fetch_add(1, Ordering::Relaxed);
        let nanos = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |time| time.as_nanos());
        self.parent.join(format!(".{}.{kind}-{}-{count}-{nanos}", self.name, std::process::id()))
    }

    /// Creates a fresh folder named by [`OutputFolder::unique`].
    fn fresh(&self, kind: &str) -> Result<PathBuf, OutputError> {
        // A clash needs the same process id, count and clock reading; a few tries are plenty.
        const TRIES: usize = 8;
        let mut last = String::new();
        for _ in 0..TRIES {
            let path = self.unique(kind);
            match std::fs::create_dir(&path) {
                Ok(()) => return Ok(path),
                Err(error) if error.kind() == std::io::ErrorKind::AlreadyExists => {
                    last = error.to_string();
                }
                Err(error) => {
                    return Err(OutputError::Write {
                        file: path.display().to_string(),
                        reason: error.to_string(),
                    });
                }
            }
        }
        Err(OutputError::Write { file: self.parent.display().to_string(), reason: last })
    }
}

/// The process id a lock file names, as " (process N)", or nothing.
fn holder(file: &mut File) -> String {
    let mut text = String::new();
    match file.read_to_string(&mut text).ok().and_then(|_| text.trim().parse::<u32>().ok()) {
        Some(pid) => format!(" (process {pid})"),
        None => String::new(),
    }
}

/// Writes every file under `dir`, flushed to disk, so that a folder renamed into place is whole.
fn write_files(dir: &Path, files: &[(&Path, &[u8])]) -> Result<(), OutputError> {
    for (relative, contents) in files {
        let path = dir.join(relative);
        let failed = |error: std::io::Error| OutputError::Write {
            file: relative.display().to_string(),
            reason: error.to_string(),
        };
        if let Some(folder) = path.parent() {
            std::fs::create_dir_all(folder).map_err(failed)?;
        }
        let mut file = File::create(&path).map_err(failed)?;
        file.write_all(contents).and_then(|()| file.sync_all()).map_err(failed)?;
    }
    Ok(())
}

/// Removes a folder with everything in it, or a file.
fn remove_any(path: &Path) -> std::io::Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(metadata) if metadata.is_dir() => std::fs::remove_dir_all(path),
        Ok(_) => std::fs::remove_file(path),
        Err(error) => Err(error),
    }
}

/// Removes `folder` when it holds nothing but files named in `files` (a report lampc wrote,
/// now out of date); a folder holding anything else, or that cannot be read, is left alone.
pub(crate) fn remove_if_only(folder: &Path, files: &[&str]) {
    let only = std::fs::read_dir(folder).is_ok_and(|entries| {
        entries.flatten().all(|entry| files.contains(&&*entry.file_name().to_string_lossy()))
    });
    if only {
        let _ = std::fs::remove_dir_all(folder);
    }
}

/// What is at a path, for messages: "a file", "a directory", "a symbolic link", "a socket", …
pub(crate) fn kind_of(metadata: &std::fs::Metadata) -> &'static str {
    if metadata.is_file() { "a file" } else { crate::files::describe(&metadata.file_type()) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .expect("readable")
            .flatten()
            .map(|entry| entry.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn replaces_the_whole_folder_and_leaves_only_the_lock_beside_it() {
        let scratch = tempfile::tempdir().expect("scratch");
        let target = scratch.path().join("out");
        let folder = OutputFolder::new(&target).expect("named");
        let lock = folder.lock("build").expect("free");
        folder.replace(&lock, &[(Path::new("a/x.txt"), b"one")]).expect("written");
        folder.replace(&lock, &[(Path::new("b.txt"), b"two")]).expect("replaced");
        assert_eq!(listing(&target), ["b.txt"], "nothing of the old folder is mixed in");
        assert_eq!(listing(scratch.path()), [".out.lock", "out"]);
    }

    #[test]
    fn a_failed_write_leaves_the_old_folder_and_no_staging_folder() {
        let scratch = tempfile::tempdir().expect("scratch");
        let target = scratch.path().join("out");
        let folder = OutputFolder::new(&target).expect("named");
        let lock = folder.lock("build").expect("free");
        folder.replace(&lock, &[(Path::new("x.txt"), b"old")]).expect("written");
        let long = "n".repeat(300);
        let error = folder
            .replace(&lock, &[(Path::new("y.txt"), b"new"), (Path::new(&long), b"new")])
            .err()
            .expect("a name too long fails");
        assert!(matches!(error, OutputError::Write { .. }), "{error}");
        assert_eq!(listing(&target), ["x.txt"]);
        assert_eq!(std::fs::read(target.join("x.txt")).expect("kept"), b"old");
        assert_eq!(listing(scratch.path()), [".out.lock", "out"]);
    }

    #[test]
    fn a_second_writer_is_refused_while_the_first_holds_the_lock() {
        let scratch = tempfile::tempdir().expect("scratch");
        let folder = OutputFolder::new(&scratch.path().join("out")).expect("named");
        let lock = folder.lock("solve").expect("free");
        let error = folder.lock("solve").err().expect("held");
        let message = error.to_string();
        assert!(message.contains("is being written by another lampc (process "), "{message}");
        assert!(matches!(folder.lock_for_reading(), Err(OutputError::Building { .. })));
        drop(lock);
        assert!(folder.lock_for_reading().expect("free").is_some());
        folder.lock("solve").expect("free again");
    }

    #[test]
    fn leftovers_of_an_interrupted_swap_are_found_and_removed_by_the_next_writer() {
        let scratch = tempfile::tempdir().expect("scratch");
        let folder = OutputFolder::new(&scratch.path().join("model")).expect("named");
        std::fs::create_dir(scratch.path().join(".model.old-1-0-0")).expect("made");
        std::fs::create_dir(scratch.path().join(".modelx.old-1-0-0")).expect("made");
        assert_eq!(folder.leftovers(), [scratch.path().join(".model.old-1-0-0")]);
        let lock = folder.lock("build").expect("free");
        folder.remove_leftovers(&lock);
        assert!(folder.leftovers().is_empty());
        assert!(scratch.path().join(".modelx.old-1-0-0").is_dir(), "another folder's are kept");
    }
}
