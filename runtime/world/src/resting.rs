//! Letting go of an object: it is settled straight down to rest on what is below it, and kept
//! only if it is statically supported there. One rule for the demonstrators, the solver and the
//! final replay, written down in `docs/world.md`.
//!
//! "At rest" follows the scenes' convention that touching counts as a collision: a resting body
//! floats [`RESTING_GAP`] above its support, the way the bundled scenes place their objects.

use lamp_geometry::{BodyId, ContactPoint, Pose, Real, Rotation, Vec3};
use nalgebra::Translation3;

use crate::scene::Scene;

/// The clearance a body at rest keeps above what supports it (metres): 1 mm, as every bundled
/// scene places its objects, so that a resting body can be grabbed again without touching.
pub const RESTING_GAP: Real = 0.001;

/// The farthest a released body may be settled down (metres): what a robot may drop an object
/// by without it bouncing or tipping, and what the physics check lets a body move. A body
/// released higher above its support than this is refused, not dropped.
pub const MAX_SETTLE_DROP: Real = 0.005;

/// A drop shorter than this (metres) is rounding: the body is left where it is, so that a
/// placement made exactly at rest is not rewritten by a micrometre.
const AT_REST: Real = 1e-6;

/// How far beyond [`RESTING_GAP`] (metres) a point still counts as a contact that supports.
const CONTACT_BAND: Real = 0.0005;

/// The least upward component of a supporting contact's normal: a face tilted more than 45°
/// from level does not hold a body up (friction would have to, which the rule does not count on).
const LEVEL_ENOUGH: Real = std::f64::consts::FRAC_1_SQRT_2;

/// How far (metres) the centre of mass may lie outside the support polygon and still count as
/// inside: the rounding of contact points, and a round body's line of contact.
pub const SUPPORT_TOLERANCE: Real = 0.0005;

/// The most a released body may lean from lying level (radians) and still be set level as it
/// lands: 5°. A robot lets go of what it carries with the small tilt its grasp and inverse
/// kinematics leave; a box or a can that lands on a flat face seats itself on it. A body leaning
/// further is left as it is, for the support test to judge.
pub const MAX_SETTLE_TILT: Real = 5.0 * std::f64::consts::PI / 180.0;

/// A lean under this (radians) is rounding: the orientation is left as it is.
const LEVEL: Real = 1e-9;

/// A turn under this (radians) of a body the rule would settle again is rounding: it is at
/// rest.
const LEAVE_ALONE_TURN: Real = 1e-6;

/// A lean under this (radians, 0.06°) cannot tip any real body over (one would need to be
/// a thousand times taller than it is wide), and its low edge is a matter of rounding among the
/// contact points: the body is seated without the tipping test.
const TIPS_NEVER: Real = 1e-3;

/// How far down a release looks for a support (metres): far enough to name what is below a
/// body released much too high.
const LOOK_DOWN: Real = 100.0;

/// Why a released body cannot be left at rest where it is.
#[derive(Clone, Debug, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum RestError {
    /// Nothing at all below the body.
    #[error("`{object}` would fall: there is nothing below it")]
    #[diagnostic(
        code(lamp::world::nothing_below),
        help("an object must be put down on a surface or on another object")
    )]
    NothingBelow { object: String },
    /// The body is let go of too high above its support.
    #[error(
        "`{object}` would drop {:.1} mm onto `{below}`, more than the {:.0} mm a release may settle",
        drop * 1000.0,
        MAX_SETTLE_DROP * 1000.0
    )]
    #[diagnostic(
        code(lamp::world::released_too_high),
        help("lower the object to within a few millimetres of its support before letting go")
    )]
    TooHigh { object: String, below: String, drop: Real },
    /// The body touches or overlaps another where it is let go of.
    #[error("`{object}` touches `{body}` where it is let go of")]
    #[diagnostic(
        code(lamp::world::released_touching),
        help("a released object must clear what is under it; it is settled down, never lifted")
    )]
    Touching { object: String, body: String },
    /// At rest, the body would touch a robot (the gripper that let go of it).
    #[error("`{object}` would touch {link} as it comes to rest")]
    #[diagnostic(
        code(lamp::world::released_into_robot),
        help("let go of the object level, or with the fingers clear of where it will rest")
    )]
    TouchingRobot { object: String, link: String },
    /// Landed on the low edge of its base, the body's centre of mass lies beyond that edge: it
    /// falls over instead of seating itself level.
    #[error(
        "`{object}` would tip over: let go of leaning {:.1}°, its centre of mass is beyond the edge it lands on (it seats itself only when leaning less than {:.1}° that way)",
        lean.to_degrees(),
        tipping.to_degrees()
    )]
    #[diagnostic(
        code(lamp::world::tips_over),
        help("let go of the object more nearly level, above the face it is to rest on")
    )]
    TipsOver { object: String, lean: Real, tipping: Real },
    /// The body's centre of mass is outside the polygon of its supporting contacts.
    #[error(
        "`{object}` is not supported: its centre of mass is {:.1} mm outside the contacts that hold it up{}",
        outside * 1000.0,
        on_list(supports)
    )]
    #[diagnostic(
        code(lamp::world::unsupported),
        help(
            "put the object down with its centre of mass over what it rests on, not hanging over an edge"
        )
    )]
    Unsupported { object: String, outside: Real, supports: Vec<String> },
}

impl RestError {
    /// The released object, where the refusal says that nothing holds it up where it was let go
    /// of: nothing below it, its support too far down, or its centre of mass beyond its contacts.
    /// Something set down later may hold it up there; a body in the way or a lean is another
    /// matter.
    pub fn lacks_support(&self) -> Option<&str> {
        match self {
            RestError::NothingBelow { object }
            | RestError::TooHigh { object, .. }
            | RestError::Unsupported { object, .. } => Some(object),
            RestError::Touching { .. }
            | RestError::TouchingRobot { .. }
            | RestError::TipsOver { .. } => None,
        }
    }
}

/// An object that would no longer rest once what it rested on is taken away
/// ([`Scene::rests_without`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("`{object}` would be left without its support: {reason}")]
pub struct LeftUnsupported {
    /// The object left behind.
    pub object: String,
    /// How it would fall: the resting rule's refusal, or how far it would settle.
    pub reason: String,
}

fn on_list(supports: &[String]) -> String {
    if supports.is_empty() {
        " (no level contact)".to_string()
    } else {
        format!(
            " (on {})",
            supports.iter().map(|name| format!("`{name}`")).collect::<Vec<_>>().join(", ")
        )
    }
}

impl Scene {
    /// Lets go of what `robot` holds and settles it to rest: straight down to [`RESTING_GAP`]
    /// above what is below it, if that is at most [`MAX_SETTLE_DROP`] away, and only if it is
    /// statically supported there. Returns the released body (`None` when the gripper is
    /// empty); on an error the scene is unchanged and the body still held.
    pub fn release_at_rest(&mut self, robot: usize) -> Result<Option<usize>, RestError> {
        let Some(held) = self.held(robot) else { return Ok(None) };
        let rest = self.resting_pose(held.body)?;
        // Seating itself level turns the object about the point it lands on, which may swing
        // its top into the fingers that just let go of it.
        if let Some(link) = self.link_near_body(held.body, &rest) {
            let object = self.bodies[held.body].name.clone();
            return Err(RestError::TouchingRobot { object, link });
        }
        self.release(robot);
        self.set_body_pose(held.body, rest);
        Ok(Some(held.body))
    }

    /// Where `body` comes to rest if let go of now, or why it cannot (the rule of
    /// [`Scene::release_at_rest`]). Held objects and markers are not supports.
    pub fn resting_pose(&self, body: usize) -> Result<Pose, RestError> {
        let name = || self.bodies[body].name.clone();
        let Some(shape) = self.collision.shape(BodyId(body)) else {
            // A marker has no geometry: nothing to settle.
            return Ok(self.body_pose(body));
        };
        let released = self.body_pose(body);
        let skip = |id: BodyId| id.0 == body;
        let Some((below, gap)) = self.collision.first_below(shape, &released, LOOK_DOWN, skip)
        else {
            return Err(RestError::NothingBelow { object: name() });
        };
        let below_name = self.bodies[below.0].name.clone();
        if gap <= 0.0 {
            return Err(RestError::Touching { object: name(), body: below_name });
        }
        // The first point to land falls `gap`: that is the drop the limit is about, whether or
        // not the body then seats itself level.
        let drop = gap - RESTING_GAP;
        if drop > MAX_SETTLE_DROP {
            return Err(RestError::TooHigh { object: name(), below: below_name, drop });
        }
        let landed = if drop > AT_REST {
            Translation3::from(Vec3::new(0.0, 0.0, -drop)) * released
        } else {
            released
        };
        let Some(turn) = leveling_turn(&landed) else {
            self.check_support(body, &landed)?;
            return Ok(landed);
        };
        // It seats itself by turning about the point it landed on (the low edge of its base),
        // which stays where it is, as friction holds it.
        let reach = RESTING_GAP + CONTACT_BAND;
        let pivot = self
            .collision
            .contact_points(shape, &landed, reach, skip)
            .into_iter()
            .map(|(_, contact)| contact.point)
            .min_by(|a, b| a.z.total_cmp(&b.z))
            .unwrap_or_else(|| landed * shape.centre_of_mass());
        // Gravity seats it only when it pulls the centre of mass down along the levelling turn;
        // past the edge's tipping angle it pulls the other way, and the body falls over.
        let centre = landed * shape.centre_of_mass();
        let arm = centre - pivot;
        let axis = turn.axis().map_or_else(Vec3::zeros, |axis| axis.into_inner());
        // The turn's axis is level, so this is how far the centre of mass lies beyond the edge
        // across it, whatever its offset along the edge.
        let beyond_edge = axis.cross(&arm).z;
        let lean = turn.angle();
        if beyond_edge >= 0.0 && lean >= TIPS_NEVER {
            let beyond = beyond_edge.atan2(arm.z.max(0.0));
            return Err(RestError::TipsOver {
                object: name(),
                lean,
                tipping: (lean - beyond).max(0.0),
            });
        }
        let seated =
            Translation3::from(pivot.coords) * turn * Translation3::from(-pivot.coords) * landed;
        if let Some(touched) = self.collision.first_contact(shape, &seated, 0.0, skip) {
            let body = self.bodies[touched.0].name.clone();
            return Err(RestError::Touching { object: name(), body });
        }
        // Level now, its base lies at the pivot's height, 1 mm above what was below the pivot;
        // what is below the rest of the base may be nearer (a step) or farther (an edge).
        let Some((below, gap)) = self.collision.first_below(shape, &seated, LOOK_DOWN, skip) else {
            return Err(RestError::NothingBelow { object: name() });
        };
        let drop = gap - RESTING_GAP;
        if drop > MAX_SETTLE_DROP {
            let below = self.bodies[below.0].name.clone();
            return Err(RestError::TooHigh { object: name(), below, drop });
        }
        // Seated nearer than the resting gap, it stays there: a body let go of never rises.
        let rest = if drop > AT_REST {
            Translation3::from(Vec3::new(0.0, 0.0, -drop)) * seated
        } else {
            seated
        };
        self.check_support(body, &rest)?;
        Ok(rest)
    }

    /// Whether every object that rested on `taken`, now held (a held object is no support),
    /// still rests where it is: `Err` names the first that would not, and why. An object
    /// within 1.5 mm of `taken` counts as resting on it; it still rests when the resting rule
    /// leaves it where it is (within a micrometre), else it would drop, tip or hang in the air,
    /// which no real robot can leave it to do.
    ///
    /// # Errors
    /// [`LeftUnsupported`] naming the first object that would no longer rest.
    pub fn rests_without(&self, taken: usize) -> Result<(), LeftUnsupported> {
        let Some(taken_shape) = self.collision.shape(BodyId(taken)) else { return Ok(()) };
        let taken_pose = self.body_pose(taken);
        let held: Vec<usize> = self
            .robots
            .iter()
            .filter_map(|robot| robot.gripper.as_ref()?.held.map(|held| held.body))
            .collect();
        let reach = RESTING_GAP + CONTACT_BAND;
        for (index, body) in self.bodies.iter().enumerate() {
            if !body.movable || index == taken || held.contains(&index) {
                continue;
            }
            let Some(shape) = self.collision.shape(BodyId(index)) else { continue };
            let pose = self.body_pose(index);
            if lamp_geometry::distance(shape, &pose, taken_shape, &taken_pose) > reach {
                continue;
            }
            let reason = match self.resting_pose(index) {
                Err(error) => error.to_string(),
                Ok(rest) => {
                    let moved = pose.inv_mul(&rest);
                    let shift = moved.translation.vector.norm();
                    if shift <= AT_REST && moved.rotation.angle() <= LEAVE_ALONE_TURN {
                        continue;
                    }
                    format!("it would settle {:.1} mm", shift * 1000.0)
                }
            };
            return Err(LeftUnsupported { object: body.name.clone(), reason });
        }
        Ok(())
    }

    /// Whether `body` at `pose` is statically supported: its centre of mass, projected straight
    /// down, lies within [`SUPPORT_TOLERANCE`] of the convex hull of its level contacts.
    fn check_support(&self, body: usize, pose: &Pose) -> Result<(), RestError> {
        let Some(shape) = self.collision.shape(BodyId(body)) else { return Ok(()) };
        let reach = RESTING_GAP + CONTACT_BAND;
        let contacts: Vec<(BodyId, ContactPoint)> = self
            .collision
            .contact_points(shape, pose, reach, |id| id.0 == body)
            .into_iter()
            .filter(|(_, contact)| contact.normal.z >= LEVEL_ENOUGH && contact.gap <= reach)
            .collect();
        let centre = pose * shape.centre_of_mass();
        let footprint: Vec<[Real; 2]> =
            contacts.iter().map(|(_, contact)| [contact.point.x, contact.point.y]).collect();
        let outside = distance_outside_hull([centre.x, centre.y], &footprint);
        if outside <= SUPPORT_TOLERANCE {
            return Ok(());
        }
        let mut supports: Vec<String> =
            contacts.iter().map(|(id, _)| self.bodies[id.0].name.clone()).collect();
        supports.sort();
        supports.dedup();
        Err(RestError::Unsupported { object: self.bodies[body].name.clone(), outside, supports })
    }
}

/// The turn that makes the body axis nearest to vertical vertical, when it leans by more than
/// rounding and less than [`MAX_SETTLE_TILT`]; `None` otherwise.
fn leveling_turn(pose: &Pose) -> Option<Rotation> {
    let rotation = pose.rotation.to_rotation_matrix();
    let nearest = rotation
        .matrix()
        .column_iter()
        .map(|axis| axis.into_owned())
        .max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))?;
    let lean = nearest.z.abs().min(1.0).acos();
    if !(LEVEL..=MAX_SETTLE_TILT).contains(&lean) {
        return None;
    }
    let vertical = Vec3::new(0.0, 0.0, nearest.z.signum());
    Rotation::rotation_between(&nearest, &vertical)
}

/// How far `point` lies outside the convex hull of `points` in the plane (0 inside; infinite
/// when there are no points).
fn distance_outside_hull(point: [Real; 2], points: &[[Real; 2]]) -> Real {
    let hull = convex_hull(points);
    match hull.as_slice() {
        [] => Real::INFINITY,
        [only] => length(sub(point, *only)),
        _ => {
            let edges = hull.iter().zip(hull.iter().cycle().skip(1));
            let inside = hull.len() > 2
                && edges.clone().all(|(a, b)| cross(sub(*b, *a), sub(point, *a)) >= 0.0);
            if inside {
                0.0
            } else {
                edges.map(|(a, b)| segment_distance(point, *a, *b)).fold(Real::INFINITY, Real::min)
            }
        }
    }
}

/// The convex hull, counter-clockwise, without collinear points (Andrew's monotone chain).
fn convex_hull(points: &[[Real; 2]]) -> Vec<[Real; 2]> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let mut hull: Vec<[Real; 2]> = Vec::with_capacity(2 * sorted.len());
    for pass in 0..2 {
        let start = hull.len();
        let sweep: Box<dyn Iterator<Item = &[Real; 2]>> =
            if pass == 0 { Box::new(sorted.iter()) } else { Box::new(sorted.iter().rev()) };
        for &p in sweep {
            while hull.len() >= start + 2
                && cross(
                    sub(hull[hull.len() - 1], hull[hull.len() - 2]),
                    sub(p, hull[hull.len() - 2]),
                ) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

fn sub(a: [Real; 2], b: [Real; 2]) -> [Real; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(a: [Real; 2], b: [Real; 2]) -> Real {
    a[0] * b[1] - a[1] * b[0]
}

fn length(a: [Real; 2]) -> Real {
    a[0].hypot(a[1])
}

fn segment_distance(point: [Real; 2], a: [Real; 2], b: [Real; 2]) -> Real {
    let along = sub(b, a);
    let squared = along[0] * along[0] + along[1] * along[1];
    let t = if squared > 0.0 {
        ((sub(point, a)[0] * along[0] + sub(point, a)[1] * along[1]) / squared).clamp(0.0, 1.0)
    } else {
        0.0
    };
    length(sub(point, [a[0] + t * along[0], a[1] + t * along[1]]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_inside_a_square_is_zero_outside_and_one_beyond_is_measured() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]];
        assert_eq!(distance_outside_hull([0.5, 0.5], &square), 0.0);
        assert_eq!(distance_outside_hull([1.0, 0.5], &square), 0.0);
        assert!((distance_outside_hull([2.0, 0.5], &square) - 1.0).abs() < 1e-12);
        assert!((distance_outside_hull([-0.5, -0.5], &square) - 0.5_f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_line_of_contact_holds_only_points_on_it() {
        let line = [[0.0, 0.0], [1.0, 0.0], [0.5, 0.0]];
        assert!(distance_outside_hull([0.5, 0.0], &line) < 1e-12);
        assert!((distance_outside_hull([0.5, 0.2], &line) - 0.2).abs() < 1e-12);
        assert_eq!(distance_outside_hull([0.0, 0.0], &[]), Real::INFINITY);
    }
}
