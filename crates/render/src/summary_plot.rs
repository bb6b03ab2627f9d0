//! Figures of a parameter study: every metric against one varied key, a small panel per metric,
//! in the style of the run plots ([`super::plot`]).
//!
//! When other keys vary too, each combination of their values is a series of its own (a line
//! with points), so a 3 × 2 grid over `E` and `θ₀` shows two lines per panel in the figure
//! against `E`. A key spanning more than two decades of positive values is drawn on a log axis.

use std::path::Path;

use plotters::prelude::*;

use super::plot::{axis_label, draw_legend_sized, range_of, render_png, DrawResult, Root};
use crate::Error;

/// One panel: a metric against the key, one series per combination of the other keys.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Panel {
    /// The metric (a column name of `summary.csv`).
    pub metric: String,
    /// `(label, points (key value, metric value))`; the label is empty for a single series.
    pub series: Vec<(String, Vec<(f64, f64)>)>,
}

/// Panels per row of the figure.
const COLUMNS: usize = 3;
/// Size of one panel \[px\].
const PANEL: (u32, u32) = (460, 320);
/// Series drawn with a legend at most (more are drawn without one).
const LEGEND_SERIES: usize = 8;

/// Whether values of a key are best drawn on a log axis: all positive and spanning more than two
/// decades.
pub fn wants_log_axis(values: &[f64]) -> bool {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
    lo > 0.0 && hi / lo > 100.0
}

/// Writes the figure of `panels` against `key` to `path` (PNG).
pub fn write_summary_png(path: &Path, key: &str, panels: &[Panel]) -> Result<(), Error> {
    let rows = panels.len().div_ceil(COLUMNS).max(1) as u32;
    let size = (PANEL.0 * COLUMNS as u32, 60 + PANEL.1 * rows);
    let xs: Vec<f64> = panels
        .iter()
        .flat_map(|p| p.series.iter().flat_map(|s| s.1.iter().map(|q| q.0)))
        .collect();
    let log = wants_log_axis(&xs);
    render_png(path, size, |root| draw(root, key, log, panels))
}

const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

fn draw(root: &Root<'_>, key: &str, log: bool, panels: &[Panel]) -> DrawResult {
    let root = root.titled(&format!("Sweep summary against {key}"), ("sans-serif", 26))?;
    let rows = panels.len().div_ceil(COLUMNS).max(1);
    let areas = root.margin(10, 0, 0, 0).split_evenly((rows, COLUMNS));
    let tx = |x: f64| if log { x.log10() } else { x };
    let x_desc = if log {
        format!("{key} (log scale)")
    } else {
        key.to_string()
    };
    for (i, (panel, area)) in panels.iter().zip(areas.iter()).enumerate() {
        let points: Vec<(f64, f64)> = panel
            .series
            .iter()
            .flat_map(|s| s.1.iter().map(|&(x, y)| (tx(x), y)))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        if points.is_empty() {
            area.draw(&Text::new(
                format!("{}: no values", panel.metric),
                (20, 30),
                ("sans-serif", 16).into_font().color(&RGBColor(90, 90, 90)),
            ))?;
            continue;
        }
        let (xlo, xhi) = range_of(points.iter().map(|p| &p.0));
        let (ylo, yhi) = range_of(points.iter().map(|p| &p.1));
        let (xs, ys) = (xhi - xlo, yhi - ylo);
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.metric, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(xlo..xhi, ylo..yhi)?;
        let x_label = |v: &f64| {
            if log {
                format!("{:.2e}", 10f64.powf(*v))
            } else {
                axis_label(*v, xs)
            }
        };
        chart
            .configure_mesh()
            .x_desc(x_desc.as_str())
            .axis_desc_style(("sans-serif", 14))
            .label_style(("sans-serif", 12))
            .x_labels(5)
            .y_labels(6)
            .x_label_formatter(&x_label)
            .y_label_formatter(&|v| axis_label(*v, ys))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(205, 205, 205))
            .draw()?;
        let legend = i == 0 && panel.series.len() > 1 && panel.series.len() <= LEGEND_SERIES;
        for (j, (label, pts)) in panel.series.iter().enumerate() {
            let colour = COLOURS[j % COLOURS.len()];
            let mut pts: Vec<(f64, f64)> = pts
                .iter()
                .map(|&(x, y)| (tx(x), y))
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let line = chart.draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(2)))?;
            if legend {
                line.label(label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            }
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
        }
        if legend {
            draw_legend_sized(&mut chart, 12)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_axes_for_positive_keys_over_two_decades() {
        assert!(wants_log_axis(&[1e6, 1e7, 2.1e11]));
        assert!(!wants_log_axis(&[10.0, 20.0, 60.0]));
        assert!(!wants_log_axis(&[0.0, 1e6]));
    }
}
