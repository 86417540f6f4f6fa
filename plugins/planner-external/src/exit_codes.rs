//! What Fast Downward's exit codes (shared by the K* fork) say about a run.
//!
//! The codes are those of the driver's `returncodes` module: 0–3 a plan was found (1–3: and a
//! memory or time limit was then hit), 10–13 no plan exists, 20–24 out of memory or time, 30–37
//! errors of the translator, the search or the driver.

/// The meaning of one exit code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The run ended normally; the plan files hold its plans.
    Finished,
    /// Plans were found, then a memory or time limit stopped the run.
    FinishedAtLimit,
    /// The task has no plan; the text says who proved it.
    Unsolvable(&'static str),
    /// The planner's own time limit passed.
    OutOfTime,
    /// The planner refused the task as input it cannot handle.
    Refused(&'static str),
    /// The planner failed (out of memory, a critical error, an unknown code).
    Failure(&'static str),
}

/// The verdict of exit code `code`.
#[must_use]
pub fn verdict(code: i32) -> Verdict {
    match code {
        0 => Verdict::Finished,
        1..=3 => Verdict::FinishedAtLimit,
        10 => Verdict::Unsolvable("the translator proved the task unsolvable"),
        11 => Verdict::Unsolvable("the search proved the task unsolvable"),
        12 => Verdict::Unsolvable("the search ended without reaching the goal"),
        13 => Verdict::Unsolvable("no plan exists within the cost bound"),
        20 => Verdict::Failure("the translator ran out of memory"),
        22 => Verdict::Failure("the search ran out of memory"),
        21 | 23 | 24 => Verdict::OutOfTime,
        30 => Verdict::Failure("the translator failed with a critical error"),
        31 => Verdict::Refused("the translator refused the input"),
        32 => Verdict::Failure("the search failed with a critical error"),
        33 => Verdict::Refused("the search refused its input"),
        34 => Verdict::Refused("the search does not support the task"),
        35 => Verdict::Failure("the driver failed with a critical error"),
        36 => Verdict::Failure("the driver refused its arguments"),
        37 => Verdict::Failure("the driver does not support the configuration"),
        _ => {
            Verdict::Failure("the planner stopped with an exit code Fast Downward does not define")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_documented_codes_have_their_meaning() {
        assert_eq!(verdict(0), Verdict::Finished);
        assert_eq!(verdict(2), Verdict::FinishedAtLimit);
        for code in [10, 11, 12, 13] {
            assert!(matches!(verdict(code), Verdict::Unsolvable(_)), "{code}");
        }
        for code in [21, 23, 24] {
            assert_eq!(verdict(code), Verdict::OutOfTime, "{code}");
        }
        assert!(matches!(verdict(31), Verdict::Refused(_)));
        for code in [20, 22, 30, 32, 35, 36, 37, 4, -1, 127] {
            assert!(matches!(verdict(code), Verdict::Failure(_)), "{code}");
        }
    }
}
