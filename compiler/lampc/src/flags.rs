//! The command line's numbers, parsed for clap by the limits the spec checker applies to the same
//! quantities (`lamp_spec::limits`): a value refused in a spec is refused as a flag, in the same
//! words.

use lamp_spec::limits::{self, Limit};

/// A time limit in seconds (`--timeout`): at least a millisecond, at most a week.
pub(crate) fn seconds(text: &str) -> Result<f64, String> {
    limits::SECONDS.check(number(text)?).map_err(|error| error.to_string())
}

/// Plans to ask the planner for (`--plans`).
pub(crate) fn plans(text: &str) -> Result<usize, String> {
    count(text, &limits::PLANS)
}

/// Threads to share a solve's work between (`lampc solve --threads`).
pub(crate) fn threads(text: &str) -> Result<usize, String> {
    count(text, &limits::THREADS)
}

/// Demonstrations to generate (`lampc demos --count`).
pub(crate) fn demonstrations(text: &str) -> Result<u32, String> {
    count(text, &limits::DEMONSTRATIONS)
}

fn number(text: &str) -> Result<f64, String> {
    text.trim().parse::<f64>().map_err(|_| format!("`{text}` is not a number"))
}

/// A whole number `limit` allows, as the type the flag needs.
fn count<T: TryFrom<u64>>(text: &str, limit: &Limit) -> Result<T, String> {
    let value = limit.count(number(text)?).map_err(|error| error.to_string())?;
    // Every limit of a count is far below the range of the flag's type.
    T::try_from(value).map_err(|_| format!("`{text}` is too large"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_refuse_what_the_spec_checker_refuses_in_its_words() {
        assert_eq!(seconds("2.5"), Ok(2.5));
        assert_eq!(
            seconds("1e308"),
            Err("1e308 is out of range; the value must be from 0.001 s to 604800 s (one week)"
                .to_string())
        );
        for refused in ["0", "-3", "1e-300", "0.0005", "1e19", "inf", "NaN"] {
            assert!(seconds(refused).is_err(), "{refused}");
        }
        assert_eq!(seconds("soon"), Err("`soon` is not a number".to_string()));
        assert_eq!(plans("5"), Ok(5));
        assert!(plans("0").is_err_and(|message| message.contains("from 1 to 1000")));
        assert!(plans("2.5").is_err_and(|message| message.contains("not a whole number")));
        assert_eq!(threads("2"), Ok(2));
        assert!(threads("0").is_err_and(|message| message.contains("from 1 to 256")));
        assert_eq!(demonstrations("200"), Ok(200));
        assert!(demonstrations("0").is_err_and(|message| message.contains("from 1 to 10000")));
        assert!(demonstrations("100000").is_err());
    }
}
