//! Time-parameterization of a path: how long a robot takes to move through a sequence of
//! configurations from rest to rest within its joints' velocity and acceleration limits.
//!
//! The path is piecewise linear in joint space: a list of pieces, each the displacement from one
//! recorded state to the next (`Robot::displacement`). Along it the speed is chosen as in
//! time-optimal path parameterization by reachability (TOPP-RA, with a path sampled at the
//! recorded states): a backward and a forward pass bound the path speed at every state by the
//! velocity limits, by what the acceleration limits let the robot reach from the start and still
//! stop by the end, and at a turn between pieces by the acceleration that turn asks for; within a
//! piece the speed follows the fastest trapezoid (accelerate, cruise, decelerate) between the
//! speeds at its ends. A straight move of one piece or many is therefore the textbook
//! trapezoidal profile, and a sharp turn is taken nearly at rest.
//!
//! What is guaranteed is what a recording shows: for every piece, its displacement divided by its
//! duration is within every coordinate's velocity limit; and the change between consecutive such
//! velocities, divided by the time between the pieces' midpoints (at the ends, from rest over half
//! the piece), is within every acceleration limit. A final check measures both and, where a turn
//! still asks for more, lowers the speed there; as a last resort it slows the whole path by the
//! factor that brings the worst sample within its limit.

/// The acceleration limit of every coordinate (m/s² or rad/s²): URDF has no acceleration limit,
/// and 1.0 is the default MoveIt's time-optimal parameterization applies to a joint that has none
/// in its `joint_limits.yaml`; it is gentle for every shipped robot (a Fetch arm joint reaches its
/// 1.5 rad/s limit in 1.5 s).
pub const DEFAULT_ACCELERATION: f64 = 1.0;
/// The velocity limit of a joint whose URDF limit says 0 (rad/s or m/s).
pub const DEFAULT_JOINT_VELOCITY: f64 = 1.0;
/// The velocity limit of a mount's translation (a mobile base's x and y, a free-flying gripper's
/// x, y and z), in m/s: the mount is no URDF joint, so nothing gives one; half the 1.0 m/s top
/// speed of a Fetch base, the usual speed of an indoor mobile base among furniture.
pub const MOUNT_LINEAR_VELOCITY: f64 = 0.5;
/// The velocity limit of a mount's rotation (a mobile base's yaw, and each component of a
/// free-flying gripper's angular displacement), in rad/s.
pub const MOUNT_ANGULAR_VELOCITY: f64 = 1.0;

/// How many times the final check may lower the speed at turns before it slows the whole path.
const MAX_REPAIRS: usize = 64;
/// Relative slack of the final check: ratios to a limit within rounding of 1 count as within it.
const RATIO_SLACK: f64 = 1e-9;

/// Why a path could not be timed.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum TimingError {
    /// There are not as many acceleration limits as velocity limits.
    #[error("{velocity} velocity limits and {acceleration} acceleration limits")]
    #[diagnostic(code(lamp::timing::limit_count))]
    LimitCount { velocity: usize, acceleration: usize },
    /// A piece has another number of entries than there are limits.
    #[error("piece {piece} has {found} coordinates, and there are limits for {expected}")]
    #[diagnostic(code(lamp::timing::dimension))]
    Dimension { piece: usize, found: usize, expected: usize },
    /// A limit is not a positive finite number.
    #[error("the {what} limit of coordinate {coordinate} is {value}, not a positive number")]
    #[diagnostic(code(lamp::timing::limit))]
    Limit { what: &'static str, coordinate: usize, value: f64 },
    /// A piece moves a coordinate by something that is not a number.
    #[error("piece {piece} moves coordinate {coordinate} by {value}")]
    #[diagnostic(code(lamp::timing::not_finite))]
    NotFinite { piece: usize, coordinate: usize, value: f64 },
}

/// The velocity and acceleration limits of each coordinate of a path's pieces.
#[derive(Clone, Copy, Debug)]
pub struct Limits<'a> {
    pub velocity: &'a [f64],
    pub acceleration: &'a [f64],
}

/// The duration in seconds of each piece of a path that starts and ends at rest (see the module's
/// documentation for the profile and what it guarantees). A piece that moves nothing takes no
/// time, and the robot is at rest at both its ends.
pub fn time_path(pieces: &[Vec<f64>], limits: &Limits<'_>) -> Result<Vec<f64>, TimingError> {
    let dimension = limits.velocity.len();
    if limits.acceleration.len() != dimension {
        return Err(TimingError::LimitCount {
            velocity: dimension,
            acceleration: limits.acceleration.len(),
        });
    }
    for (what, values) in [("velocity", limits.velocity), ("acceleration", limits.acceleration)] {
        if let Some(coordinate) = values.iter().position(|&v| !(v.is_finite() && v > 0.0)) {
            return Err(TimingError::Limit { what, coordinate, value: values[coordinate] });
        }
    }
    for (piece, displacement) in pieces.iter().enumerate() {
        if displacement.len() != dimension {
            return Err(TimingError::Dimension {
                piece,
                found: displacement.len(),
                expected: dimension,
            });
        }
        if let Some(coordinate) = displacement.iter().position(|value| !value.is_finite()) {
            return Err(TimingError::NotFinite {
                piece,
                coordinate,
                value: displacement[coordinate],
            });
        }
    }
    let mut durations = vec![0.0; pieces.len()];
    // A piece that moves nothing is a rest: each run of moving pieces between rests is timed on
    // its own, from rest to rest.
    let mut start = 0;
    while start < pieces.len() {
        if is_still(&pieces[start]) {
            start += 1;
            continue;
        }
        let end = (start..pieces.len()).find(|&k| is_still(&pieces[k])).unwrap_or(pieces.len());
        let run = Run::new(&pieces[start..end], limits);
        durations[start..end].copy_from_slice(&run.durations());
        start = end;
    }
    Ok(durations)
}

fn is_still(displacement: &[f64]) -> bool {
    displacement.iter().all(|&value| value == 0.0)
}

/// One run of moving pieces, in the path parameter `s` whose unit is the time a piece takes at
/// full speed: a piece's length is the longest time any coordinate needs for it at its velocity
/// limit, so that a path speed of 1 puts the limiting coordinate at its limit and the velocity
/// limits become "speed at most 1" at every state.
struct Run<'a> {
    pieces: &'a [Vec<f64>],
    limits: &'a Limits<'a>,
    /// Each piece's length in `s`.
    lengths: Vec<f64>,
    /// Each piece's largest path acceleration (1/s) that keeps every coordinate within its limit.
    accelerations: Vec<f64>,
    /// The bound on the squared path speed at each state (pieces + 1 of them).
    caps: Vec<f64>,
}

impl<'a> Run<'a> {
    fn new(pieces: &'a [Vec<f64>], limits: &'a Limits<'a>) -> Run<'a> {
        let lengths: Vec<f64> = pieces
            .iter()
            .map(|piece| {
                piece.iter().zip(limits.velocity).map(|(d, v)| d.abs() / v).fold(0.0, f64::max)
            })
            .collect();
        let accelerations = pieces
            .iter()
            .zip(&lengths)
            .map(|(piece, &length)| {
                piece
                    .iter()
                    .zip(limits.acceleration)
                    .filter(|(d, _)| **d != 0.0)
                    .map(|(d, a)| a * length / d.abs())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        // At rest at both ends; every state between is bounded by its turn.
        let caps = (0..=pieces.len())
            .map(|state| match state {
                0 => 0.0,
                last if last == pieces.len() => 0.0,
                _ => turn_cap(pieces, &lengths, limits, state),
            })
            .collect();
        Run { pieces, limits, lengths, accelerations, caps }
    }

    /// The squared path speed at each state: the largest the caps allow from which the run can
    /// still start and stop within the pieces' accelerations (the backward and forward passes).
    fn speeds(&self) -> Vec<f64> {
        let mut squared = self.caps.clone();
        let reach = |k: usize| 2.0 * self.accelerations[k] * self.lengths[k];
        for k in (0..self.pieces.len()).rev() {
            squared[k] = squared[k].min(squared[k + 1] + reach(k));
        }
        for k in 0..self.pieces.len() {
            squared[k + 1] = squared[k + 1].min(squared[k] + reach(k));
        }
        squared
    }

    fn durations(mut self) -> Vec<f64> {
        let mut durations = Vec::new();
        for _ in 0..MAX_REPAIRS {
            let squared = self.speeds();
            durations = self.piece_durations(&squared);
            let ratios = self.turn_ratios(&durations);
            let mut repaired = false;
            for (state, &ratio) in ratios.iter().enumerate() {
                // The ends are at rest already. A turn that asks for too much is taken slower:
                // the change of velocity there grows with the speed and the time it is spread
                // over shrinks with it, so the acceleration goes as the squared speed.
                if ratio > 1.0 + RATIO_SLACK && state > 0 && state < self.pieces.len() {
                    self.caps[state] = squared[state] / ratio;
                    repaired = true;
                }
            }
            if !repaired {
                break;
            }
        }
        // Whatever is left over (a repair that did not converge) is removed by slowing the whole
        // run: time scaled by c divides velocities by c and accelerations by c².
        let worst_acceleration =
            self.turn_ratios(&durations).into_iter().fold(1.0, f64::max).sqrt();
        let worst_velocity = self.velocity_ratios(&durations).fold(1.0, f64::max);
        let scale = worst_acceleration.max(worst_velocity);
        if scale > 1.0 + RATIO_SLACK {
            durations.iter_mut().for_each(|duration| *duration *= scale);
        }
        durations
    }

    /// The time each piece takes with squared path speeds `squared` at its ends: the fastest
    /// trapezoid between them within the piece's path acceleration and a path speed of 1.
    fn piece_durations(&self, squared: &[f64]) -> Vec<f64> {
        (0..self.pieces.len())
            .map(|k| {
                let (length, acceleration) = (self.lengths[k], self.accelerations[k]);
                let (start, end) = (squared[k].max(0.0), squared[k + 1].max(0.0));
                let peak_squared = (acceleration * length + (start + end) / 2.0).min(1.0);
                let peak = peak_squared.sqrt();
                let ramps = (2.0 * peak_squared - start - end) / (2.0 * acceleration);
                let cruise = (length - ramps).max(0.0);
                ((peak - start.sqrt()).max(0.0) + (peak - end.sqrt()).max(0.0)) / acceleration
                    + cruise / peak
            })
            .collect()
    }

    /// Per piece, the largest ratio of a coordinate's recorded velocity to its limit.
    fn velocity_ratios<'d>(&'d self, durations: &'d [f64]) -> impl Iterator<Item = f64> + 'd {
        self.pieces.iter().zip(durations).map(|(piece, duration)| {
            piece
                .iter()
                .zip(self.limits.velocity)
                .map(|(d, v)| d.abs() / duration / v)
                .fold(0.0, f64::max)
        })
    }

    /// Per state, the largest ratio of a coordinate's recorded acceleration to its limit: the
    /// change of the piece velocities on either side over the time between the pieces' midpoints,
    /// with rest before the first piece and after the last.
    fn turn_ratios(&self, durations: &[f64]) -> Vec<f64> {
        let count = self.pieces.len();
        (0..=count)
            .map(|state| {
                let before = state.checked_sub(1);
                let after = (state < count).then_some(state);
                let half = |k: Option<usize>| k.map_or(0.0, |k| durations[k] / 2.0);
                let interval = half(before) + half(after);
                (0..self.limits.velocity.len())
                    .map(|j| {
                        let velocity =
                            |k: Option<usize>| k.map_or(0.0, |k| self.pieces[k][j] / durations[k]);
                        (velocity(after) - velocity(before)).abs()
                            / interval
                            / self.limits.acceleration[j]
                    })
                    .fold(0.0, f64::max)
            })
            .collect()
    }
}

/// The bound on the squared path speed at the turn between pieces `state - 1` and `state`: the
/// direction of motion (per unit of `s`) changes there, and at path speed σ every coordinate's
/// velocity changes by σ times its change of direction, in about the time between the pieces'
/// midpoints, half their lengths over σ; so σ² may be at most the acceleration limit times that
/// half length over the change of direction.
fn turn_cap(pieces: &[Vec<f64>], lengths: &[f64], limits: &Limits<'_>, state: usize) -> f64 {
    let (before, after) = (state - 1, state);
    let half = (lengths[before] + lengths[after]) / 2.0;
    pieces[before]
        .iter()
        .zip(&pieces[after])
        .zip(limits.acceleration)
        .map(|((b, a), limit)| {
            let change = (a / lengths[after] - b / lengths[before]).abs();
            if change == 0.0 { f64::INFINITY } else { limit * half / change }
        })
        .fold(1.0, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The recorded velocity and acceleration of every coordinate, as ratios to its limits (the
    /// module's definition), and the largest of each.
    fn worst_ratios(pieces: &[Vec<f64>], durations: &[f64], limits: &Limits<'_>) -> (f64, f64) {
        let run = Run::new(pieces, limits);
        let velocity = run.velocity_ratios(durations).fold(0.0, f64::max);
        let acceleration = run.turn_ratios(durations).into_iter().fold(0.0, f64::max);
        (velocity, acceleration)
    }

    /// `length` along one coordinate, cut into `count` equal pieces.
    fn straight(length: f64, count: usize) -> Vec<Vec<f64>> {
        vec![vec![length / count as f64]; count]
    }

    /// The textbook rest-to-rest time of a straight move of `length` at most `v` and `a`.
    fn trapezoid_time(length: f64, v: f64, a: f64) -> f64 {
        if length >= v * v / a { length / v + v / a } else { 2.0 * (length / a).sqrt() }
    }

    #[test]
    fn a_straight_move_takes_the_trapezoid_time_however_it_is_cut() {
        let limits = Limits { velocity: &[1.0], acceleration: &[2.0] };
        // 1 m at 1 m/s and 2 m/s²: 0.5 s up, 0.5 s cruise, 0.5 s down = 1.5 s. 0.16 m never
        // reaches the limit: a triangle of 2·√(0.16/2) = 0.566 s.
        for (length, expected) in [(1.0, 1.5), (0.16, 2.0 * 0.08f64.sqrt())] {
            assert!((trapezoid_time(length, 1.0, 2.0) - expected).abs() < 1e-12);
            for count in [1, 2, 7, 100, 333] {
                let pieces = straight(length, count);
                let durations = time_path(&pieces, &limits).expect("times");
                let total: f64 = durations.iter().sum();
                assert!(
                    (total - expected).abs() < 1e-9,
                    "{length} m in {count} pieces: {total} s, not {expected} s"
                );
                let (velocity, acceleration) = worst_ratios(&pieces, &durations, &limits);
                assert!(velocity <= 1.0 + 1e-9, "{count} pieces: velocity ratio {velocity}");
                assert!(acceleration <= 1.0 + 1e-9, "{count} pieces: accel ratio {acceleration}");
            }
        }
    }

    #[test]
    fn the_slowest_coordinate_sets_the_pace_and_all_arrive_together() {
        // 0.5 m at 0.1 m/s (5 s at full speed) with 1 rad at 1 rad/s: the first coordinate caps
        // the speed; the second's 1 rad/s² caps the path's acceleration at 5 /s², so the
        // trapezoid is 5 s + 1/5 s.
        let limits = Limits { velocity: &[0.1, 1.0], acceleration: &[1.0, 1.0] };
        let pieces = vec![vec![0.005, 0.01]; 100];
        let durations = time_path(&pieces, &limits).expect("times");
        let total: f64 = durations.iter().sum();
        assert!((total - 5.2).abs() < 1e-9, "{total}");
        let (velocity, acceleration) = worst_ratios(&pieces, &durations, &limits);
        assert!((velocity - 1.0).abs() < 1e-9, "the first coordinate reaches its limit");
        assert!(acceleration <= 1.0 + 1e-9);
    }

    #[test]
    fn a_sharp_turn_is_taken_slowly_and_every_sample_stays_within_its_limits() {
        let limits = Limits { velocity: &[1.0, 1.0], acceleration: &[1.0, 1.0] };
        // 1 m along x, then 1 m along y, in 1 cm pieces: the turn is a right angle.
        let mut pieces = vec![vec![0.01, 0.0]; 100];
        pieces.extend(vec![vec![0.0, 0.01]; 100]);
        let durations = time_path(&pieces, &limits).expect("times");
        let (velocity, acceleration) = worst_ratios(&pieces, &durations, &limits);
        assert!(velocity <= 1.0 + 1e-9, "{velocity}");
        assert!(acceleration <= 1.0 + 1e-9, "{acceleration}");
        // Nearly a stop at the corner: not much faster than two separate moves (2 s each), and
        // not slowed as a whole (the straight parts still reach full speed).
        let total: f64 = durations.iter().sum();
        assert!((3.8..=4.0).contains(&total), "{total}");
        let fastest = pieces
            .iter()
            .zip(&durations)
            .map(|(piece, duration)| piece[0].abs().max(piece[1].abs()) / duration)
            .fold(0.0, f64::max);
        assert!(fastest > 0.99, "the straight parts reach the limit: {fastest}");
    }

    #[test]
    fn a_gently_curving_path_keeps_its_speed_and_its_limits() {
        // A quarter circle of radius 1 in 200 pieces: the turns are small, the speed stays high.
        let limits = Limits { velocity: &[1.0, 1.0], acceleration: &[2.0, 2.0] };
        let points: Vec<[f64; 2]> = (0..=200)
            .map(|k| {
                let angle = std::f64::consts::FRAC_PI_2 * k as f64 / 200.0;
                [angle.cos(), angle.sin()]
            })
            .collect();
        let pieces: Vec<Vec<f64>> =
            points.windows(2).map(|w| vec![w[1][0] - w[0][0], w[1][1] - w[0][1]]).collect();
        let durations = time_path(&pieces, &limits).expect("times");
        let (velocity, acceleration) = worst_ratios(&pieces, &durations, &limits);
        assert!(velocity <= 1.0 + 1e-9, "{velocity}");
        assert!(acceleration <= 1.0 + 1e-9, "{acceleration}");
        let total: f64 = durations.iter().sum();
        // The arc is 1.571 m long; at 1 m/s on the faster axis it takes well under 3 s.
        assert!(total < 3.0, "{total}");
    }

    #[test]
    fn still_pieces_take_no_time_and_split_the_path_into_rests() {
        let limits = Limits { velocity: &[1.0], acceleration: &[2.0] };
        let mut pieces = straight(1.0, 10);
        pieces.push(vec![0.0]);
        pieces.extend(straight(0.16, 4));
        let durations = time_path(&pieces, &limits).expect("times");
        assert_eq!(durations[10], 0.0);
        let first: f64 = durations[..10].iter().sum();
        let second: f64 = durations[11..].iter().sum();
        assert!((first - 1.5).abs() < 1e-9 && (second - 2.0 * 0.08f64.sqrt()).abs() < 1e-9);
        assert_eq!(time_path(&[], &limits), Ok(Vec::new()));
    }

    #[test]
    fn bad_limits_and_pieces_are_named() {
        let limits = Limits { velocity: &[1.0, 0.0], acceleration: &[1.0, 1.0] };
        assert_eq!(
            time_path(&[vec![1.0, 1.0]], &limits),
            Err(TimingError::Limit { what: "velocity", coordinate: 1, value: 0.0 })
        );
        let limits = Limits { velocity: &[1.0], acceleration: &[1.0] };
        assert_eq!(
            time_path(&[vec![1.0], vec![1.0, 2.0]], &limits),
            Err(TimingError::Dimension { piece: 1, found: 2, expected: 1 })
        );
        assert!(matches!(
            time_path(&[vec![f64::NAN]], &limits),
            Err(TimingError::NotFinite { piece: 0, coordinate: 0, .. })
        ));
    }
}
