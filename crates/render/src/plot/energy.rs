//! `energy.png`: the energies over time, and with a wall each impact on its own time scale.
//!
//! - **Upper panel**: the kinetic energy and the *changes* since t = 0 of the gravitational and
//!   the total energy \[J\] (with a torque, the work it has done; with a wall, the contact energy,
//!   part of the total), so every curve lives on the scale of the motion: the gravitational energy
//!   itself (about −2 J for the default pendulum, measured from the pivot) would squeeze a 0.12 J
//!   kinetic energy flat.
//! - **Strain panel**: the strain energy alone on its own scale (about a millionth of the others
//!   for a steel pendulum, it would lie flat on zero); the figure's caption states the ratio.
//! - **Impact panel** (runs with a wall): the kinetic and the contact energy against the time since
//!   each impact's start \[ms\], every impact overlaid, so identical blows lie on one curve.
//!
//! The time panels draw every curve at the resolution of their pixel columns ([`bars`]): the
//! samples in one column become a bar from their smallest to their largest value, and the samples
//! of one impact (an impact is a column or two of a plot of the whole run, sampled by many rows of
//! `impacts.csv`) become one bar at the column where the impact starts. So every impact is drawn
//! to its full height and identical impacts are drawn identically, whatever the sub-pixel phase of
//! their samples. (A polyline through an impact's samples, going up and back within a column or
//! two, folds onto itself, and the rasteriser's polygon fill cuts identical spikes to different
//! heights.) Where the kinetic and the contact energy trade places in an impact's column, the
//! contact energy is drawn on top; the impact panel shows both.

use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::{draw_impacts, draw_legend, draw_mesh, range_of, time_range, with_legend_room, DrawResult, History, Root};

/// Width and height of the figure without the impact panel.
const SIZE: (u32, u32) = (1000, 850);
/// Height the impact panel adds.
const IMPACT_PANEL: u32 = 340;
/// The upper panel's share of the height of the two time panels.
const UPPER_SHARE: f64 = 0.56;

const BLUE: RGBColor = RGBColor(31, 119, 180);
const RED: RGBColor = RGBColor(214, 39, 40);
const ORANGE: RGBColor = RGBColor(255, 127, 14);

/// The figure's size: taller when `h` has impacts to show on their own time scale.
pub fn size(h: &History) -> (u32, u32) {
    if h.impacts.is_empty() {
        SIZE
    } else {
        (SIZE.0, SIZE.1 + IMPACT_PANEL)
    }
}

/// One bar of a curve: the samples of one pixel column, or of one impact, spanning `t` (the
/// column's left and right edge \[s\]), with their smallest, largest, first and last value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bar {
    /// Left and right edge of the pixel column \[s\].
    pub t: (f64, f64),
    /// Smallest and largest sample.
    pub range: (f64, f64),
    /// First and last sample, where the joins to the neighbouring bars start and end.
    pub ends: (f64, f64),
    /// Whether the bar holds the samples of an impact.
    pub impact: bool,
}

/// The bars of the curve `v(t)` in a plot of `columns` pixel columns over `t0..t1`: the samples of
/// each impact of `impacts` (`(start, end)` \[s\]) make one bar at the column of its start, every
/// other sample the bar of its column; consecutive samples of one column or impact share a bar.
/// Non-finite samples are skipped.
pub fn bars(t: &[f64], v: &[f64], (t0, t1): (f64, f64), columns: usize, impacts: &[(f64, f64)]) -> Vec<Bar> {
    let columns = columns.max(1);
    let width = (t1 - t0) / columns as f64;
    let column_of = |t: f64| (((t - t0) / width).floor().max(0.0) as usize).min(columns - 1);
    let mut out: Vec<(Option<usize>, usize, Bar)> = Vec::new();
    // the samples and the impacts are in time order: the first impact not yet over
    let mut next = 0;
    for (&ti, &vi) in t.iter().zip(v) {
        if !(ti.is_finite() && vi.is_finite()) {
            continue;
        }
        while next < impacts.len() && impacts[next].1 < ti {
            next += 1;
        }
        let impact = (next < impacts.len() && impacts[next].0 <= ti).then_some(next);
        let column = column_of(impact.map_or(ti, |k| impacts[k].0));
        match out.last_mut() {
            Some((k, c, bar)) if *k == impact && *c == column => {
                bar.range = (bar.range.0.min(vi), bar.range.1.max(vi));
                bar.ends.1 = vi;
            }
            _ => {
                let left = t0 + column as f64 * width;
                let bar = Bar {
                    t: (left, left + width),
                    range: (vi, vi),
                    ends: (vi, vi),
                    impact: impact.is_some(),
                };
                out.push((impact, column, bar));
            }
        }
    }
    out.into_iter().map(|(_, _, bar)| bar).collect()
}

type Chart<'a, 'b> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws `bars` on `chart` (value axis `lo..hi`) in `colour`, about 2 px wide: each bar filled
/// from its smallest to its largest value, consecutive bars joined from the last value of one to
/// the first of the next; with `impacts_only`, just the impacts' bars. A legend entry when `label`
/// is given.
fn draw_bars(
    chart: &mut Chart<'_, '_>,
    bars: &[Bar],
    (lo, hi): (f64, f64),
    colour: RGBColor,
    label: Option<&str>,
    impacts_only: bool,
) -> DrawResult {
    // half a stroke is one pixel in value units, so a flat stretch is as thick as a slope; a
    // column's bar is widened to 2 px, an impact's to 3 px (over the 2 px line marking its start)
    let half = (hi - lo) / f64::from(chart.plotting_area().dim_in_pixel().1.max(1));
    chart.draw_series(bars.iter().filter(|b| b.impact || !impacts_only).map(|b| {
        let widen = if b.impact { 1.0 } else { 0.5 } * (b.t.1 - b.t.0);
        Rectangle::new(
            [(b.t.0 - widen, b.range.1 + half), (b.t.1 + widen, b.range.0 - half)],
            colour.filled(),
        )
    }))?;
    if impacts_only {
        return Ok(());
    }
    let centre = |b: &Bar| 0.5 * (b.t.0 + b.t.1);
    let joins: Vec<[(f64, f64); 2]> = bars
        .windows(2)
        .map(|p| [(centre(&p[0]), p[0].ends.1), (centre(&p[1]), p[1].ends.0)])
        // a segment of no length in pixels has no direction to be widened along
        .filter(|[a, b]| chart.backend_coord(a) != chart.backend_coord(b))
        .collect();
    let anno = chart.draw_series(
        joins
            .into_iter()
            .map(|seg| PathElement::new(seg.to_vec(), colour.stroke_width(2))),
    )?;
    if let Some(label) = label {
        anno.label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(2)));
    }
    Ok(())
}

/// A chart of `area` over `x` × `y` with the project's mesh style and axis descriptions.
fn chart_on<'a, 'b>(
    area: &'a Root<'b>,
    caption: Option<&str>,
    (x, y): ((f64, f64), (f64, f64)),
    (x_desc, y_desc): (&str, &str),
) -> Result<Chart<'a, 'b>, Box<dyn std::error::Error>> {
    let mut builder = ChartBuilder::on(area);
    if let Some(caption) = caption {
        builder.caption(caption, ("sans-serif", 18));
    }
    let mut chart = builder
        .margin(14)
        .x_label_area_size(45)
        .y_label_area_size(85)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
    draw_mesh(&mut chart, (x_desc, y_desc), (x.1 - x.0, y.1 - y.0))?;
    Ok(chart)
}

/// Draws the figure on `root`, of [`size`]`(h)`.
pub fn draw(root: &Root<'_>, h: &History) -> DrawResult {
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let (k_peak, s_peak) = (peak(&h.kinetic), peak(&h.strain));
    let ratio = if k_peak > 0.0 {
        format!("{:.1e}", s_peak / k_peak)
    } else {
        "n/a".into()
    };
    let root = root.titled("Energy over time", ("sans-serif", 26))?;
    let note = format!(
        "Gravitational and total energy as changes since t = 0. Strain energy peaks at {ratio} × the kinetic peak: \
         the lower panel shows it on its own scale."
    );
    root.draw(&Text::new(
        note,
        (20, 0),
        ("sans-serif", 15).into_font().color(&RGBColor(60, 60, 60)),
    ))?;
    let body = root.margin(24, 0, 0, 0);
    let (time_panels, impact_panel) = if h.impacts.is_empty() {
        (body, None)
    } else {
        let (t, i) = body.split_vertically(body.dim_in_pixel().1 - IMPACT_PANEL);
        (t, Some(i))
    };
    let (upper, lower) = time_panels.split_vertically((SIZE.1 as f64 * UPPER_SHARE) as u32);
    let span = time_range(h);

    let curves = h.energy_curves();
    let colours = [BLUE, RGBColor(44, 160, 44), BLACK, RED, RGBColor(140, 86, 75)];
    let series: Vec<(&str, &[f64], RGBColor)> = curves
        .iter()
        .zip(colours)
        .map(|((name, v), c)| (*name, v.as_slice(), c))
        .collect();
    // room above the curves for the legend's up to six entries, so it covers no data
    let y = range_of(series.iter().flat_map(|s| s.1.iter()));
    let y = (y.0, y.1 + 0.45 * (y.1 - y.0));
    let mut chart = chart_on(
        &upper,
        None,
        (span, y),
        ("time t [s]", "energy, change since t = 0 [J]"),
    )?;
    draw_impacts(&mut chart, h, y)?;
    let columns = chart.plotting_area().dim_in_pixel().0 as usize;
    // the contact energy first, under the others: between impacts it lies on the total's zero;
    // its impact bars again last, on top of the kinetic energy's dip in the same columns
    let (under, over): (Vec<_>, Vec<_>) = series
        .into_iter()
        .map(|(name, values, colour)| (name, bars(&h.time, values, span, columns, &h.impacts), colour))
        .partition(|s| s.0.starts_with("contact"));
    for (name, bars, colour) in under.iter().chain(&over) {
        draw_bars(&mut chart, bars, y, *colour, Some(name), false)?;
    }
    for (_, bars, colour) in &under {
        draw_bars(&mut chart, bars, y, *colour, None, true)?;
    }
    draw_legend(&mut chart)?;

    let y = range_of(h.strain.iter());
    let mut chart = chart_on(
        &lower,
        Some("Strain energy alone (own scale)"),
        (span, y),
        ("time t [s]", "strain energy [J]"),
    )?;
    let bars = bars(&h.time, &h.strain, span, columns, &h.impacts);
    draw_bars(&mut chart, &bars, y, ORANGE, None, false)?;

    if let Some(area) = impact_panel {
        draw_impact_panel(&area, h)?;
    }
    Ok(())
}

/// The samples of each impact of `h` and of a margin of 15 % of its duration on either side, as
/// (time since the impact's start \[ms\], kinetic energy, contact energy) \[J\].
pub fn impact_samples(h: &History) -> Vec<Vec<(f64, f64, f64)>> {
    h.impacts
        .iter()
        .map(|&(s, e)| {
            let margin = 0.15 * (e - s);
            (0..h.time.len().min(h.kinetic.len()).min(h.contact.len()))
                .filter(|&i| h.time[i] >= s - margin && h.time[i] <= e + margin)
                .map(|i| ((h.time[i] - s) * 1e3, h.kinetic[i], h.contact[i]))
                .collect()
        })
        .collect()
}

/// The impact panel: kinetic and contact energy against the time since each impact's start.
fn draw_impact_panel(area: &Root<'_>, h: &History) -> DrawResult {
    let impacts = impact_samples(h);
    let x = range_of(impacts.iter().flatten().map(|p| &p.0));
    let y = with_legend_room(range_of(impacts.iter().flatten().flat_map(|p| [&p.1, &p.2])));
    let n = impacts.len();
    let caption = format!(
        "The {n} impact{} on their own time scale, overlaid (sub-steps from impacts.csv)",
        if n == 1 { "" } else { "s" }
    );
    let mut chart = chart_on(
        area,
        Some(&caption),
        (x, y),
        ("time since the impact's start [ms]", "energy [J]"),
    )?;
    let kinetic: fn(&(f64, f64, f64)) -> f64 = |p| p.1;
    let contact: fn(&(f64, f64, f64)) -> f64 = |p| p.2;
    for (value, colour, name) in [(kinetic, BLUE, "kinetic"), (contact, RED, "contact")] {
        let mut anno = None;
        for samples in &impacts {
            anno = Some(chart.draw_series(LineSeries::new(
                samples.iter().map(|p| (p.0, value(p))),
                colour.stroke_width(2),
            ))?);
        }
        if let Some(anno) = anno {
            anno.label(format!("{name}, every impact"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(2)));
        }
    }
    draw_legend(&mut chart)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_impacts_at_different_sub_pixel_phases_make_identical_bars() {
        // a 2 ms pulse sampled every 0.1 ms, at three starts that fall at different places in
        // their 1.25 ms pixel columns, between samples every 10 ms
        let pulse = |t: f64| {
            if (0.0..=2e-3).contains(&t) {
                (std::f64::consts::PI * t / 2e-3).sin().max(0.0)
            } else {
                0.0
            }
        };
        let starts = [0.2403, 0.7209, 1.2017];
        let mut t: Vec<f64> = (0..=200).map(|k| k as f64 * 0.01).collect();
        for s in starts {
            t.extend((0..=20).map(|k| s + k as f64 * 1e-4));
        }
        t.sort_by(f64::total_cmp);
        let v: Vec<f64> = t
            .iter()
            .map(|&ti| starts.iter().map(|&s| pulse(ti - s)).sum::<f64>())
            .collect();
        let impacts: Vec<(f64, f64)> = starts.iter().map(|&s| (s, s + 2e-3)).collect();
        let bars = bars(&t, &v, (0.0, 2.0), 1600, &impacts);
        let hits: Vec<&Bar> = bars.iter().filter(|b| b.impact).collect();
        assert_eq!(hits.len(), 3, "one bar per impact: {hits:?}");
        for b in &hits {
            // the whole pulse, 0 to its peak, in one bar one column wide
            assert!(b.range.0.abs() < 1e-12 && (b.range.1 - 1.0).abs() < 1e-12, "{b:?}");
            assert!(((b.t.1 - b.t.0) - 2.0 / 1600.0).abs() < 1e-15, "{b:?}");
        }
        // each sits in the column of its impact's start
        for (b, s) in hits.iter().zip(starts) {
            assert!(b.t.0 <= s && s < b.t.1, "{b:?} for a start at {s}");
        }
        // samples outside impacts keep a bar per column
        assert_eq!(bars.iter().filter(|b| !b.impact).count(), 201);
    }
}
