//! What the command-line tests share: running `lampc`, and looking at the folders a command
//! leaves behind.

use std::ffi::OsStr;
use std::path::Path;
use std::process::{Command, Output};

/// Runs `lampc` with `args`, without colour and wide enough that no message is wrapped.
#[allow(dead_code)] // not every test file runs lampc through it
pub fn lampc<S: AsRef<OsStr>>(args: impl IntoIterator<Item = S>) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lampc"))
        .args(args)
        .env("NO_COLOR", "1")
        .env("COLUMNS", "10000")
        .output()
        .expect("lampc runs")
}

/// The names in `dir`, sorted, hidden ones (locks, staging folders) included.
#[allow(dead_code)] // not every test file looks at folders
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("a folder")
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The standard channels Foxglove and RViz read are in a trajectory file beside `/lamp/world`
/// (lamp-demonstrators' `viewer_channels` test decodes their contents); an MCAP channel record
/// holds its topic as a length-prefixed string.
#[allow(dead_code)] // only the tests that write trajectories look at them
pub fn assert_viewer_channels(bytes: &[u8], name: &str) {
    for topic in ["/lamp/world", "/tf", "/robot_description", "/lamp/scene"] {
        let length = u32::try_from(topic.len()).expect("a short topic");
        let record = [&length.to_le_bytes()[..], topic.as_bytes()].concat();
        assert!(bytes.windows(record.len()).any(|w| w == record), "{name} has no {topic} channel");
    }
}
