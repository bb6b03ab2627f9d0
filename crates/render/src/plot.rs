//! Time-history plots of a run's [`History`], the values of its `results.csv` and `impacts.csv`
//! rows taken from the records as the run writes them (the pictures' observer,
//! [`crate::pictures`]) and drawn at its end:
//!
//! - `theta.png`: the rigid-body angle proxy θ(t) in degrees, with dashed lines at ±θ_max, as in
//!   the tutorial's matplotlib figure (θ_max = |θ(0)|, the release angle, like the tutorial's
//!   `theta_vals[0]`; when the run starts at θ = 0, the largest |θ| instead); a line is drawn only
//!   on a side the motion reaches ([`theta_limits`]: a swing stopped by a wall has no −θ_max), and
//!   the axis spans the data and the lines drawn. With an applied
//!   torque the release angle bounds nothing, so the lines are left out and the torque M(t) is
//!   drawn instead, on its own axis at the right; they are left out too when the body turns over
//!   (|θ| > 180°, a spin).
//! - `energy.png` ([`energy`]): the kinetic energy and the *changes* since t = 0 of the
//!   gravitational and the total energy, the strain energy in a panel of its own, and with a wall
//!   every impact on its own time scale.
//!
//! Drawing uses plotters' bitmap backend into an RGB buffer with the shipped font (`font.rs`); the
//! PNG is encoded with the `png` crate and written atomically.

use std::path::Path;

use pendulum_fem_core::post::unsigned_zero;
use pendulum_fem_core::simulation::{ContactEvent, ContactEventKind, StepRecord};
use plotters::prelude::*;

use super::font;
use crate::Error;

pub mod energy;

/// The columns of `results.csv` (and `impacts.csv`) the plots use, one entry per record in time
/// order, and the impacts.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// Time \[s\].
    pub time: Vec<f64>,
    /// Proxy angle \[rad\].
    pub theta: Vec<f64>,
    /// Kinetic energy \[J\].
    pub kinetic: Vec<f64>,
    /// Strain energy \[J\].
    pub strain: Vec<f64>,
    /// Gravitational potential energy \[J\].
    pub gravity: Vec<f64>,
    /// Total energy \[J\].
    pub total: Vec<f64>,
    /// Applied torque \[N m\].
    pub torque: Vec<f64>,
    /// Work of the torque \[J\].
    pub torque_work: Vec<f64>,
    /// Contact energy \[J\], part of the total (empty for a run without a wall).
    pub contact: Vec<f64>,
    /// The impacts, `(start, end)` \[s\], from the run's contact events, the rows of `events.csv`
    /// (see [`History::set_impacts`]); an impact still going on at the end of the run ends at the
    /// last time.
    pub impacts: Vec<(f64, f64)>,
}

impl History {
    /// The history of `records` (rows of `results.csv` and `impacts.csv`, in time order).
    pub fn of_records<'a>(records: impl IntoIterator<Item = &'a StepRecord>) -> Self {
        let mut h = Self::default();
        records.into_iter().for_each(|r| h.push(r));
        h
    }

    /// Takes the next record (in time order) with the values of its row in `results.csv` (a
    /// negative zero as `0`, [`unsigned_zero`]); its contact energy when it has one (a run with a
    /// wall).
    pub fn push(&mut self, r: &StepRecord) {
        let z = unsigned_zero;
        self.time.push(z(r.time));
        self.theta.push(z(r.theta));
        self.kinetic.push(z(r.kinetic));
        self.strain.push(z(r.strain));
        self.gravity.push(z(r.gravity));
        self.total.push(z(r.total));
        self.torque.push(z(r.torque));
        self.torque_work.push(z(r.torque_work));
        if let Some(c) = &r.contact {
            self.contact.push(z(c.energy));
        }
    }

    /// Sets [`History::impacts`] from the contact events (in the order they happened): each start
    /// opens an impact, the next end closes it; an impact without its end ends at the history's
    /// last time.
    pub fn set_impacts(&mut self, events: &[ContactEvent]) {
        let mut spans = Vec::new();
        let mut open = None;
        for e in events {
            match e.kind {
                ContactEventKind::Start => open = Some(e.time),
                ContactEventKind::End => spans.push((open.take().unwrap_or(e.time), e.time)),
            }
        }
        if let Some(start) = open {
            let end = self.time.last().copied().unwrap_or(0.0);
            spans.push((start, end.max(start)));
        }
        self.impacts = spans;
    }

    /// Whether the run had a wall (its records have the contact columns).
    pub fn has_wall(&self) -> bool {
        !self.contact.is_empty()
    }

    /// Whether a torque was applied at some time.
    pub fn has_torque(&self) -> bool {
        self.torque.iter().any(|m| *m != 0.0)
    }

    /// The curves of the upper energy panel, `(label, values)`: the kinetic energy, the changes of
    /// the gravitational and the total energy since the first row, and the torque's work when
    /// there is a torque.
    pub fn energy_curves(&self) -> Vec<(&'static str, Vec<f64>)> {
        let change = |v: &[f64]| {
            let v0 = v.first().copied().unwrap_or(0.0);
            v.iter().map(|x| x - v0).collect::<Vec<f64>>()
        };
        let mut curves = vec![
            ("kinetic", self.kinetic.clone()),
            ("gravitational − its start value", change(&self.gravity)),
            ("total − its start value", change(&self.total)),
        ];
        if self.has_torque() && self.torque_work.len() == self.time.len() {
            curves.push(("work of the torque", self.torque_work.clone()));
        }
        if self.has_wall() && self.contact.len() == self.time.len() {
            curves.push(("contact (part of the total)", self.contact.clone()));
        }
        curves
    }
}

/// Colour of the impact marks in the plots.
pub const IMPACT_RGB: (u8, u8, u8) = (148, 103, 189);

/// Draws the impacts of `h` on `chart` (a shaded span from start to end and a line at the start,
/// over `lo..hi`) with one legend entry.
pub(crate) fn draw_impacts<DB: DrawingBackend>(
    chart: &mut ChartContext<
        '_,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    h: &History,
    (lo, hi): (f64, f64),
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    if h.impacts.is_empty() {
        return Ok(());
    }
    let colour = RGBColor(IMPACT_RGB.0, IMPACT_RGB.1, IMPACT_RGB.2);
    chart.draw_series(
        h.impacts
            .iter()
            .map(|&(s, e)| Rectangle::new([(s, lo), (e, hi)], colour.mix(0.25).filled())),
    )?;
    let n = h.impacts.len();
    chart
        .draw_series(
            h.impacts
                .iter()
                .map(|&(s, _)| PathElement::new(vec![(s, lo), (s, hi)], colour.stroke_width(2))),
        )?
        .label(format!(
            "impact{} ({n}, start to end, from events.csv)",
            if n == 1 { "" } else { "s" }
        ))
        .legend(move |(x, y)| Rectangle::new([(x + 9, y - 6), (x + 15, y + 6)], colour.filled()));
    Ok(())
}

const THETA_SIZE: (u32, u32) = (1000, 600);

/// Writes `theta.png`.
pub fn write_theta_png(path: &Path, h: &History) -> Result<(), Error> {
    render_png(path, THETA_SIZE, |root| draw_theta(root, h))
}

/// Writes `energy.png` (see [`energy`]).
pub fn write_energy_png(path: &Path, h: &History) -> Result<(), Error> {
    render_png(path, energy::size(h), |root| energy::draw(root, h))
}

pub(crate) type Root<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
pub(crate) type DrawResult = Result<(), Box<dyn std::error::Error>>;

pub(crate) fn render_png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Root<'_>) -> DrawResult,
) -> Result<(), Error> {
    font::register_for_plotters();
    let mut buf = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_error(path, e))?;
        draw(&root).map_err(|e| plot_error(path, e))?;
        root.present().map_err(|e| plot_error(path, e))?;
    }
    pendulum_fem_core::store::write_atomically(path, |w| {
        let mut enc = png::Encoder::new(w, size.0, size.1);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().map_err(std::io::Error::other)?;
        writer.write_image_data(&buf).map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    })
}

fn plot_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::io(path, std::io::Error::other(format!("drawing the plot failed: {e}")))
}

/// `[lo, hi]` of the values, widened when flat, padded by 5 %.
pub(crate) fn range_of<'a>(values: impl IntoIterator<Item = &'a f64>) -> (f64, f64) {
    let (mut lo, mut hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
    if !lo.is_finite() {
        return (-1.0, 1.0);
    }
    if hi - lo <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        lo -= d;
        hi += d;
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Axis label text for a value on an axis spanning `span` (decimals for about five ticks).
pub(crate) fn axis_label(v: f64, span: f64) -> String {
    if v.abs() <= 1e-9 * span {
        "0".into()
    } else if !(1e-3..1e5).contains(&span) {
        format!("{v:.2e}")
    } else {
        let d = (-(span / 5.0).log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.d$}")
    }
}

/// Raises the top of a range by 30 % so the legend sits above the curves.
pub(crate) fn with_legend_room((lo, hi): (f64, f64)) -> (f64, f64) {
    (lo, hi + 0.3 * (hi - lo))
}

pub(crate) fn time_range(h: &History) -> (f64, f64) {
    let t0 = h.time.first().copied().unwrap_or(0.0);
    let t1 = h.time.last().copied().unwrap_or(1.0);
    if t1 > t0 {
        (t0, t1)
    } else {
        (t0, t0 + 1.0)
    }
}

/// The share of θ_max the motion must reach on a side for the dashed line there to be drawn: a
/// swing reaches ±θ_max up to its energy error (and a damped one loses a little per swing), while
/// a swing stopped by a wall never goes past the wall's angle (about 0° here) on that side.
pub const THETA_LIMIT_REACHED: f64 = 0.9;

/// The dashed limit lines of `theta.png` and its angle axis, for θ(t) in degrees (`deg`): the lines
/// at +θ_max and −θ_max (θ_max = |θ(0)|, or the largest |θ| for a start at 0) that the motion
/// reaches, each as (sign, value) (none with a torque or for a body that turns over), and the
/// axis: the range of the data and of those lines, with room for the legend at the top.
pub fn theta_limits(deg: &[f64], torque: bool) -> (Vec<(f64, f64)>, (f64, f64)) {
    let first = deg.first().copied().unwrap_or(0.0).abs();
    let theta_max = if first > 1e-9 {
        first
    } else {
        deg.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    };
    // ±θ_max bound a swing; a body that turns over (a spin) has no such bounds
    let show_bounds = !torque && deg.iter().all(|v| v.abs() <= 180.0) && theta_max > 0.0;
    let (lo, hi) = deg.iter().fold((0.0f64, 0.0f64), |(l, h), &v| (l.min(v), h.max(v)));
    let lines: Vec<(f64, f64)> = [(1.0, hi), (-1.0, -lo)]
        .into_iter()
        .filter(|&(_, reached)| show_bounds && reached >= THETA_LIMIT_REACHED * theta_max)
        .map(|(sign, _)| (sign, sign * theta_max))
        .collect();
    let axis = with_legend_room(range_of(deg.iter().chain(lines.iter().map(|(_, y)| y))));
    (lines, axis)
}

fn draw_theta(root: &Root<'_>, h: &History) -> DrawResult {
    let deg: Vec<f64> = h.theta.iter().map(|t| t.to_degrees()).collect();
    let (t0, t1) = time_range(h);
    let torque = h.has_torque() && h.torque.len() == h.time.len();
    let (lines, (lo, hi)) = theta_limits(&deg, torque);
    let (mlo, mhi) = with_legend_room(range_of(h.torque.iter().chain([0.0].iter())));
    let mut chart = ChartBuilder::on(root)
        .caption("Rigid-body angle proxy θ(t)", ("sans-serif", 26))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .right_y_label_area_size(if torque { 80 } else { 0 })
        .build_cartesian_2d(t0..t1, lo..hi)?
        .set_secondary_coord(t0..t1, mlo..mhi);
    draw_mesh(&mut chart, ("time t [s]", "angle θ [deg]"), (t1 - t0, hi - lo))?;
    draw_impacts(&mut chart, h, (lo, hi))?;
    let blue = RGBColor(31, 119, 180);
    let points: Vec<(f64, f64)> = h.time.iter().copied().zip(deg.iter().copied()).collect();
    chart
        .draw_series(LineSeries::new(points.iter().copied(), blue.stroke_width(2)))?
        .label("θ(t), rigid-body angle proxy")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], blue.stroke_width(2)));
    if points.len() <= 250 {
        chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, blue.filled())))?;
    }
    if torque {
        let ms = mhi - mlo;
        chart
            .configure_secondary_axes()
            .y_desc("torque M [N m]")
            .axis_desc_style(("sans-serif", 18))
            .label_style(("sans-serif", 15))
            .y_label_formatter(&|v| axis_label(*v, ms))
            .draw()?;
        let red = RGBColor(214, 39, 40);
        chart
            .draw_secondary_series(LineSeries::new(
                h.time.iter().copied().zip(h.torque.iter().copied()),
                red.stroke_width(2),
            ))?
            .label("applied torque M(t) (right axis)")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], red.stroke_width(2)));
    }
    for &(sign, y) in &lines {
        let (color, name) = if sign > 0.0 {
            (RGBColor(214, 39, 40), "+θ_max")
        } else {
            (BLACK, "−θ_max")
        };
        chart
            .draw_series(DashedLineSeries::new([(t0, y), (t1, y)], 10, 6, color.stroke_width(2)))?
            .label(format!("{name} = {:+.2}°", y))
            .legend(move |(x, yy)| PathElement::new(vec![(x, yy), (x + 24, yy)], color.stroke_width(2)));
    }
    draw_legend(&mut chart)
}

/// Draws the grid, the axes' labels (for axes spanning `spans`) and their descriptions `descs` of
/// `chart`, in the plots' style.
pub(crate) fn draw_mesh<'a, 'b: 'a>(
    chart: &mut ChartContext<
        'a,
        BitMapBackend<'b>,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    (x_desc, y_desc): (&str, &str),
    (xs, ys): (f64, f64),
) -> DrawResult {
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .x_label_formatter(&|v| axis_label(*v, xs))
        .y_label_formatter(&|v| axis_label(*v, ys))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()?;
    Ok(())
}

/// Draws the legend of `chart` in the upper right corner, in the plots' style (labels of 15 px).
pub(crate) fn draw_legend<'a, 'b: 'a>(
    chart: &mut ChartContext<
        'a,
        BitMapBackend<'b>,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
) -> DrawResult {
    draw_legend_sized(chart, 15)
}

/// Draws the legend of `chart` in the upper right corner, in the plots' style, with labels of
/// `font` px: the one legend style of the run's plots and a sweep's summary figures.
pub(crate) fn draw_legend_sized<'a, 'b: 'a>(
    chart: &mut ChartContext<
        'a,
        BitMapBackend<'b>,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    font: u32,
) -> DrawResult {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", font))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_upper_energy_panel_shows_changes_so_the_kinetic_energy_spans_most_of_it() {
        // a pendulum whose gravitational energy sits near −2 J while 0.12 J change hands
        let n = 50;
        let mut h = History::default();
        for k in 0..=n {
            let s = (k as f64 / n as f64 * std::f64::consts::PI).sin().powi(2);
            h.time.push(k as f64 * 0.01);
            h.theta.push(0.35 * (1.0 - 2.0 * s));
            h.kinetic.push(0.12 * s);
            h.gravity.push(-2.0 - 0.12 * s);
            h.strain.push(1e-7);
            h.total.push(-2.0 + 1e-7);
        }
        let curves = h.energy_curves();
        assert_eq!(curves.len(), 3, "no torque curve without a torque");
        let (lo, hi) = range_of(curves.iter().flat_map(|c| c.1.iter()));
        // the kinetic energy spans at least 40 % of the panel
        assert!(0.12 / (hi - lo) > 0.4, "panel [{lo}, {hi}]");
        assert!(!h.has_torque());
        h.torque = vec![0.5; n + 1];
        h.torque_work = h.kinetic.clone();
        assert!(h.has_torque());
        assert_eq!(h.energy_curves().last().unwrap().0, "work of the torque");
    }

    /// θ(t) [deg] of a 20° swing sampled over `periods`, folded at `floor` (a wall at that angle).
    fn swing(periods: f64, floor: f64) -> Vec<f64> {
        (0..=400)
            .map(|k| (20.0 * (2.0 * std::f64::consts::PI * periods * k as f64 / 400.0).cos()).max(floor))
            .collect()
    }

    #[test]
    fn a_free_swing_draws_both_limits_on_an_axis_around_them() {
        let (lines, (lo, hi)) = theta_limits(&swing(2.0, -90.0), false);
        assert_eq!(lines, vec![(1.0, 20.0), (-1.0, -20.0)]);
        assert!(lo < -20.0 && hi > 20.0, "[{lo}, {hi}]");
    }

    #[test]
    fn a_swing_against_a_wall_draws_only_the_limit_it_reaches_on_an_axis_limited_to_the_data() {
        // the wall stops the swing at θ ≈ −0.1° (the penetration); −20° is never approached
        let (lines, (lo, hi)) = theta_limits(&swing(2.0, -0.1), false);
        assert_eq!(lines, vec![(1.0, 20.0)], "no −θ_max line");
        // below: the data's 5 % padding of the 20.1° span, no more; above: the data and the legend's 30 %
        assert!(
            (-0.1 - 1.01..-0.1).contains(&lo),
            "axis bottom {lo}: the data end at −0.1°"
        );
        // 20° + 5 % padding + 30 % for the legend = 27.6°; with a −20° line it would be 35.2°
        assert!(hi < 28.0, "axis top {hi}");
        // a torque or a spin: no lines at all
        assert!(theta_limits(&swing(2.0, -90.0), true).0.is_empty());
        let spin: Vec<f64> = (0..100).map(|k| 20.0 + 10.0 * k as f64).collect();
        assert!(theta_limits(&spin, false).0.is_empty());
    }

    #[test]
    fn a_history_holds_the_values_of_its_records_rows_and_the_impacts_of_their_events() {
        use pendulum_fem_core::simulation::ContactRecord;
        let record = |time: f64, energy| StepRecord {
            time,
            theta: -0.0,
            kinetic: 0.5 * time,
            torque: 0.25,
            contact: Some(ContactRecord {
                energy,
                ..Default::default()
            }),
            ..Default::default()
        };
        let records = [record(0.0, 0.0), record(0.01, 0.002), record(0.02, 0.0)];
        let mut h = History::of_records(&records);
        assert_eq!(h.time, [0.0, 0.01, 0.02]);
        assert_eq!(h.kinetic, [0.0, 0.005, 0.01]);
        assert_eq!(h.contact, [0.0, 0.002, 0.0]);
        assert!(
            h.theta.iter().all(|t| t.is_sign_positive()),
            "−0 as 0, as results.csv has it"
        );
        assert!(h.has_wall() && h.has_torque());
        let event = |time, kind| ContactEvent {
            time,
            kind,
            theta: 0.0,
            omega: 0.0,
            impulse: 0.0,
            penetration: 0.0,
            force: 0.0,
        };
        let (start, end) = (ContactEventKind::Start, ContactEventKind::End);
        h.set_impacts(&[event(0.005, start), event(0.008, end), event(0.015, start)]);
        assert_eq!(
            h.impacts,
            [(0.005, 0.008), (0.015, 0.02)],
            "the open impact ends at the last time"
        );
        let plain = History::of_records(&[StepRecord::default()]);
        assert!(!plain.has_wall() && plain.contact.is_empty());
    }
}
