//! Closing the resting gaps before the simulation.
//!
//! lamp's scenes leave a body at rest up to a resting gap above its support (touching would be
//! a collision), so a stack of n bodies stands n gaps higher than the same stack would in the
//! world. Bridging the gaps inside the engine (a contact skin) would hide that: the simulation
//! would hold every body at its planned height. Instead each free body is lowered straight down
//! onto what is under it before the simulation, from the bottom up, so that a body also goes down
//! by the sink of what it rests on. The sink is how far the body ends below where the scene has
//! it; the simulation then starts from bodies that touch and needs no skin.
//!
//! Only a body's own gap of at most the resting gap (and a little numerical slack) is closed. A
//! body farther above its support is not resting by the scene's convention: it is left where it
//! is, and the simulation lets it fall.

use lamp_geometry::{Aabb, CollisionShape, Pose, Real, drop_distance};

use crate::{PhysicsBody, PhysicsError};

/// How much more than the resting gap a body may be above its support and still have its gap
/// closed (metres): rounding in the poses a scene was written with.
const SLACK: Real = 1e-5;

/// Where a body starts the simulation, and how far it was lowered to get there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lowered {
    pub pose: Pose,
    /// How far the body went straight down (metres): its own gap and what it rests on sank.
    pub sink: Real,
}

/// Every body lowered onto what is under it, in the order given; fixed bodies and bodies without
/// shapes stay where they are.
pub(crate) fn onto_contact(
    bodies: &[PhysicsBody<'_>],
    resting_gap: Real,
) -> Result<Vec<Lowered>, PhysicsError> {
    let shapes = bodies
        .iter()
        .map(|body| {
            if body.parts.is_empty() {
                return Ok(None);
            }
            CollisionShape::compound(body.parts).map(Some).map_err(|error| PhysicsError::Shape {
                body: body.name.to_string(),
                reason: error.to_string(),
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut lowered: Vec<Lowered> =
        bodies.iter().map(|body| Lowered { pose: body.pose, sink: 0.0 }).collect();
    let boxes: Vec<Option<Aabb>> = shapes
        .iter()
        .zip(bodies)
        .map(|(shape, body)| Some(shape.as_ref()?.aabb(&body.pose)))
        .collect();
    // Bottom up: what a body may rest on has been lowered before it (ties by the order given).
    let mut order: Vec<usize> = (0..bodies.len())
        .filter(|&index| !bodies[index].fixed && shapes[index].is_some())
        .collect();
    order.sort_by(|&a, &b| bottom(&boxes[a]).total_cmp(&bottom(&boxes[b])).then(a.cmp(&b)));
    let mut settled: Vec<bool> = bodies.iter().map(|body| body.fixed).collect();
    for index in order {
        let (Some(shape), Some(outline)) = (&shapes[index], &boxes[index]) else { continue };
        let pose = bodies[index].pose;
        let mut landing: Option<(Real, Real)> = None;
        for support in (0..bodies.len()).filter(|&other| other != index && settled[other]) {
            let (Some(under), Some(under_box)) = (&shapes[support], &boxes[support]) else {
                continue;
            };
            let sunk = lowered[support].sink;
            let reach = resting_gap + SLACK + sunk;
            if !beneath(outline, under_box, sunk, reach) {
                continue;
            }
            if let Some(drop) = drop_distance(shape, &pose, under, &lowered[support].pose, reach)
                && landing.is_none_or(|(nearest, _)| drop < nearest)
            {
                landing = Some((drop, drop - sunk));
            }
        }
        if let Some((drop, own_gap)) = landing
            && own_gap <= resting_gap + SLACK
        {
            let mut at = pose;
            at.translation.vector.z -= drop;
            lowered[index] = Lowered { pose: at, sink: drop };
        }
        settled[index] = true;
    }
    Ok(lowered)
}

fn bottom(outline: &Option<Aabb>) -> Real {
    outline.as_ref().map_or(Real::INFINITY, |outline| outline.mins.z)
}

/// Whether `under`, lowered by `sunk`, can be within `reach` below `body` (their boxes overlap
/// across and `under` does not lie wholly above).
fn beneath(body: &Aabb, under: &Aabb, sunk: Real, reach: Real) -> bool {
    let across = (0..2)
        .all(|axis| body.mins[axis] <= under.maxs[axis] && under.mins[axis] <= body.maxs[axis]);
    across && under.mins.z - sunk <= body.maxs.z && under.maxs.z - sunk >= body.mins.z - reach
}
