//! The allowed range of every number a user gives lamp outside a scene's geometry: time limits,
//! counts, checking resolutions, learning grids, structure offsets and the built-in plugins'
//! options.
//!
//! The spec checker (lamp-lang) and the command line (lampc) read the same rules from here, so a
//! value refused in one place is refused in the other, in the same words. Every bound is in SI
//! units (seconds, metres, radians) and says why it is where it is.

use std::fmt;
use std::time::Duration;

/// The longest time limit anywhere: one week. Far beyond any solve lamp can finish, and far below
/// where a `Duration` (or an `Instant` plus it) could overflow.
pub const MAX_SECONDS: f64 = 7.0 * 24.0 * 3600.0;

/// The shortest time limit anywhere: one millisecond. A shorter one ends every solve before its
/// first step, and a value like `1e-300` would be echoed back in hundreds of digits.
pub const MIN_SECONDS: f64 = 0.001;

/// A time limit (`--timeout`, a plugin's `timeout`): at least a millisecond, at most a week.
pub const SECONDS: Limit = Limit::closed(MIN_SECONDS, MAX_SECONDS, "s").noting("one week");

/// The longest problem name, in bytes: a problem's name names its files (`problems/NAME.pddl`,
/// the solution folder `solutions/NAME/` and the temporary files written beside them), and a file
/// name holds at most 255 bytes on common file systems; 200 leaves room for what is appended.
pub const MAX_PROBLEM_NAME_BYTES: usize = 200;

/// Plans asked of the planner (`--plans`, the planner's `plans`): refinement tries them one by
/// one, so more than a thousand is a search that could never be refined in a useful time.
pub const PLANS: Limit = Limit::whole(1, 1_000);

/// Threads a solve shares its work between (`lampc solve --threads`): the machines lamp runs on
/// have a few to a few dozen cores; more threads than that only wait on each other.
pub const THREADS: Limit = Limit::whole(1, 256);

/// Ground operators the built-in planners may make (`planner gbfs-ff { operators N }`): an
/// operator holds a few dozen facts, so a hundred million would take tens of gigabytes.
pub const OPERATORS: Limit = Limit::whole(1, 100_000_000);

/// Demonstrations generated (`lampc demos --count`, `simulate … { count }`): a demonstration is
/// a few hundred steps that the learner holds in memory together, so ten thousand (fifty times
/// the bundled domains' count) is where memory, not learning, would become the limit.
pub const DEMONSTRATIONS: Limit = Limit::whole(1, 10_000);

/// The tracking noise of a simulated demonstration's object poses, per axis (`simulate … { noise
/// D A }`, the distance D): motion capture is good to a millimetre or so and a perception
/// pipeline to a centimetre or two; ten centimetres is more than a can's width, beyond which the
/// recorded relations are noise, not a tracker's error.
pub const NOISE_POSITION: Limit = Limit::closed(0.0, 0.1, "m").noting("10 cm");

/// The tracking noise's largest turn (`simulate … { noise D A }`, the angle A): trackers are
/// good to a degree or a few; beyond 45° a box's recorded faces swap their roles.
pub const NOISE_ROTATION: Limit =
    Limit::closed(0.0, std::f64::consts::FRAC_PI_4, "rad").noting("45°");

/// The share of tracked poses a simulated tracker misses (`simulate … { dropped F }`): a tracker
/// that misses more than nine poses in ten records where things were, not where they are.
pub const DROPPED_POSES: Limit = Limit::closed(0.0, 0.9, "");

/// The rate of a simulated demonstration's recording (`simulate … { rate R Hz }`): robot loggers
/// write joint states and tracked poses at 50 to 1000 Hz; below 1 Hz a grasp (half a second) may
/// fall between two steps, and above 1 kHz a demonstration holds more steps than its motion has
/// anything to show (a 10 s demonstration is already 10 000 steps).
pub const RECORDING_RATE: Limit = Limit::closed(1.0, 1000.0, "Hz");

/// The most Gaussian components of one region (`learn { components max K }`): model selection
/// fits a mixture for every count up to it, so fitting time grows with it (a cap of 100,000 made
/// learning Packing take 71 s instead of 0.4 s), while the bundled domains use 6, the default.
pub const COMPONENTS: Limit = Limit::whole(1, 64);

/// The largest grab distance (`robot R { grab distance MIN .. MAX }`), in metres: a grab happens
/// within reach of a gripper's link, and a few centimetres is what every bundled robot takes; past
/// ten metres the value is a slip of the unit or the exponent (`1e300 m` let a magnet pick up a
/// can anywhere in the room, and the solve "succeeded").
pub const MAX_GRAB_DISTANCE: f64 = 10.0;

/// The half-range of a learned pair's position grid (`learn { position … range (RX, RY, RZ) m }`),
/// per axis: relative positions in `[-R, R]` are binned. A relation between two objects a
/// kilometre apart is far beyond any robot's reach; much larger values (`1e300 m`) make the
/// cells' coordinates so large that their squares overflow, and learning then fails in its
/// mixtures with a covariance that is not positive definite instead of here.
pub const POSITION_RANGE: Limit = Limit::above(0.0, 1000.0, "m").noting("one kilometre");

/// Position bins per axis of a learned pair's grid (`learn { position bins (NX, NY, NZ) … }`):
/// at the default half-range of 0.3 m, ten thousand bins are cells of 60 µm, finer than any robot
/// repeats a placement (the learner's own choice stops at 400 bins and 0.1 mm).
pub const POSITION_BINS: Limit = Limit::whole(1, 10_000);

/// Rotation bins per rotation-vector component (`learn { rotation bins N }`) over `[-π, π]`:
/// 3600 bins are 0.1° each, finer than any demonstration repeats an orientation (the learner's
/// own choice stops at 61).
pub const ROTATION_BINS: Limit = Limit::whole(1, 3_600);

/// A coordinate of where a structure puts an object relative to its anchor (`structure S { T O at
/// POSE }`), and of a structure goal's offset (`structure S at A offset POSE`): a structure is
/// built by robots within reach of its anchor, so a kilometre is already absurd; beyond it the
/// value is a slip of the unit or the exponent, and values such as `1e300 m` leave the range in
/// which collision queries are exact (the structure was then said to intersect itself).
pub const STRUCTURE_OFFSET: Limit = Limit::closed(-1000.0, 1000.0, "m").noting("one kilometre");

/// Candidates the `gmm` refiner yields per action (`samples`): each is an alternative that
/// chronological backtracking may try.
pub const SAMPLES: Limit = Limit::whole(1, 10_000);

/// Region draws of one `gmm` candidate stream (`draws`): each costs an inverse-kinematics search,
/// so a million is hours per action.
pub const DRAWS: Limit = Limit::whole(1, 1_000_000);

/// The `gmm` refiner's longest random move of a link leaving a region (`displacement`): no
/// bundled workspace is larger than ten metres.
pub const DISPLACEMENT: Limit = Limit::above(0.0, 10.0, "m");

/// The checking and recording resolution for lengths (the motion planner's `resolution` in a
/// length unit). Finer than a millimetre multiplies the states every motion is checked and
/// recorded at (a metre is a thousand of them already) without telling a collision apart that a
/// millimetre misses; coarser than 5 cm lets a checked edge pass through a wall thinner than that
/// (the Packing box's walls are 1 cm).
pub const LINEAR_RESOLUTION: Limit = Limit::closed(0.001, 0.05, "m");

/// The checking and recording resolution for angles (the motion planner's `resolution` in an
/// angle unit): at 0.001 rad a joint's half turn is already 3,142 checked states; above 0.1 rad
/// (6°) the end of a metre-long arm moves 10 cm between checked states.
pub const ANGULAR_RESOLUTION: Limit = Limit::closed(0.001, 0.1, "rad");

/// The `rrt-connect` planner's longest extension (`step`), in the host's configuration distance:
/// beyond 100 one step crosses any configuration space of a bundled robot many times over.
pub const RRT_STEP: Limit = Limit::above(0.0, 100.0, "");

/// The `rrt-connect` planner's shortcutting attempts after a path is found (`shortcuts`); 0
/// disables shortcutting.
pub const SHORTCUTS: Limit = Limit::whole(0, 100_000);

/// The `rrt-connect` planner's iterations when a request sets none (`iterations`).
pub const ITERATIONS: Limit = Limit::whole(1, 10_000_000);

/// The range of one quantity, in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    /// The smallest value allowed, or, when `open_min` is set, the largest one refused.
    pub min: f64,
    /// Whether `min` itself is refused (a displacement must be more than 0 m).
    pub open_min: bool,
    /// The largest value allowed.
    pub max: f64,
    /// Whether only whole numbers are allowed (a count).
    pub whole: bool,
    /// The SI unit the bounds are in, for messages; empty for a plain number.
    pub unit: &'static str,
    /// What the maximum amounts to, for messages ("one week"); empty when nothing needs saying.
    pub note: &'static str,
}

impl Limit {
    /// Whole numbers from `min` to `max`.
    #[must_use]
    pub const fn whole(min: u32, max: u32) -> Limit {
        Limit { min: min as f64, open_min: false, max: max as f64, whole: true, unit: "", note: "" }
    }

    /// Numbers greater than `min` and at most `max`.
    #[must_use]
    pub const fn above(min: f64, max: f64, unit: &'static str) -> Limit {
        Limit { min, open_min: true, max, whole: false, unit, note: "" }
    }

    /// Numbers from `min` to `max`, both included.
    #[must_use]
    pub const fn closed(min: f64, max: f64, unit: &'static str) -> Limit {
        Limit { min, open_min: false, max, whole: false, unit, note: "" }
    }

    /// The same range, with a note on what the maximum amounts to.
    #[must_use]
    pub const fn noting(self, note: &'static str) -> Limit {
        Limit { note, ..self }
    }

    /// Whether `value` is allowed.
    #[must_use]
    pub fn allows(&self, value: f64) -> bool {
        self.problem(value).is_none()
    }

    /// `value` if it is allowed, else why not.
    ///
    /// # Errors
    /// [`RangeError`] for a value that is not finite, not whole where a count is needed, or
    /// outside the range.
    pub fn check(&self, value: f64) -> Result<f64, RangeError> {
        match self.problem(value) {
            None => Ok(value),
            Some(problem) => Err(RangeError { value, problem, expected: self.expected() }),
        }
    }

    /// A whole number if it is allowed (for a limit of whole numbers), else why not.
    ///
    /// # Errors
    /// As [`check`](Self::check).
    pub fn count(&self, value: f64) -> Result<u64, RangeError> {
        let value = self.check(value)?;
        if value.fract() != 0.0 || value < 0.0 {
            return Err(RangeError {
                value,
                problem: Problem::NotWhole,
                expected: self.expected(),
            });
        }
        // Checked above: whole, not negative and at most `max`, which is a u32.
        Ok(value as u64)
    }

    fn problem(&self, value: f64) -> Option<Problem> {
        if !value.is_finite() {
            return Some(Problem::NotFinite);
        }
        if self.whole && value.fract() != 0.0 {
            return Some(Problem::NotWhole);
        }
        let low = if self.open_min { value <= self.min } else { value < self.min };
        (low || value > self.max).then_some(Problem::OutOfRange)
    }

    /// The allowed range in words, as the end of "the value must be …": "a whole number from 1
    /// to 1000", "greater than 0 m and at most 10 m", "from 0.001 s to 604800 s (one week)".
    #[must_use]
    pub fn expected(&self) -> String {
        let unit = |value: f64| match self.unit {
            "" => number(value),
            unit => format!("{} {unit}", number(value)),
        };
        let range = if self.whole {
            format!("a whole number from {} to {}", unit(self.min), unit(self.max))
        } else if self.open_min {
            format!("greater than {} and at most {}", unit(self.min), unit(self.max))
        } else {
            format!("from {} to {}", unit(self.min), unit(self.max))
        };
        match self.note {
            "" => range,
            note => format!("{range} ({note})"),
        }
    }
}

/// What is wrong with a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Problem {
    /// Infinite or not a number.
    NotFinite,
    /// A fraction where a count is needed.
    NotWhole,
    /// Below the minimum or above the maximum.
    OutOfRange,
}

/// A value outside its [`Limit`], with the range it must lie in.
#[derive(Clone, Debug, PartialEq)]
pub struct RangeError {
    /// The value as given, in SI units.
    pub value: f64,
    pub problem: Problem,
    /// The allowed range in words ([`Limit::expected`]).
    pub expected: String,
}

impl fmt::Display for RangeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let value = number(self.value);
        match self.problem {
            Problem::NotFinite => write!(f, "{value} is not a finite number")?,
            Problem::NotWhole => write!(f, "{value} is not a whole number")?,
            Problem::OutOfRange => write!(f, "{value} is out of range")?,
        }
        write!(f, "; the value must be {}", self.expected)
    }
}

impl std::error::Error for RangeError {}

/// A time limit in seconds as a `Duration`, refused unless [`SECONDS`] allows it.
///
/// # Errors
/// [`RangeError`] for a value [`SECONDS`] refuses.
pub fn duration(seconds: f64) -> Result<Duration, RangeError> {
    let seconds = SECONDS.check(seconds)?;
    Duration::try_from_secs_f64(seconds).map_err(|_| RangeError {
        value: seconds,
        problem: Problem::OutOfRange,
        expected: SECONDS.expected(),
    })
}

/// A number for a message: plain notation for everyday magnitudes, scientific beyond them (so
/// that `1e308` does not print as 309 digits).
pub fn number(value: f64) -> String {
    let magnitude = value.abs();
    if value.is_finite() && magnitude != 0.0 && !(1e-4..1e9).contains(&magnitude) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seconds_are_finite_at_least_a_millisecond_and_at_most_a_week() {
        assert_eq!(SECONDS.check(30.0), Ok(30.0));
        assert_eq!(SECONDS.check(MIN_SECONDS), Ok(MIN_SECONDS));
        assert_eq!(SECONDS.check(MAX_SECONDS), Ok(MAX_SECONDS));
        let refused_values = [
            0.0,
            -30.0,
            -0.0,
            1e-300,
            0.0009,
            MAX_SECONDS + 1.0,
            1e19,
            1e308,
            f64::INFINITY,
            f64::NAN,
        ];
        for refused in refused_values {
            assert!(SECONDS.check(refused).is_err(), "{refused}");
            assert!(duration(refused).is_err(), "{refused}");
        }
        assert_eq!(duration(1.5), Ok(Duration::from_millis(1500)));
        let message = SECONDS.check(1e308).expect_err("refused").to_string();
        assert_eq!(
            message,
            "1e308 is out of range; the value must be from 0.001 s to 604800 s (one week)"
        );
        let message = SECONDS.check(1e-300).expect_err("refused").to_string();
        assert_eq!(
            message,
            "1e-300 is out of range; the value must be from 0.001 s to 604800 s (one week)"
        );
    }

    #[test]
    fn counts_are_whole_and_within_their_bounds() {
        assert_eq!(PLANS.count(3.0), Ok(3));
        assert_eq!(PLANS.count(0.0).map_err(|e| e.problem), Err(Problem::OutOfRange));
        assert_eq!(PLANS.count(2.5).map_err(|e| e.problem), Err(Problem::NotWhole));
        assert_eq!(PLANS.count(f64::INFINITY).map_err(|e| e.problem), Err(Problem::NotFinite));
        assert_eq!(SHORTCUTS.count(0.0), Ok(0));
        assert_eq!(PLANS.expected(), "a whole number from 1 to 1000");
    }

    #[test]
    fn resolutions_have_a_floor_and_a_ceiling() {
        assert!(LINEAR_RESOLUTION.allows(0.005));
        assert!(ANGULAR_RESOLUTION.allows(0.01));
        for refused in [0.0, -0.01, 1e-9, 1.0] {
            assert!(!LINEAR_RESOLUTION.allows(refused), "{refused}");
            assert!(!ANGULAR_RESOLUTION.allows(refused), "{refused}");
        }
        assert_eq!(ANGULAR_RESOLUTION.expected(), "from 0.001 rad to 0.1 rad");
    }
}
