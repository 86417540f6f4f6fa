//! The two axis-aligned views: which world axes they show and which way is "towards the viewer".

use lamp_geometry::Point3;

/// An orthographic view along a world axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum View {
    /// Looking down the world z axis: x to the right, y up the page.
    Top,
    /// Looking along +y from the front (the viewer stands at negative y): x to the right, z up.
    Side,
}

impl View {
    /// The point's coordinates in the view's plane (right, up), in metres.
    pub(crate) fn project(self, point: &Point3) -> (f64, f64) {
        match self {
            View::Top => (point.x, point.y),
            View::Side => (point.x, point.z),
        }
    }

    /// The key painters sort by, ascending: what is drawn first is furthest from the viewer.
    ///
    /// The top view paints the lowest tops first; the side view paints the farthest backs (the
    /// largest y) first. Comparing extremes rather than centres keeps a can in front of the wide
    /// table it stands on, whose centre may be nearer the viewer than the can's.
    pub(crate) fn depth(self, points: &[Point3]) -> f64 {
        match self {
            View::Top => points.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max),
            View::Side => -points.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max),
        }
    }

    /// The view's title.
    pub(crate) fn title(self) -> &'static str {
        match self {
            View::Top => "top view (x\u{2013}y)",
            View::Side => "side view (x\u{2013}z)",
        }
    }

    /// The name of the vertical axis.
    pub(crate) fn vertical_axis(self) -> &'static str {
        match self {
            View::Top => "y",
            View::Side => "z",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn higher_tops_are_painted_later_from_above() {
        let table = [Point3::new(-0.45, -0.45, -0.05), Point3::new(0.45, 0.45, 0.0)];
        let can = [Point3::new(0.0, -0.2, 0.0), Point3::new(0.05, -0.15, 0.15)];
        assert!(View::Top.depth(&table) < View::Top.depth(&can));
        // From the front, the table's back edge is farther than the can's.
        assert!(View::Side.depth(&table) < View::Side.depth(&can));
    }
}
