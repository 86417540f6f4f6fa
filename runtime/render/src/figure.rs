//! The drawing before projection: solids, paths, dots and labels in world coordinates.
//!
//! Scenes, trajectories and region plots all become a [`Figure`]; the layout then projects it
//! into the top and the side view, so both views always show the same things at the same scale.

use lamp_geometry::{Point3, Pose, Shape};

use crate::colour::Style;
use crate::outline::world_points;

/// One shape in the world, to be drawn as the filled convex hull of its projected points.
#[derive(Clone, Debug)]
pub(crate) struct Solid {
    pub(crate) points: Vec<Point3>,
    pub(crate) style: Style,
    /// Backdrop (the static world): left out of the drawing's extent when it dwarfs the rest,
    /// so a 20 m floor does not shrink a café to a few pixels.
    pub(crate) backdrop: bool,
}

/// A polyline in the world (a gripper path).
#[derive(Clone, Debug)]
pub(crate) struct Path {
    pub(crate) points: Vec<Point3>,
    pub(crate) colour: String,
}

/// A point marker in the world (a region sample).
#[derive(Clone, Debug)]
pub(crate) struct Dot {
    pub(crate) point: Point3,
    pub(crate) colour: String,
}

/// A name written next to what it names.
#[derive(Clone, Debug)]
pub(crate) struct Label {
    pub(crate) text: String,
    /// The world-axis-aligned box of the named thing: the top view writes the label at its
    /// centre, the side view just above it.
    pub(crate) min: Point3,
    pub(crate) max: Point3,
    pub(crate) backdrop: bool,
    /// Written in the thing's upper left corner instead of its middle: surfaces, so that the
    /// names of what stands on them stay readable.
    pub(crate) corner: bool,
}

/// Where a label goes on what it names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Placement {
    /// In the middle (from above) or just above (from the side).
    Middle,
    /// In the upper left corner.
    Corner,
}

/// An entry of the legend under the views.
#[derive(Clone, Debug)]
pub(crate) struct LegendEntry {
    pub(crate) text: String,
    pub(crate) colour: String,
    /// Drawn as a line (paths) instead of a dot.
    pub(crate) line: bool,
}

/// Everything to draw, in world coordinates.
#[derive(Clone, Debug, Default)]
pub(crate) struct Figure {
    pub(crate) title: String,
    pub(crate) solids: Vec<Solid>,
    pub(crate) paths: Vec<Path>,
    pub(crate) dots: Vec<Dot>,
    pub(crate) labels: Vec<Label>,
    pub(crate) legend: Vec<LegendEntry>,
}

impl Figure {
    /// Adds a body made of `parts` (each placed in the body's frame) at `pose`, with a label.
    pub(crate) fn add_body(
        &mut self,
        name: &str,
        pose: &Pose,
        parts: &[(Pose, Shape)],
        style: &Style,
        backdrop: bool,
        label: Option<Placement>,
    ) {
        let mut all = Vec::new();
        for (origin, shape) in parts {
            let points = world_points(&(pose * origin), shape);
            all.extend_from_slice(&points);
            self.solids.push(Solid { points, style: style.clone(), backdrop });
        }
        if let Some(placement) = label {
            self.add_label(name, &all, backdrop, placement);
        }
    }

    /// Adds a label for the thing made of `points` (nothing if there are none).
    pub(crate) fn add_label(
        &mut self,
        text: &str,
        points: &[Point3],
        backdrop: bool,
        placement: Placement,
    ) {
        if let Some((min, max)) = bounding_box(points) {
            let corner = placement == Placement::Corner;
            self.labels.push(Label { text: text.to_string(), min, max, backdrop, corner });
        }
    }
}

/// The axis-aligned box around finite points, or `None` if there are none.
pub(crate) fn bounding_box(points: &[Point3]) -> Option<(Point3, Point3)> {
    let mut finite = points.iter().filter(|p| p.coords.iter().all(|c| c.is_finite()));
    let first = finite.next()?;
    let (mut min, mut max) = (*first, *first);
    for point in finite {
        min = min.inf(point);
        max = max.sup(point);
    }
    Some((min, max))
}
