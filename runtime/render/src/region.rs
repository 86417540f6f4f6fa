//! Region plots: sample poses of a secondary object in a primary object's frame, drawn as points
//! around the primary's outline (as in Figure 5 of the LAMP paper), one colour per region.

use lamp_geometry::{Point3, Pose, Shape};

use crate::colour::{Role, Style, set_colour, style_for};
use crate::figure::{Dot, Figure, LegendEntry, Placement};
use crate::layout::{RenderOptions, render};

/// Sample poses of one region, drawn in one colour.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleSet {
    /// The legend's name for the region, for example `surface_can_1`.
    pub label: String,
    /// Poses of the secondary object in the primary's frame; their positions are drawn.
    pub poses: Vec<Pose>,
}

/// What a region plot shows.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionPlot {
    /// The primary object's type (the frame the samples are in).
    pub primary: String,
    /// The secondary object's type (what the samples place).
    pub secondary: String,
    /// The primary's shapes in its own frame, drawn at the origin.
    pub primary_parts: Vec<(Pose, Shape)>,
    /// One or more regions.
    pub sets: Vec<SampleSet>,
}

/// The colour of the primary's origin marker.
const ORIGIN_COLOUR: &str = "#000000";

/// Draws a region plot: top and side views of the samples around the primary's outline.
pub fn render_regions(plot: &RegionPlot, options: &RenderOptions) -> String {
    let mut figure = Figure {
        title: format!("{} relative to {}", plot.secondary, plot.primary),
        ..Figure::default()
    };
    // A light fill: the primary is the frame of reference, the samples are the picture.
    let style =
        Style { fill: "#e4e4e4".to_string(), ..style_for(Role::Surface, &plot.primary, false) };
    let label = Some(Placement::Corner);
    figure.add_body(&plot.primary, &Pose::identity(), &plot.primary_parts, &style, false, label);
    for (index, set) in plot.sets.iter().enumerate() {
        let colour = set_colour(index).to_string();
        for pose in &set.poses {
            let point = Point3::from(pose.translation.vector);
            figure.dots.push(Dot { point, colour: colour.clone() });
        }
        figure.legend.push(LegendEntry {
            text: format!("{} ({} samples)", set.label, set.poses.len()),
            colour,
            line: false,
        });
    }
    figure.dots.push(Dot { point: Point3::origin(), colour: ORIGIN_COLOUR.to_string() });
    figure.legend.push(LegendEntry {
        text: format!("origin of {}", plot.primary),
        colour: ORIGIN_COLOUR.to_string(),
        line: false,
    });
    render(&figure, options)
}
