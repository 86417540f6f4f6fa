//! Laying a figure out on the page: the drawing's extent, one scale for both views, the two
//! panels side by side with grid, ticks in metres, titles, labels, a scale bar and a legend.

use std::fmt::Write as _;

use lamp_geometry::Point3;

use crate::colour::MARK_COLOUR;
use crate::figure::{Figure, Label, Solid, bounding_box};
use crate::outline::convex_hull;
use crate::svg::{Svg, escape, num, points};
use crate::view::View;

/// How a drawing is laid out.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// The longest side of a view, in pixels; both views share the scale this implies.
    pub view_size: f64,
    /// Whether bodies and robots are labelled with their names.
    pub labels: bool,
    /// A title over both views, replacing the default one.
    pub title: Option<String>,
    /// Bodies drawn with a thick red outline, by name: what a failed solve found in the way.
    pub marked: Vec<String>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { view_size: 480.0, labels: true, title: None, marked: Vec::new() }
    }
}

/// A backdrop wider than this many times the rest of the drawing is cut to the rest's extent
/// (a packing table, 0.9 m under half a metre of cans and gripper, stays; a 20 m floor goes).
const BACKDROP_FACTOR: f64 = 2.0;
/// The smallest labelled object (a can) is drawn at least this wide, in pixels, so that it can
/// be seen and named; the view grows for it, up to `LARGEST_VIEW`.
const SMALLEST_OBJECT: f64 = 12.0;
/// The longest side of a view grown for small objects, in pixels.
const LARGEST_VIEW: f64 = 1000.0;
/// The margin around the drawing's extent, as a fraction of its longest side.
const PADDING_FRACTION: f64 = 0.06;
/// The smallest extent drawn along any axis, in metres, so a flat or empty drawing still has
/// a readable frame.
const MINIMUM_EXTENT: f64 = 0.1;

const LEFT: f64 = 56.0;
const GAP: f64 = 72.0;
const RIGHT: f64 = 24.0;
const TOP: f64 = 58.0;
const TITLE_SIZE: f64 = 15.0;
const TEXT_SIZE: f64 = 11.0;
const TICK_SIZE: f64 = 9.0;
const LABEL_SIZE: f64 = 8.0;

/// The world box shown: x is shared by both views, y by the top and z by the side view.
#[derive(Clone, Copy, Debug)]
struct Extent {
    min: Point3,
    max: Point3,
}

impl Extent {
    fn range(&self, view: View) -> ((f64, f64), (f64, f64)) {
        let (min, max) = (view.project(&self.min), view.project(&self.max));
        ((min.0, max.0), (min.1, max.1))
    }
}

/// One panel on the page: where it is and how metres map to pixels.
#[derive(Clone, Copy, Debug)]
struct Panel {
    view: View,
    left: f64,
    top: f64,
    width: f64,
    height: f64,
    /// World range shown horizontally and vertically.
    horizontal: (f64, f64),
    vertical: (f64, f64),
    scale: f64,
}

impl Panel {
    fn to_page(self, (u, v): (f64, f64)) -> (f64, f64) {
        (
            self.left + (u - self.horizontal.0) * self.scale,
            self.top + (self.vertical.1 - v) * self.scale,
        )
    }

    fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.left
            && x <= self.left + self.width
            && y >= self.top
            && y <= self.top + self.height
    }

    fn clip_id(&self) -> &'static str {
        match self.view {
            View::Top => "clip-top",
            View::Side => "clip-side",
        }
    }
}

/// Draws the figure: top view on the left, side view on the right, same scale.
pub(crate) fn render(figure: &Figure, options: &RenderOptions) -> String {
    let extent = extent(figure);
    let size = |axis: usize| extent.max[axis] - extent.min[axis];
    let longest = size(0).max(size(1)).max(size(2));
    let scale = scale(figure, options.view_size.max(50.0), longest);
    let top_panel = panel(View::Top, &extent, scale, LEFT);
    let side_panel = panel(View::Side, &extent, scale, LEFT + top_panel.width + GAP);
    let panels_height = top_panel.height.max(side_panel.height);
    let width = side_panel.left + side_panel.width + RIGHT;
    let step = tick_step(longest);
    // The legend starts right of the scale bar and its label.
    let legend_left = LEFT + step * scale + 70.0;
    let legend_rows = legend_rows(figure, (width - legend_left - RIGHT).max(200.0));
    let height = TOP + panels_height + 64.0 + 16.0 * legend_rows.len() as f64;

    let mut svg = Svg::new(width, height);
    let title = options.title.as_deref().unwrap_or(&figure.title);
    svg.text(LEFT, 22.0, TITLE_SIZE, "start", "#111111", title);
    let mut defs = String::from("<defs>");
    for panel in [&top_panel, &side_panel] {
        let _ = write!(
            defs,
            "<clipPath id=\"{}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>",
            panel.clip_id(),
            num(panel.left),
            num(panel.top),
            num(panel.width),
            num(panel.height)
        );
    }
    defs.push_str("</defs>");
    svg.line(&defs);
    for panel in [&top_panel, &side_panel] {
        draw_panel(&mut svg, panel, figure, options, step);
    }
    let below = TOP + panels_height + 40.0;
    scale_bar(&mut svg, &top_panel, step, below);
    legend(&mut svg, figure, &legend_rows, legend_left, below);
    svg.finish()
}

/// The world box to show: everything but oversized backdrops, padded.
fn extent(figure: &Figure) -> Extent {
    let mut core: Vec<Point3> = Vec::new();
    for solid in figure.solids.iter().filter(|s| !s.backdrop) {
        core.extend_from_slice(&solid.points);
    }
    for path in &figure.paths {
        core.extend_from_slice(&path.points);
    }
    core.extend(figure.dots.iter().map(|dot| dot.point));
    let mut all = core.clone();
    match bounding_box(&core) {
        Some((min, max)) => {
            let reach = (max - min).amax().max(MINIMUM_EXTENT);
            for solid in figure.solids.iter().filter(|s| s.backdrop) {
                if let Some((lo, hi)) = bounding_box(&solid.points)
                    && (hi - lo).amax() <= BACKDROP_FACTOR * reach
                {
                    all.extend_from_slice(&solid.points);
                }
            }
        }
        None => {
            for solid in &figure.solids {
                all.extend_from_slice(&solid.points);
            }
        }
    }
    let (mut min, mut max) =
        bounding_box(&all).unwrap_or((Point3::new(-0.5, -0.5, 0.0), Point3::new(0.5, 0.5, 1.0)));
    for axis in 0..3 {
        let missing = MINIMUM_EXTENT - (max[axis] - min[axis]);
        if missing > 0.0 {
            min[axis] -= missing / 2.0;
            max[axis] += missing / 2.0;
        }
    }
    let pad = PADDING_FRACTION * (max - min).amax();
    for axis in 0..3 {
        min[axis] -= pad;
        max[axis] += pad;
    }
    Extent { min, max }
}

/// Pixels per metre: the view size over the extent, more if the smallest object would be tiny.
fn scale(figure: &Figure, view_size: f64, longest: f64) -> f64 {
    let base = view_size / longest;
    let smallest = figure
        .labels
        .iter()
        .filter(|label| !label.backdrop && !label.corner)
        .map(|label| (label.max.x - label.min.x).max(label.max.y - label.min.y))
        .filter(|size| *size > 0.0)
        .fold(f64::INFINITY, f64::min);
    if smallest.is_finite() && smallest * base < SMALLEST_OBJECT {
        let grown = (SMALLEST_OBJECT / smallest).min(LARGEST_VIEW.max(view_size) / longest);
        base.max(grown)
    } else {
        base
    }
}

fn panel(view: View, extent: &Extent, scale: f64, left: f64) -> Panel {
    let (horizontal, vertical) = extent.range(view);
    Panel {
        view,
        left,
        top: TOP,
        width: (horizontal.1 - horizontal.0) * scale,
        height: (vertical.1 - vertical.0) * scale,
        horizontal,
        vertical,
        scale,
    }
}

/// A round tick spacing (1, 2 or 5 times a power of ten) giving about six ticks over `range`.
pub(crate) fn tick_step(range: f64) -> f64 {
    let raw = (range / 6.0).max(1e-6);
    let power = 10f64.powf(raw.log10().floor());
    let fraction = raw / power;
    let nice = if fraction < 1.5 {
        1.0
    } else if fraction < 3.5 {
        2.0
    } else if fraction < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * power
}

/// A tick value with as many decimals as the step needs.
fn tick_text(value: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let text = format!("{value:.decimals$}");
    if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}

/// Multiples of `step` within `range`.
fn ticks(range: (f64, f64), step: f64) -> Vec<f64> {
    let first = (range.0 / step).ceil() as i64;
    let last = (range.1 / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn draw_panel(svg: &mut Svg, panel: &Panel, figure: &Figure, options: &RenderOptions, step: f64) {
    let (left, top, right, bottom) =
        (panel.left, panel.top, panel.left + panel.width, panel.top + panel.height);
    svg.text((left + right) / 2.0, top - 8.0, TEXT_SIZE, "middle", "#333333", panel.view.title());

    // Grid under everything, ticks and their values outside the frame.
    let vertical_ticks = ticks(panel.vertical, step);
    let horizontal_ticks = ticks(panel.horizontal, step);
    for &u in &horizontal_ticks {
        let (x, _) = panel.to_page((u, 0.0));
        svg.segment((x, top), (x, bottom), "#ececec", 0.6);
        svg.segment((x, bottom), (x, bottom + 4.0), "#444444", 0.8);
        svg.text(x, bottom + 14.0, TICK_SIZE, "middle", "#444444", &tick_text(u, step));
    }
    for &v in &vertical_ticks {
        let (_, y) = panel.to_page((0.0, v));
        svg.segment((left, y), (right, y), "#ececec", 0.6);
        svg.segment((left - 4.0, y), (left, y), "#444444", 0.8);
        svg.text(left - 6.0, y + 3.0, TICK_SIZE, "end", "#444444", &tick_text(v, step));
    }
    svg.text((left + right) / 2.0, bottom + 27.0, TICK_SIZE, "middle", "#444444", "x (m)");
    let (ax, ay) = (left - 38.0, (top + bottom) / 2.0);
    svg.line(&format!(
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"middle\" fill=\"#444444\" \
         transform=\"rotate(-90 {} {})\">{} (m)</text>",
        num(ax),
        num(ay),
        num(TICK_SIZE),
        num(ax),
        num(ay),
        panel.view.vertical_axis()
    ));

    svg.line(&format!("<g clip-path=\"url(#{})\">", panel.clip_id()));
    let mut order: Vec<(f64, &Solid)> =
        figure.solids.iter().map(|solid| (panel.view.depth(&solid.points), solid)).collect();
    // Stable: equal depths keep the figure's order (faded copies were added first).
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (_, solid) in order {
        draw_solid(svg, panel, solid);
    }
    for path in &figure.paths {
        let page: Vec<(f64, f64)> =
            path.points.iter().map(|p| panel.to_page(panel.view.project(p))).collect();
        svg.line(&format!(
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.6\" \
             stroke-linejoin=\"round\" stroke-linecap=\"round\"/>",
            points(&page),
            path.colour
        ));
        if let (Some(first), Some(last)) = (page.first(), page.last()) {
            svg.line(&format!(
                "<circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"#ffffff\" stroke=\"{}\" stroke-width=\"1.4\"/>",
                num(first.0),
                num(first.1),
                path.colour
            ));
            svg.line(&format!(
                "<circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"{}\"/>",
                num(last.0),
                num(last.1),
                path.colour
            ));
        }
    }
    for dot in &figure.dots {
        let (x, y) = panel.to_page(panel.view.project(&dot.point));
        svg.line(&format!(
            "<circle cx=\"{}\" cy=\"{}\" r=\"1.6\" fill=\"{}\" fill-opacity=\"0.6\"/>",
            num(x),
            num(y),
            dot.colour
        ));
    }
    svg.line("</g>");
    svg.line(&format!(
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444444\" stroke-width=\"0.8\"/>",
        num(left),
        num(top),
        num(panel.width),
        num(panel.height)
    ));
    if options.labels {
        draw_labels(svg, panel, &figure.labels);
    }
}

fn draw_solid(svg: &mut Svg, panel: &Panel, solid: &Solid) {
    let projected: Vec<(f64, f64)> =
        solid.points.iter().map(|p| panel.to_page(panel.view.project(p))).collect();
    let hull = convex_hull(&projected);
    if hull.is_empty() {
        return;
    }
    let style = &solid.style;
    let (stroke, width) =
        if style.marked { (MARK_COLOUR, "2.4") } else { (style.stroke.as_str(), "0.8") };
    let mut markup = format!(
        "<polygon points=\"{}\" fill=\"{}\" stroke=\"{stroke}\" stroke-width=\"{width}\" stroke-linejoin=\"round\"",
        points(&hull),
        style.fill,
    );
    if style.opacity < 1.0 {
        let _ = write!(markup, " opacity=\"{}\"", num(style.opacity));
    }
    if style.dashed {
        markup.push_str(" stroke-dasharray=\"3 2\"");
    }
    markup.push_str("/>");
    svg.line(&markup);
}

/// Writes labels, moving one up or down a line when it would cover an earlier one.
fn draw_labels(svg: &mut Svg, panel: &Panel, labels: &[Label]) {
    let mut placed: Vec<(f64, f64, f64, f64)> = Vec::new();
    for label in labels {
        let (min, max) = (panel.view.project(&label.min), panel.view.project(&label.max));
        if label.backdrop
            && !(panel.contains(panel.to_page(min)) && panel.contains(panel.to_page(max)))
        {
            continue; // cut by the frame: its corner is not on the page
        }
        let width = 0.58 * LABEL_SIZE * label.text.chars().count() as f64;
        let (left, top) = panel.to_page((min.0, max.1));
        let (right, bottom) = panel.to_page((max.0, min.1));
        let centre = (left + right) / 2.0;
        // Inside the upper left corner; in the middle if the name fits; else just above.
        let (x, base) = if label.corner {
            (left + 3.0, top + LABEL_SIZE + 2.0)
        } else if panel.view == View::Top && right - left >= width {
            (centre - width / 2.0, (top + bottom) / 2.0 + LABEL_SIZE / 3.0)
        } else {
            (centre - width / 2.0, top - 3.0)
        };
        let mut chosen = base;
        for shift in [0.0, -1.0, 1.0, -2.0, 2.0] {
            let y = base + shift * (LABEL_SIZE + 1.0);
            let rect = (x, y - LABEL_SIZE, x + width, y + 1.0);
            if !placed.iter().any(|other| overlaps(rect, *other)) {
                chosen = y;
                break;
            }
        }
        placed.push((x, chosen - LABEL_SIZE, x + width, chosen + 1.0));
        svg.line(&format!(
            "<text x=\"{}\" y=\"{}\" font-size=\"{}\" fill=\"#222222\" stroke=\"#ffffff\" \
             stroke-width=\"2\" stroke-opacity=\"0.8\" paint-order=\"stroke\">{}</text>",
            num(x),
            num(chosen),
            num(LABEL_SIZE),
            escape(&label.text)
        ));
    }
}

fn overlaps(a: (f64, f64, f64, f64), b: (f64, f64, f64, f64)) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

fn scale_bar(svg: &mut Svg, panel: &Panel, step: f64, y: f64) {
    let x = panel.left;
    let length = step * panel.scale;
    svg.segment((x, y), (x + length, y), "#222222", 2.0);
    svg.segment((x, y - 4.0), (x, y + 4.0), "#222222", 1.0);
    svg.segment((x + length, y - 4.0), (x + length, y + 4.0), "#222222", 1.0);
    svg.text(
        x + length + 6.0,
        y + 4.0,
        TEXT_SIZE,
        "start",
        "#222222",
        &format!("{} m", tick_text(step, step)),
    );
}

/// Legend entries grouped into rows of at most `available` pixels.
fn legend_rows(figure: &Figure, available: f64) -> Vec<Vec<usize>> {
    let mut rows: Vec<Vec<usize>> = Vec::new();
    let mut used = f64::INFINITY;
    for (index, entry) in figure.legend.iter().enumerate() {
        let entry_width = legend_entry_width(&entry.text);
        if used + entry_width > available {
            rows.push(Vec::new());
            used = 0.0;
        }
        if let Some(row) = rows.last_mut() {
            row.push(index);
        }
        used += entry_width;
    }
    rows
}

fn legend_entry_width(text: &str) -> f64 {
    28.0 + 0.6 * TEXT_SIZE * text.chars().count() as f64
}

fn legend(svg: &mut Svg, figure: &Figure, rows: &[Vec<usize>], left: f64, top: f64) {
    for (row_index, row) in rows.iter().enumerate() {
        let y = top + 16.0 * row_index as f64;
        let mut x = left;
        for &index in row {
            let entry = &figure.legend[index];
            if entry.line {
                svg.segment((x, y), (x + 18.0, y), &entry.colour, 2.0);
            } else {
                svg.line(&format!(
                    "<circle cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"{}\"/>",
                    num(x + 9.0),
                    num(y),
                    entry.colour
                ));
            }
            svg.text(x + 24.0, y + 4.0, TEXT_SIZE, "start", "#222222", &entry.text);
            x += legend_entry_width(&entry.text);
        }
    }
}
