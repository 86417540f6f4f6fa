//! The physics check: does a scene stay put under gravity?
//!
//! The bodies of a final scene are simulated for [`SIMULATED_SECONDS`] with a real rigid-body
//! engine (rapier3d, of the same family as the parry that lamp-geometry uses), fixed bodies
//! held in place, and each free body's drift measured: how far it moved and how far it turned.
//! A body that moves more than [`MAX_SHIFT`] or turns more than [`MAX_TURN`] was not at rest.
//!
//! Rapier is used only inside the private `rapier_boundary` module; the public API speaks
//! lamp-geometry's shapes and nalgebra poses. The simulation runs a fixed number of fixed
//! steps, reads no clock and is single-threaded, so the same scene gives the same drifts.

mod contact;
mod rapier_boundary;

use lamp_geometry::{Pose, Real, Shape};

/// How long a scene is simulated (seconds): long enough for a body that tips over an edge, or
/// slides off a slope, to move well beyond the thresholds.
pub const SIMULATED_SECONDS: Real = 2.0;

/// The simulation's time step (seconds): about 1 ms, four steps per period of the stiffest
/// contact ([`CONTACT_FREQUENCY`] against fixed bodies is twice that), which keeps the contacts
/// stable.
pub const STEP_SECONDS: Real = 1.0 / 960.0;

/// The natural frequency of a contact between two free bodies (Hz; against a fixed body, twice
/// this). Rapier's contacts are springs: a stack of n bodies sinks by about g / ω² per body above
/// each contact, g / ω² · n(n + 1)/2 in all, so the engine's default of 30 Hz (built for metre-sized
/// game objects) lets a 15-layer Jenga tower sink 4 mm at its base and 40 mm at its top, and the
/// check would call a perfect tower unstable. At 240 Hz the same tower sinks 0.6 mm at its top.
pub const CONTACT_FREQUENCY: Real = 240.0;

/// The farthest a body may move (metres) and still count as at rest: 5 mm, the settling a
/// release is allowed.
pub const MAX_SHIFT: Real = 0.005;

/// The largest rotation a body may make (radians) and still count as at rest: 3°.
pub const MAX_TURN: Real = 3.0 * std::f64::consts::PI / 180.0;

/// Gravity, along −z (m/s²).
pub const GRAVITY: Real = 9.81;

/// The coefficient of friction of every contact: 0.5, between wood and wood or a can on a
/// table; the check asks whether things stay where they are put, not whether they grip.
pub const FRICTION: Real = 0.5;

/// A body to simulate.
#[derive(Clone, Copy, Debug)]
pub struct PhysicsBody<'a> {
    pub name: &'a str,
    /// The body's shapes, each placed in its frame (at uniform density).
    pub parts: &'a [(Pose, Shape)],
    /// Where the body is.
    pub pose: Pose,
    /// Fixed bodies never move (the floor, tables, walls).
    pub fixed: bool,
}

/// How far a free body drifted over the simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct Drift {
    pub name: String,
    /// Distance its frame's origin moved (metres).
    pub shift: Real,
    /// Angle of the rotation it made (radians).
    pub turn: Real,
    /// How far it was lowered onto what is under it before the simulation (metres): its own
    /// resting gap and the sink of what it rests on. `shift` and `turn` are measured from the
    /// lowered pose; the sink is how far below the scene's pose the body would end in the world.
    pub sink: Real,
}

impl Drift {
    /// Whether the body stayed within [`MAX_SHIFT`] and [`MAX_TURN`].
    pub fn at_rest(&self) -> bool {
        self.shift <= MAX_SHIFT && self.turn <= MAX_TURN
    }
}

/// A scene the physics engine cannot simulate.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum PhysicsError {
    /// A shape the engine refuses.
    #[error("body `{body}` cannot be simulated: {reason}")]
    #[diagnostic(code(lamp::physics::shape), help("check the body type's shapes and mesh files"))]
    Shape { body: String, reason: String },
}

/// Simulates `bodies` under gravity for [`SIMULATED_SECONDS`]; returns the drift of every body
/// that is not fixed, in the order given.
///
/// The scenes' convention is that a body at rest floats up to `resting_gap` (metres) above its
/// support (touching would be a collision). Before the simulation every free body is lowered
/// straight down onto what is under it, from the bottom up, its own gap and the sink of its
/// support, and its drift is measured from there; the engine itself bridges no gap.
pub fn simulate(bodies: &[PhysicsBody<'_>], resting_gap: Real) -> Result<Vec<Drift>, PhysicsError> {
    let steps = (SIMULATED_SECONDS / STEP_SECONDS).round() as usize;
    let lowered = contact::onto_contact(bodies, resting_gap.max(0.0))?;
    let starts: Vec<PhysicsBody<'_>> = bodies
        .iter()
        .zip(&lowered)
        .map(|(body, lowered)| PhysicsBody { pose: lowered.pose, ..*body })
        .collect();
    let finals = rapier_boundary::simulate(&starts, steps)?;
    Ok(starts
        .iter()
        .zip(lowered)
        .zip(finals)
        .filter(|((body, _), _)| !body.fixed)
        .map(|((body, lowered), end)| Drift {
            name: body.name.to_string(),
            shift: (end.translation.vector - body.pose.translation.vector).norm(),
            turn: body.pose.rotation.angle_to(&end.rotation),
            sink: lowered.sink,
        })
        .collect())
}

/// The first free body (in the order given) that does not stay at rest, with its drift
/// ([`simulate`] says what `resting_gap` is).
pub fn first_unsettled(
    bodies: &[PhysicsBody<'_>],
    resting_gap: Real,
) -> Result<Option<Drift>, PhysicsError> {
    Ok(simulate(bodies, resting_gap)?.into_iter().find(|drift| !drift.at_rest()))
}
