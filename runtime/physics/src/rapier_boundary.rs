//! The one place where rapier (and the parry and glam types it speaks) meets lamp's shapes and
//! nalgebra poses.

use lamp_geometry::{Pose, Shape, Vec3};
use rapier3d_f64::math::{Pose as RapierPose, Rotation as RapierRotation, Vector};
use rapier3d_f64::prelude::{ColliderBuilder, PhysicsWorld, RigidBodyBuilder};

use crate::{CONTACT_FREQUENCY, FRICTION, GRAVITY, PhysicsBody, PhysicsError, STEP_SECONDS};

fn to_rapier(pose: &Pose) -> RapierPose {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    RapierPose::from_parts(
        Vector::new(t.x, t.y, t.z),
        RapierRotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

fn from_rapier(pose: &RapierPose) -> Pose {
    let t = pose.translation;
    let q = pose.rotation;
    Pose::from_parts(
        nalgebra::Translation3::new(t.x, t.y, t.z),
        nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q.w, q.x, q.y, q.z)),
    )
}

fn vector(v: &lamp_geometry::Point3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// A collider for one part, in the body's frame. A free body's triangle mesh is simulated as
/// its convex hull: a body needs a volume to have a mass.
fn collider(
    name: &str,
    placement: &Pose,
    shape: &Shape,
    fixed: bool,
) -> Result<ColliderBuilder, PhysicsError> {
    let refused =
        |reason: &str| PhysicsError::Shape { body: name.to_string(), reason: reason.to_string() };
    let (builder, local) = match shape {
        Shape::Box { half_extents } => (
            ColliderBuilder::cuboid(half_extents.x, half_extents.y, half_extents.z),
            Pose::identity(),
        ),
        Shape::Sphere { radius } => (ColliderBuilder::ball(*radius), Pose::identity()),
        // Rapier's cylinders run along y, lamp's along z.
        Shape::Cylinder { radius, half_height } => (
            ColliderBuilder::cylinder(*half_height, *radius),
            Pose::rotation(Vec3::x() * std::f64::consts::FRAC_PI_2),
        ),
        Shape::ConvexHull { points } => {
            let points: Vec<Vector> = points.iter().map(vector).collect();
            let hull = ColliderBuilder::convex_hull(&points)
                .ok_or_else(|| refused("its convex hull spans no volume"))?;
            (hull, Pose::identity())
        }
        Shape::TriMesh { vertices, triangles } if fixed => {
            let vertices: Vec<Vector> = vertices.iter().map(vector).collect();
            let mesh = ColliderBuilder::trimesh(vertices, triangles.clone())
                .map_err(|error| refused(&error.to_string()))?;
            (mesh, Pose::identity())
        }
        Shape::TriMesh { vertices, .. } => {
            let points: Vec<Vector> = vertices.iter().map(vector).collect();
            let hull = ColliderBuilder::convex_hull(&points)
                .ok_or_else(|| refused("its mesh spans no volume"))?;
            (hull, Pose::identity())
        }
    };
    Ok(builder.position(to_rapier(&(placement * local))).friction(FRICTION).restitution(0.0))
}

/// Every body's pose after `steps` steps, in the order given. Colliders have no contact skin:
/// bodies touch where their shapes do.
pub(crate) fn simulate(
    bodies: &[PhysicsBody<'_>],
    steps: usize,
) -> Result<Vec<Pose>, PhysicsError> {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -GRAVITY);
    world.integration_parameters.dt = STEP_SECONDS;
    let contacts = &mut world.integration_parameters;
    contacts.contact_softness.natural_frequency = CONTACT_FREQUENCY;
    contacts.static_contact_softness.natural_frequency = 2.0 * CONTACT_FREQUENCY;
    let mut handles = Vec::with_capacity(bodies.len());
    for body in bodies {
        let builder =
            if body.fixed { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() };
        let handle = world.bodies.insert(builder.pose(to_rapier(&body.pose)));
        for (placement, shape) in body.parts {
            let part = collider(body.name, placement, shape, body.fixed)?;
            world.colliders.insert_with_parent(part, handle, &mut world.bodies);
        }
        handles.push(handle);
    }
    for _ in 0..steps {
        world.step();
    }
    Ok(handles
        .into_iter()
        .zip(bodies)
        .map(|(handle, body)| {
            world.bodies.get(handle).map_or(body.pose, |placed| from_rapier(placed.position()))
        })
        .collect())
}
