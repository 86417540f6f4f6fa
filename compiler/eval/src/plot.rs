//! The two plots as SVG text: `sample_efficiency.svg` (the solved fraction per demonstration
//! count, mean with a shaded ± one sample standard deviation band and one dot per run, the paper's
//! Figure 4b) and `success.svg` (per test problem, the fraction of runs that solved it, one bar per
//! demonstration count, with the generalization factor, after Figure 4a).
//!
//! Written with lamp-render's SVG conventions (two-decimal numbers, escaped text), so the same
//! rows give the same bytes.

use std::fmt::Write as _;

use lamp_render::svg::{Svg, escape, num, points};

use crate::report::{factor_text, percent};
use crate::row::{EvalInfo, Row};
use crate::stats::{efficiency, generalization, success_table};

/// One colour per demonstration count, in the order given (Okabe–Ito: told apart with the
/// common colour-vision deficiencies); more counts reuse them.
const PALETTE: [&str; 7] =
    ["#0072b2", "#e69f00", "#009e73", "#d55e00", "#cc79a7", "#56b4e9", "#000000"];
/// The colour of the sample-efficiency line and band.
const LINE: &str = "#0072b2";
/// Text and axes.
const INK: &str = "#222222";
/// Grid lines and secondary text.
const FAINT: &str = "#d0d0d0";
const GREY: &str = "#666666";

/// A step of 1, 2 or 5 × 10^k that cuts `range` into about `ticks` parts (never below 1, for
/// whole counts).
fn nice_step(range: f64, ticks: f64) -> f64 {
    let raw = (range / ticks).max(1.0);
    let magnitude = 10f64.powf(raw.log10().floor());
    let normalised = raw / magnitude;
    let factor = if normalised <= 1.0 {
        1.0
    } else if normalised <= 2.0 {
        2.0
    } else if normalised <= 5.0 {
        5.0
    } else {
        10.0
    };
    factor * magnitude
}

/// A plot area inside a document: pixel bounds and the value ranges they show.
struct Area {
    left: f64,
    right: f64,
    top: f64,
    bottom: f64,
    x_max: f64,
}

impl Area {
    fn x(&self, value: f64) -> f64 {
        self.left + (self.right - self.left) * value / self.x_max
    }

    /// `fraction` in 0..1 to a pixel row (0 at the bottom).
    fn y(&self, fraction: f64) -> f64 {
        self.bottom - (self.bottom - self.top) * fraction.clamp(0.0, 1.0)
    }

    /// Horizontal grid lines and labels every 20 % of the fraction axis, and its title.
    fn fraction_axis(&self, svg: &mut Svg, title: &str) {
        for step in 0..=5 {
            let fraction = f64::from(step) / 5.0;
            let y = self.y(fraction);
            svg.segment((self.left, y), (self.right, y), FAINT, 1.0);
            svg.text(self.left - 8.0, y + 4.0, 12.0, "end", INK, &percent(fraction, 0));
        }
        let (x, y) = (self.left - 52.0, (self.top + self.bottom) / 2.0);
        svg.line(&format!(
            "<text x=\"{}\" y=\"{}\" font-size=\"13\" text-anchor=\"middle\" fill=\"{INK}\" transform=\"rotate(-90 {} {})\">{}</text>",
            num(x),
            num(y),
            num(x),
            num(y),
            escape(title)
        ));
    }
}

/// The title, and one line of subtitle per entry of `subtitles`.
fn title(svg: &mut Svg, x: f64, title: &str, subtitles: &[&str]) {
    svg.line(&format!(
        "<text x=\"{}\" y=\"26\" font-size=\"17\" font-weight=\"bold\" fill=\"{INK}\">{}</text>",
        num(x),
        escape(title)
    ));
    for (index, subtitle) in subtitles.iter().enumerate() {
        svg.text(x, 46.0 + 16.0 * index as f64, 12.0, "start", GREY, subtitle);
    }
}

fn circle(svg: &mut Svg, (x, y): (f64, f64), radius: f64, fill: &str, extra: &str) {
    svg.line(&format!(
        "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\"{extra}/>",
        num(x),
        num(y),
        num(radius)
    ));
}

/// `sample_efficiency.svg`: x the number of training demonstrations (from 0), y the fraction of
/// test problems solved per run; the mean per count joined by a line, the shaded band mean ± one
/// sample standard deviation (clipped to 0–100 %), small grey dots for the runs (spread sideways
/// by run so that equal values stay visible) and the mean written above each point.
pub fn sample_efficiency_plot(info: &EvalInfo, rows: &[Row]) -> String {
    let (width, height) = (760.0, 460.0);
    let mut svg = Svg::new(width, height);
    let mut summaries = efficiency(info, rows);
    summaries.retain(|summary| summary.mean.is_some());
    summaries.sort_by_key(|summary| summary.count);
    title(
        &mut svg,
        20.0,
        &format!("Sample efficiency: {}", info.domain),
        &[&format!(
            "Test problems solved per run ({} problems): mean ± sample std over {} runs (band), one dot per run",
            info.problems.len(),
            info.runs
        )],
    );
    let most = info.counts.iter().copied().max().unwrap_or(1).max(1) as f64;
    let step = nice_step(most, 5.0);
    let x_max = (most / step).ceil() * step;
    let area = Area { left: 90.0, right: width - 40.0, top: 70.0, bottom: height - 70.0, x_max };
    area.fraction_axis(&mut svg, "test problems solved");
    let mut tick = 0.0;
    while tick <= x_max + 0.5 {
        let x = area.x(tick);
        svg.segment((x, area.bottom), (x, area.bottom + 5.0), INK, 1.0);
        svg.text(x, area.bottom + 20.0, 12.0, "middle", INK, &format!("{tick}"));
        tick += step;
    }
    svg.segment((area.left, area.bottom), (area.right, area.bottom), INK, 1.0);
    svg.segment((area.left, area.top), (area.left, area.bottom), INK, 1.0);
    svg.text(
        (area.left + area.right) / 2.0,
        height - 22.0,
        13.0,
        "middle",
        INK,
        "training demonstrations",
    );
    if summaries.is_empty() {
        svg.text(
            (area.left + area.right) / 2.0,
            (area.top + area.bottom) / 2.0,
            14.0,
            "middle",
            GREY,
            "no finished runs yet",
        );
        return svg.finish();
    }

    let spread = |summary: &crate::stats::CountSummary| {
        let mean = summary.mean.unwrap_or(0.0);
        let std = summary.std.unwrap_or(0.0);
        (mean, (mean + std).min(1.0), (mean - std).max(0.0))
    };
    let mut band: Vec<(f64, f64)> =
        summaries.iter().map(|s| (area.x(s.count as f64), area.y(spread(s).1))).collect();
    band.extend(summaries.iter().rev().map(|s| (area.x(s.count as f64), area.y(spread(s).2))));
    svg.line(&format!(
        "<polygon points=\"{}\" fill=\"{LINE}\" fill-opacity=\"0.18\" stroke=\"none\"/>",
        points(&band)
    ));
    for summary in &summaries {
        let (_, high, low) = spread(summary);
        let x = area.x(summary.count as f64);
        svg.line(&format!(
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{LINE}\" stroke-opacity=\"0.5\" stroke-width=\"1.5\"/>",
            num(x),
            num(area.y(high)),
            num(x),
            num(area.y(low))
        ));
        let runs = summary.fractions.len() as f64;
        for (index, fraction) in summary.fractions.iter().enumerate() {
            let offset = (index as f64 - (runs - 1.0) / 2.0) * 2.5;
            circle(&mut svg, (x + offset, area.y(*fraction)), 2.5, GREY, " fill-opacity=\"0.45\"");
        }
    }
    let line: Vec<(f64, f64)> =
        summaries.iter().map(|s| (area.x(s.count as f64), area.y(s.mean.unwrap_or(0.0)))).collect();
    svg.line(&format!(
        "<polyline points=\"{}\" fill=\"none\" stroke=\"{LINE}\" stroke-width=\"2.5\"/>",
        points(&line)
    ));
    for (summary, point) in summaries.iter().zip(&line) {
        circle(&mut svg, *point, 5.0, LINE, " stroke=\"#ffffff\" stroke-width=\"1.5\"");
        // Beside the marker, clear of the runs' dots: to the right, or to the left at the edge.
        let label = percent(summary.mean.unwrap_or(0.0), 0);
        let (x, anchor) = if point.0 > area.right - 60.0 {
            (point.0 - 10.0, "end")
        } else {
            (point.0 + 10.0, "start")
        };
        let y = (point.1 - 6.0).max(area.top + 12.0);
        svg.line(&format!(
            "<text x=\"{}\" y=\"{}\" font-size=\"12\" font-weight=\"bold\" text-anchor=\"{anchor}\" fill=\"{LINE}\" stroke=\"#ffffff\" stroke-width=\"3\" paint-order=\"stroke\">{}</text>",
            num(x),
            num(y),
            escape(&label)
        ));
    }
    // Legend, bottom right inside the plot area.
    let (lx, ly) = (area.right - 210.0, area.bottom - 58.0);
    svg.line(&format!(
        "<rect x=\"{}\" y=\"{}\" width=\"200\" height=\"50\" fill=\"#ffffff\" fill-opacity=\"0.85\" stroke=\"{FAINT}\"/>",
        num(lx),
        num(ly)
    ));
    svg.segment((lx + 10.0, ly + 15.0), (lx + 34.0, ly + 15.0), LINE, 2.5);
    svg.text(lx + 42.0, ly + 19.0, 11.0, "start", INK, "mean; band: ± 1 sample std");
    circle(&mut svg, (lx + 22.0, ly + 35.0), 2.5, GREY, " fill-opacity=\"0.45\"");
    svg.text(lx + 42.0, ly + 39.0, 11.0, "start", INK, "one run");
    svg.finish()
}

/// `success.svg`: per test problem (in spec order, labelled with its objects), one bar per
/// demonstration count (in the order given) with the fraction of runs that solved it, and the
/// generalization factor in the subtitle.
pub fn success_plot(info: &EvalInfo, rows: &[Row]) -> String {
    let table = success_table(info, rows);
    let bars = info.counts.len().max(1) as f64;
    let groups = table.len().max(1) as f64;
    let left = 90.0;
    // At least 10 px per bar and a gap of 18 px per problem; at least 560 px in all.
    let plot_width = ((10.0 * bars + 18.0) * groups).max(560.0);
    // Bars fill 70 % of their problem's share of the width, at most 28 px each.
    let bar = (0.7 * plot_width / groups / bars).min(28.0);
    let width = left + plot_width + 40.0;
    let height = 500.0;
    let mut svg = Svg::new(width, height);
    let g = generalization(info, rows);
    let factor = match (g.factor, g.test_objects) {
        (Some(factor), Some(test)) => format!(
            "Generalization factor {}: {test} objects in the largest solved problem ÷ {} in a demonstration",
            factor_text(factor),
            g.training_objects
        ),
        _ => "No test problem was solved: no generalization factor".to_string(),
    };
    let fraction = format!(
        "Fraction of the {} runs that solved each problem, per number of training demonstrations",
        info.runs
    );
    title(&mut svg, 20.0, &format!("Test problems solved: {}", info.domain), &[&fraction, &factor]);
    let area = Area {
        left,
        right: left + plot_width,
        top: 112.0,
        bottom: height - 110.0,
        x_max: plot_width,
    };
    area.fraction_axis(&mut svg, "runs that solved the problem");
    svg.segment((area.left, area.bottom), (area.right, area.bottom), INK, 1.0);
    svg.segment((area.left, area.top), (area.left, area.bottom), INK, 1.0);
    // Legend: one swatch per count, above the plot.
    let mut x = left;
    for (index, count) in info.counts.iter().enumerate() {
        let colour = PALETTE[index % PALETTE.len()];
        svg.line(&format!(
            "<rect x=\"{}\" y=\"78\" width=\"12\" height=\"12\" fill=\"{colour}\"/>",
            num(x)
        ));
        let label = format!("{count} demonstrations");
        svg.text(x + 17.0, 88.0, 12.0, "start", INK, &label);
        x += 30.0 + 7.0 * label.len() as f64;
    }
    let gap = (plot_width / table.len().max(1) as f64 - bar * bars) / 2.0;
    for (problem_index, line) in table.iter().enumerate() {
        let (problem, objects, cells) = (&line.problem, line.objects, &line.cells);
        let start = area.left + problem_index as f64 * (plot_width / table.len() as f64) + gap;
        for (index, (solved, total)) in cells.iter().enumerate() {
            let colour = PALETTE[index % PALETTE.len()];
            let x = start + index as f64 * bar;
            if *total == 0 {
                continue;
            }
            let fraction = *solved as f64 / *total as f64;
            let top = area.y(fraction);
            let mut markup = String::new();
            let _ = write!(
                markup,
                "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{colour}\"><title>{}</title></rect>",
                num(x + 0.5),
                num(top),
                num(bar - 1.0),
                num((area.bottom - top).max(0.0)),
                escape(&format!("{problem}, {}: {solved}/{total}", info.counts[index]))
            );
            svg.line(&markup);
            if *solved == 0 {
                // A zero bar has no height: a tick on the axis shows that the count was tried.
                svg.segment(
                    (x + 0.5, area.bottom - 1.5),
                    (x + bar - 0.5, area.bottom - 1.5),
                    colour,
                    3.0,
                );
            }
        }
        let centre = start + bar * bars / 2.0;
        let y = area.bottom + 14.0;
        svg.line(&format!(
            "<text x=\"{}\" y=\"{}\" font-size=\"12\" text-anchor=\"end\" fill=\"{INK}\" transform=\"rotate(-40 {} {})\">{}</text>",
            num(centre),
            num(y),
            num(centre),
            num(y),
            escape(&format!("{problem} ({objects})"))
        ));
    }
    svg.text(
        (area.left + area.right) / 2.0,
        height - 12.0,
        13.0,
        "middle",
        INK,
        "test problem (objects)",
    );
    svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::row::tests::{info, rows};

    #[test]
    fn steps_are_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(nice_step(200.0, 5.0), 50.0);
        assert_eq!(nice_step(40.0, 5.0), 10.0);
        assert_eq!(nice_step(3.0, 5.0), 1.0);
        assert_eq!(nice_step(1000.0, 5.0), 200.0);
    }

    #[test]
    fn the_efficiency_plot_has_a_band_a_line_and_a_dot_per_run() {
        let svg = sample_efficiency_plot(&info(), &rows());
        assert!(svg.starts_with("<svg"), "{svg}");
        assert!(svg.ends_with("</svg>\n"));
        assert_eq!(svg.matches("<polygon").count(), 1, "one band");
        assert_eq!(svg.matches("<polyline").count(), 1, "one mean line");
        // 2 counts × 2 runs dots, 2 mean markers, 1 legend dot.
        assert_eq!(svg.matches("<circle").count(), 7);
        assert!(svg.contains(">25 %</text>") && svg.contains(">100 %</text>"), "{svg}");
        assert_eq!(svg, sample_efficiency_plot(&info(), &rows()), "deterministic");
    }

    #[test]
    fn the_efficiency_plot_of_no_rows_says_so() {
        let svg = sample_efficiency_plot(&info(), &[]);
        assert!(svg.contains("no finished runs yet"));
        assert!(!svg.contains("<polygon"));
    }

    #[test]
    fn the_success_plot_has_a_bar_per_problem_and_count_and_the_factor() {
        let svg = success_plot(&info(), &rows());
        assert_eq!(svg.matches("<title>").count(), 4, "2 problems × 2 counts");
        assert!(svg.contains("<title>pack4, 20: 0/2</title>"), "{svg}");
        assert!(svg.contains("Generalization factor 4×"), "{svg}");
        assert!(svg.contains(">pack4 (4)</text>"));
        assert!(svg.contains(">20 demonstrations</text>"));
        assert_eq!(svg, success_plot(&info(), &rows()), "deterministic");
    }
}
