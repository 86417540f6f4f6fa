//! Laying out a structure demonstration's scene (Jenga, Keva): the objects of a training
//! structure already placed and settled, and loose ones scattered on the table top.

use lamp_geometry::Pose;
use lamp_world::{Body, Scene, SpecWorld};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::skills::{Attempt, SurfaceTop, pose};

/// The table of a structure demonstration: the widest static body (not a marker) of the spec's
/// first problem, with its pose, its top and its type's name.
pub(crate) struct Table {
    pub(crate) body: Body,
    pub(crate) pose: Pose,
    pub(crate) top: SurfaceTop,
    pub(crate) type_name: String,
}

impl Table {
    /// The spec's table, or `None` when its first problem has no static body with a top.
    pub(crate) fn of(world: &SpecWorld) -> Option<Table> {
        let problem = world.spec().problems.first()?;
        let mut table: Option<Table> = None;
        for object in &problem.scene.objects {
            let Some(body) = world.body(&object.name, &object.type_name) else { continue };
            if body.movable || body.is_marker() {
                continue;
            }
            let Some(top) = SurfaceTop::of_parts(object.pose, &body.parts) else { continue };
            let area = |top: &SurfaceTop| top.half_x * top.half_y;
            if table.as_ref().is_none_or(|best| area(&top) > area(&best.top)) {
                let type_name = object.type_name.clone();
                table = Some(Table { body, pose: object.pose, top, type_name });
            }
        }
        table
    }
}

/// Object number `index` of a type, named `<stem><index + 1>` (`block1`, `plank2`, …).
pub(crate) fn numbered_body(
    world: &SpecWorld,
    stem: &str,
    type_name: &str,
    index: usize,
) -> Attempt<Body> {
    world
        .body(&format!("{stem}{}", index + 1), type_name)
        .ok_or_else(|| format!("no type `{type_name}`"))
}

/// Adds a body made by `body(index)` at each pose, each settled by the resting rule before the
/// next is added (one resting on another finds it in place); their scene indices, in order.
pub(crate) fn add_settled(
    scene: &mut Scene,
    poses: &[Pose],
    body: impl Fn(usize) -> Attempt<Body>,
) -> Attempt<Vec<usize>> {
    let mut added = Vec::with_capacity(poses.len());
    for (index, at) in poses.iter().enumerate() {
        let object = scene.add_body(body(index)?, *at).map_err(|e| e.to_string())?;
        let rest = scene.resting_pose(object).map_err(|e| format!("pre-placed: {e}"))?;
        scene.set_body_pose(object, rest);
        added.push(object);
    }
    Ok(added)
}

/// Adds a body made by `body(index)` at each pose, as it is; their scene indices, in order.
pub(crate) fn add_at(
    scene: &mut Scene,
    poses: &[Pose],
    body: impl Fn(usize) -> Attempt<Body>,
) -> Attempt<Vec<usize>> {
    let mut added = Vec::with_capacity(poses.len());
    for (index, at) in poses.iter().enumerate() {
        added.push(scene.add_body(body(index)?, *at).map_err(|e| e.to_string())?);
    }
    Ok(added)
}

/// Where loose objects go on a table top: within ±`half` of its centre, their frames `height`
/// above it, at any yaw, their frames at least
/// `clearance` from a structure's anchor and `spacing` from each other (along the top).
pub(crate) struct Scatter {
    pub(crate) half: (f64, f64),
    pub(crate) height: f64,
    pub(crate) clearance: f64,
    pub(crate) spacing: f64,
    /// Draws before giving up.
    pub(crate) draws: usize,
}

impl Scatter {
    /// `count` poses on `top` clear of `anchor` and of each other, or `None` when the draws run
    /// out first.
    pub(crate) fn poses(
        &self,
        top: &SurfaceTop,
        anchor: &Pose,
        count: usize,
        rng: &mut ChaCha8Rng,
    ) -> Option<Vec<Pose>> {
        let (half_x, half_y) = self.half;
        let centre = anchor.translation.vector;
        let along_top = |a: &nalgebra::Vector3<f64>, b: &nalgebra::Vector3<f64>| {
            ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt()
        };
        let mut poses: Vec<Pose> = Vec::new();
        for _ in 0..self.draws {
            if poses.len() == count {
                break;
            }
            let at = top.pose
                * pose(
                    rng.random_range(-half_x..=half_x),
                    rng.random_range(-half_y..=half_y),
                    self.height,
                    0.0,
                    0.0,
                    rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
                );
            let p = at.translation.vector;
            if along_top(&p, &centre) >= self.clearance
                && poses
                    .iter()
                    .all(|other| along_top(&p, &other.translation.vector) >= self.spacing)
            {
                poses.push(at);
            }
        }
        (poses.len() == count).then_some(poses)
    }
}
